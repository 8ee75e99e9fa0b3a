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

use std::f64::consts::PI;

use super::solver::{fingerprint, Contact, ContactError, SlipDirection, Workspace};
use super::solver::{DG_TOL, TRACTION_TOL};
use crate::params::LoadPoint;

/// A stick node at the limit leaves it only if the slack `f p - |q|` falls
/// faster than this per unit of the increment parameter: over a whole
/// increment the friction law then holds to `RATE_TOL`, well inside
/// [`TRACTION_TOL`].
const RATE_TOL: f64 = 1e-13;
/// `|y|` within this relative distance of `2 pi` is on the torque limit.
const GROSS_TOL: f64 = 1e-9;

/// `point` moved onto the torque limit: `|y|` the first number above
/// `2 pi` in the direction `dy` (gross slip is `|y| > 2 pi`, model.md
/// section 2), `x` unchanged.
fn on_torque_limit(point: LoadPoint, dy: f64) -> LoadPoint {
    let beyond = f64::from_bits((2.0 * PI).to_bits() + 1);
    LoadPoint::new(point.x(), beyond.copysign(dy))
}

/// What happened at an event inside an increment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactEventKind {
    /// Stick nodes reached `|q| = f p` and started to slip.
    SlipEntry,
    /// Slipping nodes stuck again (their slip rate reached zero).
    AdvancingStick,
}

/// An event located exactly within an increment.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactEvent {
    pub kind: ContactEventKind,
    /// Parameter in `[0, 1]` of the increment's straight segment.
    pub fraction: f64,
    /// The load point of the event.
    pub load: LoadPoint,
    /// The nodes involved, in increasing order.
    pub nodes: Vec<usize>,
}

/// What the last [`Contact::advance`] did.
#[derive(Debug, Clone)]
pub struct Increment {
    /// The segment's end points.
    pub from: LoadPoint,
    pub to: LoadPoint,
    /// How far along the segment the contact got: 1 unless the run ended
    /// (gross slip, separation) or the rate problem failed.
    pub reached: f64,
    /// `1/2 int q dg dtheta = f/2 int p |dg| dtheta` over the increment.
    pub dissipation: f64,
    /// Straight sub-segments with a fixed slip set.
    pub segments: usize,
    /// Entries into slip and advancing stick, in order.
    pub events: Vec<ContactEvent>,
    /// Positive slip of each node over the increment.
    pub forward: Vec<f64>,
    /// Negative slip of each node over the increment, as a positive number.
    pub backward: Vec<f64>,
    /// Whether any node slipped.
    pub slipped: bool,
    /// Whether the slip set or a direction changed.
    pub set_changed: bool,
    /// Rate problems solved, and LU factorisations computed.
    pub rate_solves: usize,
    pub factorisations: usize,
    /// The increment (or its rest) was solved by the finite-step active-set
    /// iteration because the rate problem did not settle.
    pub fallback: bool,
}

impl Increment {
    pub(super) fn new(n: usize) -> Self {
        Self {
            from: LoadPoint::ORIGIN,
            to: LoadPoint::ORIGIN,
            reached: 0.0,
            dissipation: 0.0,
            segments: 0,
            events: Vec::new(),
            forward: vec![0.0; n],
            backward: vec![0.0; n],
            slipped: false,
            set_changed: false,
            rate_solves: 0,
            factorisations: 0,
            fallback: false,
        }
    }

    fn reset(&mut self, from: LoadPoint, to: LoadPoint) {
        self.from = from;
        self.to = to;
        self.reached = 0.0;
        self.dissipation = 0.0;
        self.segments = 0;
        self.events.clear();
        if self.slipped {
            self.forward.fill(0.0);
            self.backward.fill(0.0);
        }
        self.slipped = false;
        self.set_changed = false;
        self.rate_solves = 0;
        self.factorisations = 0;
        self.fallback = false;
    }
}

/// Cached responses of one slip set and the scratch of the increment.
#[derive(Clone)]
pub(crate) struct Engine {
    /// Whether the responses belong to `dirs`.
    valid: bool,
    /// The slip set of the cached responses, and as `(node, sign)`.
    dirs: Vec<SlipDirection>,
    set: Vec<(usize, f64)>,
    /// Slip rates on the set per unit `x` and `y` (zero elsewhere).
    gx: Vec<f64>,
    gy: Vec<f64>,
    /// Residual pressure `H g'` and shear `-|D| g'` per unit `x` and `y`.
    hpx: Vec<f64>,
    hpy: Vec<f64>,
    hqx: Vec<f64>,
    hqy: Vec<f64>,
    /// Elastic pressure and shear per unit `x` and `y`.
    epx: Vec<f64>,
    epy: Vec<f64>,
    eqx: Vec<f64>,
    eqy: Vec<f64>,
    elastic_ready: bool,
    /// Rates along the current segment: slip, residual p and q, total p and q.
    rg: Vec<f64>,
    rhp: Vec<f64>,
    rhq: Vec<f64>,
    rp: Vec<f64>,
    rq: Vec<f64>,
    /// Rate-problem scratch.
    trial: Vec<SlipDirection>,
    before: Vec<SlipDirection>,
    seen: Vec<u64>,
    rhs: Vec<f64>,
    x: Vec<f64>,
    full: Vec<f64>,
    hbuf: Vec<f64>,
    dbuf: Vec<f64>,
}

impl Engine {
    pub(super) fn new(n: usize) -> Self {
        let z = || vec![0.0; n];
        Self {
            valid: false,
            dirs: vec![SlipDirection::Stick; n],
            set: Vec::with_capacity(n),
            gx: z(),
            gy: z(),
            hpx: z(),
            hpy: z(),
            hqx: z(),
            hqy: z(),
            epx: z(),
            epy: z(),
            eqx: z(),
            eqy: z(),
            elastic_ready: false,
            rg: z(),
            rhp: z(),
            rhq: z(),
            rp: z(),
            rq: z(),
            trial: vec![SlipDirection::Stick; n],
            before: vec![SlipDirection::Stick; n],
            seen: Vec::new(),
            rhs: z(),
            x: z(),
            full: z(),
            hbuf: z(),
            dbuf: z(),
        }
    }
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
    /// there is valid) and the error carries its load point;
    /// [`Increment::reached`] tells how far along the segment it is. On
    /// [`ContactError::NotSettled`] the contact is also left valid where it
    /// got to, so the caller may cut the rest of the segment.
    pub fn advance(&mut self, target: LoadPoint) -> Result<(), ContactError> {
        let n = self.nodes();
        let mut w = self.work.take().unwrap_or_else(|| Workspace::new(n));
        let result = self.advance_with(target, &mut w);
        self.work = Some(w);
        result
    }

    fn advance_with(&mut self, target: LoadPoint, w: &mut Workspace) -> Result<(), ContactError> {
        let from = self.load;
        self.increment.reset(from, target);
        let (dx, dy) = (target.x() - from.x(), target.y() - from.y());
        if dx == 0.0 && dy == 0.0 {
            self.increment.reached = 1.0;
            return Ok(());
        }
        if !w.engine.elastic_ready {
            self.elastic_responses(w);
        }
        let n = self.nodes();
        let mut s = 0.0;
        let mut rate_solves_here = 0;
        let max_events = 4 * n + 20;
        let mut events = 0;
        loop {
            if !w.engine.valid {
                self.responses(w)?;
            }
            self.combine(w, dx, dy);
            let remaining = 1.0 - s;
            let (stop, t, need_rates) = self.scan(w, dy, remaining);
            if need_rates {
                // A settled rate problem leaves nothing to decide here: a
                // second request at the same point means it did not hold.
                rate_solves_here += 1;
                if rate_solves_here > 2 {
                    return self.fallback(target, s, w);
                }
                match self.rate_problem(w, dx, dy, s, remaining) {
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
                        return Err(ContactError::GrossSlip { load: self.load });
                    }
                    Err(RateFailure::NotSettled) => return self.fallback(target, s, w),
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
            self.move_along(w, t, load);
            s = s_new;
            self.increment.reached = s;
            match stop {
                Stop::End => return Ok(()),
                Stop::Entry => {
                    events += 1;
                    if events > max_events {
                        return self.fallback(target, s, w);
                    }
                }
                Stop::Separation(node) => {
                    return Err(self.separation(self.load, node, self.pressure[node]));
                }
                Stop::Gross => return Err(ContactError::GrossSlip { load: self.load }),
            }
        }
    }

    /// Elastic tractions per unit `x` and unit `y` (model.md section 2).
    fn elastic_responses(&self, w: &mut Workspace) {
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
    }

    /// Responses of the slip set `self.directions` to unit `x` and `y`.
    fn responses(&mut self, w: &mut Workspace) -> Result<(), ContactError> {
        w.engine.trial.copy_from_slice(&self.directions);
        if self.responses_for_trial(w) {
            Ok(())
        } else {
            Err(ContactError::NotSettled {
                load: self.load,
                iterations: 1,
            })
        }
    }

    /// Responses of the slip set `w.engine.trial`; false if the reduced
    /// system gave no finite solution.
    fn responses_for_trial(&mut self, w: &mut Workspace) -> bool {
        let f = self.material.friction();
        let e = &mut w.engine;
        e.dirs.copy_from_slice(&e.trial);
        e.set.clear();
        e.set.extend(
            e.dirs
                .iter()
                .enumerate()
                .filter(|(_, d)| d.is_slipping())
                .map(|(j, d)| (j, d.sign())),
        );
        e.valid = false;
        let k = e.set.len();
        if k == 0 {
            for v in [&mut e.gx, &mut e.gy, &mut e.hpx, &mut e.hpy, &mut e.hqx, &mut e.hqy] {
                v.fill(0.0);
            }
            e.valid = true;
            return true;
        }
        for axis in 0..2 {
            let (ep, eq) = if axis == 0 {
                (&e.epx, &e.eqx)
            } else {
                (&e.epy, &e.eqy)
            };
            for (r, &(j, sg)) in e.rhs.iter_mut().zip(&e.set) {
                *r = -(eq[j] - sg * f * ep[j]);
            }
            let before = w.reduced.factorisations;
            w.reduced
                .solve(&self.ops, f, &e.set, &e.rhs[..k], &mut e.x[..k]);
            self.increment.factorisations += w.reduced.factorisations - before;
            e.full.fill(0.0);
            for (&v, &(j, _)) in e.x[..k].iter().zip(&e.set) {
                if !v.is_finite() {
                    return false;
                }
                e.full[j] = v;
            }
            self.ops
                .apply_both(&e.full, &mut e.hbuf, &mut e.dbuf, &mut w.fft);
            let (g, hp, hq) = if axis == 0 {
                (&mut e.gx, &mut e.hpx, &mut e.hqx)
            } else {
                (&mut e.gy, &mut e.hpy, &mut e.hqy)
            };
            g.copy_from_slice(&e.full);
            hp.copy_from_slice(&e.hbuf);
            for (o, &d) in hq.iter_mut().zip(&e.dbuf) {
                *o = -d;
            }
        }
        e.valid = true;
        true
    }

    /// Rates along the segment direction `(dx, dy)` from the cached responses.
    #[inline]
    fn combine(&self, w: &mut Workspace, dx: f64, dy: f64) {
        let e = &mut w.engine;
        for &(j, _) in &e.set {
            e.rg[j] = dx * e.gx[j] + dy * e.gy[j];
        }
        if e.set.is_empty() {
            for j in 0..e.rp.len() {
                e.rp[j] = dx * e.epx[j] + dy * e.epy[j];
                e.rq[j] = dx * e.eqx[j] + dy * e.eqy[j];
            }
        } else {
            for j in 0..e.rp.len() {
                let hp = dx * e.hpx[j] + dy * e.hpy[j];
                let hq = dx * e.hqx[j] + dy * e.hqy[j];
                e.rhp[j] = hp;
                e.rhq[j] = hq;
                e.rp[j] = dx * e.epx[j] + dy * e.epy[j] + hp;
                e.rq[j] = dx * e.eqx[j] + dy * e.eqy[j] + hq;
            }
        }
    }

    /// The first event in `(0, remaining]` of the segment with the cached
    /// set, or a request to solve the rate problem here first.
    fn scan(&self, w: &Workspace, dy: f64, remaining: f64) -> (Stop, f64, bool) {
        let f = self.material.friction();
        let e = &w.engine;
        let mut t_min = remaining;
        let mut stop = Stop::End;
        let mut need_rates = false;
        let scale = e
            .set
            .iter()
            .map(|&(j, _)| e.rg[j].abs())
            .fold(0.0, f64::max);
        for &(j, sg) in &e.set {
            if sg * e.rg[j] < -DG_TOL * scale {
                need_rates = true;
            }
        }
        for j in 0..e.rp.len() {
            let (p, q, a, b) = (self.pressure[j], self.shear[j], e.rp[j], e.rq[j]);
            if a < 0.0 {
                let t = p.max(0.0) / -a;
                if t < t_min {
                    t_min = t;
                    stop = Stop::Separation(j);
                }
            }
            if !e.dirs[j].is_slipping() {
                // Slack on the forward (sigma = 1) and backward side.
                for sigma in [1.0, -1.0] {
                    let h1 = f * a - sigma * b;
                    let h0 = f * p - sigma * q;
                    if h1 < -RATE_TOL && h0 + remaining * h1 < -TRACTION_TOL {
                        if h0 <= TRACTION_TOL {
                            need_rates = true;
                        } else {
                            let t = h0 / -h1;
                            if t < t_min {
                                t_min = t;
                                stop = Stop::Entry;
                            }
                        }
                    }
                }
            }
        }
        if dy != 0.0 {
            let y = self.load.y();
            let limit = 2.0 * PI * dy.signum();
            let t = if y.abs() >= 2.0 * PI * (1.0 - GROSS_TOL) && y * dy > 0.0 {
                0.0
            } else {
                (limit - y) / dy
            };
            if t >= 0.0 && t <= t_min {
                t_min = t;
                stop = Stop::Gross;
            }
        }
        (stop, t_min, need_rates)
    }

    /// Move by `t` of the segment parameter with the cached set, to `load`.
    fn move_along(&mut self, w: &mut Workspace, t: f64, load: LoadPoint) {
        let f = self.material.friction();
        let n = self.nodes();
        let e = &w.engine;
        self.increment.segments += 1;
        self.load = load;
        let slipping = !e.set.is_empty() && t > 0.0;
        if slipping {
            let mut before = 0.0;
            for &(j, _) in &e.set {
                let dg = t * e.rg[j];
                before += self.pressure[j] * dg.abs();
                self.slip[j] += dg;
                if dg > 0.0 {
                    self.increment.forward[j] += dg;
                } else {
                    self.increment.backward[j] -= dg;
                }
            }
            for j in 0..n {
                self.residual_pressure[j] += t * e.rhp[j];
                self.residual_shear[j] += t * e.rhq[j];
            }
            self.increment.slipped = true;
            self.refresh_tractions();
            let after: f64 = e
                .set
                .iter()
                .map(|&(j, _)| self.pressure[j] * (t * e.rg[j]).abs())
                .sum();
            let dtheta = 2.0 * PI / n as f64;
            self.increment.dissipation += 0.5 * f * 0.5 * (before + after) * dtheta;
        } else {
            self.refresh_tractions();
        }
    }

    /// `p` and `q` at the current load from the elastic and residual parts.
    fn refresh_tractions(&mut self) {
        let loads = self.material.to_loads(self.load);
        let two_pi = 2.0 * PI;
        let pr = self.material.beta() * loads.radial / two_pi;
        let qr = self.material.alpha() * loads.radial / two_pi;
        let qt = loads.torque / two_pi;
        for j in 0..self.pressure.len() {
            self.pressure[j] = 1.0 - pr * self.sin[j] + self.residual_pressure[j];
            self.shear[j] = -qt - qr * self.cos[j] + self.residual_shear[j];
        }
    }

    /// Decide the slip set at the current point for the load direction
    /// `(dx, dy)`: the active-set iteration on the rates, over the slip set
    /// and the stick nodes at the friction limit. Records the entries and
    /// the advancing stick it finds as events at parameter `s`.
    fn rate_problem(
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
        let max_iterations = 4 * n + 20;
        let mut settled = false;
        for iteration in 1..=max_iterations {
            if !w.engine.valid || w.engine.dirs != w.engine.trial {
                if !self.responses_for_trial(w) {
                    return Err(RateFailure::NotSettled);
                }
            }
            self.combine(w, dx, dy);
            let e = &mut w.engine;
            let scale = e
                .set
                .iter()
                .map(|&(j, _)| e.rg[j].abs())
                .fold(0.0, f64::max);
            let mut changed = false;
            for &(j, sg) in &e.set {
                if sg * e.rg[j] < -DG_TOL * scale {
                    e.trial[j] = SlipDirection::Stick;
                    changed = true;
                }
            }
            for j in 0..n {
                if e.dirs[j].is_slipping() {
                    continue;
                }
                let (p, q) = (self.pressure[j], self.shear[j]);
                for sigma in [1.0, -1.0] {
                    let h0 = f * p - sigma * q;
                    let h1 = f * e.rp[j] - sigma * e.rq[j];
                    if h0 <= TRACTION_TOL
                        && h1 < -RATE_TOL
                        && h0 + remaining * h1 < -TRACTION_TOL
                    {
                        e.trial[j] = if sigma > 0.0 {
                            SlipDirection::Forward
                        } else {
                            SlipDirection::Backward
                        };
                        changed = true;
                        break;
                    }
                }
            }
            if e.trial.iter().all(|d| d.is_slipping()) {
                // All nodes at the limit: only possible on |y| = 2 pi.
                return Err(if self.load.y().abs() >= 2.0 * PI * (1.0 - GROSS_TOL) {
                    RateFailure::Gross
                } else {
                    RateFailure::NotSettled
                });
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
        if e.before != e.dirs {
            self.directions.copy_from_slice(&e.dirs);
            self.increment.set_changed = true;
            let load = self.load;
            let entered: Vec<usize> = (0..n)
                .filter(|&j| !e.before[j].is_slipping() && e.dirs[j].is_slipping())
                .collect();
            let stuck: Vec<usize> = (0..n)
                .filter(|&j| e.before[j].is_slipping() && e.dirs[j] != e.before[j])
                .collect();
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
                }
            }
        }
        Ok(())
    }

    /// Last resort: the finite-step active-set iteration from the current
    /// point to `target`.
    fn fallback(
        &mut self,
        target: LoadPoint,
        s: f64,
        w: &mut Workspace,
    ) -> Result<(), ContactError> {
        let n = self.nodes();
        let f = self.material.friction();
        self.increment.fallback = true;
        match self.solve_with(target, f, n, w) {
            Ok(trial) => {
                self.increment.dissipation += trial.dissipation;
                self.increment.segments += 1;
                self.increment.factorisations += trial.factorisations;
                for (j, &d) in trial.slip_increment.iter().enumerate() {
                    if d > 0.0 {
                        self.increment.forward[j] += d;
                        self.increment.slipped = true;
                    } else if d < 0.0 {
                        self.increment.backward[j] -= d;
                        self.increment.slipped = true;
                    }
                }
                if trial.directions != self.directions {
                    self.increment.set_changed = true;
                }
                w.engine.valid = false;
                // `commit` without the invalidation of the (taken) workspace.
                self.commit(trial);
                self.increment.reached = 1.0;
                Ok(())
            }
            Err(ContactError::GrossSlip { .. }) => {
                // Only on the torque limit; otherwise the trial set had not
                // settled.
                let (y0, y1) = (self.load.y(), target.y());
                if y1.abs() >= 2.0 * PI && y0.abs() < 2.0 * PI && y1 != y0 {
                    let limit = 2.0 * PI * (y1 - y0).signum();
                    let r = (limit - y0) / (y1 - y0);
                    let load = on_torque_limit(self.load.lerp(target, r), y1 - y0);
                    self.increment.reached = s + (1.0 - s) * r;
                    Err(ContactError::GrossSlip { load })
                } else {
                    self.increment.reached = s;
                    Err(ContactError::NotSettled {
                        load: target,
                        iterations: 0,
                    })
                }
            }
            Err(e) => {
                self.increment.reached = s;
                Err(e)
            }
        }
    }
}
