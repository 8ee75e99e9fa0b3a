//! The stepper: advances the contact one load increment at a time along a
//! transient and then the steady cycle, and reports what happened as events.
//! The TUI and the batch runs are both consumers of this one type.

use std::f64::consts::PI;
use std::sync::Arc;

use serde::Serialize;

use crate::contact::{Contact, ContactError, Operators, SlipDirection, Trial};
use crate::params::{Cycle, Discretisation, LoadPoint, Material};
use crate::path::{entry_waypoints, segments, Initial, Segment};
use crate::steady::{assess, Approach, Convergence, CycleRecord, SteadyState};
use crate::verdict::{trend, Trend};

/// A numerical failure of the stepper. Physical end states (gross slip,
/// separation) are not errors: they are outcomes.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    #[error(
        "the active set did not settle at load point {load} ({phase}), even with the increment bisected {bisections} times"
    )]
    NotSettled {
        load: LoadPoint,
        phase: String,
        bisections: usize,
    },
    /// The `optimal` initial slip could not be computed (model.md section 7).
    #[error("initial path 'optimal': {0}")]
    Initial(#[from] crate::limit::LimitError),
}

/// Options of the stepper.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepOptions {
    /// Bisections of an increment in which a slip node sticks again
    /// (advancing stick): the locked-in slip there is history.
    pub stick_bisections: usize,
    /// Bisections of an increment whose active set does not settle.
    pub failure_bisections: usize,
    pub convergence: Convergence,
}

impl Default for StepOptions {
    fn default() -> Self {
        Self {
            stick_bisections: 1,
            failure_bisections: 12,
            convergence: Convergence::default(),
        }
    }
}

/// Where the stepper is on its path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// In the initial transient: segment index and increment within it.
    Transient { segment: usize, increment: usize },
    /// In cycle `cycle` (1-based), `increment` increments done.
    Cycle { cycle: usize, increment: usize },
}

/// Something the stepper observed during one step.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "kebab-case")]
pub enum Event {
    /// The set of slipping nodes or their directions changed.
    SlipSetChanged { slipping: usize, zones: usize },
    /// Nodes that slipped stuck again; the increment was cut into
    /// `substeps` sub-increments to resolve the slip locked in there.
    AdvancingStick { nodes: Vec<usize>, substeps: usize },
    /// The transient is over: the next step is the first of cycle 1.
    TransientFinished,
    /// A cycle ended.
    CycleCompleted {
        cycle: usize,
        dissipation: f64,
        rotation: f64,
    },
    /// The steady state was reached and classified.
    SteadyStateReached(Summary),
    /// The whole interface slides: the run ends here.
    GrossSlip { load: LoadPoint, time: Option<f64> },
    /// The pressure went negative: the run ends here.
    Separation {
        load: LoadPoint,
        time: Option<f64>,
        theta: f64,
    },
}

/// The outcome of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub state: SteadyState,
    pub approach: Approach,
    /// `W` of the last complete cycle (model.md normalisation).
    pub dissipation: f64,
    /// Complete cycles run.
    pub cycles: usize,
    /// Net rigid rotation of the last cycle.
    pub rotation_per_cycle: f64,
    /// Where gross slip or separation happened.
    pub terminal_load: Option<LoadPoint>,
    /// `omega t` of the terminal point, when it was in the cycle.
    pub terminal_time: Option<f64>,
    /// Node angle of separation.
    pub terminal_theta: Option<f64>,
    /// For a `not-converged` run: the trend of `W` over the last cycles and
    /// an estimate of its limit.
    pub trend: Option<Trend>,
}

/// What one call to [`Stepper::step`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepReport {
    pub events: Vec<Event>,
    /// Sub-increments taken (1 unless the increment was bisected).
    pub substeps: usize,
    /// Dissipation of this increment.
    pub dissipation: f64,
    /// Nodes that went from slip to stick during this step.
    pub newly_stuck: Vec<usize>,
    /// LU factorisations computed during this step.
    pub factorisations: usize,
    /// Active-set iterations during this step (discarded trials included).
    pub iterations: usize,
}

/// The run's status.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    Running,
    /// Classified; stepping may continue through further cycles.
    Steady(Summary),
    /// Gross slip or separation: no further steps are possible.
    Ended(Summary),
}

/// Advances a contact along `transient` and then the steady `cycle`.
#[derive(Debug, Clone)]
pub struct Stepper {
    contact: Contact,
    transient: Vec<Segment>,
    cycle: Cycle,
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
}

/// Set up the shared pieces of a run once.
pub fn operators(disc: &Discretisation) -> Arc<Operators> {
    // The reduced systems are small; faer's thread pool would only add
    // overhead, and sweeps are already parallel over runs.
    faer::set_global_parallelism(faer::Par::Seq);
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
            // The optimal slip of the lambda_2 problem for this cycle.
            Initial::Optimal => match crate::limit::shakedown_limit(
                &material,
                cycle.center,
                cycle.slope,
                cycle.phase,
                &disc,
                crate::limit::DEFAULT_SAMPLES,
            ) {
                Ok(limit) => Some(Arc::new(limit.slip)),
                Err(e) => {
                    unresolved = Some(StepError::Initial(e));
                    None
                }
            },
            _ => None,
        };
        if let Some(slip) = slip {
            contact.set_slip(&slip);
            contact.set_load_elastic(cycle.center);
        }
        let mut waypoints = initial.waypoints_to(cycle.center);
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
        Self {
            contact,
            transient,
            cycle,
            disc,
            options,
            phase,
            current: CycleRecord::new(1, nodes),
            rotation_at_cycle_start: rotation,
            history: Vec::new(),
            status: Status::Running,
            increments: 0,
            unresolved: None,
        }
    }

    /// The contact after the transient up to the cycle centre `A` (the
    /// `A -> C` entry not included): it depends on the initial path only.
    pub fn prepare_at_center(
        ops: Arc<Operators>,
        material: Material,
        disc: Discretisation,
        initial: &Initial,
        center: LoadPoint,
        options: StepOptions,
    ) -> Result<Result<Contact, Summary>, StepError> {
        let dummy = Cycle::new(center, 0.0, 0.0, 0.0).expect("a zero cycle at a valid centre");
        let mut s = Self::with_operators(ops, material, disc, initial, dummy, options);
        // The dummy cycle starts at A, so the transient ends exactly there.
        while matches!(s.phase, Phase::Transient { .. }) {
            s.step()?;
            if let Status::Ended(summary) = &s.status {
                return Ok(Err(summary.clone()));
            }
        }
        Ok(Ok(s.contact))
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

    pub fn contact(&self) -> &Contact {
        &self.contact
    }
    pub fn cycle(&self) -> &Cycle {
        &self.cycle
    }
    pub fn discretisation(&self) -> &Discretisation {
        &self.disc
    }
    pub fn options(&self) -> &StepOptions {
        &self.options
    }
    pub fn phase(&self) -> Phase {
        self.phase
    }
    pub fn status(&self) -> &Status {
        &self.status
    }
    pub fn history(&self) -> &[CycleRecord] {
        &self.history
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
    pub fn is_finished(&self) -> bool {
        matches!(self.status, Status::Ended(_))
    }
    pub fn summary(&self) -> Option<&Summary> {
        match &self.status {
            Status::Running => None,
            Status::Steady(s) | Status::Ended(s) => Some(s),
        }
    }
    /// `omega t` in the cycle, or `None` in the transient.
    pub fn time(&self) -> Option<f64> {
        match self.phase {
            Phase::Transient { .. } => None,
            Phase::Cycle { increment, .. } => {
                Some(2.0 * PI * increment as f64 / self.disc.steps_per_cycle() as f64)
            }
        }
    }

    /// The load point of a parameter `s` in `[0, 1]` of the current increment.
    fn point(&self, s: f64) -> LoadPoint {
        match self.phase {
            Phase::Transient { segment, increment } => {
                let seg = &self.transient[segment];
                seg.at((increment as f64 + s) / seg.increments as f64)
            }
            Phase::Cycle { increment, .. } => {
                let steps = self.disc.steps_per_cycle() as f64;
                self.cycle.at(2.0 * PI * (increment as f64 + s) / steps)
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

    /// Advance one increment. Does nothing once the run has ended.
    pub fn step(&mut self) -> Result<StepReport, StepError> {
        let mut report = StepReport::default();
        if let Some(e) = &self.unresolved {
            return Err(e.clone());
        }
        if self.is_finished() {
            return Ok(report);
        }
        let before: Vec<SlipDirection> = self.contact.directions().to_vec();
        match self.advance(0.0, 1.0, 0, 0, &mut report) {
            Ok(()) => {}
            Err(ContactError::NotSettled { load, .. }) => {
                return Err(StepError::NotSettled {
                    load,
                    phase: self.phase_label(),
                    bisections: self.options.failure_bisections,
                })
            }
            Err(e) => {
                self.end(e, &mut report);
                return Ok(report);
            }
        }
        self.increments += 1;
        if before != self.contact.directions() {
            let dirs = self.contact.directions();
            report.events.push(Event::SlipSetChanged {
                slipping: dirs.iter().filter(|d| d.is_slipping()).count(),
                zones: slip_zones(dirs).len(),
            });
        }
        if !report.newly_stuck.is_empty() {
            report.newly_stuck.sort_unstable();
            report.newly_stuck.dedup();
            report.events.push(Event::AdvancingStick {
                nodes: report.newly_stuck.clone(),
                substeps: report.substeps,
            });
        }
        self.move_on(&mut report);
        Ok(report)
    }

    /// Solve the increment between parameters `s0` and `s1`, bisecting on
    /// advancing stick and where the active set does not settle.
    fn advance(
        &mut self,
        s0: f64,
        s1: f64,
        stick_depth: usize,
        fail_depth: usize,
        report: &mut StepReport,
    ) -> Result<(), ContactError> {
        let target = self.point(s1);
        match self.contact.solve(target) {
            Ok(trial) => {
                report.factorisations += trial.factorisations;
                report.iterations += trial.iterations;
                let stuck = trial.advancing_stick(self.contact.directions());
                if !stuck.is_empty() && stick_depth < self.options.stick_bisections {
                    let mid = 0.5 * (s0 + s1);
                    self.advance(s0, mid, stick_depth + 1, fail_depth, report)?;
                    return self.advance(mid, s1, stick_depth + 1, fail_depth, report);
                }
                report.newly_stuck.extend(stuck);
                self.record(trial, report);
                Ok(())
            }
            Err(ContactError::NotSettled { .. })
                if fail_depth < self.options.failure_bisections =>
            {
                let mid = 0.5 * (s0 + s1);
                self.advance(s0, mid, stick_depth, fail_depth + 1, report)?;
                self.advance(mid, s1, stick_depth, fail_depth + 1, report)
            }
            Err(e) => Err(e),
        }
    }

    fn record(&mut self, trial: Trial, report: &mut StepReport) {
        report.substeps += 1;
        report.dissipation += trial.dissipation;
        if matches!(self.phase, Phase::Cycle { .. }) {
            self.current.dissipation += trial.dissipation;
            for (j, &d) in trial.slip_increment.iter().enumerate() {
                if d > 0.0 {
                    self.current.forward[j] += d;
                } else if d < 0.0 {
                    self.current.backward[j] -= d;
                }
            }
        }
        self.contact.commit(trial);
    }

    fn end(&mut self, error: ContactError, report: &mut StepReport) {
        let time = self.time();
        let (state, load, theta, event) = match error {
            ContactError::GrossSlip { load } => (
                SteadyState::GrossSlip,
                load,
                None,
                Event::GrossSlip { load, time },
            ),
            ContactError::Separation { load, theta, .. } => (
                SteadyState::Separation,
                load,
                Some(theta),
                Event::Separation { load, time, theta },
            ),
            ContactError::NotSettled { .. } => unreachable!("handled by step"),
        };
        let last = self.history.last();
        let summary = Summary {
            state,
            approach: Approach::Terminal,
            dissipation: last.map_or(0.0, |r| r.dissipation),
            cycles: self.history.len(),
            rotation_per_cycle: last.map_or(0.0, |r| r.rotation),
            terminal_load: Some(load),
            terminal_time: time,
            terminal_theta: theta,
            trend: None,
        };
        report.events.push(event);
        report
            .events
            .push(Event::SteadyStateReached(summary.clone()));
        self.status = Status::Ended(summary);
    }

    /// Advance the position on the path, closing cycles as they end.
    fn move_on(&mut self, report: &mut StepReport) {
        match self.phase {
            Phase::Transient { segment, increment } => {
                let next = increment + 1;
                if next < self.transient[segment].increments {
                    self.phase = Phase::Transient {
                        segment,
                        increment: next,
                    };
                } else if segment + 1 < self.transient.len() {
                    self.phase = Phase::Transient {
                        segment: segment + 1,
                        increment: 0,
                    };
                } else {
                    self.phase = Phase::Cycle {
                        cycle: 1,
                        increment: 0,
                    };
                    self.rotation_at_cycle_start = self.contact.rotation();
                    report.events.push(Event::TransientFinished);
                }
            }
            Phase::Cycle { cycle, increment } => {
                let next = increment + 1;
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
                report.events.push(Event::CycleCompleted {
                    cycle,
                    dissipation: done.dissipation,
                    rotation: done.rotation,
                });
                self.history.push(done);
                self.phase = Phase::Cycle {
                    cycle: cycle + 1,
                    increment: 0,
                };
                if matches!(self.status, Status::Running) {
                    if let Some((state, approach)) =
                        assess(&self.history, &self.options.convergence)
                    {
                        let last = self.history.last().expect("just pushed");
                        // A run that reached the cap keeps its last cycle
                        // and says where `W` was heading.
                        let trend = if approach == Approach::Cap {
                            let w: Vec<f64> = self.history.iter().map(|r| r.dissipation).collect();
                            trend(&w)
                        } else {
                            None
                        };
                        let summary = Summary {
                            state,
                            approach,
                            dissipation: last.dissipation,
                            cycles: self.history.len(),
                            rotation_per_cycle: last.rotation,
                            terminal_load: None,
                            terminal_time: None,
                            terminal_theta: None,
                            trend,
                        };
                        report
                            .events
                            .push(Event::SteadyStateReached(summary.clone()));
                        self.status = Status::Steady(summary);
                    }
                }
            }
        }
    }

    /// Step until the steady state is reached (or the run ends).
    pub fn run_to_steady(&mut self) -> Result<Summary, StepError> {
        while matches!(self.status, Status::Running) {
            self.step()?;
        }
        Ok(self.summary().cloned().expect("not running"))
    }

    /// Step until the current cycle ends (or the run ends).
    pub fn run_to_cycle_end(&mut self) -> Result<Vec<Event>, StepError> {
        let mut events = Vec::new();
        let target = self.history.len() + 1;
        while !self.is_finished() && self.history.len() < target {
            events.extend(self.step()?.events);
        }
        Ok(events)
    }
}

/// Contiguous runs of slipping nodes round the circle, as
/// `(first, length, direction)`; a run may wrap through node 0. A change of
/// direction starts a new zone.
pub fn slip_zones(dirs: &[SlipDirection]) -> Vec<(usize, usize, SlipDirection)> {
    let n = dirs.len();
    if n == 0 {
        return Vec::new();
    }
    if dirs.iter().all(|d| *d == dirs[0]) {
        return if dirs[0].is_slipping() {
            vec![(0, n, dirs[0])]
        } else {
            Vec::new()
        };
    }
    // Start scanning just after a boundary so no zone is split by wrap-around.
    let start = (0..n)
        .find(|&j| dirs[j] != dirs[(j + n - 1) % n])
        .expect("not all equal");
    let mut zones = Vec::new();
    let mut j = 0;
    while j < n {
        let idx = (start + j) % n;
        let d = dirs[idx];
        let mut len = 1;
        while j + len < n && dirs[(start + j + len) % n] == d {
            len += 1;
        }
        if d.is_slipping() {
            zones.push((idx, len, d));
        }
        j += len;
    }
    zones
}

#[cfg(test)]
mod tests {
    use super::*;
    use SlipDirection::*;

    #[test]
    fn zones_wrap_round() {
        let d = [Forward, Stick, Stick, Forward, Forward];
        assert_eq!(slip_zones(&d), vec![(3, 3, Forward)]);
        let d = [Forward, Backward, Stick, Stick];
        assert_eq!(slip_zones(&d).len(), 2);
        assert!(slip_zones(&[Stick; 4]).is_empty());
        assert_eq!(slip_zones(&[Forward; 4]), vec![(0, 4, Forward)]);
    }
}
