//! `shakedown limit`: `lambda_2` by linear programming and its optimal slip.

use std::f64::consts::PI;
use std::io::Write;
use std::process::ExitCode;

use anyhow::{anyhow, Result};
use clap::Args;
use serde_json::json;
use shakedown::analysis::case::{Case, CaseParams};
use shakedown::analysis::limit::{shakedown_limit, Limit, LimitError, DEFAULT_SAMPLES};
use shakedown::model::{LoadPoint, Material};

use super::{CaseArgs, InputError};

#[derive(Debug, Args)]
pub struct LimitArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Load points on an elliptical cycle (phi != 0); a straight line uses its two ends.
    #[arg(long, value_name = "M")]
    pub samples: Option<String>,
    /// Write the optimal slip g(theta) here as CSV (with --phi LIST|RANGE: the curve phi,lambda_2,lower_bound).
    #[arg(long, value_name = "FILE", default_value = "optimal_slip.csv")]
    pub out: std::path::PathBuf,
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

pub fn limit(args: LimitArgs) -> Result<ExitCode> {
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
    params.initial = "OA".into();
    let case = Case::from_params(&params).map_err(|e| anyhow!(InputError(e.to_string())))?;
    let samples = match &args.samples {
        Some(t) => t
            .trim()
            .parse::<usize>()
            .map_err(|_| anyhow!(InputError(format!("--samples {t}: not a whole number"))))?,
        None => DEFAULT_SAMPLES,
    };
    let (material, center) = (case.material, case.cycle.center);
    let solve = |m: usize| -> Result<Limit> {
        shakedown_limit(
            &material,
            center,
            case.cycle.slope,
            case.cycle.phase,
            &case.disc,
            m,
        )
        .map_err(classify)
    };
    let limit = solve(samples)?;
    // Convergence in the sample count: the same programme on coarser
    // samplings (a line has nothing to converge).
    let mut convergence = Vec::new();
    if !limit.line {
        let mut m = samples / 8;
        while m < samples {
            if m >= 3 {
                let l = solve(m)?;
                convergence.push((m, l.load_factor, l.lower_bound));
            }
            m *= 2;
        }
        convergence.push((samples, limit.load_factor, limit.lower_bound));
    }

    let csv = slip_csv(&limit, case.disc.nodes());
    std::fs::File::create(&args.out)
        .and_then(|mut f| f.write_all(csv.as_bytes()))
        .map_err(|e| anyhow!(InputError(format!("--out {}: {e}", args.out.display()))))?;

    if args.json {
        let conv: Vec<_> = convergence
            .iter()
            .map(|(m, l, lo)| json!({"samples": m, "lambda_2": l, "lower_bound": lo}))
            .collect();
        println!(
            "{}",
            json!({
                "lambda_2": limit.load_factor,
                "lower_bound": limit.lower_bound,
                "line": limit.line,
                "samples": if limit.line { 2 } else { samples },
                "convergence": conv,
                "max_violation": limit.max_violation,
                "iterations": limit.iterations,
                "slip_csv": args.out.display().to_string(),
                "parameters": parameters(&params, &material, center),
            })
        );
    } else {
        print!(
            "{}",
            readable(&params, &limit, &convergence, &args.out, samples)
        );
    }
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

/// `theta,g` at every node.
pub fn slip_csv(limit: &Limit, nodes: usize) -> String {
    let mut out = String::from("theta,g\n");
    for (j, g) in limit.slip.iter().enumerate() {
        out.push_str(&format!("{},{}\n", 2.0 * PI * j as f64 / nodes as f64, g));
    }
    out
}

fn readable(
    p: &CaseParams,
    l: &Limit,
    convergence: &[(usize, f64, f64)],
    out: &std::path::Path,
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
        "check     max(|q| - f p) of the optimal slip at lambda_2: {:.2e}  ({} interior-point iterations)",
        l.max_violation, l.iterations
    );
    let _ = writeln!(
        o,
        "slip      optimal g(theta) written to {} ({} nodes); use it with --initial optimal",
        out.display(),
        l.slip.len()
    );
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
    params.initial = "OA".into();
    let case = Case::from_params(&params).map_err(|e| anyhow!(InputError(e.to_string())))?;
    let samples = match &args.samples {
        Some(t) => t
            .trim()
            .parse::<usize>()
            .map_err(|_| anyhow!(InputError(format!("--samples {t}: not a whole number"))))?,
        None => DEFAULT_SAMPLES,
    };
    let points = limit_curve(
        &case.material,
        case.cycle.center,
        case.cycle.slope,
        &phases,
        &case.disc,
        samples,
    );
    if let Some(e) = points.iter().find_map(|p| p.limit.as_ref().err()) {
        eprintln!("warning: the programme failed at some phases (empty values): {e}");
    }
    let csv = curve_csv(&points);
    print!("{csv}");
    // The default --out names the optimal-slip file of a single phase; a
    // curve is written only where the user asks.
    if args.out != std::path::Path::new(DEFAULT_OUT) {
        std::fs::write(&args.out, &csv)
            .map_err(|e| anyhow!(InputError(format!("--out {}: {e}", args.out.display()))))?;
    }
    Ok(ExitCode::SUCCESS)
}

const DEFAULT_OUT: &str = "optimal_slip.csv";
