//! One step of the stepper: the load points and times of the increment
//! (or straight run) under way, the contact's advance along it with the
//! bisection of a failure, what the step reports, and the move to the next
//! increment.

use super::*;

impl Stepper {
    /// `omega t` at parameter `s` of the current increment, or `None` in
    /// the transient.
    pub(super) fn time_at(&self, s: f64) -> Option<f64> {
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
    pub(super) fn next_span(&mut self) -> usize {
        if self.resume.is_some() || self.contact.pauses_at_events() {
            return 1;
        }
        match self.phase {
            Phase::Transient { segment, increment } => self
                .runs
                .span_in_segment(increment, self.transient[segment].increments()),
            Phase::Cycle { increment, .. } => {
                self.runs.span_in_cycle(&self.cycle_points, increment)
            }
        }
    }

    /// The load point of a parameter `s` in `[0, 1]` of the current increment.
    pub(super) fn point(&self, s: f64) -> LoadPoint {
        match self.phase {
            Phase::Transient { segment, increment } => {
                let seg = &self.transient[segment];
                seg.at((increment as f64 + s * self.runs.span as f64) / seg.increments() as f64)
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

    pub(super) fn phase_label(&self) -> String {
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
    pub(super) fn recycle(&mut self, report: &mut StepReport) {
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

    pub(super) fn step_body(&mut self, report: &mut StepReport) -> Result<(), StepError> {
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
            let result = self.advance(start, 1.0, self.options.failure_bisections(), report);
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
                    bisections: self.options.failure_bisections(),
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
    pub(super) fn after_increment(&mut self, events_before: usize, report: &mut StepReport) {
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
    pub(super) fn advance(
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
                if fail_depth < self.options.failure_bisections() && reached < s1 =>
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
    pub(super) fn record(&mut self, s0: f64, s1: f64, report: &mut StepReport) {
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
                // Slices, not indexing: with the lengths known once the
                // compiler vectorises the sums (indexed, it reloaded each
                // vector's pointer and length at every node).
                let current = &mut self.current;
                for (sum, f) in current.forward.iter_mut().zip(&inc.forward) {
                    *sum += f;
                }
                for (sum, b) in current.backward.iter_mut().zip(&inc.backward) {
                    *sum += b;
                }
            }
        }
    }

    /// The run ends at parameter `at` of the current increment, where the
    /// contact is and the error's load point is.
    pub(super) fn end(&mut self, end: ContactEnd, at: f64, report: &mut StepReport) {
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
    pub(super) fn arrived_at_center(&mut self) {
        self.contact = self.contact.clone();
    }

    /// Advance the position on the path, closing cycles as they end.
    pub(super) fn move_on(&mut self, report: &mut StepReport) {
        match self.phase {
            Phase::Transient { segment, increment } => {
                let next = increment + self.runs.span;
                if next >= self.transient[segment].increments()
                    && self.transient[segment].to() == self.cycle.center()
                {
                    self.arrived_at_center();
                }
                if next < self.transient[segment].increments() {
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
}
