//! `shakedown run`: one case to its steady state.

use std::process::ExitCode;

use anyhow::Result;
use clap::Args;
use serde_json::json;
use shakedown::analysis::case::CaseParams;
use shakedown::stepping::{Outcome, ShakedownProof, Verdict};

use super::batch::print_stdout;
use super::CaseArgs;

#[derive(Debug, Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Print one JSON object instead of the readable summary.
    #[arg(long)]
    pub json: bool,
    /// Start at the cycle centre with the slip in FILE (as `limit --out
    /// FILE` writes it; its node count must be --nodes).
    #[arg(long, value_name = "FILE")]
    pub initial_slip: Option<String>,
    /// Write the fretting profile of the verdict cycle here as CSV: per
    /// node theta, p and q extremes, slip amplitude and path, dissipation,
    /// Ruiz parameter and wear (model.md section 4.1).
    #[arg(long, value_name = "FILE")]
    pub profile: Option<std::path::PathBuf>,
    /// Replace an existing, non-empty --profile FILE.
    #[arg(long)]
    pub force: bool,
}

/// Run `shakedown run`.
pub fn run(args: RunArgs) -> Result<ExitCode> {
    let base = args.case.base(CaseParams::default())?;
    if let (Some(_), Some(i)) = (&args.initial_slip, &args.case.initial) {
        return Err(anyhow::anyhow!(super::InputError(format!(
            "--initial {i}: give either --initial or --initial-slip, not both"
        ))));
    }
    let (mut params, mut case) = args.case.case(base)?;
    if let Some(path) = &args.initial_slip {
        case.initial = super::initial_slip(path, params.nodes)?;
        params.initial = case.initial.name();
    }
    if let Some(out) = &args.profile {
        if !args.force && shakedown::io::output::is_nonempty_file(out) {
            return Err(anyhow::anyhow!(super::InputError(format!(
                "--profile {}: it exists and is not empty: add --force to replace it",
                out.display()
            ))));
        }
    }
    let mut stepper = case.stepper();
    let outcome = match &args.profile {
        None => stepper.run_to_steady()?,
        Some(out) => {
            let (summary, profile) = shakedown::analysis::profile::profile_run(&mut stepper)?;
            let Some(profile) = profile else {
                return Err(anyhow::anyhow!(super::InputError(format!(
                    "--profile {}: the run ended ({}) before it completed a cycle: there is no cycle to profile",
                    out.display(),
                    summary.state()
                ))));
            };
            let csv =
                shakedown::io::profile::profile_csv(&case, &params.initial, &summary, &profile);
            super::batch::write_file("--profile", out, csv.as_bytes())?;
            summary
        }
    };
    let history: Vec<f64> = stepper.history().iter().map(|r| r.dissipation).collect();
    let text = if args.json {
        format!(
            "{}\n",
            serde_json::to_string(&to_json(&params, &outcome, &history))?
        )
    } else {
        readable(&params, &outcome, &history)
    };
    // A closed pipe (`shakedown run | head -1`) is not an error.
    print_stdout(&text)?;
    Ok(ExitCode::SUCCESS)
}

pub fn to_json(params: &CaseParams, s: &Outcome, history: &[f64]) -> serde_json::Value {
    json!({
        "state": s.state(),
        "dissipation": s.dissipation,
        "cycles": s.cycles,
        "rotation_per_cycle": s.rotation_per_cycle,
        "approach": s.approach(),
        "terminal_load": s.terminal_load(),
        "terminal_time": s.terminal_time(),
        "terminal_theta": s.terminal_theta(),
        "trend": s.trend(),
        "level": s.level,
        "steady_rotation": s.steady_rotation,
        "rotation_drift": s.rotation_drift(),
        "certificate": s.certificate(),
        "version": env!("CARGO_PKG_VERSION"),
        "dissipation_history": history,
        "parameters": {
            "lambda": params.load_factor,
            "phi": params.phase,
            "psi": params.slope,
            "center": [params.center.0, params.center.1],
            "friction": params.friction,
            "nu": params.poisson,
            "plane": params.plane,
            "initial": params.initial,
            "nodes": params.nodes,
            "steps": params.steps,
            "max_cycles": params.max_cycles,
            "safe_state": params.safe_state,
        }
    })
}

fn readable(p: &CaseParams, s: &Outcome, history: &[f64]) -> String {
    use std::fmt::Write;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "case      lambda = {}  phi = {:.6} rad ({:.4} pi)  psi = {}  A = ({:.4}, {:.4})",
        shakedown::io::csv::fmt_number(p.load_factor),
        p.phase,
        p.phase / std::f64::consts::PI,
        p.slope,
        p.center.0,
        p.center.1
    );
    let _ = writeln!(
        o,
        "material  f = {}  nu = {}  plane {}   initial path {}   N = {}, {} increments/cycle",
        p.friction, p.poisson, p.plane, p.initial, p.nodes, p.steps
    );
    let how = match s.verdict {
        Verdict::Shakedown(ShakedownProof::NoSlipCycle) => "a whole cycle without slip".to_string(),
        Verdict::Shakedown(ShakedownProof::SafeState(c)) => format!(
            "a safe state: margin {:.3e} > f C R = {:.3e} x {:.3e}, so all slip to come is at most {:.3e}",
            c.margin, c.coupling, c.distance, c.slip_bound
        ),
        Verdict::Shakedown(ShakedownProof::Converged)
        | Verdict::CyclicSlip
        | Verdict::Ratchetting { .. } => format!(
            "W changed by less than 0.01 % over {} successive cycles, its level known to 0.04 %",
            shakedown::stepping::steady::SETTLE_CYCLES
        ),
        Verdict::GrossSlip(_) | Verdict::Separation(_) => {
            match (s.terminal_load(), s.terminal_time()) {
                (Some(l), Some(t)) => format!(
                    "at load point {l}, omega t = {t:.4} in cycle {}",
                    s.cycles + 1
                ),
                (Some(l), None) => format!("at load point {l} in the initial transient"),
                _ => String::new(),
            }
        }
        Verdict::NotConverged { .. } => format!(
            "the cap of {} cycles was reached with W still changing",
            p.max_cycles
        ),
    };
    let _ = writeln!(o, "state     {}  ({how})", s.state());
    match s.certificate() {
        Some(c) => {
            let _ = writeln!(
                o,
                "W         {:.6e}  (steady cycle: W tends to zero; {:.6e} in cycle {}, the last one run)",
                s.dissipation, c.last_dissipation, c.cycle
            );
        }
        None => {
            let _ = writeln!(
                o,
                "W         {:.6e}  (last cycle, W mu / ((kappa+1) p0^2 a^2))",
                s.dissipation
            );
        }
    }
    if let Some(l) = s.level {
        let _ = writeln!(
            o,
            "level     W -> {:.6e} +- {:.1e}  (the steady level the cycles approach)",
            l.value, l.uncertainty
        );
    }
    let _ = writeln!(
        o,
        "rotation  {:.6e} per cycle (mean g)",
        s.rotation_per_cycle
    );
    if let (Some(r), Some(drift)) = (s.steady_rotation, s.rotation_drift()) {
        let _ = writeln!(
            o,
            "          steady {:.6e} +- {:.1e}; the last cycle drifts {:.3e} apart from it",
            r.value, r.uncertainty, drift
        );
    }
    let _ = writeln!(o, "cycles    {}", s.cycles);
    if let Some(t) = s.trend() {
        let _ = writeln!(
            o,
            "trend     W heading for {:.3e} +- {:.3e}  (changes shrink by {:.4} a cycle; W ~ k^-{:.2} over the last {} cycles)",
            t.limit,
            t.uncertainty,
            t.ratio,
            t.exponent,
            shakedown::stepping::verdict::WINDOW
        );
    }
    if history.len() > 1 {
        let shown: Vec<String> = history
            .iter()
            .rev()
            .take(6)
            .rev()
            .map(|w| format!("{w:.6e}"))
            .collect();
        let _ = writeln!(o, "W history (last {}): {}", shown.len(), shown.join(" "));
    }
    o
}
