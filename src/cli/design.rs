//! `shakedown design`: search transients `O -> P1 -> ... -> PK -> A` for one
//! whose steady cycle shakes down (docs/model.md section 10), and
//! `design --frontier`: the highest `lambda` at which a found path shakes
//! down, per family and `K`.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;

use anyhow::{anyhow, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;
use shakedown::analysis::case::{Case, CaseParams};
use shakedown::analysis::design::{
    frontier, initial_path_text, references, search, Budget, Candidate, DesignError, Family,
    FrontierRow, Progress, Region, Runner, Shape, GROSS_SLIP_GAP,
};
use shakedown::io::csv::case_metadata;
use shakedown::io::design::{frontier_csv, frontier_line};
use shakedown::io::output::{check_folder, is_nonempty_file, OutputLock};
use shakedown::stepping::steady::{Approach, SteadyState};
use shakedown::stepping::Outcome;

use super::batch::{ctrl_c, lock_file_output, print_stdout, refuse_input_as_output, write_file};
use super::{values, CaseArgs, InputError};
use shakedown::model::ranges;

/// The flags of `shakedown design`.
#[derive(Debug, Args)]
pub struct DesignArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    // The helps quote the ranges (`model::ranges`, the one place they are written).
    #[arg(long, value_name = "K", allow_hyphen_values = true, value_parser = values::count(ranges::VERTICES),
          help = format!("Vertices K of the path between O and A ({}); with --frontier, the largest K (default 8)", ranges::VERTICES.expected))]
    pub vertices: Option<String>,
    /// Seed of the search's random draws (the same seed gives the same result, whatever the thread count).
    #[arg(
        long,
        value_name = "S",
        default_value = "1",
        allow_hyphen_values = true
    )]
    pub seed: String,
    /// Path family: free (K free vertices) or decaying (alternating loads of decreasing amplitude about A).
    #[arg(long, value_name = "free|decaying", default_value = "free")]
    pub family: String,
    /// Particles of the swarm (default 24; 16 with --frontier).
    #[arg(long, value_name = "P", allow_hyphen_values = true, value_parser = values::count(ranges::PARTICLES))]
    pub particles: Option<String>,
    /// Swarm generations after the first (default 20; 8 per search with --frontier).
    #[arg(long, value_name = "I", allow_hyphen_values = true, value_parser = values::count(ranges::ITERATIONS))]
    pub iterations: Option<String>,
    #[arg(long, value_name = "G", allow_hyphen_values = true, value_parser = values::number(ranges::GROSS_GAP),
          help = format!("How far inside the gross-slip line |y| = 2 pi a vertex must stay ({}; default {}). A wider gap shows how much that line limits the frontier (docs/model.md section 10)", ranges::GROSS_GAP.expected, ranges::GROSS_GAP.low))]
    pub gross_gap: Option<String>,
    /// The highest lambda at which a found path shakes down, for K = 1..--vertices and both families, beside lambda_1, the best of the 25 and lambda_2 (CSV).
    #[arg(long)]
    pub frontier: bool,
    /// With --frontier: write the CSV here too.
    #[arg(long, value_name = "FILE", requires = "frontier")]
    pub out: Option<PathBuf>,
    /// Replace an existing, non-empty --out FILE.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON object instead of the readable report.
    #[arg(long, conflicts_with = "frontier")]
    pub json: bool,
}

fn number<T: std::str::FromStr>(flag: &str, text: &str, accepts: &str) -> Result<T> {
    text.trim().parse::<T>().map_err(|_| {
        anyhow!(InputError(format!(
            "--{flag} {text}: not a whole number: expected {accepts}"
        )))
    })
}

/// `--gross-gap G`: the distance a vertex keeps from `|y| = 2 pi`.
fn gross_gap(text: Option<&str>) -> Result<f64> {
    let Some(text) = text else {
        return Ok(GROSS_SLIP_GAP);
    };
    // Checked against its range while the command line was parsed.
    shakedown::io::parse::parse_number(text).map_err(|e| {
        anyhow!(InputError(format!(
            "--gross-gap {text}: {e}: expected {}",
            ranges::GROSS_GAP.expected
        )))
    })
}

fn family(text: &str) -> Result<Family> {
    match text.trim().to_ascii_lowercase().as_str() {
        "free" => Ok(Family::Free),
        "decaying" => Ok(Family::Decaying),
        _ => Err(anyhow!(InputError(format!(
            "--family {text}: unknown family: expected free or decaying"
        )))),
    }
}

fn design_error(e: DesignError) -> anyhow::Error {
    match e {
        DesignError::Param(_) | DesignError::Vertices(_) => anyhow!(InputError(e.to_string())),
        other => anyhow!(other),
    }
}

/// A bar on stderr when it is a terminal: runs, and the best so far.
fn bar(len: Option<usize>) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let b = match len {
        Some(n) => ProgressBar::new(n as u64),
        None => ProgressBar::new_spinner(),
    };
    let template = if len.is_some() {
        "{bar:30} {pos}/{len} runs  {elapsed}  {msg}"
    } else {
        "{spinner} {pos} runs  {elapsed}  {msg}"
    };
    b.set_style(ProgressStyle::with_template(template).expect("valid template"));
    b
}

fn best_message(p: &Progress) -> String {
    let best = if p.best_cost < 0.0 {
        "shakedown found".to_string()
    } else {
        format!("least W {:.3e}", p.best_cost)
    };
    match p.best_lambda {
        Some(l) => format!("best lambda {l:.4}; searching at {:.4}: {best}", p.lambda),
        None => format!("lambda {:.4}: {best}", p.lambda),
    }
}

/// Run `shakedown design`.
pub fn design(args: DesignArgs) -> Result<ExitCode> {
    for flag in ["initial", "initial-path"] {
        if let Some(v) = args.case.given(flag) {
            return Err(anyhow!(InputError(format!(
                "--{flag} {v}: design searches the initial path itself: drop it"
            ))));
        }
    }
    // The search is the paper's question, on its ellipse: a polyline has
    // no phi, and the search needs one.
    let polyline = match (args.case.given("cycle"), args.case.preset()?) {
        (Some(c), _) => Some(format!("--cycle {c}")),
        (None, Some(p)) if p.params.cycle.is_some() => {
            Some(format!("--preset {}: its cycle", p.name))
        }
        _ => None,
    };
    if let Some(what) = polyline {
        return Err(anyhow!(InputError(format!(
            "{what}: design searches transients for the paper's elliptical cycle (docs/model.md section 10), not a polyline: drop it"
        ))));
    }
    let seed: u64 = number("seed", &args.seed, "0 to 18446744073709551615")?;
    let family = family(&args.family)?;
    let frontier_mode = args.frontier;
    // The counts were checked against their ranges while the command line
    // was parsed (`values::count`).
    let particles: usize = match &args.particles {
        Some(t) => number("particles", t, ranges::PARTICLES.expected)?,
        None if frontier_mode => 16,
        None => 24,
    };
    let iterations: u64 = match &args.iterations {
        Some(t) => number("iterations", t, ranges::ITERATIONS.expected)?,
        None if frontier_mode => 8,
        None => 20,
    };
    let vertices: usize = match &args.vertices {
        Some(t) => number("vertices", t, ranges::VERTICES.expected)?,
        None if frontier_mode => 8,
        None => 2,
    };
    let budget =
        Budget::new(particles, iterations, seed).map_err(|e| anyhow!(InputError(e.to_string())))?;
    let gap = gross_gap(args.gross_gap.as_deref())?;
    if frontier_mode {
        if let Some(v) = args.case.given("lambda") {
            return Err(anyhow!(InputError(format!(
                "--lambda {v}: --frontier searches over lambda itself: drop it"
            ))));
        }
        return run_frontier(&args, vertices, budget, gap);
    }
    let Some(lambda_text) = args.case.given("lambda") else {
        return Err(anyhow!(InputError(
            "--lambda: design needs the load factor to design for (e.g. --lambda 4.81)".into()
        )));
    };
    let base = args.case.base(CaseParams::default())?;
    let (params, case) = args.case.case(base.clone())?;
    // The flags that `run` needs besides the path, as the user gave them.
    let mut lambda_text = lambda_text;
    if let Some(p) = &args.case.preset {
        lambda_text.push_str(&format!(" --preset {p}"));
    }
    for flag in [
        "phi",
        "psi",
        "center",
        "friction",
        "nu",
        "plane",
        "nodes",
        "steps",
        "max-cycles",
    ] {
        if let Some(v) = args.case.given(flag) {
            lambda_text.push_str(&format!(" --{flag} {v}"));
        }
    }
    if args.case.model.run_out {
        lambda_text.push_str(" --run-out");
    }
    let runner = Runner::new(&case);
    let shape = Shape::new(
        family,
        vertices,
        Region::with_gross_gap(&case.material(), gap)
            .map_err(|e| anyhow!(InputError(format!("--gross-gap: {e}"))))?,
        case.cycle().center(),
    )
    .map_err(design_error)?;
    let stop = ctrl_c()?;
    let b = bar(Some(particles * (iterations as usize + 1)));
    let report = |p: Progress| {
        b.set_position(p.evaluations as u64);
        b.set_message(best_message(&p));
    };
    let found = search(
        &runner,
        shape,
        params.load_factor,
        budget,
        &[],
        stop,
        &report,
    )
    .map_err(design_error)?;
    b.finish_and_clear();
    let Some(best) = found.best else {
        errln!("interrupted before any candidate was run");
        return Ok(ExitCode::from(super::batch::INTERRUPTED));
    };
    // The reproduction: the path's text through `run`'s own flags.
    let text = initial_path_text(&best.path);
    let mut flags = args.case.clone();
    flags.initial_path = Some(text.clone());
    let (_, again) = flags.case(base)?;
    let rerun = again.stepper().run_to_steady()?;
    let reproduced = rerun.state() == best.summary.state()
        && rerun.dissipation.to_bits() == best.summary.dissipation.to_bits();
    let out = if args.json {
        format!(
            "{}\n",
            serde_json::to_string(&to_json(
                &case,
                &params,
                shape,
                budget,
                &best,
                &rerun,
                &text,
                reproduced,
                found.evaluations,
                found.interrupted,
            ))?
        )
    } else {
        readable(
            &case,
            &lambda_text,
            shape,
            budget,
            &best,
            &rerun,
            &text,
            reproduced,
            found.evaluations,
            found.interrupted,
        )
    };
    print_stdout(&out)?;
    if !reproduced {
        return Err(anyhow!(
            "the designed path did not reproduce its state through run ({} then {}): please report this",
            best.summary.state(),
            rerun.state()
        ));
    }
    if found.interrupted {
        return Ok(ExitCode::from(super::batch::INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}

#[allow(clippy::too_many_arguments)]
fn to_json(
    case: &Case,
    params: &CaseParams,
    shape: Shape,
    budget: Budget,
    best: &Candidate,
    rerun: &Outcome,
    text: &str,
    reproduced: bool,
    evaluations: usize,
    interrupted: bool,
) -> serde_json::Value {
    let path: Vec<[f64; 2]> = best.path.iter().map(|p| [p.x(), p.y()]).collect();
    json!({
        "initial_path": text,
        "state": rerun.state(),
        "lambda": case.cycle().load_factor(),
        "dissipation": rerun.dissipation,
        "approach": rerun.approach(),
        "cycles": rerun.cycles,
        "certificate": rerun.certificate(),
        "reproduced": reproduced,
        "path": path,
        "family": shape.family(),
        "vertices": shape.vertices(),
        "region": shape.region(),
        "seed": budget.seed(),
        "particles": budget.particles(),
        "iterations": budget.iterations(),
        "evaluations": evaluations,
        "interrupted": interrupted,
        "threads": rayon::current_num_threads(),
        "version": env!("CARGO_PKG_VERSION"),
        "parameters": {
            "lambda": params.load_factor,
            "phi": params.phase,
            "psi": params.slope,
            "center": [params.center.0, params.center.1],
            "friction": params.friction,
            "nu": params.poisson,
            "plane": params.plane,
            "nodes": params.nodes,
            "steps": params.steps,
            "max_cycles": params.max_cycles,
            "safe_state": params.safe_state,
        }
    })
}

#[allow(clippy::too_many_arguments)]
fn readable(
    case: &Case,
    lambda_text: &str,
    shape: Shape,
    budget: Budget,
    best: &Candidate,
    rerun: &Outcome,
    text: &str,
    reproduced: bool,
    evaluations: usize,
    interrupted: bool,
) -> String {
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "search    {} family, K = {}, seed {}: {} candidates run by the engine ({} particles, up to {} generations, {} threads){}",
        shape.family().as_str(),
        shape.vertices(),
        budget.seed(),
        evaluations,
        budget.particles(),
        budget.iterations() + 1,
        rayon::current_num_threads(),
        if interrupted { "; stopped by Ctrl-C" } else { "" }
    );
    let _ = writeln!(
        o,
        "region    |x| <= {:.4}, |y| <= {:.4} (inside gross slip |y| = 2 pi and separation)",
        shape.region().x_max(),
        shape.region().y_max()
    );
    let _ = writeln!(
        o,
        "case      lambda = {}  phi = {}  A = ({:.4}, {:.4})  N = {}, {} increments/cycle",
        case.cycle().load_factor(),
        case.cycle().phase(),
        case.cycle().center().x(),
        case.cycle().center().y(),
        case.disc().nodes(),
        case.disc().steps_per_cycle()
    );
    let _ = writeln!(o, "path      O");
    for p in &best.path {
        let _ = writeln!(o, "       -> ({:.6}, {:.6})", p.x(), p.y());
    }
    let _ = writeln!(
        o,
        "       -> A = ({:.6}, {:.6})",
        case.cycle().center().x(),
        case.cycle().center().y()
    );
    let how = match rerun.approach() {
        Approach::NoSlipCycle => "a whole cycle without slip".to_string(),
        Approach::SafeState => "a safe state (certificate below)".to_string(),
        Approach::Converged => "W settled to 0.01 %".to_string(),
        Approach::Terminal => "a terminal event".to_string(),
        Approach::Cap => "the cycle cap".to_string(),
    };
    let _ = writeln!(
        o,
        "state     {}  ({how}, cycle {})",
        rerun.state(),
        rerun.cycles
    );
    let _ = writeln!(o, "W         {:.6e}", rerun.dissipation);
    match rerun.certificate() {
        Some(c) => {
            let _ = writeln!(
                o,
                "certificate  margin delta = {:.4e} > f C R = {:.4e} x {:.4e} = {:.4e} after cycle {}; all slip to come <= {:.4e}",
                c.margin,
                c.coupling,
                c.distance,
                c.coupling * c.distance,
                c.cycle,
                c.slip_bound
            );
        }
        None if rerun.state() == SteadyState::Shakedown => {
            let _ = writeln!(
                o,
                "certificate  none needed: a whole cycle passed without slip, so every later cycle does"
            );
        }
        None => {
            let _ = writeln!(
                o,
                "certificate  none: no shakedown path was found at this lambda; this is the least W found"
            );
        }
    }
    let _ = writeln!(
        o,
        "reproduce shakedown run --lambda {lambda_text} --initial-path \"{text}\"{}",
        if reproduced {
            "   (rerun: same state and W)"
        } else {
            "   (rerun DIFFERS)"
        }
    );
    let _ = writeln!(
        o,
        "explore   shakedown tui --lambda {lambda_text} --initial-path \"{text}\"   (the path is drawn on the load plane, the slip built step by step)"
    );
    o
}

/// Refuse a bad `--out` before any work; the lock lives as long as the
/// guard.
fn prepare_out(args: &DesignArgs) -> Result<Option<OutputLock>> {
    let Some(out) = &args.out else {
        return Ok(None);
    };
    refuse_input_as_output("--out", out, &args.case.input_files())?;
    if !args.force && is_nonempty_file(out) {
        return Err(anyhow!(InputError(format!(
            "--out {}: it exists and is not empty: add --force to replace it",
            out.display()
        ))));
    }
    check_folder(out).map_err(|e| {
        anyhow!(InputError(format!(
            "--out {}: cannot create it: {e}: expected a writable file path",
            out.display()
        )))
    })?;
    lock_file_output("--out", out)
}

/// The frontier's table as text (metadata header, references, rows) and
/// whether Ctrl-C cut it short.
pub fn frontier_table(
    case: &Case,
    vertices: usize,
    budget: Budget,
    gap: f64,
    families: &[Family],
) -> Result<(String, bool)> {
    let region = Region::with_gross_gap(&case.material(), gap)
        .map_err(|e| anyhow!(InputError(format!("--gross-gap: {e}"))))?;
    let runner = Runner::new(case);
    let stop = ctrl_c()?;
    let b = bar(None);
    b.set_message("the 25 paper transients and lambda_2");
    let refs = references(&runner).map_err(design_error)?;
    let report = |p: Progress| {
        b.inc(1);
        b.set_message(best_message(&p));
    };
    let rows = Mutex::new(Vec::<FrontierRow>::new());
    for &f in families {
        let mut done = |r: &FrontierRow| {
            b.println(frontier_line(r).trim_end());
            rows.lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(r.clone());
        };
        frontier(
            &runner, f, vertices, &refs, region, budget, stop, &report, &mut done,
        )
        .map_err(design_error)?;
    }
    b.finish_and_clear();
    let mut meta = case_metadata("design-frontier", case, "designed");
    meta.set("lambda", "searched");
    meta.push(
        "region",
        format!("|x| <= {}, |y| <= {}", region.x_max(), region.y_max()),
    );
    meta.push("seed", budget.seed())
        .push("particles", budget.particles())
        .push("iterations", budget.iterations())
        .push("vertices", vertices)
        .push("threads", rayon::current_num_threads());
    meta.push("best_of_25", &refs.best_name);
    let rows = rows.into_inner().unwrap_or_else(|e| e.into_inner());
    Ok((
        format!("{}{}", meta.render(), frontier_csv(&refs, &rows)),
        stop.is_draining(),
    ))
}

fn run_frontier(args: &DesignArgs, vertices: usize, budget: Budget, gap: f64) -> Result<ExitCode> {
    let base = args.case.base(CaseParams::default())?;
    let (_, case) = args.case.case(base)?;
    let _lock = prepare_out(args)?;
    let (csv, interrupted) = frontier_table(
        &case,
        vertices,
        budget,
        gap,
        &[Family::Free, Family::Decaying],
    )?;
    print_stdout(&csv)?;
    if let Some(out) = &args.out {
        write_file("--out", out, csv.as_bytes())?;
    }
    if interrupted {
        errln!("interrupted: the rows finished so far are written");
        return Ok(ExitCode::from(super::batch::INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}

/// `figure design`: the frontier table (from `--from FILE.csv`, or made now
/// with `K <= 8`, as `design --frontier`, and the frontier's default budget) drawn as design.svg and
/// design.png.
pub fn figure(args: &super::figure::FigureArgs) -> Result<ExitCode> {
    use shakedown::figure::{design::DesignPlot, Frame};
    use shakedown::io::csv::Metadata;
    use shakedown::io::design::read_frontier_csv;
    use shakedown::io::parse::parse_point;
    let (dir, style) = super::figure::out_dir_and_style(args, "a design --frontier table")?;
    let (csv_path, svg, png, caption) = (
        dir.join("design.csv"),
        dir.join("design.svg"),
        dir.join("design.png"),
        dir.join("design.caption.txt"),
    );
    let mut files = vec![&svg, &png, &caption];
    if args.from.is_none() {
        files.push(&csv_path);
    }
    if !args.force {
        if let Some(f) = files.iter().find(|f| is_nonempty_file(f)) {
            return Err(anyhow!(InputError(format!(
                "--out {}: {} exists: add --force to replace it",
                dir.display(),
                f.display()
            ))));
        }
    }
    let text = match &args.from {
        // A frontier table is a few rows: 1 MiB is far more than one can be.
        Some(f) => shakedown::io::read::read_text_capped(f, 1 << 20)
            .map_err(|e| anyhow!(InputError(format!("--from {}: {e}", f.display()))))?,
        None => {
            let base = args.model.apply(CaseParams::default())?;
            let case = Case::from_params(&base).map_err(|e| anyhow!(InputError(e.to_string())))?;
            let (csv, interrupted) = frontier_table(
                &case,
                8,
                Budget::new(16, 8, 1)?,
                GROSS_SLIP_GAP,
                &[Family::Free, Family::Decaying],
            )?;
            write_file("--out", &csv_path, csv.as_bytes())?;
            if interrupted {
                errln!(
                    "interrupted: the rows finished so far are in {}; no plot was drawn",
                    csv_path.display()
                );
                return Ok(ExitCode::from(super::batch::INTERRUPTED));
            }
            csv
        }
    };
    let from = args
        .from
        .as_deref()
        .unwrap_or(&csv_path)
        .display()
        .to_string();
    let bad = |e: String| anyhow!(InputError(format!("--from {from}: {e}")));
    let meta = Metadata::parse(&text);
    if meta.get("table") != Some("design-frontier") {
        return Err(bad(format!(
            "it is a '{}' table: expected the table of design --frontier (table = design-frontier)",
            shakedown::io::read::escape_text(meta.get("table").unwrap_or("unlabelled"), 40)
        )));
    }
    let rows = read_frontier_csv(&text).map_err(bad)?;
    let center = meta
        .get("center")
        .and_then(|c| parse_point(c).ok())
        .ok_or_else(|| bad("its header has no 'center'".into()))?;
    let slope = meta
        .get("psi")
        .and_then(|v| v.parse::<f64>().ok())
        .ok_or_else(|| bad("its header has no 'psi'".into()))?;
    let plot = DesignPlot {
        rows: &rows,
        center: shakedown::LoadPoint::new(center.0, center.1),
        slope,
        frame: Frame {
            title: format!(
                "Designed transients: N = {}, {} increments per cycle, φ = {}",
                meta.get("nodes").unwrap_or("?"),
                meta.get("steps").unwrap_or("?"),
                meta.get("phi").unwrap_or("?")
            ),
            show_title: args.title,
            style,
        },
    };
    super::figure::write_plot(&plot, &svg, &png)?;
    errln!(
        "wrote {}, {} and {}",
        svg.display(),
        png.display(),
        svg.with_extension("caption.txt").display()
    );
    Ok(ExitCode::SUCCESS)
}
