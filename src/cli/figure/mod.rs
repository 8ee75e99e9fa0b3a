//! `shakedown figure NAME --out DIR`: run a preset and write its data as
//! CSV and its plot as SVG and PNG; `--from NAME.csv` redraws from the CSV
//! without running, `--resume` continues an interrupted sweep figure.

mod from;
pub(super) use from::check_cycle;
use from::*;

/// Samples of an elliptical cycle for each point of the regime map's
/// `lambda_2(phi)` curve: within `1 - cos(pi/32)` (0.5 %) of the limit, and
/// a quarter of the time of the default 64 (25 phases in seconds).
const CURVE_SAMPLES: usize = 32;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{anyhow, Result};
use clap::Args;
use shakedown::analysis::case::Case;
use shakedown::analysis::limit::{shakedown_limit, Limit, DEFAULT_SAMPLES};
use shakedown::analysis::limit_curve::{curve_csv, limit_curve, parse_curve_csv};
use shakedown::analysis::memory::{
    memory_points, memory_runs, ratchetting_onset, MemoryError, MemoryPoint,
};
use shakedown::analysis::regime::{RegimeCell, RegimeMap};
use shakedown::analysis::slip_map::{slip_map, SlipMap, SlipMapError};
use shakedown::analysis::sweep::SweepSpec;
use shakedown::analysis::sweep::{Axis, SweepLists};
use shakedown::figure::data::parse_sweep_csv;
use shakedown::figure::dissipation::memory_window;
use shakedown::figure::FigureError;
use shakedown::figure::{
    write_svg_png, DissipationPlot, Drawing, FigureStyle, Frame, MemoryPlot, RegimePlot,
    SlipMapPlot, SweepPoint, TimeOrigin,
};
use shakedown::io::parse::{parse_angle, parse_number, parse_values};
use shakedown::io::preset::{FigureKind, FigureSpec, Preset};

use shakedown::analysis::case::CaseParams;
use shakedown::io::csv::{
    fmt_number, read_slip_map, slip_csv, slip_map_metadata, sweep_metadata, Metadata,
    MetadataError, SlipMapFile,
};
use shakedown::io::cycle::{check_recorded_cycle, LOAD_CYCLE_KEY};
use shakedown::io::memory_csv::{memory_csv, read_memory_csv};
use shakedown::io::output::{check_file_stem, is_nonempty_file, same_file};
use shakedown::model::Polyline;

use super::batch::{
    lock_output, progress, refuse_input_as_output, report_interrupt, stream_sweep, write_file,
    INTERRUPTED,
};
use super::sweep::{job_key, spec, warn_failures, ListArgs};
use super::{load_preset, InputError, ModelArgs};

/// The flags of `shakedown figure`.
#[derive(Debug, Args)]
pub struct FigureArgs {
    /// The figure: a built-in preset (fig3 ... fig9, regime; see `shakedown presets`) or a path to a .toml file.
    #[arg(value_name = "NAME|FILE")]
    pub name: String,
    /// Directory to write NAME.csv, NAME.svg and NAME.png into (created if missing); with --from, the CSV's directory by default.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Replace the figure's files if they exist (without it, an existing
    /// NAME.csv, NAME.svg or NAME.png is refused and left untouched). The
    /// old files stay until the new ones are complete.
    #[arg(long)]
    pub force: bool,
    /// Redraw from a CSV this figure wrote (NAME.csv; a slip map also reads NAME_load.csv beside it), without running anything. The figure is drawn with the CSV's model (its header): lambda_2, lambda_3 and the title are those of the data. A CSV made with --cycle is redrawn only with --cycle and a file of the same content (its header's load-cycle sha256).
    #[arg(long, value_name = "FILE.csv", conflicts_with = "resume")]
    pub from: Option<PathBuf>,
    /// With --from: draw a partial CSV (an interrupted figure); the caption (and the title, with --title) then says "partial: k of n runs". Without it a partial CSV is refused.
    #[arg(long, requires = "from")]
    pub partial: bool,
    /// Continue an interrupted figure: keep the complete rows of DIR/NAME.csv, run the rest, then draw (sweep figures and the regime map).
    #[arg(long)]
    pub resume: bool,
    /// Slip maps (fig5, fig7): omega t at the bottom of the axes. auto starts at a slip-free instant (or the one with least slip), so no slip event is cut in two; or 0, or an angle (pi/2).
    #[arg(
        long,
        value_name = "auto|0|ANGLE",
        default_value = "auto",
        allow_hyphen_values = true
    )]
    pub time_origin: String,
    /// Where the figure goes: paper-1col (90 mm wide, 600 dpi), paper-2col (190 mm, 600 dpi) or slide (16:9, 1920 x 1080); sets the size, fonts and line widths.
    #[arg(long, value_name = "STYLE", default_value = "paper-2col")]
    pub style: String,
    /// Draw the caption's title on the figure (for slides); by default it is only written beside the figure, as NAME.caption.txt.
    #[arg(long)]
    pub title: bool,
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
const SUFFIXES: [&str; 6] = [
    ".csv",
    "_limit.csv",
    "_load.csv",
    ".svg",
    ".png",
    ".caption.txt",
];

/// Draw the plot into temporary files beside `svg` and `png`, then rename
/// them into place: an interrupted or failed drawing leaves the old ones.
pub(super) fn write_plot<D: Drawing>(plot: &D, svg: &Path, png: &Path) -> Result<()> {
    // The caption a journal prints under the figure, beside it.
    let caption = svg.with_extension("caption.txt");
    write(&caption, &(plot.caption() + "\n"))?;
    // The backends choose the format by extension: keep it last.
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

/// The folder a figure is written to: `--out`, else that of `--from`.
fn out_dir_of(args: &FigureArgs) -> Option<PathBuf> {
    match (&args.out, &args.from) {
        (Some(d), _) => Some(d.clone()),
        (None, Some(f)) => Some(
            f.parent()
                .filter(|p| !p.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
        ),
        (None, None) => None,
    }
}

/// The folder a figure is written to ([`out_dir_of`]), created, and its
/// `--style`: what every kind of figure (the presets', `design`,
/// `profile`) needs first. `redraw` names what `--from` reads, for the
/// message when neither `--out` nor `--from` is given.
pub(super) fn out_dir_and_style(args: &FigureArgs, redraw: &str) -> Result<(PathBuf, FigureStyle)> {
    let style: FigureStyle = args
        .style
        .parse()
        .map_err(|e| anyhow!(InputError(format!("--style {}: {e}", args.style))))?;
    let Some(out_dir) = out_dir_of(args) else {
        return Err(anyhow!(InputError(format!(
            "figure {}: --out DIR is needed (or --from FILE.csv to redraw {redraw})",
            args.name
        ))));
    };
    std::fs::create_dir_all(&out_dir).map_err(|e| {
        anyhow!(InputError(format!(
            "--out {}: cannot create the directory: {e}",
            out_dir.display()
        )))
    })?;
    Ok((out_dir, style))
}

/// Run `shakedown figure`. A refused or failed figure leaves no trace: an
/// output folder it created is removed again when nothing was written
/// into it.
pub fn figure(args: FigureArgs) -> Result<ExitCode> {
    if args.name == "design" {
        // The transient search is the paper's question, on its ellipse; a
        // frontier records no cycle, so none may be given to draw it.
        if let Some(c) = &args.model.cycle {
            return Err(anyhow!(InputError(format!(
                "--cycle {c}: figure design searches transients for the paper's elliptical cycle (docs/model.md section 10), not a polyline: drop --cycle"
            ))));
        }
        return super::design::figure(&args);
    }
    if args.name == "profile" {
        return super::run::profile_figure(&args);
    }
    let created = out_dir_of(&args).filter(|d| std::fs::symlink_metadata(d).is_err());
    let result = figure_into(args);
    if let (Err(_), Some(dir)) = (&result, created) {
        // Only an empty folder: `remove_dir` leaves anything written.
        let _ = std::fs::remove_dir(dir);
    }
    result
}

fn figure_into(args: FigureArgs) -> Result<ExitCode> {
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
    let (out_dir, style) = out_dir_and_style(&args, "its CSV")?;
    let origin: TimeOrigin = args.time_origin.parse().map_err(|e| {
        anyhow!(InputError(format!(
            "--time-origin {}: {e}: expected auto, 0 or an angle",
            args.time_origin
        )))
    })?;
    // A redraw is drawn with the model of its data: the --from file's
    // header gives every model flag the command line does not.
    let header = args.from.as_deref().map(from_header).transpose()?;
    let mut model = match &header {
        Some(h) => header_model(&args.model, h),
        None => args.model.clone(),
    };
    // A redraw is drawn with the cycle its data was made with, checked
    // before anything else of the header is used, and then named as the
    // file records it (the same content under any file name).
    let mut preset = preset;
    let base = preset.params.clone();
    if let (Some(f), Some(h)) = (&args.from, &header) {
        let given = match &args.model.cycle {
            Some(c) => Some(super::cycle_file(c)?),
            None => preset.params.cycle.take(),
        };
        check_cycle(f, h, given.as_ref())?;
        preset.params.cycle = as_recorded(h, given);
        model.cycle = None;
    }
    let used = model
        .apply(preset.params.clone())
        .map_err(|e| match &args.from {
            Some(f) => anyhow!(InputError(format!(
                "--from {}: its header: {e}",
                f.display()
            ))),
            None => e,
        })?;
    if fig.kind == FigureKind::Regime {
        if let Some(p) = &used.cycle {
            return Err(anyhow!(InputError(format!(
                "figure {stem}: the regime map is drawn over the phase phi, which the load cycle {} has not: drop --cycle",
                p.name()
            ))));
        }
    }
    let mut notes = model_note(&base, &used);
    let file = |ext: &str| out_dir.join(format!("{stem}{ext}"));
    let preset_path = Path::new(&args.name);
    if preset_path.exists() {
        for ext in SUFFIXES {
            refuse_input_as_output("--out", &file(ext), &[("preset file", preset_path)])?;
        }
    }
    // No output may be one of the inputs, under any name.
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(slip) = &args.lists.initial_slip {
        inputs.push(("--initial-slip file", Path::new(slip)));
    }
    if let Some(from) = &args.from {
        inputs.push(("--from file", from.as_path()));
    }
    inputs.extend(args.model.input_files());
    for ext in SUFFIXES {
        let out = file(ext);
        let reads_it = ext == ".csv" && args.from.as_deref().is_some_and(|f| same_file(f, &out));
        if !reads_it {
            refuse_input_as_output("--out", &out, &inputs)?;
        }
    }
    let redraw = args.from.is_some();
    if redraw && !args.force {
        if let Some(old) = [".svg", ".png"]
            .iter()
            .map(|e| file(e))
            .find(|p| is_nonempty_file(p))
        {
            return Err(anyhow!(InputError(format!(
                "--out {}: {} exists: add --force to replace the figure's plots",
                out_dir.display(),
                old.display()
            ))));
        }
    }
    // A figure made before is replaced only when the user asks: with
    // --force, or by redrawing (--from) or continuing (--resume) it.
    let existing: Vec<PathBuf> = SUFFIXES
        .iter()
        .map(|e| file(e))
        .filter(|p| is_nonempty_file(p))
        .collect();
    if !existing.is_empty() && !args.force && !args.resume && !redraw {
        return Err(anyhow!(InputError(format!(
            "--out {}: {} exists (a figure made before): add --force to replace the figure's files, --resume to continue it or --from to redraw it",
            out_dir.display(),
            existing[0].display()
        ))));
    }
    let replace = !existing.is_empty() && args.force && !args.resume && !redraw;
    // One writer per figure: the lock is DIR/NAME.lock.
    let _lock = lock_output("--out", &out_dir.join(&stem))?;
    let base_title = fig
        .title
        .clone()
        .unwrap_or_else(|| preset.description.clone());
    // The title (and so the caption) says where the model is not the
    // preset's, and how much of the table a partial redraw holds.
    let titled = |notes: &[String]| {
        if notes.is_empty() {
            base_title.clone()
        } else {
            format!("{base_title} ({})", notes.join(", "))
        }
    };
    let frame = |title: String| Frame {
        title,
        show_title: args.title,
        style,
    };
    let started = Instant::now();
    let mut written = Vec::new();
    if args.resume && !matches!(fig.kind, FigureKind::Dissipation | FigureKind::Regime) {
        errln!("note: --resume applies to sweep figures; {stem} runs in full");
    }
    match fig.kind {
        FigureKind::Dissipation => {
            let spec = sweep_spec(&args, &model, &preset)?;
            notes.splice(0..0, grid_note(&preset.sweep, &spec, fig.axis));
            let (points, partial) = match sweep_points(&args, &spec, &file(".csv"), replace)? {
                Ok(p) => p,
                Err(code) => return Ok(code),
            };
            note_partial(&mut notes, partial.as_ref())?;
            if !redraw {
                written.push(file(".csv"));
            }
            let limit_file = (!redraw).then(|| file("_limit.csv"));
            let limit = mark_limit(&fig, &spec, &points, limit_file, &mut written)?;
            if let Some((l1, l3)) = memory_window(&points) {
                outln!("the transients disagree from lambda = {l1} to lambda_3 = {l3}");
            }
            let plot = DissipationPlot {
                points: &points,
                axis: fig.axis,
                ratchetting: fig.ratchetting,
                lines: fig.lines,
                frame: frame(titled(&notes)),
                limit,
            };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
            outln!("{} runs", points.len());
        }
        FigureKind::Regime => {
            let spec = sweep_spec(&args, &model, &preset)?;
            if spec.initials().len() != 1 {
                return Err(anyhow!(InputError(format!(
                    "figure {stem}: the regime map is for one transient, but {} are given: pick one with --initial",
                    spec.initials().len()
                ))));
            }
            let (points, partial) = match sweep_points(&args, &spec, &file(".csv"), replace)? {
                Ok(p) => p,
                Err(code) => return Ok(code),
            };
            note_partial(&mut notes, partial.as_ref())?;
            if !redraw {
                written.push(file(".csv"));
            }
            let map = RegimeMap::from_cells(points.iter().map(|p| {
                (
                    p.load_factor,
                    p.phase,
                    RegimeCell {
                        state: p.state,
                        dissipation: p.dissipation,
                    },
                )
            }));
            // A redraw takes the curve from beside its CSV when there is
            // one (checked as the CSV is); else it is computed and written
            // to --out, which never replaces a file without --force.
            let stored = match &args.from {
                Some(f) => stored_curve(
                    &f.with_file_name(format!("{stem}_limit.csv")),
                    &spec,
                    map.phases(),
                )?,
                None => None,
            };
            let curve = match stored {
                Some(c) => c,
                None if fig.limit => {
                    let pts = limit_curve(
                        &spec.material(),
                        spec.center(),
                        spec.slope(),
                        map.phases(),
                        &spec.disc(),
                        CURVE_SAMPLES,
                    );
                    let curve_file = file("_limit.csv");
                    if redraw && !args.force && is_nonempty_file(&curve_file) {
                        return Err(anyhow!(InputError(format!(
                            "--out {}: {} exists: add --force to replace it",
                            out_dir.display(),
                            curve_file.display()
                        ))));
                    }
                    write(
                        &curve_file,
                        &(curve_metadata(&spec).render() + &curve_csv(&pts)),
                    )?;
                    written.push(curve_file);
                    pts.iter()
                        .filter_map(|p| p.limit.as_ref().ok().map(|l| (p.phase, l.0)))
                        .collect()
                }
                None => Vec::new(),
            };
            let plot = RegimePlot {
                map: &map,
                limit: &curve,
                frame: frame(format!(
                    "{}, transient {}",
                    titled(&notes),
                    spec.initials()[0].name()
                )),
                paper_lines: true,
            };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
            outln!("{} runs", points.len());
        }
        FigureKind::Memory => {
            let spec = sweep_spec(&args, &model, &preset)?;
            notes.splice(0..0, grid_note(&preset.sweep, &spec, fig.axis));
            let points = match &args.from {
                Some(f) => from_memory_csv(f, &spec)?,
                None => {
                    let jobs = spec.jobs();
                    let bar = progress(jobs.len());
                    let runs = memory_runs(&spec, &|| bar.inc(1)).map_err(|e| input(e.into()))?;
                    bar.finish_and_clear();
                    let points = memory_points(&runs);
                    let mut meta = sweep_metadata(&spec);
                    meta.set("table", "memory");
                    write(&file(".csv"), &(meta.render() + &memory_csv(&points)))?;
                    written.push(file(".csv"));
                    points
                }
            };
            let limit_file = (!redraw).then(|| file("_limit.csv"));
            let limit = mark_limit(&fig, &spec, &[], limit_file, &mut written)?;
            if let Some(l3) = ratchetting_onset(&points) {
                outln!("lambda_3 = {l3} (every transient ratchets from here on)");
            }
            let plot = MemoryPlot {
                points: &points,
                frame: frame(titled(&notes)),
                limit,
            };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
        }
        FigureKind::SlipMap => {
            let (map, initial) = match (&args.from, &header) {
                (Some(f), Some(h)) => (
                    read_slip_map_files(f, used.cycle.as_ref())?,
                    h.get("initial").unwrap_or_default().to_string(),
                ),
                _ => {
                    let case = single_case(&args, &preset)?;
                    let map = slip_map(&case).map_err(|e| input(e.into()))?;
                    let meta = slip_map_metadata(&case, &map).render();
                    write(&file(".csv"), &(meta.clone() + &map.csv()))?;
                    write(&file("_load.csv"), &(meta + &map.load_csv()))?;
                    written.push(file(".csv"));
                    written.push(file("_load.csv"));
                    (map, case.initial().name())
                }
            };
            describe(&map)?;
            // The preset's title names its case (fig5: λ = 7, φ = 0): the
            // caption says where the case drawn is another.
            let preset_initial = preset.initial_path.clone().unwrap_or(base.initial.clone());
            let case_notes = case_note(&base, &preset_initial, &map.cycle, &initial);
            notes.splice(0..0, case_notes);
            let plot = SlipMapPlot {
                map: &map,
                frame: frame(titled(&notes)),
                origin,
            };
            outln!(
                "drawn from omega t = {:.4} pi",
                origin.resolve(&map) / std::f64::consts::PI
            );
            write_plot(&plot, &file(".svg"), &file(".png"))?;
        }
    }
    written.push(file(".svg"));
    written.push(file(".png"));
    written.push(file(".caption.txt"));
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

/// Add "partial: k of n runs" to the title's notes of a partial redraw.
fn note_partial(notes: &mut Vec<String>, partial: Option<&Partial>) -> Result<()> {
    if let Some(p) = partial {
        notes.push(format!("partial: {} of {} runs", p.kept, p.total));
        outln!("partial: {} of {} runs drawn", p.kept, p.total);
    }
    Ok(())
}

fn sweep_spec(args: &FigureArgs, model: &ModelArgs, preset: &Preset) -> Result<SweepSpec> {
    spec(
        model,
        &args.lists,
        preset.params.clone(),
        Some(&preset.sweep),
    )
}

/// `lambda_2` when the figure marks it and the sweep has one phase (the
/// phase of `points` when given, else the sweep's).
fn limit_of(fig: &FigureSpec, spec: &SweepSpec, points: &[SweepPoint]) -> Result<Option<Limit>> {
    let mut phases: Vec<f64> = if points.is_empty() {
        spec.phases().to_vec()
    } else {
        points.iter().map(|p| p.phase).collect()
    };
    phases.sort_by(f64::total_cmp);
    phases.dedup();
    if !fig.limit || fig.axis != Axis::Lambda || phases.len() != 1 {
        return Ok(None);
    }
    if let Some(job) = spec.jobs().first().filter(|_| spec.polyline().is_some()) {
        let cycle = spec.cycle(job)?;
        let l = shakedown::analysis::limit::cycle_limit(
            &spec.material(),
            &cycle,
            &spec.disc(),
            DEFAULT_SAMPLES,
        )?;
        return Ok(Some(l));
    }
    let l = shakedown_limit(
        &spec.material(),
        spec.center(),
        spec.slope(),
        phases[0],
        &spec.disc(),
        DEFAULT_SAMPLES,
    )?;
    Ok(Some(l))
}

/// `lambda_2` as the figure marks it ([`limit_of`]), printed; a figure
/// that is made (not redrawn) also writes it to `file` (`NAME_limit.csv`),
/// which then joins `written`.
fn mark_limit(
    fig: &FigureSpec,
    spec: &SweepSpec,
    points: &[SweepPoint],
    file: Option<PathBuf>,
    written: &mut Vec<PathBuf>,
) -> Result<Option<f64>> {
    let Some(l) = limit_of(fig, spec, points)? else {
        return Ok(None);
    };
    if let Some(file) = file {
        write_limit(&file, &l, spec)?;
        written.push(file);
    }
    outln!("lambda_2 = {:.6} (linear programme)", l.load_factor);
    Ok(Some(l.load_factor))
}

fn write_limit(path: &Path, l: &Limit, spec: &SweepSpec) -> Result<()> {
    if let Some(p) = spec.polyline() {
        let csv = shakedown::io::csv::polyline_slip_csv(l, &spec.material(), spec.center(), p);
        return write(path, &csv);
    }
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
        p.initial = super::parse_initial(t).map_err(|e| super::bad_flag("initial", t, e))?;
    }
    let mut case = Case::from_params(&p).map_err(|e| anyhow!(InputError(e.to_string())))?;
    if let Some(text) = &args.lists.initial_path {
        case.set_initial(super::custom_path(text, &case.material())?)?;
    } else if args.lists.initials.is_none() {
        if let Some(path) = &preset.initial_path {
            case.set_initial(path.clone())?;
        }
    }
    Ok(case)
}
