//! The engine of the exact increment ([`Engine`]): the responses of one
//! slip set (its slip rates, `H g'`, `-|D| g'` and the totals) per unit of
//! two load directions, kept while the set holds, with the bounds that
//! spare passes over the nodes and the response cache of a sweep.

use super::*;

use crate::contact::cache::{self, ResponseCache, SetKey};
use crate::contact::kernels::{self, rate_extremes};
use crate::contact::operators::{FftScratch, Operators};
use crate::contact::solver::MAX_HELD;
use crate::contact::solver::{push_differences, SlipDirection};
use crate::contact::tolerances::DG_TOL;
use crate::model::LoadPoint;

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
    pub(super) valid: bool,
    /// The slip set of the cached responses, and as `(node, sign)`.
    pub(super) dirs: Vec<SlipDirection>,
    pub(super) set: Vec<(usize, f64)>,
    /// The set as the response cache knows it, made from `set` for each
    /// lookup ([`SetKey::set_to`]).
    pub(super) key: SetKey,
    /// Scratch of a change of set: the nodes whose direction changes.
    pub(super) changes: Vec<usize>,
    /// The two load directions of the responses: `u1` the direction of the
    /// segment on which the set was decided, `u2` its perpendicular (the
    /// fields named `..x` / `..y` below hold the responses to `u1` / `u2`).
    /// The response to `u2` is computed only when the set outlives the
    /// segment's direction (`have2`).
    pub(super) u1: (f64, f64),
    pub(super) have2: bool,
    /// Slip rates on the set per unit `u1` and `u2` (zero elsewhere).
    pub(super) gx: Vec<f64>,
    pub(super) gy: Vec<f64>,
    /// Residual pressure `H g'` and shear `-|D| g'` per unit `u1` and `u2`,
    /// unless `lent` says where in the cache's pool they are.
    pub(super) hpx: Vec<f64>,
    pub(super) hpy: Vec<f64>,
    pub(super) hqx: Vec<f64>,
    pub(super) hqy: Vec<f64>,
    /// Per axis, the start in the cache's pool of the kept `H g'` then
    /// `-|D| g'` that a hit gave, read there instead of copied out (the
    /// copy was 4 % of the Fig. 3 map's time, from memory the pool holds in
    /// L3). The pool's numbers move only at an eviction or a compaction
    /// ([`ResponseCache::pool`]): an insert follows a miss, after the change
    /// of set that cleared these, and the response to `u2` added to a lent
    /// entry copies them out first if it would evict.
    pub(super) lent: [Option<usize>; 2],
    /// Elastic pressure and shear per unit `x` and `y`.
    pub(super) epx: Vec<f64>,
    pub(super) epy: Vec<f64>,
    pub(super) eqx: Vec<f64>,
    pub(super) eqy: Vec<f64>,
    pub(super) elastic_ready: bool,
    /// Total pressure and shear (elastic + residual) per unit `u1` and `u2`.
    pub(super) tpx: Vec<f64>,
    pub(super) tpy: Vec<f64>,
    pub(super) tqx: Vec<f64>,
    pub(super) tqy: Vec<f64>,
    /// Whether a node sticks in the cached set, and its slip sign (0 if it
    /// sticks).
    pub(super) stick: Vec<bool>,
    pub(super) sgn: Vec<f64>,
    /// 0 on stick nodes, infinity on slip nodes (their slack is not watched).
    pub(super) off: Vec<f64>,
    /// The end margins of the segment being scanned.
    pub(super) margins: Vec<f64>,
    /// Slip rates along the current segment at every node (0 off the set).
    pub(super) rg: Vec<f64>,
    /// The coefficients `(a1, a2)` that `rg` was combined for from the
    /// present `gx` and `gy`; `None` once either changes. A rate problem
    /// begins, and the segment after it begins, with the combination just
    /// made: two passes over the nodes per event that need not be made.
    pub(super) rg_for: Option<(f64, f64)>,
    /// `(max |rg|, min sgn rg)` of the present `rg` and signs, once asked
    /// for ([`Engine::rate_extremes`]): a settled rate problem and the scan
    /// of the segment after it ask for the same.
    pub(super) rg_extremes: Option<(f64, f64)>,
    /// `(max |gx|, min sgn gx)`: the extremes of the rates per unit `u1`,
    /// from which those of `rg = a1 gx` follow exactly for any `a1 > 0`
    /// ([`Engine::rate_extremes`]).
    pub(super) gx_extremes: Option<(f64, f64)>,
    /// The rates' extremes for the direction of the last segment whose
    /// scan looked at them ([`Engine::rates_against`]), and `max |gy|`
    /// (`max |gx|` is in `gx_extremes`).
    pub(super) rates_seen: Option<RatesSeen>,
    pub(super) gy_scale: Option<f64>,
    /// Test only: the passes over the rates and the end margins that the
    /// bounds spared.
    #[cfg(feature = "counters")]
    pub(crate) spared: [usize; 2],
    /// Per axis (`u1`, `u2`), the fastest any node's end margin can fall
    /// per unit of load along it ([`kernels::reach`]), once asked for: it
    /// follows the totals and the set.
    pub(super) reach: [Option<f64>; 2],
    /// A lower bound on every node's end margin at the contact's present
    /// state, and the load point it holds at: the lowest end margin of the
    /// last segment, less the round-off in which the move there and the
    /// margins can differ ([`Contact::scan`]). Kept only while the state
    /// and the set are those it was taken for.
    pub(super) clearance: Option<(LoadPoint, f64)>,
    /// Rate-problem scratch.
    pub(super) trial: Vec<SlipDirection>,
    /// The stick nodes at the friction limit at the rate problem's point.
    pub(super) candidates: Vec<usize>,
    pub(super) before: Vec<SlipDirection>,
    pub(super) seen: Vec<u64>,
    /// Nodes held stuck where a trial set would hold every node.
    pub(super) held: Vec<usize>,
    pub(super) full: Vec<f64>,
    /// Slip rates of recently seen sets, and the entry of the current one.
    pub(super) cache: ResponseCache,
    pub(super) slot: Option<usize>,
}

impl Engine {
    /// Make `trial` the set: `dirs`, `set` and the per-node views `stick`,
    /// `sgn` and `off` follow it.
    ///
    /// A set changes by a node or two at a time, so only the nodes whose
    /// direction changes are visited: they are found by comparing the
    /// directions sixteen at a time, branch-free (a test per node of all
    /// `N` was a twentieth of a sweep's time). A few changes are edited
    /// into the set where they belong (a binary search and a short move
    /// each); merging the whole set with them, as before, was a fifteenth
    /// of a sweep's time. Many changes at once make the set afresh from the
    /// directions.
    pub(super) fn change_set_to_trial(&mut self) {
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
    pub(super) fn axis(&self, axis: usize) -> (f64, f64) {
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
    pub(super) fn rate_extremes(&mut self) -> (f64, f64) {
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
    pub(super) fn forget_bounds(&mut self) {
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
    pub(super) fn combine(&mut self, a1: f64, a2: f64) {
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
    pub(super) fn rates_against(&mut self, a1: f64, a2: f64, bounded: bool) -> bool {
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
    pub(super) fn rate_scale(&mut self, axis: usize) -> f64 {
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
    pub(super) fn reach(&mut self, axis: usize, f: f64) -> f64 {
        let (tp, tq) = if axis == 0 {
            (&self.tpx, &self.tqx)
        } else {
            (&self.tpy, &self.tqy)
        };
        *self.reach[axis].get_or_insert_with(|| kernels::reach(tp, tq, &self.off, f))
    }

    /// Total responses to the direction of `axis`.
    pub(super) fn totals(&mut self, axis: usize) {
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
    pub(super) fn responses(&self) -> [&[f64]; 4] {
        let own = [&self.hpx[..], &self.hpy, &self.hqx, &self.hqy];
        lent_or_own(self.cache.pool(), self.lent, own)
    }

    /// A clone that holds its responses itself: a clone's cache starts
    /// empty, so what this one's lent is copied out of it.
    pub(in crate::contact) fn clone_owning(&self) -> Self {
        let mut clone = self.clone();
        clone.own_responses(&self.cache);
        clone
    }

    /// Copy the responses that `cache` lent (this engine's cache, or that
    /// of the engine this one was cloned from) into the engine's own
    /// arrays: before the cache goes or is replaced.
    pub(in crate::contact) fn own_responses(&mut self, cache: &ResponseCache) {
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
    pub(super) fn fill_axis(&mut self, ops: &Operators, fft: &mut FftScratch, axis: usize) {
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
        ops.convolve_with(&self.full, fft, |pairs| {
            kernels::from_complex_totals(pairs, [hp, hq], [tp, tq], u, elastic)
        });
        // `full` is filled afresh before each use: hand its buffer over.
        std::mem::swap(g, &mut self.full);
    }

    /// The responses to the direction of `axis` from its slip rates in
    /// `full` and the kept `H g'` then `-|D| g'` of a cache entry, which
    /// start at `at` in the cache's pool: the numbers [`Self::fill_axis`]
    /// would compute, without the FFT, and read where they are kept.
    pub(super) fn restore_axis(&mut self, axis: usize, kept: &[f64], at: usize) {
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

    pub(in crate::contact) fn new(n: usize) -> Self {
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
