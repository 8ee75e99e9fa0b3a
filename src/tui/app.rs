//! The explorer's state machine: what is being run, what the user asked
//! for, and which instant of the record is on screen. No terminal I/O
//! happens here, so every key can be tested with plain calls.
//!
//! The physics runs on the [`Worker`] thread; this file sends it commands
//! and files what comes back in the [`History`] and the event log. The
//! panels read the instant under the cursor ([`App::shown`]).

use std::f64::consts::PI;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

pub use super::format::{
    format_load_factor, format_phase, format_sci, node_theta, plural, PHASE_STEP,
};
use super::history::History;
pub use super::history::{Detail, Record, BACKWARD, DIRECTION_MASK, FORWARD, NEWLY_STUCK, STICK};
use super::keys::{self, Action, Mode};
use super::log::{EventKind, Filter, LogEntry, KINDS, MIN_NODES};
use super::regime::{CurveState, Regime, RegimeSource};
use super::sweep::{LimitState, Sweep, SweepSource};
use super::worker::{self, Command, Reply, Stopped, Worker};
use crate::analysis::case::Case;
use crate::contact::Operators;
use crate::model::path::{Initial, Segment};
use crate::model::Cycle;
use crate::stepping::{self, Phase, Status};

/// `lambda` change of the arrow keys, and with Shift.
pub const LOAD_FACTOR_STEP: f64 = 0.05;
/// `lambda` change of Shift with the left and right arrows.
pub const LOAD_FACTOR_BIG_STEP: f64 = 0.5;
/// Increments per frame the speed keys choose from.
pub const SPEEDS: [usize; 9] = [1, 2, 4, 8, 16, 32, 64, 128, 256];
const DEFAULT_SPEED: usize = 2;
/// Default history budget (`--history-mb`).
pub const DEFAULT_HISTORY_MB: usize = 256;
/// Bytes a log entry holds, about, for its share of the budget: the entry
/// twice (the ring buffer's spare capacity) and its text on the heap.
const LOG_ENTRY_BYTES: usize = 2 * std::mem::size_of::<LogEntry>() + 64;
/// `--history-mb` is shared: the event log gets this fraction (1/8) ...
const LOG_SHARE: usize = 8;
/// ... the stepper's own record of completed cycles 1/16 (the worker keeps
/// per-node data of the last few cycles only, so this is a safety net) ...
const STEPPER_SHARE: usize = 16;
/// ... and `W` per cycle at most this many cycles (older ones are thinned
/// to every 2nd, 4th, ... cycle, which the `W` panel cannot tell apart);
/// the increments' records get the rest.
const MAX_W_CYCLES: usize = 8192;
/// Most worker replies taken per frame, so a frame never runs long.
const MAX_REPLIES_PER_FRAME: usize = 20_000;

/// How the explorer draws, and how much it may keep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// False when `NO_COLOR` asks for monochrome; glyphs carry the meaning.
    pub color: bool,
    /// ASCII only: no Braille, box drawing or Greek letters.
    pub ascii: bool,
    /// The terminal shows 24-bit colour (`COLORTERM=truecolor`): the
    /// regime map's state colours are exact, else the nearest of the 256.
    pub truecolor: bool,
    /// Bytes the record of the run may use (`--history-mb`): the
    /// increments' history, the event log, the stepper's record of cycles
    /// and the `W` series share it.
    pub history_bytes: usize,
}

impl Config {
    /// Colour unless `NO_COLOR` is set to a non-empty value (no-color.org);
    /// ASCII on terminals that cannot show more (`TERM=linux`, `vt100`,
    /// `dumb`).
    pub fn from_env() -> Self {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        let term = std::env::var("TERM").unwrap_or_default();
        let colorterm = std::env::var("COLORTERM").unwrap_or_default();
        Self {
            color: !no_color,
            ascii: matches!(term.as_str(), "linux" | "vt100" | "vt102" | "dumb"),
            truecolor: matches!(colorterm.as_str(), "truecolor" | "24bit"),
            history_bytes: DEFAULT_HISTORY_MB << 20,
        }
    }
}

impl Default for Config {
    fn default() -> Self {
        Self {
            color: true,
            ascii: false,
            truecolor: true,
            history_bytes: DEFAULT_HISTORY_MB << 20,
        }
    }
}

/// What the screen shows: the one run being stepped, or a sweep's map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    /// The one run being stepped: its panels, history and event log.
    #[default]
    Stepping,
    /// The sweep's map over `lambda` (or `phi`), filled in the background.
    Sweep,
    /// The sweep view's regime map: the steady state over `(lambda, phi)`
    /// for one transient, computed while it is on screen.
    Regime,
}

/// The preset the sweep view uses when the explorer was started without
/// one: the paper's Fig. 3, which the default case belongs to.
pub const DEFAULT_SWEEP_PRESET: &str = "fig3";

/// A stopping point the user asked for with `c` or `s`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    /// Until the transient path is done and the first cycle begins.
    TransientEnd,
    /// Until this many cycles are complete.
    CycleEnd(usize),
    /// Until the run is classified as a steady state.
    Steady,
}

/// Something that waits for `y` before it happens.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Confirm {
    /// Quit with this exit status.
    Quit(u8),
    /// Throw away the sweep's map and run it again.
    RestartSweep,
}

/// A run pinned for comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct Pinned {
    /// What the run was: `lambda`, `phi` and the initial path.
    pub label: String,
    /// Its initial path alone (the short label when space is short).
    pub path: String,
    /// Its steady state when pinned, or `unclassified`.
    pub state: String,
    /// `(cycle, W)` of every completed cycle.
    pub cycles: Vec<(usize, f64)>,
    /// `g` minus its mean at the instant pinned.
    pub slip: Vec<f32>,
}

/// The explorer's whole state.
pub struct App {
    config: Config,
    case: Case,
    operators: Arc<Operators>,
    worker: Worker,
    generation: u64,
    /// The last `Go` sent, and what it asked for.
    seq: u64,
    sent: Option<worker::Goal>,
    started: bool,
    paths: Vec<Initial>,
    path_index: usize,
    running: bool,
    speed: usize,
    goal: Option<Goal>,
    pause_on_events: bool,
    filter: Filter,
    help: bool,
    log_open: bool,
    log_selected: usize,
    quit: bool,
    exit_code: u8,
    confirm: Option<Confirm>,
    entry: Option<String>,
    history: History,
    log: std::collections::VecDeque<LogEntry>,
    log_dropped: usize,
    cycles: Vec<(usize, f64)>,
    transient: Vec<Segment>,
    friction: f64,
    /// The increment on screen; `None` follows the newest.
    cursor: Option<usize>,
    /// The largest `|g - mean g|` seen: the slip panel's steady scale.
    slip_scale: f64,
    pinned: Option<Pinned>,
    last_event: Option<String>,
    notice: Option<String>,
    failure: Option<String>,
    view: View,
    sweep: Result<Sweep, String>,
    regime: Result<Regime, String>,
    /// Where `g` in the regime map goes back to: the view it came from.
    regime_back: View,
    sweep_log_w: bool,
    sweep_saved: bool,
    suspend: bool,
    save_dir: std::path::PathBuf,
}

impl App {
    /// The explorer on `case`, running, with the built-in
    /// [`DEFAULT_SWEEP_PRESET`] for the sweep view.
    pub fn new(case: Case, config: Config) -> Self {
        let source = crate::io::preset::load(DEFAULT_SWEEP_PRESET)
            .map_err(|e| e.to_string())
            .and_then(|p| SweepSource::from_preset(&p, &case).map_err(|e| e.to_string()));
        Self::with_sweep(case, config, source)
    }

    /// The explorer on `case` with `source` for the sweep view (an error
    /// is shown there instead of a map). The sweep starts the first time
    /// the sweep view opens, so a user who never looks at it pays nothing.
    pub fn with_sweep(case: Case, config: Config, source: Result<SweepSource, String>) -> Self {
        let operators = stepping::operators(&case.disc);
        let worker = Worker::spawn(Arc::clone(&operators));
        worker.send(Command::Budget(config.history_bytes / STEPPER_SHARE));
        let mut paths = Initial::paper_set();
        let path_index = match paths.iter().position(|p| *p == case.initial) {
            Some(i) => i,
            None => {
                paths.push(case.initial.clone());
                paths.len() - 1
            }
        };
        let regime = RegimeSource::builtin(&case).map(Regime::new);
        let mut app = Self {
            history: History::new(history_share(config.history_bytes)),
            config,
            case,
            operators,
            worker,
            generation: 0,
            seq: 0,
            sent: None,
            started: false,
            paths,
            path_index,
            running: true,
            speed: DEFAULT_SPEED,
            goal: None,
            pause_on_events: false,
            filter: Filter::default(),
            help: false,
            log_open: false,
            log_selected: 0,
            quit: false,
            exit_code: 0,
            confirm: None,
            entry: None,
            log: Default::default(),
            log_dropped: 0,
            cycles: Vec::new(),
            transient: Vec::new(),
            friction: 0.0,
            cursor: None,
            slip_scale: 0.0,
            pinned: None,
            last_event: None,
            notice: None,
            failure: None,
            view: View::Stepping,
            sweep: source.map(Sweep::new),
            regime,
            regime_back: View::Sweep,
            sweep_log_w: true,
            sweep_saved: false,
            suspend: false,
            save_dir: std::path::PathBuf::from("."),
        };
        app.send_restart();
        app
    }

    // ----- what the panels read -------------------------------------------

    /// How the explorer draws and how much it may keep.
    pub fn config(&self) -> Config {
        self.config
    }
    /// The case being stepped, with the current `lambda`, `phi` and path.
    pub fn case(&self) -> &Case {
        &self.case
    }
    /// The disc's contact operators, shared with the worker.
    pub fn operators(&self) -> &Arc<Operators> {
        &self.operators
    }
    /// The load factor `lambda` of the current cycle.
    pub fn load_factor(&self) -> f64 {
        self.case.cycle.load_factor()
    }
    /// The phase `phi` of the current cycle, in radians.
    pub fn phase(&self) -> f64 {
        self.case.cycle.phase()
    }
    /// The initial paths `[` and `]` cycle through.
    pub fn paths(&self) -> &[Initial] {
        &self.paths
    }
    /// Index of the current initial path in [`App::paths`].
    pub fn path_index(&self) -> usize {
        self.path_index
    }
    /// Whether the run steps on by itself each frame (Space).
    pub fn is_running(&self) -> bool {
        self.running
    }
    /// The stopping point asked for with `c` or `s`, while it is pending.
    pub fn goal(&self) -> Option<Goal> {
        self.goal
    }
    /// Increments per frame while running.
    pub fn speed(&self) -> usize {
        SPEEDS[self.speed]
    }
    /// Whether the run pauses on events of the filter's kind (`e`).
    pub fn pauses_on_events(&self) -> bool {
        self.pause_on_events
    }
    /// Which events the log lists, `{`/`}` jump to and `e` pauses on.
    pub fn filter(&self) -> Filter {
        self.filter
    }
    /// Whether the help overlay is open.
    pub fn help_visible(&self) -> bool {
        self.help
    }
    /// Whether the event log overlay is open.
    pub fn log_visible(&self) -> bool {
        self.log_open
    }
    /// Index of the selected row among [`App::log_entries`].
    pub fn log_selected(&self) -> usize {
        self.log_selected
    }
    /// Whether the loop should end and restore the terminal.
    pub fn should_quit(&self) -> bool {
        self.quit
    }
    /// 0 after `q`, 130 after Ctrl-C.
    pub fn exit_code(&self) -> u8 {
        self.exit_code
    }
    /// The question waiting for `y`, if one is asked.
    pub fn confirm(&self) -> Option<Confirm> {
        self.confirm
    }
    /// The typed entry in progress (after `:`).
    pub fn entry(&self) -> Option<&str> {
        self.entry.as_deref()
    }
    /// The record of the run's increments, for scrubbing back.
    pub fn history(&self) -> &History {
        &self.history
    }
    /// Every event kept, oldest first.
    pub fn log(&self) -> &std::collections::VecDeque<LogEntry> {
        &self.log
    }
    /// Log entries dropped to stay within budget.
    pub fn log_dropped(&self) -> usize {
        self.log_dropped
    }
    /// The log entries the overlay lists: those matching the filter.
    pub fn log_entries(&self) -> Vec<&LogEntry> {
        self.log
            .iter()
            .filter(|e| self.filter.kind.is_none() || self.filter.matches(e))
            .collect()
    }
    /// `(cycle, W)` of every completed cycle.
    pub fn cycles(&self) -> &[(usize, f64)] {
        &self.cycles
    }
    /// The transient path's segments, from the worker's start of the run.
    pub fn transient(&self) -> &[Segment] {
        &self.transient
    }
    /// The friction coefficient of the run, from the worker's start of the run.
    pub fn friction(&self) -> f64 {
        self.friction
    }
    /// The largest `|g - mean g|` seen so far: the slip panel's steady scale.
    pub fn slip_scale(&self) -> f64 {
        self.slip_scale
    }
    /// The run pinned with `p` for comparison, if any.
    pub fn pinned(&self) -> Option<&Pinned> {
        self.pinned.as_ref()
    }
    /// Increments done by the run so far.
    pub fn increments(&self) -> usize {
        self.history.newest().map_or(0, |r| r.increment + 1)
    }
    /// The newest increment.
    pub fn latest(&self) -> Option<&Record> {
        self.history.newest()
    }
    /// The increment on screen: under the cursor, or the newest.
    pub fn shown(&self) -> Option<&Record> {
        match self.cursor {
            Some(i) => self.history.get(i).or(self.history.newest()),
            None => self.history.newest(),
        }
    }
    /// The profiles on screen: the shown increment's, or the nearest
    /// earlier one that kept them (older detail is decimated).
    pub fn shown_detail(&self) -> Option<(&Record, &Detail)> {
        self.history.detail_at(self.shown()?.increment)
    }
    /// `Some(increment)` while looking back at history.
    pub fn cursor(&self) -> Option<usize> {
        self.cursor
    }
    /// The run's status as of the newest increment.
    pub fn status(&self) -> &Status {
        const RUNNING: Status = Status::Running;
        self.history.newest().map_or(&RUNNING, |r| &r.status)
    }
    /// The stepper's phase after the newest increment.
    pub fn stepper_phase(&self) -> Phase {
        self.history.newest().map_or(
            match self.case.initial {
                Initial::Direct => Phase::Cycle {
                    cycle: 1,
                    increment: 0,
                },
                _ => Phase::Transient {
                    segment: 0,
                    increment: 0,
                },
            },
            |r| r.after,
        )
    }
    /// The text of the newest event, or of the solver's failure.
    pub fn last_event(&self) -> Option<&str> {
        self.last_event.as_deref()
    }
    /// A message about the last thing the user did (a restart, a pause).
    pub fn notice(&self) -> Option<&str> {
        // Never `live` while an instant of the history is on screen.
        if self.cursor.is_some() && self.notice.as_deref() == Some("live") {
            return None;
        }
        self.notice.as_deref()
    }
    /// Why the solver failed, once it has; stepping is refused until a restart.
    pub fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }
    /// Which view is on screen.
    pub fn view(&self) -> View {
        self.view
    }
    /// Which key table applies now.
    pub fn mode(&self) -> Mode {
        match self.view {
            View::Sweep => Mode::Sweep,
            View::Regime => Mode::Regime,
            View::Stepping if self.log_open => Mode::Log,
            View::Stepping => Mode::Stepping,
        }
    }
    /// The sweep view's sweep, or why there is none.
    pub fn sweep(&self) -> Result<&Sweep, &str> {
        self.sweep.as_ref().map_err(String::as_str)
    }
    /// For tests and tools that feed rows in themselves.
    pub fn sweep_mut(&mut self) -> Option<&mut Sweep> {
        self.sweep.as_mut().ok()
    }
    /// The regime map of the sweep view, or why there is none.
    pub fn regime(&self) -> Result<&Regime, &str> {
        self.regime.as_ref().map_err(String::as_str)
    }
    /// For tests and tools that feed runs in themselves.
    pub fn regime_mut(&mut self) -> Option<&mut Regime> {
        self.regime.as_mut().ok()
    }
    /// Cover another grid with the regime map (the built-in
    /// [`REGIME_PRESET`](super::regime::REGIME_PRESET)'s unless changed):
    /// tests use a small one. The map it replaces is cancelled.
    pub fn set_regime_source(&mut self, source: Result<RegimeSource, String>) {
        self.regime = source.map(Regime::new);
    }
    /// Where `s` in the sweep view saves the map (the current directory
    /// unless changed).
    pub fn set_save_dir(&mut self, dir: impl Into<std::path::PathBuf>) {
        self.save_dir = dir.into();
    }
    /// Ctrl-Z was pressed: the loop, which owns the terminal, suspends.
    pub fn take_suspend(&mut self) -> bool {
        std::mem::take(&mut self.suspend)
    }
    /// The sweep view draws `W` on a log axis.
    pub fn sweep_log_w(&self) -> bool {
        self.sweep_log_w
    }

    /// Show `view` without starting anything: what snapshots use.
    pub fn show_view(&mut self, view: View) {
        self.view = view;
    }

    // ----- input ------------------------------------------------------------

    /// Dispatch a key through the key table (or to the prompt open).
    pub fn handle_key(&mut self, key: KeyEvent) {
        if let Some(c) = self.confirm.take() {
            let yes = matches!(key.code, KeyCode::Char('y' | 'Y'))
                || (key.code == KeyCode::Char('c')
                    && key.modifiers.contains(KeyModifiers::CONTROL)
                    && c == Confirm::Quit(130));
            if yes {
                match c {
                    Confirm::Quit(code) => self.quit_now(code),
                    Confirm::RestartSweep => self.restart_sweep(),
                }
            } else {
                self.notice = Some("cancelled".into());
            }
            return;
        }
        if self.entry.is_some() {
            self.entry_key(key);
            return;
        }
        let Some(action) = keys::action_for(&key, self.mode()) else {
            return;
        };
        self.apply(action);
    }

    /// A mouse wheel notch: history back (`-1`) or forward. It never
    /// changes `lambda` or `phi`.
    pub fn scroll(&mut self, delta: i32) {
        match self.mode() {
            Mode::Log => self.move_log(delta as isize),
            Mode::Sweep => self.with_sweep_mut(|s| s.move_run(-delta as isize)),
            Mode::Regime => self.with_regime_mut(|r| r.move_phase(-delta as isize)),
            Mode::Stepping => self.scrub(delta as isize),
        }
    }

    /// Do what `action` asks, as its key would (also for tests).
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
                self.cursor = None;
                if self.can_step() {
                    self.notice = None;
                    self.go(worker::Goal::Increments(1));
                }
            }
            Action::Back1 => self.scrub(-1),
            Action::Forward1 => self.scrub(1),
            Action::BackCycle => self.scrub_cycle(-1),
            Action::ForwardCycle => self.scrub_cycle(1),
            Action::Oldest => {
                if let Some(i) = self.history.oldest().map(|r| r.increment) {
                    self.pause_for_history();
                    self.cursor = Some(i);
                    self.notice = None;
                }
            }
            Action::Live => {
                self.cursor = None;
                self.notice = Some("live".into());
            }
            Action::PrevEvent => self.jump_event(false),
            Action::NextEvent => self.jump_event(true),
            Action::EventKind => {
                let i = KINDS
                    .iter()
                    .position(|k| *k == self.filter.kind)
                    .unwrap_or(0);
                self.filter.kind = KINDS[(i + 1) % KINDS.len()];
                self.log_selected = 0;
                self.filter_changed();
            }
            Action::MinNodes => {
                let i = MIN_NODES
                    .iter()
                    .position(|k| *k == self.filter.min_nodes)
                    .unwrap_or(0);
                self.filter.min_nodes = MIN_NODES[(i + 1) % MIN_NODES.len()];
                self.filter_changed();
            }
            Action::ToggleLog => {
                self.log_open = !self.log_open;
                let n = self.log_entries().len();
                self.log_selected = n.saturating_sub(1);
            }
            Action::LogUp => self.move_log(-1),
            Action::LogDown => self.move_log(1),
            Action::LogPageUp => self.move_log(-10),
            Action::LogPageDown => self.move_log(10),
            Action::LogFirst => self.log_selected = 0,
            Action::LogLast => self.log_selected = self.log_entries().len().saturating_sub(1),
            Action::LogGo => {
                if let Some(e) = self.log_entries().get(self.log_selected) {
                    let i = e.increment;
                    self.pause_for_history();
                    self.cursor = Some(i);
                    self.log_open = false;
                    if self.history.get(i).is_none() {
                        self.notice = Some("that increment was dropped from history".into());
                    }
                }
            }
            Action::Pin => self.pin(),
            Action::Entry => self.entry = Some(String::new()),
            Action::ToCycleEnd => self.set_goal(match self.stepper_phase() {
                Phase::Transient { .. } => Goal::TransientEnd,
                Phase::Cycle { cycle, .. } => Goal::CycleEnd(cycle),
            }),
            Action::ToSteady => {
                if let Status::Steady(s) = self.status() {
                    self.notice = Some(format!(
                        "already classified: {} after {} cycles",
                        s.state().as_str(),
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
                self.notice = Some(format!("speed: {} incr/frame", self.speed()));
            }
            Action::Slower => {
                self.speed = self.speed.saturating_sub(1);
                self.notice = Some(format!("speed: {} incr/frame", self.speed()));
            }
            Action::PauseOnEvents => {
                self.pause_on_events = !self.pause_on_events;
                self.send_filter();
                self.notice = Some(if self.pause_on_events {
                    format!("pause on events: on ({})", self.filter.describe())
                } else {
                    "pause on events: off".into()
                });
            }
            Action::Help => self.help = !self.help,
            Action::Back => {
                if self.help {
                    self.help = false;
                } else if self.log_open {
                    self.log_open = false;
                } else if self.view == View::Sweep {
                    self.view = View::Stepping;
                } else if self.view == View::Regime {
                    self.pause_regime();
                    self.view = View::Stepping;
                } else if self.cursor.is_some() {
                    self.cursor = None;
                    self.notice = Some("live".into());
                }
            }
            Action::Quit => self.ask_quit(0),
            Action::Interrupt => self.ask_quit(130),
            Action::Suspend => self.suspend = true,
            Action::ToggleView => self.toggle_view(),
            Action::SweepPrevX => self.with_sweep_mut(|s| s.move_x(-1)),
            Action::SweepNextX => self.with_sweep_mut(|s| s.move_x(1)),
            Action::SweepPageDown => self.with_sweep_mut(|s| s.move_x(10)),
            Action::SweepPageUp => self.with_sweep_mut(|s| s.move_x(-10)),
            Action::SweepFirst => self.with_sweep_mut(|s| s.move_x(-(isize::MAX / 2))),
            Action::SweepLast => self.with_sweep_mut(|s| s.move_x(isize::MAX / 2)),
            Action::SweepPrevRun => self.with_sweep_mut(|s| s.move_run(-1)),
            Action::SweepNextRun => self.with_sweep_mut(|s| s.move_run(1)),
            Action::SweepLogW => self.sweep_log_w = !self.sweep_log_w,
            Action::SweepSave => self.save_sweep(),
            Action::OpenRun => self.open_selected(),
            Action::RestartSweep => {
                if self.sweep_has_work() {
                    self.confirm = Some(Confirm::RestartSweep);
                } else {
                    self.restart_sweep();
                }
            }
            Action::ToggleRegime => self.toggle_regime(),
            Action::RegimePrevLambda => self.with_regime_mut(|r| r.move_lambda(-1)),
            Action::RegimeNextLambda => self.with_regime_mut(|r| r.move_lambda(1)),
            Action::RegimePhaseDown => self.with_regime_mut(|r| r.move_phase(-1)),
            Action::RegimePhaseUp => self.with_regime_mut(|r| r.move_phase(1)),
            Action::RegimePageDown => self.with_regime_mut(|r| r.move_lambda(10)),
            Action::RegimePageUp => self.with_regime_mut(|r| r.move_lambda(-10)),
            Action::RegimeFirst => self.with_regime_mut(|r| r.move_lambda(-(isize::MAX / 2))),
            Action::RegimeLast => self.with_regime_mut(|r| r.move_lambda(isize::MAX / 2)),
            Action::RegimeOpen => self.open_regime_cell(),
            Action::RegimePrevPath => self.regime_path(self.paths.len() - 1),
            Action::RegimeNextPath => self.regime_path(1),
            Action::RegimeRestart => {
                if let Ok(r) = &mut self.regime {
                    r.restart();
                    self.notice = Some(format!(
                        "regime map of {}: computing again",
                        r.initial().name()
                    ));
                }
            }
        }
    }

    /// `g`: the regime map, from the stepping view or the sweep's `W`
    /// plot, and back to where it came from. The map computes only while
    /// it is shown.
    fn toggle_regime(&mut self) {
        match self.view {
            View::Regime => {
                self.pause_regime();
                self.view = self.regime_back;
            }
            from => {
                self.regime_back = from;
                self.view = View::Regime;
                self.log_open = false;
                self.help = false;
                let (lambda, phi) = (self.load_factor(), self.phase());
                match &mut self.regime {
                    Ok(r) => {
                        if !r.started() {
                            r.move_near(lambda, phi);
                        }
                        r.start();
                        self.notice = Some(if r.is_running() {
                            format!(
                                "regime map of {}: {} of {} runs to do, in the background",
                                r.initial().name(),
                                r.total() - r.done(),
                                r.total()
                            )
                        } else {
                            format!("regime map of {}", r.initial().name())
                        });
                    }
                    Err(e) => self.notice = Some(format!("no regime map: {e}")),
                }
            }
        }
    }

    /// The map left: its runs stop (the cells done are kept).
    fn pause_regime(&mut self) {
        if let Ok(r) = &mut self.regime {
            r.pause();
        }
    }

    /// `[` `]` in the regime map: the map of another initial path, in the
    /// order `[` and `]` go through them in the stepping view.
    fn regime_path(&mut self, offset: usize) {
        let Ok(r) = &mut self.regime else {
            return;
        };
        let n = self.paths.len();
        let i = self
            .paths
            .iter()
            .position(|p| p == r.initial())
            .map_or(0, |i| (i + offset) % n);
        let initial = self.paths[i].clone();
        let name = initial.name();
        r.set_initial(initial, true);
        self.notice = Some(match r.error() {
            Some(e) => format!("no regime map of {name}: {e}"),
            None => format!("regime map of {name}: computing"),
        });
    }

    /// Enter in the regime map: the case under the cursor, with the map's
    /// transient, in the stepping view.
    fn open_regime_cell(&mut self) {
        let Ok(r) = &self.regime else {
            return;
        };
        let (lambda, phi) = r.selected();
        let initial = r.initial().clone();
        self.open_case(lambda, phi, initial);
    }

    fn with_regime_mut(&mut self, f: impl FnOnce(&mut Regime)) {
        if let Ok(r) = &mut self.regime {
            f(r);
        }
    }

    /// Whether leaving would throw away a sweep map: one still running, or
    /// finished and not saved.
    fn sweep_has_work(&self) -> bool {
        self.sweep
            .as_ref()
            .is_ok_and(|s| s.started() && (s.is_running() || (s.done() > 0 && !self.sweep_saved)))
    }

    fn ask_quit(&mut self, code: u8) {
        if self.sweep_has_work() {
            self.confirm = Some(Confirm::Quit(code));
        } else {
            self.quit_now(code);
        }
    }

    fn quit_now(&mut self, code: u8) {
        self.exit_code = code;
        self.request_quit();
    }

    /// Quit from outside the key table (a signal). The sweep's runs not
    /// yet started are dropped so the process is not kept busy.
    pub fn request_quit(&mut self) {
        self.quit = true;
        self.worker.send(Command::Pause);
        if let Ok(s) = &mut self.sweep {
            s.cancel();
        }
        self.pause_regime();
    }

    /// Quit with a status, from a signal.
    pub fn request_quit_with(&mut self, code: u8) {
        self.exit_code = code;
        self.request_quit();
    }

    fn restart_sweep(&mut self) {
        if let Ok(s) = &mut self.sweep {
            s.start();
            self.sweep_saved = false;
            self.notice = Some("sweep restarted".into());
        }
    }

    fn save_sweep(&mut self) {
        let Ok(s) = &self.sweep else {
            return;
        };
        let path = self.save_dir.join(format!("sweep-{}.csv", s.source().name));
        let n = s.done();
        // Through sweep's own writer: metadata header, and create_new so an
        // existing file (or a symlink) is never replaced.
        match crate::io::csv::save_sweep_csv(&path, &s.source().spec, s.rows()) {
            Ok(()) => {
                self.sweep_saved = !s.is_running();
                self.notice = Some(format!("saved {n} runs to {}", path.display()));
            }
            Err(e) => self.notice = Some(format!("not saved: {e}")),
        }
    }

    fn with_sweep_mut(&mut self, f: impl FnOnce(&mut Sweep)) {
        if let Ok(s) = &mut self.sweep {
            f(s);
        }
    }

    fn filter_changed(&mut self) {
        self.send_filter();
        self.notice = Some(format!("events: {}", self.filter.describe()));
    }

    fn send_filter(&self) {
        self.worker.send(Command::PauseOn(
            self.pause_on_events.then_some(self.filter),
        ));
    }

    fn move_log(&mut self, delta: isize) {
        let n = self.log_entries().len();
        self.log_selected = self
            .log_selected
            .saturating_add_signed(delta)
            .min(n.saturating_sub(1));
    }

    /// Looking back pauses the run, so the instant stays put.
    fn pause_for_history(&mut self) {
        if self.running || self.goal.is_some() {
            self.running = false;
            self.goal = None;
        }
    }

    fn scrub(&mut self, delta: isize) {
        let (Some(first), Some(last)) = (self.history.oldest(), self.history.newest()) else {
            return;
        };
        let (first, last) = (first.increment, last.increment);
        let now = self.cursor.unwrap_or(last);
        let to = now.saturating_add_signed(delta).clamp(first, last);
        if delta > 0 && to == last {
            self.cursor = None;
            self.notice = Some("live".into());
            return;
        }
        self.pause_for_history();
        self.cursor = Some(to);
        self.notice = None;
    }

    fn scrub_cycle(&mut self, delta: isize) {
        let steps = self.case.disc.steps_per_cycle() as isize;
        self.scrub(delta * steps);
    }

    fn jump_event(&mut self, forward: bool) {
        let now = self.shown().map_or(0, |r| r.increment);
        let found = if forward {
            self.log
                .iter()
                .find(|e| e.increment > now && self.filter.matches(e))
        } else {
            self.log
                .iter()
                .rev()
                .find(|e| e.increment < now && self.filter.matches(e))
        };
        match found {
            Some(e) => {
                let (i, text) = (e.increment, e.text.clone());
                self.pause_for_history();
                self.cursor = Some(i);
                if self.history.newest().is_some_and(|r| r.increment == i) {
                    self.cursor = None;
                }
                if self.log_open {
                    // The log follows: its selection is the event shown.
                    if let Some(k) = self
                        .log_entries()
                        .iter()
                        .position(|e| e.increment == i && e.text == text)
                    {
                        self.log_selected = k;
                    }
                }
                self.notice = Some(format!("at {text}"));
            }
            None => {
                self.notice = Some(format!(
                    "no {} event {}",
                    self.filter.describe(),
                    if forward { "later" } else { "earlier" }
                ))
            }
        }
    }

    fn pin(&mut self) {
        if self.pinned.is_some() {
            self.pinned = None;
            self.notice = Some("unpinned".into());
            return;
        }
        let Some((_, d)) = self.shown_detail() else {
            self.notice = Some("nothing to pin yet".into());
            return;
        };
        let slip = d.slip.clone();
        let state = match self.status() {
            Status::Running => "unclassified".to_string(),
            Status::Steady(s) | Status::Ended(s) => s.state().as_str().to_string(),
        };
        let label = format!(
            "lambda {} phi {} {}",
            format_load_factor(self.load_factor()),
            format_phase(self.phase()),
            self.case.initial.name()
        );
        self.notice = Some(format!("pinned {label}: change the run to compare"));
        self.pinned = Some(Pinned {
            label,
            path: self.case.initial.name(),
            state,
            cycles: self.cycles.clone(),
            slip,
        });
    }

    fn entry_key(&mut self, key: KeyEvent) {
        let Some(text) = &mut self.entry else {
            return;
        };
        match key.code {
            KeyCode::Esc => {
                self.entry = None;
                self.notice = Some("cancelled".into());
            }
            KeyCode::Backspace => {
                text.pop();
            }
            KeyCode::Enter => {
                let text = self.entry.take().unwrap_or_default();
                self.apply_entry(&text);
            }
            KeyCode::Char(c) if text.len() < 40 => text.push(c),
            _ => {}
        }
    }

    /// `lambda = 5.13`, `phi = pi/4` (or radians), `path = OA`.
    fn apply_entry(&mut self, text: &str) {
        let (name, value) = match text.split_once(['=', ' ']) {
            Some((n, v)) => (
                n.trim().to_lowercase(),
                v.trim().trim_start_matches('=').trim(),
            ),
            None => {
                self.notice =
                    Some("type name = value: lambda = 5.13, phi = pi/4, path = OA".into());
                return;
            }
        };
        match name.as_str() {
            "lambda" | "l" | "λ" => match value.parse::<f64>() {
                Ok(v) if v >= 0.0 && v.is_finite() => {
                    self.change_cycle(v, self.phase(), format!("lambda {}", format_load_factor(v)))
                }
                _ => self.notice = Some(format!("not a lambda: {value}")),
            },
            "phi" | "p" | "φ" => match parse_phase(value) {
                Some(v) => {
                    self.change_cycle(self.load_factor(), v, format!("phi {}", format_phase(v)))
                }
                None => self.notice = Some(format!("not a phase: {value}")),
            },
            "path" | "initial" => {
                match self
                    .paths
                    .iter()
                    .position(|p| p.name().eq_ignore_ascii_case(value))
                {
                    Some(i) => {
                        self.path_index = i;
                        self.case.initial = self.paths[i].clone();
                        self.restart(&format!("path {}", self.case.initial.name()));
                    }
                    // Not a named path: the user's own, `X1,Y1;X2,Y2`.
                    None if value.contains(',') => self.custom_path(value),
                    None => {
                        self.notice = Some(format!(
                            "no initial path {value}: a name, or points X1,Y1;X2,Y2"
                        ))
                    }
                }
            }
            _ => self.notice = Some(format!("unknown name {name}: lambda, phi or path")),
        }
    }

    /// The user's own transient `O -> points -> A`, checked as `run --path`
    /// checks it, added to the paths `[` and `]` go through.
    fn custom_path(&mut self, value: &str) {
        let points = match crate::io::parse::parse_points(value) {
            Ok(p) => p,
            Err(e) => {
                self.notice = Some(format!("path = X1,Y1;X2,Y2: {e}"));
                return;
            }
        };
        let points = points
            .into_iter()
            .map(|(x, y)| crate::model::LoadPoint::new(x, y))
            .collect();
        match Initial::custom_for(points, &self.case.material) {
            Ok(initial) => {
                let i = match self.paths.iter().position(|p| *p == initial) {
                    Some(i) => i,
                    None => {
                        self.paths.push(initial.clone());
                        self.paths.len() - 1
                    }
                };
                self.path_index = i;
                self.case.initial = initial;
                self.restart(&format!("path {}", self.case.initial.name()));
            }
            Err(e) => self.notice = Some(format!("path = X1,Y1;X2,Y2: {e}")),
        }
    }

    fn toggle_view(&mut self) {
        self.view = match self.view {
            View::Stepping => View::Sweep,
            View::Sweep => View::Stepping,
            View::Regime => {
                self.pause_regime();
                View::Stepping
            }
        };
        self.help = false;
        self.log_open = false;
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

    fn can_step(&mut self) -> bool {
        if let Some(f) = &self.failure {
            self.notice = Some(format!("the solver failed ({f}); r to rerun"));
            return false;
        }
        if let Status::Ended(s) = self.status() {
            self.notice = Some(format!(
                "the run has ended ({}); r to rerun, or change lambda, phi or the path",
                s.state().as_str()
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
            self.cursor = None;
            self.notice = None;
        }
    }

    fn set_goal(&mut self, goal: Goal) {
        if self.can_step() {
            self.running = false;
            self.cursor = None;
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
        if self.case.cycle.as_polyline().is_some() {
            self.notice = Some("a polyline cycle (--cycle) has no phase".into());
            return;
        }
        let old = self.phase();
        let k = (old / PHASE_STEP).round();
        let mut new = if (old - k * PHASE_STEP).abs() < 1e-9 {
            (k + sign) * PHASE_STEP
        } else {
            old + sign * PHASE_STEP
        };
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
        match self.cycle_at(load_factor, phase) {
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

    fn send_restart(&mut self) {
        self.generation += 1;
        self.sent = None;
        self.worker.send(Command::Restart {
            generation: self.generation,
            case: Box::new(self.case.clone()),
        });
        self.send_filter();
    }

    /// Start the run again (the work it replaces is cancelled), keeping
    /// the running/paused choice and the pinned run.
    fn restart(&mut self, why: &str) {
        self.send_restart();
        self.history.clear();
        self.log.clear();
        self.log_dropped = 0;
        self.log_selected = 0;
        self.cycles.clear();
        self.transient.clear();
        self.cursor = None;
        self.slip_scale = 0.0;
        self.last_event = None;
        self.failure = None;
        self.goal = None;
        let from = match self.case.initial {
            Initial::Slip { .. } => "restarted at A with the prescribed slip",
            _ => "restarted from O",
        };
        self.notice = Some(format!("{why}: {from}"));
    }

    // ----- the worker ---------------------------------------------------------

    /// What the worker should be doing now.
    fn wanted(&self) -> Option<worker::Goal> {
        if self.view != View::Stepping || self.quit || self.failure.is_some() {
            return None;
        }
        match self.goal {
            Some(Goal::TransientEnd) => Some(worker::Goal::TransientEnd),
            Some(Goal::CycleEnd(_)) => Some(worker::Goal::CycleEnd),
            Some(Goal::Steady) => Some(worker::Goal::Steady),
            None if self.running => Some(worker::Goal::Paced(self.speed())),
            None => None,
        }
    }

    fn go(&mut self, goal: worker::Goal) {
        self.seq += 1;
        self.sent = Some(goal);
        self.worker.send(Command::Go {
            seq: self.seq,
            goal,
        });
    }

    /// Tell the worker what is wanted, if that changed.
    fn sync(&mut self) {
        let wanted = self.wanted();
        if wanted == self.sent
            || (wanted.is_none() && matches!(self.sent, Some(worker::Goal::Increments(_))))
        {
            return;
        }
        match wanted {
            Some(g) => self.go(g),
            None => {
                self.seq += 1;
                self.worker.send(Command::Pause);
                self.sent = None;
            }
        }
    }

    /// One frame: take what the worker sent (at most `budget` of time),
    /// poll the sweep, and tell the worker what to do next.
    pub fn tick(&mut self, budget: Duration) {
        let deadline = Instant::now() + budget;
        if let Ok(s) = &mut self.sweep {
            s.poll();
        }
        if let Ok(r) = &mut self.regime {
            r.poll();
        }
        self.started = true;
        self.sync();
        for i in 0..MAX_REPLIES_PER_FRAME {
            if i % 256 == 255 && Instant::now() >= deadline {
                break;
            }
            match self.worker.try_recv() {
                Some(r) => self.take(r),
                None => break,
            }
        }
        self.sync();
    }

    /// Exactly `n` increments (fewer if the run stops), waiting for them:
    /// what tests use to reach a reproducible state.
    pub fn advance(&mut self, n: usize) {
        if self.sent.is_some() {
            self.seq += 1;
            self.worker.send(Command::Pause);
            self.sent = None;
        }
        self.go(worker::Goal::Increments(n));
        let seq = self.seq;
        while let Some(reply) = self.worker.recv() {
            let done = matches!(&reply, Reply::Stopped { seq: s, generation, .. }
                if *s == seq && *generation == self.generation);
            self.take(reply);
            if done {
                break;
            }
        }
        self.sent = None;
    }

    /// Wait until the worker has finished what it was last asked (a run
    /// that goes on for ever is paused first), and take all it sent:
    /// what tests use after a key that steps.
    pub fn settle(&mut self) {
        if matches!(self.sent, Some(worker::Goal::Paced(_))) || self.sent.is_none() {
            self.advance(0);
            return;
        }
        while self.sent.is_some() {
            match self.worker.recv() {
                Some(r) => self.take(r),
                None => break,
            }
        }
    }

    /// Whether the loop has stepping to do (else it can sleep longer).
    pub fn is_busy(&self) -> bool {
        if self.sweep.as_ref().is_ok_and(|s| {
            s.is_running() || s.started() && matches!(s.limit(), LimitState::Computing)
        }) {
            return true;
        }
        if self.regime.as_ref().is_ok_and(|r| {
            r.is_running() || r.started() && matches!(r.curve(), CurveState::Computing)
        }) {
            return true;
        }
        self.sent.is_some() || self.view == View::Stepping && (self.running || self.goal.is_some())
    }

    /// File `record` as if the worker had sent it (its generation is set
    /// to the current run's): tests drive a fixed, synthetic state with it,
    /// so screen snapshots hold no solver numbers.
    pub fn feed(&mut self, mut record: Record) {
        record.generation = self.generation;
        self.file(record);
    }

    /// Set the transient and friction coefficient as the worker's start of
    /// a run does (tests, with [`App::feed`]).
    pub fn feed_started(&mut self, transient: Vec<Segment>, friction: f64) {
        self.transient = transient;
        self.friction = friction;
    }

    fn take(&mut self, reply: Reply) {
        match reply {
            Reply::Started {
                generation,
                transient,
                friction,
            } if generation == self.generation => {
                self.transient = transient;
                self.friction = friction;
            }
            Reply::Record(r) if r.generation == self.generation => self.file(*r),
            Reply::Stopped {
                generation,
                seq,
                why,
            } if generation == self.generation && seq == self.seq => {
                self.sent = None;
                self.stopped(why);
            }
            _ => {}
        }
    }

    fn stopped(&mut self, why: Stopped) {
        match why {
            Stopped::Reached => {
                if let Some(goal) = self.goal.take() {
                    self.notice = Some(match (goal, self.status()) {
                        (Goal::Steady, Status::Steady(s) | Status::Ended(s)) => format!(
                            "steady state: {} after {} cycles",
                            s.state().as_str(),
                            s.cycles
                        ),
                        (Goal::TransientEnd, _) => "end of the transient".into(),
                        (Goal::CycleEnd(c), _) => format!("end of cycle {c}"),
                        (Goal::Steady, _) => "stopped".into(),
                    });
                }
            }
            Stopped::Event(text, load) => {
                self.running = false;
                self.goal = None;
                self.last_event = Some(text);
                // Inside its increment the second status line gives the
                // event's load point; the notice keeps to the point.
                self.notice = Some(if load.is_some() {
                    "paused at the event (Space runs on)".into()
                } else {
                    "paused on the event (Space runs on)".into()
                });
            }
            Stopped::Ended => {
                self.running = false;
                self.goal = None;
                if let Status::Ended(s) | Status::Steady(s) = self.status() {
                    self.notice = Some(format!("the run ended: {}", s.state().as_str()));
                }
            }
            Stopped::Failed(text) => {
                self.running = false;
                self.goal = None;
                self.last_event = Some(format!("solver failed: {text}"));
                self.failure = Some(text);
            }
            Stopped::Memory => {
                self.running = false;
                self.goal = None;
                self.notice =
                    Some("paused: the record of cycles filled its share of --history-mb".into());
            }
            Stopped::Cancelled => {}
        }
    }

    fn file(&mut self, r: Record) {
        if let Some(d) = &r.detail {
            let m = d
                .slip
                .iter()
                .chain(d.slip_before.iter().flatten())
                .fold(0.0f32, |m, v| m.max(v.abs()));
            self.slip_scale = self.slip_scale.max(f64::from(m));
        }
        if let Some(c) = r.completed {
            if self.cycles.len() >= MAX_W_CYCLES {
                thin_older_half(&mut self.cycles);
            }
            self.cycles.push(c);
        }
        for e in &r.events {
            self.last_event = Some(e.text.clone());
            let max_log = (self.config.history_bytes / LOG_SHARE / LOG_ENTRY_BYTES).max(1000);
            if self.log.len() >= max_log {
                self.log.pop_front();
                self.log_dropped += 1;
                self.log_selected = self.log_selected.saturating_sub(1);
            }
            self.log.push_back(e.clone());
        }
        self.history.push(r);
        if let Some(c) = self.cursor {
            // The cursor's increment was dropped: hold the oldest kept.
            if let Some(first) = self.history.oldest() {
                if c < first.increment {
                    self.cursor = Some(first.increment);
                }
            }
        }
    }

    /// Open the run under the sweep cursor in the stepping view.
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
            Initial::Optimal => match sweep.limit() {
                LimitState::Known(l) if sweep.source().spec.phases() == [job.phase] => {
                    Initial::Slip {
                        name: "optimal".into(),
                        slip: Arc::new(l.slip.clone()),
                    }
                }
                _ => match self
                    .cycle_at(job.load_factor, job.phase)
                    .map_err(|e| e.to_string())
                    .and_then(|c| {
                        crate::analysis::limit::optimal_initial(
                            &self.case.material,
                            &c,
                            &self.case.disc,
                        )
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
        self.open_case(job.load_factor, job.phase, initial);
    }

    /// Step the case `(lambda, phi)` with the transient `initial` (the
    /// explorer's model otherwise) in the stepping view, from the start:
    /// what Enter in the sweep view and in the regime map does.
    /// The explorer's cycle at `load_factor` and `phase`: a polyline keeps
    /// its shape (it has no phase).
    fn cycle_at(&self, load_factor: f64, phase: f64) -> Result<Cycle, crate::model::ParamError> {
        let c = &self.case.cycle;
        match c.as_polyline() {
            Some(_) => c.with_load_factor(load_factor),
            None => Cycle::new(c.center(), load_factor, c.slope(), phase),
        }
    }

    fn open_case(&mut self, load_factor: f64, phase: f64, initial: Initial) {
        let cycle = match self.cycle_at(load_factor, phase) {
            Ok(cycle) => cycle,
            Err(e) => {
                self.notice = Some(e.to_string());
                return;
            }
        };
        self.pause_regime();
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
            format_load_factor(load_factor),
            format_phase(phase),
            self.case.initial.name()
        );
        self.restart(&what);
    }
}

/// `pi/4`, `-3pi/8`, `0.3`.
/// What the increments' records may use of `--history-mb`: what the event
/// log, the stepper's record of cycles and the `W` series leave.
fn history_share(budget: usize) -> usize {
    let w = MAX_W_CYCLES * std::mem::size_of::<(usize, f64)>();
    budget
        .saturating_sub(budget / LOG_SHARE + budget / STEPPER_SHARE)
        .saturating_sub(w)
}

/// Drop every other entry of the older half of `cycles` (the newest half
/// is kept whole), so a series thinned again and again keeps the recent
/// cycles dense and the old ones ever sparser.
fn thin_older_half(cycles: &mut Vec<(usize, f64)>) {
    let half = cycles.len() / 2;
    let mut i = 0;
    cycles.retain(|_| {
        let keep = i >= half || i % 2 == 0;
        i += 1;
        keep
    });
}

fn parse_phase(s: &str) -> Option<f64> {
    let s = s.trim().replace('π', "pi");
    if let Ok(v) = s.parse::<f64>() {
        return v.is_finite().then_some(v);
    }
    let (num, den) = match s.split_once('/') {
        Some((a, b)) => (a.trim(), b.trim().parse::<f64>().ok()?),
        None => (s.as_str(), 1.0),
    };
    let k = match num.strip_suffix("pi")?.trim() {
        "" => 1.0,
        "-" => -1.0,
        k => k.parse::<f64>().ok()?,
    };
    Some(k * PI / den)
}

/// Kinds the log and jump keys know, for tests.
pub fn event_kinds() -> &'static [Option<EventKind>] {
    &KINDS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phases_parse() {
        assert_eq!(parse_phase("pi/4"), Some(PI / 4.0));
        assert_eq!(parse_phase("-3pi/8"), Some(-3.0 * PI / 8.0));
        assert_eq!(parse_phase("0.3"), Some(0.3));
        assert_eq!(parse_phase("x"), None);
    }
}
