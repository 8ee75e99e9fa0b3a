//! The stepping thread: it owns the [`Stepper`] so that the UI thread never
//! waits on the physics. It takes [`Command`]s (restart with a case, step
//! towards a goal, pause, the pause filter) and sends back one [`Record`]
//! per increment and a [`Reply::Stopped`] when a goal ends. Every goal is
//! run by [`stepping::drive`] with an observer; the observer stops the
//! drive as soon as a new command arrives, so a restart cancels the work it
//! replaces.
//!
//! The worker also keeps a copy of its stepper at the start of the last
//! two cycles, so that the fretting profile of the last completed cycle
//! ([`Command::Profile`]) is computed from the very state that cycle began
//! with, on a thread of its own, while the run goes on.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender, SyncSender, TryRecvError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::history::{Detail, Record, BACKWARD, FORWARD, NEWLY_STUCK, STICK};
use super::log::{self, At, Filter};
use crate::analysis::case::Case;
use crate::analysis::curves;
use crate::analysis::episodes::{EpisodeTracker, LockedSlip};
use crate::analysis::profile::{profile_cycle, Profile};
use crate::contact::{Operators, SlipDirection};
use crate::model::path::{Initial, Segment};
use crate::stepping::{self, Control, Event, Observer, Phase, Status, StepReport, Stepper};

/// How far the worker should go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    /// Exactly this many increments (fewer if the run stops).
    Increments(usize),
    /// Until the transient path is done.
    TransientEnd,
    /// Until the cycle in progress is complete.
    CycleEnd,
    /// Until the run is classified as a steady state.
    Steady,
    /// Run on at this many increments per frame until told otherwise.
    Paced(usize),
}

/// What the UI asks of the worker.
#[derive(Debug)]
pub enum Command {
    /// A new run on `case`; records of older generations are stale.
    Restart {
        /// Number of the new run; replies carry it so stale ones are ignored.
        generation: u64,
        /// The case to run.
        case: Box<Case>,
        /// The initial path to run it from: [`Initial::Optimal`] is
        /// resolved by the worker, off the UI thread.
        initial: Initial,
    },
    /// Step towards `goal`; `Stopped` answers with the same `seq`.
    Go {
        /// Number of this request; the [`Reply::Stopped`] that ends it carries it.
        seq: u64,
        /// How far to step.
        goal: Goal,
    },
    /// Stop stepping (the drive in progress, if any, answers `Stopped`).
    Pause,
    /// Which events stop a drive (`None`: none do).
    PauseOn(Option<Filter>),
    /// The byte budget the stepper's own record of completed cycles may
    /// use (only a very high cycle cap can reach it).
    Budget(usize),
    /// The fretting profile of the last completed cycle, computed on a
    /// thread of its own ([`Reply::Profile`] answers); the run is not
    /// interrupted.
    Profile,
}

/// Why a drive stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum Stopped {
    /// The goal was met.
    Reached,
    /// An event the filter asked to pause on: its text, and its load point
    /// when the run stopped there, inside the increment (`None`: at the
    /// end of the increment, for events that belong to it as a whole).
    Event(String, Option<(f64, f64)>),
    /// Gross slip or separation: no further steps are possible.
    Ended,
    /// The solver failed.
    Failed(String),
    /// A new command replaced the drive.
    Cancelled,
    /// The stepper's own record of cycles reached its budget (a run far
    /// from its verdict under a very high cycle cap).
    Memory,
}

/// What the worker sends back.
#[derive(Debug)]
pub enum Reply {
    /// A run began: its transient and friction coefficient.
    Started {
        /// The generation of the run (see [`Command::Restart`]).
        generation: u64,
        /// The segments of the initial transient path.
        transient: Vec<Segment>,
        /// The friction coefficient `f` of the case.
        friction: f64,
    },
    /// One increment of the run, with the generation it belongs to.
    Record(Box<Record>),
    /// The fretting profile of the last completed cycle of a run
    /// (`Ok(None)`: no cycle was complete when it was asked for).
    Profile {
        /// The generation of the run it belongs to.
        generation: u64,
        /// The profile, or why it could not be computed.
        profile: Result<Option<Box<Profile>>, String>,
    },
    /// A drive ended, for whatever reason.
    Stopped {
        /// The generation of the run it belongs to.
        generation: u64,
        /// The `seq` of the [`Command::Go`] it answers.
        seq: u64,
        /// Why it stopped.
        why: Stopped,
    },
}

/// Bytes of replies in flight before the worker waits for the UI: a few
/// frames at top speed, little enough not to matter beside
/// `--history-mb` even when the UI is held up (a record holds about 16
/// bytes a node).
const CHANNEL_BYTES: usize = 2 << 20;

/// Replies in flight for `nodes` nodes: [`CHANNEL_BYTES`] worth, between
/// 64 and 4096 of them.
fn channel_len(nodes: usize) -> usize {
    (CHANNEL_BYTES / (16 * nodes.max(1))).clamp(64, 4096)
}
/// The frame the paced goal keeps to.
const FRAME: Duration = Duration::from_millis(16);

/// The UI's handle on the worker thread; dropping it ends the thread.
pub struct Worker {
    tx: Option<Sender<Command>>,
    rx: Receiver<Reply>,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// Start the worker thread on `operators` (shared with the UI), idle
    /// until the first [`Command::Restart`].
    pub fn spawn(operators: Arc<Operators>) -> Self {
        let (tx, commands) = mpsc::channel();
        let (replies, rx) = mpsc::sync_channel(channel_len(operators.nodes()));
        let thread = std::thread::Builder::new()
            .name("shakedown-stepper".into())
            .spawn(move || Thread::new(operators, commands, replies).run())
            .ok();
        Self {
            tx: Some(tx),
            rx,
            thread,
        }
    }

    /// Send `command`; ignored if the thread is gone.
    pub fn send(&self, command: Command) {
        if let Some(tx) = &self.tx {
            let _ = tx.send(command);
        }
    }

    /// The next reply if one is waiting, without blocking.
    pub fn try_recv(&self) -> Option<Reply> {
        self.rx.try_recv().ok()
    }

    /// Wait for the next reply (tests and `advance`); `None` if the thread
    /// is gone.
    pub fn recv(&self) -> Option<Reply> {
        self.rx.recv().ok()
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // Closing both channels ends the thread: at its next command wait,
        // its next send, or its next check between increments. It is not
        // joined, so quitting never waits on an increment in progress.
        self.tx = None;
        let (_, dead) = mpsc::sync_channel(0);
        drop(std::mem::replace(&mut self.rx, dead));
        drop(self.thread.take());
    }
}

struct Thread {
    operators: Arc<Operators>,
    commands: Receiver<Command>,
    replies: SyncSender<Reply>,
    stepper: Option<Stepper>,
    /// Why the last case has no stepper: its optimal slip could not be
    /// found.
    unresolved: Option<String>,
    /// `g` when each node's slip episode began, for what advancing stick
    /// locks in; it follows the stepper across drives.
    episodes: Option<EpisodeTracker>,
    generation: u64,
    filter: Option<Filter>,
    budget: usize,
    pending: Option<Command>,
    closed: bool,
    /// Copies of the stepper at the start of the last two cycles.
    starts: CycleStarts,
    /// Raised to cancel the profile being computed.
    profile_cancel: Arc<AtomicBool>,
}

/// Up to this many nodes the copies of the cycles' starts are kept from
/// the first cycle, so `f` shows a profile at once. A copy holds the slip
/// set's factors, room for `N x N` (8 MiB at 1024 nodes): above that the
/// copies are kept only once a profile has been asked for.
const ALWAYS_KEEP_NODES: usize = 1024;

/// Copies of a run's stepper where its last two cycles began: the older
/// one began the last completed cycle (once the newer one has begun).
struct CycleStarts {
    /// Whether copies are kept (see [`ALWAYS_KEEP_NODES`]).
    keep: bool,
    previous: Option<Box<Stepper>>,
    current: Option<Box<Stepper>>,
}

impl CycleStarts {
    fn new(keep: bool) -> Self {
        Self {
            keep,
            previous: None,
            current: None,
        }
    }

    /// Keep a copy of `s` if it stands at the start of a cycle not yet
    /// kept. A copy is a few vectors of N and the factors of the slip set,
    /// once a cycle.
    fn note(&mut self, s: &Stepper) {
        if !self.keep {
            return;
        }
        if !matches!(s.phase(), Phase::Cycle { increment: 0, .. }) || s.is_inside_increment() {
            return;
        }
        let kept = self.current.as_ref().map(|c| c.phase());
        if kept == Some(s.phase()) {
            return;
        }
        self.previous = self.current.take();
        self.current = Some(Box::new(s.clone()));
    }

    /// The stepper at the start of the last completed cycle.
    fn last_completed(&self) -> Option<&Stepper> {
        self.previous.as_deref()
    }
}

/// Compute the profile of the last completed cycle in `starts` on a thread
/// of its own and send it as a [`Reply::Profile`]; the one in progress, if
/// any, is cancelled.
fn spawn_profile(
    starts: &mut CycleStarts,
    replies: &SyncSender<Reply>,
    generation: u64,
    cancel: &mut Arc<AtomicBool>,
) {
    cancel.store(true, Ordering::Relaxed);
    *cancel = Arc::new(AtomicBool::new(false));
    starts.keep = true;
    let Some(start) = starts.last_completed() else {
        let _ = replies.send(Reply::Profile {
            generation,
            profile: Ok(None),
        });
        return;
    };
    let mut stepper = start.clone();
    let stop = Arc::clone(cancel);
    let sender = replies.clone();
    let spawned = std::thread::Builder::new()
        .name("shakedown-profile".into())
        .spawn(move || {
            let profile = profile_cycle(&mut stepper, &stop)
                .map(|p| p.map(Box::new))
                .map_err(|e| e.to_string());
            if !stop.load(Ordering::Relaxed) {
                let _ = sender.send(Reply::Profile {
                    generation,
                    profile,
                });
            }
        });
    if let Err(e) = spawned {
        let _ = replies.send(Reply::Profile {
            generation,
            profile: Err(format!("no thread for the profile: {e}")),
        });
    }
}

impl Thread {
    fn new(
        operators: Arc<Operators>,
        commands: Receiver<Command>,
        replies: SyncSender<Reply>,
    ) -> Self {
        let keep = operators.nodes() <= ALWAYS_KEEP_NODES;
        Self {
            operators,
            commands,
            replies,
            stepper: None,
            unresolved: None,
            episodes: None,
            generation: 0,
            filter: None,
            budget: usize::MAX,
            pending: None,
            closed: false,
            starts: CycleStarts::new(keep),
            profile_cancel: Arc::new(AtomicBool::new(false)),
        }
    }

    fn run(mut self) {
        while !self.closed {
            let command = match self.pending.take() {
                Some(c) => c,
                None => match self.commands.recv() {
                    Ok(c) => c,
                    Err(_) => return,
                },
            };
            self.handle(command);
        }
    }

    fn handle(&mut self, command: Command) {
        match command {
            Command::Restart {
                generation,
                case,
                initial,
            } => {
                // A storm of restarts builds only the last one.
                let mut case = case;
                let mut generation = generation;
                let mut requested = initial;
                loop {
                    match self.commands.try_recv() {
                        Ok(Command::Restart {
                            generation: g,
                            case: c,
                            initial: i,
                        }) => {
                            generation = g;
                            case = c;
                            requested = i;
                        }
                        Ok(other) => {
                            self.pending = Some(other);
                            break;
                        }
                        Err(TryRecvError::Empty) => break,
                        Err(TryRecvError::Disconnected) => {
                            self.closed = true;
                            return;
                        }
                    }
                }
                // The optimal slip's linear programme is solved here, off
                // the UI thread, like every other step of the run.
                let initial = curves::resolve_initial(
                    &requested,
                    &case.material(),
                    case.cycle(),
                    &case.disc(),
                    None,
                );
                self.unresolved = initial
                    .as_ref()
                    .err()
                    .map(|e| format!("no optimal slip: {e}"));
                let initial = initial.unwrap_or(requested);
                let mut stepper = Stepper::with_operators(
                    Arc::clone(&self.operators),
                    case.material(),
                    case.disc(),
                    &initial,
                    case.cycle().clone(),
                    case.options(),
                );
                stepper.set_pause_at_events(self.filter.is_some_and(|f| f.inside_increments()));
                self.generation = generation;
                self.episodes = Some(EpisodeTracker::new(&stepper));
                self.profile_cancel.store(true, Ordering::Relaxed);
                self.starts = CycleStarts::new(self.starts.keep);
                self.starts.note(&stepper);
                let reply = Reply::Started {
                    generation,
                    transient: stepper.transient().to_vec(),
                    friction: stepper.contact().material().friction(),
                };
                self.stepper = Some(stepper);
                self.send(reply);
            }
            Command::Go { seq, goal } => self.go(seq, goal),
            Command::Pause => {}
            Command::PauseOn(f) => {
                self.filter = f;
                // Stop the contact at the event's exact load point (the
                // path is the same), not at the end of its increment.
                if let Some(s) = &mut self.stepper {
                    s.set_pause_at_events(f.is_some_and(|f| f.inside_increments()));
                }
            }
            Command::Budget(b) => self.budget = b,
            Command::Profile => spawn_profile(
                &mut self.starts,
                &self.replies,
                self.generation,
                &mut self.profile_cancel,
            ),
        }
    }

    fn send(&mut self, reply: Reply) {
        if self.replies.send(reply).is_err() {
            self.closed = true;
        }
    }

    fn go(&mut self, seq: u64, goal: Goal) {
        let why = match goal {
            Goal::Paced(rate) => loop {
                let start = Instant::now();
                match self.drive(stepping::Goal::Increments(rate.max(1)), false) {
                    Stopped::Reached => {}
                    other => break other,
                }
                // Wait out the frame, but answer a command at once.
                let left = FRAME.saturating_sub(start.elapsed());
                match self.commands.recv_timeout(left) {
                    Ok(c) => {
                        self.pending = Some(c);
                        break Stopped::Cancelled;
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        self.closed = true;
                        break Stopped::Cancelled;
                    }
                }
            },
            Goal::Increments(n) => self.drive(stepping::Goal::Increments(n), true),
            Goal::TransientEnd => self.drive(stepping::Goal::TransientEnd, true),
            Goal::CycleEnd => self.drive(stepping::Goal::CycleEnd, true),
            // Cycle by cycle, so that the stepper's record of cycles is
            // trimmed on the way (a slow approach can take thousands).
            Goal::Steady => loop {
                let running = self
                    .stepper
                    .as_ref()
                    .is_some_and(|s| matches!(s.status(), Status::Running));
                let goal = if running {
                    stepping::Goal::CycleEnd
                } else {
                    stepping::Goal::Steady
                };
                match self.drive(goal, true) {
                    Stopped::Reached if running => {}
                    other => break other,
                }
            },
        };
        let generation = self.generation;
        self.send(Reply::Stopped {
            generation,
            seq,
            why,
        });
    }

    /// One call of the driver. `to_the_end`: the goal is the user's (so
    /// the end of the run reports `Ended` rather than `Reached`).
    fn drive(&mut self, goal: stepping::Goal, to_the_end: bool) -> Stopped {
        if let Some(why) = &self.unresolved {
            return Stopped::Failed(why.clone());
        }
        let Some(mut stepper) = self.stepper.take() else {
            return Stopped::Failed("no run".into());
        };
        if stepper.is_finished() {
            self.stepper = Some(stepper);
            return Stopped::Ended;
        }
        let mut why: Option<Stopped> = None;
        let mut slip_before: Vec<f32> = centred_slip(&stepper);
        let mut episodes = self
            .episodes
            .take()
            .unwrap_or_else(|| EpisodeTracker::new(&stepper));
        let budget = self.budget;
        let filter = self.filter;
        let generation = self.generation;
        let result = {
            let commands = &self.commands;
            let replies = &self.replies;
            let pending = &mut self.pending;
            let closed = &mut self.closed;
            let starts = &mut self.starts;
            let profile_cancel = &mut self.profile_cancel;
            let mut observer = |s: &Stepper, report: &StepReport| -> Control {
                episodes.observe(s, report);
                // Before the record goes: once the UI reads that a cycle
                // completed, its start is the one kept as `previous`.
                starts.note(s);
                let record = make_record(s, report, generation, &slip_before, &episodes);
                slip_before = record
                    .detail
                    .as_ref()
                    .map(|d| d.slip.clone())
                    .unwrap_or_default();
                let inside = report.partial.is_some();
                let pause = filter.and_then(|f| {
                    record
                        .events
                        .iter()
                        .find(|e| f.matches(e))
                        .map(|e| (e.text.clone(), inside.then_some(record.load)))
                });
                if replies.send(Reply::Record(Box::new(record))).is_err() {
                    *closed = true;
                    return Control::Stop;
                }
                if let Some((text, load)) = pause {
                    why = Some(Stopped::Event(text, load));
                    return Control::Stop;
                }
                // A profile is asked for without stopping the run.
                let mut command = commands.try_recv();
                while let Ok(Command::Profile) = command {
                    spawn_profile(starts, replies, generation, profile_cancel);
                    command = commands.try_recv();
                }
                match command {
                    Ok(c) => {
                        *pending = Some(c);
                        why = Some(Stopped::Cancelled);
                        return Control::Stop;
                    }
                    Err(TryRecvError::Disconnected) => {
                        *closed = true;
                        why = Some(Stopped::Cancelled);
                        return Control::Stop;
                    }
                    Err(TryRecvError::Empty) => {}
                }
                // The stepper's record of cycles is trimmed after every
                // drive (see `KEEP_CYCLES`); before the verdict it keeps
                // `W` of every cycle, which only a cycle cap far beyond
                // the default could make large.
                if cycle_bytes(s) > budget {
                    why = Some(Stopped::Memory);
                    return Control::Stop;
                }
                Control::Continue
            };
            stepping::drive(&mut stepper, goal, &mut observer)
        };
        self.episodes = Some(episodes);
        stepper.trim_history(KEEP_CYCLES);
        let finished = stepper.is_finished();
        self.stepper = Some(stepper);
        match result {
            Err(e) => Stopped::Failed(e.to_string()),
            Ok(_) => match why {
                Some(w) => w,
                None if finished && to_the_end => Stopped::Ended,
                None if finished => Stopped::Ended,
                None => Stopped::Reached,
            },
        }
    }
}

/// Completed cycles whose per-node slip the stepper keeps
/// ([`Stepper::trim_history`]): the steady-state verdict reads no more.
const KEEP_CYCLES: usize = 8;

/// Bytes the stepper's record of completed cycles holds.
fn cycle_bytes(s: &Stepper) -> usize {
    let history = s.history();
    let slip: usize = history
        .iter()
        .rev()
        .take_while(|r| !r.forward.is_empty())
        .map(|r| std::mem::size_of_val(&r.forward[..]) + std::mem::size_of_val(&r.backward[..]))
        .sum();
    std::mem::size_of_val(history) + slip
}

/// What the nodes that stuck in this step locked in, all advancing-stick
/// events of the step together.
fn locked_slip(report: &StepReport, episodes: &EpisodeTracker) -> Option<Box<LockedSlip>> {
    if report.newly_stuck.is_empty() {
        return None;
    }
    let all = Event::AdvancingStick {
        nodes: report.newly_stuck.clone(),
        substeps: report.substeps,
        time: None,
        load: crate::model::LoadPoint::new(0.0, 0.0),
    };
    episodes.locked_slip(&all).map(Box::new)
}

/// `g` minus its mean, as stored.
fn centred_slip(s: &Stepper) -> Vec<f32> {
    let c = s.contact();
    let r = c.rotation();
    c.slip().iter().map(|&g| (g - r) as f32).collect()
}

fn make_record(
    s: &Stepper,
    report: &StepReport,
    generation: u64,
    before: &[f32],
    episodes: &EpisodeTracker,
) -> Record {
    let c = s.contact();
    let after = s.phase();
    // A step paused at an event is inside the increment in progress.
    let inside = report.partial.is_some();
    let increment = if inside {
        s.increments()
    } else {
        s.increments().saturating_sub(1)
    };
    // The phase the increment was taken in: one step back from `after`.
    let phase = match after {
        _ if inside => after,
        Phase::Cycle { cycle, increment } if increment > 0 => Phase::Cycle {
            cycle,
            increment: increment - 1,
        },
        Phase::Cycle { cycle, .. } if cycle > 1 => Phase::Cycle {
            cycle: cycle - 1,
            increment: s.discretisation().steps_per_cycle() - 1,
        },
        Phase::Cycle { .. } => Phase::Transient {
            segment: s.transient().len().saturating_sub(1),
            increment: 0,
        },
        t => t,
    };
    let mut cells: Vec<u8> = c
        .directions()
        .iter()
        .map(|d| match d {
            SlipDirection::Stick => STICK,
            SlipDirection::Forward => FORWARD,
            SlipDirection::Backward => BACKWARD,
        })
        .collect();
    for &j in &report.newly_stuck {
        if let Some(x) = cells.get_mut(j) {
            *x |= NEWLY_STUCK;
        }
    }
    let load = (c.load().x(), c.load().y());
    let cycle = match phase {
        Phase::Transient { .. } => 0,
        Phase::Cycle { cycle, .. } => cycle,
    };
    let at = At {
        increment,
        cycle,
        time: s.time(),
        load,
    };
    let events = log::entries(&report.events, at, c.directions());
    let slip_before =
        (!report.newly_stuck.is_empty() && before.len() == c.nodes()).then(|| before.to_vec());
    Record {
        generation,
        increment,
        phase,
        after,
        time: s.time(),
        load,
        partial: report.partial,
        cells,
        dissipation: s.current_cycle().dissipation,
        rotation: c.rotation(),
        status: s.status().clone(),
        events,
        newly_stuck: report.newly_stuck.clone(),
        locked: locked_slip(report, episodes),
        substeps: report.substeps,
        completed: report.events.iter().find_map(|e| match e {
            Event::CycleCompleted {
                cycle, dissipation, ..
            } => Some((*cycle, *dissipation)),
            _ => None,
        }),
        detail: Some(Box::new(Detail {
            pressure: c.pressure().iter().map(|&v| v as f32).collect(),
            shear: c.shear().iter().map(|&v| v as f32).collect(),
            slip: centred_slip(s),
            slip_before,
        })),
    }
}
