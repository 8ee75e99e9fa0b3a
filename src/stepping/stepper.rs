//! The stepper: advances the contact one load increment at a time along a
//! transient and then the steady cycle, and reports what happened as events.
//! The TUI and the batch runs are both consumers of this one type.

use std::f64::consts::PI;
use std::sync::Arc;

use super::driver::{drive, Control, Driven, Goal, Silent};
use super::options::{StepError, StepOptions};
use super::outcome::{GrossSlip, Outcome, Separation, ShakedownProof, Verdict};
use super::report::{AtCenter, Event, Phase, Status, StepReport};
use super::safe_state::{self, Certificate, Fall, SafeStateSearch};
use super::steady::{assess, Approach, CycleRecord, SteadyState};
use super::straight::StraightRuns;
use super::verdict::trend;
use super::zones::{slip_zones, zone_changes, SlipZone};
use crate::contact::{
    Advanced, Contact, ContactEnd, ContactError, ContactEventKind, Operators, SlipDirection,
};
use crate::model::path::{entry_waypoints, segments, Initial, Segment};
use crate::model::{Cycle, Discretisation, LoadPoint, Material};

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
    /// A run from the unloaded state (or the initial slip at `A`) along
    /// `initial`, then the cycle.
    pub fn new(
        material: Material,
        disc: Discretisation,
        initial: &Initial,
        cycle: Cycle,
        options: StepOptions,
    ) -> Self {
        Self::with_operators(operators(&disc), material, disc, initial, cycle, options)
    }

    /// As [`Stepper::new`], with operators `H` and `|D|` already built by
    /// [`operators`] for the same number of nodes, so that runs can share
    /// them.
    ///
    /// An [`Initial::Optimal`] that was not resolved is not an error here:
    /// the first [`Stepper::step`] reports [`StepError::UnresolvedOptimal`].
    pub fn with_operators(
        ops: Arc<Operators>,
        material: Material,
        disc: Discretisation,
        initial: &Initial,
        cycle: Cycle,
        options: StepOptions,
    ) -> Self {
        let mut contact = Contact::new(material, ops);
        let mut unresolved = None;
        let slip = match initial {
            Initial::Slip { slip, .. } => Some(Arc::clone(slip)),
            Initial::Optimal => {
                unresolved = Some(StepError::UnresolvedOptimal);
                None
            }
            _ => None,
        };
        if let Some(slip) = slip {
            contact.set_slip(&slip);
            contact.set_load_elastic(cycle.center());
        }
        let mut waypoints = initial.waypoints_to(cycle.center());
        waypoints.push(cycle.start());
        let mut stepper = Self::from_contact(contact, &waypoints, cycle, disc, options);
        stepper.unresolved = unresolved;
        stepper
    }

    /// Continue from a prepared contact (e.g. the state at `A`, which does
    /// not depend on `lambda`) through `waypoints` into the cycle.
    pub fn from_contact(
        contact: Contact,
        waypoints: &[LoadPoint],
        cycle: Cycle,
        disc: Discretisation,
        options: StepOptions,
    ) -> Self {
        let mut w = vec![contact.load()];
        w.extend_from_slice(waypoints);
        let transient = segments(&w, disc.transient_step());
        let nodes = contact.nodes();
        let rotation = contact.rotation();
        let contact_dirs = contact.directions().to_vec();
        let phase = if transient.is_empty() {
            Phase::Cycle {
                cycle: 1,
                increment: 0,
            }
        } else {
            Phase::Transient {
                segment: 0,
                increment: 0,
            }
        };
        let steps = disc.steps_per_cycle();
        let cycle_points = (0..=steps)
            .map(|i| cycle.at(cycle_angle(i as f64, steps)))
            .collect();
        Self {
            contact,
            transient,
            cycle,
            cycle_points,
            disc,
            options,
            phase,
            current: CycleRecord::new(1, nodes),
            rotation_at_cycle_start: rotation,
            history: Vec::new(),
            status: Status::Running,
            increments: 0,
            unresolved: None,
            zones: slip_zones(&contact_dirs),
            zone_dirs: contact_dirs,
            zone_events: true,
            event_reports: true,
            resume: None,
            spare_nodes: Vec::new(),
            safe_state: None,
            safe_state_setup: None,
            runs: StraightRuns::new(steps),
        }
    }

    /// The contact after the transient up to the cycle centre `A` (the
    /// `A -> C` entry not included): it depends on the initial path only.
    ///
    /// It is [`AtCenter::Ready`] with the contact at `A`, or
    /// [`AtCenter::Ended`] when the transient itself ended the run (gross
    /// slip or separation before `A`).
    ///
    /// # Errors
    ///
    /// [`StepError::NotSettled`] when an increment of the transient fails
    /// numerically; [`StepError::UnresolvedOptimal`] for an
    /// [`Initial::Optimal`] that was not resolved; [`StepError::Param`] for
    /// a centre out of range.
    pub fn prepare_at_center(
        ops: Arc<Operators>,
        material: Material,
        disc: Discretisation,
        initial: &Initial,
        center: LoadPoint,
        options: StepOptions,
    ) -> Result<AtCenter, StepError> {
        let dummy = Cycle::new(center, 0.0, 0.0, 0.0)?;
        let mut s = Self::with_operators(ops, material, disc, initial, dummy, options);
        s.zone_events = false;
        s.event_reports = false;
        s.runs.on = true;
        // The dummy cycle starts at A, so the transient ends exactly there.
        drive(&mut s, Goal::TransientEnd, &mut Silent)?;
        if let Status::Ended(outcome) = s.status {
            return Ok(AtCenter::Ended(outcome));
        }
        Ok(AtCenter::Ready(Box::new(s.contact)))
    }

    /// Start the cycle from a contact prepared at the centre `A`.
    pub fn from_center(
        contact: Contact,
        cycle: Cycle,
        disc: Discretisation,
        options: StepOptions,
    ) -> Self {
        Self::from_contact(contact, &entry_waypoints(&cycle), cycle, disc, options)
    }

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

    /// `omega t` at parameter `s` of the current increment, or `None` in
    /// the transient.
    fn time_at(&self, s: f64) -> Option<f64> {
        match self.phase {
            Phase::Transient { .. } => None,
            Phase::Cycle { increment, .. } => {
                let (m, r) = self.runs.within(&self.cycle_points, increment, s);
                Some(cycle_angle(m as f64 + r, self.disc.steps_per_cycle()))
            }
        }
    }

    /// Increments the next step takes: the rest of the transient segment
    /// or of the straight run of the cycle when [`Stepper::set_straight_runs`]
    /// asked for it, else 1.
    fn next_span(&mut self) -> usize {
        if self.resume.is_some() || self.contact.pauses_at_events() {
            return 1;
        }
        match self.phase {
            Phase::Transient { segment, increment } => self
                .runs
                .span_in_segment(increment, self.transient[segment].increments),
            Phase::Cycle { increment, .. } => {
                self.runs.span_in_cycle(&self.cycle_points, increment)
            }
        }
    }

    /// The load point of a parameter `s` in `[0, 1]` of the current increment.
    fn point(&self, s: f64) -> LoadPoint {
        match self.phase {
            Phase::Transient { segment, increment } => {
                let seg = &self.transient[segment];
                seg.at((increment as f64 + s * self.runs.span as f64) / seg.increments as f64)
            }
            Phase::Cycle { increment, .. } if self.runs.span > 1 => {
                // A straight run: its chord.
                let (a, b) = (
                    self.cycle_points[increment],
                    self.cycle_points[increment + self.runs.span],
                );
                if s == 1.0 {
                    b
                } else {
                    a.lerp(b, s)
                }
            }
            Phase::Cycle { increment, .. } => {
                // The ends of an increment from the table (`increment + s`
                // is then a whole number, as in the table).
                let end = if s == 0.0 {
                    self.cycle_points.get(increment)
                } else if s == 1.0 {
                    self.cycle_points.get(increment + 1)
                } else {
                    None
                };
                let steps = self.disc.steps_per_cycle();
                end.copied()
                    .unwrap_or_else(|| self.cycle.at(cycle_angle(increment as f64 + s, steps)))
            }
        }
    }

    fn phase_label(&self) -> String {
        match self.phase {
            Phase::Transient { segment, increment } => {
                format!(
                    "transient segment {}, increment {}",
                    segment + 1,
                    increment + 1
                )
            }
            Phase::Cycle { cycle, increment } => {
                format!("cycle {cycle}, increment {}", increment + 1)
            }
        }
    }

    /// Advance one increment, or the straight run of increments from here
    /// if [`Stepper::set_straight_runs`] asked for it. Does nothing once the
    /// run has ended.
    ///
    /// Gross slip and separation are not errors: they end the run with
    /// [`Event::GrossSlip`] or [`Event::Separation`] in the report and
    /// [`Status::Ended`].
    ///
    /// # Errors
    ///
    /// [`StepError::NotSettled`] when the active set of the increment does
    /// not settle even with the increment bisected; every call reports
    /// [`StepError::UnresolvedOptimal`] when the run was set up with an
    /// [`Initial::Optimal`] that was not resolved.
    pub fn step(&mut self) -> Result<StepReport, StepError> {
        let mut report = StepReport::default();
        self.step_into(&mut report).map(|()| report)
    }

    /// [`Stepper::step`] into `report`, which is cleared first: a loop that
    /// hands the same report back each time (as [`drive`] does) allocates
    /// nothing per step once the run is under way, its buffers and the
    /// events' node lists being reused.
    ///
    /// # Errors
    ///
    /// As [`Stepper::step`].
    ///
    /// [`drive`]: super::drive
    pub fn step_into(&mut self, report: &mut StepReport) -> Result<(), StepError> {
        self.recycle(report);
        self.step_body(report)
    }

    /// Empty `report`, keeping its buffers and its events' node lists.
    fn recycle(&mut self, report: &mut StepReport) {
        for event in report.events.drain(..) {
            if let Event::AdvancingStick { mut nodes, .. } | Event::SlipEntry { mut nodes, .. } =
                event
            {
                nodes.clear();
                self.spare_nodes.push(nodes);
            }
        }
        let mut newly_stuck = std::mem::take(&mut report.newly_stuck);
        newly_stuck.clear();
        *report = StepReport {
            events: std::mem::take(&mut report.events),
            newly_stuck,
            ..StepReport::default()
        };
    }

    fn step_body(&mut self, report: &mut StepReport) -> Result<(), StepError> {
        if let Some(e) = &self.unresolved {
            return Err(e.clone());
        }
        if self.is_finished() {
            return Ok(());
        }
        let events_before = report.events.len();
        self.runs.span = self.next_span();
        let start = self.resume.take().unwrap_or(0.0);
        let result = if self.runs.span > 1 {
            // A straight run: no bisection of it (a failure is taken one
            // increment at a time below).
            self.contact.set_segment_increments(self.runs.span);
            let result = self.advance(start, 1.0, self.options.failure_bisections, report);
            self.contact.set_segment_increments(1);
            result
        } else {
            self.advance(start, 1.0, 0, report)
        };
        match result {
            Ok(Progress::Done) => {}
            Err(ContactError::NotSettled { .. }) if self.runs.span > 1 => {
                // The rest of the run one increment at a time, from the
                // increment where the contact stopped.
                let reached = self.contact.last_increment().reached;
                let (from, increment, r) = match self.phase {
                    Phase::Transient { increment, .. } => {
                        // Equal increments.
                        let at = reached * self.runs.span as f64;
                        let m = (at.floor() as usize).min(self.runs.span - 1);
                        (increment, increment + m, at - m as f64)
                    }
                    Phase::Cycle { increment, .. } => {
                        let (m, r) = self.runs.within(&self.cycle_points, increment, reached);
                        (increment, m, r)
                    }
                };
                self.runs.refuse_below(from + self.runs.span);
                self.increments += increment - from;
                match &mut self.phase {
                    Phase::Transient { increment: i, .. } | Phase::Cycle { increment: i, .. } => {
                        *i = increment
                    }
                }
                self.runs.span = 1;
                self.resume = (r > 0.0).then_some(r.min(1.0));
                self.after_increment(events_before, report);
                return Ok(());
            }
            Ok(Progress::Paused(at)) => {
                self.resume = Some(at);
                report.partial = Some(at);
                self.after_increment(events_before, report);
                return Ok(());
            }
            Err(ContactError::NotSettled { load, .. }) => {
                return Err(StepError::NotSettled {
                    load,
                    phase: self.phase_label(),
                    bisections: self.options.failure_bisections,
                })
            }
            // Gross slip and separation are outcomes, not failures.
            Ok(Progress::Ended(end, at)) => {
                self.end(end, at, report);
                return Ok(());
            }
        }
        self.increments += self.runs.span;
        self.after_increment(events_before, report);
        self.move_on(report);
        self.runs.span = 1;
        Ok(())
    }

    /// What a step reports once the contact has got where it goes: the
    /// sub-increments of advancing stick, the slip-zone changes.
    fn after_increment(&mut self, events_before: usize, report: &mut StepReport) {
        for event in &mut report.events[events_before..] {
            if let Event::AdvancingStick { substeps, .. } = event {
                *substeps = report.substeps;
            }
        }
        if self.zone_events
            && report.slip_set_changed
            && self.contact.directions() != self.zone_dirs.as_slice()
        {
            let dirs = self.contact.directions();
            let now = slip_zones(dirs);
            report.events.push(Event::SlipSetChanged {
                slipping: dirs.iter().filter(|d| d.is_slipping()).count(),
                zones: now.len(),
                changes: zone_changes(&self.zones, &now, dirs.len()),
            });
            self.zone_dirs.clone_from_slice(dirs);
            self.zones = now;
        }
        if !report.newly_stuck.is_empty() {
            report.newly_stuck.sort_unstable();
            report.newly_stuck.dedup();
        }
    }

    /// Advance the increment from parameter `s0` to `s1`. The contact
    /// locates every event on the way exactly (entry into slip, advancing
    /// stick, gross slip, separation); only where its rate problem does not
    /// settle is the rest of the increment bisected, as a last resort. A
    /// physical end comes back with the parameter where it happened.
    fn advance(
        &mut self,
        s0: f64,
        s1: f64,
        fail_depth: usize,
        report: &mut StepReport,
    ) -> Result<Progress, ContactError> {
        let target = self.point(s1);
        let result = self.contact.advance(target);
        let reached = s0 + self.contact.last_increment().reached * (s1 - s0);
        self.record(s0, s1, report);
        match result {
            Ok(Advanced::Reached) => Ok(Progress::Done),
            Ok(Advanced::Ended(end)) => Ok(Progress::Ended(end, reached)),
            Ok(Advanced::Paused) => Ok(Progress::Paused(reached)),
            Err(ContactError::NotSettled { .. })
                if fail_depth < self.options.failure_bisections && reached < s1 =>
            {
                let mid = 0.5 * (reached + s1);
                match self.advance(reached, mid, fail_depth + 1, report)? {
                    Progress::Done => self.advance(mid, s1, fail_depth + 1, report),
                    stopped => Ok(stopped),
                }
            }
            Err(e) => Err(e),
        }
    }

    /// Collect what the contact's last advance (parameters `s0` to `s1` of
    /// the increment) did: dissipation, per-node slip, events.
    fn record(&mut self, s0: f64, s1: f64, report: &mut StepReport) {
        let inc = self.contact.last_increment();
        report.substeps += inc.segments;
        report.dissipation += inc.dissipation;
        report.factorisations += inc.factorisations;
        report.iterations += inc.rate_solves;
        report.slip_set_changed |= inc.set_changed;
        let events = if self.event_reports {
            &inc.events[..]
        } else {
            &[]
        };
        for ev in events {
            let time = self.time_at(s0 + ev.fraction * (s1 - s0));
            // A new list has room for every node, so that no list grows.
            let n = self.contact.nodes();
            let mut nodes = self
                .spare_nodes
                .pop()
                .unwrap_or_else(|| Vec::with_capacity(n));
            nodes.extend_from_slice(&ev.nodes);
            report.events.push(match ev.kind {
                ContactEventKind::AdvancingStick => {
                    report.newly_stuck.extend_from_slice(&nodes);
                    Event::AdvancingStick {
                        nodes,
                        substeps: 0,
                        time,
                        load: ev.load,
                    }
                }
                ContactEventKind::SlipEntry => Event::SlipEntry {
                    nodes,
                    time,
                    load: ev.load,
                },
            });
        }
        if matches!(self.phase, Phase::Cycle { .. }) {
            self.current.dissipation += inc.dissipation;
            if inc.slipped {
                for (j, (f, b)) in inc.forward.iter().zip(&inc.backward).enumerate() {
                    self.current.forward[j] += f;
                    self.current.backward[j] += b;
                }
            }
        }
    }

    /// The run ends at parameter `at` of the current increment, where the
    /// contact is and the error's load point is.
    fn end(&mut self, end: ContactEnd, at: f64, report: &mut StepReport) {
        let time = self.time_at(at);
        let (verdict, event) = match end {
            ContactEnd::GrossSlip { load } => {
                let end = GrossSlip { load, time };
                (Verdict::GrossSlip(end), Event::GrossSlip(end))
            }
            ContactEnd::Separation { load, theta, .. } => {
                let end = Separation { load, time, theta };
                (Verdict::Separation(end), Event::Separation(end))
            }
        };
        let last = self.history.last();
        let outcome = Outcome {
            verdict,
            dissipation: last.map_or(0.0, |r| r.dissipation),
            cycles: last.map_or(0, |r| r.cycle),
            rotation_per_cycle: last.map_or(0.0, |r| r.rotation),
            level: None,
            steady_rotation: None,
        };
        report.events.push(event);
        report.events.push(Event::SteadyStateReached(outcome));
        self.status = Status::Ended(outcome);
    }

    /// The initial path has just reached the cycle centre `A`. A sweep
    /// starts every `lambda` and `phi` of an initial path from one contact
    /// prepared at `A` ([`Stepper::prepare_at_center`]), cloned, and a
    /// clone keeps the state but not the solver's caches (the slip rates of
    /// the sets met so far, the factors of the reduced inverse). Those
    /// decide only the round-off of the rates, not what the rates are, but
    /// the round-off is then not the same as in a run that kept them.
    /// Dropping them here too, the same way, makes a run from `O` give the
    /// very numbers of the sweep's row for the same case: `run`, `sweep`
    /// and the explorer agree to the last digit.
    fn arrived_at_center(&mut self) {
        self.contact = self.contact.clone();
    }

    /// Advance the position on the path, closing cycles as they end.
    fn move_on(&mut self, report: &mut StepReport) {
        match self.phase {
            Phase::Transient { segment, increment } => {
                let next = increment + self.runs.span;
                if next >= self.transient[segment].increments
                    && self.transient[segment].to == self.cycle.center()
                {
                    self.arrived_at_center();
                }
                if next < self.transient[segment].increments {
                    self.phase = Phase::Transient {
                        segment,
                        increment: next,
                    };
                } else if segment + 1 < self.transient.len() {
                    self.runs.refuse_none();
                    self.phase = Phase::Transient {
                        segment: segment + 1,
                        increment: 0,
                    };
                } else {
                    self.runs.refuse_none();
                    self.phase = Phase::Cycle {
                        cycle: 1,
                        increment: 0,
                    };
                    self.rotation_at_cycle_start = self.contact.rotation();
                    report.events.push(Event::TransientFinished);
                }
            }
            Phase::Cycle { cycle, increment } => {
                let next = increment + self.runs.span;
                if next < self.disc.steps_per_cycle() {
                    self.phase = Phase::Cycle {
                        cycle,
                        increment: next,
                    };
                    return;
                }
                let rotation = self.contact.rotation();
                let mut done = std::mem::replace(
                    &mut self.current,
                    CycleRecord::new(cycle + 1, self.contact.nodes()),
                );
                done.rotation = rotation - self.rotation_at_cycle_start;
                self.rotation_at_cycle_start = rotation;
                self.close_cycle(done, report);
            }
        }
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
        let verdict = match assess(&self.history, &self.options.convergence) {
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
                    super::steady::dissipation_level(&self.history),
                    super::steady::steady_rotation(&self.history, state),
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
        if !self.options.convergence.safe_state {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn stepper() -> Stepper {
        Stepper::new(
            Material::paper(),
            Discretisation::new(64, 200).unwrap(),
            &Initial::Direct,
            Cycle::paper(5.5, 0.0).unwrap(),
            StepOptions::default(),
        )
    }

    /// The events' `omega t` and load points, in order.
    fn events(r: &StepReport, into: &mut Vec<(Option<f64>, LoadPoint)>) {
        for e in &r.events {
            if let Event::AdvancingStick { time, load, .. } | Event::SlipEntry { time, load, .. } =
                e
            {
                into.push((*time, *load));
            }
        }
    }

    #[test]
    fn a_straight_run_that_does_not_settle_goes_on_one_increment_at_a_time() {
        let mut plain = stepper();
        let mut e1 = Vec::new();
        drive(
            &mut plain,
            Goal::Steady,
            &mut |_: &Stepper, r: &StepReport| {
                events(r, &mut e1);
                Control::Continue
            },
        )
        .unwrap();
        let a = plain.outcome().cloned().unwrap();
        // Each straight run gives up at its first event: the stepper takes
        // the rest of it one increment at a time, from that event.
        let mut refused = stepper();
        refused.contact.refuse_runs = true;
        refused.set_straight_runs(true);
        let (mut inside, mut steps, mut e2) = (0, 0, Vec::new());
        drive(
            &mut refused,
            Goal::Steady,
            &mut |s: &Stepper, r: &StepReport| {
                steps += 1;
                inside += usize::from(s.is_inside_increment());
                events(r, &mut e2);
                Control::Continue
            },
        )
        .unwrap();
        let b = refused.outcome().cloned().unwrap();
        assert!(
            inside > 10,
            "{inside} of {steps} steps stopped inside an increment"
        );
        assert!(steps < refused.increments(), "{steps} steps");
        assert_eq!((a.state(), a.cycles), (b.state(), b.cycles));
        assert_eq!(plain.increments(), refused.increments());
        let rel = (a.dissipation - b.dissipation).abs() / a.dissipation;
        assert!(rel < 1e-9, "W {} vs {}", a.dissipation, b.dissipation);
        // The same events at the same instants and load points.
        assert_eq!(e1.len(), e2.len());
        for ((t1, l1), (t2, l2)) in e1.iter().zip(&e2) {
            if let (Some(t1), Some(t2)) = (t1, t2) {
                assert!((t1 - t2).abs() < 1e-9, "{t1} vs {t2}");
            }
            assert!(l1.distance(*l2) < 1e-9, "{l1} vs {l2}");
        }
    }
}
