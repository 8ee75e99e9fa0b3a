//! The stepper: advances the contact one load increment at a time along a
//! transient and then the steady cycle, and reports what happened as events.
//! The TUI and the batch runs are both consumers of this one type.
//!
//! [`Stepper`]'s data and its methods live in this folder: the state, its
//! accessors and the close of a cycle with its verdict here, its
//! construction in [`build`], a step in [`step`], and the straight-run
//! bookkeeping in [`straight`].

use std::f64::consts::PI;
use std::sync::Arc;

use crate::contact::{
    Advanced, Contact, ContactEnd, ContactError, ContactEventKind, Operators, SlipDirection,
};
use crate::model::path::{entry_waypoints, segments, Initial, Segment};
use crate::model::{Cycle, Discretisation, LoadPoint, Material};
use crate::stepping::driver::{drive, Control, Driven, Goal, Silent};
use crate::stepping::options::{StepError, StepOptions};
use crate::stepping::outcome::{GrossSlip, Outcome, Separation, ShakedownProof, Verdict};
use crate::stepping::report::{AtCenter, Event, Phase, Status, StepReport};
use crate::stepping::safe_state::{self, Certificate, Fall, SafeStateSearch};
use crate::stepping::steady::{assess, Approach, CycleRecord, SteadyState};
use crate::stepping::verdict::trend;
use crate::stepping::zones::{slip_zones, zone_changes, SlipZone};

mod build;
mod step;
mod straight;
#[cfg(test)]
mod tests;
use straight::StraightRuns;

/// How far [`Stepper::advance`] got along its part of the increment.
enum Progress {
    /// To its end.
    Done,
    /// To an event at this parameter of the increment (pausing at events).
    Paused(f64),
    /// To a physical end at this parameter.
    Ended(ContactEnd, f64),
}

/// `omega t` at `position` increments into a cycle of `steps` increments:
/// one expression for the cycle's load points and their table, the times of
/// events and the points of a safe-state search, so that they agree to the
/// bit.
pub(crate) fn cycle_angle(position: f64, steps: usize) -> f64 {
    2.0 * PI * position / steps as f64
}

/// Advances a contact along `transient` and then the steady `cycle`.
#[derive(Debug, Clone)]
pub struct Stepper {
    contact: Contact,
    transient: Vec<Segment>,
    cycle: Cycle,
    /// The cycle's load points at the ends of its increments, `ωt = 2π i /
    /// steps` for `i = 0..=steps`: the same numbers [`Stepper::point`]
    /// computes there, once per run instead of twice per increment.
    cycle_points: Vec<LoadPoint>,
    disc: Discretisation,
    options: StepOptions,
    phase: Phase,
    current: CycleRecord,
    rotation_at_cycle_start: f64,
    history: Vec<CycleRecord>,
    status: Status,
    increments: usize,
    /// An initial condition that could not be set up: the first step reports it.
    unresolved: Option<StepError>,
    /// The slip directions at the last reported change of the slip set,
    /// for the slip-zone topology of the next one.
    zone_dirs: Vec<SlipDirection>,
    /// The slip zones of `zone_dirs`.
    zones: Vec<SlipZone>,
    /// Whether steps report [`Event::SlipSetChanged`] (a pass over the
    /// nodes at every change of the slip set, which a batch run that reads
    /// no events need not pay).
    zone_events: bool,
    /// Whether steps report the contact's events (entries into slip and
    /// advancing stick, with their `omega t`), which a batch run that reads
    /// no events need not build.
    event_reports: bool,
    /// Where in the current increment a step paused at an event.
    resume: Option<f64>,
    /// The search for a safe state that proves shakedown early (set up at
    /// the first cycle that needs it).
    safe_state: Option<Box<SafeStateSearch>>,
    /// The setup of an earlier run's search for a safe state, for this
    /// run's search to take if it fits ([`Stepper::give_safe_state_setup`]).
    safe_state_setup: Option<Arc<safe_state::Setup>>,
    /// Node lists of the events of reports handed back to
    /// [`Stepper::step_into`], emptied, for the next events to reuse.
    spare_nodes: Vec<Vec<usize>>,
    /// Whether and how far a step takes a straight run of increments.
    runs: StraightRuns,
}

/// Set up the shared pieces of a run once.
///
/// The operators `H` and `|D|` (model.md section 2.2) on the
/// discretisation's `N` nodes, to be shared by every run on the same nodes
/// (e.g. the runs of a sweep, through [`Stepper::with_operators`]).
pub fn operators(disc: &Discretisation) -> Arc<Operators> {
    Arc::new(Operators::new(disc.nodes()))
}

impl Stepper {
    /// The contact in its current state: the load point, the slip `g` at
    /// every node, the slip directions and the tractions `p`, `q`.
    pub fn contact(&self) -> &Contact {
        &self.contact
    }

    /// The contact, to take its cached slip rates to the next run of a
    /// sweep's group (nothing else may change it between increments).
    pub(crate) fn contact_mut(&mut self) -> &mut Contact {
        &mut self.contact
    }

    /// Hand this run the setup of an earlier run's search for a safe
    /// state: its search takes it if it was made for the same cycle,
    /// material and grid (see [`SafeStateSearch::sharing`]).
    pub(crate) fn give_safe_state_setup(&mut self, setup: Arc<safe_state::Setup>) {
        self.safe_state_setup = Some(setup);
    }

    /// The setup of this run's search for a safe state, or the one it was
    /// given if it made none, for the next run of the cycle.
    pub(crate) fn take_safe_state_setup(&mut self) -> Option<Arc<safe_state::Setup>> {
        match &self.safe_state {
            Some(search) => Some(Arc::clone(search.setup())),
            None => self.safe_state_setup.take(),
        }
    }
    /// The steady cycle of eq. (11): centre `A`, `load_factor` λ, `slope`
    /// ψ and `phase` φ (model.md section 5.1).
    pub fn cycle(&self) -> &Cycle {
        &self.cycle
    }
    /// The nodes `N` and the increments per cycle (model.md section 3.3).
    pub fn discretisation(&self) -> &Discretisation {
        &self.disc
    }
    /// The options the run was started with.
    pub fn options(&self) -> &StepOptions {
        &self.options
    }
    /// Where the stepper is on its path: the increment the next
    /// [`Stepper::step`] takes. Not the cycle's phase φ (that is
    /// [`Cycle`]'s field `phase`).
    pub fn phase(&self) -> Phase {
        self.phase
    }
    /// Whether the run is still going, has a steady-state verdict, or has
    /// ended.
    pub fn status(&self) -> &Status {
        &self.status
    }
    /// The completed cycles kept, first to last: their dissipation `W`, net
    /// rotation and per-node slip. All of them unless
    /// [`Stepper::trim_history`] was called (each record's `cycle` says
    /// which cycle it is).
    pub fn history(&self) -> &[CycleRecord] {
        &self.history
    }
    /// Keep the per-node slip of the last `keep` completed cycles only
    /// (never fewer than the [`SETTLE_CYCLES`](super::steady::SETTLE_CYCLES)
    /// `+ 1` that the verdict classifies), so that a run stepped on for
    /// hours holds a bounded amount of memory. While the run is
    /// [`Status::Running`], older cycles keep their number, `W` and
    /// rotation (the cycle cap and the trend of `W` read those), with
    /// `forward` and `backward` emptied; once it has its verdict, nothing
    /// reads them any more and older cycles are dropped altogether. No
    /// verdict, outcome or count of cycles changes. Returns the bytes freed.
    pub fn trim_history(&mut self, keep: usize) -> usize {
        let keep = keep.max(super::steady::SETTLE_CYCLES + 1);
        let end = self.history.len().saturating_sub(keep);
        let slip_bytes = |r: &CycleRecord| {
            std::mem::size_of::<f64>() * (r.forward.capacity() + r.backward.capacity())
        };
        if !matches!(self.status, Status::Running) {
            return self
                .history
                .drain(..end)
                .map(|r| std::mem::size_of::<CycleRecord>() + slip_bytes(&r))
                .sum();
        }
        let mut freed = 0;
        for r in self.history[..end].iter_mut().rev() {
            if r.forward.capacity() == 0 && r.backward.capacity() == 0 {
                // Trimmed by an earlier call, and so is everything before.
                break;
            }
            freed += slip_bytes(r);
            r.forward = Vec::new();
            r.backward = Vec::new();
        }
        freed
    }
    /// The cycle in progress (its dissipation so far, its per-node slip).
    pub fn current_cycle(&self) -> &CycleRecord {
        &self.current
    }
    /// The transient's straight segments.
    pub fn transient(&self) -> &[Segment] {
        &self.transient
    }
    /// Increments committed so far (bisected ones count once).
    pub fn increments(&self) -> usize {
        self.increments
    }
    /// Whether the run has ended (gross slip or separation): further
    /// steps do nothing. A run with a steady-state verdict is not finished;
    /// it can step on through more cycles.
    pub fn is_finished(&self) -> bool {
        matches!(self.status, Status::Ended(_))
    }
    /// The cycle whose start the stepper is at (no increment of it taken),
    /// if it is at one.
    pub fn cycle_start(&self) -> Option<usize> {
        match self.phase {
            Phase::Cycle {
                cycle,
                increment: 0,
            } if self.resume.is_none() => Some(cycle),
            _ => None,
        }
    }

    /// The outcome, once there is one: the steady-state verdict or the end
    /// of the run; `None` while [`Status::Running`].
    pub fn outcome(&self) -> Option<&Outcome> {
        match &self.status {
            Status::Running => None,
            Status::Steady(s) | Status::Ended(s) => Some(s),
        }
    }
    /// `omega t` in the cycle, or `None` in the transient: where the
    /// contact is (inside an increment after a step paused at an event).
    pub fn time(&self) -> Option<f64> {
        self.time_at(self.resume.unwrap_or(0.0))
    }

    /// Stop each step at every entry into slip and every advancing stick,
    /// at the event's exact load point ([`StepReport::partial`]), or not
    /// (the default). The run is the same either way: the next step goes on
    /// along the same straight segment.
    pub fn set_pause_at_events(&mut self, pause: bool) {
        self.contact.set_pause_at_events(pause);
    }

    /// Whether the last step paused inside its increment, at an event.
    pub fn is_inside_increment(&self) -> bool {
        self.resume.is_some()
    }

    /// Record the cycle just completed, move to the next, and give the
    /// verdict if the history now has one.
    fn close_cycle(&mut self, done: CycleRecord, report: &mut StepReport) {
        let cycle = done.cycle;
        report.events.push(Event::CycleCompleted {
            cycle,
            dissipation: done.dissipation,
            rotation: done.rotation,
        });
        self.history.push(done);
        self.runs.refuse_none();
        self.phase = Phase::Cycle {
            cycle: cycle + 1,
            increment: 0,
        };
        if !matches!(self.status, Status::Running) {
            return;
        }
        let verdict = match assess(&self.history, &self.options.convergence()) {
            Some((state, approach)) => self.verdict_of(state, approach),
            None => match self.safe_state_certificate() {
                Some(c) => Verdict::Shakedown(ShakedownProof::SafeState(c)),
                None => return,
            },
        };
        let last = self.history.last().expect("just pushed");
        // A safe state proves that W tends to zero: the steady cycle's W
        // and rotation are zero (the last cycle's W is in the certificate).
        let (dissipation, rotation_per_cycle) = match verdict {
            Verdict::Shakedown(ShakedownProof::SafeState(_)) => (0.0, 0.0),
            _ => (last.dissipation, last.rotation),
        };
        // Cyclic slip and ratchetting carry the levels their cycles approach.
        let (level, steady_rotation) = match verdict {
            Verdict::CyclicSlip | Verdict::Ratchetting { .. } => {
                let state = last.classify();
                (
                    crate::stepping::steady::dissipation_level(&self.history),
                    crate::stepping::steady::steady_rotation(&self.history, state),
                )
            }
            _ => (None, None),
        };
        let outcome = Outcome {
            verdict,
            dissipation,
            cycles: self.history.len(),
            rotation_per_cycle,
            level,
            steady_rotation,
        };
        report.events.push(Event::SteadyStateReached(outcome));
        self.status = Status::Steady(outcome);
    }

    /// The verdict of [`assess`] on the history: the state it found, with
    /// how, and for a run that reached the cap where `W` was heading.
    fn verdict_of(&self, state: SteadyState, approach: Approach) -> Verdict {
        match (state, approach) {
            (SteadyState::Shakedown, Approach::NoSlipCycle) => {
                Verdict::Shakedown(ShakedownProof::NoSlipCycle)
            }
            (SteadyState::Shakedown, _) => Verdict::Shakedown(ShakedownProof::Converged),
            (SteadyState::CyclicSlip, _) => Verdict::CyclicSlip,
            (SteadyState::RatchettingMonotonic, _) => Verdict::Ratchetting { monotonic: true },
            (SteadyState::RatchettingNonMonotonic, _) => Verdict::Ratchetting { monotonic: false },
            // `assess` draws no terminal verdict and stops at the cap only:
            // a run that reached it keeps its last cycle and says where `W`
            // was heading.
            (SteadyState::GrossSlip | SteadyState::Separation | SteadyState::NotConverged, _) => {
                let w: Vec<f64> = self.history.iter().map(|r| r.dissipation).collect();
                Verdict::NotConverged { trend: trend(&w) }
            }
        }
    }

    /// Take a whole cycle from another run of the same case instead of
    /// stepping it: `record` is what that run's cycle did, and `end_slip`
    /// its slip at the cycle's end, to which `shift` (a rigid rotation) is
    /// added. Valid only when this run starts the cycle in the state that
    /// one started it in, up to the rotation (see
    /// [`crate::analysis::sweep`]'s replay of coinciding runs): the cycle
    /// is then the same, and so is everything decided after it (the
    /// verdict, a search for a safe state), which is decided here as after
    /// a cycle stepped. False, doing nothing, unless the stepper is at the
    /// start of cycle `record.cycle` with no verdict.
    pub(crate) fn replay_cycle(
        &mut self,
        record: &CycleRecord,
        end_slip: &[f64],
        shift: f64,
    ) -> bool {
        let at_start =
            matches!(self.phase, Phase::Cycle { cycle, increment: 0 } if cycle == record.cycle);
        if !at_start || !matches!(self.status, Status::Running) || self.resume.is_some() {
            return false;
        }
        let slip: Vec<f64> = end_slip.iter().map(|g| g + shift).collect();
        self.contact.set_slip(&slip);
        self.increments += self.disc.steps_per_cycle();
        self.current = CycleRecord::new(record.cycle + 1, self.contact.nodes());
        self.rotation_at_cycle_start = self.contact.rotation();
        self.close_cycle(record.clone(), &mut StepReport::default());
        true
    }

    /// After a complete cycle without a verdict: shakedown proven by a safe
    /// state near the slip reached (model.md section 6.4), if there is one.
    fn safe_state_certificate(&mut self) -> Option<Certificate> {
        if !self.options.convergence().safe_state() {
            return None;
        }
        let n = self.history.len();
        let last = self.history.last()?;
        // Every node slipped: ratchetting, or on its way to it.
        if last.slipping_nodes().iter().all(|&s| s) {
            return None;
        }
        // A search is worth its cost only while W falls: a quick one after
        // any fall, a full one only after a slow fall (W falling fast, by
        // more than SLOW_FALL a cycle, reaches a cycle without slip, or
        // its level, sooner than a full search pays for itself).
        let w = last.dissipation;
        let fall = match n.checked_sub(2).map(|k| self.history[k].dissipation) {
            Some(before) if w < before && w > safe_state::SLOW_FALL * before => Fall::Slow,
            Some(before) if w < before => Fall::Fast,
            _ => Fall::None,
        };
        if self.safe_state.is_none() && (last.cycle < safe_state::QUICK_FIRST || fall == Fall::None)
        {
            return None;
        }
        let shared = &mut self.safe_state_setup;
        let search = self.safe_state.get_or_insert_with(|| {
            Box::new(SafeStateSearch::sharing(
                shared.take(),
                &self.contact,
                &self.cycle,
                self.disc.steps_per_cycle(),
            ))
        });
        let ops = Arc::clone(self.contact.operators());
        search.check(&self.contact, &ops, last.cycle, last.dissipation, fall)
    }

    /// Run to the steady state (or the end of the run) reporting nothing
    /// on the way: the stepper takes straight runs and reports no events
    /// from here on ([`Stepper::set_straight_runs`],
    /// [`Stepper::set_zone_events`], [`Stepper::set_event_reports`]), then
    /// [`drive`]s with [`Goal::Steady`]. A run that already has its outcome
    /// gives it at once.
    ///
    /// # Errors
    ///
    /// A numerical failure of an increment.
    pub fn run_to_steady(&mut self) -> Result<Outcome, StepError> {
        self.set_zone_events(false);
        self.set_event_reports(false);
        self.set_straight_runs(true);
        // A silent observer never stops the drive: it comes back finished.
        loop {
            if let Driven::Finished(outcome) = drive(self, Goal::Steady, &mut Silent)? {
                return Ok(outcome);
            }
        }
    }

    /// Let each step take a whole straight run of increments (`on`), or
    /// one increment (the default, for a viewer that steps increment by
    /// increment): the rest of a transient segment, or the increments of
    /// the cycle whose load points lie on one chord (all of a half cycle
    /// when `phi = 0`). The path is the same polygon and every event on it
    /// is located exactly either way, at the same load point and `omega t`;
    /// only the stops between events go. [`Stepper::run_to_steady`] takes
    /// straight runs.
    pub fn set_straight_runs(&mut self, on: bool) {
        self.runs.on = on;
    }

    /// Report [`Event::SlipSetChanged`] at every change of the slip set
    /// (the default), or not: the slip-zone topology costs a pass over the
    /// nodes per change, which a run that reads no events need not pay.
    /// Switched back on, the first report describes the change since the
    /// last one reported.
    pub fn set_zone_events(&mut self, on: bool) {
        self.zone_events = on;
    }

    /// Report each entry into slip and each advancing stick as an
    /// [`Event`] (the default), or not: a run that reads no events (a
    /// sweep) need not build them. Terminal events, cycle ends and the
    /// verdict are reported either way.
    pub fn set_event_reports(&mut self, on: bool) {
        self.event_reports = on;
    }

    /// Step until the current cycle ends (or the run ends), returning the
    /// events on the way.
    ///
    /// # Errors
    ///
    /// A numerical failure of an increment.
    pub fn run_to_cycle_end(&mut self) -> Result<Vec<Event>, StepError> {
        let mut events = Vec::new();
        drive(self, Goal::CycleEnd, &mut |_: &Stepper, r: &StepReport| {
            events.extend(r.events.iter().cloned());
            Control::Continue
        })?;
        Ok(events)
    }
}
