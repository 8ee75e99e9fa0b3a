//! The incremental frictional problem (model.md section 3).
//!
//! Across one load increment the slip changes by `dg`. Stick nodes keep
//! `dg = 0` and `|q| <= f p`; slip nodes satisfy `q = s f p` with
//! `s = sign(dg)`. Because `p` depends on `g` through `H`, the reduced system
//! `(-|D| - f diag(s) H)_SS dg_S = -(q - s f p)_S` is non-symmetric and is
//! solved by an active-set iteration warm-started from the previous
//! increment's slip set. The system matrix depends only on `(S, s)`, so its
//! LU factorisation is kept and reused while the slip set does not change.
//!
//! [`Contact`]'s data and its methods live in this folder: the state and
//! its accessors here, the vocabulary of directions and results in
//! [`types`], the finite step in [`finite`], and the exact path-following
//! increment ([`Contact::advance`]) and its engine in [`increment`].

use std::f64::consts::PI;

mod finite;
mod increment;
#[cfg(test)]
pub(super) mod tests;
mod types;
use super::inverse::SetInverse;
use super::kernels::DenseLu;
use super::operators::{FftScratch, Operators};
use crate::model::{LoadPoint, Material};
pub(super) use finite::{fingerprint, node_to_hold, on_the_torque_limit, MAX_HELD};
use increment::Engine;
pub use increment::{ContactEvent, ContactEventKind, Increment};
pub(super) use types::{push_differences, same_directions};
pub use types::{Advanced, ContactEnd, ContactError, SlipDirection, Solved, Trial};

/// Scratch space of the active-set iteration, kept between increments so
/// that a run allocates little per increment, with the reduced-system
/// solver and its factorisations.
pub(super) struct Workspace {
    p0: Vec<f64>,
    q0: Vec<f64>,
    set: Vec<(usize, f64)>,
    rhs: Vec<f64>,
    x: Vec<f64>,
    pressure_change: Vec<f64>,
    relief: Vec<f64>,
    pub(super) fft: FftScratch,
    /// The LU of the finite step's reduced system.
    reduced: DenseLu,
    /// The inverse of the exact increment's reduced matrix.
    pub(super) inverse: SetInverse,
    /// The exact path-following increment's cached responses and scratch.
    pub(super) engine: Engine,
}

impl Clone for Workspace {
    fn clone(&self) -> Self {
        // The engine's clone starts with an empty cache ([`Engine::clone_owning`]).
        let engine = self.engine.clone_owning();
        Self {
            p0: self.p0.clone(),
            q0: self.q0.clone(),
            set: self.set.clone(),
            rhs: self.rhs.clone(),
            x: self.x.clone(),
            pressure_change: self.pressure_change.clone(),
            relief: self.relief.clone(),
            fft: self.fft.clone(),
            // The LU is scratch: a clone starts empty.
            reduced: DenseLu::new(0),
            inverse: self.inverse.clone(),
            engine,
        }
    }
}

impl Workspace {
    pub(super) fn new(n: usize) -> Self {
        Self {
            p0: vec![0.0; n],
            q0: vec![0.0; n],
            set: Vec::with_capacity(n),
            rhs: vec![0.0; n],
            x: vec![0.0; n],
            pressure_change: vec![0.0; n],
            relief: vec![0.0; n],
            fft: FftScratch::default(),
            reduced: DenseLu::new(0),
            inverse: SetInverse::new(n),
            engine: Engine::new(n),
        }
    }
}

/// The contact state: locked-in slip `g`, tractions at the current load and
/// the slip set of the last increment.
#[derive(Clone)]
pub struct Contact {
    pub(super) material: Material,
    pub(super) ops: std::sync::Arc<Operators>,
    pub(super) sin: Vec<f64>,
    pub(super) cos: Vec<f64>,
    pub(super) load: LoadPoint,
    pub(super) slip: Vec<f64>,
    pub(super) residual_pressure: Vec<f64>,
    pub(super) residual_shear: Vec<f64>,
    pub(super) pressure: Vec<f64>,
    pub(super) shear: Vec<f64>,
    pub(super) directions: Vec<SlipDirection>,
    /// Taken out during a solve so the rest of `self` stays borrowable
    /// (boxed: taking it out and putting it back moves a pointer, not the
    /// workspace, on every increment).
    pub(super) work: Option<Box<Workspace>>,
    /// What the last [`Contact::advance`] did.
    pub(super) increment: Increment,
    /// Whether [`Contact::advance`] stops at each event (for a viewer that
    /// pauses there).
    pub(super) pause_at_events: bool,
    /// Increments of the caller's path that the next segments span (see
    /// [`Contact::set_segment_increments`]).
    pub(super) segment_increments: usize,
    /// For tests (false otherwise): over a straight run, do not settle at
    /// the first event (to exercise the stepper's way round that). A plain
    /// switch, read once a segment, rather than a test-only build of the
    /// increment.
    pub(crate) refuse_runs: bool,
    /// For tests (false otherwise): the increment makes every pass its
    /// bounds would spare (the clearance of the end margins, the rates'
    /// direction), so that a test can compare the two.
    pub(crate) unbounded: bool,
}

impl std::fmt::Debug for Contact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Contact")
            .field("load", &self.load)
            .field("nodes", &self.slip.len())
            .finish_non_exhaustive()
    }
}

impl Contact {
    /// The shrink-fit state: no load, no slip, uniform pressure.
    pub fn new(material: Material, ops: std::sync::Arc<Operators>) -> Self {
        let n = ops.nodes();
        let theta = |j: usize| 2.0 * PI * j as f64 / n as f64;
        let mut c = Self {
            material,
            sin: (0..n).map(|j| theta(j).sin()).collect(),
            cos: (0..n).map(|j| theta(j).cos()).collect(),
            ops,
            load: LoadPoint::ORIGIN,
            slip: vec![0.0; n],
            residual_pressure: vec![0.0; n],
            residual_shear: vec![0.0; n],
            pressure: vec![1.0; n],
            shear: vec![0.0; n],
            directions: vec![SlipDirection::Stick; n],
            work: Some(Box::new(Workspace::new(n))),
            increment: Increment::new(n),
            pause_at_events: false,
            segment_increments: 1,
            refuse_runs: false,
            unbounded: false,
        };
        c.refresh();
        c
    }

    /// Make [`Contact::advance`] stop at every entry into slip and every
    /// advancing stick ([`Advanced::Paused`]), at the event's exact load
    /// point, or not (the default). The path is the same either way: the
    /// events are located on the same straight segment.
    pub fn set_pause_at_events(&mut self, pause: bool) {
        self.pause_at_events = pause;
    }

    /// Whether [`Contact::advance`] stops at events
    /// ([`Contact::set_pause_at_events`]).
    pub fn pauses_at_events(&self) -> bool {
        self.pause_at_events
    }

    /// Say that the segments the next [`Contact::advance`] calls follow
    /// are straight runs of `increments` increments of the caller's path
    /// (1, the default: one increment each).
    ///
    /// The path-following itself does not depend on the segment's length:
    /// every event on it is located exactly. Two last resorts do: the cap on
    /// the events of one segment (which notices an event loop) scales with
    /// it, and over more than one increment the finite-step fallback is not
    /// taken (it would solve the whole run in one finite step): the
    /// contact stops where it got to with [`ContactError::NotSettled`], so
    /// that the caller takes the rest one increment at a time.
    pub fn set_segment_increments(&mut self, increments: usize) {
        self.segment_increments = increments.max(1);
    }

    /// Replace the locked-in slip (an initial condition) without any load
    /// change. The caller is responsible for it satisfying the friction law.
    pub fn set_slip(&mut self, slip: &[f64]) {
        self.slip.copy_from_slice(slip);
        self.residual_pressure = self.ops.residual_pressure(&self.slip);
        self.residual_shear = self.ops.residual_shear(&self.slip);
        self.directions.fill(SlipDirection::Stick);
        self.invalidate_responses();
        self.refresh();
    }

    /// Move the load without slip (valid while the friction law holds, as
    /// in a shakedown state); used to place a state at a known point.
    pub fn set_load_elastic(&mut self, load: LoadPoint) {
        self.load = load;
        self.directions.fill(SlipDirection::Stick);
        self.invalidate_responses();
        self.refresh();
    }

    fn refresh(&mut self) {
        let (p, q) = self.tractions_at(self.load);
        self.pressure = p;
        self.shear = q;
    }

    /// Tractions at `load` with the current slip and no further slip:
    /// eqs. (1)-(2) plus the residual parts.
    pub fn tractions_at(&self, load: LoadPoint) -> (Vec<f64>, Vec<f64>) {
        let (mut p, mut q) = self.elastic_tractions(load);
        for j in 0..p.len() {
            p[j] += self.residual_pressure[j];
            q[j] += self.residual_shear[j];
        }
        (p, q)
    }

    /// Tractions of eqs. (1)-(2) alone: the loads without any slip.
    pub fn elastic_tractions(&self, load: LoadPoint) -> (Vec<f64>, Vec<f64>) {
        let loads = self.material.to_loads(load);
        let (alpha, beta) = (self.material.alpha(), self.material.beta());
        let two_pi = 2.0 * PI;
        let p = self
            .sin
            .iter()
            .map(|s| 1.0 - beta * loads.radial * s / two_pi)
            .collect();
        let q = self
            .cos
            .iter()
            .map(|c| -loads.torque / two_pi - alpha * loads.radial * c / two_pi)
            .collect();
        (p, q)
    }

    /// The least of `f p - q` and of `f p + q` (index 0 and 1) at each
    /// node over the load points `points`, with the elastic tractions of
    /// eqs. (1)-(2) alone (no slip). Both are affine in the loads, so this
    /// costs two multiply-adds per node and point.
    pub fn least_elastic_margins(
        &self,
        points: impl IntoIterator<Item = LoadPoint>,
    ) -> Vec<[f64; 2]> {
        let f = self.material.friction();
        let (alpha, beta) = (self.material.alpha(), self.material.beta());
        let two_pi = 2.0 * PI;
        // f p -+ q = f +- T / 2 pi + R (+-alpha cos - f beta sin) / 2 pi.
        let plus: Vec<f64> = (self.cos.iter().zip(&self.sin))
            .map(|(c, s)| (alpha * c - f * beta * s) / two_pi)
            .collect();
        let minus: Vec<f64> = (self.cos.iter().zip(&self.sin))
            .map(|(c, s)| (-alpha * c - f * beta * s) / two_pi)
            .collect();
        // One contiguous array per sign, so that the pass over the nodes
        // for each point vectorises: as `[f64; 2]` pairs it did not, and a
        // safe-state search's set-up took twice the instructions.
        let n = self.sin.len();
        let (mut forward, mut backward) = (vec![f64::INFINITY; n], vec![f64::INFINITY; n]);
        for point in points {
            let loads = self.material.to_loads(point);
            let (radial, torque) = (loads.radial, loads.torque / two_pi);
            let (lift, drop) = (f + torque, f - torque);
            for (m, a) in forward.iter_mut().zip(&plus) {
                *m = m.min(lift + radial * a);
            }
            for (m, b) in backward.iter_mut().zip(&minus) {
                *m = m.min(drop + radial * b);
            }
        }
        forward
            .into_iter()
            .zip(backward)
            .map(|(a, b)| [a, b])
            .collect()
    }

    /// Residual pressure `H g`.
    pub fn residual_pressure(&self) -> &[f64] {
        &self.residual_pressure
    }

    /// Residual shear `-|D| g`.
    pub fn residual_shear(&self) -> &[f64] {
        &self.residual_shear
    }

    /// The operators `H` and `|D|` on the contact's nodes.
    pub fn operators(&self) -> &std::sync::Arc<Operators> {
        &self.ops
    }

    /// The material (friction and elastic constants).
    pub fn material(&self) -> &Material {
        &self.material
    }
    /// Number of nodes `N`.
    pub fn nodes(&self) -> usize {
        self.slip.len()
    }
    /// The load point the contact is at.
    pub fn load(&self) -> LoadPoint {
        self.load
    }
    /// Locked-in slip `g(theta_j)`.
    pub fn slip(&self) -> &[f64] {
        &self.slip
    }
    /// Pressure `p(theta_j)` (scaled by `p0`).
    pub fn pressure(&self) -> &[f64] {
        &self.pressure
    }
    /// Shear traction `q(theta_j)` (scaled by `p0`).
    pub fn shear(&self) -> &[f64] {
        &self.shear
    }
    /// Slip set and directions of the last increment.
    pub fn directions(&self) -> &[SlipDirection] {
        &self.directions
    }
    /// Rigid rotation: the mean of `g` (its `n = 0` mode).
    pub fn rotation(&self) -> f64 {
        self.slip.iter().sum::<f64>() / self.slip.len() as f64
    }
}
