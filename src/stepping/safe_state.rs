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
//! maximise `delta - f C R` over the safe states. Whatever the solver
//! returns is checked afresh, exactly, before it is believed.

use std::f64::consts::PI;

use clarabel::algebra::CscMatrix;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use clarabel::solver::{
    DefaultInfo, DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT,
    SecondOrderConeT, SolverStatus,
};
use serde::Serialize;

use crate::contact::{Contact, Operators};
use crate::model::Cycle;

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

/// The first search for a safe state is made after this cycle, and only
/// after a cycle whose `W` fell slowly ([`SLOW_FALL`]). A search costs about
/// as much as 50 to 80 cycles at `N = 128`: most runs settle by themselves
/// before cycle 20, and a `W` that falls fast reaches a cycle without slip
/// (or its level) sooner than a search would pay for itself. On the Fig. 3
/// map this leaves 8 searches in 2275 runs; in `fig6`, 318 in 1225.
pub(crate) const FIRST_ATTEMPT: usize = 20;

/// A search is made only after a cycle whose `W` fell by less than this
/// factor from the cycle before (see `Stepper`).
pub(crate) const SLOW_FALL: f64 = 0.8;
/// Later searches are spaced by this factor in the cycle count. The best
/// safe state hardly depends on the slip reached (a search at cycle 35
/// finds the one found at cycle 10 to 1e-9), so the candidate found is
/// re-checked after every cycle, at `O(N)`, and searches are rare.
const ATTEMPT_GROWTH: f64 = 4.0;

/// The search for a safe state, and the best candidate so far, for one run.
#[derive(Debug, Clone)]
pub struct SafeStateSearch {
    friction: f64,
    /// `f C` (module docs).
    coupling: f64,
    /// The least of `f p - s q` over the cycle's load points with no slip,
    /// per node and sign `s = +1, -1`, less the allowance for a path that
    /// leaves the chords ([`Self::new`]).
    elastic: Vec<[f64; 2]>,
    /// The basis of the cone programme's slip change.
    basis: Basis,
    /// The best safe state found: `g_s`, `|D| g_s` and its margin.
    candidate: Option<(Vec<f64>, Vec<f64>, f64)>,
    next_attempt: usize,
    /// Searches run (cone programmes solved).
    pub searches: usize,
}

/// `f C` for `N` nodes: the largest `|f (H e)_j|` over `e` with
/// `e^T |D| e = 1` (Cauchy-Schwarz on the Fourier modes, attained).
pub fn coupling_constant(friction: f64, nodes: usize) -> f64 {
    let harmonic: f64 = (1..nodes / 2).map(|k| 1.0 / k as f64).sum();
    friction * (2.0 * harmonic / nodes as f64).sqrt()
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
        let n = contact.nodes();
        let friction = contact.material().friction();
        let mut elastic = vec![[f64::INFINITY; 2]; n];
        for j in 0..steps {
            let (p, q) = contact.elastic_tractions(cycle.at(2.0 * PI * j as f64 / steps as f64));
            for (e, (p, q)) in elastic.iter_mut().zip(p.iter().zip(&q)) {
                e[0] = e[0].min(friction * p - q);
                e[1] = e[1].min(friction * p + q);
            }
        }
        let dt = 2.0 * PI / steps as f64;
        let allowance =
            std::f64::consts::SQRT_2 * friction / (2.0 * PI) * cycle.load_factor() * dt * dt / 8.0;
        for e in &mut elastic {
            e[0] -= allowance;
            e[1] -= allowance;
        }
        let basis = Basis::harmonics(n);
        Self {
            friction,
            coupling: coupling_constant(friction, n),
            elastic,
            basis,
            candidate: None,
            next_attempt: FIRST_ATTEMPT,
            searches: 0,
        }
    }

    /// After complete cycle `cycle` (with `W` = `dissipation`, and `falling`
    /// when it fell from the cycle before): a certificate if the contact's
    /// present slip is proven to shake down.
    pub fn check(
        &mut self,
        contact: &Contact,
        ops: &Operators,
        cycle: usize,
        dissipation: f64,
        falling: bool,
    ) -> Option<Certificate> {
        if self.candidate.is_none() && (cycle < self.next_attempt || !falling) {
            return None;
        }
        let g = contact.slip();
        // |D| g afresh from g (the contact's own copy is updated increment
        // by increment): O(N^2), some microseconds a cycle.
        let relief: Vec<f64> = ops.residual_shear(g).iter().map(|v| -v).collect();
        if let Some(c) = self.certify_candidate(g, &relief, cycle, dissipation) {
            return Some(c);
        }
        if cycle < self.next_attempt || !falling {
            return None;
        }
        self.next_attempt = ((cycle as f64 * ATTEMPT_GROWTH).ceil() as usize).max(cycle + 1);
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
        self.searches += 1;
        let z = self.solve(&margins)?;
        let safe: Vec<f64> = g.iter().zip(&z).map(|(a, b)| a + b).collect();
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
                self.value(g, &relief, (&safe, &safe_relief, margin))
                    > self.value(g, &relief, (old, old_relief, *old_margin))
            }
        };
        if keep {
            self.candidate = Some((safe, safe_relief, margin));
        }
        self.certify_candidate(g, &relief, cycle, dissipation)
    }

    /// `f p - s q` at the least point of the cycle, per node and sign, for
    /// locked-in slip with residual pressure `pressure` (`H g`) and relief
    /// `relief` (`|D| g`).
    fn margins(&self, pressure: &[f64], relief: &[f64]) -> Vec<[f64; 2]> {
        self.elastic
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

    /// The cone programme for a safe state `g_s = g + z`, `z = Z u` in the
    /// basis ([`Basis`]), `t >= |u| = R`: maximise `delta - f C t` subject
    /// to, at every node `j` and sign `s`,
    /// `margin_js + f (H z)_j + s (|D| z)_j >= delta`. Returns `z`, or
    /// `None` if the solver finds no optimum.
    fn solve(&self, margins: &[[f64; 2]]) -> Option<Vec<f64>> {
        let n = margins.len();
        let basis = &self.basis;
        let v = basis.size;
        let f = self.friction;
        let rows = 2 * n;
        // Variables: u (v), delta, t. Rows: the margins, t <= cap, then the
        // cone (t, u).
        let total = rows + 1 + (v + 1);
        let mut colptr = Vec::with_capacity(v + 3);
        let mut rowval = Vec::with_capacity((rows + 1) * v + rows + 2);
        let mut nzval = Vec::with_capacity((rows + 1) * v + rows + 2);
        colptr.push(0);
        for col in 0..v {
            let shear = &basis.relief[col * n..(col + 1) * n];
            let pressure = &basis.pressure[col * n..(col + 1) * n];
            for j in 0..n {
                // -s (|D| z)_j - f (H z)_j + delta <= margin_js
                rowval.push(2 * j);
                nzval.push(-shear[j] - f * pressure[j]);
                rowval.push(2 * j + 1);
                nzval.push(shear[j] - f * pressure[j]);
            }
            rowval.push(rows + 2 + col);
            nzval.push(-1.0);
            colptr.push(nzval.len());
        }
        for r in 0..rows {
            rowval.push(r);
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
        for (j, m) in margins.iter().enumerate() {
            b[2 * j] = m[0];
            b[2 * j + 1] = m[1];
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
            .build()
            .ok()?;
        let mut solver = DefaultSolver::new(&p, &c, &a, &b, &cones, settings).ok()?;
        // The optimum itself is not needed: stop once the iterate is nearly
        // feasible and both bounds agree on the sign of `delta - f C t`
        // (whatever comes back is checked exactly).
        let verdict = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&verdict);
        solver.set_termination_callback(move |info: &DefaultInfo<f64>| {
            if info.res_primal > EARLY_RESIDUAL || info.res_dual > EARLY_RESIDUAL {
                return false;
            }
            // A search that proves nothing runs to its optimum: that safe
            // state is kept and re-checked as the slip moves on.
            let proves = info.cost_primal < -EARLY_VALUE && info.cost_dual < -EARLY_VALUE;
            flag.store(proves, Ordering::Relaxed);
            proves
        });
        solver.solve();
        match solver.solution.status {
            SolverStatus::CallbackTerminated if !verdict.load(Ordering::Relaxed) => None,
            SolverStatus::Solved
            | SolverStatus::AlmostSolved
            | SolverStatus::CallbackTerminated => {
                let u = &solver.solution.x[..v];
                if !u.iter().all(|x| x.is_finite()) {
                    return None;
                }
                let mut z = vec![0.0; n];
                for (col, &uc) in u.iter().enumerate() {
                    for (zj, bj) in z.iter_mut().zip(&basis.slip[col * n..(col + 1) * n]) {
                        *zj += uc * bj;
                    }
                }
                Some(z)
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
        for k in 1..=modes {
            let kf = k as f64;
            let scale = 1.0 / (n as f64 * kf / 2.0).sqrt();
            for odd in [false, true] {
                for j in 0..n {
                    let (sin, cos) = (kf * 2.0 * PI * j as f64 / n as f64).sin_cos();
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

/// Early stop of a search that proves shakedown: residuals below this, and
/// both objective bounds below `-EARLY_VALUE`.
const EARLY_RESIDUAL: f64 = 1e-7;
const EARLY_VALUE: f64 = 1e-8;

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
