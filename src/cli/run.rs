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
        case.set_initial(super::initial_slip(path, params.nodes)?)?;
        params.initial = case.initial().clone();
    }
    if let Some(out) = &args.profile {
        let mut inputs = args.case.input_files();
        if let Some(slip) = &args.initial_slip {
            inputs.push(("--initial-slip file", std::path::Path::new(slip.as_str())));
        }
        super::batch::refuse_input_as_output("--profile", out, &inputs)?;
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
            let csv = shakedown::io::profile::profile_csv(
                &case,
                &case.initial().name(),
                &summary,
                &profile,
            );
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
            "initial": params.initial.name(),
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
            "trend     W heading for {:.3e} +- {:.3e}  (changes shrink by {:.4} a cycle; W ~ k^{:.2} over the last {} cycles)",
            t.limit,
            t.uncertainty,
            t.ratio,
            // `exponent` is the decay p of W ~ k^-p: a W that rises has p < 0.
            -t.exponent,
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

/// `figure profile`: the fretting profile against theta (model.md section
/// 4.1). With `--from FILE.csv` (a `run --profile` output) it redraws that
/// profile; otherwise it runs the one case of the model flags and single
/// `--lambda`, `--phi` and `--initial` values, and writes `profile.csv`
/// beside the plot.
pub fn profile_figure(args: &super::figure::FigureArgs) -> Result<ExitCode> {
    use anyhow::anyhow;
    use shakedown::figure::{Frame, ProfilePlot};
    use shakedown::io::output::is_nonempty_file;
    use std::path::PathBuf;

    let bad = |m: String| anyhow!(super::InputError(m));
    let stem = args
        .from
        .as_ref()
        .and_then(|f| f.file_stem())
        .map_or("profile".into(), |s| s.to_string_lossy().into_owned());
    shakedown::io::output::check_file_stem(&stem)
        .map_err(|why| bad(format!("--from: its name cannot be used: {why}")))?;
    let (out_dir, style) = super::figure::out_dir_and_style(args, "a run --profile output")?;
    let file = |ext: &str| out_dir.join(format!("{stem}{ext}"));
    let outputs: Vec<PathBuf> = if args.from.is_some() {
        vec![file(".svg"), file(".png"), file(".caption.txt")]
    } else {
        vec![
            file(".csv"),
            file(".svg"),
            file(".png"),
            file(".caption.txt"),
        ]
    };
    if !args.force {
        if let Some(old) = outputs.iter().find(|p| is_nonempty_file(p)) {
            return Err(bad(format!(
                "--out {}: {} exists: add --force to replace it",
                out_dir.display(),
                old.display()
            )));
        }
    }
    let (profile, friction, title) = match &args.from {
        Some(from) => {
            // The profile is drawn as it was run: a model or case flag
            // would not change it, so it is refused rather than ignored.
            let model = ["psi", "center", "friction", "nu", "plane", "nodes", "steps"]
                .into_iter()
                .chain(["max-cycles"])
                .find_map(|f| args.model.given(f).map(|v| (f, v)));
            let lists = &args.lists;
            let case = [
                ("lambda", &lists.lambdas),
                ("phi", &lists.phis),
                ("initial", &lists.initials),
                ("initial-slip", &lists.initial_slip),
                ("initial-path", &lists.initial_path),
            ]
            .into_iter()
            .find_map(|(f, v)| v.clone().map(|v| (f, v)));
            let run_out = args.model.run_out.then(|| ("run-out", String::new()));
            if let Some((flag, v)) = model.or(case).or(run_out) {
                return Err(bad(format!(
                    "--{flag} {v}: figure profile --from draws the profile as it was run (its header says how): drop --{flag}"
                )));
            }
            let shown = shakedown::io::read::escape_text(&from.display().to_string(), 200);
            let text = shakedown::io::read::read_text_capped(from, 64 << 20)
                .map_err(|e| bad(format!("--from {shown}: {e}")))?;
            let (meta, profile) = shakedown::io::profile::read_profile_csv(&text)
                .map_err(|e| bad(format!("--from {shown}: {e}")))?;
            // The profile is drawn without its cycle (the caption names
            // it from the header), but a --cycle given must be that one.
            if let Some(c) = &args.model.cycle {
                super::figure::check_cycle(from, &meta, Some(&super::cycle_file(c)?))?;
            }
            let friction = meta
                .get("friction")
                .and_then(|f| f.trim().parse::<f64>().ok())
                .ok_or_else(|| bad(format!("--from {shown}: its header has no friction")))?;
            let title = profile_title(|k| meta.get(k).map(str::to_string));
            (profile, friction, title)
        }
        None => {
            let single = |flag: &str, v: &Option<String>| -> Result<Option<String>> {
                match v {
                    Some(t)
                        if t.contains(':')
                            || t.matches(',').count() > usize::from(flag == "initial") =>
                    {
                        Err(bad(format!(
                            "--{flag} {t}: figure profile draws one case: give one value"
                        )))
                    }
                    other => Ok(other.clone()),
                }
            };
            let case_args = super::CaseArgs {
                preset: None,
                lambda: single("lambda", &args.lists.lambdas)?,
                phi: single("phi", &args.lists.phis)?,
                initial: single("initial", &args.lists.initials)?,
                initial_path: args.lists.initial_path.clone(),
                model: args.model.clone(),
            };
            let (_, case) = case_args.case(CaseParams::default())?;
            let mut stepper = case.stepper();
            let (summary, profile) = shakedown::analysis::profile::profile_run(&mut stepper)?;
            let Some(profile) = profile else {
                return Err(bad(format!(
                    "figure profile: the run ended ({}) before it completed a cycle: there is no cycle to profile",
                    summary.state()
                )));
            };
            let csv = shakedown::io::profile::profile_csv(
                &case,
                &case.initial().name(),
                &summary,
                &profile,
            );
            super::batch::write_file("--out", &file(".csv"), csv.as_bytes())?;
            let meta = shakedown::io::csv::Metadata::parse(&csv);
            let title = profile_title(|k| meta.get(k).map(str::to_string));
            (profile, case.material().friction(), title)
        }
    };
    let plot = ProfilePlot {
        profile: &profile,
        friction,
        frame: Frame {
            title,
            show_title: args.title,
            style,
        },
    };
    super::figure::write_plot(&plot, &file(".svg"), &file(".png"))?;
    outln!(
        "wrote {} and {} (the fretting profile of cycle {})",
        file(".svg").display(),
        file(".png").display(),
        profile.cycle
    );
    Ok(ExitCode::SUCCESS)
}

/// The caption's start: the case, from the profile's header.
fn profile_title(get: impl Fn(&str) -> Option<String>) -> String {
    let value = |k: &str| get(k).unwrap_or_else(|| "?".into());
    let cycle = match get("load-cycle") {
        Some(c) => format!("the load cycle {c}"),
        None => format!("φ = {}", value("phi")),
    };
    format!(
        "Fretting profile: λ = {}, {cycle}, initial path {}, state {}",
        value("lambda"),
        value("initial"),
        value("state")
    )
}
