//! A proof of shakedown before the first cycle without slip: a safe state
//! near the present one, and an energy bound on all the slip still to come
//! (`docs/model.md` section 6.4).
//!
//! Runs that shake down only asymptotically slip less and less for hundreds
//! of cycles before a cycle passes without any slip. Melan's theorem does
//! not hold for this coupled system in general (slip changes the pressure),
//! but a local form of it does: if some locked-in slip `g_s` (a *safe
//! state*) keeps `|q| <= f p - delta` at every node and instant of the
//! cycle, and the present slip `g` is close enough to it,
//!
//! ```text
//! f C R < delta,    R^2 = (g - g_s)^T |D| (g - g_s),    C^2 = 2 (1 + 1/2 + ... + 1/(N/2 - 1)) / N,
//! ```
//!
//! then the stored energy `E = R^2 / 2` never grows, and the total slip of
//! all nodes in all later cycles is at most `R^2 / (2 (delta - f C R))`.
//! Finite total slip means the slip per cycle tends to zero: shakedown. The
//! reasoning is in `docs/model.md` section 6.4.
//!
//! Finding `g_s` is a second-order cone programme (solved with Clarabel):
//! maximise `delta - f C R` over the safe states. It is solved small and
//! early (a *quick search*: `g_s - g` among the lowest harmonics, from
//! cycle 2), which proves the runs that approach shakedown geometrically,
//! and in full late and rarely (every harmonic, from cycle 20), which the
//! slow power-law approaches need. Whatever the solver returns is checked
//! afresh, exactly, before it is believed.

use std::f64::consts::PI;
use std::sync::{Arc, OnceLock};

use clarabel::algebra::CscMatrix;

use clarabel::solver::{
    DefaultInfo, DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT,
    SecondOrderConeT, SolverStatus,
};
use serde::Serialize;

use super::stepper::cycle_angle;
use crate::contact::{Contact, Operators};
use crate::model::{Cycle, Material};

/// What proves a run's shakedown before a cycle without slip: a safe state,
/// its margin and distance, and the bound on the slip still to come
/// (`docs/model.md` section 6.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Certificate {
    /// The cycle after which it was proven.
    pub cycle: usize,
    /// `delta`: the safe state keeps `|q| <= f p - delta` at every node and
    /// instant of the cycle.
    pub margin: f64,
    /// `R`: the energy distance from the slip after `cycle` to the safe
    /// state, `sqrt((g - g_s)^T |D| (g - g_s))`.
    pub distance: f64,
    /// `f C`: how much pressure a unit of energy distance can change at
    /// most (the normal-tangential coupling).
    pub coupling: f64,
    /// The total slip `sum |dg|` of all nodes over all cycles after
    /// `cycle` is at most this (so is any one node's).
    pub slip_bound: f64,
    /// `W` of cycle `cycle`, the last one run.
    pub last_dissipation: f64,
}

/// Below this value of `delta - f C R` a candidate proves nothing: the
/// solver's tractions meet the friction law to about `1e-12`.
const PROOF_TOLERANCE: f64 = 1e-9;

/// The first full search for a safe state is made after this cycle, and
/// only after a cycle whose `W` fell slowly ([`SLOW_FALL`]). A full search
/// (all `N - 1` harmonics) costs about as much as 50 to 80 cycles at
/// `N = 128`; the quick searches ([`QUICK_FIRST`]) have by then proven the
/// runs whose safe state is smooth, and a `W` that falls fast reaches a
/// cycle without slip (or its level) sooner than a full search would pay
/// for itself.
pub(crate) const FIRST_ATTEMPT: usize = 20;

/// A full search is made only after a cycle whose `W` fell by less than
/// this factor from the cycle before (see `Stepper`).
pub(crate) const SLOW_FALL: f64 = 0.8;
/// Later full searches are spaced by this factor in the cycle count. The
/// best safe state hardly depends on the slip reached (a search at cycle 35
/// finds the one found at cycle 10 to 1e-9), so the candidate found is
/// re-checked after every cycle, at `O(N)`, and searches are rare.
const ATTEMPT_GROWTH: f64 = 4.0;

/// The first quick search is made after this cycle, after any cycle whose
/// `W` fell, and later ones at twice the cycle count of the last. A quick
/// search looks for a safe state among the slip changes of the lowest
/// [`QUICK_HARMONICS`] harmonics only, and only on the margins that can
/// bind: it costs about two cycles at `N = 128`, against the tens of cycles
/// that a run with a smooth safe state still needs before its first cycle
/// without slip.
pub(crate) const QUICK_FIRST: usize = 2;

/// Harmonics of the quick search. Fewer fail where a safe state needs a
/// change of the slip over a fifth of the circle (`lambda = 4.5`, `phi =
/// 0`, path `7,-7`: 4 harmonics prove nothing by cycle 32, 8 prove it at
/// cycle 2).
const QUICK_HARMONICS: usize = 8;

/// Both searches start from the margin rows below this fraction of the
/// largest (the rest are far from binding) and add any row their answer
/// violates, at most [`QUICK_ROUNDS`] or [`FULL_ROUNDS`] times. The quick
/// search from 5 % (about 80 of the 256 rows at `N = 128`) violated most of
/// the others, and two searches in three needed a second round on about
/// 225 rows; from 20 % one in three does, and the searches of the Fig. 3
/// map take a fifth less time (0.95 s against 1.19 s, 377 searches, one
/// thread). The full search, on every row before, takes about 160 of 256
/// from 20 % and nearly always one round: the full searches of the Fig. 6
/// map took 12.3 s against 17.9 s (265 searches, two threads; 15.5 s from
/// 10 %, 23.0 s from 5 %, where more rounds are needed). The same rows came
/// out of the Fig. 3, `phi = pi/2` and Fig. 6 maps.
const START_ROWS: f64 = 0.2;
const QUICK_ROUNDS: usize = 3;
/// A full search stops adding rows after this many rounds (three at most
/// were needed in the Fig. 6 map); its answer is checked exactly anyway.
const FULL_ROUNDS: usize = 8;

/// How far a run's `W` fell in its last cycle: what decides whether a
/// search for a safe state is worth its cost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fall {
    /// `W` did not fall: no search.
    None,
    /// `W` fell by more than the factor `SLOW_FALL` (0.8): a quick search
    /// only.
    Fast,
    /// `W` fell by less than the factor `SLOW_FALL`: a quick or a full
    /// search.
    Slow,
}

/// The search for a safe state, and the best candidate so far, for one run.
#[derive(Debug, Clone)]
pub struct SafeStateSearch {
    friction: f64,
    /// `f C` (module docs).
    coupling: f64,
    /// The elastic margins and the basis: what depends on the cycle, the
    /// material and the grid only, shared by the runs of one cycle.
    setup: Arc<Setup>,
    /// The best safe state found: `g_s`, `|D| g_s` and its margin.
    candidate: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// The cycle of the next full search.
    next_attempt: usize,
    /// The cycle of the next quick search.
    next_quick: usize,
    /// Searches run (quick and full).
    pub searches: usize,
}

/// `f C` for `N` nodes: the largest `|f (H e)_j|` over `e` with
/// `e^T |D| e = 1` (Cauchy-Schwarz on the Fourier modes, attained).
pub fn coupling_constant(friction: f64, nodes: usize) -> f64 {
    let harmonic: f64 = (1..nodes / 2).map(|k| 1.0 / k as f64).sum();
    friction * (2.0 * harmonic / nodes as f64).sqrt()
}

/// What a [`SafeStateSearch`] needs that depends only on the cycle, the
/// material, the nodes and the increments per cycle, not on the run's
/// history: the least elastic margins over the cycle and the basis of the
/// cone programme. Made once per cycle and shared
/// ([`SafeStateSearch::sharing`]): setting up took about 2 % of a Fig. 3
/// sweep's instructions when every run made its own.
#[derive(Debug)]
pub(crate) struct Setup {
    material: Material,
    cycle: Cycle,
    nodes: usize,
    steps: usize,
    /// The least of `f p - s q` over the cycle's load points with no slip,
    /// per node and sign `s = +1, -1`, less the allowance for a path that
    /// leaves the chords ([`SafeStateSearch::new`]).
    elastic: Vec<[f64; 2]>,
    /// The basis of the cone programme's slip change, built at the first
    /// search (most runs never make one).
    basis: OnceLock<Basis>,
}

impl Setup {
    fn new(contact: &Contact, cycle: &Cycle, steps: usize) -> Self {
        let friction = contact.material().friction();
        let mut elastic = contact
            .least_elastic_margins((0..steps).map(|j| cycle.at(cycle_angle(j as f64, steps))));
        let dt = 2.0 * PI / steps as f64;
        let allowance =
            std::f64::consts::SQRT_2 * friction / (2.0 * PI) * cycle.load_factor() * dt * dt / 8.0;
        for e in &mut elastic {
            e[0] -= allowance;
            e[1] -= allowance;
        }
        Self {
            material: *contact.material(),
            cycle: cycle.clone(),
            nodes: contact.nodes(),
            steps,
            elastic,
            basis: OnceLock::new(),
        }
    }

    /// Whether this setup is the one a search of `cycle` on `contact`'s
    /// material and nodes, `steps` increments a cycle, would make.
    fn fits(&self, contact: &Contact, cycle: &Cycle, steps: usize) -> bool {
        self.material == *contact.material()
            && self.cycle == *cycle
            && self.nodes == contact.nodes()
            && self.steps == steps
    }
}

impl SafeStateSearch {
    /// Set up for a run of `cycle` on the contact's nodes and material.
    ///
    /// The contact follows straight chords between the cycle's
    /// `steps` load points, where every `f p - s q` is linear, so its least
    /// value over the cycle is the least over the points. Where an
    /// increment that failed to settle is bisected, the path visits points
    /// of the ellipse between them instead; these lie within
    /// `lambda (2 pi / steps)^2 / 8` of the chord, and `f p - s q` changes
    /// by at most `sqrt(2) f / (2 pi)` per unit of load, so that much is
    /// taken off every margin.
    pub fn new(contact: &Contact, cycle: &Cycle, steps: usize) -> Self {
        Self::sharing(None, contact, cycle, steps)
    }

    /// As [`Self::new`], taking the elastic margins and the basis from
    /// `shared` (the setup of an earlier run's search) if it was made for
    /// the same cycle, material, nodes and increments, and making them
    /// afresh if not. They are the same for every run of a cycle whatever
    /// its initial path: a sweep hands them from run to run within a
    /// `lambda` and `phi`, as it hands the response cache.
    pub(crate) fn sharing(
        shared: Option<Arc<Setup>>,
        contact: &Contact,
        cycle: &Cycle,
        steps: usize,
    ) -> Self {
        let setup = shared
            .filter(|s| s.fits(contact, cycle, steps))
            .unwrap_or_else(|| Arc::new(Setup::new(contact, cycle, steps)));
        let friction = contact.material().friction();
        Self {
            friction,
            coupling: coupling_constant(friction, contact.nodes()),
            setup,
            candidate: None,
            next_attempt: FIRST_ATTEMPT,
            next_quick: QUICK_FIRST,
            searches: 0,
        }
    }

    /// The setup this search works with, for the next run of its cycle
    /// ([`Self::sharing`]).
    pub(crate) fn setup(&self) -> &Arc<Setup> {
        &self.setup
    }

    fn basis(&self) -> &Basis {
        let elastic = &self.setup.elastic;
        self.setup
            .basis
            .get_or_init(|| Basis::harmonics(elastic.len()))
    }

    /// After complete cycle `cycle` (with `W` = `dissipation`, and `fall`
    /// how far it fell from the cycle before): a certificate if the
    /// contact's present slip is proven to shake down.
    pub fn check(
        &mut self,
        contact: &Contact,
        ops: &Operators,
        cycle: usize,
        dissipation: f64,
        fall: Fall,
    ) -> Option<Certificate> {
        let quick = fall != Fall::None && cycle >= self.next_quick;
        let full = fall == Fall::Slow && cycle >= self.next_attempt;
        if self.candidate.is_none() && !quick && !full {
            return None;
        }
        let g = contact.slip();
        // |D| g afresh from g (the contact's own copy is updated increment
        // by increment): O(N^2), some microseconds a cycle.
        let relief: Vec<f64> = ops.residual_shear(g).iter().map(|v| -v).collect();
        if let Some(c) = self.certify_candidate(g, &relief, cycle, dissipation) {
            return Some(c);
        }
        if !quick && !full {
            return None;
        }
        if quick {
            self.next_quick = 2 * cycle;
        }
        if full {
            self.next_attempt = ((cycle as f64 * ATTEMPT_GROWTH).ceil() as usize).max(cycle + 1);
        }
        let margins = self.margins(&ops.residual_pressure(g), &relief);
        // The margin of a safe state is at most the mean of the two signs'
        // margins at any node (the shear terms cancel, the pressure gains
        // at most f C R): a quick test that rules out cyclic slip.
        let best = margins
            .iter()
            .map(|m| 0.5 * (m[0] + m[1]))
            .fold(f64::INFINITY, f64::min);
        if best <= PROOF_TOLERANCE {
            return None;
        }
        let searches = [
            (quick, 2 * QUICK_HARMONICS.min(self.basis().size / 2)),
            (full, self.basis().size),
        ];
        for (due, columns) in searches {
            if !due {
                continue;
            }
            self.searches += 1;
            let Some(z) = self.solve(&margins, columns) else {
                continue;
            };
            self.consider(ops, g, &relief, &z);
            if let Some(c) = self.certify_candidate(g, &relief, cycle, dissipation) {
                return Some(c);
            }
        }
        None
    }

    /// Keep the safe state `g + z` if it proves more than the one kept:
    /// its margin recomputed exactly at every node, not taken from the
    /// solver.
    fn consider(&mut self, ops: &Operators, g: &[f64], relief: &[f64], z: &[f64]) {
        let safe: Vec<f64> = g.iter().zip(z).map(|(a, b)| a + b).collect();
        let safe_relief: Vec<f64> = ops.residual_shear(&safe).iter().map(|v| -v).collect();
        let safe_pressure = ops.residual_pressure(&safe);
        let margin = self
            .margins(&safe_pressure, &safe_relief)
            .iter()
            .flat_map(|m| m.iter().copied())
            .fold(f64::INFINITY, f64::min);
        let keep = match &self.candidate {
            None => true,
            Some((old, old_relief, old_margin)) => {
                self.value(g, relief, (&safe, &safe_relief, margin))
                    > self.value(g, relief, (old, old_relief, *old_margin))
            }
        };
        if keep {
            self.candidate = Some((safe, safe_relief, margin));
        }
    }

    /// `f p - s q` at the least point of the cycle, per node and sign, for
    /// locked-in slip with residual pressure `pressure` (`H g`) and relief
    /// `relief` (`|D| g`).
    fn margins(&self, pressure: &[f64], relief: &[f64]) -> Vec<[f64; 2]> {
        self.setup
            .elastic
            .iter()
            .zip(pressure.iter().zip(relief))
            .map(|(e, (p, r))| {
                let f = self.friction;
                // q = q_el - |D| g, p = p_el + H g.
                [e[0] + f * p + r, e[1] + f * p - r]
            })
            .collect()
    }

    /// `delta - f C R` of a safe state `(g_s, |D| g_s, delta)` for the
    /// present slip `g` (with `|D| g` = `relief`).
    fn value(&self, g: &[f64], relief: &[f64], safe: (&[f64], &[f64], f64)) -> f64 {
        let (gs, rs, margin) = safe;
        let distance = self.distance(g, relief, gs, rs);
        margin - self.coupling * distance
    }

    /// `sqrt((g - g_s)^T |D| (g - g_s))` from the kept `|D| g` and `|D| g_s`.
    fn distance(&self, g: &[f64], relief: &[f64], gs: &[f64], rs: &[f64]) -> f64 {
        let e: f64 = g
            .iter()
            .zip(gs)
            .zip(relief.iter().zip(rs))
            .map(|((a, b), (ra, rb))| (a - b) * (ra - rb))
            .sum();
        e.max(0.0).sqrt()
    }

    fn certify_candidate(
        &self,
        g: &[f64],
        relief: &[f64],
        cycle: usize,
        dissipation: f64,
    ) -> Option<Certificate> {
        let (gs, rs, margin) = self.candidate.as_ref()?;
        let distance = self.distance(g, relief, gs, rs);
        let value = margin - self.coupling * distance;
        (value > PROOF_TOLERANCE).then(|| Certificate {
            cycle,
            margin: *margin,
            distance,
            coupling: self.coupling,
            slip_bound: distance * distance / (2.0 * value),
            last_dissipation: dissipation,
        })
    }

    /// A safe state `g_s = g + z`, with `z = Z u` over the first `columns`
    /// columns of the basis ([`Basis`]): the change `z`, or `None` if the
    /// cone programme finds no optimum. It starts from the rows that can
    /// bind ([`START_ROWS`]) and adds those its answer violates; an answer
    /// that violates none is the optimum over every row. Either way the
    /// answer is only a candidate: its margin is recomputed exactly before
    /// it proves anything.
    fn solve(&self, margins: &[[f64; 2]], columns: usize) -> Option<Vec<f64>> {
        self.solve_from(margins, columns, START_ROWS)
    }

    /// [`Self::solve`] from the rows below `start` times the largest margin
    /// (every row for `f64::INFINITY`).
    fn solve_from(&self, margins: &[[f64; 2]], columns: usize, start: f64) -> Option<Vec<f64>> {
        let n = margins.len();
        let basis = self.basis();
        let f = self.friction;
        let rows = 2 * n;
        let flat: Vec<f64> = margins.iter().flat_map(|m| m.iter().copied()).collect();
        // gain[col * rows + 2 j + (0 | 1)]: what a unit of u_col adds to
        // the margin of node j, sign + or -: f (H z)_j +- (|D| z)_j.
        let mut gain = Vec::with_capacity(columns * rows);
        for col in 0..columns {
            let shear = &basis.relief[col * n..(col + 1) * n];
            let pressure = &basis.pressure[col * n..(col + 1) * n];
            for (s, p) in shear.iter().zip(pressure) {
                gain.push(s + f * p);
                gain.push(-s + f * p);
            }
        }
        // The quick test of `check` leaves some margin positive; the least
        // is always taken (with no row the programme would be unbounded).
        let quick = columns < basis.size;
        let rounds = if quick { QUICK_ROUNDS } else { FULL_ROUNDS };
        let top = flat.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let least = flat.iter().copied().fold(f64::INFINITY, f64::min);
        let mut chosen: Vec<bool> = flat
            .iter()
            .map(|&m| m < start * top || m == least)
            .collect();
        let mut round = 1;
        let u = loop {
            let picked: Vec<usize> = (0..rows).filter(|&r| chosen[r]).collect();
            let x = self.cone_programme(&gain, columns, &flat, &picked, quick)?;
            let delta = x[columns];
            let mut violated = false;
            for r in 0..rows {
                if chosen[r] {
                    continue;
                }
                let value: f64 = flat[r]
                    + (0..columns)
                        .map(|col| gain[col * rows + r] * x[col])
                        .sum::<f64>();
                if value < delta {
                    chosen[r] = true;
                    violated = true;
                }
            }
            if !violated || round == rounds {
                break x;
            }
            round += 1;
        };
        let mut z = vec![0.0; n];
        for (col, &uc) in u[..columns].iter().enumerate() {
            for (zj, bj) in z.iter_mut().zip(&basis.slip[col * n..(col + 1) * n]) {
                *zj += uc * bj;
            }
        }
        Some(z)
    }

    /// The cone programme over `v` basis coefficients `u`, `delta` and
    /// `t >= |u| = R` on the margin rows `picked` (of `margins`, with
    /// `gain` as [`Self::solve`] lays it out): maximise `delta - f C t`
    /// subject to `margin_r + gain_r . u >= delta`. Returns `(u, delta)`,
    /// or `None` if the solver finds no optimum. A `quick` search skips
    /// the iterative refinement of the solver's linear systems (its answer
    /// is checked exactly like any other, and without it takes half the
    /// time) and gives up as soon as both bounds say it cannot prove
    /// anything.
    fn cone_programme(
        &self,
        gain: &[f64],
        v: usize,
        margins: &[f64],
        picked: &[usize],
        quick: bool,
    ) -> Option<Vec<f64>> {
        let all = margins.len();
        let rows = picked.len();
        // Variables: u (v), delta, t. Rows: the margins, t <= cap, then the
        // cone (t, u).
        let total = rows + 1 + (v + 1);
        let mut colptr = Vec::with_capacity(v + 3);
        let mut rowval = Vec::with_capacity((rows + 1) * v + rows + 2);
        let mut nzval = Vec::with_capacity((rows + 1) * v + rows + 2);
        colptr.push(0);
        for col in 0..v {
            let column = &gain[col * all..(col + 1) * all];
            for (i, &r) in picked.iter().enumerate() {
                // -gain_r u + delta <= margin_r
                rowval.push(i);
                nzval.push(-column[r]);
            }
            rowval.push(rows + 2 + col);
            nzval.push(-1.0);
            colptr.push(nzval.len());
        }
        for i in 0..rows {
            rowval.push(i);
            nzval.push(1.0);
        }
        colptr.push(nzval.len());
        rowval.push(rows);
        nzval.push(1.0);
        rowval.push(rows + 1);
        nzval.push(-1.0);
        colptr.push(nzval.len());
        let a = CscMatrix::new(total, v + 2, colptr, rowval, nzval);
        let mut b = vec![0.0; total];
        for (bi, &r) in b.iter_mut().zip(picked) {
            *bi = margins[r];
        }
        b[rows] = DISTANCE_CAP;
        let mut c = vec![0.0; v + 2];
        c[v] = -1.0;
        c[v + 1] = self.coupling;
        let p = CscMatrix::<f64>::zeros((v + 2, v + 2));
        let cones = [NonnegativeConeT(rows + 1), SecondOrderConeT(v + 1)];
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(100)
            .tol_gap_abs(1e-10)
            .tol_gap_rel(1e-6)
            .iterative_refinement_enable(!quick)
            .build()
            .ok()?;
        let mut solver = DefaultSolver::new(&p, &c, &a, &b, &cones, settings).ok()?;
        // The optimum itself is not needed: stop once the iterate is nearly
        // feasible and both bounds agree on the sign of `delta - f C t`
        // (whatever comes back is checked exactly).
        solver.set_termination_callback(move |info: &DefaultInfo<f64>| {
            let within = |residual: f64| info.res_primal <= residual && info.res_dual <= residual;
            // A search that proves stops at a coarser iterate than one that
            // cannot: a proof is re-checked exactly at once, and stands or
            // falls by that check, while the iterate of a search that cannot
            // prove is kept as the candidate re-checked cycle after cycle,
            // where a coarser one proves later.
            let proves = info.cost_primal < -EARLY_VALUE && info.cost_dual < -EARLY_VALUE;
            if proves && within(PROOF_RESIDUAL) {
                return true;
            }
            // A full search that proves nothing runs to its optimum: that
            // safe state is kept and re-checked as the slip moves on. A
            // quick one stops as soon as both bounds say that it cannot
            // prove anything: its iterate is as good a candidate to keep
            // and re-check, and the full search, later, finds the best.
            let hopeless = quick && info.cost_primal > 0.0 && info.cost_dual > 0.0;
            hopeless && within(EARLY_RESIDUAL)
        });
        solver.solve();
        // Whatever the solver stopped at is only a candidate (checked
        // exactly) or, in a search's first rounds, a guide to the rows
        // that bind: so the last iterate of a search that ran out of
        // progress or iterations serves too. (On the few rows a search
        // starts from, the programme can be nearly unbounded: the iterate runs
        // to the distance cap and Clarabel reports insufficient progress.
        // Refused, it left runs such as lambda = 3.25, path 7,-7 of the
        // Fig. 3 map unproven until cycle 37; the next round, on the rows
        // that iterate violates, proves it after cycle 2.) No time limit is
        // set, so there is no `MaxTime`.
        match solver.solution.status {
            SolverStatus::Solved
            | SolverStatus::AlmostSolved
            | SolverStatus::CallbackTerminated
            | SolverStatus::InsufficientProgress
            | SolverStatus::MaxIterations => {
                let x = solver.solution.x[..=v].to_vec();
                x.iter().all(|x| x.is_finite()).then_some(x)
            }
            _ => None,
        }
    }
}

/// A basis for the change `z` of the slip towards a safe state, orthonormal
/// in the energy `z^T |D| z`: the harmonics `cos(k theta)`, `sin(k theta)`,
/// `k = 1 .. N/2 - 1`, scaled by `1 / sqrt(N k / 2)`, and the Nyquist mode.
/// (A rigid rotation changes nothing and is left out.) Each column is kept
/// as the slip, `|D|` of it and `H` of it (`H cos = sin`, `H sin = -cos`).
/// Fewer harmonics were tried: with 32 or 16 the proofs come hundreds of
/// cycles later or not at all, since a safe state needs local corrections.
#[derive(Debug, Clone)]
struct Basis {
    size: usize,
    slip: Vec<f64>,
    relief: Vec<f64>,
    pressure: Vec<f64>,
}

impl Basis {
    fn harmonics(n: usize) -> Self {
        let modes = n / 2 - 1;
        let size = 2 * modes + 1;
        let mut slip = Vec::with_capacity(size * n);
        let mut relief = Vec::with_capacity(size * n);
        let mut pressure = Vec::with_capacity(size * n);
        // sin and cos of k theta_j = 2 pi (k j mod N) / N from one table:
        // N sines instead of N^2 (a run that never searches builds this
        // too, once, at its first quick test).
        let table: Vec<(f64, f64)> = (0..n)
            .map(|m| (2.0 * PI * m as f64 / n as f64).sin_cos())
            .collect();
        for k in 1..=modes {
            let kf = k as f64;
            let scale = 1.0 / (n as f64 * kf / 2.0).sqrt();
            for odd in [false, true] {
                for j in 0..n {
                    let (sin, cos) = table[k * j % n];
                    let (value, conjugate) = if odd { (sin, -cos) } else { (cos, sin) };
                    slip.push(scale * value);
                    relief.push(scale * kf * value);
                    pressure.push(scale * conjugate);
                }
            }
        }
        // The Nyquist mode (-1)^j: |D| gives N/2 times it, H nothing.
        let scale = 1.0 / (n as f64 * n as f64 / 2.0).sqrt();
        for j in 0..n {
            let value = if j % 2 == 0 { scale } else { -scale };
            slip.push(value);
            relief.push(value * (n / 2) as f64);
            pressure.push(0.0);
        }
        Self {
            size,
            slip,
            relief,
            pressure,
        }
    }
}

/// Early stop of a quick search that cannot prove: both objective bounds
/// above 0 with residuals below `EARLY_RESIDUAL`. One proves once both
/// bounds are below `-EARLY_VALUE` (residuals below [`PROOF_RESIDUAL`]).
const EARLY_RESIDUAL: f64 = 1e-7;
const EARLY_VALUE: f64 = 1e-8;

/// The residuals at which a search that proves stops: coarser than
/// [`EARLY_RESIDUAL`], since its iterate is checked exactly at once. The
/// Fig. 3 map's quick searches took 4162 interior-point iterations against
/// 7017 (the same rows out, every proof standing at the same cycle), and
/// the Fig. 6 map gave the same rows; at `1e-3` one run of the Fig. 3 map
/// (`lambda = 4.1`, path `-7,-7`) was proven at cycle 4 instead of 2. The
/// certificate's numbers are those of the coarser point (a looser slip
/// bound: 6.1 against 5.0 at `lambda = 4.5`, path `7,-7`).
const PROOF_RESIDUAL: f64 = 1e-4;

/// The cap on the energy distance `R` of a safe state: far beyond any
/// that proves anything (`R` is at most `delta / (f C)`, and `delta` at
/// most about `f`).
const DISTANCE_CAP: f64 = 1e3;

#[cfg(test)]
mod tests {
    use super::*;

    fn dot(a: &[f64], b: &[f64]) -> f64 {
        a.iter().zip(b).map(|(x, y)| x * y).sum()
    }

    /// A setup handed on is taken only by a search of the cycle, material
    /// and grid it was made for; any other makes its own, with the margins
    /// a fresh search has.
    #[test]
    fn a_shared_setup_is_taken_only_where_it_fits() {
        use crate::model::{Material, Plane};
        let contact = |f: f64, n: usize| {
            let material = Material::new(f, 0.3, Plane::Strain).unwrap();
            Contact::new(material, std::sync::Arc::new(Operators::new(n)))
        };
        let (c, cycle) = (contact(0.1, 64), Cycle::paper(5.0, 0.0).unwrap());
        let first = SafeStateSearch::new(&c, &cycle, 200);
        let shared = || Some(Arc::clone(first.setup()));
        let same = SafeStateSearch::sharing(shared(), &c, &cycle, 200);
        assert!(Arc::ptr_eq(same.setup(), first.setup()));
        let others = [
            (contact(0.1, 64), Cycle::paper(5.5, 0.0).unwrap(), 200),
            (contact(0.1, 64), Cycle::paper(5.0, 0.3).unwrap(), 200),
            (contact(0.2, 64), cycle.clone(), 200),
            (contact(0.1, 32), cycle.clone(), 200),
            (contact(0.1, 64), cycle.clone(), 400),
        ];
        for (c, cycle, steps) in &others {
            let search = SafeStateSearch::sharing(shared(), c, cycle, *steps);
            assert!(!Arc::ptr_eq(search.setup(), first.setup()));
            let fresh = SafeStateSearch::new(c, cycle, *steps);
            assert_eq!(search.setup().elastic, fresh.setup().elastic);
        }
    }

    #[test]
    fn coupling_bounds_the_pressure_of_any_slip_and_is_attained() {
        let n = 64;
        let ops = Operators::new(n);
        let c = coupling_constant(1.0, n);
        // Random-ish slips obey the bound.
        for seed in 1..20u64 {
            let e: Vec<f64> = (0..n)
                .map(|j| ((j as u64 * 2654435761 + seed * 97) % 1000) as f64 / 500.0 - 1.0)
                .collect();
            let he = ops.residual_pressure(&e);
            let de = ops.residual_shear(&e);
            let norm = (-dot(&e, &de)).sqrt();
            let peak = he.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(peak <= c * norm * (1.0 + 1e-12), "{peak} > {c} {norm}");
        }
        // The extremal slip: modes 1/|n| in phase at node 0, so that
        // (H e)_0 = sum 1/|n| and e^T |D| e = N sum 1/|n|.
        let e: Vec<f64> = (0..n)
            .map(|j| {
                let theta = 2.0 * PI * j as f64 / n as f64;
                (1..n / 2)
                    .map(|k| -2.0 * (k as f64 * theta).sin() / k as f64)
                    .sum()
            })
            .collect();
        let he = ops.residual_pressure(&e);
        let de = ops.residual_shear(&e);
        let norm = (-dot(&e, &de)).sqrt();
        assert!(
            (he[0].abs() / (c * norm) - 1.0).abs() < 1e-9,
            "{} vs {}",
            he[0],
            c * norm
        );
    }

    /// A full search from the rows that can bind, adding those its answer
    /// violates, ends where a search on every row does: where neither
    /// proves anything (both run to the optimum) with the same value
    /// `delta - f C R`, recomputed exactly over every row; where one
    /// proves, so does the other.
    #[test]
    fn a_search_from_the_binding_rows_ends_at_the_optimum_over_every_row() {
        use crate::model::{Material, Plane};
        let n = 64;
        let material = Material::new(0.1, 0.3, Plane::Strain).unwrap();
        let ops = Arc::new(Operators::new(n));
        let contact = Contact::new(material, Arc::clone(&ops));
        let search = SafeStateSearch::new(&contact, &Cycle::paper(5.0, 0.0).unwrap(), 200);
        let columns = search.basis().size;
        // delta - f C R of the safe state g + z for margins `m` at g.
        let value = |m: &[[f64; 2]], z: &[f64]| {
            let (p, d) = (ops.residual_pressure(z), ops.residual_shear(z));
            let delta = (0..n)
                .flat_map(|j| {
                    let f = search.friction;
                    [m[j][0] + f * p[j] - d[j], m[j][1] + f * p[j] + d[j]]
                })
                .fold(f64::INFINITY, f64::min);
            delta - search.coupling * (-dot(z, &d)).max(0.0).sqrt()
        };
        let (mut proving, mut not) = (0, 0);
        for (level, dip, width) in [
            (0.02, 0.03, 3.0),
            (0.02, 0.06, 8.0),
            (0.01, 0.2, 5.0),
            (0.005, 0.5, 12.0),
            (0.03, 1.0, 2.0),
        ] {
            // Margins with a dip about node n/4 (sign +) and n/2 (sign -).
            let margins: Vec<[f64; 2]> = (0..n)
                .map(|j| {
                    let bump = |at: f64| (-((j as f64 - at) / width).powi(2)).exp();
                    let wave = 0.01 * (2.0 * PI * 3.0 * j as f64 / n as f64).cos();
                    [
                        level + wave - dip * bump(n as f64 / 4.0),
                        level - wave - 0.5 * dip * bump(n as f64 / 2.0),
                    ]
                })
                .collect();
            let from_some = search.solve_from(&margins, columns, START_ROWS).unwrap();
            let from_all = search.solve_from(&margins, columns, f64::INFINITY).unwrap();
            let (a, b) = (value(&margins, &from_some), value(&margins, &from_all));
            assert_eq!(a > PROOF_TOLERANCE, b > PROOF_TOLERANCE, "{a} vs {b}");
            if b > PROOF_TOLERANCE {
                proving += 1;
            } else {
                not += 1;
                assert!((a - b).abs() <= 1e-6 * b.abs().max(1e-3), "{a} vs {b}");
            }
        }
        // Both kinds were met.
        assert!(proving > 0 && not > 0, "{proving} proving, {not} not");
    }

    #[test]
    fn basis_columns_carry_their_operators_and_unit_energy() {
        let n = 32;
        let ops = Operators::new(n);
        let b = Basis::harmonics(n);
        assert_eq!(b.size, n - 1);
        for col in 0..b.size {
            let z = &b.slip[col * n..(col + 1) * n];
            let relief: Vec<f64> = ops.residual_shear(z).iter().map(|v| -v).collect();
            let pressure = ops.residual_pressure(z);
            for j in 0..n {
                assert!(
                    (relief[j] - b.relief[col * n + j]).abs() < 1e-12,
                    "column {col}"
                );
                assert!(
                    (pressure[j] - b.pressure[col * n + j]).abs() < 1e-12,
                    "column {col}"
                );
            }
            for other in 0..b.size {
                let y = &b.slip[other * n..(other + 1) * n];
                let energy = dot(y, &relief);
                let expected = if other == col { 1.0 } else { 0.0 };
                assert!((energy - expected).abs() < 1e-12, "{col} {other}: {energy}");
            }
        }
    }
}
