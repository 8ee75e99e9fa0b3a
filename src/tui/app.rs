//! The explorer's state machine: what is being run, how fast, what the user
//! asked for, and the record of the slip map. No terminal I/O happens here,
//! so every key and every step can be tested with plain calls.
//!
//! All physics lives in [`Stepper`]; this file only drives it and keeps
//! what the panels need to draw.

use std::collections::VecDeque;
use std::f64::consts::PI;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossterm::event::KeyEvent;

use super::keys::{self, Action};
use super::sweep::{LimitState, Sweep, SweepSource};
use crate::case::Case;
use crate::contact::{Operators, SlipDirection};
use crate::params::Cycle;
use crate::path::Initial;
use crate::stepper::{self, slip_zones, Event, Phase, Status, Stepper};

/// `lambda` change of the arrow keys, and with Shift.
pub const LOAD_FACTOR_STEP: f64 = 0.05;
pub const LOAD_FACTOR_BIG_STEP: f64 = 0.5;
/// `phi` change of the up and down keys.
pub const PHASE_STEP: f64 = PI / 24.0;
/// Increments per frame the speed keys choose from.
pub const SPEEDS: [usize; 9] = [1, 2, 4, 8, 16, 32, 64, 128, 256];
const DEFAULT_SPEED: usize = 2;

/// Slip-map cell codes: the direction in the low bits, a flag on top.
pub const STICK: u8 = 0;
pub const FORWARD: u8 = 1;
pub const BACKWARD: u8 = 2;
pub const DIRECTION_MASK: u8 = 3;
/// The node went from slip to stick during this increment.
pub const NEWLY_STUCK: u8 = 4;

/// Enough rows of history for the widest slip map at the coarsest time
/// scale, but no more than a few megabytes however many nodes there are.
const HISTORY_BYTES: usize = 4 << 20;
const MIN_HISTORY_ROWS: usize = 4096;

/// How the explorer draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// False when `NO_COLOR` asks for monochrome; glyphs carry the meaning.
    pub color: bool,
}

impl Config {
    /// Colour unless `NO_COLOR` is set to a non-empty value (no-color.org).
    pub fn from_env() -> Self {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        Self { color: !no_color }
    }
}

impl Default for Config {
    fn default() -> Self {
        Self { color: true }
    }
}

/// What the screen shows: the one run being stepped, or a sweep's map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    #[default]
    Stepping,
    Sweep,
}

/// The preset the sweep view uses when the explorer was started without
/// one: the paper's Fig. 3, which the default case belongs to.
pub const DEFAULT_SWEEP_PRESET: &str = "fig3";

/// A stopping point the user asked for with `c` or `s`, reached
/// progressively over several frames so keys stay live meanwhile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    TransientEnd,
    /// Until this many cycles are complete.
    CycleEnd(usize),
    Steady,
}

/// One increment of the slip map.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlipRow {
    /// Increment number from the start of the run (0-based).
    pub increment: usize,
    /// Cycle the increment belongs to, 0 in the transient.
    pub cycle: usize,
    /// First increment of a cycle.
    pub cycle_start: bool,
    /// Per node: [`STICK`], [`FORWARD`] or [`BACKWARD`], maybe with
    /// [`NEWLY_STUCK`].
    pub cells: Vec<u8>,
}

/// The last advancing stick: where history got locked in, and how finely
/// the solver had to cut the increment to resolve it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StickInfo {
    pub nodes: Vec<usize>,
    pub substeps: usize,
    pub increment: usize,
}

/// Why a batch of steps stopped early.
enum Stop {
    /// The run cannot go on (ended, or the solver failed).
    Blocked,
    /// An event the user wants to see.
    Paused,
}

/// The explorer's whole state.
pub struct App {
    config: Config,
    case: Case,
    operators: Arc<Operators>,
    stepper: Stepper,
    paths: Vec<Initial>,
    path_index: usize,
    running: bool,
    speed: usize,
    goal: Option<Goal>,
    pause_on_events: bool,
    help: bool,
    quit: bool,
    rows: VecDeque<SlipRow>,
    row_capacity: usize,
    zones: Vec<(usize, usize, SlipDirection)>,
    recent_stuck: Vec<usize>,
    last_stick: Option<StickInfo>,
    last_event: Option<String>,
    notice: Option<String>,
    failure: Option<String>,
    view: View,
    /// The sweep view's sweep, or why there is none.
    sweep: Result<Sweep, String>,
}

impl App {
    /// The explorer on `case`, running, with the built-in
    /// [`DEFAULT_SWEEP_PRESET`] for the sweep view.
    pub fn new(case: Case, config: Config) -> Self {
        let source = crate::preset::load(DEFAULT_SWEEP_PRESET)
            .map_err(|e| e.to_string())
            .and_then(|p| SweepSource::from_preset(&p, &case).map_err(|e| e.to_string()));
        Self::with_sweep(case, config, source)
    }

    /// The explorer on `case` with `source` for the sweep view (an error
    /// is shown there instead of a map). The sweep starts the first time
    /// the sweep view opens, so a user who never looks at it pays nothing.
    pub fn with_sweep(case: Case, config: Config, source: Result<SweepSource, String>) -> Self {
        let operators = stepper::operators(&case.disc);
        let stepper = Self::fresh_stepper(&case, &operators);
        let mut paths = Initial::paper_set();
        let path_index = match paths.iter().position(|p| *p == case.initial) {
            Some(i) => i,
            None => {
                paths.push(case.initial.clone());
                paths.len() - 1
            }
        };
        let row_capacity = (HISTORY_BYTES / case.disc.nodes()).max(MIN_HISTORY_ROWS);
        Self {
            config,
            case,
            operators,
            stepper,
            paths,
            path_index,
            running: true,
            speed: DEFAULT_SPEED,
            goal: None,
            pause_on_events: false,
            help: false,
            quit: false,
            rows: VecDeque::new(),
            row_capacity,
            zones: Vec::new(),
            recent_stuck: Vec::new(),
            last_stick: None,
            last_event: None,
            notice: None,
            failure: None,
            view: View::Stepping,
            sweep: source.map(Sweep::new),
        }
    }

    fn fresh_stepper(case: &Case, operators: &Arc<Operators>) -> Stepper {
        Stepper::with_operators(
            Arc::clone(operators),
            case.material,
            case.disc,
            &case.initial,
            case.cycle,
            case.options,
        )
    }

    // ----- what the panels read -------------------------------------------

    pub fn config(&self) -> Config {
        self.config
    }
    pub fn case(&self) -> &Case {
        &self.case
    }
    pub fn stepper(&self) -> &Stepper {
        &self.stepper
    }
    pub fn load_factor(&self) -> f64 {
        self.case.cycle.load_factor
    }
    pub fn phase(&self) -> f64 {
        self.case.cycle.phase
    }
    pub fn paths(&self) -> &[Initial] {
        &self.paths
    }
    pub fn path_index(&self) -> usize {
        self.path_index
    }
    pub fn is_running(&self) -> bool {
        self.running
    }
    pub fn goal(&self) -> Option<Goal> {
        self.goal
    }
    /// Increments per frame while running.
    pub fn speed(&self) -> usize {
        SPEEDS[self.speed]
    }
    pub fn pauses_on_events(&self) -> bool {
        self.pause_on_events
    }
    pub fn help_visible(&self) -> bool {
        self.help
    }
    pub fn should_quit(&self) -> bool {
        self.quit
    }
    pub fn slip_rows(&self) -> &VecDeque<SlipRow> {
        &self.rows
    }
    /// Nodes that went from slip to stick in the latest increment that had
    /// advancing stick, if that was in the last batch of steps.
    pub fn recent_stuck(&self) -> &[usize] {
        &self.recent_stuck
    }
    pub fn last_stick(&self) -> Option<&StickInfo> {
        self.last_stick.as_ref()
    }
    pub fn last_event(&self) -> Option<&str> {
        self.last_event.as_deref()
    }
    /// A message about the last thing the user did (a restart, a pause).
    pub fn notice(&self) -> Option<&str> {
        self.notice.as_deref()
    }
    pub fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }
    /// The contiguous slip zones now.
    pub fn zones(&self) -> &[(usize, usize, SlipDirection)] {
        &self.zones
    }

    pub fn view(&self) -> View {
        self.view
    }
    /// The sweep view's sweep, or why there is none.
    pub fn sweep(&self) -> Result<&Sweep, &str> {
        self.sweep.as_ref().map_err(String::as_str)
    }
    /// For tests and tools that feed rows in themselves (as the background
    /// channel does), without starting the background sweep.
    pub fn sweep_mut(&mut self) -> Option<&mut Sweep> {
        self.sweep.as_mut().ok()
    }

    /// Show `view` without starting anything: what snapshots use, so the
    /// map holds only the rows they inject.
    pub fn show_view(&mut self, view: View) {
        self.view = view;
    }

    // ----- input ------------------------------------------------------------

    /// Dispatch a key through the key table.
    pub fn handle_key(&mut self, key: KeyEvent) {
        let Some(action) = keys::action_for(&key, self.view) else {
            return;
        };
        // With the help open, Esc closes it rather than quitting: the
        // help is the one place a user may press Esc just to back out.
        if self.help && action == Action::Quit && key.code == crossterm::event::KeyCode::Esc {
            self.help = false;
            return;
        }
        self.apply(action);
    }

    pub fn apply(&mut self, action: Action) {
        match action {
            Action::LoadFactorDown => self.change_load_factor(-LOAD_FACTOR_STEP),
            Action::LoadFactorUp => self.change_load_factor(LOAD_FACTOR_STEP),
            Action::LoadFactorDownBig => self.change_load_factor(-LOAD_FACTOR_BIG_STEP),
            Action::LoadFactorUpBig => self.change_load_factor(LOAD_FACTOR_BIG_STEP),
            Action::PhaseDown => self.change_phase(-1.0),
            Action::PhaseUp => self.change_phase(1.0),
            Action::PreviousPath => self.change_path(self.paths.len() - 1),
            Action::NextPath => self.change_path(1),
            Action::RunPause => self.run_pause(),
            Action::StepOne => {
                self.running = false;
                self.goal = None;
                if self.can_step() {
                    self.notice = None;
                    self.run_batch(1, None);
                }
            }
            Action::ToCycleEnd => self.set_goal(match self.stepper.phase() {
                Phase::Transient { .. } => Goal::TransientEnd,
                Phase::Cycle { .. } => Goal::CycleEnd(self.stepper.history().len() + 1),
            }),
            Action::ToSteady => {
                if let Status::Steady(s) = self.stepper.status() {
                    self.notice = Some(format!(
                        "already classified: {} after {} cycles",
                        s.state.as_str(),
                        s.cycles
                    ));
                } else {
                    self.set_goal(Goal::Steady);
                }
            }
            Action::Reset => {
                self.restart("reset");
                self.running = true;
            }
            Action::Faster => {
                self.speed = (self.speed + 1).min(SPEEDS.len() - 1);
                self.notice = Some(format!("speed: {} increments per frame", self.speed()));
            }
            Action::Slower => {
                self.speed = self.speed.saturating_sub(1);
                self.notice = Some(format!("speed: {} increments per frame", self.speed()));
            }
            Action::PauseOnEvents => {
                self.pause_on_events = !self.pause_on_events;
                self.notice = Some(if self.pause_on_events {
                    "pause on events: on (advancing stick, slip zones, classification)".into()
                } else {
                    "pause on events: off".into()
                });
            }
            Action::Help => self.help = !self.help,
            Action::Quit => self.request_quit(),
            Action::ToggleView => self.toggle_view(),
            Action::SweepPrevX => self.with_sweep_mut(|s| s.move_x(-1)),
            Action::SweepNextX => self.with_sweep_mut(|s| s.move_x(1)),
            Action::SweepPrevRun => self.with_sweep_mut(|s| s.move_run(-1)),
            Action::SweepNextRun => self.with_sweep_mut(|s| s.move_run(1)),
            Action::OpenRun => self.open_selected(),
            Action::RestartSweep => {
                if let Ok(s) = &mut self.sweep {
                    s.start();
                    self.notice = Some("sweep restarted".into());
                }
            }
        }
    }

    /// Quit from outside the key table (a SIGINT). The sweep's runs not yet
    /// started are dropped so the process is not kept busy on the way out.
    pub fn request_quit(&mut self) {
        self.quit = true;
        if let Ok(s) = &mut self.sweep {
            s.cancel();
        }
    }

    fn with_sweep_mut(&mut self, f: impl FnOnce(&mut Sweep)) {
        if let Ok(s) = &mut self.sweep {
            f(s);
        }
    }

    fn toggle_view(&mut self) {
        self.view = match self.view {
            View::Stepping => View::Sweep,
            View::Sweep => View::Stepping,
        };
        match (&mut self.sweep, self.view) {
            (Ok(s), View::Sweep) if !s.started() => {
                s.start();
                self.notice = Some(format!(
                    "sweep {} started in the background ({} runs)",
                    s.source().name,
                    s.total()
                ));
            }
            (Err(e), View::Sweep) => self.notice = Some(format!("no sweep: {e}")),
            _ => {}
        }
    }

    /// Open the run under the sweep cursor in the stepping view: its
    /// `lambda`, `phi` and initial path, restarted from O like the keys
    /// that change them.
    fn open_selected(&mut self) {
        let Ok(sweep) = &self.sweep else {
            return;
        };
        let Some((job, _)) = sweep.selected() else {
            self.notice = Some("no run under the cursor".into());
            return;
        };
        let job = *job;
        let initial = match sweep.initial(&job) {
            // The stepper needs the slip itself. The limit computed for the
            // map at this phase is that slip; only when it is not known yet
            // (or is for another phase) is the programme solved here.
            Initial::Optimal => match sweep.limit() {
                LimitState::Known(l) if sweep.source().spec.phases == [job.phase] => {
                    Initial::Slip {
                        name: "optimal".into(),
                        slip: Arc::new(l.slip.clone()),
                    }
                }
                _ => match Cycle::new(
                    self.case.cycle.center,
                    job.load_factor,
                    self.case.cycle.slope,
                    job.phase,
                )
                .map_err(|e| e.to_string())
                .and_then(|c| {
                    crate::limit::optimal_initial(&self.case.material, &c, &self.case.disc)
                        .map_err(|e| e.to_string())
                }) {
                    Ok(i) => i,
                    Err(e) => {
                        self.notice = Some(format!("cannot open the optimal slip: {e}"));
                        return;
                    }
                },
            },
            other => other.clone(),
        };
        let c = &self.case.cycle;
        let cycle = match Cycle::new(c.center, job.load_factor, c.slope, job.phase) {
            Ok(cycle) => cycle,
            Err(e) => {
                self.notice = Some(e.to_string());
                return;
            }
        };
        self.case.cycle = cycle;
        self.path_index = match self.paths.iter().position(|p| *p == initial) {
            Some(i) => i,
            None => {
                self.paths.push(initial.clone());
                self.paths.len() - 1
            }
        };
        self.case.initial = initial;
        self.view = View::Stepping;
        self.running = true;
        let what = format!(
            "opened lambda {}, phi {}, path {}",
            format_load_factor(job.load_factor),
            format_phase(job.phase),
            self.case.initial.name()
        );
        self.restart(&what);
    }

    fn can_step(&mut self) -> bool {
        if let Some(f) = &self.failure {
            self.notice = Some(format!("the solver failed ({f}); r to rerun"));
            return false;
        }
        if let Status::Ended(s) = self.stepper.status() {
            self.notice = Some(format!(
                "the run has ended ({}); r to rerun, or change lambda, phi or the path",
                s.state.as_str()
            ));
            return false;
        }
        true
    }

    fn run_pause(&mut self) {
        if self.running || self.goal.is_some() {
            self.running = false;
            self.goal = None;
            self.notice = Some("paused".into());
        } else if self.can_step() {
            self.running = true;
            self.notice = None;
        }
    }

    fn set_goal(&mut self, goal: Goal) {
        if self.can_step() {
            self.running = false;
            self.goal = Some(goal);
            self.notice = Some(match goal {
                Goal::TransientEnd => "to the end of the transient…".into(),
                Goal::CycleEnd(c) => format!("to the end of cycle {c}…"),
                Goal::Steady => "to the steady state…".into(),
            });
        }
    }

    fn change_load_factor(&mut self, delta: f64) {
        let old = self.load_factor();
        // Rounded so that repeated steps of 0.05 show as 5.55, not 5.550000001.
        let new = ((old + delta) * 1e6).round() / 1e6;
        let new = new.max(0.0);
        if new == old {
            self.notice = Some("lambda cannot go below 0".into());
            return;
        }
        self.change_cycle(
            new,
            self.phase(),
            format!("lambda {}", format_load_factor(new)),
        );
    }

    fn change_phase(&mut self, sign: f64) {
        let old = self.phase();
        let k = (old / PHASE_STEP).round();
        // Stay on the grid of pi/24 when on it, so labels stay exact.
        let mut new = if (old - k * PHASE_STEP).abs() < 1e-9 {
            (k + sign) * PHASE_STEP
        } else {
            old + sign * PHASE_STEP
        };
        // phi and phi +- 2 pi are the same cycle; keep it in (-pi, pi].
        if new > PI + 1e-9 {
            new -= 2.0 * PI;
        } else if new <= -PI + 1e-9 {
            new += 2.0 * PI;
        }
        self.change_cycle(
            self.load_factor(),
            new,
            format!("phi {}", format_phase(new)),
        );
    }

    fn change_cycle(&mut self, load_factor: f64, phase: f64, what: String) {
        let c = &self.case.cycle;
        match Cycle::new(c.center, load_factor, c.slope, phase) {
            Ok(cycle) => {
                self.case.cycle = cycle;
                self.restart(&what);
            }
            Err(e) => self.notice = Some(e.to_string()),
        }
    }

    fn change_path(&mut self, offset: usize) {
        self.path_index = (self.path_index + offset) % self.paths.len();
        self.case.initial = self.paths[self.path_index].clone();
        let what = format!("path {}", self.case.initial.name());
        self.restart(&what);
    }

    /// Start the run again from the unloaded state (or from `A` with a
    /// prescribed slip), keeping the running/paused choice.
    fn restart(&mut self, why: &str) {
        self.stepper = Self::fresh_stepper(&self.case, &self.operators);
        self.rows.clear();
        self.zones.clear();
        self.recent_stuck.clear();
        self.last_stick = None;
        self.last_event = None;
        self.failure = None;
        self.goal = None;
        let from = match self.case.initial {
            Initial::Slip { .. } => "restarted at A with the prescribed slip",
            _ => "restarted from O",
        };
        self.notice = Some(format!("{why}: {from}"));
    }

    // ----- stepping -----------------------------------------------------------

    /// One frame's stepping: the goal if there is one (as fast as the
    /// budget allows), else `speed` increments if running.
    pub fn tick(&mut self, budget: Duration) {
        let deadline = Instant::now() + budget;
        if let Ok(s) = &mut self.sweep {
            s.poll();
        }
        // The stepping run waits while the map is shown: its increments
        // would only take a core from the sweep the user is watching.
        if self.view == View::Sweep {
            return;
        }
        if self.goal.is_some() {
            self.run_batch(usize::MAX, Some(deadline));
        } else if self.running {
            self.run_batch(self.speed(), Some(deadline));
        }
    }

    /// Exactly `n` increments (fewer if the run stops), with no clock
    /// involved: what tests use to reach a reproducible state.
    pub fn advance(&mut self, n: usize) {
        self.run_batch(n, None);
    }

    /// Whether the loop has stepping to do (else it can sleep longer).
    pub fn is_busy(&self) -> bool {
        if self.sweep.as_ref().is_ok_and(|s| {
            s.is_running() || s.started() && matches!(s.limit(), LimitState::Computing)
        }) {
            return true;
        }
        self.view == View::Stepping
            && (self.running || self.goal.is_some())
            && self.failure.is_none()
            && !self.stepper.is_finished()
    }

    fn goal_reached(&self) -> bool {
        match self.goal {
            None => false,
            Some(Goal::TransientEnd) => matches!(self.stepper.phase(), Phase::Cycle { .. }),
            Some(Goal::CycleEnd(n)) => self.stepper.history().len() >= n,
            Some(Goal::Steady) => !matches!(self.stepper.status(), Status::Running),
        }
    }

    fn finish_goal(&mut self) {
        let Some(goal) = self.goal.take() else {
            return;
        };
        self.notice = Some(match (goal, self.stepper.summary()) {
            (Goal::Steady, Some(s)) => format!(
                "steady state: {} after {} cycles",
                s.state.as_str(),
                s.cycles
            ),
            (Goal::TransientEnd, _) => "end of the transient".into(),
            (Goal::CycleEnd(c), _) => format!("end of cycle {c}"),
            (Goal::Steady, None) => "stopped".into(),
        });
    }

    fn run_batch(&mut self, max: usize, deadline: Option<Instant>) {
        let mut cleared = false;
        for _ in 0..max {
            if self.goal_reached() {
                self.finish_goal();
                return;
            }
            if deadline.is_some_and(|d| Instant::now() >= d) {
                return;
            }
            if !cleared {
                // Highlights are per batch so none is lost when many
                // increments go by between two frames.
                self.recent_stuck.clear();
                cleared = true;
            }
            match self.step_once() {
                Ok(()) => {}
                Err(Stop::Blocked) => {
                    self.running = false;
                    self.goal = None;
                    return;
                }
                Err(Stop::Paused) => {
                    self.running = false;
                    self.goal = None;
                    return;
                }
            }
        }
        if self.goal_reached() {
            self.finish_goal();
        }
    }

    fn step_once(&mut self) -> Result<(), Stop> {
        if self.failure.is_some() || self.stepper.is_finished() {
            return Err(Stop::Blocked);
        }
        let phase = self.stepper.phase();
        let before = self.stepper.increments();
        let report = match self.stepper.step() {
            Ok(r) => r,
            Err(e) => {
                let text = e.to_string();
                self.last_event = Some(format!("solver failed: {text}"));
                self.failure = Some(text);
                return Err(Stop::Blocked);
            }
        };
        if self.stepper.increments() > before {
            self.record_row(phase, before, &report.newly_stuck);
        }
        if !report.newly_stuck.is_empty() {
            // Only the latest advancing stick is "just stuck": a batch of
            // hundreds of increments would otherwise light up everything.
            self.recent_stuck.clone_from(&report.newly_stuck);
        }

        let mut pause: Option<String> = None;
        // Set when an event worth pausing for happened; its text is what
        // the status line shows as the last event.
        for event in &report.events {
            let text = match event {
                Event::SlipSetChanged { slipping, zones } => {
                    let new = slip_zones(self.stepper.contact().directions());
                    let changes = zone_changes(&self.zones, &new, self.case.disc.nodes());
                    self.zones = new;
                    if changes.is_empty() {
                        format!(
                            "slip set changed: {slipping} nodes slipping in {}",
                            plural(*zones, "zone")
                        )
                    } else {
                        let text =
                            format!("{} ({} now)", changes.join(", "), plural(*zones, "zone"));
                        if changes.iter().any(|c| !c.contains("vanished")) {
                            pause.get_or_insert_with(|| text.clone());
                        }
                        text
                    }
                }
                Event::AdvancingStick {
                    nodes,
                    substeps,
                    load,
                    ..
                } => {
                    self.last_stick = Some(StickInfo {
                        nodes: nodes.clone(),
                        substeps: *substeps,
                        increment: before,
                    });
                    let text = format!(
                        "advancing stick at {} at load point ({:.4}, {:.4}) ({} sub-increments)",
                        describe_nodes(nodes, self.case.disc.nodes()),
                        load.x(),
                        load.y(),
                        substeps
                    );
                    pause.get_or_insert_with(|| text.clone());
                    text
                }
                Event::SlipEntry { nodes, load, .. } => format!(
                    "slip entry at {} at load point ({:.4}, {:.4})",
                    describe_nodes(nodes, self.case.disc.nodes()),
                    load.x(),
                    load.y()
                ),
                Event::TransientFinished => "transient finished: cycle 1 begins".into(),
                Event::CycleCompleted {
                    cycle,
                    dissipation,
                    rotation,
                } => format!(
                    "cycle {cycle} completed: W = {}, rotation {}",
                    format_sci(*dissipation),
                    format_sci(*rotation)
                ),
                Event::SteadyStateReached(s) => {
                    let text =
                        format!("classified: {} after {} cycles", s.state.as_str(), s.cycles);
                    pause = Some(text.clone());
                    text
                }
                Event::GrossSlip { load, .. } => {
                    format!(
                        "gross slip at load point ({:.3}, {:.3})",
                        load.x(),
                        load.y()
                    )
                }
                Event::Separation { theta, .. } => {
                    format!("separation at theta = {:.3}pi", theta / PI)
                }
            };
            self.last_event = Some(text);
        }
        if self.stepper.is_finished() {
            if let Some(s) = self.stepper.summary() {
                self.notice = Some(format!("the run ended: {}", s.state.as_str()));
            }
            return Err(Stop::Blocked);
        }
        match pause {
            Some(text) if self.pause_on_events => {
                // The event itself goes on the status line, where the last
                // event is shown, so the notice need not repeat it.
                self.last_event = Some(text);
                self.notice = Some("paused on the event (Space runs on)".into());
                Err(Stop::Paused)
            }
            _ => Ok(()),
        }
    }

    fn record_row(&mut self, phase: Phase, increment: usize, newly_stuck: &[usize]) {
        let (cycle, cycle_start) = match phase {
            Phase::Transient { .. } => (0, false),
            Phase::Cycle { cycle, increment } => (cycle, increment == 0),
        };
        let mut cells: Vec<u8> = self
            .stepper
            .contact()
            .directions()
            .iter()
            .map(|d| match d {
                SlipDirection::Stick => STICK,
                SlipDirection::Forward => FORWARD,
                SlipDirection::Backward => BACKWARD,
            })
            .collect();
        for &j in newly_stuck {
            if let Some(c) = cells.get_mut(j) {
                *c |= NEWLY_STUCK;
            }
        }
        if self.rows.len() == self.row_capacity {
            self.rows.pop_front();
        }
        self.rows.push_back(SlipRow {
            increment,
            cycle,
            cycle_start,
            cells,
        });
    }
}

/// What happened to the slip zones between two increments: zones of the
/// same direction that share a node are the same zone, continued.
pub fn zone_changes(
    old: &[(usize, usize, SlipDirection)],
    new: &[(usize, usize, SlipDirection)],
    nodes: usize,
) -> Vec<String> {
    let owners = |zones: &[(usize, usize, SlipDirection)]| {
        let mut owner = vec![None; nodes];
        for (i, &(first, len, _)) in zones.iter().enumerate() {
            for k in 0..len {
                owner[(first + k) % nodes] = Some(i);
            }
        }
        owner
    };
    let old_owner = owners(old);
    let new_owner = owners(new);
    let links = |zone: (usize, usize, SlipDirection),
                 other: &[(usize, usize, SlipDirection)],
                 owner: &[Option<usize>]| {
        let mut found: Vec<usize> = (0..zone.1)
            .filter_map(|k| owner[(zone.0 + k) % nodes])
            .filter(|&i| other[i].2 == zone.2)
            .collect();
        found.sort_unstable();
        found.dedup();
        found.len()
    };
    let word = |d: SlipDirection| match d {
        SlipDirection::Backward => "backward",
        _ => "forward",
    };
    let mut out = Vec::new();
    for &z in new {
        match links(z, old, &old_owner) {
            0 => out.push(format!("{} slip zone appeared", word(z.2))),
            1 => {}
            _ => out.push(format!("{} slip zones merged", word(z.2))),
        }
    }
    for &z in old {
        match links(z, new, &new_owner) {
            0 => out.push(format!("{} slip zone vanished", word(z.2))),
            1 => {}
            _ => out.push(format!("{} slip zone split", word(z.2))),
        }
    }
    out.dedup();
    out
}

/// Nodes as runs of neighbours, by their angle: `theta/pi = -0.73..-0.70`.
fn describe_nodes(nodes: &[usize], n: usize) -> String {
    let theta = |j: usize| node_theta(j, n) / PI;
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for &j in nodes {
        match runs.last_mut() {
            Some((_, last)) if *last + 1 == j => *last = j,
            _ => runs.push((j, j)),
        }
    }
    let shown: Vec<String> = runs
        .iter()
        .take(3)
        .map(|&(a, b)| {
            if a == b {
                format!("{:.2}", theta(a))
            } else {
                format!("{:.2}..{:.2}", theta(a), theta(b))
            }
        })
        .collect();
    let more = if runs.len() > 3 { ", …" } else { "" };
    format!(
        "{}, theta/pi = {}{more}",
        plural(nodes.len(), "node"),
        shown.join(", ")
    )
}

/// `1 zone`, `2 zones`.
pub fn plural(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// Node angle shown in `[-pi, pi)`, the range the paper's figures use.
pub fn node_theta(j: usize, n: usize) -> f64 {
    let t = 2.0 * PI * j as f64 / n as f64;
    if t >= PI {
        t - 2.0 * PI
    } else {
        t
    }
}

/// `lambda` with at least two decimals: `5.50`, `5.55`, `5.123`.
pub fn format_load_factor(v: f64) -> String {
    let two = format!("{v:.2}");
    if (two.parse::<f64>().unwrap_or(v) - v).abs() < 1e-9 {
        two
    } else {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').to_string()
    }
}

/// `phi` as a multiple of `pi` when it is one of the `pi/24` steps
/// (`0`, `pi/24`, `-3pi/8`), else in radians.
pub fn format_phase(v: f64) -> String {
    let k = (v / PHASE_STEP).round();
    if (v - k * PHASE_STEP).abs() > 1e-9 {
        return format!("{v:.4} rad");
    }
    let k = k as i64;
    if k == 0 {
        return "0".into();
    }
    let g = gcd(k.unsigned_abs(), 24) as i64;
    let (num, den) = (k / g, 24 / g);
    let sign = if num < 0 { "-" } else { "" };
    let num = num.abs();
    let head = if num == 1 {
        format!("{sign}pi")
    } else {
        format!("{sign}{num}pi")
    };
    if den == 1 {
        head
    } else {
        format!("{head}/{den}")
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// Three significant digits in scientific notation, `-` for zero.
pub fn format_sci(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phase_labels() {
        assert_eq!(format_phase(0.0), "0");
        assert_eq!(format_phase(PI / 24.0), "pi/24");
        assert_eq!(format_phase(-3.0 * PI / 8.0), "-3pi/8");
        assert_eq!(format_phase(PI / 2.0), "pi/2");
        assert_eq!(format_phase(PI), "pi");
        assert_eq!(format_phase(0.3), "0.3000 rad");
    }

    #[test]
    fn load_factor_labels() {
        assert_eq!(format_load_factor(5.5), "5.50");
        assert_eq!(format_load_factor(5.55), "5.55");
        assert_eq!(format_load_factor(5.123), "5.123");
    }

    #[test]
    fn zone_changes_name_what_happened() {
        use SlipDirection::*;
        let one = [(2, 6, Forward)];
        let two = [(2, 2, Forward), (6, 2, Forward)];
        assert_eq!(
            zone_changes(&one, &two, 16),
            vec!["forward slip zone split"]
        );
        assert_eq!(
            zone_changes(&two, &one, 16),
            vec!["forward slip zones merged"]
        );
        assert_eq!(
            zone_changes(&[], &one, 16),
            vec!["forward slip zone appeared"]
        );
        assert_eq!(
            zone_changes(&one, &[], 16),
            vec!["forward slip zone vanished"]
        );
        assert!(zone_changes(&one, &[(3, 6, Forward)], 16).is_empty());
    }
}
