//! `shakedown sweep`: a grid of runs written as CSV.

use std::io::{IsTerminal, Write};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;

use anyhow::{anyhow, Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use shakedown::case::{Case, CaseParams};
use shakedown::parse::{parse_angle, parse_number, parse_values};
use shakedown::path::Initial;
use shakedown::preset::SweepLists;
use shakedown::sweep::{SweepSpec, CSV_HEADER};

use super::{load_preset, InputError, ModelArgs};

/// The swept lists. Unset ones come from the preset, else from the case.
#[derive(Debug, Clone, Default, Args)]
pub struct ListArgs {
    /// Load factors: a list (5,5.5,6) or a range start:stop:step (3:7.5:0.05).
    #[arg(long = "lambda", value_name = "LIST|RANGE", allow_hyphen_values = true)]
    pub lambdas: Option<String>,
    /// Phases: a list or a range; angles accept pi (0:pi:pi/24).
    #[arg(long = "phi", value_name = "LIST|RANGE", allow_hyphen_values = true)]
    pub phis: Option<String>,
    /// Initial paths: all (the paper's 25), optimal (the lambda_2 slip, per phase), or a list such as OA,7,-7 (points take two numbers) or all,optimal.
    #[arg(long = "initial", value_name = "all|NAMES", allow_hyphen_values = true)]
    pub initials: Option<String>,
}

#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Start from a preset: a built-in name (see `shakedown presets`) or a path to a .toml file.
    #[arg(long, value_name = "NAME|FILE")]
    pub preset: Option<String>,
    #[command(flatten)]
    pub lists: ListArgs,
    /// Write the CSV here instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub model: ModelArgs,
}

/// The sweep: the model flags over `base`, with the lists from the flags,
/// else from `preset`, else the base case's single values.
pub fn spec(
    model: &ModelArgs,
    lists: &ListArgs,
    base: CaseParams,
    preset: Option<&SweepLists>,
) -> Result<SweepSpec> {
    let mut params = model.apply(base)?;
    let lambdas = match (&lists.lambdas, preset) {
        (Some(t), _) => parse_values(t, parse_number).with_context(|| format!("--lambda {t}"))?,
        (None, Some(p)) => p.load_factors.clone(),
        (None, None) => vec![params.load_factor],
    };
    let phis = match (&lists.phis, preset) {
        (Some(t), _) => parse_values(t, parse_angle).with_context(|| format!("--phi {t}"))?,
        (None, Some(p)) => p.phases.clone(),
        (None, None) => vec![params.phase],
    };
    let initials = match (&lists.initials, preset) {
        (Some(t), _) => Initial::parse_list(t)
            .map_err(|e| anyhow!(InputError(format!("--initial {t}: {e}"))))?,
        (None, Some(p)) => p.initials.clone(),
        (None, None) => Initial::parse_list(&params.initial)
            .map_err(|e| anyhow!(InputError(format!("initial path: {e}"))))?,
    };
    params.load_factor = lambdas[0];
    params.phase = phis[0];
    // The initial paths are already resolved; validate the rest.
    params.initial = "OA".into();
    let case = Case::from_params(&params).map_err(|e| anyhow!(InputError(e.to_string())))?;
    let spec = SweepSpec {
        material: case.material,
        disc: case.disc,
        options: case.options,
        center: case.cycle.center,
        slope: case.cycle.slope,
        load_factors: lambdas,
        phases: phis,
        initials,
    };
    spec.validate()
        .map_err(|e| anyhow!(InputError(e.to_string())))?;
    Ok(spec)
}

/// A progress bar on stderr when it is a terminal.
pub fn progress(len: usize) -> ProgressBar {
    if std::io::stderr().is_terminal() {
        let b = ProgressBar::new(len as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {elapsed} (eta {eta})")
                .expect("valid template"),
        );
        b
    } else {
        ProgressBar::hidden()
    }
}

/// Warn about runs that failed, with the distinct reasons.
pub fn warn_failures(rows: &[shakedown::sweep::Row]) {
    let failed: Vec<String> = rows
        .iter()
        .filter_map(|r| r.outcome.as_ref().err().map(|e| e.to_string()))
        .collect();
    if failed.is_empty() {
        return;
    }
    let mut reasons = failed.clone();
    reasons.sort();
    reasons.dedup();
    eprintln!(
        "warning: {} of {} runs failed (state 'failed' in the CSV): {}",
        failed.len(),
        rows.len(),
        reasons.join("; ")
    );
}

pub fn sweep(args: SweepArgs) -> Result<ExitCode> {
    let preset = args
        .preset
        .as_deref()
        .map(|name| load_preset("--preset", name))
        .transpose()?;
    let base = preset
        .as_ref()
        .map_or_else(CaseParams::default, |p| p.params.clone());
    let spec = spec(
        &args.model,
        &args.lists,
        base,
        preset.as_ref().map(|p| &p.sweep),
    )?;
    let jobs = spec.jobs();
    let mut out: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(std::io::BufWriter::new(
            std::fs::File::create(path)
                .map_err(|e| anyhow!(InputError(format!("--out {}: {e}", path.display()))))?,
        )),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let bar = progress(jobs.len());
    let cancel = AtomicBool::new(false);
    let rows = spec.run(&jobs, &|_| bar.inc(1), &cancel);
    bar.finish_and_clear();
    writeln!(out, "{CSV_HEADER}")?;
    for row in &rows {
        writeln!(out, "{}", row.csv_line())?;
    }
    out.flush()?;
    warn_failures(&rows);
    Ok(ExitCode::SUCCESS)
}
