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

use shakedown::io::csv::{case_metadata, slip_csv, sweep_metadata};
use shakedown::io::output::{check_file_stem, is_nonempty_file, temp_path};

use super::batch::{ctrl_c, lock_output, refuse_input_as_output, write_file, Output};
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
    /// Replace the figure's files if they exist (without it, an existing
    /// NAME.csv, NAME.svg or NAME.png is refused and left untouched). The
    /// old files stay until the new ones are complete.
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub lists: ListArgs,
    #[command(flatten)]
    pub model: ModelArgs,
}

/// Replace `path` whole (temporary file, then rename).
fn write(path: &Path, text: &str) -> Result<()> {
    write_file("--out", path, text.as_bytes())
}

/// The files a figure may write, by suffix.
const SUFFIXES: [&str; 5] = [".csv", "_limit.csv", "_load.csv", ".svg", ".png"];

/// Draw the plot into temporary files beside `svg` and `png`, then rename
/// them into place: an interrupted or failed drawing leaves the old ones.
fn write_plot<D: shakedown::figure::draw::Drawing>(plot: &D, svg: &Path, png: &Path) -> Result<()> {
    let temp = |p: &Path| {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
        p.with_file_name(format!(
            ".tmp-{}-{}",
            std::process::id(),
            name.unwrap_or_default()
        ))
    };
    let (tsvg, tpng) = (temp(svg), temp(png));
    let result = write_svg_png(plot, &tsvg, &tpng)
        .map_err(anyhow::Error::from)
        .and_then(|()| {
            std::fs::rename(&tsvg, svg)
                .and_then(|()| std::fs::rename(&tpng, png))
                .map_err(|e| anyhow!("--out: cannot replace {}: {e}", svg.display()))
        });
    if result.is_err() {
        let _ = std::fs::remove_file(&tsvg);
        let _ = std::fs::remove_file(&tpng);
    }
    result
}

/// Run `shakedown figure`.
pub fn figure(args: FigureArgs) -> Result<ExitCode> {
    let preset = load_preset("figure", &args.name)?;
    let Some(fig) = preset.figure.clone() else {
        return Err(anyhow!(InputError(format!(
            "figure {}: {} has no [figure] table, so there is nothing to draw",
            args.name, preset.file
        ))));
    };
    let stem = preset.name.clone();
    // A preset's name becomes a file name: it must stay inside --out.
    check_file_stem(&stem).map_err(|why| {
        anyhow!(InputError(format!(
            "figure {}: name '{}' cannot be used: {why}",
            args.name,
            shakedown::io::read::escape_text(&stem, 60)
        )))
    })?;
    if fig.kind == FigureKind::Memory {
        if let Some(t) = &args.lists.phis {
            if parse_values(t, parse_angle).is_ok_and(|v| v.len() != 1) {
                return Err(anyhow!(InputError(format!(
                    "--phi {t}: the memory figure needs a single phase, as in its preset"
                ))));
            }
        }
    }
    std::fs::create_dir_all(&args.out).map_err(|e| {
        anyhow!(InputError(format!(
            "--out {}: cannot create the directory: {e}",
            args.out.display()
        )))
    })?;
    let file = |ext: &str| args.out.join(format!("{stem}{ext}"));
    let preset_path = Path::new(&args.name);
    for ext in SUFFIXES {
        if preset_path.exists() {
            refuse_input_as_output("--out", &file(ext), &[("preset file", preset_path)])?;
        }
    }
    let existing: Vec<PathBuf> = SUFFIXES
        .iter()
        .map(|e| file(e))
        .filter(|p| is_nonempty_file(p))
        .collect();
    if !existing.is_empty() && !args.force {
        return Err(anyhow!(InputError(format!(
            "--out {}: {} exists (a figure made before): add --force to replace the figure's files",
            args.out.display(),
            existing[0].display()
        ))));
    }
    // One writer per figure: the lock is DIR/NAME.lock.
    let _lock = lock_output("--out", &args.out.join(&stem))?;
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
            // A figure made before stays whole until the new table is.
            let csv_path = if existing.is_empty() {
                file(".csv")
            } else {
                temp_path(&file(".csv"))
            };
            let meta = sweep_metadata(&spec);
            let mut out = Output::open(
                Some(&csv_path),
                false,
                true,
                &meta,
                CSV_HEADER,
                &keys,
                row_key,
            )?;
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
            drop(out);
            if !result?.is_complete() {
                if csv_path != file(".csv") {
                    let _ = std::fs::remove_file(&csv_path);
                    eprintln!(
                        "interrupted: {} of {} runs were done; the figure made before is unchanged",
                        rows.len(),
                        jobs.len()
                    );
                    return Ok(ExitCode::from(super::batch::INTERRUPTED));
                }
                eprintln!(
                    "interrupted: {} of {} runs are in {} (complete rows only); no plot was drawn",
                    rows.len(),
                    jobs.len(),
                    csv_path.display()
                );
                return Ok(ExitCode::from(super::batch::INTERRUPTED));
            }
            warn_failures(&rows);
            if csv_path != file(".csv") {
                std::fs::rename(&csv_path, file(".csv")).map_err(|e| {
                    anyhow!("--out: cannot replace {}: {e}", file(".csv").display())
                })?;
            }
            written.push(file(".csv"));
            if let Some(l) = &limit {
                write_limit(&file("_limit.csv"), l, &spec)?;
                written.push(file("_limit.csv"));
                outln!("lambda_2 = {:.6} (linear programme)", l.load_factor);
            }
            let plot = DissipationPlot {
                rows: &rows,
                axis: fig.axis,
                ratchetting: fig.ratchetting,
                lines: fig.lines,
                title,
                limit: limit.as_ref().map(|l| l.load_factor),
            };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
            outln!("{} runs", rows.len());
        }
        FigureKind::Memory => {
            let spec = sweep_spec(&args, &preset)?;
            let limit = limit_of(&fig, &spec)?;
            let jobs = spec.jobs();
            let bar = progress(jobs.len());
            let runs = memory_runs(&spec, &|| bar.inc(1)).map_err(|e| input(e.into()))?;
            bar.finish_and_clear();
            let points = memory_points(&runs);
            let mut meta = sweep_metadata(&spec);
            meta.set("table", "memory");
            write(&file(".csv"), &(meta.render() + &memory_csv(&points)))?;
            written.push(file(".csv"));
            if let Some(l) = &limit {
                write_limit(&file("_limit.csv"), l, &spec)?;
                written.push(file("_limit.csv"));
                outln!("lambda_2 = {:.6} (linear programme)", l.load_factor);
            }
            if let Some(l3) = ratchetting_onset(&points) {
                outln!("lambda_3 = {l3} (every transient ratchets from here on)");
            }
            let plot = MemoryPlot {
                points: &points,
                title,
                limit: limit.as_ref().map(|l| l.load_factor),
            };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
            outln!("{} runs", runs.len());
        }
        FigureKind::SlipMap => {
            let case = single_case(&args, &preset)?;
            let map = slip_map(&case).map_err(|e| input(e.into()))?;
            let meta = case_metadata("slip-map", &case, &case.initial.name()).render();
            write(&file(".csv"), &(meta.clone() + &map.csv()))?;
            write(&file("_load.csv"), &(meta + &map.load_csv()))?;
            written.push(file(".csv"));
            written.push(file("_load.csv"));
            describe(&map)?;
            let plot = SlipMapPlot { map: &map, title };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
        }
    }
    written.push(file(".svg"));
    written.push(file(".png"));
    // Files of a figure made before that this one does not have.
    for ext in SUFFIXES {
        let p = file(ext);
        if !written.contains(&p) && existing.contains(&p) {
            let _ = std::fs::remove_file(&p);
        }
    }
    for w in &written {
        outln!("wrote {}", w.display());
    }
    outln!("took {:.1} s", started.elapsed().as_secs_f64());
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

fn write_limit(path: &Path, l: &Limit, spec: &SweepSpec) -> Result<()> {
    let csv = slip_csv(
        l,
        &spec.material(),
        spec.center(),
        spec.slope(),
        spec.phases()[0],
        DEFAULT_SAMPLES,
    );
    write(path, &csv)
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

fn describe(map: &SlipMap) -> Result<()> {
    let s = &map.summary;
    outln!(
        "steady state: {} after {} cycles, W = {:.6e}, rotation {:.3e} per cycle",
        s.state,
        s.cycles,
        s.dissipation,
        s.rotation_per_cycle
    );
    Ok(())
}
