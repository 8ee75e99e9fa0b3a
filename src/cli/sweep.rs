//! `shakedown sweep`: a grid of runs written as CSV, row by row in job
//! order, so that an interrupted file can be resumed and shards merged.

use std::process::ExitCode;

use anyhow::{anyhow, Result};
use clap::Args;
use shakedown::analysis::case::{Case, CaseError, CaseParams};
use shakedown::analysis::sweep::SweepLists;
use shakedown::analysis::sweep::{groups, Job, SweepSpec, MAX_RUNS};
use shakedown::io::batch::Shard;
use shakedown::io::parse::{parse_angle, parse_number, parse_values};
use shakedown::model::path::Initial;
use shakedown::model::ranges;

use std::path::Path;

use super::batch::{is_broken_pipe, refuse_input_as_output, report_interrupt, stream_sweep};
use super::{bad_flag, case_error, load_preset, ModelArgs};

/// The CSV header: `lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle`.
pub use shakedown::analysis::sweep::CSV_HEADER as HEADER;

#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub grid: GridArgs,
    /// Write the CSV here instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<std::path::PathBuf>,
    /// Continue an interrupted --out FILE: keep its complete rows, skip
    /// those runs, append the rest (the result is the uninterrupted file).
    #[arg(long, conflicts_with = "force")]
    pub resume: bool,
    /// Replace an existing, non-empty --out FILE (without it, such a file
    /// is refused and left untouched).
    #[arg(long)]
    pub force: bool,
    /// Run only the K-th of N disjoint slices of the runs (1 <= K <= N):
    /// the runs of the K-th, K+N-th, K+2N-th, ... lambda and phi, each
    /// with all its initial paths. Join the slices with `shakedown merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
}

/// The swept lists. Unset ones come from the preset, else from the case.
#[derive(Debug, Clone, Default, Args)]
pub struct ListArgs {
    /// Load factors: a list (5,5.5,6) or a range start:stop:step (3:7.5:0.05).
    #[arg(long = "lambda", value_name = "LIST|RANGE", allow_hyphen_values = true,
          value_parser = super::values::list(ranges::LAMBDA, parse_number))]
    pub lambdas: Option<String>,
    /// Phases: a list or a range; angles accept pi (0:pi:pi/24).
    #[arg(long = "phi", value_name = "LIST|RANGE", allow_hyphen_values = true,
          value_parser = super::values::list(ranges::PHI, parse_angle))]
    pub phis: Option<String>,
    /// Initial paths: all (the paper's 25), optimal (the lambda_2 slip, per phase), or a list such as OA,7,-7 (points take two numbers) or all,optimal.
    #[arg(long = "initial", value_name = "all|NAMES", allow_hyphen_values = true)]
    pub initials: Option<String>,
    /// Start every run at the cycle centre with the slip in FILE (as
    /// `limit --out FILE` writes it; its node count must be --nodes).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["initials", "initial_path"])]
    pub initial_slip: Option<String>,
    /// A custom transient O -> points -> A: load-plane points "X1,Y1;X2,Y2" (angles as in --phi, e.g. "1.75pi,-1.75pi"). Runs alone, or after the --initial list when that is given.
    #[arg(
        long = "initial-path",
        value_name = "X,Y;...",
        allow_hyphen_values = true
    )]
    pub initial_path: Option<String>,
}

/// The grid of a sweep: what `sweep` runs and what `merge` re-derives.
#[derive(Debug, Clone, Default, Args)]
pub struct GridArgs {
    /// Start from a preset: a built-in name (see `shakedown presets`) or a path to a .toml file.
    #[arg(long, value_name = "NAME|FILE")]
    pub preset: Option<String>,
    #[command(flatten)]
    pub lists: ListArgs,
    #[command(flatten)]
    pub model: ModelArgs,
}

/// The sweep of `grid`: its preset (if any) under the flags given.
pub fn grid_spec(grid: &GridArgs) -> Result<SweepSpec> {
    let preset = grid
        .preset
        .as_deref()
        .map(|name| load_preset("--preset", name))
        .transpose()?;
    let base = preset
        .as_ref()
        .map_or_else(CaseParams::default, |p| p.params.clone());
    spec(
        &grid.model,
        &grid.lists,
        base,
        preset.as_ref().map(|p| &p.sweep),
    )
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
        (Some(t), _) => parse_values(t, parse_number).map_err(|e| bad_flag("lambda", t, e))?,
        (None, Some(p)) => p.load_factors.clone(),
        (None, None) => vec![params.load_factor],
    };
    let phis = match (&lists.phis, preset) {
        (Some(t), _) => {
            super::refuse_phase_with_polyline(&params, "phi", t)?;
            parse_values(t, parse_angle).map_err(|e| bad_flag("phi", t, e))?
        }
        (None, Some(p)) => p.phases.clone(),
        (None, None) => vec![params.phase],
    };
    let mut initials = match (&lists.initials, preset) {
        _ if lists.initial_slip.is_some() => {
            let path = lists.initial_slip.as_deref().unwrap_or_default();
            vec![super::initial_slip(path, params.nodes)?]
        }
        (Some(t), _) => Initial::parse_list(t).map_err(|e| bad_flag("initial", t, e))?,
        (None, Some(p)) => p.initials.clone(),
        (None, None) => vec![params.initial.clone()],
    };
    if let Some(text) = &lists.initial_path {
        let material =
            shakedown::model::Material::new(params.friction, params.poisson, params.plane)
                .map_err(|e| case_error(CaseError::Param(e), |f| model.given(f)))?;
        let custom = super::custom_path(text, &material)?;
        if lists.initials.is_none() {
            initials.clear();
        }
        if !initials.contains(&custom) {
            initials.push(custom);
        }
    }
    let given = |flag: &str| match flag {
        "lambda" => lists.lambdas.clone(),
        "phi" => lists.phis.clone(),
        "initial" => lists.initials.clone(),
        f => model.given(f),
    };
    check_grid_size(lambdas.len(), phis.len(), initials.len())?;
    params.load_factor = lambdas[0];
    params.phase = phis[0];
    // The initial paths are already resolved; validate the rest.
    params.initial = Initial::Direct;
    let case = Case::from_params(&params).map_err(|e| case_error(e, given))?;
    // Only a valid case is worth a warning about its cost.
    super::warn_if_slow(
        params.nodes,
        params.steps,
        super::CostClass::of(&params, &phis),
    );
    let lists = SweepLists {
        load_factors: lambdas,
        phases: phis,
        initials,
    };
    let spec =
        SweepSpec::over(&case, &lists).map_err(|e| case_error(CaseError::Param(e), given))?;
    Ok(spec)
}

/// Refuse a grid of more than [`MAX_RUNS`] runs, before anything of that
/// size is allocated.
pub fn check_grid_size(lambdas: usize, phis: usize, initials: usize) -> Result<()> {
    let runs = lambdas.saturating_mul(phis).saturating_mul(initials);
    if runs > MAX_RUNS {
        return Err(anyhow!(super::InputError(format!(
            "--lambda x --phi x --initial: {lambdas} x {phis} x {initials} = {runs} runs, more than the cap of {MAX_RUNS}: split the grid into several sweeps"
        ))));
    }
    Ok(())
}

/// Warn about the runs that failed (`failed`: each one's reason, of
/// `total` runs), with the distinct reasons.
pub fn warn_failures(failed: &[String], total: usize) {
    if failed.is_empty() {
        return;
    }
    let mut reasons = failed.to_vec();
    reasons.sort();
    reasons.dedup();
    errln!(
        "warning: {} of {total} runs failed (state 'failed' in the CSV): {}",
        failed.len(),
        reasons.join("; ")
    );
}

/// The identity of a job's line: its first three fields `lambda,phi,"initial"`.
/// Every line of the CSV starts with its job's key and a comma.
pub fn job_key(spec: &SweepSpec, job: &Job) -> String {
    key(
        job.load_factor,
        job.phase,
        &spec.initials()[job.initial].name(),
    )
}

use shakedown::io::sweep_csv::row_key as key;

#[cfg(test)]
/// The key of a CSV line (see [`job_key`]) after validating the whole row
/// ([`shakedown::io::csv::sweep_row_key`]), or what is wrong with it.
pub fn row_key(line: &str) -> std::result::Result<&str, String> {
    shakedown::io::csv::sweep_row_key(line)
}

/// The jobs of a sweep after `--shard`, and their line keys.
pub fn shard_jobs(spec: &SweepSpec, shard: Option<&str>) -> Result<(Vec<Job>, Vec<String>)> {
    let all = spec.jobs();
    let jobs = match shard {
        None => all,
        Some(text) => Shard::parse(text)
            .map_err(|e| anyhow!(super::InputError(format!("--shard {text}: {e}"))))?
            .select_groups(&all, &groups(&all)),
    };
    let keys = jobs.iter().map(|j| job_key(spec, j)).collect();
    Ok((jobs, keys))
}

pub fn sweep(mut args: SweepArgs) -> Result<ExitCode> {
    args.out = super::batch::dash_is_stdout(args.out.take());
    let spec = grid_spec(&args.grid)?;
    let (jobs, keys) = shard_jobs(&spec, args.shard.as_deref())?;
    if let Some(out) = &args.out {
        // No output may be one of the inputs, under any name.
        let mut inputs = Vec::new();
        if let Some(preset) = &args.grid.preset {
            inputs.push(("--preset file", Path::new(preset)));
        }
        if let Some(slip) = &args.grid.lists.initial_slip {
            inputs.push(("--initial-slip file", Path::new(slip)));
        }
        inputs.extend(args.grid.model.input_files());
        refuse_input_as_output("--out", out, &inputs)?;
    }
    let mut failed = 0;
    let streamed = stream_sweep(
        &spec,
        &jobs,
        &keys,
        args.out.as_deref(),
        args.resume,
        args.force,
        |row, bar| {
            if let Err(e) = &row.outcome {
                failed += 1;
                bar.suspend(|| {
                    errln!(
                        "warning: run lambda = {}, phi = {}, initial {} failed: {e}",
                        shakedown::io::metadata::fmt_number(row.job.load_factor),
                        shakedown::io::metadata::fmt_number(row.job.phase),
                        row.initial
                    )
                });
            }
        },
    );
    let streamed = match streamed {
        Err(e) if is_broken_pipe(&e) => return Ok(ExitCode::SUCCESS),
        Err(e) => return Err(e),
        Ok(s) => s,
    };
    if !streamed.complete {
        return Ok(report_interrupt(&streamed.out, jobs.len()));
    }
    if failed > 0 {
        errln!(
            "warning: {failed} of {} runs failed (state 'failed' in the CSV)",
            streamed.out.written
        );
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shakedown::analysis::sweep::{Row, RowState, RunError};
    use shakedown::stepping::StepError;

    #[test]
    fn every_line_starts_with_its_key() {
        let spec = grid_spec(&GridArgs {
            preset: None,
            lists: ListArgs {
                lambdas: Some("0.5,1e-7".into()),
                phis: Some("0,pi/3".into()),
                initials: Some("OA,-7,3".into()),
                initial_slip: None,
                initial_path: None,
            },
            model: ModelArgs::default(),
        })
        .unwrap();
        for job in spec.jobs() {
            let row = Row {
                job,
                initial: spec.initials()[job.initial].name(),
                outcome: Err(RunError::Step(StepError::NotSettled {
                    load: shakedown::LoadPoint::new(1.0, 2.0),
                    phase: "cycle 1, increment 1".into(),
                    bisections: 12,
                })),
            };
            assert_eq!(row.state(), RowState::Failed);
            let line = shakedown::io::sweep_csv::row_line(&row);
            assert!(line.contains(",failed,"), "{line}");
            assert_eq!(row_key(&line), Ok(job_key(&spec, &job).as_str()), "{line}");
        }
        assert_eq!(HEADER.split(',').count(), 7);
    }

    #[test]
    fn row_key_rejects_incomplete_lines() {
        let line = "5.5,0,\"7,-7\",cyclic-slip,0.001,12,0";
        assert_eq!(row_key(line), Ok("5.5,0,\"7,-7\""));
        for cut in 0..line.len() {
            assert!(row_key(&line[..cut]).is_err(), "{}", &line[..cut]);
        }
        assert!(row_key("a,b,c,d,e,f,g").is_err());
        assert!(row_key("1,2,3,\"OA\",x,1,2,3").is_err());
    }
}
