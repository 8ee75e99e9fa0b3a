//! The event log: every event of the run with its cycle, `omega t`, load
//! point and `theta` range, and the filters that choose which events the
//! jump keys land on and which pause the run.
//!
//! Entries are made from the stepper's [`Event`]s as they come (the slip
//! zone changes are the stepper's own, see `stepping::zones`); nothing is
//! worked out here beyond describing them.

use std::f64::consts::PI;

use super::format::{format_sci, plural};
use crate::analysis::episodes::ThetaRange;
use crate::contact::SlipDirection;
use crate::stepping::{slip_zones, Event, GrossSlip, Separation, ZoneChange};

/// The kinds of events the log lists and the filters choose from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// Nodes that slipped stuck again (their slip rate reached zero).
    AdvancingStick,
    /// Stick nodes reached `|q| = f p` and began to slip.
    SlipEntry,
    /// A slip zone appeared (one with no predecessor).
    Appeared,
    /// A slip zone split into two or more.
    Split,
    /// Two or more slip zones merged into one.
    Merged,
    /// A slip zone vanished (one with no successor).
    Vanished,
    /// The transient ended or a cycle completed.
    Cycle,
    /// Classified, gross slip, separation, or a solver failure.
    State,
}

impl EventKind {
    /// The kind in words, as the log and the filter's description show it.
    pub fn name(self) -> &'static str {
        match self {
            EventKind::AdvancingStick => "advancing stick",
            EventKind::SlipEntry => "slip entry",
            EventKind::Appeared => "zone appeared",
            EventKind::Split => "zone split",
            EventKind::Merged => "zones merged",
            EventKind::Vanished => "zone vanished",
            EventKind::Cycle => "cycle",
            EventKind::State => "state",
        }
    }
}

/// Which events the jump keys and the pause on events look for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Filter {
    /// `None`: every kind except cycle ends and vanishing zones.
    pub kind: Option<EventKind>,
    /// Advancing stick of fewer nodes is ignored.
    pub min_nodes: usize,
}

impl Default for Filter {
    fn default() -> Self {
        Self {
            kind: None,
            min_nodes: 1,
        }
    }
}

/// The kinds `k` cycles through, `None` being "any notable event".
pub const KINDS: [Option<EventKind>; 9] = [
    None,
    Some(EventKind::AdvancingStick),
    Some(EventKind::SlipEntry),
    Some(EventKind::Appeared),
    Some(EventKind::Split),
    Some(EventKind::Merged),
    Some(EventKind::Vanished),
    Some(EventKind::Cycle),
    Some(EventKind::State),
];

/// The sizes `m` cycles through for advancing stick.
pub const MIN_NODES: [usize; 8] = [1, 2, 4, 8, 16, 32, 64, 128];

impl Filter {
    /// Whether the entry is of the kind looked for (advancing stick of at
    /// least [`Filter::min_nodes`] nodes).
    pub fn matches(&self, e: &LogEntry) -> bool {
        let kind_ok = match self.kind {
            None => !matches!(
                e.kind,
                EventKind::Cycle | EventKind::Vanished | EventKind::SlipEntry
            ),
            Some(k) => k == e.kind,
        };
        kind_ok && (e.kind != EventKind::AdvancingStick || e.nodes >= self.min_nodes)
    }

    /// Whether events of the filter happen inside an increment (entries
    /// into slip, advancing stick, slip-zone changes), so that a pause on
    /// them stops the contact at the event's load point.
    pub fn inside_increments(&self) -> bool {
        !matches!(self.kind, Some(EventKind::Cycle | EventKind::State))
    }

    /// The filter in words, for notices and the log's title.
    pub fn describe(&self) -> String {
        let kind = self.kind.map_or("any event", EventKind::name);
        if self.min_nodes > 1 && matches!(self.kind, None | Some(EventKind::AdvancingStick)) {
            format!("{kind}, stick >= {} nodes", self.min_nodes)
        } else {
            kind.to_string()
        }
    }
}

/// One line of the log.
#[derive(Debug, Clone, PartialEq)]
pub struct LogEntry {
    /// What kind of event this is.
    pub kind: EventKind,
    /// Increment number from the start of the run (0-based).
    pub increment: usize,
    /// 0 in the transient.
    pub cycle: usize,
    /// `omega t` of the event, `None` in the transient.
    pub time: Option<f64>,
    /// The load point of the event.
    pub load: (f64, f64),
    /// Nodes concerned (advancing stick), else 0.
    pub nodes: usize,
    /// First and last `theta` concerned, in `[-pi, pi)`, along the
    /// shortest arc (first > last when it runs through `theta = pi`).
    pub theta: Option<(f64, f64)>,
    /// What happened, in words.
    pub text: String,
}

impl LogEntry {
    /// Bytes the entry holds, as the history budget counts them.
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.text.len()
    }
}

/// Where and when the events of one increment happened. The stepper's
/// events do not all carry their own time and load point yet; until they
/// do, the increment's end stands for them.
#[derive(Debug, Clone, Copy)]
pub struct At {
    /// Increment number from the start of the run (0-based).
    pub increment: usize,
    /// Cycle of the increment, 0 in the transient.
    pub cycle: usize,
    /// `omega t` at the end of the increment, `None` in the transient.
    pub time: Option<f64>,
    /// The load point `(x, y)` at the end of the increment.
    pub load: (f64, f64),
}

/// The log entries of one increment's events. `directions` are the slip
/// directions after the increment (for the `theta` range of zones).
pub fn entries(events: &[Event], at: At, directions: &[SlipDirection]) -> Vec<LogEntry> {
    let n = directions.len();
    let entry = |kind, nodes, theta, text: String| LogEntry {
        kind,
        increment: at.increment,
        cycle: at.cycle,
        time: at.time,
        load: at.load,
        nodes,
        theta,
        text,
    };
    let mut out = Vec::new();
    for event in events {
        match event {
            Event::SlipSetChanged { changes, .. } => {
                for change in changes {
                    let (kind, d) = match *change {
                        ZoneChange::Appeared(d) => (EventKind::Appeared, d),
                        ZoneChange::Split(d) => (EventKind::Split, d),
                        ZoneChange::Merged(d) => (EventKind::Merged, d),
                        ZoneChange::Vanished(d) => (EventKind::Vanished, d),
                    };
                    let nodes: Vec<usize> = slip_zones(directions)
                        .iter()
                        .filter(|z| z.direction == d)
                        .flat_map(|z| z.nodes(n).collect::<Vec<_>>())
                        .collect();
                    out.push(entry(kind, 0, theta_range(&nodes, n), change.to_string()));
                }
            }
            Event::AdvancingStick {
                nodes, time, load, ..
            } => {
                // Located exactly within the increment by the engine.
                let mut e = entry(
                    EventKind::AdvancingStick,
                    nodes.len(),
                    theta_range(nodes, n),
                    // The sub-segments belong to the increment, not the
                    // event: the tractions panel counts them, once.
                    format!("advancing stick at {}", plural(nodes.len(), "node")),
                );
                e.load = (load.x(), load.y());
                e.time = time.or(e.time);
                out.push(e);
            }
            Event::SlipEntry { nodes, time, load } => {
                let mut e = entry(
                    EventKind::SlipEntry,
                    nodes.len(),
                    theta_range(nodes, n),
                    format!("slip entry at {}", plural(nodes.len(), "node")),
                );
                e.load = (load.x(), load.y());
                e.time = time.or(e.time);
                out.push(e);
            }
            Event::TransientFinished => out.push(entry(
                EventKind::Cycle,
                0,
                None,
                "transient finished: cycle 1 begins".into(),
            )),
            Event::CycleCompleted {
                cycle,
                dissipation,
                rotation,
            } => out.push(entry(
                EventKind::Cycle,
                0,
                None,
                format!(
                    "cycle {cycle} completed: W = {}, rotation {}",
                    format_sci(*dissipation),
                    format_sci(*rotation)
                ),
            )),
            Event::SteadyStateReached(s) => out.push(entry(
                EventKind::State,
                0,
                None,
                format!(
                    "classified: {} after {} cycles ({})",
                    s.state().as_str(),
                    s.cycles,
                    s.approach()
                ),
            )),
            Event::GrossSlip(GrossSlip { load, time }) => {
                let mut e = entry(
                    EventKind::State,
                    0,
                    None,
                    format!(
                        "gross slip at load point ({:.3}, {:.3})",
                        load.x(),
                        load.y()
                    ),
                );
                e.load = (load.x(), load.y());
                e.time = time.or(e.time);
                out.push(e);
            }
            Event::Separation(Separation { load, time, theta }) => {
                let mut e = entry(
                    EventKind::State,
                    0,
                    Some((*theta, *theta)),
                    format!("separation at theta = {:.3}pi", theta / PI),
                );
                e.load = (load.x(), load.y());
                e.time = time.or(e.time);
                out.push(e);
            }
        }
    }
    out
}

/// The first and last `theta` of `nodes` along the shortest arc that holds
/// them: `first > last` when the arc runs through `theta = pi`.
fn theta_range(nodes: &[usize], n: usize) -> Option<(f64, f64)> {
    ThetaRange::of_nodes(nodes, n).map(|r| (r.from, r.to))
}

/// `theta/pi = -0.73..-0.70`, `0.85..-0.90 (wraps)`, or one value.
pub fn format_theta(range: Option<(f64, f64)>) -> String {
    match range {
        None => "–".into(),
        Some((from, to)) => ThetaRange { from, to }.to_string(),
    }
}
