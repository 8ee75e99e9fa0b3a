//! The terminal explorer: live stepping of the contact, and a sweep view
//! whose map of `W` fills in as a background sweep runs, with the regime
//! map over `(lambda, phi)` one key away.
//!
//! [`app`] is the state machine (no I/O); [`worker`] the thread that owns
//! the stepper; [`history`] the record of the run within its memory
//! budget; [`log`] the event log and its filters; [`sweep`] the sweep
//! view's state and its background threads; [`regime`] the regime map's
//! state and its cancellable computation; [`keys`] the one key table;
//! [`event`] the loop's inputs; [`terminal`] setup, restore and signals;
//! [`mod@format`] how numbers are written; and [`ui`] the panels, one widget
//! each. The loop here takes what the worker sent, draws, and answers keys.

pub mod app;
pub mod event;
pub mod format;
pub mod history;
pub mod keys;
pub mod log;
pub mod regime;
pub mod sweep;
pub mod terminal;
pub mod ui;
pub mod worker;

use std::io;
use std::time::{Duration, Instant};

use crate::analysis::case::{Case, CaseParams};
use crate::io::preset::Preset;
use app::{App, Config};
use event::Event;

/// Time between frames while stepping (60 fps).
pub const FRAME: Duration = Duration::from_millis(16);
/// Time a frame may spend taking the worker's records: half a frame,
/// leaving the rest to drawing and input so a frame never runs long.
pub const STEP_BUDGET: Duration = Duration::from_millis(8);
/// Wait between redraws when nothing is stepping.
const IDLE_WAIT: Duration = Duration::from_millis(250);

/// The case the explorer opens on: the paper's Fig. 3 (in phase) at a
/// `lambda` in the cyclic-slip range, reached through the transient via
/// `(7pi/4, -7pi/4)`, which leaves the stick diamond so locked-in slip
/// shows from the start.
pub fn default_params() -> CaseParams {
    CaseParams {
        load_factor: 6.0,
        initial: crate::model::Initial::Via { a: 7, b: -7 },
        ..CaseParams::default()
    }
}

/// Errors of the terminal explorer. A terminal that is too small is not
/// one: the screen says so and waits for a resize.
#[derive(Debug, thiserror::Error)]
pub enum TuiError {
    /// Stdin or stdout is not a TTY.
    #[error("the explorer needs a terminal: stdin and stdout must both be a TTY (use `shakedown run` for plain output)")]
    NotATerminal,
    /// Reading from or drawing to the terminal failed.
    #[error("terminal: {0}")]
    Io(#[from] io::Error),
}

/// Frame timings, written to the file named by `SHAKEDOWN_FRAME_STATS` on
/// exit: the only way to see them without disturbing the screen.
#[derive(Debug, Default)]
struct FrameStats {
    frames: u64,
    busy_frames: u64,
    total: Duration,
    busy_total: Duration,
    max: Duration,
    max_step: Duration,
    max_draw: Duration,
    over_50ms: u64,
    /// The slowest frames: (frame, step, draw, increments stepped).
    slowest: Vec<(u64, Duration, Duration, usize)>,
}

impl FrameStats {
    fn record(&mut self, step: Duration, draw: Duration, stepped: usize, busy: bool) {
        let took = step + draw;
        self.frames += 1;
        self.total += took;
        if busy {
            self.busy_frames += 1;
            self.busy_total += took;
        }
        self.max = self.max.max(took);
        self.max_step = self.max_step.max(step);
        self.max_draw = self.max_draw.max(draw);
        if took > Duration::from_millis(50) {
            self.over_50ms += 1;
        }
        self.slowest.push((self.frames, step, draw, stepped));
        self.slowest.sort_by_key(|s| std::cmp::Reverse(s.1 + s.2));
        self.slowest.truncate(5);
    }

    fn write(&self, path: &std::ffi::OsStr, increments: usize) {
        let mean = |t: Duration, n: u64| t.as_secs_f64() * 1e3 / n.max(1) as f64;
        let text = format!(
            "frames {}\nstepping frames {}\nmean frame ms {:.3}\nmean stepping frame ms {:.3}\nmax frame ms {:.3}\nmax step ms {:.3}\nmax draw ms {:.3}\nframes over 50 ms {}\nincrements {}\n",
            self.frames,
            self.busy_frames,
            mean(self.total, self.frames),
            mean(self.busy_total, self.busy_frames),
            self.max.as_secs_f64() * 1e3,
            self.max_step.as_secs_f64() * 1e3,
            self.max_draw.as_secs_f64() * 1e3,
            self.over_50ms,
            increments
        );
        let mut text = text;
        for (frame, step, draw, stepped) in &self.slowest {
            text.push_str(&format!(
                "slow frame {frame}: step {:.3} ms ({stepped} increments), draw {:.3} ms\n",
                step.as_secs_f64() * 1e3,
                draw.as_secs_f64() * 1e3
            ));
        }
        let _ = std::fs::write(path, text);
    }
}

/// Run the explorer on `case` until the user quits. The sweep view runs
/// `preset`'s sweep over the case's model, or the built-in
/// [`app::DEFAULT_SWEEP_PRESET`] without one.
pub fn run(case: Case, preset: Option<Preset>) -> Result<(), TuiError> {
    run_with(case, preset, Config::from_env()).map(|_| ())
}

/// [`run`] with an explicit configuration; returns the exit status: 0
/// after `q`, 130 after Ctrl-C, 128 + the signal after SIGTERM, SIGHUP or
/// SIGQUIT (the terminal is restored first in every case).
pub fn run_with(case: Case, preset: Option<Preset>, config: Config) -> Result<u8, TuiError> {
    run_app(case, preset, config, false)
}

/// [`run_with`], opening on the guided tour's first stop (`tui --tour`):
/// the tour's cases use the model of `case` (its disc, material and
/// solver options).
pub fn run_tour(case: Case, preset: Option<Preset>, config: Config) -> Result<u8, TuiError> {
    run_app(case, preset, config, true)
}

fn run_app(case: Case, preset: Option<Preset>, config: Config, tour: bool) -> Result<u8, TuiError> {
    terminal::check_tty()?;
    let signals = terminal::signals();
    let mut app = match preset {
        Some(p) => {
            let source = sweep::SweepSource::from_preset(&p, &case).map_err(|e| e.to_string());
            App::with_sweep(case, config, source)
        }
        None => App::new(case, config),
    };
    if tour {
        app.start_tour();
    }
    let mut term = terminal::setup()?;
    let result = event_loop(&mut term, &mut app, &signals);
    terminal::restore();
    result
}

fn event_loop(
    term: &mut terminal::Term,
    app: &mut App,
    signals: &std::sync::atomic::AtomicUsize,
) -> Result<u8, TuiError> {
    let mut stats = FrameStats::default();
    loop {
        let start = Instant::now();
        let busy = app.is_busy();
        let before = app.increments();
        app.tick(STEP_BUDGET);
        let stepped = app.increments().saturating_sub(before);
        let drawing = Instant::now();
        term.draw(|frame| ui::draw(frame, app))?;
        stats.record(drawing - start, drawing.elapsed(), stepped, busy);

        // Wait out the rest of the frame, acting on every key that comes
        // in; a key redraws at once rather than at the next tick.
        let wait = if app.is_busy() { FRAME } else { IDLE_WAIT };
        let deadline = start + wait;
        loop {
            match terminal::take_signal(signals) {
                terminal::Signal::None => {}
                terminal::Signal::Interrupt => app.request_quit_with(130),
                terminal::Signal::Exit(code) => {
                    app.request_quit_with(code);
                }
                terminal::Signal::Suspend => {
                    terminal::suspend(term)?;
                    break;
                }
            }
            if app.take_suspend() {
                terminal::suspend(term)?;
                break;
            }
            if app.should_quit() {
                if let Some(path) = std::env::var_os("SHAKEDOWN_FRAME_STATS") {
                    stats.write(&path, app.increments());
                }
                return Ok(app.exit_code());
            }
            // Short polls, so a signal is answered within a frame.
            let left = deadline
                .saturating_duration_since(Instant::now())
                .min(FRAME);
            match event::next(left)? {
                Event::Key(key) => {
                    app.handle_key(key);
                    break;
                }
                Event::Scroll(delta) => {
                    app.scroll(delta);
                    break;
                }
                Event::Resize(..) => {
                    term.autoresize()?;
                    break;
                }
                Event::Tick => {
                    if Instant::now() >= deadline {
                        break;
                    }
                }
            }
        }
    }
}
