//! Solutions on the current set: the base's solutions corrected through
//! the capacitance system of the pinned and reversed nodes (the Woodbury
//! identity), for the unit load directions and for any right-hand side.

use super::*;

impl SetInverse {
    /// The slip rates of the set for the load direction `(ux, uy)`,
    /// `M_SS^-1 (ux b_x + uy b_y)`, from the kept solutions into `out` by
    /// node (other nodes untouched); false if not finite. Needs
    /// [`Self::set_loads`].
    pub(crate) fn rates(&self, ux: f64, uy: f64, out: &mut [f64]) -> bool {
        debug_assert!(self.loads.is_some(), "rates without loads");
        let k = self.nodes.len();
        let mut finite = true;
        let [sx, sy] = if self.special.is_empty() {
            &self.base_sol
        } else {
            &self.sol
        };
        if self.special.is_empty() {
            // No pinned node: no role to look at.
            for ((&node, &x), &y) in self.nodes.iter().zip(&sx[..k]).zip(&sy[..k]) {
                let r = ux * x + uy * y;
                finite &= r.is_finite();
                out[node] = r;
            }
            return finite;
        }
        let positions = self.nodes.iter().zip(&self.roles);
        for (((&node, &role), &x), &y) in positions.zip(&sx[..k]).zip(&sy[..k]) {
            if role != Role::Pinned {
                let r = ux * x + uy * y;
                finite &= r.is_finite();
                out[node] = r;
            }
        }
        finite
    }

    /// `x = A^-1 x` (by position of `A`), through the factors.
    pub(super) fn solve_base(&mut self, x: &mut [f64]) {
        let (k, ld) = (self.nodes.len(), self.ld);
        let y = &mut self.v;
        for (yi, &p) in y[..k].iter_mut().zip(&self.perm) {
            *yi = x[p];
        }
        let f = Factors {
            lu: &self.lu,
            ld,
            k,
        };
        triangular(f, Pass::Lower { y, from: 0 });
        triangular(f, Pass::Inverse { y });
        x[..k].copy_from_slice(&y[..k]);
    }

    /// Factorise the capacitance system of the correction and apply it to
    /// the kept solutions; false if it is singular to working precision.
    pub(super) fn correct(&mut self) -> bool {
        // Without loads there are no kept solutions to correct.
        if self.special.is_empty() || self.loads.is_none() {
            return true;
        }
        if !self.factor_capacitance() {
            return false;
        }
        let k = self.nodes.len();
        for d in 0..2 {
            let mut out = std::mem::take(&mut self.sol[d]);
            let base = std::mem::take(&mut self.base_sol[d]);
            // The change of the reversed rows' right-hand sides.
            for (t, &q) in self.special.iter().enumerate() {
                let (node, s) = (self.nodes[q], self.signs[q]);
                self.coef[t] = self.rhs(node, -s)[d] - self.rhs(node, s)[d];
            }
            let ok = self.apply_correction(&base[..k], &mut out[..k]);
            self.sol[d] = out;
            self.base_sol[d] = base;
            if !ok {
                return false;
            }
        }
        true
    }

    /// The capacitance system of the pinned and reversed positions `q`
    /// (slots `t`), for the unknowns `z_t` of `x = x_A + sum_t z_t A^-1 e_q`:
    /// a reversed row `t` says `z_t = beta_t - delta_t . x`, a pinned row
    /// says `x_q = 0`.
    pub(super) fn factor_capacitance(&mut self) -> bool {
        let (n, k, m) = (self.n, self.nodes.len(), self.special.len());
        let mut scale = 0.0f64;
        for b in 0..m {
            let w = &self.special_cols[b * n..b * n + k];
            for (a, &q) in self.special.iter().enumerate() {
                let c = if self.roles[q] == Role::Reversed {
                    let delta = &self.deltas[a * n..a * n + k];
                    f64::from(u8::from(a == b)) + dot(delta, w)
                } else {
                    w[q]
                };
                scale = scale.max(c.abs());
                self.capacitance.lu[b * m + a] = c;
            }
        }
        self.capacitance.factorise(m);
        (0..m).all(|i| {
            let d = self.capacitance.lu[i * m + i];
            d.is_finite() && d.abs() > PIVOT_TOL * scale
        })
    }

    /// `out = x_A + sum_t z_t A^-1 e_q` for the base solution `base`
    /// (`x_A`) and the reversed rows' right-hand side changes in `coef`,
    /// with the capacitance system factorised; 0 at pinned positions.
    pub(super) fn apply_correction(&mut self, base: &[f64], out: &mut [f64]) -> bool {
        let (n, k, m) = (self.n, self.nodes.len(), self.special.len());
        let mut z = std::mem::take(&mut self.coef);
        for (t, &q) in self.special.iter().enumerate() {
            z[t] = if self.roles[q] == Role::Reversed {
                z[t] - dot(&self.deltas[t * n..t * n + k], base)
            } else {
                -base[q]
            };
        }
        self.capacitance.solve(&mut z[..m]);
        out.copy_from_slice(base);
        if k >= structured::MIN_NODES {
            // Four columns a pass over `out` in the lanes of [`Kernel`]
            // (below `MIN_NODES` the plain loops' numbers, as in
            // [`Self::follow_border`]).
            let mut cols: [&[f64]; MAX_SPECIAL] = [&[]; MAX_SPECIAL];
            let mut c = [0.0; MAX_SPECIAL];
            for (t, (w, c)) in cols.iter_mut().zip(&mut c).enumerate().take(m) {
                *w = &self.special_cols[t * n..t * n + k];
                *c = -z[t];
            }
            axpys(self.arch, out, &cols[..m], &c[..m]);
        } else {
            for (t, &zt) in z[..m].iter().enumerate() {
                let w = &self.special_cols[t * n..t * n + k];
                for (x, &wi) in out.iter_mut().zip(w) {
                    *x += zt * wi;
                }
            }
        }
        self.coef = z;
        for &q in &self.special {
            if self.roles[q] == Role::Pinned {
                out[q] = 0.0;
            }
        }
        // Every entry tested (no early exit), so the test vectorises.
        out.iter().fold(true, |ok, x| ok & x.is_finite())
    }

    /// `x = M_SS^-1 b` with `b` given per node by `rhs(node, sign)`; the
    /// result goes to `out` by node (other nodes untouched).
    #[cfg(test)]
    pub(crate) fn solve(&mut self, rhs: impl Fn(usize, f64) -> f64, out: &mut [f64]) -> bool {
        let k = self.nodes.len();
        let mut x = vec![0.0; self.n];
        for (p, xp) in x[..k].iter_mut().enumerate() {
            *xp = rhs(self.nodes[p], self.signs[p]);
        }
        if k > 0 {
            self.solve_base(&mut x);
        }
        let mut sol = x.clone();
        if !self.special.is_empty() {
            for (t, &q) in self.special.iter().enumerate() {
                let (node, s) = (self.nodes[q], self.signs[q]);
                self.coef[t] = rhs(node, -s) - rhs(node, s);
            }
            assert!(self.factor_capacitance());
            if !self.apply_correction(&x[..k], &mut sol[..k]) {
                return false;
            }
        }
        let mut finite = true;
        for p in 0..k {
            if self.roles[p] != Role::Pinned {
                finite &= sol[p].is_finite();
                out[self.nodes[p]] = sol[p];
            }
        }
        finite
    }
}
