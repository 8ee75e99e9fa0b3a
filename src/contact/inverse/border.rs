//! A node enters: the bordering of the dense factors by its row and
//! column (one pass over them, [`crate::contact::kernels::border_pass`]),
//! and the kept solutions and correction columns that follow it.

use super::*;

impl SetInverse {
    /// Node `a` enters with sign `sign`: `A` is bordered by its column and
    /// row, and the kept solutions and correction columns follow; false if
    /// the Schur complement is too small (the caller refactorises).
    ///
    /// Next to an arc of a base of a few arcs, by the arcs' structure
    /// ([`structured`]); else through the dense factors (bordered up to
    /// the set first if structured borderings left them behind), after
    /// which a large base of a few arcs takes up the structured ones.
    pub(super) fn border(&mut self, ops: &Operators, a: usize, sign: f64) -> bool {
        if self.structured.is_some() {
            match self.border_structured(ops, a, sign) {
                Bordered::Done => return true,
                Bordered::Singular => return false,
                Bordered::NotHere => {
                    if !self.catch_up(ops) {
                        return false;
                    }
                }
            }
        }
        // Kept if the node starts an arc of its own.
        let kept = self.structured.take();
        let k = self.nodes.len();
        let Some(sigma) = self.extend_factors(ops, k, a, sign) else {
            return false;
        };
        self.follow_border(ops, a, sign, sigma);
        self.push(a, sign);
        if let Some(st) = kept {
            self.structured = st.add_arc(self, ops, a, sign, sigma);
            return true;
        }
        if k + 1 >= structured::MIN_NODES && self.last_entry + structured::MIN_NODES / 4 <= k {
            self.last_entry = k;
            self.structured = Structured::enter(self, ops);
        }
        true
    }

    /// Append node `a` with sign `sign` to the base, active.
    pub(super) fn push(&mut self, a: usize, sign: f64) {
        self.pos[a] = self.nodes.len();
        self.nodes.push(a);
        self.signs.push(sign);
        self.roles.push(Role::Active);
    }

    /// Border the dense factors of positions `0..p` with node `a` of sign
    /// `sign` as position `p` (its column and row over them): `l`, `u` and
    /// `v = A^-1 c` from one pass ([`border_pass`]), `v` and the row left
    /// in `self.v` and `self.row`; the Schur complement, or `None` if it is
    /// too small.
    pub(super) fn extend_factors(
        &mut self,
        ops: &Operators,
        p: usize,
        a: usize,
        sign: f64,
    ) -> Option<f64> {
        debug_assert_eq!(self.perm.len(), p, "factors up to p");
        let (nodes, signs) = (&self.nodes[..p], &self.signs[..p]);
        let f = self.friction;
        let hcol = ops.hilbert_col(a);
        let dcol = ops.abs_derivative_col(a);
        let (col, row) = (&mut self.col[..p], &mut self.row[..p]);
        for ((c, r), (&node, &s)) in col.iter_mut().zip(row).zip(nodes.iter().zip(signs)) {
            *c = -dcol[node] - f * s * hcol[node];
            *r = -dcol[node] + f * sign * hcol[node];
        }
        let d0 = Self::entry(ops, f, a, sign, a);
        // u = L^-1 P c, l = U^-T r and v = U^-1 u = A^-1 c.
        let col = &self.col[..p];
        for (ui, &q) in self.u[..p].iter_mut().zip(&self.perm) {
            *ui = col[q];
        }
        let factors = Factors {
            lu: &self.lu,
            ld: self.ld,
            k: p,
        };
        border_pass(factors, &mut self.u, &self.row, &mut self.l, &mut self.v);
        let lu_dot = dot(&self.l[..p], &self.u[..p]);
        let sigma = d0 - lu_dot;
        let scale = d0.abs().max(lu_dot.abs());
        if !sigma.is_finite() || sigma.abs() <= PIVOT_TOL * scale {
            return None;
        }
        if p == self.ld {
            self.relayout(stride(p, self.n));
        }
        // The bordered factors: row l of L, and U's new column (u, sigma)
        // inverted, the column (-v / sigma, 1 / sigma) of W.
        let ld = self.ld;
        let lu = &mut self.lu[..];
        for (j, &lj) in self.l[..p].iter().enumerate() {
            lu[j * ld + p] = lj;
        }
        for (o, &vi) in lu[p * ld..p * ld + p].iter_mut().zip(&self.v[..p]) {
            *o = -vi / sigma;
        }
        lu[p * ld + p] = 1.0 / sigma;
        self.perm.push(p);
        self.perm_inv.push(p);
        Some(sigma)
    }

    /// Border the dense factors up to the set, where structured borderings
    /// left them behind; false at a small pivot. The kept solutions (and
    /// the structured vectors, which stay valid: the base is the same)
    /// have followed already.
    pub(super) fn catch_up(&mut self, ops: &Operators) -> bool {
        let k = self.nodes.len();
        if self.perm.len() == k {
            return true;
        }
        if self.ld < k {
            self.relayout(stride(k, self.n));
        }
        (self.perm.len()..k).all(|p| {
            let (a, sign) = (self.nodes[p], self.signs[p]);
            self.extend_factors(ops, p, a, sign).is_some()
        })
    }

    /// The kept solutions and correction columns follow the bordering of
    /// the base (of `k` positions) by node `a` with sign `sign`, given
    /// `v = A^-1 M_Sa` in `self.v`, the row `M_aS` in `self.row` and the
    /// Schur complement `sigma`.
    pub(super) fn follow_border(&mut self, ops: &Operators, a: usize, sign: f64, sigma: f64) {
        let (k, f, n, arch) = (self.nodes.len(), self.friction, self.n, self.arch);
        let hcol = ops.hilbert_col(a);
        let v = &self.v[..k];
        let row = &self.row[..k];
        // r . w for the correction's columns w and r . x for the kept
        // solutions x: four a pass over the row ([`dots`]) past
        // `MIN_NODES`; below it, one at a time in the plain loops, whose
        // numbers the runs at the defaults (`N = 128`) keep, as they keep
        // the dense borderings (the Fig. 3 map's bytes moved with the
        // lanes).
        let wide = k >= structured::MIN_NODES;
        let m = self.special.len();
        let solved = if self.loads.is_some() { 2 } else { 0 };
        let mut d = [0.0; MAX_SPECIAL + 2];
        {
            let mut vecs: [&[f64]; MAX_SPECIAL + 2] = [&[]; MAX_SPECIAL + 2];
            for (t, w) in vecs.iter_mut().enumerate().take(m) {
                *w = &self.special_cols[t * n..t * n + k];
            }
            for (x, sol) in vecs[m..m + solved].iter_mut().zip(&self.base_sol) {
                *x = &sol[..k];
            }
            if wide {
                dots(arch, &vecs[..m + solved], row, &mut d[..m + solved]);
            } else {
                for (d, x) in d.iter_mut().zip(&vecs[..m + solved]) {
                    *d = dot(row, x);
                }
            }
        }
        // The correction's columns: A_new^-1 e_q = (w + v (r.w) / sigma,
        // -(r.w) / sigma) for w = A^-1 e_q, and the reversed rows' changes
        // gain column a.
        for (t, &q) in self.special.iter().enumerate() {
            let w = &mut self.special_cols[t * n..t * n + k + 1];
            let c = d[t] / sigma;
            if wide {
                arch.dispatch(Kernel::Axpy {
                    y: &mut w[..k],
                    x: v,
                    a: -c,
                });
            } else {
                for (wi, &vi) in w[..k].iter_mut().zip(v) {
                    *wi += c * vi;
                }
            }
            w[k] = -c;
            if self.roles[q] == Role::Reversed {
                self.deltas[t * n + k] = 2.0 * f * self.signs[q] * hcol[self.nodes[q]];
            }
        }
        if self.loads.is_some() {
            // The bordered system's solution: the new entry
            // xi = (beta - r^T x) / sigma, and x - xi v on the old set.
            let betas = self.rhs(a, sign);
            for ((sol, beta), &rx) in self.base_sol.iter_mut().zip(betas).zip(&d[m..]) {
                let xi = (beta - rx) / sigma;
                if wide {
                    arch.dispatch(Kernel::Axpy {
                        y: &mut sol[..k],
                        x: v,
                        a: xi,
                    });
                } else {
                    for (x, &vi) in sol[..k].iter_mut().zip(v) {
                        *x -= xi * vi;
                    }
                }
                sol[k] = xi;
            }
        }
    }
}
