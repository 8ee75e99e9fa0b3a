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
//! [`Contact`]'s data and its methods live in this folder: the state, its
//! accessors and the finite step here, the exact path-following increment
//! ([`Contact::advance`]) and its engine in [`increment`].

use std::f64::consts::PI;

mod increment;
use super::inverse::SetInverse;
use super::kernels::DenseLu;
use super::operators::{FftScratch, Operators};
use super::tolerances::{DG_TOL, GROSS_TOL, TRACTION_TOL};
use crate::model::{LoadPoint, Material};
use increment::Engine;
pub use increment::{ContactEvent, ContactEventKind, Increment};

/// Direction of slip at one node during the last increment, named as the
/// paper names it (model.md section 1.3): **forward** slip is `dh > 0`, that
/// is `dg < 0` (`g` is proportional to `-h`), with `q = -f p`: the disc
/// moves clockwise relative to the plate, the way a positive torque drives
/// it. It is the direction of the ratchet at the paper's points B and C.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SlipDirection {
    /// No slip.
    #[default]
    Stick,
    /// The paper's forward slip: `dh > 0`, `dg < 0`, `q = -f p`.
    Forward,
    /// The paper's backward slip: `dh < 0`, `dg > 0`, `q = +f p`.
    Backward,
}

impl SlipDirection {
    /// The sign of `dg` for this direction: `-1` forward, `+1` backward,
    /// `0` for stick (it is also the sign of `q` at the friction limit).
    pub fn sign(self) -> f64 {
        match self {
            SlipDirection::Stick => 0.0,
            SlipDirection::Backward => 1.0,
            SlipDirection::Forward => -1.0,
        }
    }
    /// The direction whose `dg` has the sign of `s`.
    pub(crate) fn from_sign(s: f64) -> Self {
        if s > 0.0 {
            SlipDirection::Backward
        } else {
            SlipDirection::Forward
        }
    }
    /// `+1` for forward slip, `-1` for backward, `0` for stick: the paper's
    /// sense, as the slip-map CSV writes it.
    pub fn paper_sign(self) -> i8 {
        match self {
            SlipDirection::Stick => 0,
            SlipDirection::Forward => 1,
            SlipDirection::Backward => -1,
        }
    }
    /// Whether the node slips.
    pub fn is_slipping(self) -> bool {
        self != SlipDirection::Stick
    }
}

/// A physical end of the contact problem within an increment: the load
/// cannot go further along its path. These are outcomes of the physics
/// (the stepper reports them as [`crate::stepping::Outcome`]s), not failures.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactEnd {
    /// `|y|` reached `2 pi`: the friction torque cannot grow further and the
    /// whole interface slides (model.md section 2).
    GrossSlip {
        /// Where it happened.
        load: LoadPoint,
    },
    /// The pressure reached zero at a node.
    Separation {
        /// Where it happened.
        load: LoadPoint,
        /// The node that separated.
        node: usize,
        /// Its angle.
        theta: f64,
        /// Its pressure (at most 0).
        pressure: f64,
    },
}

impl std::fmt::Display for ContactEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ContactEnd::GrossSlip { load } => {
                write!(f, "gross slip at load point {load}: the whole interface slides")
            }
            ContactEnd::Separation {
                load,
                node,
                theta,
                pressure,
            } => write!(
                f,
                "separation at load point {load}: p = {pressure:.4} at theta = {theta:.4} rad (node {node})"
            ),
        }
    }
}

/// What [`Contact::advance`] reached.
#[derive(Debug, Clone, PartialEq)]
pub enum Advanced {
    /// The target load point, with the friction law satisfied on the way.
    Reached,
    /// A physical end on the way; the contact is left at that point
    /// ([`Increment::reached`] tells how far along the segment).
    Ended(ContactEnd),
    /// Stopped at an event (entry into slip, advancing stick) short of the
    /// target, as [`Contact::set_pause_at_events`] asked. The contact is
    /// left at the event's load point with the slip set decided there;
    /// advancing to the same target again goes on along the same segment.
    Paused,
}

impl Advanced {
    /// Whether the target was reached.
    pub fn is_reached(&self) -> bool {
        matches!(self, Advanced::Reached)
    }
}

/// What [`Contact::solve`] found for one finite increment.
#[derive(Debug, Clone)]
pub enum Solved {
    /// The increment's solution, to [`Contact::commit`].
    Trial(Trial),
    /// A physical end: the increment has no frictional solution.
    Ended(ContactEnd),
}

impl Solved {
    /// The trial, or `None` at a physical end.
    pub fn trial(self) -> Option<Trial> {
        match self {
            Solved::Trial(t) => Some(t),
            Solved::Ended(_) => None,
        }
    }
}

/// A numerical failure of the contact solver (the physical ends are
/// [`ContactEnd`]s, not errors).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ContactError {
    /// The active set did not settle.
    #[error("active set did not settle at load point {load} after {iterations} iterations")]
    NotSettled {
        /// Where it happened.
        load: LoadPoint,
        /// Iterations tried.
        iterations: usize,
    },
}

pub(super) fn most_negative(p: &[f64]) -> Option<(usize, f64)> {
    p.iter()
        .copied()
        .enumerate()
        .filter(|(_, v)| *v < 0.0)
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Whether two slip sets with directions are the same. A branch-free pass
/// over the direction codes: slice `==` on an enum compares element by
/// element with an early exit, which does not vectorise, and the increment
/// asks at every event.
pub(super) fn same_directions(a: &[SlipDirection], b: &[SlipDirection]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .fold(0u8, |acc, (&x, &y)| acc | (x as u8 ^ y as u8))
            == 0
}

/// The nodes at which two slip sets' directions differ, appended to `out`
/// in node order.
pub(super) fn push_differences(a: &[SlipDirection], b: &[SlipDirection], out: &mut Vec<usize>) {
    debug_assert_eq!(a.len(), b.len());
    let differ = a.iter().zip(b).enumerate().filter(|(_, (x, y))| x != y);
    out.extend(differ.map(|(j, _)| j));
}

/// `x` with `(-|D| - f diag(s) H)_SS x = rhs` for the slip set `set`
/// (nodes and signs `s`), by a fresh LU with partial pivoting of the
/// `k x k` reduced matrix. The finite step is the fallback of the exact
/// increment and the public one-step solve, not a hot path: a fresh
/// factorisation each pass is the simple way, and the path-following
/// increment keeps its own low-rank updated inverse ([`SetInverse`]).
fn solve_reduced(
    lu: &mut DenseLu,
    ops: &Operators,
    friction: f64,
    set: &[(usize, f64)],
    rhs: &[f64],
    x: &mut [f64],
) {
    let k = set.len();
    lu.reserve(ops.nodes());
    for (b, &(col, _)) in set.iter().enumerate() {
        let hcol = ops.hilbert_col(col);
        let dcol = ops.abs_derivative_col(col);
        let out = &mut lu.lu[b * k..(b + 1) * k];
        for (o, &(row, sign)) in out.iter_mut().zip(set) {
            *o = -dcol[row] - friction * sign * hcol[row];
        }
    }
    lu.factorise(k);
    x.copy_from_slice(rhs);
    lu.solve(x);
}

/// A hash of a slip set with directions, to notice a cycling active set.
pub(super) fn fingerprint(dirs: &[SlipDirection]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    dirs.hash(&mut h);
    h.finish()
}

/// Where a trial slip set would hold every node off the torque limit, one
/// node is held stuck instead, and if that fails the next: at most this
/// many in one search (model.md section 3.2, "Every node at the limit").
pub(super) const MAX_HELD: usize = 8;

/// Whether `y` is on the torque limit `|y| = 2 pi` (to [`GROSS_TOL`]).
pub(super) fn on_the_torque_limit(y: f64) -> bool {
    y.abs() >= 2.0 * PI * (1.0 - GROSS_TOL)
}

/// The node to hold stuck where a trial set would hold every node off the
/// torque limit: of `slipping` (node, how fast it slips or how far it is
/// past the limit), the least, among nodes not `held` already.
///
/// With every node slipping, the slip rates are fixed only up to a rigid
/// rotation, which changes no traction, so the `N` equations of the set
/// have `N - 1` effective unknowns and in general no solution: some node
/// must stick. Where the last stick node reaches the limit beside a zone
/// slipping the other way, the stick zone moves over by a node: the
/// neighbour on the other side, the slowest node of that zone, sticks.
pub(super) fn node_to_hold(
    slipping: impl Iterator<Item = (usize, f64)>,
    held: &[usize],
) -> Option<usize> {
    slipping
        .filter(|(j, _)| !held.contains(j))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(j, _)| j)
}

/// The result of solving one increment, not yet committed.
#[derive(Debug, Clone)]
pub struct Trial {
    /// The load point the increment ends at.
    pub load: LoadPoint,
    /// `dg` at every node.
    pub slip_increment: Vec<f64>,
    /// `p` at every node at the end of the increment.
    pub pressure: Vec<f64>,
    /// `q` at every node at the end of the increment.
    pub shear: Vec<f64>,
    /// How each node slipped during the increment.
    pub directions: Vec<SlipDirection>,
    /// `1/2 int q dg dtheta` over this increment (>= 0).
    pub dissipation: f64,
    /// Active-set iterations taken.
    pub iterations: usize,
    /// Factorisations computed (the rest reused the cached one).
    pub factorisations: usize,
}

impl Trial {
    /// Nodes that slipped before this increment and stick after it.
    pub fn advancing_stick(&self, before: &[SlipDirection]) -> Vec<usize> {
        before
            .iter()
            .zip(&self.directions)
            .enumerate()
            .filter(|(_, (b, a))| b.is_slipping() && !a.is_slipping())
            .map(|(j, _)| j)
            .collect()
    }
}

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

    /// Solve the increment to `load` in one finite step, without
    /// committing it (model.md section 3.2): the active-set iteration from
    /// the last increment's slip set. Events inside the step are not
    /// located ([`Contact::advance`] finds them exactly).
    ///
    /// It ends in [`ContactEnd::GrossSlip`] only where every node slips and
    /// `load` is on or past the torque limit `|y| = 2 pi` (reported at
    /// `load`, not at the crossing); off it, a node is held stuck where a
    /// trial set would hold every node. [`ContactEnd::Separation`] is
    /// reported where the solution makes `p < 0`, and
    /// [`ContactError::NotSettled`] where the iteration finds no consistent
    /// set (a shorter step then helps).
    ///
    /// # Examples
    ///
    /// ```
    /// use shakedown::contact::Solved;
    /// use shakedown::stepping::operators;
    /// use shakedown::{Contact, ContactEnd, Discretisation, LoadPoint, Material};
    ///
    /// let mut contact = Contact::new(Material::paper(), operators(&Discretisation::default()));
    /// // Past the stick diamond |x| + |y| <= 2 pi some nodes slip.
    /// let Ok(Solved::Trial(trial)) = contact.solve(LoadPoint::new(1.0, 5.8)) else {
    ///     panic!("a partial slip step settles");
    /// };
    /// assert!(trial.directions.iter().any(|d| d.is_slipping()));
    /// contact.commit(trial);
    /// // Past |y| = 2 pi the whole interface slides.
    /// let end = contact.solve(LoadPoint::new(1.0, 7.0)).unwrap();
    /// assert!(matches!(end, Solved::Ended(ContactEnd::GrossSlip { .. })));
    /// ```
    pub fn solve(&mut self, load: LoadPoint) -> Result<Solved, ContactError> {
        let n = self.nodes();
        let f = self.material.friction();
        let mut w = self
            .work
            .take()
            .unwrap_or_else(|| Box::new(Workspace::new(n)));
        let result = self.solve_with(load, f, n, &mut w);
        self.work = Some(w);
        result
    }

    pub(super) fn solve_with(
        &self,
        load: LoadPoint,
        f: f64,
        n: usize,
        w: &mut Workspace,
    ) -> Result<Solved, ContactError> {
        self.tractions_into(load, &mut w.p0, &mut w.q0);
        if let Some((node, pressure)) = most_negative(&w.p0) {
            return Ok(Solved::Ended(self.separation(load, node, pressure)));
        }

        // Warm start: last increment's slip set plus every predictor violation.
        let mut dirs = self.directions.clone();
        for ((d, &q0), &p0) in dirs.iter_mut().zip(&w.q0).zip(&w.p0) {
            if q0.abs() > f * p0 + TRACTION_TOL {
                *d = SlipDirection::from_sign(q0);
            }
        }

        let max_iterations = 4 * n + 20;
        let mut seen: Vec<u64> = Vec::new();
        let mut held: Vec<usize> = Vec::new();
        let mut factorisations = 0;
        let mut dg = vec![0.0f64; n];
        let mut p = w.p0.clone();
        let mut q = w.q0.clone();
        for iteration in 1..=max_iterations {
            w.set.clear();
            w.set.extend(
                (0..n)
                    .filter(|&j| dirs[j].is_slipping())
                    .map(|j| (j, dirs[j].sign())),
            );
            if w.set.len() == n {
                if on_the_torque_limit(load.y()) {
                    return Ok(Solved::Ended(ContactEnd::GrossSlip { load }));
                }
                // Off the torque limit not every node can slip: hold the
                // slowest node of the last pass (before any pass, the node
                // least past the limit) and try again; `node_to_hold`.
                let passed = dg.iter().any(|&d| d != 0.0);
                let slipping =
                    w.set
                        .iter()
                        .filter(|&&(j, _)| !passed || dg[j] != 0.0)
                        .map(|&(j, _)| {
                            let key = if passed {
                                dg[j].abs()
                            } else {
                                w.q0[j].abs() - f * w.p0[j]
                            };
                            (j, key)
                        });
                match node_to_hold(slipping, &held) {
                    Some(j) if held.len() < MAX_HELD => {
                        dirs[j] = SlipDirection::Stick;
                        held.push(j);
                        continue;
                    }
                    _ => break,
                }
            }
            dg.fill(0.0);
            p.copy_from_slice(&w.p0);
            q.copy_from_slice(&w.q0);
            if !w.set.is_empty() {
                let k = w.set.len();
                for (r, &(j, s)) in w.rhs.iter_mut().zip(&w.set) {
                    *r = -(w.q0[j] - s * f * w.p0[j]);
                }
                solve_reduced(
                    &mut w.reduced,
                    &self.ops,
                    f,
                    &w.set,
                    &w.rhs[..k],
                    &mut w.x[..k],
                );
                factorisations += 1;
                for (&d, &(col, _)) in w.x[..k].iter().zip(&w.set) {
                    if !d.is_finite() {
                        return Err(ContactError::NotSettled {
                            load,
                            iterations: iteration,
                        });
                    }
                    dg[col] = d;
                }
                self.ops
                    .apply_both(&dg, &mut w.pressure_change, &mut w.relief, &mut w.fft);
                for j in 0..n {
                    p[j] = w.p0[j] + w.pressure_change[j];
                    q[j] = w.q0[j] - w.relief[j];
                }
            }

            let scale = w.set.iter().map(|&(j, _)| dg[j].abs()).fold(0.0, f64::max);
            let mut changed = false;
            for &(j, _) in &w.set {
                if dirs[j].sign() * dg[j] < -DG_TOL * scale {
                    dirs[j] = SlipDirection::Stick;
                    changed = true;
                }
            }
            // A node released in this pass still carries its dg here; it comes
            // back next pass if its traction then asks for it.
            for j in 0..n {
                if dg[j] == 0.0 && !dirs[j].is_slipping() && q[j].abs() > f * p[j] + TRACTION_TOL {
                    dirs[j] = SlipDirection::from_sign(q[j]);
                    changed = true;
                }
            }
            if !changed {
                if let Some((node, pressure)) = most_negative(&p) {
                    return Ok(Solved::Ended(self.separation(load, node, pressure)));
                }
                let directions: Vec<SlipDirection> = (0..n)
                    .map(|j| {
                        if dirs[j].is_slipping() && dg[j] != 0.0 {
                            SlipDirection::from_sign(dg[j])
                        } else {
                            SlipDirection::Stick
                        }
                    })
                    .collect();
                let dtheta = 2.0 * PI / n as f64;
                // q dg = f p |dg| on slip nodes; averaging the pressure at the
                // start (old load) and end of the increment makes the sum
                // second order in the increment.
                let dissipation: f64 = (0..n)
                    .filter(|&j| dg[j] != 0.0)
                    .map(|j| 0.5 * f * 0.5 * (p[j] + self.pressure[j]) * dg[j].abs())
                    .sum::<f64>()
                    * dtheta;
                return Ok(Solved::Trial(Trial {
                    load,
                    slip_increment: dg,
                    pressure: p,
                    shear: q,
                    directions,
                    dissipation,
                    iterations: iteration,
                    factorisations,
                }));
            }
            // Most increments settle in one to three passes; only a longer
            // search is watched for revisiting a slip set (a cycle).
            if iteration > 4 {
                let h = fingerprint(&dirs);
                if seen.contains(&h) {
                    break;
                }
                seen.push(h);
            }
        }
        Err(ContactError::NotSettled {
            load,
            iterations: max_iterations.min(seen.len() + 5),
        })
    }

    /// Tractions at `load` with the current slip, into the given buffers.
    pub(super) fn tractions_into(&self, load: LoadPoint, p: &mut [f64], q: &mut [f64]) {
        let loads = self.material.to_loads(load);
        let two_pi = 2.0 * PI;
        let pr = self.material.beta() * loads.radial / two_pi;
        let qr = self.material.alpha() * loads.radial / two_pi;
        let qt = loads.torque / two_pi;
        for j in 0..p.len() {
            p[j] = 1.0 - pr * self.sin[j] + self.residual_pressure[j];
            q[j] = -qt - qr * self.cos[j] + self.residual_shear[j];
        }
    }

    pub(super) fn separation(&self, load: LoadPoint, node: usize, pressure: f64) -> ContactEnd {
        ContactEnd::Separation {
            load,
            node,
            theta: 2.0 * PI * node as f64 / self.nodes() as f64,
            pressure,
        }
    }

    /// Commit a solved increment.
    pub fn commit(&mut self, trial: Trial) {
        self.forget_clearance();
        if trial.slip_increment.iter().any(|&d| d != 0.0) {
            for (g, d) in self.slip.iter_mut().zip(&trial.slip_increment) {
                *g += d;
            }
            let (p_el, q_el) = self.elastic_tractions(trial.load);
            for j in 0..self.nodes() {
                self.residual_pressure[j] = trial.pressure[j] - p_el[j];
                self.residual_shear[j] = trial.shear[j] - q_el[j];
            }
        }
        self.load = trial.load;
        self.pressure = trial.pressure;
        self.shear = trial.shear;
        if self.directions != trial.directions {
            self.invalidate_responses();
        }
        self.directions = trial.directions;
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::{push_differences, same_directions, SlipDirection};
    use proptest::prelude::*;

    /// Any of the three directions of a node.
    pub(in crate::contact) fn direction() -> impl Strategy<Value = SlipDirection> {
        prop_oneof![
            Just(SlipDirection::Stick),
            Just(SlipDirection::Forward),
            Just(SlipDirection::Backward),
        ]
    }

    proptest! {
        /// The branch-free comparison agrees with slice equality, on equal
        /// sets, sets that differ at one node, and sets of other lengths.
        #[test]
        fn same_directions_is_slice_equality(
            a in proptest::collection::vec(direction(), 0..300),
            at in any::<prop::sample::Index>(),
            other in direction(),
            b in proptest::collection::vec(direction(), 0..300),
        ) {
            prop_assert!(same_directions(&a, &a));
            let mut changed = a.clone();
            if !changed.is_empty() {
                let j = at.index(changed.len());
                changed[j] = other;
            }
            prop_assert_eq!(same_directions(&a, &changed), a == changed);
            prop_assert_eq!(same_directions(&a, &b), a == b);
        }

        /// The differences are the nodes where the sets differ, in node
        /// order, after what the list held: for sets that differ at a few
        /// nodes (as at an event) and for unrelated sets, of any length.
        #[test]
        fn push_differences_lists_the_differing_nodes(
            a in proptest::collection::vec(direction(), 0..300),
            changes in proptest::collection::vec((any::<prop::sample::Index>(), direction()), 0..6),
            b in proptest::collection::vec(direction(), 0..300),
        ) {
            let mut changed = a.clone();
            if !changed.is_empty() {
                for (at, d) in &changes {
                    let j = at.index(changed.len());
                    changed[j] = *d;
                }
            }
            // `b` at the length of `a` (`a` itself where `b` is empty).
            let b: Vec<SlipDirection> = (0..a.len())
                .map(|j| if b.is_empty() { a[j] } else { b[j % b.len()] })
                .collect();
            for other in [&changed, &b] {
                let expected: Vec<usize> = (0..a.len()).filter(|&j| a[j] != other[j]).collect();
                let mut out = vec![usize::MAX];
                push_differences(&a, other, &mut out);
                prop_assert_eq!(out[0], usize::MAX);
                prop_assert_eq!(&out[1..], &expected[..]);
            }
        }

        /// The least elastic margins from the affine form agree with the
        /// tractions at each point.
        #[test]
        fn least_elastic_margins_are_the_least_over_the_points(
            points in proptest::collection::vec((-9.0..9.0f64, -9.0..9.0f64), 1..20),
            friction in 0.05..0.8f64,
        ) {
            use crate::model::{LoadPoint, Material, Plane};
            let material = Material::new(friction, 0.3, Plane::Strain).unwrap();
            let contact = super::Contact::new(material, std::sync::Arc::new(crate::contact::Operators::new(32)));
            let loads: Vec<LoadPoint> = points.iter().map(|&(x, y)| LoadPoint::new(x, y)).collect();
            let least = contact.least_elastic_margins(loads.iter().copied());
            for j in 0..32 {
                let mut expected = [f64::INFINITY; 2];
                for &load in &loads {
                    let (p, q) = contact.elastic_tractions(load);
                    expected[0] = expected[0].min(friction * p[j] - q[j]);
                    expected[1] = expected[1].min(friction * p[j] + q[j]);
                }
                for s in 0..2 {
                    prop_assert!((least[j][s] - expected[s]).abs() < 1e-12, "{j} {s}: {} {}", least[j][s], expected[s]);
                }
            }
        }
    }
}
