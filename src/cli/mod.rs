//! Command-line interface. Each subcommand lives in its own file; this one
//! holds the flags every case shares and the error-to-exit-code mapping.

/// `println!` that never panics: a closed pipe ends the command quietly,
/// a full disk is an error (see [`batch::print_stdout`]).
macro_rules! outln {
    () => {
        $crate::cli::batch::print_stdout("\n")?
    };
    ($($arg:tt)*) => {
        $crate::cli::batch::print_stdout(&format!("{}\n", format_args!($($arg)*)))?
    };
}

/// `eprintln!` that never panics: when stderr cannot be written (a full
/// disk, a closed pipe), nothing more can be said, so the process ends
/// quietly with status 1 (an environment failure).
macro_rules! errln {
    ($($arg:tt)*) => {
        $crate::cli::batch::print_stderr(&format!("{}\n", format_args!($($arg)*)))
    };
}

pub mod batch;
mod design;
mod events;
mod figure;
mod limit;
mod merge;
mod presets;
mod run;
mod sweep;
mod values;

use std::process::ExitCode;

use anyhow::{anyhow, Result};
use clap::{Args, Parser, Subcommand};
use shakedown::analysis::case::{Case, CaseError, CaseParams};
use shakedown::io::parse::{parse_angle, parse_number, parse_point};
use shakedown::io::preset::Preset;
use shakedown::model::{ranges, Plane};

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
    /// Join the outputs of `sweep --shard K/N` into one CSV, in the order an
    /// unsharded sweep with the same flags writes.
    Merge(merge::MergeArgs),
    /// Open the terminal explorer (the default).
    Tui(TuiArgs),
    /// List the built-in presets (the paper's figures).
    Presets,
    /// Reproduce one of the paper's figures: data as CSV, plot as SVG and PNG.
    Figure(figure::FigureArgs),
    /// The shakedown limit lambda_2 by linear programming, and its optimal slip.
    Limit(limit::LimitArgs),
    /// Search transients O -> P1 -> ... -> PK -> A whose steady cycle shakes down at --lambda (or, with --frontier, the highest lambda at which one found does).
    Design(design::DesignArgs),
    /// Every event of one run (advancing stick, slip start, zone changes, ...) as a labelled CSV.
    Events(events::EventsArgs),
}

/// Flags of the model and its discretisation, shared by every command.
/// Unset flags keep the preset's (or the paper's) values.
#[derive(Debug, Clone, Default, Args)]
pub struct ModelArgs {
    /// Slope psi of the load line (eq. 13).
    #[arg(long, value_name = "PSI", allow_hyphen_values = true, value_parser = values::number(ranges::PSI))]
    pub psi: Option<String>,
    /// Cycle centre A = x0,y0 in the load plane (accepts pi: pi,0.75pi).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true, value_parser = values::point(ranges::CENTER))]
    pub center: Option<String>,
    /// Coulomb friction coefficient f.
    #[arg(long, value_name = "F", allow_hyphen_values = true, value_parser = values::number(ranges::FRICTION))]
    pub friction: Option<String>,
    /// Poisson's ratio nu.
    #[arg(long, value_name = "NU", allow_hyphen_values = true, value_parser = values::number(ranges::NU))]
    pub nu: Option<String>,
    /// Plane strain or plane stress.
    #[arg(long, value_name = "strain|stress")]
    pub plane: Option<String>,
    // The help quotes the range (`model::ranges`, the one place it is written).
    #[arg(long, value_name = "N", allow_hyphen_values = true, value_parser = values::count(ranges::NODES),
          help = format!("Nodes round the interface: {}", ranges::NODES.expected))]
    pub nodes: Option<String>,
    /// Increments per cycle.
    #[arg(long, value_name = "STEPS", allow_hyphen_values = true, value_parser = values::count(ranges::STEPS))]
    pub steps: Option<String>,
    /// Cycle cap before a run is reported not-converged.
    #[arg(long, value_name = "CYCLES", allow_hyphen_values = true, value_parser = values::count(ranges::MAX_CYCLES))]
    pub max_cycles: Option<String>,
    /// Run asymptotic shakedown out to its first cycle without slip instead
    /// of stopping once a safe state proves it (docs/model.md section 6.4).
    #[arg(long)]
    pub run_out: bool,
    /// Any closed load cycle instead of the ellipse: a CSV with header u,v, one vertex (offset from the centre A) a row in time order; the load is A + lambda (u, v), equal time per chord, so --steps must be a multiple of the vertex count (docs/model.md section 5.4). Not with --phi or --psi.
    #[arg(long, value_name = "FILE", conflicts_with = "psi")]
    pub cycle: Option<String>,
}

impl ModelArgs {
    /// The files these flags read (`--cycle`), as `(what, path)` for
    /// [`batch::refuse_input_as_output`]: no output may be one of them.
    pub fn input_files(&self) -> Vec<(&'static str, &std::path::Path)> {
        self.cycle
            .iter()
            .map(|c| ("--cycle file", std::path::Path::new(c.as_str())))
            .collect()
    }
}

/// The polyline cycle of `--cycle FILE`; a bad file is bad input, on one
/// line naming the flag.
pub fn cycle_file(path: &str) -> Result<shakedown::model::Polyline> {
    shakedown::io::cycle::read_cycle_file(std::path::Path::new(path)).map_err(|e| {
        anyhow!(InputError(format!(
            "--cycle {}: {e}",
            shakedown::io::read::escape_text(path, 200)
        )))
    })
}

/// Flags that define one case. Unset flags keep the preset's (or the
/// paper's) values.
#[derive(Debug, Clone, Default, Args)]
pub struct CaseArgs {
    /// Start from a preset: a built-in name (see `shakedown presets`) or a path to a .toml file.
    #[arg(long, value_name = "NAME|FILE")]
    pub preset: Option<String>,
    /// Load factor lambda (eq. 12).
    #[arg(long, value_name = "LAMBDA", allow_hyphen_values = true, value_parser = values::number(ranges::LAMBDA))]
    pub lambda: Option<String>,
    /// Phase phi between torque and force, radians or multiples of pi (0.5pi, pi/2).
    // Parsed as a list: `limit --phi LIST|RANGE` draws the curve; the
    // commands that take one phase refuse a list when they read it.
    #[arg(long, value_name = "ANGLE", allow_hyphen_values = true, value_parser = values::list(ranges::PHI, parse_angle))]
    pub phi: Option<String>,
    /// Initial path: OA, one of the 24 points as a,b in units of pi/4 (e.g. 7,-7), or optimal.
    #[arg(long, value_name = "NAME", allow_hyphen_values = true)]
    pub initial: Option<String>,
    /// A custom transient O -> points -> A instead of --initial: load-plane points "X1,Y1;X2,Y2" (angles as in --phi, e.g. "1.75pi,-1.75pi").
    #[arg(
        long,
        value_name = "X,Y;...",
        allow_hyphen_values = true,
        conflicts_with = "initial"
    )]
    pub initial_path: Option<String>,
    #[command(flatten)]
    pub model: ModelArgs,
}

impl CaseArgs {
    /// The files a case reads (the preset file, `--cycle`): no output may
    /// be one of them ([`batch::refuse_input_as_output`]).
    pub fn input_files(&self) -> Vec<(&'static str, &std::path::Path)> {
        let mut files: Vec<(&'static str, &std::path::Path)> = self
            .preset
            .iter()
            .map(|p| ("--preset file", std::path::Path::new(p.as_str())))
            .collect();
        files.extend(self.model.input_files());
        files
    }
}

/// The custom transient of `--initial-path TEXT` for `material`; a bad
/// point is bad input, on one line.
pub fn custom_path(
    text: &str,
    material: &shakedown::model::Material,
) -> Result<shakedown::model::path::Initial> {
    let points = shakedown::io::parse::parse_points(text).map_err(|e| {
        anyhow!(InputError(format!(
            "--initial-path {text}: {e}: expected points X1,Y1;X2,Y2 (e.g. 1.75pi,-1.75pi)"
        )))
    })?;
    let points = points
        .into_iter()
        .map(|(x, y)| shakedown::LoadPoint::new(x, y))
        .collect();
    shakedown::model::path::Initial::custom_for(points, material)
        .map_err(|e| anyhow!(InputError(format!("--initial-path {text}: {e}"))))
}

/// An initial path as the command line names it: `OA`, `a,b` or
/// `optimal` (resolved when the case is built).
pub fn parse_initial(
    text: &str,
) -> std::result::Result<shakedown::model::Initial, shakedown::model::PathError> {
    if text.trim().eq_ignore_ascii_case("optimal") {
        Ok(shakedown::model::Initial::Optimal)
    } else {
        shakedown::model::Initial::parse(text)
    }
}

/// Load a preset named by a flag; a bad one is an input error.
pub fn load_preset(flag: &str, name: &str) -> Result<Preset> {
    shakedown::io::preset::load(name)
        .map_err(|e| anyhow!(InputError(format!("{flag} {name}: {e}"))))
}

/// What each flag accepts, as error messages say it: the library's own
/// ranges (`shakedown::model::ranges`), written once there.
pub fn accepted(flag: &str) -> Option<String> {
    Some(match flag {
        "center" => format!(
            "x0,y0 with {} (pi allowed: pi,0.75pi)",
            ranges::CENTER.expected
        ),
        "plane" => "strain or stress".into(),
        "cycle" => "a CSV file with header u,v and at least 3 finite vertices".into(),
        f => ranges::expected(f)?.into(),
    })
}

/// The one-line error of a bad `--{flag} {value}`: the flag, the value, why,
/// and what the flag accepts.
pub fn bad_flag(flag: &str, value: &str, why: impl std::fmt::Display) -> anyhow::Error {
    let why = why.to_string();
    let message = match accepted(flag) {
        Some(range) if !why.contains("expected") => {
            format!("--{flag} {value}: {why}: expected {range}")
        }
        _ => format!("--{flag} {value}: {why}"),
    };
    anyhow!(InputError(message))
}

/// The flag a validation error is about.
pub fn flag_of(e: &CaseError) -> Option<&'static str> {
    match e {
        CaseError::Param(p) => Some(match p.name() {
            "x0" | "y0" | "center" => "center",
            "lambda" => "lambda",
            "phi" => "phi",
            "psi" => "psi",
            "friction" => "friction",
            "nu" => "nu",
            "nodes" => "nodes",
            "steps" => "steps",
            "cycle" => "cycle",
            "max-cycles" => "max-cycles",
            _ => return None,
        }),
        CaseError::Path(_) | CaseError::Optimal(_) => Some("initial"),
        CaseError::Slip { .. } => None,
    }
}

/// A validation error as bad input, naming the flag when `given` knows the
/// flag's value on the command line.
pub fn case_error(e: CaseError, given: impl Fn(&str) -> Option<String>) -> anyhow::Error {
    match flag_of(&e).and_then(|f| given(f).map(|v| (f, v))) {
        Some((flag, value)) => bad_flag(flag, &value, e),
        None => anyhow!(InputError(e.to_string())),
    }
}

fn flag<T, E: std::fmt::Display>(
    name: &str,
    value: &Option<String>,
    parse: impl Fn(&str) -> std::result::Result<T, E>,
) -> Result<Option<T>> {
    value
        .as_deref()
        .map(|v| parse(v).map_err(|e| bad_flag(name, v, e)))
        .transpose()
}

fn count(text: &str) -> std::result::Result<usize, String> {
    text.trim()
        .parse::<usize>()
        .map_err(|_| format!("'{text}' is not a whole number"))
}

impl ModelArgs {
    /// Apply the flags that were given on top of `p`.
    pub fn apply(&self, mut p: CaseParams) -> Result<CaseParams> {
        if let Some(v) = flag("psi", &self.psi, parse_number)? {
            p.slope = v;
        }
        if let Some(v) = flag("center", &self.center, parse_point)? {
            p.center = v;
        }
        if let Some(v) = flag("friction", &self.friction, parse_number)? {
            p.friction = v;
        }
        if let Some(v) = flag("nu", &self.nu, parse_number)? {
            p.poisson = v;
        }
        if let Some(v) = flag("plane", &self.plane, |t| t.parse::<Plane>())? {
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
        if self.run_out {
            p.safe_state = false;
        }
        if let Some(path) = &self.cycle {
            p.cycle = Some(cycle_file(path)?);
        }
        if let Some(psi) = &self.psi {
            refuse_phase_with_polyline(&p, "psi", psi)?;
        }
        Ok(p)
    }
}

impl ModelArgs {
    /// The value given for `--{flag}`, if any.
    pub fn given(&self, flag: &str) -> Option<String> {
        match flag {
            "psi" => self.psi.clone(),
            "center" => self.center.clone(),
            "friction" => self.friction.clone(),
            "nu" => self.nu.clone(),
            "plane" => self.plane.clone(),
            "nodes" => self.nodes.clone(),
            "steps" => self.steps.clone(),
            "max-cycles" => self.max_cycles.clone(),
            "cycle" => self.cycle.clone(),
            _ => None,
        }
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
    pub fn apply(&self, p: CaseParams) -> Result<CaseParams> {
        let mut p = self.model.apply(p)?;
        if let Some(v) = flag("lambda", &self.lambda, parse_number)? {
            p.load_factor = v;
        }
        if let Some(v) = flag("phi", &self.phi, parse_angle)? {
            refuse_phase_with_polyline(&p, "phi", self.phi.as_deref().unwrap_or_default())?;
            p.phase = v;
        }
        if let Some(v) = &self.initial {
            p.initial = parse_initial(v).map_err(|e| bad_flag("initial", v, e))?;
        }
        Ok(p)
    }

    /// The validated case. A custom transient (`--initial-path`, else the
    /// preset's `initial-path` unless `--initial` is given) replaces the
    /// named initial path.
    pub fn case(&self, base: CaseParams) -> Result<(CaseParams, Case)> {
        let params = self.apply(base)?;
        let mut case = Case::from_params(&params).map_err(|e| case_error(e, |f| self.given(f)))?;
        warn_if_slow(
            params.nodes,
            params.steps,
            CostClass::of(&params, &[params.phase]),
        );
        if let Some(text) = &self.initial_path {
            case.set_initial(custom_path(text, &case.material())?)?;
        } else if self.initial.is_none() {
            if let Some(path) = self.preset()?.and_then(|p| p.initial_path) {
                case.set_initial(path)?;
            }
        }
        Ok((params, case))
    }

    /// The value given for `--{flag}`, if any.
    pub fn given(&self, flag: &str) -> Option<String> {
        match flag {
            "lambda" => self.lambda.clone(),
            "phi" => self.phi.clone(),
            "initial" => self.initial.clone(),
            "initial-path" => self.initial_path.clone(),
            f => self.model.given(f),
        }
    }
}

/// `--phi` (or `--psi`) with a polyline cycle: refused, since a polyline
/// has neither (docs/model.md section 5.4).
pub fn refuse_phase_with_polyline(p: &CaseParams, flag: &str, value: &str) -> Result<()> {
    if p.cycle.is_some() {
        return Err(anyhow!(InputError(format!(
            "--{flag} {value}: a polyline cycle (--cycle or the preset's cycle) has no {flag}: drop --{flag}, or give the phase in the cycle's vertices"
        ))));
    }
    Ok(())
}

/// Largest `--nodes` and `--steps` of the interactive range: a run takes
/// well under a second up to here.
pub const INTERACTIVE_NODES: usize = 512;
/// See [`INTERACTIVE_NODES`].
pub const INTERACTIVE_STEPS: usize = 2000;

/// CPU seconds of one run to its verdict at 400 increments per cycle, by
/// node count, measured for a fast case (`--lambda 5.5 --phi 0`, cyclic
/// slip) and a slow one (`--lambda 6 --phi pi/2`, out of phase,
/// ratchetting): `(nodes, fast, slow)`. Between the two lie the cases
/// tried; the cost is the events of each cycle (about `N^2` while the
/// slip zones are a few arcs) times the cycles to a verdict, and out of
/// phase both grow faster with `N`.
const RUN_SECONDS: [(f64, f64, f64); 4] = [
    (512.0, 0.12, 0.08),
    (1024.0, 0.49, 0.72),
    (2048.0, 2.22, 22.7),
    (4096.0, 12.35, 182.6),
];

/// The expected CPU time of one run, `(fast, slow)` in seconds: the
/// measured times of [`RUN_SECONDS`] interpolated in `log N` (as `N^2.1`
/// below 512 nodes), plus the increments beyond 400 a cycle (about
/// `2.5e-10 N^2` s each: 0.36 s more at 1024 nodes and 1600 increments).
pub fn expected_run_seconds(nodes: usize, steps: usize) -> (f64, f64) {
    let n = nodes as f64;
    let at = |pick: fn(&(f64, f64, f64)) -> f64| {
        let first = &RUN_SECONDS[0];
        if n <= first.0 {
            return pick(first) * (n / first.0).powf(2.1);
        }
        for w in RUN_SECONDS.windows(2) {
            if n <= w[1].0 {
                let f = (n / w[0].0).ln() / (w[1].0 / w[0].0).ln();
                return pick(&w[0]) * (pick(&w[1]) / pick(&w[0])).powf(f);
            }
        }
        let last = &RUN_SECONDS[RUN_SECONDS.len() - 1];
        pick(last) * (n / last.0).powi(3)
    };
    let extra = 2.5e-10 * n * n * steps.saturating_sub(400) as f64;
    (at(|r| r.1) + extra, at(|r| r.2) + extra)
}

/// A time for a warning: `about 3 s`, `about 2 min`.
fn readable_time(t: f64) -> String {
    if t < 0.5 {
        "under a second".to_string()
    } else if t < 10.0 {
        format!("about {t:.1} s")
    } else if t < 60.0 {
        format!("about {t:.0} s")
    } else if t < 3600.0 {
        format!("about {:.0} min", t / 60.0)
    } else {
        format!("about {:.1} h", t / 3600.0)
    }
}

/// Which of the measured cases of [`RUN_SECONDS`] the runs ahead are like:
/// an in-phase cycle (a straight line, `phi = 0` or `pi`) costs like the
/// fast case, an elliptical one like the slow case; a sweep over both, or
/// a polyline cycle, gets the range between them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CostClass {
    /// Every cycle is a straight line.
    Line,
    /// Every cycle is an ellipse.
    Ellipse,
    /// Some of each, or a polyline.
    Mixed,
}

impl CostClass {
    /// The class of the cycles of `params` over the phases `phases`.
    pub fn of(params: &CaseParams, phases: &[f64]) -> Self {
        if params.cycle.is_some() {
            return Self::Mixed;
        }
        let line = |phi: f64| shakedown::analysis::limit::is_line(params.slope, phi);
        match (
            phases.iter().all(|&p| line(p)),
            phases.iter().any(|&p| line(p)),
        ) {
            (true, _) => Self::Line,
            (false, false) => Self::Ellipse,
            _ => Self::Mixed,
        }
    }
}

/// Warn on stderr (one line) when `--nodes` or `--steps` is above the
/// interactive range, with the expected time per run
/// ([`expected_run_seconds`]): that of the measured case the runs are
/// like ([`CostClass`]), or the range from the fast case to the slow one.
pub fn warn_if_slow(nodes: usize, steps: usize, class: CostClass) {
    if nodes <= INTERACTIVE_NODES && steps <= INTERACTIVE_STEPS {
        return;
    }
    let (fast, slow) = expected_run_seconds(nodes, steps);
    let (lo, hi) = match class {
        CostClass::Line => (fast, fast),
        CostClass::Ellipse => (slow, slow),
        CostClass::Mixed => (fast.min(slow), fast.max(slow)),
    };
    let time = if hi < 2.0 * lo || hi < 0.5 {
        format!("{} of CPU per run", readable_time(hi))
    } else {
        format!(
            "{} to {} of CPU per run (out of phase, ratchetting runs take longest)",
            readable_time(lo),
            readable_time(hi).trim_start_matches("about ")
        )
    };
    errln!(
        "warning: --nodes {nodes} --steps {steps} is above the interactive range (nodes <= {INTERACTIVE_NODES}, steps <= {INTERACTIVE_STEPS}): expect {time}"
    );
}

/// The initial path of `--initial-slip FILE`: start at the cycle centre
/// with the slip of an optimal-slip CSV (`limit --out FILE`), which must
/// have one finite value per node of `nodes`.
pub fn initial_slip(path: &str, nodes: usize) -> Result<shakedown::model::Initial> {
    use shakedown::io::read::{escape_text, read_text_capped, MAX_PRESET_BYTES};
    let shown = escape_text(path, 200);
    let bad =
        |e: &dyn std::fmt::Display| anyhow!(InputError(format!("--initial-slip {shown}: {e}")));
    let text =
        read_text_capped(std::path::Path::new(path), MAX_PRESET_BYTES).map_err(|e| bad(&e))?;
    // The slip is identified by its content, not its name: a file replaced
    // meanwhile gives another name, which --resume and merge refuse.
    let id = shakedown::io::hash::content_id(text.as_bytes());
    let slip = shakedown::io::csv::read_slip_csv(&text, nodes).map_err(|e| bad(&e))?;
    let stem = std::path::Path::new(path)
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem: String = stem
        .chars()
        .map(|c| {
            if c == '"' || c == ',' || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    Ok(shakedown::model::Initial::Slip {
        name: format!("slip:{stem}@sha256:{id}"),
        slip: std::sync::Arc::new(slip),
    })
}

/// Bad user input: reported on one line with exit status 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// The explorer opens on the paper's Fig. 3 case at lambda = 6 (phi = 0)
/// through the transient `7,-7`, unless the case flags say otherwise.
#[derive(Debug, Args, Default)]
#[command(
    after_help = "Defaults for tui: --lambda 6 --phi 0 --initial 7,-7 (the paper's Fig. 3, cyclic slip).\nASCII drawing is automatic for TERM=linux, vt100 and dumb; NO_COLOR turns colour off."
)]
pub struct TuiArgs {
    #[command(flatten)]
    pub case: CaseArgs,
    /// Draw with ASCII only (no Braille, box drawing or Greek letters).
    #[arg(long)]
    pub ascii: bool,
    /// Memory for the record of the run (history, event log, cycles), in
    /// MiB; older detail is decimated, then dropped, to stay within it.
    #[arg(long, value_name = "MIB", default_value_t = shakedown::tui::app::DEFAULT_HISTORY_MB as u64,
          value_parser = clap::value_parser!(u64).range(8..=65536))]
    pub history_mb: u64,
    /// Open on the guided tour: the paper's story in eight live stops
    /// (n next, N back, Esc takes over).
    #[arg(long)]
    pub tour: bool,
}

/// Parse the command line, run it, and map errors to exit codes: 2 for bad
/// input, 1 for a failure while running.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            let help = matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            );
            if help || !e.use_stderr() {
                // `--help > /dev/full`: the help was not shown, so fail.
                let shown =
                    e.print().is_ok() && std::io::Write::flush(&mut std::io::stdout()).is_ok();
                return ExitCode::from(match (shown, e.use_stderr()) {
                    (false, _) => 1,
                    (true, true) => 2,
                    (true, false) => 0,
                });
            }
            match values::render(&e) {
                Some(line) => errln!(
                    "error: {}",
                    shorten_numbers(&shakedown::io::read::escape_text(&line, 2000))
                ),
                None => errln!("error: {}", clap_one_line(&e)),
            }
            return ExitCode::from(2);
        }
    };
    clamp_threads();
    let result = match cli.command {
        None => tui(TuiArgs {
            history_mb: shakedown::tui::app::DEFAULT_HISTORY_MB as u64,
            ..TuiArgs::default()
        }),
        Some(Command::Run(a)) => run::run(a),
        Some(Command::Sweep(a)) => sweep::sweep(a),
        Some(Command::Merge(a)) => merge::merge(a),
        Some(Command::Tui(a)) => tui(a),
        Some(Command::Presets) => presets::presets(),
        Some(Command::Figure(a)) => figure::figure(a),
        Some(Command::Limit(a)) => limit::limit(a),
        Some(Command::Design(a)) => design::design(a),
        Some(Command::Events(a)) => events::events(a),
    };
    match result {
        Ok(code) => code,
        // `shakedown presets | head -1`: the reader has what it wants.
        Err(e) if batch::is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            errln!("error: {}", one_line(&e));
            if is_input_error(&e) {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}

/// The whole error chain on one line, control characters escaped (a
/// file's content may be quoted in it) and very long numbers shortened.
fn one_line(e: &anyhow::Error) -> String {
    let text = e
        .chain()
        .map(|c| c.to_string())
        .collect::<Vec<_>>()
        .join(": ")
        .replace('\n', " ");
    shorten_numbers(&shakedown::io::read::escape_text(&text, 2000))
}

/// Numbers written out with more than 30 digits (`1e300` printed by
/// `{}`) in exponent form; any shorter number is kept as written.
fn shorten_numbers(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find(|c: char| c.is_ascii_digit()) {
        out.push_str(&rest[..start]);
        let tail = &rest[start..];
        let len = tail
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(tail.len());
        let run = &tail[..len];
        let digits = run.chars().filter(char::is_ascii_digit).count();
        match run.parse::<f64>() {
            // Only numbers no shortest form needs (`1e-320` written out):
            // a row's `-0.0000033333333333333335` is quoted as it is.
            Ok(v) if digits > 30 => out.push_str(&format!("{v:e}")),
            _ => out.push_str(run),
        }
        rest = &tail[len..];
    }
    out.push_str(rest);
    out
}

/// A command-line syntax error from clap on one line: its first line
/// (without clap's own `error: `), and where to look for help.
fn clap_one_line(e: &clap::Error) -> String {
    // The message up to the usage line: a missing argument's name is on
    // the lines after the first.
    let text = e.render().to_string();
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .filter(|l| !l.is_empty())
        .collect();
    let joined = if lines.is_empty() {
        "invalid command line".to_string()
    } else {
        lines.join(" ")
    };
    let first = joined.strip_prefix("error: ").unwrap_or(&joined);
    // The help of the subcommand that refused it (the first argument, where
    // it names one): that is where its flags are listed.
    // (`args_os`: an argument that is not UTF-8 is a syntax error too.)
    let command = std::env::args_os()
        .nth(1)
        .and_then(|first| {
            use clap::CommandFactory;
            Cli::command()
                .find_subcommand(first.to_str()?)
                .map(|c| format!("shakedown {}", c.get_name()))
        })
        .unwrap_or_else(|| "shakedown".to_string());
    format!(
        "{} (see {command} --help)",
        shakedown::io::read::escape_text(first, 500)
    )
}

fn is_input_error(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.is::<InputError>()
            || c.is::<shakedown::io::parse::ParseError>()
            || c.is::<shakedown::analysis::case::CaseError>()
            || c.is::<shakedown::model::ParamError>()
            || c.is::<shakedown::model::path::PathError>()
            || c.is::<shakedown::io::preset::PresetError>()
            || c.is::<shakedown::io::csv::MetadataError>()
            || c.is::<shakedown::io::read::ReadError>()
    })
}

/// Threads per core beyond which more threads only cost memory and
/// start-up time (`RAYON_NUM_THREADS=100000` hangs a run).
const THREADS_PER_CORE: usize = 4;

/// Clamp a `RAYON_NUM_THREADS` far above the cores, with a warning. The
/// results do not depend on the thread count, only the time does.
fn clamp_threads() {
    let Some(asked) = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok())
    else {
        return;
    };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cap = THREADS_PER_CORE * cores;
    if asked > cap {
        errln!(
            "warning: RAYON_NUM_THREADS={asked} is far above the {cores} cores: using {cap} threads (the results are the same)"
        );
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(cap)
            .build_global();
    }
}

/// The memory the system can give without swapping (`MemAvailable` of
/// `/proc/meminfo`), in MiB, where the system says.
fn available_mib() -> Option<u64> {
    let text =
        shakedown::io::read::read_text_capped(std::path::Path::new("/proc/meminfo"), 1 << 16)
            .or_else(|_| std::fs::read_to_string("/proc/meminfo"))
            .ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024)
}

/// Refuse a `--history-mb` above half the memory available: the record
/// grows to it, and the rest of the system needs the remainder.
fn check_history_mb(mib: u64) -> Result<()> {
    if let Some(avail) = available_mib() {
        let cap = (avail / 2).max(8);
        if mib > cap {
            return Err(anyhow!(InputError(format!(
                "--history-mb {mib}: at most {cap} on this machine (half the {avail} MiB of memory available): use less"
            ))));
        }
    }
    Ok(())
}

fn tui(args: TuiArgs) -> Result<ExitCode> {
    check_history_mb(args.history_mb)?;
    let preset = args.case.preset()?;
    let base = preset
        .as_ref()
        .map_or_else(shakedown::tui::default_params, |p| p.params.clone());
    let (_, case) = args.case.case(base)?;
    // Before anything touches the terminal, so a pipe gets no escape codes
    // and the exit status says "bad input" rather than "failed".
    shakedown::tui::terminal::check_tty().map_err(|e| anyhow!(InputError(e.to_string())))?;
    let mut config = shakedown::tui::app::Config::from_env();
    config.ascii |= args.ascii;
    config.history_bytes = usize::try_from(args.history_mb << 20).unwrap_or(usize::MAX);
    let code = if args.tour {
        shakedown::tui::run_tour(case, preset, config)?
    } else {
        shakedown::tui::run_with(case, preset, config)?
    };
    Ok(ExitCode::from(code))
}

#[cfg(test)]
mod tests;
