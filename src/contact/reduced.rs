//! Solves of the reduced system `(-|D| - f diag(s) H)_SS dg_S = rhs` for a
//! slip set `S` that changes a little from one solve to the next.
//!
//! A fresh LU for every slip set would cost `O(k^3)` each time the zone
//! grows, shrinks or moves by a node, which is nearly every increment. So
//! one LU is kept for a *base* set `B`, and a nearby set is solved through
//! the Woodbury identity on the augmented system over `B u A` (`A` the nodes
//! added to the base):
//!
//! * an added node `a` brings a new column (`M_Ba`) and a new row;
//! * a removed node `r` keeps its column but its row becomes `x_r = 0`;
//! * a node whose slip direction flipped gets its row's `H` term reversed.
//!
//! With `K0 = diag(LU_B, I_A)` and those changes written as `W Z^T`, the
//! solution is `x = y - Y C^-1 Z^T y` with `y = K0^-1 b`, `Y = K0^-1 W` and
//! the small capacitance matrix `C = I + Z^T Y`. The columns of `Y` that need
//! a base solve are cached per node until the base changes, so a slip set
//! that drifts by one node costs one `O(k^2)` solve instead of an LU. When
//! the change grows past a fraction of the base, the base is refactorised.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::linalg::lu::partial_pivoting::solve::solve_in_place_scratch;
use faer::{MatMut, Par};

use super::operators::Operators;

const NONE: usize = usize::MAX;

/// Largest capacitance system before the base is refactorised.
const MAX_RANK: usize = 24;

/// A dense LU with partial pivoting on a reusable column-major buffer.
pub(super) struct DenseLu {
    pub(super) lu: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    dim: usize,
    stack: MemBuffer,
    /// Permuted right-hand side of [`DenseLu::solve`].
    tmp: Vec<f64>,
}

impl DenseLu {
    pub(super) fn new(capacity: usize) -> Self {
        let req =
            lu_in_place_scratch::<usize, f64>(capacity, capacity, Par::Seq, Default::default()).or(
                solve_in_place_scratch::<usize, f64>(capacity, capacity, Par::Seq),
            );
        Self {
            lu: vec![0.0; capacity * capacity],
            perm: vec![0; capacity],
            perm_inv: vec![0; capacity],
            dim: 0,
            stack: MemBuffer::new(req),
            tmp: vec![0.0; capacity],
        }
    }

    /// Room for matrices up to `capacity x capacity`, allocated at the
    /// first need: a contact that never needs this solver (most runs of
    /// a sweep, each on its own clone) does not pay for its `N x N`
    /// buffers.
    pub(super) fn reserve(&mut self, capacity: usize) {
        if self.tmp.len() < capacity {
            *self = DenseLu::new(capacity);
        }
    }

    /// Factorise the `dim x dim` matrix already written into `self.lu`.
    pub(super) fn factorise(&mut self, dim: usize) {
        self.dim = dim;
        let m = MatMut::from_column_major_slice_mut(&mut self.lu[..dim * dim], dim, dim);
        lu_in_place(
            m,
            &mut self.perm[..dim],
            &mut self.perm_inv[..dim],
            Par::Seq,
            MemStack::new(&mut self.stack),
            Default::default(),
        );
    }

    /// `U^-1` of the last factorisation (of a `k x k` matrix) written on
    /// and above the diagonal of `dst` (`k x k`, column stride `ld`); the
    /// entries below it are left as they are.
    pub(super) fn invert_upper(&self, k: usize, dst: &mut [f64], ld: usize) {
        let src = faer::MatRef::from_column_major_slice(&self.lu[..k * k], k, k);
        let dst = MatMut::from_column_major_slice_with_stride_mut(dst, k, k, ld);
        faer::linalg::triangular_inverse::invert_upper_triangular(dst, src, Par::Seq);
    }

    /// The row permutation of the last factorisation of a `k x k` matrix:
    /// row `i` of the factors is row `perm[i]` of the matrix.
    pub(super) fn perm(&self, k: usize) -> &[usize] {
        &self.perm[..k]
    }

    /// Overwrite `rhs` (length `dim`) with the solution: `P A = L U`, so
    /// `x = U^-1 L^-1 P b`, by column-oriented substitution (one vector:
    /// the blocked solve of the library costs more than the flops here).
    pub(super) fn solve(&mut self, rhs: &mut [f64]) {
        let k = self.dim;
        let lu = &self.lu[..k * k];
        let x = &mut self.tmp[..k];
        for (xi, &pi) in x.iter_mut().zip(&self.perm[..k]) {
            *xi = rhs[pi];
        }
        // L (unit diagonal, strictly below it).
        for j in 0..k {
            let (head, tail) = x.split_at_mut(j + 1);
            let xj = head[j];
            if xj != 0.0 {
                for (t, &l) in tail.iter_mut().zip(&lu[j * k + j + 1..(j + 1) * k]) {
                    *t -= l * xj;
                }
            }
        }
        // U (the diagonal and above).
        for j in (0..k).rev() {
            let (head, tail) = x.split_at_mut(j);
            let xj = tail[0] / lu[j * k + j];
            tail[0] = xj;
            if xj != 0.0 {
                for (t, &u) in head.iter_mut().zip(&lu[j * k..j * k + j]) {
                    *t -= u * xj;
                }
            }
        }
        rhs[..k].copy_from_slice(x);
    }

    /// The library's solve, for checking [`DenseLu::solve`].
    #[cfg(test)]
    fn solve_reference(&mut self, rhs: &mut [f64]) {
        let k = self.dim;
        let lu = faer::MatRef::from_column_major_slice(&self.lu[..k * k], k, k);
        let perm = faer::perm::PermRef::new_checked(&self.perm[..k], &self.perm_inv[..k], k);
        let rhs = MatMut::from_column_major_slice_mut(&mut rhs[..k], k, 1);
        faer::linalg::lu::partial_pivoting::solve::solve_in_place(
            lu,
            lu,
            perm,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.stack),
        );
    }
}

/// What kind of change a low-rank term stands for.
#[derive(Clone, Copy)]
enum Item {
    /// The column of added node `a` (position `k + i` in the augmented set).
    Column { node: usize, i: usize },
    /// The row of added node `a` with slip sign `s`.
    AddedRow { node: usize, i: usize, sign: f64 },
    /// Base node at position `pos` no longer slips: its row pins `x = 0`.
    Removed { node: usize, pos: usize },
    /// Base node at position `pos` slips the other way.
    Flipped { node: usize, pos: usize },
}

/// Factorisations and reuse of the reduced system.
pub struct ReducedSolver {
    nodes: usize,
    /// Base slip set: nodes and signs (+1 or -1), in node order.
    base: Vec<(usize, f64)>,
    /// Position of each node in the base, or `NONE`.
    base_pos: Vec<usize>,
    base_lu: DenseLu,
    /// Cached `M_BB^-1 M_Ba` for added nodes, per node (empty: not cached).
    column_solves: Vec<Vec<f64>>,
    /// Cached `M_BB^-1 e_pos` for removed or flipped nodes, per node.
    unit_solves: Vec<Vec<f64>>,
    cap_lu: DenseLu,
    // Scratch.
    added: Vec<(usize, f64)>,
    added_pos: Vec<usize>,
    items: Vec<Item>,
    y: Vec<f64>,
    t: Vec<f64>,
    /// Dense rows of `Z^T` for row items, each over the augmented set.
    z_rows: Vec<Vec<f64>>,
    /// Whether the base matrix is known for the signs in `base`.
    valid: bool,
    /// The set of the last solve, whose plan and capacitance LU are still
    /// in place: a further solve with the same set skips both.
    planned: Vec<(usize, f64)>,
    planned_ok: bool,
    pub factorisations: usize,
}

impl Clone for ReducedSolver {
    fn clone(&self) -> Self {
        // Caches only: a clone starts empty.
        ReducedSolver::new(self.nodes)
    }
}

impl ReducedSolver {
    pub fn new(nodes: usize) -> Self {
        Self {
            nodes,
            base: Vec::with_capacity(nodes),
            base_pos: vec![NONE; nodes],
            base_lu: DenseLu::new(0),
            column_solves: vec![Vec::new(); nodes],
            unit_solves: vec![Vec::new(); nodes],
            cap_lu: DenseLu::new(0),
            added: Vec::with_capacity(nodes),
            added_pos: vec![NONE; nodes],
            items: Vec::with_capacity(MAX_RANK),
            y: vec![0.0; 2 * nodes],
            t: vec![0.0; MAX_RANK],
            z_rows: Vec::new(),
            valid: false,
            planned: Vec::with_capacity(nodes),
            planned_ok: false,
            factorisations: 0,
        }
    }

    #[inline]
    fn entry(ops: &Operators, friction: f64, row: usize, sign: f64, col: usize) -> f64 {
        -ops.abs_derivative(row, col) - friction * sign * ops.hilbert(row, col)
    }

    /// Make `set` the base and factorise it.
    fn refactorise(&mut self, ops: &Operators, friction: f64, set: &[(usize, f64)]) {
        for &(node, _) in &self.base {
            self.base_pos[node] = NONE;
        }
        for v in self
            .column_solves
            .iter_mut()
            .chain(self.unit_solves.iter_mut())
        {
            v.clear();
        }
        self.base.clear();
        self.base.extend_from_slice(set);
        let k = set.len();
        for (pos, &(node, _)) in set.iter().enumerate() {
            self.base_pos[node] = pos;
        }
        self.base_lu.reserve(self.nodes);
        for (b, &(col, _)) in set.iter().enumerate() {
            let hcol = ops.hilbert_col(col);
            let dcol = ops.abs_derivative_col(col);
            let out = &mut self.base_lu.lu[b * k..(b + 1) * k];
            for (o, &(row, sign)) in out.iter_mut().zip(set) {
                *o = -dcol[row] - friction * sign * hcol[row];
            }
        }
        self.base_lu.factorise(k);
        self.valid = true;
        self.factorisations += 1;
    }

    /// Solve `M_SS x = rhs` for the slip set `set` (nodes in increasing
    /// order with signs); `rhs` and the result `x` follow `set`'s order.
    pub fn solve(
        &mut self,
        ops: &Operators,
        friction: f64,
        set: &[(usize, f64)],
        rhs: &[f64],
        x: &mut [f64],
    ) {
        let same = self.valid && self.planned_ok && self.planned.as_slice() == set;
        if !same {
            self.planned_ok = false;
            if !self.valid || !self.plan(set) {
                self.refactorise(ops, friction, set);
                self.items.clear();
                self.added.clear();
            }
            if !self.items.is_empty() {
                self.fill_cache(ops, friction);
                self.build_capacitance(ops, friction);
            }
            self.planned.clear();
            self.planned.extend_from_slice(set);
            self.planned_ok = true;
        }
        let k = self.base.len();
        let u = k + self.added.len();

        // y = K0^-1 b over the augmented set: removed rows carry 0.
        self.y[..u].fill(0.0);
        for (&(node, _), &b) in set.iter().zip(rhs) {
            let pos = self.base_pos[node];
            if pos != NONE {
                self.y[pos] = b;
            } else {
                self.y[k + self.added_pos[node]] = b;
            }
        }
        self.base_lu.solve(&mut self.y[..k]);

        if !self.items.is_empty() {
            let m = self.items.len();
            // t = Z^T y, then C t' = t, then x = y - Y t'.
            for i in 0..m {
                self.t[i] = self.z_dot(i, &self.y[..u]);
            }
            self.cap_lu.solve(&mut self.t[..m]);
            for i in 0..m {
                let ti = self.t[i];
                if ti == 0.0 {
                    continue;
                }
                match self.items[i] {
                    Item::Column { node, .. } => {
                        for (yv, c) in self.y[..k].iter_mut().zip(&self.column_solves[node]) {
                            *yv -= c * ti;
                        }
                    }
                    Item::AddedRow { i: a, .. } => self.y[k + a] -= ti,
                    Item::Removed { node, .. } | Item::Flipped { node, .. } => {
                        for (yv, c) in self.y[..k].iter_mut().zip(&self.unit_solves[node]) {
                            *yv -= c * ti;
                        }
                    }
                }
            }
        }
        for (xi, &(node, _)) in x.iter_mut().zip(set) {
            let pos = self.base_pos[node];
            *xi = if pos != NONE {
                self.y[pos]
            } else {
                self.y[k + self.added_pos[node]]
            };
        }
    }

    /// Describe `set` as changes to the base; false if a refactorisation
    /// is the better deal.
    fn plan(&mut self, set: &[(usize, f64)]) -> bool {
        for &(node, _) in &self.added {
            self.added_pos[node] = NONE;
        }
        self.added.clear();
        self.items.clear();
        let mut in_set = 0;
        for &(node, sign) in set {
            let pos = self.base_pos[node];
            if pos == NONE {
                self.added_pos[node] = self.added.len();
                self.added.push((node, sign));
            } else {
                in_set += 1;
                if self.base[pos].1 != sign {
                    self.items.push(Item::Flipped { node, pos });
                }
            }
        }
        let removed = self.base.len() - in_set;
        let rank = 2 * self.added.len() + removed + self.items.len();
        if rank > MAX_RANK || 4 * rank > set.len().max(8) {
            for &(node, _) in &self.added {
                self.added_pos[node] = NONE;
            }
            return false;
        }
        if removed > 0 {
            // Removed: base nodes absent from the set (set is in node order).
            let mut it = set.iter().peekable();
            for (pos, &(node, _)) in self.base.iter().enumerate() {
                while it.peek().is_some_and(|&&(n, _)| n < node) {
                    it.next();
                }
                if it.peek().is_none_or(|&&(n, _)| n != node) {
                    self.items.push(Item::Removed { node, pos });
                }
            }
        }
        for (i, &(node, sign)) in self.added.iter().enumerate() {
            self.items.push(Item::Column { node, i });
            self.items.push(Item::AddedRow { node, i, sign });
        }
        true
    }

    /// Base solves for the items that need them and are not cached yet.
    fn fill_cache(&mut self, ops: &Operators, friction: f64) {
        let k = self.base.len();
        for idx in 0..self.items.len() {
            match self.items[idx] {
                Item::Column { node, .. } if self.column_solves[node].is_empty() => {
                    let mut v: Vec<f64> = self
                        .base
                        .iter()
                        .map(|&(row, sign)| Self::entry(ops, friction, row, sign, node))
                        .collect();
                    self.base_lu.solve(&mut v);
                    self.column_solves[node] = v;
                }
                Item::Removed { node, pos } | Item::Flipped { node, pos }
                    if self.unit_solves[node].is_empty() =>
                {
                    let mut v = vec![0.0; k];
                    v[pos] = 1.0;
                    self.base_lu.solve(&mut v);
                    self.unit_solves[node] = v;
                }
                _ => {}
            }
        }
    }

    /// `Z^T` row of item `i` dotted with a vector over the augmented set.
    fn z_dot(&self, i: usize, v: &[f64]) -> f64 {
        let k = self.base.len();
        match self.items[i] {
            Item::Column { i: a, .. } => v[k + a],
            _ => self.z_rows[i].iter().zip(v).map(|(z, v)| z * v).sum(),
        }
    }

    /// Dense `Z^T` rows for the row items and the capacitance LU.
    fn build_capacitance(&mut self, ops: &Operators, friction: f64) {
        let k = self.base.len();
        let u = k + self.added.len();
        let m = self.items.len();
        if self.z_rows.len() < m {
            self.z_rows.resize(m, Vec::new());
        }
        for i in 0..m {
            let row = &mut self.z_rows[i];
            row.clear();
            match self.items[i] {
                Item::Column { .. } => {}
                Item::AddedRow { node, i: a, sign } => {
                    row.extend(
                        self.base
                            .iter()
                            .map(|&(col, _)| Self::entry(ops, friction, node, sign, col)),
                    );
                    row.extend(
                        self.added
                            .iter()
                            .map(|&(col, _)| Self::entry(ops, friction, node, sign, col)),
                    );
                    row[k + a] -= 1.0;
                }
                Item::Removed { node, pos } => {
                    let sign = self.base[pos].1;
                    row.extend(
                        self.base
                            .iter()
                            .map(|&(col, _)| -Self::entry(ops, friction, node, sign, col)),
                    );
                    row.extend(
                        self.added
                            .iter()
                            .map(|&(col, _)| -Self::entry(ops, friction, node, sign, col)),
                    );
                    row[pos] += 1.0;
                }
                Item::Flipped { node, pos } => {
                    let scale = 2.0 * friction * self.base[pos].1;
                    row.extend(
                        self.base
                            .iter()
                            .map(|&(col, _)| scale * ops.hilbert(node, col)),
                    );
                    row.extend(
                        self.added
                            .iter()
                            .map(|&(col, _)| scale * ops.hilbert(node, col)),
                    );
                }
            }
            debug_assert!(row.is_empty() || row.len() == u);
        }
        // C = I + Z^T Y, column j from item j's Y column.
        self.cap_lu.reserve(MAX_RANK);
        let c = &mut self.cap_lu.lu;
        for j in 0..m {
            for i in 0..m {
                let zy = match (self.items[i], self.items[j]) {
                    (Item::Column { i: a, .. }, Item::AddedRow { i: b, .. }) => {
                        if a == b {
                            1.0
                        } else {
                            0.0
                        }
                    }
                    (Item::Column { .. }, _) => 0.0,
                    (_, Item::AddedRow { i: b, .. }) => self.z_rows[i][k + b],
                    (_, Item::Column { node, .. }) => {
                        dot(&self.z_rows[i][..k], &self.column_solves[node])
                    }
                    (_, Item::Removed { node, .. } | Item::Flipped { node, .. }) => {
                        dot(&self.z_rows[i][..k], &self.unit_solves[node])
                    }
                };
                c[j * m + i] = zy + if i == j { 1.0 } else { 0.0 };
            }
        }
        self.cap_lu.factorise(m);
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense reference: assemble and solve M_SS directly.
    fn reference(ops: &Operators, f: f64, set: &[(usize, f64)], rhs: &[f64]) -> Vec<f64> {
        let mut s = ReducedSolver::new(ops.nodes());
        s.refactorise(ops, f, set);
        let mut x = rhs.to_vec();
        s.base_lu.solve(&mut x);
        x
    }

    fn check(ops: &Operators, solver: &mut ReducedSolver, set: &[(usize, f64)]) {
        let rhs: Vec<f64> = (0..set.len())
            .map(|i| ((i * 37 % 11) as f64 - 5.0) / 7.0)
            .collect();
        let mut x = vec![0.0; set.len()];
        solver.solve(ops, 0.1, set, &rhs, &mut x);
        let want = reference(ops, 0.1, set, &rhs);
        for (a, b) in x.iter().zip(&want) {
            assert!((a - b).abs() < 1e-10 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }

    #[test]
    fn substitution_matches_the_library_solve() {
        let k = 37;
        let mut lu = DenseLu::new(k);
        for c in 0..k {
            for r in 0..k {
                lu.lu[c * k + r] =
                    (((r * 31 + c * 17) % 23) as f64 - 11.0) / 7.0 + if r == c { 0.5 } else { 0.0 };
            }
        }
        lu.factorise(k);
        let b: Vec<f64> = (0..k).map(|i| ((i * 13 % 7) as f64) - 3.0).collect();
        let (mut x, mut y) = (b.clone(), b);
        lu.solve(&mut x);
        lu.solve_reference(&mut y);
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }

    #[test]
    fn low_rank_updates_match_a_fresh_factorisation() {
        let ops = Operators::new(64);
        let mut solver = ReducedSolver::new(64);
        let zone = |from: usize, to: usize, sign: f64| -> Vec<(usize, f64)> {
            (from..to).map(|j| (j, sign)).collect()
        };
        check(&ops, &mut solver, &zone(10, 40, 1.0));
        let f0 = solver.factorisations;
        // Grow, shrink, move, flip a node, and combinations.
        check(&ops, &mut solver, &zone(10, 41, 1.0));
        check(&ops, &mut solver, &zone(12, 40, 1.0));
        check(&ops, &mut solver, &zone(11, 42, 1.0));
        let mut flipped = zone(10, 40, 1.0);
        flipped[5].1 = -1.0;
        flipped[6].1 = -1.0;
        check(&ops, &mut solver, &flipped);
        let mut split = zone(10, 40, 1.0);
        split.retain(|&(j, _)| !(20..23).contains(&j));
        split.push((50, -1.0));
        check(&ops, &mut solver, &split);
        assert_eq!(solver.factorisations, f0, "small changes reuse the base");
        // A large change refactorises and is still right.
        check(&ops, &mut solver, &zone(30, 60, -1.0));
        assert!(solver.factorisations > f0);
    }
}
