//! `shakedown limit`: `lambda_2` by linear programming and its optimal slip.

use std::f64::consts::PI;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{anyhow, Result};
use clap::Args;
use serde_json::json;
use shakedown::analysis::case::{Case, CaseParams};
use shakedown::analysis::limit::{
    sample_convergence, shakedown_limit, Limit, LimitError, DEFAULT_SAMPLES,
};
use shakedown::io::csv::slip_csv;
use shakedown::io::output::{check_folder, is_nonempty_file, OutputLock};
use shakedown::model::{LoadPoint, Material};

use super::batch::{lock_file_output, print_stdout, refuse_input_as_output, write_file};
use super::{case_error, CaseArgs, InputError};

/// The flags of `shakedown limit`.
#[derive(Debug, Args)]
pub struct LimitArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Load points on an elliptical cycle (phi != 0); a straight line uses its two ends.
    #[arg(long, value_name = "M", value_parser = super::values::count(shakedown::model::ranges::SAMPLES))]
    pub samples: Option<String>,
    /// Write the optimal slip g(theta) here as CSV (nothing is written
    /// without it); `run` and `sweep` start from it with --initial-slip FILE.
    /// With --phi LIST|RANGE: the curve phi,lambda_2,lower_bound.
    #[arg(long, value_name = "FILE")]
    pub out: Option<std::path::PathBuf>,
    /// Replace an existing, non-empty --out FILE.
    #[arg(long)]
    pub force: bool,
    /// Print one JSON object instead of the readable report.
    #[arg(long)]
    pub json: bool,
}

/// Problems with the cycle itself are the user's input; solver trouble is not.
fn classify(e: LimitError) -> anyhow::Error {
    match e {
        LimitError::Samples(_)
        | LimitError::Param(_)
        | LimitError::Infeasible { .. }
        | LimitError::Unbounded => anyhow!(InputError(e.to_string())),
        other => anyhow!(other),
    }
}

/// Run `shakedown limit`.
pub fn limit(args: LimitArgs) -> Result<ExitCode> {
    // Flags that play no part in lambda_2 are refused, not ignored.
    for flag in ["lambda", "initial", "initial-path", "max-cycles", "steps"] {
        if let Some(v) = args.case.given(flag) {
            return Err(anyhow!(InputError(format!(
                "--{flag} {v}: limit does not use it (lambda_2 depends on the cycle's direction, the material and --nodes only): drop it"
            ))));
        }
    }
    if args.case.model.run_out {
        return Err(anyhow!(InputError(
            "--run-out: limit does not use it (it changes how a run's shakedown is proven, and limit runs nothing): drop it".into()
        )));
    }
    if let (Some(_), Some(phi)) = (&args.case.model.cycle, &args.case.phi) {
        return Err(anyhow!(InputError(format!(
            "--phi {phi}: a polyline cycle (--cycle) has no phase: drop --phi"
        ))));
    }
    if let Some(phis) = args
        .case
        .phi
        .as_deref()
        .filter(|t| t.contains(':') || t.contains(','))
    {
        return curve(&args, phis);
    }
    let base = args.case.base(CaseParams::default())?;
    let mut params = args.case.apply(base)?;
    // lambda and the initial path play no part in the limit.
    params.initial = shakedown::model::Initial::Direct;
    if let Some(polyline) = params.cycle.clone() {
        return polyline_limit(&args, params, &polyline);
    }
    let case = Case::from_params(&params).map_err(|e| case_error(e, |f| args.case.given(f)))?;
    let samples = match &args.samples {
        Some(t) => t.trim().parse::<usize>().map_err(|_| {
            anyhow!(InputError(format!(
                "--samples {t}: not a whole number: expected {}",
                shakedown::model::ranges::SAMPLES.expected
            )))
        })?,
        None => DEFAULT_SAMPLES,
    };
    // A straight cycle (phi = 0) has two load points, not `samples`.
    let points = if params.phase.sin().abs() < 1e-12 {
        2
    } else {
        samples
    };
    warn_if_slow_limit(params.nodes, points);
    let _lock = prepare_out(&args)?;
    let (material, center) = (case.material(), case.cycle().center());
    let (slope, phase) = (case.cycle().slope(), case.cycle().phase());
    let limit = shakedown_limit(&material, center, slope, phase, &case.disc(), samples)
        .map_err(classify)?;
    if limit.line {
        if let Some(t) = &args.samples {
            return Err(anyhow!(InputError(format!(
                "--samples {t}: limit does not use it at phi = {} (a straight cycle uses its two ends): drop it",
                params.phase
            ))));
        }
    }
    // Convergence in the sample count (a line has nothing to converge).
    let convergence = sample_convergence(
        &material,
        center,
        slope,
        phase,
        &case.disc(),
        samples,
        &limit,
    )
    .map_err(classify)?;

    if let Some(out) = &args.out {
        let csv = slip_csv(&limit, &material, center, slope, phase, samples);
        write_file("--out", out, csv.as_bytes())?;
    }

    if args.json {
        let conv: Vec<_> = convergence
            .iter()
            .map(|(m, l, lo)| json!({"samples": m, "lambda_2": l, "lower_bound": lo}))
            .collect();
        outln!(
            "{}",
            json!({
                "lambda_2": limit.load_factor,
                "lower_bound": limit.lower_bound,
                "line": limit.line,
                "samples": if limit.line { 2 } else { samples },
                "convergence": conv,
                "max_violation": limit.max_violation,
                "iterations": limit.iterations,
                "slip_csv": args.out.as_ref().map(|p| p.display().to_string()),
                "parameters": parameters(&params, &material, center),
            })
        );
    } else {
        print_stdout(&readable(
            &params,
            &limit,
            &convergence,
            args.out.as_deref(),
            samples,
        ))?;
    }
    Ok(ExitCode::SUCCESS)
}

/// `limit` on a polyline cycle: the programme at its vertices, which is
/// exact (a slip admissible at the vertices is admissible on every chord).
fn polyline_limit(
    args: &LimitArgs,
    mut params: CaseParams,
    polyline: &shakedown::model::Polyline,
) -> Result<ExitCode> {
    if let Some(t) = &args.samples {
        return Err(anyhow!(InputError(format!(
            "--samples {t}: limit does not use it with --cycle (the cycle's vertices are its load points, and exact): drop it"
        ))));
    }
    let vertices = polyline.vertices().len();
    check_vertices(vertices)?;
    // The increments play no part in lambda_2: any count the cycle takes.
    params.steps = vertices * 16usize.div_ceil(vertices);
    let case = Case::from_params(&params).map_err(|e| case_error(e, |f| args.case.given(f)))?;
    warn_if_slow_limit(params.nodes, vertices);
    let _lock = prepare_out(args)?;
    let (material, center) = (case.material(), case.cycle().center());
    let limit = shakedown::analysis::limit::cycle_limit(&material, case.cycle(), &case.disc(), 0)
        .map_err(classify)?;
    if let Some(out) = &args.out {
        let csv = shakedown::io::csv::polyline_slip_csv(&limit, &material, center, polyline);
        write_file("--out", out, csv.as_bytes())?;
    }
    if args.json {
        outln!(
            "{}",
            json!({
                "lambda_2": limit.load_factor,
                "lower_bound": limit.lower_bound,
                "line": false,
                "samples": vertices,
                "convergence": [],
                "max_violation": limit.max_violation,
                "iterations": limit.iterations,
                "slip_csv": args.out.as_ref().map(|p| p.display().to_string()),
                "parameters": {
                    "cycle": polyline.name(),
                    "center": [center.x(), center.y()],
                    "friction": material.friction(),
                    "nu": material.poisson(),
                    "plane": material.plane(),
                    "nodes": params.nodes,
                },
            })
        );
        return Ok(ExitCode::SUCCESS);
    }
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "cycle     {} ({vertices} vertices)  A = ({:.4}, {:.4})  f = {}  nu = {}  plane {}  N = {}",
        polyline.name(),
        center.x(),
        center.y(),
        material.friction(),
        material.poisson(),
        material.plane(),
        params.nodes
    );
    let _ = writeln!(o, "lambda_2  {:.6}", limit.load_factor);
    let _ = writeln!(
        o,
        "          the friction law is imposed at the {vertices} vertices; it is linear in the load, so this is exact on the chords between them for N = {}",
        params.nodes
    );
    let _ = writeln!(
        o,
        "check     max(|q| - f p) of the optimal slip at lambda_2: {:.2e}  ({} interior-point iterations, {} pivots)",
        limit.max_violation, limit.iterations, limit.pivots
    );
    if let Some(out) = &args.out {
        let _ = writeln!(
            o,
            "slip      optimal g(theta) written to {} ({} nodes); start from it with --initial-slip {}",
            out.display(),
            limit.slip.len(),
            out.display()
        );
    }
    print_stdout(&o)?;
    Ok(ExitCode::SUCCESS)
}

fn parameters(p: &CaseParams, m: &Material, center: LoadPoint) -> serde_json::Value {
    json!({
        "phi": p.phase,
        "psi": p.slope,
        "center": [center.x(), center.y()],
        "friction": m.friction(),
        "nu": m.poisson(),
        "plane": m.plane(),
        "nodes": p.nodes,
    })
}

fn readable(
    p: &CaseParams,
    l: &Limit,
    convergence: &[(usize, f64, f64)],
    out: Option<&Path>,
    samples: usize,
) -> String {
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "cycle     phi = {:.6} rad ({:.4} pi)  psi = {}  A = ({:.4}, {:.4})  f = {}  nu = {}  plane {}  N = {}",
        p.phase,
        p.phase / PI,
        p.slope,
        p.center.0,
        p.center.1,
        p.friction,
        p.poisson,
        p.plane,
        p.nodes
    );
    if l.line {
        let _ = writeln!(o, "lambda_2  {:.6}", l.load_factor);
        let _ = writeln!(
            o,
            "          the cycle is a straight line: its two ends bound every constraint, so this is exact for N = {}",
            p.nodes
        );
    } else {
        let _ = writeln!(
            o,
            "lambda_2  {:.6}   ({:.6} <= lambda_2 <= {:.6} with {} samples of the ellipse)",
            l.load_factor, l.lower_bound, l.load_factor, samples
        );
        let _ = writeln!(o, "samples   lambda_M    lower bound lambda_M cos(pi/M)");
        for (m, lam, lo) in convergence {
            let _ = writeln!(o, "{m:7}   {lam:.6}    {lo:.6}");
        }
    }
    let _ = writeln!(
        o,
        "check     max(|q| - f p) of the optimal slip at lambda_2: {:.2e}  ({} interior-point iterations, {} pivots)",
        l.max_violation, l.iterations, l.pivots
    );
    match out {
        Some(out) => {
            let _ = writeln!(
                o,
                "slip      optimal g(theta) written to {} ({} nodes); start from it with --initial-slip {}",
                out.display(),
                l.slip.len(),
                out.display()
            );
        }
        None => {
            let _ = writeln!(
                o,
                "slip      not written (add --out FILE to keep the optimal g(theta); --initial optimal recomputes it)"
            );
        }
    }
    o
}

/// `limit --phi LIST|RANGE`: `lambda_2` against `phi` as CSV on stdout,
/// and in `--out` when given.
fn curve(args: &LimitArgs, phis: &str) -> Result<ExitCode> {
    use shakedown::analysis::limit_curve::{curve_csv, limit_curve};
    use shakedown::io::parse::{parse_angle, parse_values};
    let phases = parse_values(phis, parse_angle).map_err(|e| super::bad_flag("phi", phis, e))?;
    let base = args.case.base(CaseParams::default())?;
    let mut flags = args.case.clone();
    flags.phi = None;
    let mut params = flags.apply(base)?;
    params.phase = phases[0];
    params.initial = shakedown::model::Initial::Direct;
    let case = Case::from_params(&params).map_err(|e| anyhow!(InputError(e.to_string())))?;
    let samples = match &args.samples {
        Some(t) => t
            .trim()
            .parse::<usize>()
            .map_err(|_| anyhow!(InputError(format!("--samples {t}: not a whole number"))))?,
        None => DEFAULT_SAMPLES,
    };
    warn_if_slow_limit(params.nodes, samples.saturating_mul(phases.len()));
    let points = limit_curve(
        &case.material(),
        case.cycle().center(),
        case.cycle().slope(),
        &phases,
        &case.disc(),
        samples,
    );
    if let Some(e) = points.iter().find_map(|p| p.limit.as_ref().err()) {
        errln!("warning: the programme failed at some phases (empty values): {e}");
    }
    let _lock = prepare_out(args)?;
    let meta = shakedown::io::csv::limit_curve_metadata(
        &case.material(),
        case.cycle().center(),
        case.cycle().slope(),
        case.disc().nodes(),
        &phases,
        samples,
    );
    let csv = format!("{}{}", meta.render(), curve_csv(&points));
    match &args.out {
        None => print_stdout(&csv)?,
        Some(out) => {
            write_file("--out", out, csv.as_bytes())?;
            let solved = points.iter().filter(|p| p.limit.is_ok()).count();
            outln!(
                "lambda_2 at {solved} of {} phases written to {}",
                points.len(),
                out.display()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Refuse a cycle with more vertices than the programme takes load points
/// (the library's cap, as for `--samples`), before anything is allocated.
/// The programme keeps a rate per load point, node and sign (`16 M N`
/// bytes: 268 MB at the caps of 4096 load points and nodes).
fn check_vertices(vertices: usize) -> Result<()> {
    let cap = shakedown::analysis::limit::MAX_SAMPLES;
    if vertices > cap {
        return Err(anyhow!(InputError(format!(
            "--cycle: {vertices} vertices: limit takes at most {cap}: use fewer"
        ))));
    }
    Ok(())
}

/// Refuse a bad `--out` before any work, and hold it against a second
/// writer: the lock (if any) lives as long as the returned guard.
fn prepare_out(args: &LimitArgs) -> Result<Option<OutputLock>> {
    let Some(out) = &args.out else {
        return Ok(None);
    };
    if out.as_os_str() == "-" {
        return Err(anyhow!(InputError(
            "--out -: limit prints its report on stdout: give a file name for the CSV".into()
        )));
    }
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

/// A rough CPU time for `limit`: the factorisation of the basis on the
/// finest grid (`O(N^3)`) and the rates of `samples` load points
/// (`O(M N)`), as measured at the default 64 samples.
pub fn expected_limit_seconds(nodes: usize, samples: usize) -> f64 {
    let n = nodes as f64 / 1024.0;
    0.1 * n * n * n + 1e-8 * samples as f64 * nodes as f64
}

/// Warn on stderr (one line) when `limit` will take more than a few
/// seconds, with the expected time.
fn warn_if_slow_limit(nodes: usize, samples: usize) {
    let t = expected_limit_seconds(nodes, samples);
    if t >= 5.0 {
        let time = if t < 120.0 {
            format!("about {t:.0} s")
        } else {
            format!("about {:.0} min", t / 60.0)
        };
        errln!("warning: --nodes {nodes} with {samples} load points: expect {time} for the linear programme");
    }
}
