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

use super::{
    fingerprint, push_differences, same_directions, Advanced, Contact, ContactEnd, ContactError,
    SlipDirection, Solved, Workspace,
};
use super::{node_to_hold, on_the_torque_limit, MAX_HELD};
use crate::contact::cache::{self, ResponseCache, SetKey};
use crate::contact::kernels::{self, at_limit, end_margins, event_times, rate_extremes};
use crate::contact::operators::{FftScratch, Operators};
use crate::contact::tolerances::{
    CLEARANCE_SLACK, DG_TOL, EVENT_TIES, RATE_TOL, SCREEN, TRACTION_TOL,
};
use crate::model::LoadPoint;

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
    /// What happened.
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
    /// The segment's start point.
    pub from: LoadPoint,
    /// The segment's end point.
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
    /// Whether any node slipped (`forward` and `backward` are zero if not).
    pub slipped: bool,
    /// Whether the slip set or a direction changed.
    pub set_changed: bool,
    /// Rate problems solved.
    pub rate_solves: usize,
    /// LU factorisations computed.
    pub factorisations: usize,
    /// The increment (or its rest) was solved by the finite-step active-set
    /// iteration because the rate problem did not settle.
    pub fallback: bool,
    /// `forward` and `backward` still hold the last increment's slip: the
    /// first move of this one that slips sets them (in its pass over the
    /// nodes) instead of a pass that clears them first; [`Contact::advance`]
    /// clears them if none does.
    stale: bool,
    /// Node lists of earlier increments' events, emptied, for the next
    /// events to reuse: an event then allocates nothing once a run is under
    /// way.
    spare: Vec<Vec<usize>>,
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
            stale: false,
            spare: Vec::new(),
        }
    }

    /// An empty node list, reusing one of an earlier event if there is one.
    /// A new one has room for every node, so that no list grows later.
    fn node_list(&mut self) -> Vec<usize> {
        let n = self.forward.len();
        self.spare.pop().unwrap_or_else(|| Vec::with_capacity(n))
    }

    /// Clear `forward` and `backward` if they hold an earlier increment's
    /// slip.
    fn clear_stale(&mut self) {
        if std::mem::take(&mut self.stale) {
            self.forward.fill(0.0);
            self.backward.fill(0.0);
        }
    }

    /// Add slip `dg` of node `j` to `forward` / `backward`.
    fn add_slip(&mut self, j: usize, dg: f64) {
        self.clear_stale();
        if dg > 0.0 {
            self.forward[j] += dg;
            self.slipped = true;
        } else if dg < 0.0 {
            self.backward[j] -= dg;
            self.slipped = true;
        }
    }

    fn reset(&mut self, from: LoadPoint, to: LoadPoint) {
        self.from = from;
        self.to = to;
        self.reached = 0.0;
        self.dissipation = 0.0;
        self.segments = 0;
        for event in self.events.drain(..) {
            let mut nodes = event.nodes;
            nodes.clear();
            self.spare.push(nodes);
        }
        self.stale |= self.slipped;
        self.slipped = false;
        self.set_changed = false;
        self.rate_solves = 0;
        self.factorisations = 0;
        self.fallback = false;
    }
}

/// `[hpx, hpy, hqx, hqy]` ([`Engine::responses`]) from `own`, or, for an
/// axis that `lent` gives a start in `pool`, `H g'` then `-|D| g'` there.
fn lent_or_own<'a>(
    pool: &'a [f64],
    lent: [Option<usize>; 2],
    own: [&'a [f64]; 4],
) -> [&'a [f64]; 4] {
    let [mut hpx, mut hpy, mut hqx, mut hqy] = own;
    let n = hpx.len();
    if let Some(at) = lent[0] {
        (hpx, hqx) = (&pool[at..at + n], &pool[at + n..at + 2 * n]);
    }
    if let Some(at) = lent[1] {
        (hpy, hqy) = (&pool[at..at + n], &pool[at + n..at + 2 * n]);
    }
    [hpx, hpy, hqx, hqy]
}

/// Total pressure and shear per unit of the axis `(ux, uy)`: its elastic
/// part from those per unit `x` and `y` (`[epx, epy, eqx, eqy]`), plus the
/// residual `[H g', -|D| g']`.
fn add_totals(
    [tp, tq]: [&mut [f64]; 2],
    (ux, uy): (f64, f64),
    [epx, epy, eqx, eqy]: [&[f64]; 4],
    [hp, hq]: [&[f64]; 2],
) {
    kernels::combine_plus(tp, ux, epx, uy, epy, hp);
    kernels::combine_plus(tq, ux, eqx, uy, eqy, hq);
}

/// Cached responses of one slip set and the scratch of the increment.
#[derive(Clone)]
pub(crate) struct Engine {
    /// Whether the responses belong to `dirs`.
    valid: bool,
    /// The slip set of the cached responses, and as `(node, sign)`.
    dirs: Vec<SlipDirection>,
    set: Vec<(usize, f64)>,
    /// The set as the response cache knows it, made from `set` for each
    /// lookup ([`SetKey::set_to`]).
    key: SetKey,
    /// Scratch of a change of set: the nodes whose direction changes.
    changes: Vec<usize>,
    /// The two load directions of the responses: `u1` the direction of the
    /// segment on which the set was decided, `u2` its perpendicular (the
    /// fields named `..x` / `..y` below hold the responses to `u1` / `u2`).
    /// The response to `u2` is computed only when the set outlives the
    /// segment's direction (`have2`).
    u1: (f64, f64),
    have2: bool,
    /// Slip rates on the set per unit `u1` and `u2` (zero elsewhere).
    gx: Vec<f64>,
    gy: Vec<f64>,
    /// Residual pressure `H g'` and shear `-|D| g'` per unit `u1` and `u2`,
    /// unless `lent` says where in the cache's pool they are.
    hpx: Vec<f64>,
    hpy: Vec<f64>,
    hqx: Vec<f64>,
    hqy: Vec<f64>,
    /// Per axis, the start in the cache's pool of the kept `H g'` then
    /// `-|D| g'` that a hit gave, read there instead of copied out (the
    /// copy was 4 % of the Fig. 3 map's time, from memory the pool holds in
    /// L3). The pool's numbers move only at an eviction or a compaction
    /// ([`ResponseCache::pool`]): an insert follows a miss, after the change
    /// of set that cleared these, and the response to `u2` added to a lent
    /// entry copies them out first if it would evict.
    lent: [Option<usize>; 2],
    /// Elastic pressure and shear per unit `x` and `y`.
    epx: Vec<f64>,
    epy: Vec<f64>,
    eqx: Vec<f64>,
    eqy: Vec<f64>,
    elastic_ready: bool,
    /// Total pressure and shear (elastic + residual) per unit `u1` and `u2`.
    tpx: Vec<f64>,
    tpy: Vec<f64>,
    tqx: Vec<f64>,
    tqy: Vec<f64>,
    /// Whether a node sticks in the cached set, and its slip sign (0 if it
    /// sticks).
    stick: Vec<bool>,
    sgn: Vec<f64>,
    /// 0 on stick nodes, infinity on slip nodes (their slack is not watched).
    off: Vec<f64>,
    /// The end margins of the segment being scanned.
    margins: Vec<f64>,
    /// Slip rates along the current segment at every node (0 off the set).
    rg: Vec<f64>,
    /// The coefficients `(a1, a2)` that `rg` was combined for from the
    /// present `gx` and `gy`; `None` once either changes. A rate problem
    /// begins, and the segment after it begins, with the combination just
    /// made: two passes over the nodes per event that need not be made.
    rg_for: Option<(f64, f64)>,
    /// `(max |rg|, min sgn rg)` of the present `rg` and signs, once asked
    /// for ([`Engine::rate_extremes`]): a settled rate problem and the scan
    /// of the segment after it ask for the same.
    rg_extremes: Option<(f64, f64)>,
    /// `(max |gx|, min sgn gx)`: the extremes of the rates per unit `u1`,
    /// from which those of `rg = a1 gx` follow exactly for any `a1 > 0`
    /// ([`Engine::rate_extremes`]).
    gx_extremes: Option<(f64, f64)>,
    /// The rates' extremes for the direction of the last segment whose
    /// scan looked at them ([`Engine::rates_against`]), and `max |gy|`
    /// (`max |gx|` is in `gx_extremes`).
    rates_seen: Option<RatesSeen>,
    gy_scale: Option<f64>,
    /// Test only: the passes over the rates and the end margins that the
    /// bounds spared.
    #[cfg(feature = "counters")]
    pub(crate) spared: [usize; 2],
    /// Per axis (`u1`, `u2`), the fastest any node's end margin can fall
    /// per unit of load along it ([`kernels::reach`]), once asked for: it
    /// follows the totals and the set.
    reach: [Option<f64>; 2],
    /// A lower bound on every node's end margin at the contact's present
    /// state, and the load point it holds at: the lowest end margin of the
    /// last segment, less the round-off in which the move there and the
    /// margins can differ ([`Contact::scan`]). Kept only while the state
    /// and the set are those it was taken for.
    clearance: Option<(LoadPoint, f64)>,
    /// Rate-problem scratch.
    trial: Vec<SlipDirection>,
    /// The stick nodes at the friction limit at the rate problem's point.
    candidates: Vec<usize>,
    before: Vec<SlipDirection>,
    seen: Vec<u64>,
    /// Nodes held stuck where a trial set would hold every node.
    held: Vec<usize>,
    full: Vec<f64>,
    /// Slip rates of recently seen sets, and the entry of the current one.
    cache: ResponseCache,
    slot: Option<usize>,
}

impl Engine {
    /// Make `trial` the set: `dirs`, `set` and the per-node views `stick`,
    /// `sgn` and `off` follow it.
    ///
    /// A set changes by a node or two at a time, so only the nodes whose
    /// direction changes are visited. A few changes are edited
    /// into the set where they belong (a binary search and a short move
    /// each); merging the whole set with them, as before, was a fifteenth
    /// of a sweep's time. Many changes at once make the set afresh from the
    /// directions.
    fn change_set_to_trial(&mut self) {
        /// Past this many changes one pass over the directions is cheaper
        /// than an edit per change.
        const FEW: usize = 8;
        let mut changes = std::mem::take(&mut self.changes);
        changes.clear();
        push_differences(&self.dirs, &self.trial, &mut changes);
        // The watched nodes and the signs may change below.
        self.forget_bounds();
        if changes.len() > FEW {
            self.set.clear();
            let slipping = self
                .trial
                .iter()
                .enumerate()
                .filter(|(_, d)| d.is_slipping());
            self.set.extend(slipping.map(|(j, d)| (j, d.sign())));
        }
        for &j in &changes {
            let d = self.trial[j];
            let slips = d.is_slipping();
            if changes.len() <= FEW {
                let at = self.set.partition_point(|&(i, _)| i < j);
                let present = self.set.get(at).is_some_and(|&(i, _)| i == j);
                match (present, slips) {
                    (true, true) => self.set[at].1 = d.sign(),
                    (true, false) => {
                        self.set.remove(at);
                    }
                    (false, true) => self.set.insert(at, (j, d.sign())),
                    (false, false) => {}
                }
            }
            self.dirs[j] = d;
            self.stick[j] = !slips;
            self.sgn[j] = if slips { d.sign() } else { 0.0 };
            self.off[j] = if slips { f64::INFINITY } else { 0.0 };
        }
        self.changes = changes;
    }

    /// The load direction `u1` (axis 0) or `u2` (axis 1).
    fn axis(&self, axis: usize) -> (f64, f64) {
        let (ux, uy) = self.u1;
        if axis == 0 {
            (ux, uy)
        } else {
            (-uy, ux)
        }
    }

    /// `(max |rg|, min sgn rg)` over the nodes: the largest slip rate
    /// along the segment and the most negative along its slip direction,
    /// in one vectorised pass (the rates and signs are 0 off the set, so
    /// these are the set's; a NaN is skipped, as `f64::max` skips it), and
    /// kept until `rg` or the set changes.
    ///
    /// Along `u1` (`rg = a1 gx` with `a1 > 0`, as on every increment of a
    /// straight run, whose chords differ in their last bits) they are
    /// `a1` times those of `gx`, kept with the set: rounding is monotone,
    /// so the largest `|a1 gx|` and the lowest `a1 sgn gx` are `a1` times
    /// the largest `|gx|` and the lowest `sgn gx`, rounded, to the bit.
    fn rate_extremes(&mut self) -> (f64, f64) {
        if let Some(extremes) = self.rg_extremes {
            return extremes;
        }
        let extremes = match self.rg_for {
            Some((a1, a2)) if a2 == 0.0 && a1 > 0.0 => {
                let (scale, worst) = *self
                    .gx_extremes
                    .get_or_insert_with(|| rate_extremes(&self.gx, &self.sgn));
                (a1 * scale, a1 * worst)
            }
            _ => rate_extremes(&self.rg, &self.sgn),
        };
        self.rg_extremes = Some(extremes);
        extremes
    }

    /// Drop what follows the set, its rates or its totals: the extremes of
    /// the rates, the reach of the margins and the clearance.
    fn forget_bounds(&mut self) {
        self.gx_extremes = None;
        self.rates_seen = None;
        self.gy_scale = None;
        self.reach = [None; 2];
        self.clearance = None;
    }

    /// Slip rates along the segment direction `a1 u1 + a2 u2` at every
    /// node (0 off the set) into `rg`: one vectorised pass, cheaper than
    /// gathering the set when it is a sizeable part of the circle.
    #[inline]
    fn combine(&mut self, a1: f64, a2: f64) {
        if self.rg_for == Some((a1, a2)) {
            return;
        }
        kernels::combine(&mut self.rg, a1, &self.gx, a2, &self.gy);
        self.rg_for = Some((a1, a2));
        self.rg_extremes = None;
    }

    /// Whether a slip rate along `a1 u1 + a2 u2` opposes its node's slip
    /// direction by more than `DG_TOL` of the largest rate (the set must
    /// then be decided anew).
    ///
    /// The answer for the direction of the last segment that asked holds
    /// for a nearby one: the rates move by at most `|da1| max |gx| +
    /// |da2| max |gy|`, and their rounding by a few ulps of the largest, so
    /// if the lowest rate along its direction, lowered by that much, stays
    /// above the threshold for the largest, raised by that much, no rate
    /// can oppose its direction. The increments of a run differ in their
    /// direction by a little (along a straight path, by the rounding of its
    /// chords), so most need neither the rates nor a pass over them; they
    /// move the slip from `gx` and `gy` directly ([`kernels::Slide`]).
    fn rates_against(&mut self, a1: f64, a2: f64, bounded: bool) -> bool {
        // The bound can hold only for a direction within about `DG_TOL` of
        // the last (the lowest rate is clipped at 0, so it has no more
        // room): for others, as round an ellipse, it is not tried, and
        // costs no pass for the largest rates.
        let near = |seen: &RatesSeen| {
            let (b1, b2) = seen.along;
            (a1 - b1).abs() + (a2 - b2).abs() <= DG_TOL * (a1.abs() + a2.abs())
        };
        if let Some(seen) = self.rates_seen.filter(|seen| bounded && near(seen)) {
            let g1 = self.rate_scale(0);
            let g2 = if a2 == 0.0 && seen.along.1 == 0.0 {
                0.0
            } else {
                self.rate_scale(1)
            };
            let (b1, b2) = seen.along;
            let ulps = 4.0 * f64::EPSILON;
            let shift = (a1 - b1).abs() * g1
                + (a2 - b2).abs() * g2
                + ulps * ((a1.abs() + b1.abs()) * g1 + (a2.abs() + b2.abs()) * g2);
            let threshold = -DG_TOL * (seen.scale - shift) * (1.0 - 1e-6);
            if seen.worst - shift >= threshold {
                #[cfg(feature = "counters")]
                {
                    self.spared[0] += 1;
                }
                return false;
            }
        }
        self.combine(a1, a2);
        let (scale, worst) = self.rate_extremes();
        self.rates_seen = Some(RatesSeen {
            along: (a1, a2),
            scale,
            worst,
        });
        worst < -DG_TOL * scale
    }

    /// `max |gx|` (axis 0) or `max |gy|` (axis 1), kept with the set (a
    /// NaN is skipped, as the rates' extremes skip it).
    fn rate_scale(&mut self, axis: usize) -> f64 {
        if axis == 0 {
            return self
                .gx_extremes
                .get_or_insert_with(|| rate_extremes(&self.gx, &self.sgn))
                .0;
        }
        *self
            .gy_scale
            .get_or_insert_with(|| rate_extremes(&self.gy, &self.sgn).0)
    }

    /// The fastest any node's end margin can fall per unit of load along
    /// `u1` (axis 0) or `u2` (axis 1), kept until the totals or the set
    /// change.
    fn reach(&mut self, axis: usize, f: f64) -> f64 {
        let (tp, tq) = if axis == 0 {
            (&self.tpx, &self.tqx)
        } else {
            (&self.tpy, &self.tqy)
        };
        *self.reach[axis].get_or_insert_with(|| kernels::reach(tp, tq, &self.off, f))
    }

    /// Total responses to the direction of `axis`.
    fn totals(&mut self, axis: usize) {
        self.reach[axis] = None;
        let (ux, uy) = self.axis(axis);
        let own = [&self.hpx[..], &self.hpy, &self.hqx, &self.hqy];
        let [hpx, hpy, hqx, hqy] = lent_or_own(self.cache.pool(), self.lent, own);
        let (tp, tq, hp, hq) = if axis == 0 {
            (&mut self.tpx, &mut self.tqx, hpx, hqx)
        } else {
            (&mut self.tpy, &mut self.tqy, hpy, hqy)
        };
        let elastic = [&self.epx[..], &self.epy, &self.eqx, &self.eqy];
        add_totals([tp, tq], (ux, uy), elastic, [hp, hq]);
    }

    /// `H g'` and `-|D| g'` per unit `u1` and `u2`, `[hpx, hpy, hqx, hqy]`:
    /// in place in the cache's pool where a hit lent them.
    fn responses(&self) -> [&[f64]; 4] {
        let own = [&self.hpx[..], &self.hpy, &self.hqx, &self.hqy];
        lent_or_own(self.cache.pool(), self.lent, own)
    }

    /// A clone that holds its responses itself: a clone's cache starts
    /// empty, so what this one's lent is copied out of it.
    pub(super) fn clone_owning(&self) -> Self {
        let mut clone = self.clone();
        clone.own_responses(&self.cache);
        clone
    }

    /// Copy the responses that `cache` lent (this engine's cache, or that
    /// of the engine this one was cloned from) into the engine's own
    /// arrays: before the cache goes or is replaced.
    pub(super) fn own_responses(&mut self, cache: &ResponseCache) {
        let n = self.full.len();
        let pool = cache.pool();
        for (axis, at) in std::mem::take(&mut self.lent).into_iter().enumerate() {
            let Some(at) = at else { continue };
            let (hp, hq) = if axis == 0 {
                (&mut self.hpx, &mut self.hqx)
            } else {
                (&mut self.hpy, &mut self.hqy)
            };
            hp.copy_from_slice(&pool[at..at + n]);
            hq.copy_from_slice(&pool[at + n..at + 2 * n]);
        }
    }

    /// The responses to the direction of `axis` from its slip rates in
    /// `full` (zero off the set): `H g'` and `-|D| g'` by FFT, and totals.
    fn fill_axis(&mut self, ops: &Operators, fft: &mut FftScratch, axis: usize) {
        let u = self.axis(axis);
        self.rg_for = None;
        self.forget_bounds();
        self.lent[axis] = None;
        let (g, hp, hq, tp, tq) = if axis == 0 {
            (
                &mut self.gx,
                &mut self.hpx,
                &mut self.hqx,
                &mut self.tpx,
                &mut self.tqx,
            )
        } else {
            (
                &mut self.gy,
                &mut self.hpy,
                &mut self.hqy,
                &mut self.tpy,
                &mut self.tqy,
            )
        };
        // Straight into place: `H g'`, `|D| g'` negated, and the totals
        // ([`Self::totals`]) in the pass that unpacks the transform.
        self.reach[axis] = None;
        let elastic = [&self.epx[..], &self.epy, &self.eqx, &self.eqy];
        ops.convolve_with(&self.full, fft, |bins| {
            kernels::from_complex_totals(bins, [hp, hq], [tp, tq], u, elastic)
        });
        // `full` is filled afresh before each use: hand its buffer over.
        std::mem::swap(g, &mut self.full);
    }

    /// The responses to the direction of `axis` from its slip rates in
    /// `full` and the kept `H g'` then `-|D| g'` of a cache entry, which
    /// start at `at` in the cache's pool: the numbers [`Self::fill_axis`]
    /// would compute, without the FFT, and read where they are kept.
    fn restore_axis(&mut self, axis: usize, kept: &[f64], at: usize) {
        self.rg_for = None;
        self.forget_bounds();
        let g = if axis == 0 {
            &mut self.gx
        } else {
            &mut self.gy
        };
        // `full` is filled afresh before each use: hand its buffer over.
        std::mem::swap(g, &mut self.full);
        let n = self.full.len();
        let (hp, hq) = kept.split_at(n);
        let (ux, uy) = self.axis(axis);
        let (tp, tq) = if axis == 0 {
            (&mut self.tpx, &mut self.tqx)
        } else {
            (&mut self.tpy, &mut self.tqy)
        };
        let elastic = [&self.epx[..], &self.epy, &self.eqx, &self.eqy];
        add_totals([tp, tq], (ux, uy), elastic, [hp, hq]);
        self.lent[axis] = Some(at);
    }

    pub(super) fn new(n: usize) -> Self {
        let z = || vec![0.0; n];
        Self {
            valid: false,
            u1: (1.0, 0.0),
            have2: false,
            dirs: vec![SlipDirection::Stick; n],
            set: Vec::with_capacity(n),
            key: SetKey::with_capacity(n),
            changes: Vec::with_capacity(n),
            gx: z(),
            gy: z(),
            hpx: z(),
            hpy: z(),
            hqx: z(),
            hqy: z(),
            lent: [None; 2],
            epx: z(),
            epy: z(),
            eqx: z(),
            eqy: z(),
            elastic_ready: false,
            tpx: z(),
            tpy: z(),
            tqx: z(),
            tqy: z(),
            stick: vec![true; n],
            sgn: z(),
            off: z(),
            margins: z(),
            rg: z(),
            rg_for: None,
            rg_extremes: None,
            gx_extremes: None,
            rates_seen: None,
            gy_scale: None,
            #[cfg(feature = "counters")]
            spared: [0; 2],
            reach: [None; 2],
            clearance: None,
            trial: vec![SlipDirection::Stick; n],
            candidates: Vec::with_capacity(n),
            before: vec![SlipDirection::Stick; n],
            seen: Vec::new(),
            held: Vec::with_capacity(MAX_HELD),
            full: z(),
            cache: ResponseCache::new(cache::DEFAULT_BUDGET),
            slot: None,
        }
    }
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
        // The inverse keeps the set's slip rates per unit x and y with it.
        w.inverse.set_loads([&e.epx, &e.eqx, &e.epy, &e.eqy]);
    }

    /// Responses of the slip set `self.directions` to the direction
    /// `(dx, dy)`.
    fn responses(&mut self, w: &mut Workspace, dx: f64, dy: f64) -> Result<(), ContactError> {
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
    fn responses_for_trial(&mut self, w: &mut Workspace, dx: f64, dy: f64) -> bool {
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
    fn axis_response(&mut self, w: &mut Workspace, axis: usize) -> bool {
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
    fn direction_coefficients(
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

    /// The first event in `(0, remaining]` of the segment with the cached
    /// set, or a request to solve the rate problem here first. The segment
    /// runs along `dx u1 + dy u2`; `load_dy` is its change of `y`. With
    /// the stop, a lower bound on every node's end margin where the segment
    /// ends, if the scan took the end margins (the clearance of the next
    /// segment, should this one reach its end).
    fn scan(
        &self,
        w: &mut Workspace,
        dx: f64,
        dy: f64,
        load_dy: f64,
        remaining: f64,
    ) -> (Stop, f64, bool, Option<f64>) {
        let f = self.material.friction();
        let t_min = remaining;
        // Taken here whatever happens: it holds only for the state it was
        // taken at, which this segment leaves.
        let clearance = w.engine.clearance.take();
        // A slip rate against its direction: the set must be decided anew
        // here, and the segment is scanned again after that.
        let bounded = self.bounded();
        if !w.engine.set.is_empty() && w.engine.rates_against(dx, dy, bounded) {
            return (Stop::End, t_min, true, None);
        }
        let (ex, ey) = (remaining * dx, remaining * dy);
        if self.segment_increments == 1 && bounded {
            if let Some((_, c)) = clearance.filter(|&(at, _)| at == self.load) {
                // Every node's end margin is at least the clearance less
                // the most the segment can lower it: if that stays above
                // the screen, the pass over the nodes would find nothing
                // below it and test none, so it need not be made.
                let fall = ex.abs() * w.engine.reach(0, f)
                    + if ey == 0.0 {
                        0.0
                    } else {
                        ey.abs() * w.engine.reach(1, f)
                    };
                let ahead = c - fall * (1.0 + CLEARANCE_SLACK) - CLEARANCE_SLACK;
                if ahead >= SCREEN {
                    #[cfg(feature = "counters")]
                    {
                        w.engine.spared[1] += 1;
                    }
                    let (stop, t, need_rates) = self.gross_or(Stop::End, t_min, false, load_dy);
                    return (stop, t, need_rates, Some(ahead));
                }
            }
        }
        let mut margins = std::mem::take(&mut w.engine.margins);
        let e = &w.engine;
        let mut t_min = t_min;
        let mut stop = Stop::End;
        let mut need_rates = false;
        let n = e.tpx.len();
        let (p, q) = (&self.pressure[..n], &self.shear[..n]);
        let (tpx, tpy, tqx, tqy) = (&e.tpx[..n], &e.tpy[..n], &e.tqx[..n], &e.tqy[..n]);
        let v = [p, q, tpx, tpy, tqx, tqy, &e.off[..n]];
        // A branch-free pass over the nodes gives each a number, and the
        // nodes whose number is below `bound` take the exact test, in node
        // order. Most often that is the end margin, and nothing is below
        // the screen (no node can reach an event on the segment). On a
        // straight run of increments, though, most stick nodes would reach
        // the limit by the end of so long a segment: there the number is
        // the node's first event, and only the nodes within round-off of the
        // earliest take the exact test, which finds the same event at the
        // same parameter as testing every node would. A node at the limit
        // with its slack falling (-1 there) goes by its end margin.
        let mut lowest = -1.0;
        let mut bound = 0.0;
        if self.segment_increments > 1 {
            lowest = event_times(v, [dx, dy, remaining], f, RATE_TOL, &mut margins[..n]);
            bound = if lowest < remaining + remaining * EVENT_TIES {
                lowest + lowest * EVENT_TIES + f64::MIN_POSITIVE
            } else {
                lowest
            };
        }
        let mut ahead = None;
        if lowest < 0.0 {
            lowest = end_margins(v, f, ex, ey, &mut margins[..n]);
            bound = SCREEN;
            ahead = Some(lowest - CLEARANCE_SLACK);
        }
        if lowest < bound {
            // Chunks with no node below the bound (nearly all: an event
            // involves a node or two) are passed over branch-free; in the
            // others a bit per node below it gives the nodes to test, in
            // node order (a loop over every node of such a chunk, with a
            // branch each, cost 1.3 % more of a sweep's instructions).
            // Whole chunks and the tail apart: with `chunks`, whose length
            // the compiler does not know, the test of a chunk is a loop
            // again (`advance` took 871 M instructions on every fifth
            // `lambda` of the Fig. 3 map against 742 M).
            const CHUNK: usize = 16;
            let chunks = margins[..n].chunks_exact(CHUNK);
            let tail = chunks.remainder();
            let masks = chunks
                .map(|chunk| {
                    if !chunk.iter().fold(false, |acc, &m| acc | (m < bound)) {
                        return 0;
                    }
                    let mut below = 0u32;
                    for (i, &m) in chunk.iter().enumerate() {
                        below |= u32::from(m < bound) << i;
                    }
                    below
                })
                .chain(std::iter::once(
                    tail.iter()
                        .enumerate()
                        .fold(0u32, |acc, (i, &m)| acc | (u32::from(m < bound) << i)),
                ));
            for (c, mut below) in masks.enumerate() {
                while below != 0 {
                    let j = c * CHUNK + below.trailing_zeros() as usize;
                    below &= below - 1;
                    self.locate(
                        w,
                        j,
                        dx,
                        dy,
                        remaining,
                        &mut t_min,
                        &mut stop,
                        &mut need_rates,
                    );
                }
            }
        }
        w.engine.margins = margins;
        let (stop, t, need_rates) = self.gross_or(stop, t_min, need_rates, load_dy);
        (stop, t, need_rates, ahead)
    }

    /// The segment's first stop: `stop` at `t_min` (with `need_rates`), or
    /// gross slip where `|y|` reaches `2 pi` first (`load_dy` the change of
    /// `y` along the segment).
    fn gross_or(
        &self,
        mut stop: Stop,
        mut t_min: f64,
        need_rates: bool,
        load_dy: f64,
    ) -> (Stop, f64, bool) {
        if load_dy != 0.0 {
            let y = self.load.y();
            let limit = 2.0 * PI * load_dy.signum();
            let t = if on_the_torque_limit(y) && y * load_dy > 0.0 {
                0.0
            } else {
                (limit - y) / load_dy
            };
            if t >= 0.0 && t <= t_min {
                t_min = t;
                stop = Stop::Gross;
            }
        }
        (stop, t_min, need_rates)
    }

    /// The exact test of node `j` for an event before `t_min` (the slow
    /// part of [`Self::scan`], only for nodes whose end margin is low).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn locate(
        &self,
        w: &Workspace,
        j: usize,
        dx: f64,
        dy: f64,
        remaining: f64,
        t_min: &mut f64,
        stop: &mut Stop,
        need_rates: &mut bool,
    ) {
        let f = self.material.friction();
        let e = &w.engine;
        let (p, q) = (self.pressure[j], self.shear[j]);
        let a = dx * e.tpx[j] + dy * e.tpy[j];
        // Separation: p + t a = 0 (divide only when it comes first).
        if a < 0.0 && p < -a * *t_min {
            *t_min = p.max(0.0) / -a;
            *stop = Stop::Separation(j);
        }
        if e.stick[j] {
            let b = dx * e.tqx[j] + dy * e.tqy[j];
            // Slack f p - sigma q on the forward (sigma = 1) and backward
            // side, and its rate.
            for (h0, h1) in [(f * p - q, f * a - b), (f * p + q, f * a + b)] {
                if h1 < -RATE_TOL && h0 + remaining * h1 < -TRACTION_TOL {
                    if h0 <= TRACTION_TOL {
                        *need_rates = true;
                    } else if h0 < -h1 * *t_min {
                        *t_min = h0 / -h1;
                        *stop = Stop::Entry;
                    }
                }
            }
        }
    }

    /// Move by `t` of the segment parameter with the cached set, to `load`.
    ///
    /// The residual tractions move with the slip rates; `p` and `q` are
    /// then the elastic part at `load` plus the residual part, so they never
    /// drift from the load. One pass over the nodes does both and the
    /// dissipation `f/2 sum p |dg| dtheta`, with `p` averaged over the
    /// sub-segment (exact: `p` is linear and `dg` uniform on it).
    fn move_along(&mut self, w: &mut Workspace, t: f64, dx: f64, dy: f64, load: LoadPoint) {
        let f = self.material.friction();
        let n = self.nodes();
        let e = &mut w.engine;
        self.increment.segments += 1;
        self.load = load;
        if t == 0.0 {
            return;
        }
        let (tx, ty) = (t * dx, t * dy);
        let elastic = self.elastic_part(load);
        if e.set.is_empty() {
            // Stick only: the residual part does not change.
            let parts = [
                &self.sin[..],
                &self.cos,
                &self.residual_pressure,
                &self.residual_shear,
            ];
            kernels::tractions(elastic, parts, &mut self.pressure, &mut self.shear);
            return;
        }
        // Slip, and its forward and backward parts, change on the set only:
        // a loop over the set's indices when it is small, else in the
        // vectorised pass over every node below (the rates are 0 off the
        // set, so the two give the same numbers).
        let inc = &mut self.increment;
        inc.slipped = true;
        let by_node = e.set.len() * SET_LOOP_SHARE < n;
        if by_node {
            inc.clear_stale();
            for &(j, _) in &e.set {
                // The bits of `t rg` (`Engine::combine`).
                let dg = t * (dx * e.gx[j] + dy * e.gy[j]);
                self.slip[j] += dg;
                inc.forward[j] += dg.max(0.0);
                inc.backward[j] += (-dg).max(0.0);
            }
        }
        let slip = (!by_node).then(|| kernels::SlipOut {
            slip: &mut self.slip,
            forward: &mut inc.forward,
            backward: &mut inc.backward,
            fresh: std::mem::take(&mut inc.stale),
        });
        // The rates along the segment, if a scan or a rate problem made
        // them; else the pass makes them from those per unit `u1`, `u2`.
        let combined = e.rg_for == Some((dx, dy));
        // One pass over the nodes: the residual tractions move with the
        // slip rates, `p` and `q` follow, and the dissipation
        // f/2 sum |dg| (p before + p after) dtheta accumulates.
        let slide = kernels::Slide {
            t,
            tx,
            ty,
            elastic,
            responses: e.responses(),
            trig: [&self.sin, &self.cos],
            rates: if combined {
                [&e.rg, &[]]
            } else {
                [&e.gx, &e.gy]
            },
            along: (!combined).then_some([dx, dy]),
        };
        let state = [
            &mut self.residual_pressure[..],
            &mut self.residual_shear,
            &mut self.pressure,
            &mut self.shear,
        ];
        let acc = kernels::slide(&slide, state, slip);
        let sum = (acc[0] + acc[1]) + (acc[2] + acc[3]);
        let dtheta = 2.0 * PI / n as f64;
        self.increment.dissipation += 0.5 * f * 0.5 * sum * dtheta;
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
    fn last_resort(
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
    fn fallback(
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

#[cfg(test)]
mod tests {
    use super::super::tests::direction;
    use super::Engine;
    use proptest::prelude::*;

    proptest! {
        /// After any sequence of changes, few or many, the set and the
        /// per-node views are those a pass over every node gives.
        #[test]
        fn a_change_of_set_gives_what_a_pass_over_every_node_gives(
            n in 1usize..70,
            steps in proptest::collection::vec(
                (proptest::collection::vec((any::<prop::sample::Index>(), direction()), 0..6),
                 proptest::option::weighted(0.2, proptest::collection::vec(direction(), 70))),
                1..12,
            ),
        ) {
            let mut e = Engine::new(n);
            for (edits, whole) in steps {
                if let Some(whole) = whole {
                    e.trial.copy_from_slice(&whole[..n]);
                }
                for (at, d) in edits {
                    e.trial[at.index(n)] = d;
                }
                e.change_set_to_trial();
                let expected: Vec<(usize, f64)> = e
                    .trial
                    .iter()
                    .enumerate()
                    .filter(|(_, d)| d.is_slipping())
                    .map(|(j, d)| (j, d.sign()))
                    .collect();
                prop_assert_eq!(&e.set, &expected);
                prop_assert_eq!(&e.dirs, &e.trial);
                for (j, d) in e.trial.iter().enumerate() {
                    let slips = d.is_slipping();
                    prop_assert_eq!(e.stick[j], !slips);
                    prop_assert_eq!(e.sgn[j], if slips { d.sign() } else { 0.0 });
                    prop_assert_eq!(e.off[j], if slips { f64::INFINITY } else { 0.0 });
                }
            }
        }
    }

    /// Two back-and-forth cycles of a load that slips, at `N = 128`: the
    /// second meets the sets of the first, and reads their kept responses
    /// in place in the cache. A clone made there, and the contact after its
    /// cache is taken and given back, hold the very responses the contact
    /// read, in their own arrays (a clone's cache starts empty: read in
    /// place, its responses would be out of bounds or another set's).
    #[test]
    fn responses_read_in_place_survive_a_clone_and_a_handed_cache() {
        use crate::model::{Discretisation, LoadPoint, Material};
        use crate::Contact;
        let own = |c: &Contact| -> Vec<Vec<f64>> {
            let e = &c.work.as_ref().expect("advanced").engine;
            e.responses().iter().map(|r| r.to_vec()).collect()
        };
        let disc = Discretisation::default();
        let mut c = Contact::new(Material::paper(), crate::stepping::operators(&disc));
        let mut lent_seen = 0;
        for i in 1..=800 {
            let t = i as f64 / 400.0 * 2.0 * std::f64::consts::PI;
            c.advance(LoadPoint::new(2.0 * t.sin(), 5.8 * t.sin()))
                .expect("advances");
            let lent = c.work.as_ref().expect("advanced").engine.lent;
            if i <= 400 || lent[0].is_none() {
                continue;
            }
            lent_seen += 1;
            let read = own(&c);
            let clone = c.clone();
            let ce = &clone.work.as_ref().expect("cloned").engine;
            assert_eq!(ce.lent, [None, None]);
            assert_eq!(own(&clone), read);
            let cache = c.take_response_cache().expect("a cache");
            assert_eq!(c.work.as_ref().expect("advanced").engine.lent, [None, None]);
            assert_eq!(own(&c), read);
            c.give_response_cache(cache);
        }
        assert!(lent_seen > 10, "{lent_seen} increments read a hit in place");
    }

    /// The bounds that spare an increment its passes over the rates and the
    /// end margins change nothing: along cycles of several phases, from a
    /// straight transient, with increments of several sizes and a
    /// reversal, a contact that uses them and one that makes every pass
    /// reach the same state, slip, events and dissipation, to the bit,
    /// after every increment; and the bounds spare passes.
    #[test]
    fn bounds_that_spare_passes_change_no_bit() {
        use crate::model::{Discretisation, LoadPoint, Material};
        use crate::{Advanced, Contact};
        use std::f64::consts::PI;
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let disc = Discretisation::default();
        let ops = crate::stepping::operators(&disc);
        #[cfg(feature = "counters")]
        let mut spared = [0; 2];
        #[cfg(feature = "counters")]
        let mut increments = 0;
        for (phase, lambda, steps) in [
            (0.5, 5.5, 400),
            (0.25, 6.0, 160),
            (0.0, 5.0, 400),
            (0.375, 4.5, 1000),
        ] {
            let mut bounded = Contact::new(Material::paper(), ops.clone());
            let mut unbounded = bounded.clone();
            unbounded.unbounded = true;
            // A transient, two cycles round the ellipse of `phase`, then a
            // straight run out and back.
            let transient = (1..=50).map(|i| LoadPoint::new(-0.04 * i as f64, 0.04 * i as f64));
            let cycle = (1..=2 * steps).map(move |i| {
                let t = 2.0 * PI * i as f64 / steps as f64;
                LoadPoint::new(0.4 * lambda * (t - phase * PI).sin(), lambda * t.sin())
            });
            let end = LoadPoint::new(0.4 * lambda * (-phase * PI).sin(), 0.0);
            let out = (1..=100).map(move |i| end.lerp(LoadPoint::new(2.0, 5.5), i as f64 / 100.0));
            let back = (1..=100).map(|i| {
                LoadPoint::new(2.0, 5.5).lerp(LoadPoint::new(-1.0, -4.0), i as f64 / 100.0)
            });
            for load in transient.chain(cycle).chain(out).chain(back) {
                let a = bounded.advance(load);
                let b = unbounded.advance(load);
                assert_eq!(a, b, "at {load:?}");
                #[cfg(feature = "counters")]
                {
                    increments += 1;
                }
                let (ia, ib) = (bounded.last_increment(), unbounded.last_increment());
                assert_eq!(ia.dissipation.to_bits(), ib.dissipation.to_bits());
                assert_eq!(bits(&ia.forward), bits(&ib.forward));
                assert_eq!(bits(&ia.backward), bits(&ib.backward));
                assert_eq!(ia.events, ib.events);
                assert_eq!(bits(bounded.slip()), bits(unbounded.slip()));
                assert_eq!(bits(bounded.pressure()), bits(unbounded.pressure()));
                assert_eq!(bits(bounded.shear()), bits(unbounded.shear()));
                assert_eq!(bounded.directions(), unbounded.directions());
                if !matches!(a, Ok(Advanced::Reached)) {
                    break;
                }
            }
            #[cfg(feature = "counters")]
            {
                let e = &bounded.work.as_ref().expect("advanced").engine;
                spared[0] += e.spared[0];
                spared[1] += e.spared[1];
                let u = &unbounded.work.as_ref().expect("advanced").engine;
                assert_eq!(u.spared, [0, 0]);
            }
        }
        // The end margins of most increments; the rates of a few (those
        // of straight runs whose set holds: along an ellipse the direction
        // turns too far between increments).
        // The bounds spare passes (counted with the `counters` feature).
        #[cfg(feature = "counters")]
        assert!(
            2 * spared[1] > increments && spared[0] > 20,
            "{spared:?} of {increments} increments' passes spared"
        );
    }
}
