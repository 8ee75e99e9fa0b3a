//! Command-line interface. Each subcommand lives in its own file; this one
//! holds the flags every case shares and the error-to-exit-code mapping.

mod figure;
mod limit;
mod presets;
mod run;
mod sweep;

use std::process::ExitCode;

use anyhow::{anyhow, Context, Result};
use clap::{Args, Parser, Subcommand};
use shakedown::case::{Case, CaseParams};
use shakedown::params::Plane;
use shakedown::parse::{parse_angle, parse_number, parse_point};
use shakedown::preset::Preset;

#[derive(Debug, Parser)]
#[command(
    name = "shakedown",
    version,
    about = "Frictional shakedown of a shrink-fitted disc: terminal explorer and batch tool",
    long_about = "Frictional shakedown of a shrink-fitted disc (Cwiekala, Barber & Hills).\n\
                  Without a subcommand it opens the terminal explorer on the default case."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run one case to its steady state and print a summary (or JSON).
    Run(run::RunArgs),
    /// Run a grid of lambda x phi x initial paths and write CSV.
    Sweep(sweep::SweepArgs),
    /// Open the terminal explorer (the default).
    Tui(TuiArgs),
    /// List the built-in presets (the paper's figures).
    Presets,
    /// Reproduce one of the paper's figures: data as CSV, plot as SVG and PNG.
    Figure(figure::FigureArgs),
    /// The shakedown limit lambda_2 by linear programming, and its optimal slip.
    Limit(limit::LimitArgs),
}

/// Flags of the model and its discretisation, shared by every command.
/// Unset flags keep the preset's (or the paper's) values.
#[derive(Debug, Clone, Default, Args)]
pub struct ModelArgs {
    /// Slope psi of the load line (eq. 13).
    #[arg(long, value_name = "PSI", allow_hyphen_values = true)]
    pub psi: Option<String>,
    /// Cycle centre A = x0,y0 in the load plane (accepts pi: pi,0.75pi).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub center: Option<String>,
    /// Coulomb friction coefficient f.
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub friction: Option<String>,
    /// Poisson's ratio nu.
    #[arg(long, value_name = "NU", allow_hyphen_values = true)]
    pub nu: Option<String>,
    /// Plane strain or plane stress.
    #[arg(long, value_name = "strain|stress")]
    pub plane: Option<String>,
    /// Nodes round the interface (even, 16..4096).
    #[arg(long, value_name = "N")]
    pub nodes: Option<String>,
    /// Increments per cycle.
    #[arg(long, value_name = "STEPS")]
    pub steps: Option<String>,
    /// Cycle cap before a run is reported not-converged.
    #[arg(long, value_name = "CYCLES")]
    pub max_cycles: Option<String>,
}

/// Flags that define one case. Unset flags keep the preset's (or the
/// paper's) values.
#[derive(Debug, Clone, Default, Args)]
pub struct CaseArgs {
    /// Start from a preset: a built-in name (see `shakedown presets`) or a path to a .toml file.
    #[arg(long, value_name = "NAME|FILE")]
    pub preset: Option<String>,
    /// Load factor lambda (eq. 12).
    #[arg(long, value_name = "LAMBDA", allow_hyphen_values = true)]
    pub lambda: Option<String>,
    /// Phase phi between torque and force, radians or multiples of pi (0.5pi, pi/2).
    #[arg(long, value_name = "ANGLE", allow_hyphen_values = true)]
    pub phi: Option<String>,
    /// Initial path: OA, one of the 24 points as a,b in units of pi/4 (e.g. 7,-7), or optimal.
    #[arg(long, value_name = "NAME", allow_hyphen_values = true)]
    pub initial: Option<String>,
    #[command(flatten)]
    pub model: ModelArgs,
}

/// Load a preset named by a flag; a bad one is an input error.
pub fn load_preset(flag: &str, name: &str) -> Result<Preset> {
    shakedown::preset::load(name).map_err(|e| anyhow!(InputError(format!("{flag} {name}: {e}"))))
}

fn flag<T>(
    name: &str,
    value: &Option<String>,
    parse: impl Fn(&str) -> Result<T>,
) -> Result<Option<T>> {
    value
        .as_deref()
        .map(|v| parse(v).with_context(|| format!("--{name} {v}")))
        .transpose()
}

fn count(text: &str) -> Result<usize> {
    text.trim()
        .parse::<usize>()
        .map_err(|_| anyhow!("'{text}' is not a whole number"))
}

impl ModelArgs {
    /// Apply the flags that were given on top of `p`.
    pub fn apply(&self, mut p: CaseParams) -> Result<CaseParams> {
        let num = |t: &str| parse_number(t).map_err(anyhow::Error::from);
        if let Some(v) = flag("psi", &self.psi, num)? {
            p.slope = v;
        }
        if let Some(v) = flag("center", &self.center, |t| {
            parse_point(t).map_err(Into::into)
        })? {
            p.center = v;
        }
        if let Some(v) = flag("friction", &self.friction, num)? {
            p.friction = v;
        }
        if let Some(v) = flag("nu", &self.nu, num)? {
            p.poisson = v;
        }
        if let Some(v) = flag("plane", &self.plane, |t| {
            t.parse::<Plane>().map_err(|e| anyhow!(e))
        })? {
            p.plane = v;
        }
        if let Some(v) = flag("nodes", &self.nodes, count)? {
            p.nodes = v;
        }
        if let Some(v) = flag("steps", &self.steps, count)? {
            p.steps = v;
        }
        if let Some(v) = flag("max-cycles", &self.max_cycles, count)? {
            p.max_cycles = v;
        }
        Ok(p)
    }
}

impl CaseArgs {
    /// The preset given with `--preset`, if any.
    pub fn preset(&self) -> Result<Option<Preset>> {
        self.preset
            .as_deref()
            .map(|name| load_preset("--preset", name))
            .transpose()
    }

    /// The parameters the flags apply to: the preset's, else `default`.
    pub fn base(&self, default: CaseParams) -> Result<CaseParams> {
        Ok(self.preset()?.map_or(default, |p| p.params))
    }

    /// Apply the flags that were given on top of `base`.
    pub fn apply(&self, p: CaseParams, with_lambda_phi: bool) -> Result<CaseParams> {
        let mut p = self.model.apply(p)?;
        let num = |t: &str| parse_number(t).map_err(anyhow::Error::from);
        if with_lambda_phi {
            if let Some(v) = flag("lambda", &self.lambda, num)? {
                p.load_factor = v;
            }
            if let Some(v) = flag("phi", &self.phi, |t| parse_angle(t).map_err(Into::into))? {
                p.phase = v;
            }
        }
        if let Some(v) = &self.initial {
            p.initial = v.clone();
        }
        Ok(p)
    }

    /// The validated case.
    pub fn case(&self, base: CaseParams) -> Result<(CaseParams, Case)> {
        let params = self.apply(base, true)?;
        let case = Case::from_params(&params).map_err(|e| anyhow!(InputError(e.to_string())))?;
        Ok((params, case))
    }
}

/// Bad user input: reported on one line with exit status 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

#[derive(Debug, Args)]
pub struct TuiArgs {
    #[command(flatten)]
    pub case: CaseArgs,
}

/// Parse the command line, run it, and map errors to exit codes: 2 for bad
/// input, 1 for a failure while running.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = match cli.command {
        None => tui(TuiArgs {
            case: CaseArgs::default(),
        }),
        Some(Command::Run(a)) => run::run(a),
        Some(Command::Sweep(a)) => sweep::sweep(a),
        Some(Command::Tui(a)) => tui(a),
        Some(Command::Presets) => presets::presets(),
        Some(Command::Figure(a)) => figure::figure(a),
        Some(Command::Limit(a)) => limit::limit(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            if is_input_error(&e) {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}

/// The whole error chain on one line.
fn one_line(e: &anyhow::Error) -> String {
    e.chain()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(": ")
}

fn is_input_error(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.is::<InputError>()
            || c.is::<shakedown::parse::ParseError>()
            || c.is::<shakedown::case::CaseError>()
            || c.is::<shakedown::params::ParamError>()
            || c.is::<shakedown::path::PathError>()
            || c.is::<shakedown::preset::PresetError>()
    }) || e.root_cause().to_string().contains("is not a whole number")
        || e.root_cause().to_string().contains("is not a plane")
}

fn tui(args: TuiArgs) -> Result<ExitCode> {
    let base = args.case.base(shakedown::tui::default_params())?;
    let (_, case) = args.case.case(base)?;
    // Before anything touches the terminal, so a pipe gets no escape codes
    // and the exit status says "bad input" rather than "failed".
    shakedown::tui::terminal::check_tty().map_err(|e| anyhow!(InputError(e.to_string())))?;
    shakedown::tui::run(case)?;
    Ok(ExitCode::SUCCESS)
}
