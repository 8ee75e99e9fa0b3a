//! `shakedown merge`: join the outputs of `sweep --shard K/N` into the file
//! one unsharded `sweep` with the same flags writes, byte for byte.
//!
//! The shards' rows carry their identity (`lambda,phi,"initial"`, the first
//! three columns), and the order is re-derived from the job list of the
//! same grid flags. So the shard files may be given in any order, and a
//! missing, foreign or repeated row is an error rather than a silent gap.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{anyhow, Result};
use clap::Args;
use shakedown::io::csv::{check_preamble, sweep_metadata};
use shakedown::io::output::is_nonempty_file;
use shakedown::io::read::read_capped;

use super::batch::{lock_file_output, print_stdout, refuse_input_as_output, write_file};
use super::sweep::{grid_spec, job_key, GridArgs, HEADER};
use super::InputError;
use shakedown::io::csv::sweep_row_key_capped;

/// The flags of `shakedown merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard outputs of `sweep --shard K/N --out FILE`, in any order.
    #[arg(required = true, value_name = "SHARD.csv")]
    pub files: Vec<PathBuf>,
    /// Write the merged CSV here instead of stdout (written whole to a
    /// temporary file and renamed, so a failure leaves FILE as it was).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Replace an existing, non-empty --out FILE.
    #[arg(long)]
    pub force: bool,
    /// The grid flags the shards were run with (--lambda, --phi,
    /// --initial, ...): they give the rows' order.
    #[command(flatten)]
    pub grid: GridArgs,
}

/// Largest shard file read: the rows of every run of the grid, at a
/// generous 512 bytes each, and the header.
fn cap(header: &str, runs: usize) -> u64 {
    header.len() as u64 + 4096 + 512 * (runs as u64 + 1)
}

/// Run `shakedown merge`.
pub fn merge(mut args: MergeArgs) -> Result<ExitCode> {
    args.out = super::batch::dash_is_stdout(args.out.take());
    let spec = grid_spec(&args.grid)?;
    let keys: Vec<String> = spec.jobs().iter().map(|j| job_key(&spec, j)).collect();
    let meta = sweep_metadata(&spec);
    let header = meta.preamble(HEADER);
    // Held until the merged file is in place: no second writer.
    let _lock = match &args.out {
        Some(out) => {
            let inputs: Vec<(&str, &Path)> = args
                .files
                .iter()
                .map(|f| ("input", f.as_path()))
                .chain(
                    args.grid
                        .preset
                        .as_deref()
                        .map(|p| ("--preset file", Path::new(p))),
                )
                .chain(args.grid.model.input_files())
                .collect();
            refuse_input_as_output("--out", out, &inputs)?;
            if !args.force && is_nonempty_file(out) {
                return Err(anyhow!(InputError(format!(
                    "--out {}: it exists and is not empty: add --force to replace it",
                    out.display()
                ))));
            }
            lock_file_output("--out", out)?
        }
        None => None,
    };
    let inputs = args
        .files
        .iter()
        .map(|p| {
            let shown = p.display().to_string();
            let content = read_capped(p, cap(&header, keys.len())).map_err(|e| {
                anyhow!(InputError(format!("{shown}: cannot read this shard: {e}")))
            })?;
            check_preamble(&content, &meta)
                .map_err(|e| anyhow!(InputError(format!("merge: {shown}: {e}"))))?;
            Ok((shown, content))
        })
        .collect::<Result<Vec<_>>>()?;
    // Every row checked, its cycles against the cap the header records.
    let row_key = sweep_row_key_capped(spec.options().convergence().max_cycles() as u64);
    let merged = shakedown::io::batch::merge(&header, &keys, &inputs, row_key)
        .map_err(|e| anyhow!(InputError(format!("merge: {e}"))))?;
    match &args.out {
        None => print_stdout(&merged)?,
        Some(path) => {
            write_file("--out", path, merged.as_bytes())?;
            errln!(
                "merged {} runs from {} files into {}",
                keys.len(),
                inputs.len(),
                path.display()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
