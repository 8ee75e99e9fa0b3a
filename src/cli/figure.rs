//! `shakedown figure NAME --out DIR`: run a preset and write its data as
//! CSV and its plot as SVG and PNG.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{anyhow, Result};
use clap::Args;
use shakedown::analysis::case::Case;
use shakedown::analysis::limit::{shakedown_limit, Limit, DEFAULT_SAMPLES};
use shakedown::analysis::memory::{
    memory_csv, memory_points, memory_runs, ratchetting_onset, MemoryError,
};
use shakedown::analysis::slip_map::{slip_map, SlipMap, SlipMapError};
use shakedown::analysis::sweep::Axis;
use shakedown::analysis::sweep::{SweepSpec, CSV_HEADER};
use shakedown::figure::draw::{write_svg_png, DissipationPlot, MemoryPlot, SlipMapPlot};
use shakedown::figure::FigureError;
use shakedown::io::parse::{parse_angle, parse_number, parse_values};
use shakedown::io::preset::{FigureKind, FigureSpec, Preset};

use super::batch::{ctrl_c, Output};
use super::sweep::{job_key, progress, row_key, spec, warn_failures, ListArgs};
use super::{load_preset, InputError, ModelArgs};

#[derive(Debug, Args)]
pub struct FigureArgs {
    /// The figure: a built-in preset (fig3 ... fig9, see `shakedown presets`) or a path to a .toml file.
    #[arg(value_name = "NAME|FILE")]
    pub name: String,
    /// Directory to write NAME.csv, NAME.svg and NAME.png into (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    pub lists: ListArgs,
    #[command(flatten)]
    pub model: ModelArgs,
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| {
        anyhow!(InputError(format!(
            "--out: cannot write {}: {e}",
            path.display()
        )))
    })
}

pub fn figure(args: FigureArgs) -> Result<ExitCode> {
    let preset = load_preset("figure", &args.name)?;
    let Some(fig) = preset.figure.clone() else {
        return Err(anyhow!(InputError(format!(
            "figure {}: {} has no [figure] table, so there is nothing to draw",
            args.name, preset.file
        ))));
    };
    std::fs::create_dir_all(&args.out).map_err(|e| {
        anyhow!(InputError(format!(
            "--out {}: cannot create the directory: {e}",
            args.out.display()
        )))
    })?;
    let stem = preset.name.clone();
    let file = |ext: &str| args.out.join(format!("{stem}{ext}"));
    let title = fig
        .title
        .clone()
        .unwrap_or_else(|| preset.description.clone());
    let started = Instant::now();
    let mut written = Vec::new();
    match fig.kind {
        FigureKind::Dissipation => {
            let spec = sweep_spec(&args, &preset)?;
            let limit = limit_of(&fig, &spec)?;
            let jobs = spec.jobs();
            // Rows stream to the CSV in job order, one flushed line each, so
            // that Ctrl-C leaves a file of complete rows (a prefix of the
            // full table) and no half-drawn plot.
            let keys: Vec<String> = jobs.iter().map(|j| job_key(&spec, j)).collect();
            let csv_path = file(".csv");
            let mut out = Output::open(Some(&csv_path), false, CSV_HEADER, &keys, row_key)?;
            let interrupt = ctrl_c()?;
            let bar = progress(jobs.len());
            let mut rows = Vec::with_capacity(jobs.len());
            let result = spec.run_ordered(&jobs, interrupt, |row| {
                out.line(&row.csv_line())?;
                bar.inc(1);
                rows.push(row);
                anyhow::Ok(())
            });
            bar.finish_and_clear();
            if !result?.is_complete() {
                eprintln!(
                    "interrupted: {} of {} runs are in {} (complete rows only); no plot was drawn",
                    rows.len(),
                    jobs.len(),
                    csv_path.display()
                );
                return Ok(ExitCode::from(super::batch::INTERRUPTED));
            }
            warn_failures(&rows);
            written.push(file(".csv"));
            if let Some(l) = &limit {
                write_limit(&file("_limit.csv"), l, spec.disc().nodes())?;
                written.push(file("_limit.csv"));
                println!("lambda_2 = {:.6} (linear programme)", l.load_factor);
            }
            let plot = DissipationPlot {
                rows: &rows,
                axis: fig.axis,
                ratchetting: fig.ratchetting,
                lines: fig.lines,
                title,
                limit: limit.as_ref().map(|l| l.load_factor),
            };
            write_svg_png(&plot, &file(".svg"), &file(".png"))?;
            println!("{} runs", rows.len());
        }
        FigureKind::Memory => {
            let spec = sweep_spec(&args, &preset)?;
            let limit = limit_of(&fig, &spec)?;
            let jobs = spec.jobs();
            let bar = progress(jobs.len());
            let runs = memory_runs(&spec, &|| bar.inc(1)).map_err(|e| input(e.into()))?;
            bar.finish_and_clear();
            let points = memory_points(&runs);
            write(&file(".csv"), &memory_csv(&points))?;
            written.push(file(".csv"));
            if let Some(l) = &limit {
                write_limit(&file("_limit.csv"), l, spec.disc().nodes())?;
                written.push(file("_limit.csv"));
                println!("lambda_2 = {:.6} (linear programme)", l.load_factor);
            }
            if let Some(l3) = ratchetting_onset(&points) {
                println!("lambda_3 = {l3} (every transient ratchets from here on)");
            }
            let plot = MemoryPlot {
                points: &points,
                title,
                limit: limit.as_ref().map(|l| l.load_factor),
            };
            write_svg_png(&plot, &file(".svg"), &file(".png"))?;
            println!("{} runs", runs.len());
        }
        FigureKind::SlipMap => {
            let case = single_case(&args, &preset)?;
            let map = slip_map(&case).map_err(|e| input(e.into()))?;
            write(&file(".csv"), &map.csv())?;
            write(&file("_load.csv"), &map.load_csv())?;
            written.push(file(".csv"));
            written.push(file("_load.csv"));
            describe(&map);
            let plot = SlipMapPlot { map: &map, title };
            write_svg_png(&plot, &file(".svg"), &file(".png"))?;
        }
    }
    written.push(file(".svg"));
    written.push(file(".png"));
    for w in &written {
        println!("wrote {}", w.display());
    }
    println!("took {:.1} s", started.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}

/// A figure the chosen parameters cannot give is the user's input;
/// numerical failures are not.
fn input(e: FigureError) -> anyhow::Error {
    match e {
        FigureError::Memory(MemoryError::NoTransient(_) | MemoryError::Param(_))
        | FigureError::SlipMap(SlipMapError::NoSteadyCycle { .. }) => {
            anyhow!(InputError(e.to_string()))
        }
        other => anyhow!(other),
    }
}

fn sweep_spec(args: &FigureArgs, preset: &Preset) -> Result<SweepSpec> {
    spec(
        &args.model,
        &args.lists,
        preset.params.clone(),
        Some(&preset.sweep),
    )
}

/// `lambda_2` when the figure marks it and the sweep has one phase.
fn limit_of(fig: &FigureSpec, spec: &SweepSpec) -> Result<Option<Limit>> {
    if !fig.limit || fig.axis != Axis::Lambda || spec.phases().len() != 1 {
        return Ok(None);
    }
    let l = shakedown_limit(
        &spec.material(),
        spec.center(),
        spec.slope(),
        spec.phases()[0],
        &spec.disc(),
        DEFAULT_SAMPLES,
    )?;
    Ok(Some(l))
}

fn write_limit(path: &Path, l: &Limit, nodes: usize) -> Result<()> {
    write(path, &super::limit::slip_csv(l, nodes))
}

/// The one case of a slip map: the preset's, with at most one value from
/// each list flag.
fn single_case(args: &FigureArgs, preset: &Preset) -> Result<Case> {
    let mut p = args.model.apply(preset.params.clone())?;
    let one = |flag: &str, text: &Option<String>, item: fn(&str) -> _| -> Result<Option<f64>> {
        let Some(t) = text else { return Ok(None) };
        let v: Vec<f64> =
            parse_values(t, item).map_err(|e| anyhow!(InputError(format!("--{flag} {t}: {e}"))))?;
        if v.len() != 1 {
            return Err(anyhow!(InputError(format!(
                "--{flag} {t}: a slip map draws one case, so give one value"
            ))));
        }
        Ok(Some(v[0]))
    };
    if let Some(v) = one("lambda", &args.lists.lambdas, parse_number)? {
        p.load_factor = v;
    }
    if let Some(v) = one("phi", &args.lists.phis, parse_angle)? {
        p.phase = v;
    }
    if let Some(t) = &args.lists.initials {
        p.initial = t.clone();
    }
    Case::from_params(&p).map_err(|e| anyhow!(InputError(e.to_string())))
}

fn describe(map: &SlipMap) {
    let s = &map.summary;
    println!(
        "steady state: {} after {} cycles, W = {:.6e}, rotation {:.3e} per cycle",
        s.state, s.cycles, s.dissipation, s.rotation_per_cycle
    );
}
