//! `shakedown sweep`: a grid of runs written as CSV.

use std::io::{IsTerminal, Write};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;

use anyhow::{anyhow, Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use shakedown::case::{resolve_initial, Case, CaseParams};
use shakedown::parse::{parse_angle, parse_number, parse_values};
use shakedown::path::Initial;
use shakedown::sweep::{Row, SweepSpec};

use super::{CaseArgs, InputError};

#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Load factors: a list (5,5.5,6) or a range start:stop:step (3:7.5:0.05).
    #[arg(long = "lambda", value_name = "LIST|RANGE", allow_hyphen_values = true)]
    pub lambdas: Option<String>,
    /// Phases: a list or a range; angles accept pi (0:pi:pi/24).
    #[arg(long = "phi", value_name = "LIST|RANGE", allow_hyphen_values = true)]
    pub phis: Option<String>,
    /// Initial paths: all (the paper's 25), or a list such as OA,7,-7 (points take two numbers).
    #[arg(long = "initial", value_name = "all|NAMES", allow_hyphen_values = true)]
    pub initials: Option<String>,
    /// Write the CSV here instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub case: CaseArgs,
}

/// Split `OA,7,-7,3,7` into `OA`, `7,-7`, `3,7`: names are `OA`, `optimal`
/// or a pair of integers.
pub fn split_initials(text: &str) -> Result<Vec<String>> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < parts.len() {
        let p = parts[i];
        if p.parse::<i32>().is_ok() {
            let q = parts.get(i + 1).ok_or_else(|| {
                anyhow!(InputError(format!(
                    "--initial {text}: point '{p}' needs two numbers a,b"
                )))
            })?;
            out.push(format!("{p},{q}"));
            i += 2;
        } else {
            out.push(p.to_string());
            i += 1;
        }
    }
    Ok(out)
}

pub fn spec(args: &SweepArgs, base: CaseParams) -> Result<SweepSpec> {
    let mut params = args.case.apply(base, false)?;
    let lambdas = match &args.lambdas {
        Some(t) => parse_values(t, parse_number).with_context(|| format!("--lambda {t}"))?,
        None => vec![params.load_factor],
    };
    let phis = match &args.phis {
        Some(t) => parse_values(t, parse_angle).with_context(|| format!("--phi {t}"))?,
        None => vec![params.phase],
    };
    params.load_factor = lambdas[0];
    params.phase = phis[0];
    params.initial = "OA".into();
    let case = Case::from_params(&params).map_err(|e| anyhow!(InputError(e.to_string())))?;
    let initials = match args.initials.as_deref().map(str::trim) {
        None => vec![Initial::Direct],
        Some(t) if t.eq_ignore_ascii_case("all") => Initial::paper_set(),
        Some(t) => split_initials(t)?
            .iter()
            .map(|name| {
                resolve_initial(name, &case.material, &case.cycle, &case.disc)
                    .map_err(|e| anyhow!(InputError(format!("--initial {name}: {e}"))))
            })
            .collect::<Result<_>>()?,
    };
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

pub const HEADER: &str = "lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle";

/// One CSV line (no newline). Numbers use Rust's shortest round-trip form,
/// so the bytes do not depend on the platform or thread count.
pub fn csv_line(row: &Row) -> String {
    let (w, c, r) = match &row.outcome {
        Ok(s) => (s.dissipation, s.cycles, s.rotation_per_cycle),
        Err(_) => (f64::NAN, 0, f64::NAN),
    };
    format!(
        "{},{},\"{}\",{},{},{},{}",
        row.job.load_factor,
        row.job.phase,
        row.initial,
        row.state(),
        w,
        c,
        r
    )
}

pub fn sweep(args: SweepArgs) -> Result<ExitCode> {
    let spec = spec(&args, CaseParams::default())?;
    let jobs = spec.jobs();
    let mut out: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(std::io::BufWriter::new(
            std::fs::File::create(path)
                .map_err(|e| anyhow!(InputError(format!("--out {}: {e}", path.display()))))?,
        )),
        None => Box::new(std::io::BufWriter::new(std::io::stdout().lock())),
    };
    let bar = if std::io::stderr().is_terminal() {
        let b = ProgressBar::new(jobs.len() as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {elapsed} (eta {eta})")
                .expect("valid template"),
        );
        b
    } else {
        ProgressBar::hidden()
    };
    let cancel = AtomicBool::new(false);
    let rows = spec.run(&jobs, &|_| bar.inc(1), &cancel);
    bar.finish_and_clear();
    writeln!(out, "{HEADER}")?;
    for row in &rows {
        writeln!(out, "{}", csv_line(row))?;
    }
    out.flush()?;
    let failed = rows.iter().filter(|r| r.outcome.is_err()).count();
    if failed > 0 {
        eprintln!(
            "warning: {failed} of {} runs failed (state 'failed' in the CSV)",
            rows.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}
