//! `shakedown figure NAME --out DIR`: run a preset and write its data as
//! CSV and its plot as SVG and PNG; `--from NAME.csv` redraws from the CSV
//! without running, `--resume` continues an interrupted sweep figure.

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
    memory_csv, memory_points, memory_runs, ratchetting_onset, MemoryError, MemoryPoint,
};
use shakedown::analysis::regime::{RegimeCell, RegimeMap};
use shakedown::analysis::slip_map::{slip_map, SlipMap, SlipMapError};
use shakedown::analysis::sweep::Axis;
use shakedown::analysis::sweep::SweepSpec;
use shakedown::figure::data::parse_sweep_csv;
use shakedown::figure::dissipation::memory_window;
use shakedown::figure::FigureError;
use shakedown::figure::{
    write_svg_png, DissipationPlot, Drawing, FigureStyle, MemoryPlot, RegimePlot, SlipMapPlot,
    SweepPoint, TimeOrigin,
};
use shakedown::io::parse::{parse_angle, parse_number, parse_values};
use shakedown::io::preset::{FigureKind, FigureSpec, Preset};

use shakedown::analysis::case::CaseParams;
use shakedown::io::csv::{
    fmt_number, read_slip_map, slip_csv, slip_map_metadata, sweep_metadata, Metadata,
    MetadataError, SlipMapFile,
};
use shakedown::io::memory_csv::read_memory_csv;
use shakedown::io::output::{check_file_stem, is_nonempty_file, same_file};

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
    /// Redraw from a CSV this figure wrote (NAME.csv; a slip map also reads NAME_load.csv beside it), without running anything. The figure is drawn with the CSV's model (its header): lambda_2, lambda_3 and the title are those of the data.
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

/// Where a figure's new table grows while the one made before stays:
/// `.NAME.csv.new` beside it.
fn pending_path(csv_path: &Path) -> PathBuf {
    let name = csv_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    csv_path.with_file_name(format!(".{name}.new"))
}

/// Largest header read before the rest of a `--from` file is sized.
const HEADER_BYTES: u64 = 1 << 16;

/// The `# key = value` header of the `--from` file, read through the
/// checked reader (regular files only, at most [`HEADER_BYTES`]).
fn from_header(from: &Path) -> Result<Metadata> {
    let head = shakedown::io::read::read_head(from, HEADER_BYTES).map_err(|e| {
        anyhow!(InputError(format!(
            "--from {}: {e}",
            shakedown::io::read::escape_text(&from.to_string_lossy(), 200)
        )))
    })?;
    Ok(Metadata::parse(&String::from_utf8_lossy(&head)))
}

/// The model flags of a redraw: those given on the command line, and for
/// every other one the value the `--from` file's header records, so that
/// every line derived from the model (lambda_2, the title) is that of the
/// data. A flag given with another value than the header's is refused
/// when the header is checked.
fn header_model(given: &ModelArgs, meta: &Metadata) -> ModelArgs {
    let mut m = given.clone();
    let fill = |slot: &mut Option<String>, key: &str| {
        if slot.is_none() {
            *slot = meta.get(key).map(str::to_string);
        }
    };
    fill(&mut m.psi, "psi");
    fill(&mut m.center, "center");
    fill(&mut m.friction, "friction");
    fill(&mut m.nu, "nu");
    fill(&mut m.plane, "plane");
    fill(&mut m.nodes, "nodes");
    fill(&mut m.steps, "steps");
    fill(&mut m.max_cycles, "max-cycles");
    if meta.get("verdicts") == Some("run-out") {
        m.run_out = true;
    }
    m
}

/// The keys of a sweep header that say which table it is (the grid), as
/// against the model it was run with.
const GRID_KEYS: [&str; 4] = ["table", "lambda", "phi", "initial"];

/// Where the model of a figure differs from its preset's (the paper's), in
/// a few words for its title and caption: `f = 0.2, N = 32`.
fn model_note(base: &CaseParams, used: &CaseParams) -> Vec<String> {
    let mut v = Vec::new();
    let num = fmt_number;
    if used.friction != base.friction {
        v.push(format!("f = {}", num(used.friction)));
    }
    if used.poisson != base.poisson {
        v.push(format!("ν = {}", num(used.poisson)));
    }
    if used.plane != base.plane {
        v.push(format!("plane {}", used.plane));
    }
    if used.slope != base.slope {
        v.push(format!("ψ = {}", num(used.slope)));
    }
    if used.center != base.center {
        v.push(format!(
            "A = ({}, {})",
            num(used.center.0),
            num(used.center.1)
        ));
    }
    if used.nodes != base.nodes {
        v.push(format!("N = {}", used.nodes));
    }
    if used.steps != base.steps {
        v.push(format!("{} increments per cycle", used.steps));
    }
    if used.max_cycles != base.max_cycles {
        v.push(format!("at most {} cycles", used.max_cycles));
    }
    if used.safe_state != base.safe_state {
        v.push(if used.safe_state {
            "shakedown proven by safe states".to_string()
        } else {
            "shakedown run out".to_string()
        });
    }
    v
}

/// A sweep figure's points, and how much of its table they are.
type Drawn = (Vec<SweepPoint>, Option<Partial>);

/// How much of a sweep figure's table a `--from` CSV holds.
struct Partial {
    kept: usize,
    total: usize,
}

/// The points of a sweep figure's CSV given with `--from`, checked as
/// `--resume` checks a file: read through a size cap (regular files
/// only), its header must be this figure's table (the grid of the preset
/// and the list flags) with the model of `spec` (the file's own, from
/// [`header_model`]), and its rows must be valid, in job order. A partial
/// file is refused unless `partial`; then the complete rows are drawn.
fn from_sweep_csv(
    from: &Path,
    spec: &SweepSpec,
    keys: &[String],
    table: &str,
    partial: bool,
) -> Result<(Vec<SweepPoint>, Option<Partial>)> {
    let shown = shakedown::io::read::escape_text(&from.to_string_lossy(), 200);
    let mut meta = sweep_metadata(spec);
    meta.set("table", table);
    let header = meta.preamble(shakedown::analysis::sweep::CSV_HEADER);
    let cap = header.len() as u64 + 4096 + 512 * (keys.len() as u64 + 1);
    let bad = |e: &dyn std::fmt::Display| anyhow!(InputError(format!("--from {shown}: {e}")));
    let bytes = shakedown::io::read::read_capped(from, cap).map_err(|e| bad(&e))?;
    let found = Metadata::parse(&String::from_utf8_lossy(&bytes));
    meta.check(&found).map_err(|e| match &e {
        MetadataError::Differs { key, .. } | MetadataError::Missing { key, .. }
            if GRID_KEYS.contains(&key.as_str()) =>
        {
            bad(&format_args!(
                "{e}: it is not this figure's table (give the list flags that made it)"
            ))
        }
        MetadataError::Differs { key, .. } => bad(&format_args!(
            "{e}: drop --{key}, the figure is drawn with the CSV's model"
        )),
        _ => bad(&e),
    })?;
    let row_key =
        shakedown::io::csv::sweep_row_key_capped(spec.options().convergence.max_cycles as u64);
    let point =
        shakedown::io::batch::resume_point(&bytes, &header, keys, row_key).map_err(|e| bad(&e))?;
    let cut = point.kept < keys.len() || point.bytes < bytes.len();
    if cut && !partial {
        return Err(bad(&format_args!(
            "it is partial: {} of {} runs (an interrupted figure): finish it with --resume and --out its folder, or draw what there is with --partial",
            point.kept,
            keys.len()
        )));
    }
    if point.kept == 0 {
        return Err(bad(&"it has no complete row: there is nothing to draw"));
    }
    let text =
        std::str::from_utf8(&bytes[..point.bytes]).map_err(|_| bad(&"it is not UTF-8 text"))?;
    let points = parse_sweep_csv(text).map_err(|e| bad(&e))?;
    let partial = (point.kept < keys.len()).then_some(Partial {
        kept: point.kept,
        total: keys.len(),
    });
    Ok((points, partial))
}

fn read(flag: &str, path: &Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|e| {
        anyhow!(InputError(format!(
            "{flag} {}: cannot read it: {e}",
            path.display()
        )))
    })
}

/// A sweep figure's points: from `--from`, or by running the sweep (row by
/// row into the CSV, resumable: [`stream_sweep`]) and reading the CSV back,
/// so that a redraw from the CSV draws exactly the same figure.
///
/// With `replace` (an existing figure and `--force`), the table is written
/// beside the old one and renamed over it only once it is complete, so an
/// interrupted run leaves the figure made before whole.
fn sweep_points(
    args: &FigureArgs,
    spec: &SweepSpec,
    csv_path: &Path,
    replace: bool,
) -> Result<std::result::Result<Drawn, ExitCode>> {
    let jobs = spec.jobs();
    let keys: Vec<String> = jobs.iter().map(|j| job_key(spec, j)).collect();
    if let Some(from) = &args.from {
        return from_sweep_csv(from, spec, &keys, "sweep", args.partial).map(Ok);
    }
    // With --force over an existing figure the new table grows beside the
    // old one (`.NAME.csv.new`) and replaces it only when complete; an
    // interrupted one is kept there, and --resume continues it.
    let pending = pending_path(csv_path);
    let continuing = args.resume && pending.exists();
    let target = if replace || continuing {
        pending.clone()
    } else {
        csv_path.to_path_buf()
    };
    let replace = replace || continuing;
    let mut failed = Vec::new();
    let streamed = stream_sweep(
        spec,
        &jobs,
        &keys,
        Some(&target),
        args.resume,
        replace || args.force,
        |row, _| {
            if let Err(e) = &row.outcome {
                failed.push(e.to_string());
            }
        },
    )?;
    let out = streamed.out;
    if !streamed.complete {
        if replace {
            let done = out.kept + out.written;
            drop(out);
            errln!(
                "interrupted: {done} of {} runs are in {}; the figure made before is unchanged; run the same command with --resume to finish",
                jobs.len(),
                target.display()
            );
            return Ok(Err(ExitCode::from(INTERRUPTED)));
        }
        errln!("no plot was drawn");
        return Ok(Err(report_interrupt(&out, jobs.len())));
    }
    warn_failures(&failed, out.written);
    drop(out);
    if replace {
        std::fs::rename(&target, csv_path)
            .map_err(|e| anyhow!("--out: cannot replace {}: {e}", csv_path.display()))?;
    }
    let text = read("--out", csv_path)?;
    let points = parse_sweep_csv(&text)
        .map_err(|e| anyhow!("{}: cannot read it back: {e}", csv_path.display()))?;
    Ok(Ok((points, None)))
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

/// Run `shakedown figure`. A refused or failed figure leaves no trace: an
/// output folder it created is removed again when nothing was written
/// into it.
pub fn figure(args: FigureArgs) -> Result<ExitCode> {
    if args.name == "design" {
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
    let Some(out_dir) = out_dir_of(&args) else {
        return Err(anyhow!(InputError(
            "figure: --out DIR is needed (or --from FILE.csv to redraw)".into()
        )));
    };
    std::fs::create_dir_all(&out_dir).map_err(|e| {
        anyhow!(InputError(format!(
            "--out {}: cannot create the directory: {e}",
            out_dir.display()
        )))
    })?;
    let style: FigureStyle = args
        .style
        .parse()
        .map_err(|e| anyhow!(InputError(format!("--style {}: {e}", args.style))))?;
    let origin: TimeOrigin = args.time_origin.parse().map_err(|e| {
        anyhow!(InputError(format!(
            "--time-origin {}: {e}: expected auto, 0 or an angle",
            args.time_origin
        )))
    })?;
    // A redraw is drawn with the model of its data: the --from file's
    // header gives every model flag the command line does not.
    let model = match &args.from {
        Some(f) => header_model(&args.model, &from_header(f)?),
        None => args.model.clone(),
    };
    let used = model
        .apply(preset.params.clone())
        .map_err(|e| match &args.from {
            Some(f) => anyhow!(InputError(format!(
                "--from {}: its header: {e}",
                f.display()
            ))),
            None => e,
        })?;
    let mut notes = model_note(&preset.params, &used);
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
    let started = Instant::now();
    let mut written = Vec::new();
    if args.resume && !matches!(fig.kind, FigureKind::Dissipation | FigureKind::Regime) {
        errln!("note: --resume applies to sweep figures; {stem} runs in full");
    }
    match fig.kind {
        FigureKind::Dissipation => {
            let spec = sweep_spec(&args, &model, &preset)?;
            let (points, partial) = match sweep_points(&args, &spec, &file(".csv"), replace)? {
                Ok(p) => p,
                Err(code) => return Ok(code),
            };
            note_partial(&mut notes, partial.as_ref())?;
            if !redraw {
                written.push(file(".csv"));
            }
            let limit = limit_of(&fig, &spec, &points)?;
            if let Some(l) = &limit {
                if !redraw {
                    write_limit(&file("_limit.csv"), l, &spec)?;
                    written.push(file("_limit.csv"));
                }
                outln!("lambda_2 = {:.6} (linear programme)", l.load_factor);
            }
            if let Some((l1, l3)) = memory_window(&points) {
                outln!("the transients disagree from lambda = {l1} to lambda_3 = {l3}");
            }
            let plot = DissipationPlot {
                points: &points,
                axis: fig.axis,
                ratchetting: fig.ratchetting,
                lines: fig.lines,
                title: titled(&notes),
                show_title: args.title,
                style,
                limit: limit.as_ref().map(|l| l.load_factor),
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
                title: format!(
                    "{}, transient {}",
                    titled(&notes),
                    spec.initials()[0].name()
                ),
                show_title: args.title,
                style,
                paper_lines: true,
            };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
            outln!("{} runs", points.len());
        }
        FigureKind::Memory => {
            let spec = sweep_spec(&args, &model, &preset)?;
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
            let limit = limit_of(&fig, &spec, &[])?;
            if let Some(l) = &limit {
                if !redraw {
                    write_limit(&file("_limit.csv"), l, &spec)?;
                    written.push(file("_limit.csv"));
                }
                outln!("lambda_2 = {:.6} (linear programme)", l.load_factor);
            }
            if let Some(l3) = ratchetting_onset(&points) {
                outln!("lambda_3 = {l3} (every transient ratchets from here on)");
            }
            let plot = MemoryPlot {
                points: &points,
                title: titled(&notes),
                show_title: args.title,
                style,
                limit: limit.as_ref().map(|l| l.load_factor),
            };
            write_plot(&plot, &file(".svg"), &file(".png"))?;
        }
        FigureKind::SlipMap => {
            let map = match &args.from {
                Some(f) => read_slip_map_files(f)?,
                None => {
                    let case = single_case(&args, &preset)?;
                    let map = slip_map(&case).map_err(|e| input(e.into()))?;
                    let meta = slip_map_metadata(&case, &map).render();
                    write(&file(".csv"), &(meta.clone() + &map.csv()))?;
                    write(&file("_load.csv"), &(meta + &map.load_csv()))?;
                    written.push(file(".csv"));
                    written.push(file("_load.csv"));
                    map
                }
            };
            describe(&map)?;
            let plot = SlipMapPlot {
                map: &map,
                title: titled(&notes),
                show_title: args.title,
                style,
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
        case.initial = super::custom_path(text, &case.material)?;
    } else if args.lists.initials.is_none() {
        if let Some(path) = &preset.initial_path {
            case.initial = path.clone();
        }
    }
    Ok(case)
}

/// The header of the regime map's `lambda_2(phi)` curve (`NAME_limit.csv`).
fn curve_metadata(spec: &SweepSpec) -> Metadata {
    let mut meta = sweep_metadata(spec);
    meta.set("table", "limit-curve");
    meta.set("samples", CURVE_SAMPLES);
    meta
}

/// The regime map's stored `lambda_2(phi)` curve beside a `--from` CSV,
/// read through the checked reader: `None` when there is no such file;
/// bad input when it is not a regular file, too large, not this map's
/// curve (header) or its rows are not `lambda_2 > 0` at the map's phases.
fn stored_curve(path: &Path, spec: &SweepSpec, phases: &[f64]) -> Result<Option<Vec<(f64, f64)>>> {
    if std::fs::symlink_metadata(path).is_err() {
        return Ok(None);
    }
    let shown = shakedown::io::read::escape_text(&path.to_string_lossy(), 200);
    let bad = |e: &dyn std::fmt::Display| {
        anyhow!(InputError(format!(
            "--from: the curve beside it, {shown}: {e}"
        )))
    };
    let meta = curve_metadata(spec);
    let cap = meta.render().len() as u64 + 4096 + 128 * phases.len() as u64;
    let text = shakedown::io::read::read_text_capped(path, cap).map_err(|e| bad(&e))?;
    meta.check(&Metadata::parse(&text)).map_err(|e| bad(&e))?;
    let curve = parse_curve_csv(&text).ok_or_else(|| bad(&"it is not a lambda_2(phi) table"))?;
    let mut at = 0;
    for &(phi, l2) in &curve {
        // Phases in the map's order; a failed phase has no row.
        let Some(k) = phases[at..].iter().position(|&p| p == phi) else {
            return Err(bad(&format_args!(
                "phi = {phi} is not a phase of the map (or is out of order, or repeated)"
            )));
        };
        at += k + 1;
        if !(l2.is_finite() && l2 > 0.0) {
            return Err(bad(&format_args!(
                "lambda_2 = {l2} at phi = {phi} is not positive"
            )));
        }
    }
    Ok(Some(curve))
}

/// The memory figure's points from its `--from` CSV, through the checked
/// reader: bounded, regular files only, the header this figure's with the
/// model of `spec` (the file's own), every row a valid point of the grid.
fn from_memory_csv(from: &Path, spec: &SweepSpec) -> Result<Vec<MemoryPoint>> {
    let shown = shakedown::io::read::escape_text(&from.to_string_lossy(), 200);
    let bad = |e: &dyn std::fmt::Display| anyhow!(InputError(format!("--from {shown}: {e}")));
    let mut meta = sweep_metadata(spec);
    meta.set("table", "memory");
    let mut grid: Vec<(f64, f64)> = Vec::new();
    for j in spec.jobs() {
        if !grid.contains(&(j.load_factor, j.phase)) {
            grid.push((j.load_factor, j.phase));
        }
    }
    let cap = meta.render().len() as u64 + 4096 + 256 * grid.len() as u64;
    let bytes = shakedown::io::read::read_capped(from, cap).map_err(|e| bad(&e))?;
    read_memory_csv(&bytes, &meta, &grid, spec.initials().len()).map_err(|e| bad(&e))
}

/// The load table beside a slip map's CSV: `NAME_load.csv` for `NAME.csv`.
fn load_file_of(map: &Path) -> PathBuf {
    let stem = map
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    map.with_file_name(format!("{stem}_load.csv"))
}

/// A slip map read back from the CSV `from` and its load table beside it
/// (`NAME_load.csv`), as `figure fig5` (or `fig7`) wrote them: nothing is
/// run. A file that is not such a table, or is cut short, is bad input
/// named in one line.
fn read_slip_map_files(from: &Path) -> Result<SlipMap> {
    use shakedown::io::read::{escape_text, read_text_capped};
    let load = load_file_of(from);
    // Sized by the header (nodes x rows, at most 2^26 cells as the reader
    // checks), then read through the checked reader: regular files only.
    let bad = |file: &Path, e: &dyn std::fmt::Display| {
        anyhow!(InputError(format!(
            "--from {}: {e}",
            escape_text(&file.to_string_lossy(), 200)
        )))
    };
    let head_bytes =
        shakedown::io::read::read_head(from, HEADER_BYTES).map_err(|e| bad(from, &e))?;
    let head = Metadata::parse(&String::from_utf8_lossy(&head_bytes));
    let count = |k: &str| head.get(k).and_then(|v| v.parse::<u64>().ok()).unwrap_or(0);
    let cells = count("nodes").saturating_mul(count("rows")).min(1 << 26);
    let map_cap = HEADER_BYTES + 64 * cells;
    let load_cap = HEADER_BYTES + 160 * (count("rows").min(1 << 26) + 1);
    // Without a slip map's header, its first bytes are enough to say so.
    let map_text = if cells == 0 {
        String::from_utf8_lossy(&head_bytes).into_owned()
    } else {
        read_text_capped(from, map_cap).map_err(|e| bad(from, &e))?
    };
    let load_text = read_text_capped(&load, load_cap).map_err(|e| {
        bad(
            from,
            &format_args!("its load table {}: {e}", load.display()),
        )
    })?;
    read_slip_map(&map_text, &load_text).map_err(|e| {
        let file = match e.file {
            SlipMapFile::Map => from,
            SlipMapFile::Load => &load,
        };
        anyhow!(InputError(format!(
            "--from {}: cannot redraw a slip map from it: {e}",
            file.display()
        )))
    })
}

fn describe(map: &SlipMap) -> Result<()> {
    let s = &map.outcome;
    outln!(
        "steady state: {} after {} cycles, W = {:.6e}, rotation {:.3e} per cycle",
        s.state(),
        s.cycles,
        s.dissipation,
        s.rotation_per_cycle
    );
    Ok(())
}
