//! `figure --from`: reading back what a figure wrote (its sweep table, the
//! regime map's curve, the memory table and slip maps) through the checked
//! readers of `io/`, with the model its header names.

use super::*;

/// Where a figure's new table grows while the one made before stays:
/// `.NAME.csv.new` beside it.
pub(super) fn pending_path(csv_path: &Path) -> PathBuf {
    let name = csv_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    csv_path.with_file_name(format!(".{name}.new"))
}

/// Largest header read before the rest of a `--from` file is sized.
pub(super) const HEADER_BYTES: u64 = 1 << 16;

/// The `# key = value` header of the `--from` file, read through the
/// checked reader (regular files only, at most [`HEADER_BYTES`]).
pub(super) fn from_header(from: &Path) -> Result<Metadata> {
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
pub(super) fn header_model(given: &ModelArgs, meta: &Metadata) -> ModelArgs {
    let mut m = given.clone();
    let fill = |slot: &mut Option<String>, key: &str| {
        if slot.is_none() {
            *slot = meta.get(key).map(str::to_string);
        }
    };
    // A polyline's file records no slope (`psi = none`) but its cycle by
    // content, which only the user can give back (`--cycle`, checked by
    // [`check_cycle`]).
    if meta.get(LOAD_CYCLE_KEY).is_none() {
        fill(&mut m.psi, "psi");
    }
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

/// The `--from` file `from`, whose header is `meta`, is drawn with the
/// cycle it was made with: a polyline file with its own cycle (`--cycle`
/// or the preset's, the same sha256 as the header's `load-cycle`), a file
/// of the paper's ellipse without one. Anything else is bad input in one
/// line naming both cycles, so a polyline map is never drawn as an
/// ellipse, nor one cycle's data with another's.
pub(in crate::cli) fn check_cycle(
    from: &Path,
    meta: &Metadata,
    cycle: Option<&Polyline>,
) -> Result<()> {
    check_recorded_cycle(meta.get(LOAD_CYCLE_KEY), cycle).map_err(|e| {
        anyhow!(InputError(format!(
            "--from {}: {e}",
            shakedown::io::read::escape_text(&from.to_string_lossy(), 200)
        )))
    })
}

/// The cycle `given` (checked by [`check_cycle`]) under the name the
/// `--from` file records: the same content, and so the same headers and
/// caption as when the file was made, whatever its file is called now.
pub(super) fn as_recorded(meta: &Metadata, given: Option<Polyline>) -> Option<Polyline> {
    let recorded = meta.get(LOAD_CYCLE_KEY)?;
    let given = given?;
    if given.name() == recorded {
        return Some(given);
    }
    // Same vertices, so it is as valid as `given`.
    Some(Polyline::new(recorded, given.vertices().to_vec()).unwrap_or(given))
}

/// The keys of a sweep header that say which table it is (the grid), as
/// against the model it was run with.
pub(super) const GRID_KEYS: [&str; 4] = ["table", "lambda", "phi", "initial"];

/// Where the model of a figure differs from its preset's (the paper's), in
/// a few words for its title and caption: `f = 0.2, N = 32`.
pub(super) fn model_note(base: &CaseParams, used: &CaseParams) -> Vec<String> {
    let mut v = Vec::new();
    let num = fmt_number;
    // First: the cycle decides what the preset's title (its phi) means.
    if used.cycle != base.cycle {
        v.push(match &used.cycle {
            Some(p) => format!("load cycle {} in place of the preset's", p.name()),
            None => "the paper's ellipse in place of the preset's cycle".to_string(),
        });
    }
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

/// Where the case of a slip map (its `cycle` and `initial` path) differs
/// from its preset's (`base`, with the preset's initial path
/// `preset_initial`), whose title names it: `λ = 5`, `φ = 0.5π`,
/// `initial path 7,-7`. A polyline's phase is in its vertices, and
/// [`model_note`] names the cycle.
pub(super) fn case_note(
    base: &CaseParams,
    preset_initial: &shakedown::model::Initial,
    cycle: &shakedown::model::Cycle,
    initial: &str,
) -> Vec<String> {
    let mut v = Vec::new();
    if cycle.load_factor() != base.load_factor {
        v.push(format!("λ = {}", fmt_number(cycle.load_factor())));
    }
    if cycle.as_polyline().is_none() && cycle.phase() != base.phase {
        let phase = cycle.phase() / std::f64::consts::PI;
        v.push(format!("φ = {}π", fmt_number(phase)));
    }
    if initial != preset_initial.name() {
        v.push(format!("initial path {initial}"));
    }
    v
}

/// Where the grid of a sweep figure (`spec`, from the list flags) differs
/// from its preset's (`preset`), whose title may name it (fig6: λ = 5.1,
/// 25 transients): the transients drawn, and `lambda` or `phi` when they
/// are not on the horizontal `axis` (where the ticks show them).
pub(super) fn grid_note(preset: &SweepLists, spec: &SweepSpec, axis: Axis) -> Vec<String> {
    let range = |v: &[f64], unit: f64| -> String {
        let (lo, hi) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        let [lo, hi] = [lo / unit, hi / unit].map(fmt_number);
        if lo == hi {
            lo
        } else {
            format!("{lo} to {hi}")
        }
    };
    let mut v = Vec::new();
    if axis != Axis::Lambda && spec.load_factors() != preset.load_factors {
        v.push(format!("λ = {}", range(spec.load_factors(), 1.0)));
    }
    let phases = spec.phases();
    if axis != Axis::Phi && spec.polyline().is_none() && phases != preset.phases {
        v.push(format!("φ = {}π", range(phases, std::f64::consts::PI)));
    }
    let initials = spec.initials();
    if initials != preset.initials {
        let names: Vec<String> = initials.iter().map(|i| i.name()).collect();
        v.push(match names.len() {
            1 => format!("transient {}", names[0]),
            2..=4 => format!("transients {}", names.join(" and ")),
            n => format!("{n} transients"),
        });
    }
    v
}

/// A sweep figure's points, and how much of its table they are.
type Drawn = (Vec<SweepPoint>, Option<Partial>);

/// How much of a sweep figure's table a `--from` CSV holds.
pub(super) struct Partial {
    pub(super) kept: usize,
    pub(super) total: usize,
}

/// The points of a sweep figure's CSV given with `--from`, checked as
/// `--resume` checks a file: read through a size cap (regular files
/// only), its header must be this figure's table (the grid of the preset
/// and the list flags) with the model of `spec` (the file's own, from
/// [`header_model`]), and its rows must be valid, in job order. A partial
/// file is refused unless `partial`; then the complete rows are drawn.
pub(super) fn from_sweep_csv(
    from: &Path,
    spec: &SweepSpec,
    keys: &[String],
    table: &str,
    partial: bool,
) -> Result<(Vec<SweepPoint>, Option<Partial>)> {
    let shown = shakedown::io::read::escape_text(&from.to_string_lossy(), 200);
    let mut meta = sweep_metadata(spec);
    meta.set("table", table);
    let cap = meta.render().len() as u64 + 4096 + 512 * (keys.len() as u64 + 1);
    let bad = |e: &dyn std::fmt::Display| anyhow!(InputError(format!("--from {shown}: {e}")));
    let bytes = shakedown::io::read::read_capped(from, cap).map_err(|e| bad(&e))?;
    let found = Metadata::parse(&String::from_utf8_lossy(&bytes));
    let header = meta.preamble(shakedown::analysis::sweep::CSV_HEADER);
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
        shakedown::io::csv::sweep_row_key_capped(spec.options().convergence().max_cycles() as u64);
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

pub(super) fn read(flag: &str, path: &Path) -> Result<String> {
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
pub(super) fn sweep_points(
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

/// The header of the regime map's `lambda_2(phi)` curve (`NAME_limit.csv`).
pub(super) fn curve_metadata(spec: &SweepSpec) -> Metadata {
    let mut meta = sweep_metadata(spec);
    meta.set("table", "limit-curve");
    meta.set("samples", CURVE_SAMPLES);
    meta
}

/// The regime map's stored `lambda_2(phi)` curve beside a `--from` CSV,
/// read through the checked reader: `None` when there is no such file;
/// bad input when it is not a regular file, too large, not this map's
/// curve (header) or its rows are not `lambda_2 > 0` at the map's phases.
pub(super) fn stored_curve(
    path: &Path,
    spec: &SweepSpec,
    phases: &[f64],
) -> Result<Option<Vec<(f64, f64)>>> {
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
pub(super) fn from_memory_csv(from: &Path, spec: &SweepSpec) -> Result<Vec<MemoryPoint>> {
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
pub(super) fn load_file_of(map: &Path) -> PathBuf {
    let stem = map
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    map.with_file_name(format!("{stem}_load.csv"))
}

/// A slip map read back from the CSV `from` and its load table beside it
/// (`NAME_load.csv`), as `figure fig5` (or `fig7`) wrote them, with the
/// polyline `cycle` it was made with (`None` for the paper's ellipse):
/// nothing is run. A file that is not such a table, of another cycle, or
/// cut short, is bad input named in one line.
pub(super) fn read_slip_map_files(from: &Path, cycle: Option<&Polyline>) -> Result<SlipMap> {
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
    read_slip_map(&map_text, &load_text, cycle).map_err(|e| {
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

pub(super) fn describe(map: &SlipMap) -> Result<()> {
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
