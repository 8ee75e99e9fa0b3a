//! The rate problem at an event (model.md section 3): the active-set
//! iteration on the rates over the slip set and the stick nodes at the
//! friction limit, and the finite step as its fallback.

use super::*;
use std::f64::consts::PI;

use crate::contact::kernels::at_limit;
use crate::contact::solver::{
    fingerprint, push_differences, same_directions, Advanced, Contact, ContactEnd, ContactError,
    SlipDirection, Solved, Workspace,
};
use crate::contact::solver::{node_to_hold, on_the_torque_limit, MAX_HELD};
use crate::contact::tolerances::{DG_TOL, RATE_TOL, TRACTION_TOL};
use crate::model::LoadPoint;

impl Contact {
    /// Decide the slip set at the current point for the load direction
    /// `(dx, dy)`: the active-set iteration on the rates, over the slip set
    /// and the stick nodes at the friction limit. Records the entries and
    /// the advancing stick it finds as events at parameter `s`.
    pub(super) fn rate_problem(
        &mut self,
        w: &mut Workspace,
        dx: f64,
        dy: f64,
        s: f64,
        remaining: f64,
    ) -> Result<(), RateFailure> {
        let f = self.material.friction();
        let n = self.nodes();
        self.increment.rate_solves += 1;
        w.engine.trial.copy_from_slice(&self.directions);
        w.engine.before.copy_from_slice(&self.directions);
        w.engine.seen.clear();
        w.engine.held.clear();
        let max_iterations = 4 * n + 20;
        let mut settled = false;
        // Whether the last iteration changed `trial` (so that it differs
        // from the set of the responses).
        let mut changed = true;
        for iteration in 1..=max_iterations {
            let stale = if iteration == 1 {
                !w.engine.valid || !same_directions(&w.engine.dirs, &w.engine.trial)
            } else {
                changed
            };
            if stale && !self.responses_for_trial(w, dx, dy) {
                return Err(RateFailure::NotSettled);
            }
            let Some((a1, a2)) = self.direction_coefficients(w, dx, dy) else {
                return Err(RateFailure::NotSettled);
            };
            let e = &mut w.engine;
            e.combine(a1, a2);
            // The largest rate and the most negative rate along its slip
            // direction, in one vectorised pass over all the nodes (the
            // rates and signs are 0 off the set, so these are the set's;
            // a NaN is skipped, as `f64::max` skips it). Only when some
            // rate opposes its direction are the set's nodes visited.
            let (scale, worst) = e.rate_extremes();
            changed = false;
            // The slip set of `trial` as it leaves this iteration.
            let mut slipping = e.set.len();
            if worst < -DG_TOL * scale {
                for &(j, sg) in &e.set {
                    if sg * e.rg[j] < -DG_TOL * scale {
                        e.trial[j] = SlipDirection::Stick;
                        changed = true;
                        slipping -= 1;
                    }
                }
            }
            // Stick nodes at the friction limit: elsewhere (off the limit on
            // both sides, `f p - |q|` being the lower slack, or slipping)
            // there is nothing to decide.
            at_limit(&self.pressure, &self.shear, &e.off, f, &mut e.candidates);
            for &j in &e.candidates {
                let (p, q) = (self.pressure[j], self.shear[j]);
                // The rates of p and q along the segment, at this node only.
                let rp = a1 * e.tpx[j] + a2 * e.tpy[j];
                let rq = a1 * e.tqx[j] + a2 * e.tqy[j];
                for sigma in [1.0, -1.0] {
                    let h0 = f * p - sigma * q;
                    let h1 = f * rp - sigma * rq;
                    if h0 <= TRACTION_TOL && h1 < -RATE_TOL && h0 + remaining * h1 < -TRACTION_TOL {
                        e.trial[j] = SlipDirection::from_sign(sigma);
                        changed = true;
                        slipping += 1;
                        break;
                    }
                }
            }
            if slipping == n {
                // Every node at the limit: gross slip on |y| = 2 pi. Off it
                // a node must stick: hold the slowest of the set, and if it
                // then asks to slip, the next (`node_to_hold`).
                if on_the_torque_limit(self.load.y()) {
                    return Err(RateFailure::Gross);
                }
                let slipping_now = e
                    .set
                    .iter()
                    .filter(|&&(j, _)| e.trial[j].is_slipping())
                    .map(|&(j, _)| (j, e.rg[j].abs()));
                match node_to_hold(slipping_now, &e.held) {
                    Some(j) if e.held.len() < MAX_HELD => {
                        e.trial[j] = SlipDirection::Stick;
                        e.held.push(j);
                    }
                    _ => return Err(RateFailure::NotSettled),
                }
            }
            if !changed {
                settled = true;
                break;
            }
            if iteration > 4 {
                let h = fingerprint(&e.trial);
                if e.seen.contains(&h) {
                    break;
                }
                e.seen.push(h);
            }
        }
        if !settled {
            return Err(RateFailure::NotSettled);
        }
        // The responses are those of `trial`, now the slip set.
        let e = &w.engine;
        if !same_directions(&e.before, &e.dirs) {
            self.directions.copy_from_slice(&e.dirs);
            self.increment.set_changed = true;
            let load = self.load;
            // A node that changed entered slip if it stuck before, and
            // stuck (or turned) if it slipped.
            let mut entered = self.increment.node_list();
            let mut stuck = self.increment.node_list();
            push_differences(&e.before, &e.dirs, &mut entered);
            entered.retain(|&j| {
                let slipped = e.before[j].is_slipping();
                if slipped {
                    stuck.push(j);
                }
                !slipped
            });
            for (kind, nodes) in [
                (ContactEventKind::AdvancingStick, stuck),
                (ContactEventKind::SlipEntry, entered),
            ] {
                if !nodes.is_empty() {
                    self.increment.events.push(ContactEvent {
                        kind,
                        fraction: s,
                        load,
                        nodes,
                    });
                } else {
                    self.increment.spare.push(nodes);
                }
            }
        }
        Ok(())
    }

    /// Where the rate problem does not settle: the finite-step fallback
    /// over one increment, or, over a straight run of several
    /// ([`Contact::set_segment_increments`]), a stop here for the caller to
    /// take the rest one increment at a time. The contact is left valid
    /// where it got to, at parameter `s`.
    pub(super) fn last_resort(
        &mut self,
        target: LoadPoint,
        s: f64,
        w: &mut Workspace,
    ) -> Result<Advanced, ContactError> {
        if self.segment_increments == 1 {
            return self.fallback(target, s, w);
        }
        // The responses may be those of a trial set that did not settle.
        w.engine.valid = false;
        self.increment.reached = s;
        Err(ContactError::NotSettled {
            load: self.load,
            iterations: 0,
        })
    }

    /// Last resort: the finite-step active-set iteration from the current
    /// point to `target`.
    pub(super) fn fallback(
        &mut self,
        target: LoadPoint,
        s: f64,
        w: &mut Workspace,
    ) -> Result<Advanced, ContactError> {
        let n = self.nodes();
        let f = self.material.friction();
        self.increment.fallback = true;
        // The state moves below by another path.
        w.engine.clearance = None;
        match self.solve_with(target, f, n, w) {
            Ok(Solved::Trial(trial)) => {
                self.increment.dissipation += trial.dissipation;
                self.increment.segments += 1;
                self.increment.factorisations += trial.factorisations;
                for (j, &d) in trial.slip_increment.iter().enumerate() {
                    self.increment.add_slip(j, d);
                }
                if trial.directions != self.directions {
                    self.increment.set_changed = true;
                }
                w.engine.valid = false;
                // `commit` without the invalidation of the (taken) workspace.
                self.commit(trial);
                self.increment.reached = 1.0;
                Ok(Advanced::Reached)
            }
            Ok(Solved::Ended(ContactEnd::GrossSlip { .. })) => {
                // Only on the torque limit; otherwise the trial set had not
                // settled.
                let (y0, y1) = (self.load.y(), target.y());
                if y1.abs() >= 2.0 * PI && y0.abs() < 2.0 * PI && y1 != y0 {
                    let limit = 2.0 * PI * (y1 - y0).signum();
                    let r = (limit - y0) / (y1 - y0);
                    let load = on_torque_limit(self.load.lerp(target, r), y1 - y0);
                    self.increment.reached = s + (1.0 - s) * r;
                    Ok(Advanced::Ended(ContactEnd::GrossSlip { load }))
                } else {
                    self.increment.reached = s;
                    Err(ContactError::NotSettled {
                        load: target,
                        iterations: 0,
                    })
                }
            }
            Ok(Solved::Ended(end)) => {
                self.increment.reached = s;
                Ok(Advanced::Ended(end))
            }
            Err(e) => {
                self.increment.reached = s;
                Err(e)
            }
        }
    }
}
