//! `shakedown merge`: join the outputs of `sweep --shard K/N` into the file
//! one unsharded `sweep` with the same flags writes, byte for byte.
//!
//! The shards' rows carry their identity (`lambda,phi,"initial"`, the first
//! three columns), and the order is re-derived from the job list of the
//! same grid flags. So the shard files may be given in any order, and a
//! missing, foreign or repeated row is an error rather than a silent gap.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{anyhow, Result};
use clap::Args;

use super::batch::print_stdout;
use super::sweep::{grid_spec, job_key, row_key, GridArgs, HEADER};
use super::InputError;

#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard outputs of `sweep --shard K/N --out FILE`, in any order.
    #[arg(required = true, value_name = "SHARD.csv")]
    pub files: Vec<PathBuf>,
    /// Write the merged CSV here instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The grid flags the shards were run with (--lambda, --phi,
    /// --initial, ...): they give the rows' order.
    #[command(flatten)]
    pub grid: GridArgs,
}

pub fn merge(args: MergeArgs) -> Result<ExitCode> {
    let spec = grid_spec(&args.grid)?;
    let keys: Vec<String> = spec.jobs().iter().map(|j| job_key(&spec, j)).collect();
    let inputs = args
        .files
        .iter()
        .map(|p| {
            std::fs::read(p)
                .map(|content| (p.display().to_string(), content))
                .map_err(|e| {
                    anyhow!(InputError(format!(
                        "{}: cannot read this shard: {e}",
                        p.display()
                    )))
                })
        })
        .collect::<Result<Vec<_>>>()?;
    let merged = shakedown::io::batch::merge(HEADER, &keys, &inputs, row_key)
        .map_err(|e| anyhow!(InputError(format!("merge: {e}"))))?;
    match &args.out {
        None => {
            print_stdout(&merged)?;
        }
        Some(path) => {
            let cannot = |e: std::io::Error| {
                anyhow!(InputError(format!(
                    "--out {}: cannot write it: {e}: expected a writable file path",
                    path.display()
                )))
            };
            let mut file = std::fs::File::create(path).map_err(cannot)?;
            file.write_all(merged.as_bytes())
                .and_then(|()| file.flush())
                .map_err(cannot)?;
            eprintln!(
                "merged {} runs from {} files into {}",
                keys.len(),
                inputs.len(),
                path.display()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}
