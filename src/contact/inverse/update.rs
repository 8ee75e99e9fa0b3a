//! The kept inverse follows a new slip set: the roles of the base's nodes
//! (in the set, pinned, reversed), the refactorisation from the set (faer's
//! LU), and the columns of the correction.

use super::*;

impl SetInverse {
    /// Make the solutions those of the slip set `target`, whose slipping
    /// nodes and signs in node order are `set`; false if `M_SS` is singular
    /// to working precision (the caller then has no responses).
    ///
    /// The changes are found among the nodes noted since the last update
    /// ([`Self::note_changes`]): a few, where a pass over the base's nodes
    /// (as before) cost as much as the bordering itself at `N = 128`.
    pub(crate) fn update_to(
        &mut self,
        ops: &Operators,
        friction: f64,
        target: &[SlipDirection],
        set: &[(usize, f64)],
    ) -> bool {
        debug_assert!(
            set.iter().all(|&(j, s)| target[j].sign() == s)
                && set.len() == target.iter().filter(|d| d.is_slipping()).count()
                && set.windows(2).all(|w| w[0].0 < w[1].0),
            "set is not the slipping nodes of target in node order"
        );
        if !self.valid || self.friction != friction {
            return self.rebuild(ops, friction, target);
        }
        // Nodes that enter, and positions of A whose role changes: among
        // the nodes noted since the last update only (a node not in A that
        // was not noted still sticks), in node order and position order, as
        // a pass over all of them would find them.
        let mut dirty = std::mem::take(&mut self.dirty);
        dirty.sort_unstable();
        let mut changed = std::mem::take(&mut self.changed);
        changed.clear();
        let mut entries = 0;
        let mut special = self.special.len();
        for &j in &dirty {
            let p = self.pos[j];
            if p == NONE {
                entries += usize::from(target[j].is_slipping());
                continue;
            }
            let (old, role) = (self.roles[p], self.role_in(target, p));
            if role != old {
                special =
                    special + usize::from(role != Role::Active) - usize::from(old != Role::Active);
                changed.push((p, role));
            }
        }
        changed.sort_unstable_by_key(|&(p, _)| p);
        self.dirty = dirty;
        let changes = entries + changed.len();
        if changes == 0 {
            self.changed = changed;
            self.clear_dirty();
            return true;
        }
        // Past half the set, past a few pinned or reversed nodes, or after
        // many changes since the last factorisation, a rebuild costs about
        // as much and is cleaner.
        let k = set.len();
        if 2 * changes > k.max(8)
            || self.updates + changes > k.max(16)
            || special > special_limit(self.nodes.len() + entries)
        {
            self.changed = changed;
            return self.rebuild(ops, friction, target);
        }
        let roles_set = changed.iter().all(|&(p, role)| self.set_role(ops, p, role));
        self.changed = changed;
        if !roles_set {
            return self.rebuild(ops, friction, target);
        }
        let dirty = std::mem::take(&mut self.dirty);
        let bordered = dirty.iter().all(|&j| {
            let d = target[j];
            self.pos[j] != NONE || !d.is_slipping() || self.border(ops, j, d.sign())
        });
        self.dirty = dirty;
        self.clear_dirty();
        if !bordered || !self.correct() {
            return self.rebuild(ops, friction, target);
        }
        self.updates += changes;
        true
    }

    /// A fresh LU of `M_SS` for the set of `target`, and the solutions.
    pub(super) fn rebuild(
        &mut self,
        ops: &Operators,
        friction: f64,
        target: &[SlipDirection],
    ) -> bool {
        self.clear_dirty();
        for &node in &self.nodes {
            self.pos[node] = NONE;
        }
        self.nodes.clear();
        self.signs.clear();
        self.roles.clear();
        self.special.clear();
        for (j, d) in target.iter().enumerate() {
            if d.is_slipping() {
                self.pos[j] = self.nodes.len();
                self.nodes.push(j);
                self.signs.push(d.sign());
                self.roles.push(Role::Active);
            }
        }
        self.friction = friction;
        self.updates = 0;
        self.rebuilds += 1;
        self.structured = None;
        self.last_entry = 0;
        self.valid = false;
        let k = self.nodes.len();
        self.perm.clear();
        self.perm_inv.clear();
        if k == 0 {
            self.valid = true;
            return true;
        }
        if self.lu.len() < self.n * self.n {
            self.lu = Aligned::zeros(self.n * self.n);
            self.special_cols = vec![0.0; self.n * MAX_SPECIAL];
            self.deltas = vec![0.0; self.n * MAX_SPECIAL];
            self.factor = DenseLu::new(self.n);
        }
        self.ld = stride(k, self.n);
        let ld = self.ld;
        // Assemble M_SS column-major (k x k) and factorise it.
        for (b, &col) in self.nodes.iter().enumerate() {
            let hcol = ops.hilbert_col(col);
            let dcol = ops.abs_derivative_col(col);
            let out = &mut self.factor.lu[b * k..(b + 1) * k];
            for ((o, &row), &sign) in out.iter_mut().zip(&self.nodes).zip(&self.signs) {
                *o = -dcol[row] - friction * sign * hcol[row];
            }
        }
        self.factor.factorise(k);
        for j in 0..k {
            let d = self.factor.lu[j * k + j];
            if d == 0.0 || !d.is_finite() {
                return false;
            }
        }
        for j in 0..k {
            self.lu[j * ld..j * ld + k].copy_from_slice(&self.factor.lu[j * k..(j + 1) * k]);
        }
        // U inverted over itself (L below the diagonal is left as it is).
        self.factor
            .invert_upper(k, &mut self.lu[..(k - 1) * ld + k], ld);
        self.perm.extend_from_slice(self.factor.perm(k));
        self.perm_inv.resize(k, 0);
        for (i, &p) in self.perm.iter().enumerate() {
            self.perm_inv[p] = i;
        }
        if self.loads.is_some() {
            for d in 0..2 {
                let mut x = std::mem::take(&mut self.base_sol[d]);
                for (p, xp) in x[..k].iter_mut().enumerate() {
                    *xp = self.rhs(self.nodes[p], self.signs[p])[d];
                }
                self.solve_base(&mut x);
                let finite = x[..k].iter().all(|v| v.is_finite());
                self.base_sol[d] = x;
                if !finite {
                    return false;
                }
            }
        }
        self.valid = true;
        true
    }

    /// Give the factors the column stride `ld` (at most `N`), moving their
    /// columns: `O(k^2)`, once per `k / 8` entries at most.
    pub(super) fn relayout(&mut self, ld: usize) {
        let (old, k) = (self.ld, self.perm.len());
        let ld = ld.min(self.n);
        if ld > old {
            for j in (1..k).rev() {
                self.lu.copy_within(j * old..j * old + k, j * ld);
            }
        } else {
            for j in 1..k {
                self.lu.copy_within(j * old..j * old + k, j * ld);
            }
        }
        self.ld = ld;
    }

    /// Give the position `p` of `A` the role `role` in the correction:
    /// its column `A^-1 e_p` when it leaves the active nodes, its row's
    /// change when it reverses.
    ///
    /// False if the dense factors, bordered up to the set first where a
    /// new column `A^-1 e_p` needs them, meet a small pivot.
    pub(super) fn set_role(&mut self, ops: &Operators, p: usize, role: Role) -> bool {
        let (n, k) = (self.n, self.nodes.len());
        let old = self.roles[p];
        // A^-1 e_p: from the structured vectors if they give it, else from
        // the dense factors (bordered up to the set first).
        let leaves = old == Role::Active && role != Role::Active;
        let by_structure = leaves && self.structured_column(ops, p);
        if leaves && !by_structure && !self.catch_up(ops) {
            return false;
        }
        self.roles[p] = role;
        if role == Role::Active {
            // Out of the correction: the last slot moves into its slot.
            let t = self.special.iter().position(|&q| q == p).expect("slot");
            let last = self.special.len() - 1;
            if t != last {
                self.special_cols.copy_within(last * n..last * n + k, t * n);
                self.deltas.copy_within(last * n..last * n + k, t * n);
            }
            self.special.swap_remove(t);
            return true;
        }
        let t = if old == Role::Active {
            // A^-1 e_p: row perm_inv[p] of the factors' right-hand side.
            let t = self.special.len();
            self.special.push(p);
            if by_structure {
                let st = self.structured.as_ref().expect("structured");
                self.special_cols[t * n..t * n + k].copy_from_slice(&st.column()[..k]);
                return self.set_delta(ops, p, t, role);
            }
            let from = self.perm_inv[p];
            let ld = self.ld;
            let y = &mut self.special_cols[t * n..t * n + k];
            y.fill(0.0);
            y[from] = 1.0;
            let f = Factors {
                lu: &self.lu,
                ld,
                k,
            };
            triangular(f, Pass::Lower { y, from });
            triangular(f, Pass::Inverse { y });
            t
        } else {
            self.special.iter().position(|&q| q == p).expect("slot")
        };
        self.set_delta(ops, p, t, role)
    }

    /// The change of the row of position `p` (slot `t`) if it reverses.
    pub(super) fn set_delta(&mut self, ops: &Operators, p: usize, t: usize, role: Role) -> bool {
        let (n, k) = (self.n, self.nodes.len());
        if role == Role::Reversed {
            // Row p gains 2 f s H[node, S] (H[node, c] = -H[c, node]).
            let f2 = -2.0 * self.friction * self.signs[p];
            let hcol = ops.hilbert_col(self.nodes[p]);
            let delta = &mut self.deltas[t * n..t * n + k];
            for (d, &node) in delta.iter_mut().zip(&self.nodes) {
                *d = f2 * hcol[node];
            }
        }
        true
    }
}
