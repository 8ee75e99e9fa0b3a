//! The cone programme of a safe-state search (Clarabel): maximise
//! `delta - f C R` over the safe states `g + B c`, from the rows of the
//! cycle's least elastic margins, growing the rows it holds to.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultInfo, DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT,
    SecondOrderConeT, SolverStatus,
};

use super::*;

impl SafeStateSearch {
    /// A safe state `g_s = g + z`, with `z = Z u` over the first `columns`
    /// columns of the basis ([`Basis`]): the change `z`, or `None` if the
    /// cone programme finds no optimum. It starts from the rows that can
    /// bind ([`START_ROWS`]) and adds those its answer violates; an answer
    /// that violates none is the optimum over every row. Either way the
    /// answer is only a candidate: its margin is recomputed exactly before
    /// it proves anything.
    pub(super) fn solve(&self, margins: &[[f64; 2]], columns: usize) -> Option<Vec<f64>> {
        self.solve_from(margins, columns, START_ROWS)
    }

    /// [`Self::solve`] from the rows below `start` times the largest margin
    /// (every row for `f64::INFINITY`).
    pub(super) fn solve_from(
        &self,
        margins: &[[f64; 2]],
        columns: usize,
        start: f64,
    ) -> Option<Vec<f64>> {
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
    pub(super) fn cone_programme(
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
