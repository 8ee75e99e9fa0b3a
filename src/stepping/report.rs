//! What the stepper says: where it is ([`Phase`]), what happened in a step
//! ([`Event`], [`StepReport`]), where a run stands ([`Status`]) and how a
//! transient to the cycle centre came out ([`AtCenter`]).

use serde::Serialize;

use super::outcome::{GrossSlip, Outcome, Separation};
use super::zones::ZoneChange;
use crate::contact::Contact;
use crate::model::LoadPoint;

/// Where the stepper is on its path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// In the initial transient: segment index and increment within it.
    Transient {
        /// Index of the transient's straight segment (0-based).
        segment: usize,
        /// Index of the increment within the segment (0-based).
        increment: usize,
    },
    /// In cycle `cycle` (1-based), `increment` increments done.
    Cycle {
        /// The cycle number, 1-based.
        cycle: usize,
        /// Increments of the cycle done so far, out of
        /// [`Discretisation::steps_per_cycle`].
        increment: usize,
    },
}

/// Something the stepper observed during one step.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "kebab-case")]
pub enum Event {
    /// The set of slipping nodes or their directions changed.
    SlipSetChanged {
        /// Nodes slipping now.
        slipping: usize,
        /// Slip zones now.
        zones: usize,
        /// What happened to the zones (appeared, split, merged, vanished).
        changes: Vec<ZoneChange>,
    },
    /// Nodes that slipped stuck again (their slip rate reached zero), at
    /// the exact load point `load` within the increment, at `omega t =
    /// time` in the cycle (`None` in the transient). The increment has
    /// `substeps` straight sub-segments with a fixed slip set.
    AdvancingStick {
        /// Indices of the nodes that stuck again, with their slip `g`
        /// locked in (model.md section 3.3).
        nodes: Vec<usize>,
        /// Straight sub-segments of the increment with a fixed slip set.
        substeps: usize,
        /// `omega t` in `[0, 2 pi)` in the cycle; `None` in the transient.
        time: Option<f64>,
        /// The load point `(x, y)` where the nodes stuck.
        load: LoadPoint,
    },
    /// Stick nodes reached `|q| = f p` and started to slip, at the exact
    /// load point `load` (`omega t = time` in the cycle).
    SlipEntry {
        /// Indices of the nodes that started to slip.
        nodes: Vec<usize>,
        /// `omega t` in `[0, 2 pi)` in the cycle; `None` in the transient.
        time: Option<f64>,
        /// The load point `(x, y)` where they reached the friction limit.
        load: LoadPoint,
    },
    /// The transient is over: the next step is the first of cycle 1.
    TransientFinished,
    /// A cycle ended.
    CycleCompleted {
        /// The cycle that ended, 1-based.
        cycle: usize,
        /// Its dissipation `W`, the paper's `W~` of eq. (16) (model.md
        /// section 4).
        dissipation: f64,
        /// Its net rigid rotation: the change of the mean of the slip `g`
        /// over the cycle, negative when the disc ratchets forward
        /// (model.md section 1.3).
        rotation: f64,
    },
    /// The steady state was reached and classified (or the run ended).
    SteadyStateReached(Outcome),
    /// The whole interface slides: `|y|` reached `2 pi` (exact,
    /// interpolated within the increment). The run ends here.
    GrossSlip(GrossSlip),
    /// The pressure reached zero: the run ends here.
    Separation(Separation),
}

/// Where a transient to the cycle centre `A` left the contact
/// ([`Stepper::prepare_at_center`]).
#[derive(Debug, Clone)]
pub enum AtCenter {
    /// At `A`, ready for the cycle.
    Ready(Box<Contact>),
    /// The transient ended the run (gross slip or separation before `A`).
    Ended(Outcome),
}

/// What one call to [`Stepper::step`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepReport {
    /// What happened during the step, in order.
    pub events: Vec<Event>,
    /// Straight sub-segments with a fixed slip set (1 unless an event
    /// happened inside the increment).
    pub substeps: usize,
    /// Whether the slip set or a direction changed during the step.
    pub slip_set_changed: bool,
    /// Dissipation of this increment.
    pub dissipation: f64,
    /// Nodes that went from slip to stick during this step.
    pub newly_stuck: Vec<usize>,
    /// LU factorisations computed during this step.
    pub factorisations: usize,
    /// Rate problems solved during this step (0 while the slip set holds).
    pub iterations: usize,
    /// `Some(s)` when the step stopped at an event at parameter `s` of the
    /// increment ([`Stepper::set_pause_at_events`]): the contact is at the
    /// event's load point and the next step finishes the increment.
    pub partial: Option<f64>,
}

/// The run's status.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// No verdict yet: in the transient or in a cycle before the steady
    /// state.
    Running,
    /// Classified; stepping may continue through further cycles.
    Steady(Outcome),
    /// Gross slip or separation: no further steps are possible.
    Ended(Outcome),
}
