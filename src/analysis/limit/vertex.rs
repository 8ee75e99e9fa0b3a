//! The optimum of the `lambda_2` programme as an exact vertex, found by
//! simplex pivots from a guessed active set and certified by LP duality
//! (model.md section 7.3).
//!
//! At the optimum of the programme in `(g, lambda)` (`N + 1` unknowns) the
//! active rows are, but for a node or two, one row per node: the sign at
//! which the node's friction limit binds. A guess of that set, taken from
//! the optimum on half the nodes, is a basis: `N` friction rows and
//! `mean g = 0` make a square system whose solution is a vertex. Pivots then
//! move the basis to the optimum: dual simplex pivots (the most violated
//! row enters) while the multipliers are non-negative, primal simplex pivots
//! (the most negative multiplier leaves) once every row holds. A guess whose
//! multipliers are not all non-negative is first made dual feasible by
//! shifting the objective (the shifted programme's optimum is primal
//! feasible, and primal pivots then restore the true objective).
//!
//! The answer is accepted only with its certificate: every row holds and
//! every multiplier is non-negative (to round-off), which by LP duality makes
//! the vertex optimal. Anything else (no certificate within the pivot cap, a
//! singular basis, an infeasible or unbounded programme) returns `None` and
//! the caller solves the programme by the interior-point method instead.
//!
//! Each pivot replaces one row of the basis matrix `K`: the solves use the
//! factorisation of the basis the search started from and the
//! Sherman-Morrison-Woodbury formula for the rows replaced since, so a pivot
//! costs `O(N^2)` rather than the `O(N^3)` of a new factorisation.

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::Mat;

use super::{Programme, Row, SIGNS};
use crate::contact::FftScratch;

/// Pivots allowed per search, as a multiple of `N` (plus a constant): a
/// good guess needs a few per node that changed sign between the grids.
const PIVOTS_PER_NODE: usize = 2;
/// Rounds of dual then primal pivots: a round ends with the certificate
/// checked on a fresh factorisation, and round-off that leaves a row
/// violated there sends the search back to dual pivots.
const ROUNDS: usize = 4;
/// Rows replaced before the basis is factorised anew.
const REFACTOR_AFTER: usize = 48;

/// An optimal vertex with its certificate.
#[derive(Debug, Clone)]
pub(super) struct Vertex {
    /// The slip `g` (mean zero) and `lambda`.
    pub slip: Vec<f64>,
    pub load_factor: f64,
    /// Pivots taken from the guess.
    pub pivots: usize,
}

/// One row replaced in the basis: `K = K0 + e_slot d^T` for each.
struct Update {
    slot: usize,
    /// `d = a_new - a_old`.
    change: Vec<f64>,
    /// `K0^-1 e_slot`.
    column: Vec<f64>,
    /// `K0^-T d`.
    row: Vec<f64>,
}

/// The basis: which row sits in each of the `N` friction slots (slot `N`
/// is `mean g = 0`), with the factorisation of `K0` and the updates since.
struct Basis<'p, 'a> {
    lp: &'p Programme<'a>,
    rows: &'p [Row],
    slots: Vec<usize>,
    in_basis: Vec<bool>,
    k0: PartialPivLu<f64>,
    /// The rows replaced since `K0` was factorised.
    updates: Vec<Update>,
    /// LU of the capacitance `C = I + D^T K0^-1 E` (`p x p`).
    capacitance: Option<PartialPivLu<f64>>,
}

impl<'p, 'a> Basis<'p, 'a> {
    fn new(lp: &'p Programme<'a>, rows: &'p [Row], slots: Vec<usize>) -> Self {
        let mut in_basis = vec![false; rows.len()];
        for &s in &slots {
            in_basis[s] = true;
        }
        let k0 = Self::factor(lp, rows, &slots);
        Self {
            lp,
            rows,
            slots,
            in_basis,
            k0,
            updates: Vec::new(),
            capacitance: None,
        }
    }

    fn factor(lp: &Programme, rows: &[Row], slots: &[usize]) -> PartialPivLu<f64> {
        let n = slots.len();
        let mut k = Mat::<f64>::zeros(n + 1, n + 1);
        for (slot, &r) in slots.iter().enumerate() {
            let a = lp.row(rows[r]);
            for (c, v) in a.iter().enumerate() {
                k[(slot, c)] = *v;
            }
        }
        for c in 0..n {
            k[(n, c)] = 1.0 / n as f64;
        }
        k.partial_piv_lu()
    }

    fn lu_solve(lu: &PartialPivLu<f64>, rhs: &[f64], transpose: bool) -> Vec<f64> {
        let mut m = Mat::<f64>::from_fn(rhs.len(), 1, |i, _| rhs[i]);
        if transpose {
            lu.solve_transpose_in_place(&mut m);
        } else {
            lu.solve_in_place(&mut m);
        }
        (0..rhs.len()).map(|i| m[(i, 0)]).collect()
    }

    /// `K x = rhs`.
    fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        let mut x = Self::lu_solve(&self.k0, rhs, false);
        if let Some(cap) = &self.capacitance {
            // x = z - Z C^-1 D^T z
            let t: Vec<f64> = self.updates.iter().map(|u| dot(&u.change, &x)).collect();
            let w = Self::lu_solve(cap, &t, false);
            for (u, wi) in self.updates.iter().zip(&w) {
                for (xi, zi) in x.iter_mut().zip(&u.column) {
                    *xi -= wi * zi;
                }
            }
        }
        x
    }

    /// `K^T y = rhs`.
    fn solve_transpose(&self, rhs: &[f64]) -> Vec<f64> {
        let mut y = Self::lu_solve(&self.k0, rhs, true);
        if let Some(cap) = &self.capacitance {
            // y = v - Y C^-T E^T v, with Y = K0^-T D
            let t: Vec<f64> = self.updates.iter().map(|u| y[u.slot]).collect();
            let w = Self::lu_solve(cap, &t, true);
            for (u, wi) in self.updates.iter().zip(&w) {
                for (yi, vi) in y.iter_mut().zip(&u.row) {
                    *yi -= wi * vi;
                }
            }
        }
        y
    }

    /// Factorise the current basis afresh, dropping the updates.
    fn refactor(&mut self) {
        self.k0 = Self::factor(self.lp, self.rows, &self.slots);
        self.updates.clear();
        self.capacitance = None;
    }

    /// Put row `enter` in the slot of row `leave`.
    fn pivot(&mut self, leave_slot: usize, enter: usize) {
        let leave = self.slots[leave_slot];
        self.in_basis[leave] = false;
        self.in_basis[enter] = true;
        self.slots[leave_slot] = enter;
        if self.updates.len() >= REFACTOR_AFTER {
            self.refactor();
            return;
        }
        let a_new = self.lp.row(self.rows[enter]);
        let a_old = self.lp.row(self.rows[leave]);
        let d: Vec<f64> = a_new.iter().zip(&a_old).map(|(x, y)| x - y).collect();
        let mut e = vec![0.0; d.len()];
        e[leave_slot] = 1.0;
        let z = Self::lu_solve(&self.k0, &e, false);
        let v = Self::lu_solve(&self.k0, &d, true);
        self.updates.push(Update {
            slot: leave_slot,
            change: d,
            column: z,
            row: v,
        });
        let p = self.updates.len();
        let c = Mat::<f64>::from_fn(p, p, |i, j| {
            f64::from(u8::from(i == j)) + dot(&self.updates[i].change, &self.updates[j].column)
        });
        self.capacitance = Some(c.partial_piv_lu());
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Programme<'_> {
    /// Row `row` of the constraint matrix over `(g, lambda)`:
    /// `s q_j - f p_j` with `q = -|D| g`, `p = H g`, and `rate` on `lambda`.
    /// `|D|` is symmetric and `H` antisymmetric, so row `j` is a column.
    pub(super) fn row(&self, row: Row) -> Vec<f64> {
        let s = SIGNS[row.sign];
        let (h, d) = (
            self.ops.hilbert_col(row.node),
            self.ops.abs_derivative_col(row.node),
        );
        let mut a: Vec<f64> = h
            .iter()
            .zip(d)
            .map(|(h, d)| -s * d + self.friction * h)
            .collect();
        a.push(row.rate);
        a
    }

    /// The right-hand side `b_r = f p_center - s q_center` of row `row`.
    pub(super) fn rhs(&self, row: Row) -> f64 {
        let j = row.node;
        self.friction * self.p_center[j] - SIGNS[row.sign] * self.q_center[j]
    }

    /// `b - A x` for every row (`rows` in the order `2 j + sign`).
    fn slacks(&self, rows: &[Row], x: &[f64], scratch: &mut FftScratch) -> Vec<f64> {
        let n = x.len() - 1;
        let (mut p, mut r) = (vec![0.0; n], vec![0.0; n]);
        self.ops.apply_both(&x[..n], &mut p, &mut r, scratch);
        rows.iter()
            .map(|&row| {
                let s = SIGNS[row.sign];
                let ax = -s * r[row.node] - self.friction * p[row.node] + row.rate * x[n];
                self.rhs(row) - ax
            })
            .collect()
    }

    /// `A d` for every row.
    fn products(&self, rows: &[Row], d: &[f64], scratch: &mut FftScratch) -> Vec<f64> {
        let n = d.len() - 1;
        let (mut p, mut r) = (vec![0.0; n], vec![0.0; n]);
        self.ops.apply_both(&d[..n], &mut p, &mut r, scratch);
        rows.iter()
            .map(|&row| {
                -SIGNS[row.sign] * r[row.node] - self.friction * p[row.node] + row.rate * d[n]
            })
            .collect()
    }

    /// The optimal vertex from the guessed active rows `guess` (one per
    /// node), or `None` when no certificate is reached.
    pub(super) fn vertex(&self, rows: &[Row], guess: Vec<usize>) -> Option<Vertex> {
        let n = self.p_center.len();
        if guess.len() != n {
            return None;
        }
        // A row's value `a . x` is a sum of `N` products whose largest
        // partial sums are about `|A|_inf |x|_inf` (`|A|_inf`, the largest
        // row sum, grows as `N / 2` through `|D|`): its round-off, and so
        // the tolerance on a row, scales with that and with `b`.
        let scale = rows.iter().map(|&r| self.rhs(r).abs()).fold(1.0, f64::max);
        let (h, d) = (self.ops.hilbert_col(0), self.ops.abs_derivative_col(0));
        let rate = rows.iter().map(|r| r.rate.abs()).fold(0.0, f64::max);
        let norm = d.iter().map(|v| v.abs()).sum::<f64>()
            + self.friction * h.iter().map(|v| v.abs()).sum::<f64>()
            + rate;
        let tol_primal = |x: &[f64]| {
            let size = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            1e-13 * (scale + norm * size)
        };
        let mut basis = Basis::new(self, rows, guess);
        let mut scratch = FftScratch::default();
        let mut objective = vec![0.0; n + 1];
        objective[n] = 1.0;
        let multipliers = |basis: &Basis, c: &[f64]| basis.solve_transpose(c);
        // Shift the objective so that the guess is dual feasible.
        let y0 = multipliers(&basis, &objective);
        let ymax = y0[..n].iter().fold(0.0f64, |m, y| m.max(y.abs()));
        let tol_dual = 1e-11 * ymax.max(1e-300);
        let shifted = if y0[..n].iter().any(|&y| y < -tol_dual) {
            let mut y = y0.clone();
            for v in &mut y[..n] {
                *v = v.max(0.0);
            }
            // c' = K^T y'
            let mut c = vec![0.0; n + 1];
            for (slot, &r) in basis.slots.iter().enumerate() {
                let a = self.row(rows[r]);
                for (ci, ai) in c.iter_mut().zip(&a) {
                    *ci += y[slot] * ai;
                }
            }
            for ci in &mut c[..n] {
                *ci += y[n] / n as f64;
            }
            Some(c)
        } else {
            None
        };
        let cap = PIVOTS_PER_NODE * n + 50;
        let mut pivots = 0;
        let rhs = |basis: &Basis| -> Vec<f64> {
            basis
                .slots
                .iter()
                .map(|&r| self.rhs(rows[r]))
                .chain(std::iter::once(0.0))
                .collect()
        };
        // Dual simplex on the shifted objective first; on the true one when
        // round-off left a row violated at the end of the primal pivots.
        let mut dual_objective = shifted.unwrap_or_else(|| objective.clone());
        for _round in 0..ROUNDS {
            loop {
                let x = basis.solve(&rhs(&basis));
                let slack = self.slacks(rows, &x, &mut scratch);
                let tol = tol_primal(&x);
                let Some((enter, _)) = slack
                    .iter()
                    .enumerate()
                    .filter(|&(r, &s)| !basis.in_basis[r] && s < -tol)
                    .min_by(|a, b| a.1.total_cmp(b.1))
                else {
                    break;
                };
                if pivots == cap {
                    return None;
                }
                let y = multipliers(&basis, &dual_objective);
                let delta = basis.solve_transpose(&self.row(rows[enter]));
                // y(t) = y - t delta stays >= 0: the first slot to reach 0
                // leaves.
                let leave = (0..n)
                    .filter(|&s| delta[s] > 1e-14 * (1.0 + delta[s].abs()))
                    .min_by(|&a, &b| {
                        (y[a].max(0.0) / delta[a]).total_cmp(&(y[b].max(0.0) / delta[b]))
                    })?;
                basis.pivot(leave, enter);
                pivots += 1;
            }
            // Primal simplex on the true objective from the feasible vertex.
            loop {
                let x = basis.solve(&rhs(&basis));
                let y = multipliers(&basis, &objective);
                let Some((leave, _)) = y[..n]
                    .iter()
                    .enumerate()
                    .filter(|&(_, &v)| v < -tol_dual)
                    .min_by(|a, b| a.1.total_cmp(b.1))
                else {
                    break;
                };
                if pivots == cap {
                    return None;
                }
                // Move off row `leave`: K d = -e_leave, lambda rises by -y.
                let mut e = vec![0.0; n + 1];
                e[leave] = -1.0;
                let d = basis.solve(&e);
                let slack = self.slacks(rows, &x, &mut scratch);
                let ad = self.products(rows, &d, &mut scratch);
                let (enter, _) = (0..rows.len())
                    .filter(|&r| !basis.in_basis[r] && ad[r] > 1e-14)
                    .map(|r| (r, slack[r].max(0.0) / ad[r]))
                    .min_by(|a, b| a.1.total_cmp(&b.1))?;
                basis.pivot(leave, enter);
                pivots += 1;
            }
            // The certificate, from a fresh factorisation (without the
            // updates' round-off): every row holds, every multiplier is
            // non-negative.
            basis.refactor();
            let x = basis.solve(&rhs(&basis));
            let y = multipliers(&basis, &objective);
            let slack = self.slacks(rows, &x, &mut scratch);
            let primal = slack.iter().all(|&s| s >= -tol_primal(&x));
            let dual = y[..n].iter().all(|&v| v >= -tol_dual);
            if primal && dual && x[n].is_finite() {
                let mean = x[..n].iter().sum::<f64>() / n as f64;
                return Some(Vertex {
                    slip: x[..n].iter().map(|g| g - mean).collect(),
                    load_factor: x[n],
                    pivots,
                });
            }
            dual_objective.clone_from(&objective);
        }
        None
    }
}
