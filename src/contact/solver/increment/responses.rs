//! The responses of the slip set to the segment's direction: the elastic
//! parts, the set's slip rates (from the response cache or the kept
//! inverse) and their combination along the segment.

use std::f64::consts::PI;

use crate::contact::cache::ResponseCache;
use crate::contact::solver::{Contact, ContactError, Workspace};
use crate::model::LoadPoint;

impl Contact {
    /// Elastic tractions per unit `x` and unit `y` (model.md section 2).
    pub(super) fn elastic_responses(&self, w: &mut Workspace) {
        let e = &mut w.engine;
        let (alpha, beta) = (self.material.alpha(), self.material.beta());
        let two_pi = 2.0 * PI;
        for (unit, ep, eq) in [
            (LoadPoint::new(1.0, 0.0), &mut e.epx, &mut e.eqx),
            (LoadPoint::new(0.0, 1.0), &mut e.epy, &mut e.eqy),
        ] {
            let loads = self.material.to_loads(unit);
            for j in 0..ep.len() {
                ep[j] = -beta * loads.radial * self.sin[j] / two_pi;
                eq[j] = -loads.torque / two_pi - alpha * loads.radial * self.cos[j] / two_pi;
            }
        }
        e.elastic_ready = true;
        // The inverse keeps the set's slip rates per unit x and y with it.
        w.inverse.set_loads([&e.epx, &e.eqx, &e.epy, &e.eqy]);
    }

    /// Responses of the slip set `self.directions` to the direction
    /// `(dx, dy)`.
    pub(super) fn responses(
        &mut self,
        w: &mut Workspace,
        dx: f64,
        dy: f64,
    ) -> Result<(), ContactError> {
        w.engine.trial.copy_from_slice(&self.directions);
        if self.responses_for_trial(w, dx, dy) {
            Ok(())
        } else {
            Err(ContactError::NotSettled {
                load: self.load,
                iterations: 1,
            })
        }
    }

    /// Responses of the slip set `w.engine.trial` to the load direction
    /// `(dx, dy)` (made `u1`); false if the reduced system gave no finite
    /// solution. The response to the perpendicular `u2` waits until a
    /// segment needs it ([`Self::direction_coefficients`]).
    pub(super) fn responses_for_trial(&mut self, w: &mut Workspace, dx: f64, dy: f64) -> bool {
        let e = &mut w.engine;
        // The signs change below.
        e.rg_extremes = None;
        e.valid = false;
        e.u1 = (dx, dy);
        e.have2 = false;
        // The set's responses go with it, before the cache can change.
        e.lent = [None; 2];
        e.change_set_to_trial();
        // The inverse follows the set only when it solves (a hit does not
        // ask it): it looks at the nodes changed since then, not at all.
        w.inverse.note_changes(&e.changes);
        if e.set.is_empty() {
            e.rg_for = None;
            for v in [
                &mut e.gx, &mut e.gy, &mut e.hpx, &mut e.hpy, &mut e.hqx, &mut e.hqy,
            ] {
                v.fill(0.0);
            }
            e.totals(0);
            e.totals(1);
            e.have2 = true;
            e.valid = true;
            return true;
        }
        // The cache is lent out while its entry fills the engine (no
        // allocation: an empty cache holds none).
        let mut cache = std::mem::replace(&mut e.cache, ResponseCache::new(0));
        e.key.set_to(&e.set);
        if let Some(slot) = cache.find(&e.key) {
            // A set met before: its slip rates, and p and q from the kept
            // responses or by one FFT.
            let hit = cache.hit(slot);
            e.u1 = hit.u1;
            e.slot = Some(hit.slot);
            for (axis, rates, kept, at) in [
                (0, Some(hit.first), hit.first_responses, hit.responses_at[0]),
                (1, hit.second, hit.second_responses, hit.responses_at[1]),
            ] {
                let Some(rates) = rates else { continue };
                e.full.fill(0.0);
                for (&(j, _), &r) in e.set.iter().zip(rates) {
                    e.full[j] = r;
                }
                match (kept, at) {
                    (Some(kept), Some(at)) => e.restore_axis(axis, kept, at),
                    _ => e.fill_axis(&self.ops, &mut w.fft, axis),
                }
            }
            e.have2 = hit.second.is_some();
            e.valid = true;
            e.cache = cache;
            return true;
        }
        e.cache = cache;
        if !self.axis_response(w, 0) {
            return false;
        }
        let e = &mut w.engine;
        // `key` is the set's still: the rates do not change the set.
        e.slot = e.cache.insert(
            &e.key,
            e.u1,
            e.set.iter().map(|&(j, _)| e.gx[j]),
            (&e.hpx, &e.hqx),
        );
        e.valid = true;
        true
    }

    /// Solve for the response of the cached set to the direction of `axis`
    /// (`u1` or `u2`) and its totals; false if not finite.
    pub(super) fn axis_response(&mut self, w: &mut Workspace, axis: usize) -> bool {
        let f = self.material.friction();
        let e = &mut w.engine;
        let (ux, uy) = e.axis(axis);
        let before = w.inverse.rebuilds;
        if !w.inverse.update_to(&self.ops, f, &e.dirs, &e.set) {
            return false;
        }
        self.increment.factorisations += w.inverse.rebuilds - before;
        e.full.fill(0.0);
        if !w.inverse.rates(ux, uy, &mut e.full) {
            return false;
        }
        e.fill_axis(&self.ops, &mut w.fft, axis);
        true
    }

    /// The load direction `(dx, dy)` as `a1 u1 + a2 u2`, computing the
    /// response to `u2` first if the set needs it; `None` if that response
    /// is not finite. A direction along `u1` to within round-off (a straight
    /// load path) leaves `u2` out.
    ///
    /// "Within round-off" has two parts. Relative to the chord: `a2` below
    /// `1e-13 a1`. And absolute: the chord is the difference of two load
    /// points, each rounded to a few ulps of its size, so near a turning
    /// point of a straight cycle (where the chord is short) its direction
    /// carries a rounding of a few ulps of the load over the chord's length,
    /// which can exceed `1e-13`. A perpendicular part `|a2| |u1|` below 32
    /// ulps of the load is that rounding, not a direction; solving for `u2`
    /// there cost a full solve at about every fifth event of a `phi = 0`
    /// cycle. Leaving it out moves the residual state by at most that much
    /// load, `~1e-14`, as the rounding of the load points already does.
    pub(super) fn direction_coefficients(
        &mut self,
        w: &mut Workspace,
        dx: f64,
        dy: f64,
    ) -> Option<(f64, f64)> {
        let (ux, uy) = w.engine.u1;
        if dx == ux && dy == uy {
            return Some((1.0, 0.0));
        }
        let norm = ux * ux + uy * uy;
        let a1 = (dx * ux + dy * uy) / norm;
        let a2 = (dy * ux - dx * uy) / norm;
        if w.engine.have2 {
            return Some((a1, a2));
        }
        let load_rounding =
            32.0 * f64::EPSILON * (self.load.x().abs() + self.load.y().abs() + dx.abs() + dy.abs());
        if a2.abs() <= 1e-13 * a1.abs() || a2.abs() * norm.sqrt() <= load_rounding {
            return Some((a1, 0.0));
        }
        if !self.axis_response(w, 1) {
            return None;
        }
        let e = &mut w.engine;
        e.have2 = true;
        if let Some(slot) = e.slot {
            if e.lent[0].is_some() && e.cache.second_would_evict(e.set.len(), e.gy.len()) {
                // The eviction moves the pool's numbers: the lent ones
                // are copied out first.
                let cache = std::mem::replace(&mut e.cache, ResponseCache::new(0));
                e.own_responses(&cache);
                e.cache = cache;
            }
            e.key.set_to(&e.set);
            e.cache.add_second(
                slot,
                &e.key,
                e.set.iter().map(|&(j, _)| e.gy[j]),
                (&e.hpy, &e.hqy),
            );
        }
        Some((a1, a2))
    }
}
