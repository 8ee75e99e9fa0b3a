//! The exact, event-driven load increment (issue 9).
//!
//! With the slip set `S` and its directions `s` fixed, the incremental
//! problem of model.md section 3 is linear: the slip rate on `S` solves
//! `(-|D| - f diag(s) H)_SS g'_S = -(q_el' - s f p_el')_S`, and the rates of
//! `p = p_el + H g` and `q = q_el - |D| g` follow at every node. The elastic
//! parts are linear in the load point `(x, y)` (model.md section 2), so one
//! pair of response vectors per slip set, to a unit change of `x` and of
//! `y`, gives the rates of `g`, `p` and `q` for any direction of the load.
//!
//! Within one increment the load moves on the **straight segment** between
//! the increment's two end points (the cycle's ellipse is sampled at the end
//! points of its increments only), so with `S` fixed everything is linear in
//! the increment parameter `s` in `[0, 1]`. [`Contact::advance`] walks the
//! segment from event to event:
//!
//! * a stick node reaching `|q| = f p` (entry into slip),
//! * `p` reaching 0 (separation),
//! * `|y|` reaching `2 pi` (gross slip: the friction torque limit),
//!
//! located in closed form from the linear rates. At an event (and at the
//! start of an increment, where the direction of the load changes) the new
//! slip set is decided by the **rate problem**: the active-set iteration of
//! model.md section 3 applied to the rates, over the nodes at the friction
//! limit. A slip node whose slip rate would oppose its direction sticks there
//! (advancing stick, located at the exact load point); a node at the limit
//! that the load pushes out enters the slip set. While the set does not
//! change an increment costs `O(N)`: no linear solve, no FFT, no allocation.
//!
//! The dissipation of a sub-segment, `f/2 int p |dg| dtheta`, is exact: `p`
//! is linear and `dg` uniform in `s` there, so the trapezoid of `p` over the
//! sub-segment times `|dg|` is the integral.
//!
//! This folder holds the increment by job: the entry point
//! ([`Contact::advance`]) here, the engine of one slip set's responses in
//! [`engine`], the responses to a segment's direction in [`responses`], the
//! walk to the next event in [`events`], the rate problem in [`rates`] and
//! the report of what an increment did in [`report`].

use std::f64::consts::PI;

use super::{Advanced, Contact, ContactEnd, ContactError, Workspace};
use crate::contact::cache::ResponseCache;
use crate::contact::kernels;
use crate::model::LoadPoint;

mod engine;
mod events;
mod rates;
mod report;
mod responses;
#[cfg(test)]
mod tests;
pub(in crate::contact) use engine::Engine;
pub use report::{ContactEvent, ContactEventKind, Increment};

/// A slip set of fewer than `N / SET_LOOP_SHARE` nodes has its slip moved
/// node by node (indexed, about 20 instructions a node); a larger one by a
/// vectorised pass over all `N` nodes (about 3 a node).
const SET_LOOP_SHARE: usize = 8;

/// `point` moved onto the torque limit: `|y|` the first number above
/// `2 pi` in the direction `dy` (gross slip is `|y| > 2 pi`, model.md
/// section 2), `x` unchanged.
fn on_torque_limit(point: LoadPoint, dy: f64) -> LoadPoint {
    let beyond = f64::from_bits((2.0 * PI).to_bits() + 1);
    LoadPoint::new(point.x(), beyond.copysign(dy))
}

/// `(max |rg|, min sgn rg)` of the slip rates along `along = (a1, a2)`.
#[derive(Clone, Copy)]
struct RatesSeen {
    along: (f64, f64),
    scale: f64,
    worst: f64,
}

/// Why the walk along a segment stopped before its end.
enum Stop {
    End,
    Entry,
    Separation(usize),
    Gross,
}

/// The rate problem did not give a usable slip set.
enum RateFailure {
    NotSettled,
    Gross,
}

impl Contact {
    /// Forget the cached responses (the slip set changed outside
    /// [`Contact::advance`]).
    pub(super) fn invalidate_responses(&mut self) {
        if let Some(w) = &mut self.work {
            w.engine.valid = false;
            w.engine.clearance = None;
        }
    }

    /// Forget the clearance of the state (the tractions changed outside
    /// [`Contact::advance`]).
    pub(super) fn forget_clearance(&mut self) {
        if let Some(w) = &mut self.work {
            w.engine.clearance = None;
        }
    }

    /// Take out the slip rates this contact's increments have cached (an
    /// empty cache with the same budget stays), to hand them to the next
    /// run of a sweep's group ([`Contact::give_response_cache`]). The rates
    /// of a slip set depend on the set, the operators and `f` only
    /// (model.md section 3), so they hold for any contact of the same
    /// operators and friction.
    pub(crate) fn take_response_cache(&mut self) -> Option<ResponseCache> {
        let w = self.work.as_mut()?;
        let empty = w.engine.cache.clone();
        w.engine.slot = None;
        let cache = std::mem::replace(&mut w.engine.cache, empty);
        w.engine.own_responses(&cache);
        Some(cache)
    }

    /// Start from the cached rates `cache` of another contact with the same
    /// operators and friction ([`Contact::take_response_cache`]).
    pub(crate) fn give_response_cache(&mut self, cache: ResponseCache) {
        if let Some(w) = &mut self.work {
            let old = std::mem::replace(&mut w.engine.cache, cache);
            w.engine.own_responses(&old);
            w.engine.slot = None;
        }
    }

    /// What the last [`Contact::advance`] did.
    pub fn last_increment(&self) -> &Increment {
        &self.increment
    }

    /// Advance the load on the straight segment from the current load point
    /// to `target`, following the slip exactly through every event (entry
    /// into slip, advancing stick) on the way; see the module documentation.
    ///
    /// Gross slip is declared where `|y|` reaches `2 pi` and separation
    /// where `p` reaches 0: the contact is left at that point (its state
    /// there is valid) and [`Advanced::Ended`] carries the load point;
    /// [`Increment::reached`] tells how far along the segment it is.
    ///
    /// # Errors
    ///
    /// [`ContactError::NotSettled`] when the rate problem and the
    /// finite-step fallback do not settle; the contact is left valid where
    /// it got to, so the caller may cut the rest of the segment.
    ///
    /// # Examples
    ///
    /// ```
    /// use shakedown::{Advanced, Contact, LoadPoint, Material};
    /// use shakedown::stepping::operators;
    /// use shakedown::Discretisation;
    ///
    /// let mut contact = Contact::new(Material::paper(), operators(&Discretisation::default()));
    /// // Inside the stick diamond |x| + |y| <= 2 pi nothing slips.
    /// assert_eq!(contact.advance(LoadPoint::new(1.0, 2.0)), Ok(Advanced::Reached));
    /// assert!(contact.directions().iter().all(|d| !d.is_slipping()));
    /// // Along the torque axis the whole interface slides at |y| = 2 pi.
    /// let end = contact.advance(LoadPoint::new(1.0, 7.0)).unwrap();
    /// assert!(matches!(end, Advanced::Ended(shakedown::ContactEnd::GrossSlip { .. })));
    /// ```
    pub fn advance(&mut self, target: LoadPoint) -> Result<Advanced, ContactError> {
        let n = self.nodes();
        let mut w = self
            .work
            .take()
            .unwrap_or_else(|| Box::new(Workspace::new(n)));
        let result = self.advance_with(target, &mut w);
        self.work = Some(w);
        self.increment.clear_stale();
        result
    }

    fn advance_with(
        &mut self,
        target: LoadPoint,
        w: &mut Workspace,
    ) -> Result<Advanced, ContactError> {
        let from = self.load;
        self.increment.reset(from, target);
        let (dx, dy) = (target.x() - from.x(), target.y() - from.y());
        if dx == 0.0 && dy == 0.0 {
            self.increment.reached = 1.0;
            return Ok(Advanced::Reached);
        }
        if !w.engine.elastic_ready {
            self.elastic_responses(w);
        }
        let n = self.nodes();
        let mut s = 0.0;
        let mut rate_solves_here = 0;
        let max_events = (4 * n + 20) * self.segment_increments;
        let mut events = 0;
        // A node reached the friction limit at the end of the last
        // sub-segment: the set is decided there straight away (a scan there
        // would only ask for it).
        let mut entry = false;
        loop {
            if self.refuse_runs && self.segment_increments > 1 && s > 0.0 {
                return self.last_resort(target, s, w);
            }
            if !w.engine.valid {
                self.responses(w, dx, dy)?;
            }
            let Some((a1, a2)) = self.direction_coefficients(w, dx, dy) else {
                return Err(ContactError::NotSettled {
                    load: self.load,
                    iterations: 1,
                });
            };
            let remaining = 1.0 - s;
            let (stop, t, need_rates, ahead) = if std::mem::take(&mut entry) {
                (Stop::End, 0.0, true, None)
            } else {
                self.scan(w, a1, a2, dy, remaining)
            };
            if need_rates {
                // A settled rate problem leaves nothing to decide here: a
                // second request at the same point means it did not hold.
                rate_solves_here += 1;
                if rate_solves_here > 2 {
                    return self.last_resort(target, s, w);
                }
                let events_before = self.increment.events.len();
                match self.rate_problem(w, dx, dy, s, remaining) {
                    Ok(())
                        if self.pause_at_events && self.increment.events.len() > events_before =>
                    {
                        // `reached` is already `s`: the event's point.
                        return Ok(Advanced::Paused);
                    }
                    Ok(()) => continue,
                    Err(RateFailure::Gross) => {
                        // All nodes at the limit a round-off short of
                        // |y| = 2 pi: the crossing is the gross-slip point.
                        let t = if dy == 0.0 {
                            0.0
                        } else {
                            ((2.0 * PI * dy.signum() - self.load.y()) / dy).clamp(0.0, remaining)
                        };
                        let side = if dy == 0.0 { self.load.y() } else { dy };
                        self.increment.reached = s + t;
                        self.load = on_torque_limit(from.lerp(target, s + t), side);
                        self.refresh_tractions();
                        return Ok(Advanced::Ended(ContactEnd::GrossSlip { load: self.load }));
                    }
                    Err(RateFailure::NotSettled) => return self.last_resort(target, s, w),
                }
            }
            rate_solves_here = 0;
            let end = matches!(stop, Stop::End);
            let s_new = if end { 1.0 } else { s + t };
            let load = match stop {
                Stop::End => target,
                Stop::Gross => on_torque_limit(from.lerp(target, s_new), dy),
                _ => from.lerp(target, s_new),
            };
            self.move_along(w, t, a1, a2, load);
            s = s_new;
            self.increment.reached = s;
            match stop {
                Stop::End => {
                    // The end margins just bounded hold at the target: the
                    // next increment's scan may start from them.
                    w.engine.clearance = ahead.map(|c| (self.load, c));
                    return Ok(Advanced::Reached);
                }
                Stop::Entry => {
                    events += 1;
                    if events > max_events {
                        return self.last_resort(target, s, w);
                    }
                    entry = true;
                }
                Stop::Separation(node) => {
                    return Ok(Advanced::Ended(self.separation(
                        self.load,
                        node,
                        self.pressure[node],
                    )));
                }
                Stop::Gross => {
                    return Ok(Advanced::Ended(ContactEnd::GrossSlip { load: self.load }))
                }
            }
        }
    }

    /// Whether the scan may use the bounds that spare its passes over the
    /// nodes (a test compares it with one that may not).
    #[inline]
    fn bounded(&self) -> bool {
        !self.unbounded
    }

    /// `p` and `q` at the current load from the elastic and residual parts.
    fn refresh_tractions(&mut self) {
        let parts = [
            &self.sin[..],
            &self.cos,
            &self.residual_pressure,
            &self.residual_shear,
        ];
        kernels::tractions(
            self.elastic_part(self.load),
            parts,
            &mut self.pressure,
            &mut self.shear,
        );
    }

    /// The loads' part of the tractions at `load` (model.md section 2).
    fn elastic_part(&self, load: LoadPoint) -> kernels::Elastic {
        let loads = self.material.to_loads(load);
        let two_pi = 2.0 * PI;
        kernels::Elastic {
            pr: self.material.beta() * loads.radial / two_pi,
            qr: self.material.alpha() * loads.radial / two_pi,
            qt: loads.torque / two_pi,
        }
    }
}
