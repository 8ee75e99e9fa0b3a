//! The explorer's state machine: what is being run, what the user asked
//! for, and which instant of the record is on screen. No terminal I/O
//! happens here, so every key can be tested with plain calls.
//!
//! The physics runs on the [`Worker`] thread; this file sends it commands
//! and files what comes back in the [`History`] and the event log. The
//! panels read the instant under the cursor ([`App::shown`]).
//!
//! Each view keeps its state in a struct of its own, in its module beside
//! the keys it answers (`stepping_view.rs`, `log_view.rs`, `sweep_view.rs`,
//! `regime_view.rs`, `profile_view.rs`, `tour.rs`); `App` holds what they
//! share: the case, the worker and its channel, which view is shown, the
//! notice and the questions that wait for `y`.

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

mod log_view;
pub mod profile_view;
mod regime_view;
mod stepping_view;
mod sweep_view;
pub mod tour;
mod worker_side;

use log_view::LogView;
use regime_view::RegimeView;
use stepping_view::SteppingView;
use sweep_view::SweepView;

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
    /// Replace the file the sweep's map is being saved to.
    Overwrite,
}

/// How far a run asked for its steady state (`s`) has got, and about how
/// long it has left.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyProgress {
    /// Cycles completed.
    pub cycles: usize,
    /// The last relative change of `W`, `|W_k - W_(k-1)| / W_(k-1)`.
    pub change: Option<f64>,
    /// The stopping rule's tolerance on it (model.md 6.1).
    pub tolerance: f64,
    /// About how many cycles are left (see `left`).
    pub cycles_left: Option<usize>,
    /// About how long the cycles left will take, when the change falls
    /// steadily: the cycles until it reaches the tolerance (at its last
    /// rate of fall) and the three pairs the rule asks for, at the time
    /// the last cycles took.
    pub left: Option<Duration>,
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

/// The explorer's state: what every view shares (the case, the worker
/// and its channel, which view is shown, the notice, the prompts that wait
/// for `y`, the tour), and one state per view, each in its module beside
/// its keys: [`SteppingView`], [`LogView`], [`SweepView`], [`RegimeView`].
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
    help: bool,
    quit: bool,
    exit_code: u8,
    confirm: Option<Confirm>,
    notice: Option<String>,
    view: View,
    suspend: bool,
    /// The guided tour, while it has the keys.
    tour: Option<tour::Tour>,
    /// The run being stepped: its record, the cursor over it, the goal.
    stepping: SteppingView,
    /// The event log and the filter of events.
    log_view: LogView,
    /// The sweep's map over `lambda` (or `phi`) and its save.
    sweep_view: SweepView,
    /// The regime map over `(lambda, phi)`.
    regime_view: RegimeView,
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
        let operators = stepping::operators(&case.disc());
        let worker = Worker::spawn(Arc::clone(&operators));
        worker.send(Command::Budget(config.history_bytes / STEPPER_SHARE));
        let mut paths = Initial::paper_set();
        let path_index = match paths.iter().position(|p| p == case.initial()) {
            Some(i) => i,
            None => {
                paths.push(case.initial().clone());
                paths.len() - 1
            }
        };
        let regime = RegimeSource::builtin(&case).map(Regime::new);
        let mut app = Self {
            stepping: SteppingView::new(history_share(config.history_bytes), paths, path_index),
            config,
            case,
            operators,
            worker,
            generation: 0,
            seq: 0,
            sent: None,
            started: false,
            help: false,
            quit: false,
            exit_code: 0,
            confirm: None,
            notice: None,
            view: View::Stepping,
            suspend: false,
            tour: None,
            log_view: LogView::default(),
            sweep_view: SweepView::new(source.map(Sweep::new)),
            regime_view: RegimeView::new(regime),
        };
        app.send_restart();
        app
    }

    // ----- what the panels read -------------------------------------------

    /// How the explorer draws and how much it may keep.
    pub fn config(&self) -> Config {
        self.config
    }
    /// The initial path of the run: the one of [`App::paths`] selected,
    /// [`Initial::Optimal`] included (the worker resolves it for each run,
    /// off the UI thread; a [`Case`] holds only resolved paths, so the
    /// case's own is the one the explorer opened with).
    pub fn initial(&self) -> &Initial {
        &self.stepping.paths[self.stepping.path_index]
    }
    /// The case being stepped, with the current `lambda` and `phi`; its
    /// initial path is [`App::initial`].
    pub fn case(&self) -> &Case {
        &self.case
    }
    /// The disc's contact operators, shared with the worker.
    pub fn operators(&self) -> &Arc<Operators> {
        &self.operators
    }
    /// The load factor `lambda` of the current cycle.
    pub fn load_factor(&self) -> f64 {
        self.case.cycle().load_factor()
    }
    /// The phase `phi` of the current cycle, in radians.
    pub fn phase(&self) -> f64 {
        self.case.cycle().phase()
    }
    /// The initial paths `[` and `]` cycle through.
    pub fn paths(&self) -> &[Initial] {
        &self.stepping.paths
    }
    /// Index of the current initial path in [`App::paths`].
    pub fn path_index(&self) -> usize {
        self.stepping.path_index
    }
    /// Whether the run steps on by itself each frame (Space).
    pub fn is_running(&self) -> bool {
        self.stepping.running
    }
    /// The stopping point asked for with `c` or `s`, while it is pending.
    pub fn goal(&self) -> Option<Goal> {
        self.stepping.goal
    }
    /// Increments per frame while running.
    pub fn speed(&self) -> usize {
        SPEEDS[self.stepping.speed]
    }
    /// Whether the run pauses on events of the filter's kind (`e`).
    pub fn pauses_on_events(&self) -> bool {
        self.stepping.pause_on_events
    }
    /// Which events the log lists, `{`/`}` jump to and `e` pauses on.
    pub fn filter(&self) -> Filter {
        self.log_view.filter
    }
    /// Whether the help overlay is open.
    pub fn help_visible(&self) -> bool {
        self.help
    }
    /// Whether the event log overlay is open.
    pub fn log_visible(&self) -> bool {
        self.log_view.log_open
    }
    /// Index of the selected row among [`App::log_entries`].
    pub fn log_selected(&self) -> usize {
        self.log_view.log_selected
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
        self.stepping.entry.as_deref()
    }
    /// The file name being typed after `s` in the sweep view.
    pub fn save_entry(&self) -> Option<&str> {
        self.sweep_view.save_entry.as_deref()
    }
    /// The file `overwrite? y/N` asks about.
    pub fn save_path(&self) -> Option<&std::path::Path> {
        self.sweep_view.save_path.as_deref()
    }
    /// The record of the run's increments, for scrubbing back.
    pub fn history(&self) -> &History {
        &self.stepping.history
    }
    /// Every event kept, oldest first.
    pub fn log(&self) -> &std::collections::VecDeque<LogEntry> {
        &self.log_view.log
    }
    /// Log entries dropped to stay within budget.
    pub fn log_dropped(&self) -> usize {
        self.log_view.log_dropped
    }
    /// The log entries the overlay lists: those matching the filter.
    pub fn log_entries(&self) -> Vec<&LogEntry> {
        self.log_view.entries()
    }
    /// `(cycle, W)` of every completed cycle.
    pub fn cycles(&self) -> &[(usize, f64)] {
        &self.stepping.cycles
    }
    /// The transient path's segments, from the worker's start of the run.
    pub fn transient(&self) -> &[Segment] {
        &self.stepping.transient
    }
    /// The friction coefficient of the run, from the worker's start of the run.
    pub fn friction(&self) -> f64 {
        self.stepping.friction
    }
    /// The largest `|g - mean g|` seen so far: the slip panel's steady scale.
    pub fn slip_scale(&self) -> f64 {
        self.stepping.slip_scale
    }
    /// The run pinned with `p` for comparison, if any.
    pub fn pinned(&self) -> Option<&Pinned> {
        self.stepping.pinned.as_ref()
    }
    /// Increments done by the run so far.
    pub fn increments(&self) -> usize {
        self.stepping
            .history
            .newest()
            .map_or(0, |r| r.increment + 1)
    }
    /// The newest increment.
    pub fn latest(&self) -> Option<&Record> {
        self.stepping.history.newest()
    }
    /// The increment on screen: under the cursor, or the newest.
    pub fn shown(&self) -> Option<&Record> {
        self.stepping.shown()
    }
    /// The profiles on screen: the shown increment's, or the nearest
    /// earlier one that kept them (older detail is decimated).
    pub fn shown_detail(&self) -> Option<(&Record, &Detail)> {
        self.stepping.history.detail_at(self.shown()?.increment)
    }
    /// `Some(increment)` while looking back at history.
    pub fn cursor(&self) -> Option<usize> {
        self.stepping.cursor
    }
    /// The run's status as of the newest increment.
    pub fn status(&self) -> &Status {
        const RUNNING: Status = Status::Running;
        self.stepping
            .history
            .newest()
            .map_or(&RUNNING, |r| &r.status)
    }
    /// The stepper's phase after the newest increment.
    pub fn stepper_phase(&self) -> Phase {
        self.stepping.history.newest().map_or(
            match self.initial() {
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
        self.stepping.last_event.as_deref()
    }
    /// A message about the last thing the user did (a restart, a pause).
    pub fn notice(&self) -> Option<&str> {
        // Never `live` while an instant of the history is on screen.
        if self.stepping.cursor.is_some() && self.notice.as_deref() == Some("live") {
            return None;
        }
        self.notice.as_deref()
    }
    /// Why the solver failed, once it has; stepping is refused until a restart.
    pub fn failure(&self) -> Option<&str> {
        self.stepping.failure.as_deref()
    }
    /// Which view is on screen.
    pub fn view(&self) -> View {
        self.view
    }
    /// Which key table applies now.
    pub fn mode(&self) -> Mode {
        if self.tour.is_some() {
            return Mode::Tour;
        }
        match self.view {
            View::Sweep => Mode::Sweep,
            View::Regime => Mode::Regime,
            View::Stepping if self.log_view.log_open => Mode::Log,
            View::Stepping => Mode::Stepping,
        }
    }
    /// The sweep view's sweep, or why there is none.
    pub fn sweep(&self) -> Result<&Sweep, &str> {
        self.sweep_view.sweep.as_ref().map_err(String::as_str)
    }
    /// For tests and tools that feed rows in themselves.
    pub fn sweep_mut(&mut self) -> Option<&mut Sweep> {
        self.sweep_view.sweep.as_mut().ok()
    }
    /// The regime map of the sweep view, or why there is none.
    pub fn regime(&self) -> Result<&Regime, &str> {
        self.regime_view.regime.as_ref().map_err(String::as_str)
    }
    /// For tests and tools that feed runs in themselves.
    pub fn regime_mut(&mut self) -> Option<&mut Regime> {
        self.regime_view.regime.as_mut().ok()
    }
    /// Cover another grid with the regime map (the built-in
    /// [`REGIME_PRESET`](super::regime::REGIME_PRESET)'s unless changed):
    /// tests use a small one. The map it replaces is cancelled.
    pub fn set_regime_source(&mut self, source: Result<RegimeSource, String>) {
        self.regime_view.regime = source.map(Regime::new);
    }
    /// Where `s` in the sweep view saves the map (the current directory
    /// unless changed).
    pub fn set_save_dir(&mut self, dir: impl Into<std::path::PathBuf>) {
        self.sweep_view.save_dir = dir.into();
    }
    /// Ctrl-Z was pressed: the loop, which owns the terminal, suspends.
    pub fn take_suspend(&mut self) -> bool {
        std::mem::take(&mut self.suspend)
    }
    /// The sweep view draws `W` on a log axis.
    pub fn sweep_log_w(&self) -> bool {
        self.sweep_view.sweep_log_w
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
                    Confirm::Overwrite => self.write_sweep(true),
                }
            } else if c == Confirm::Overwrite {
                self.sweep_view.save_path = None;
                self.notice = Some("not saved: the file is kept".into());
            } else {
                self.notice = Some("cancelled".into());
            }
            return;
        }
        if self.sweep_view.save_entry.is_some() {
            self.save_entry_key(key);
            return;
        }
        if self.stepping.entry.is_some() {
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
            Mode::Tour => {}
        }
    }

    /// Do what `action` asks, as its key would (also for tests). Each
    /// view answers its own actions.
    pub fn apply(&mut self, action: Action) {
        let _ = self.stepping_action(action)
            || self.profile_action(action)
            || self.log_action(action)
            || self.sweep_action(action)
            || self.regime_action(action)
            || self.tour_action(action)
            || self.global_action(action);
    }

    /// The keys of every view: help, back, quit, the view switch.
    pub(super) fn global_action(&mut self, action: Action) -> bool {
        match action {
            Action::Help => self.help = !self.help,
            Action::Back => {
                if self.help {
                    self.help = false;
                } else if self.log_view.log_open {
                    self.log_view.log_open = false;
                } else if self.view == View::Sweep {
                    self.view = View::Stepping;
                } else if self.view == View::Regime {
                    self.pause_regime();
                    self.view = View::Stepping;
                } else if self.stepping.cursor.is_some() {
                    self.stepping.cursor = None;
                    self.notice = Some("live".into());
                }
            }
            Action::Quit => self.ask_quit(0),
            Action::Interrupt => self.ask_quit(130),
            Action::Suspend => self.suspend = true,
            Action::ToggleView => self.toggle_view(),
            _ => return false,
        }
        true
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
        if let Ok(s) = &mut self.sweep_view.sweep {
            s.cancel();
        }
        self.pause_regime();
    }

    /// Quit with a status, from a signal.
    pub fn request_quit_with(&mut self, code: u8) {
        self.exit_code = code;
        self.request_quit();
    }
}

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

/// Kinds the log and jump keys know, for tests.
pub fn event_kinds() -> &'static [Option<EventKind>] {
    &KINDS
}
