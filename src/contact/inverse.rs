//! The inverse of the reduced matrix `M_SS = (-|D| - f diag(s) H)_SS`, kept
//! up to date as the slip set changes one node at a time.
//!
//! The exact increment ([`super::increment`]) changes the slip set at its
//! events, nearly always by one node: a node enters slip, a slipping node
//! sticks (advancing stick), or a node reverses its direction. Each such
//! change of `M_SS` is a bordering or a rank-one change, so its inverse
//! follows in `O(k^2)` (`k` the size of the set) instead of the `O(k^3)` of
//! a new factorisation:
//!
//! * **a node `a` enters** with sign `s_a`: the bordered inverse, with
//!   `v = M^-1 M_Sa`, `w = M_aS M^-1` and the Schur complement
//!   `sigma = M_aa - M_aS v`;
//! * **a node leaves** the set (its slip is pinned): for `B = M^-1`, the
//!   inverse of `M` without row and column `r` is `B - B_:r B_r: / B_rr`;
//! * **a node flips** its direction: its row gains `2 f s H_r,S`, a
//!   Sherman–Morrison update.
//!
//! Each of these changes is a rank-one term `u z^T` added to the inverse.
//! The terms are not added at once: the inverse is kept as
//! `B = B0 + U Z^T` with the last few terms pending in `U` and `Z`, so that
//! a node's leaving costs `O(k t)` (its row and column of `B`, `t` terms
//! pending) instead of a pass over `B`, an entry costs one pass (its two
//! products `B c`, `r^T B` read each column of `B0` once, in
//! [`fused_products`]) instead of three, and the
//! pending terms are added to `B0` together, as one matrix product, when
//! there are `k / 4` of them (at most [`MAX_TERMS`]).
//!
//! The inverse is rebuilt from a pivoted LU (faer) when the set changes by
//! many nodes at once, when an update meets a small pivot, and after a
//! number of updates proportional to `k`, so the round-off that updates
//! accumulate stays bounded and the amortised cost stays `O(k^2)`.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};

use super::kernels::four;
use super::operators::Operators;
use super::reduced::DenseLu;
use super::solver::SlipDirection;

const NONE: usize = usize::MAX;

/// The `k x k` block of the inverse (column stride `ld`) and the two
/// vectors of an entry's products ([`fused_products`]).
struct Fused<'a> {
    b: &'a [f64],
    ld: usize,
    k: usize,
    c: &'a [f64],
    r: &'a [f64],
    v: &'a mut [f64],
    w: &'a mut [f64],
}

/// `v = B c` and `w = B^T r` in one pass over `B` (`k x k`, column stride
/// `ld`), four columns at a time: each column is read once for its part of
/// `B c` and its dot product with `r`. With two separate products (faer's
/// matrix-vector kernels) an entry read `B` twice, and at `N = 1024` the
/// two passes were half of a run.
///
/// Every entry is a chain of fused multiply-adds in a fixed order and each
/// dot product is kept in four lanes, in vectors of four where the
/// processor has them and else in groups of four ([`f64::mul_add`] rounds
/// once everywhere), so the numbers do not depend on the instruction set.
fn fused_products(
    b: &[f64],
    ld: usize,
    k: usize,
    c: &[f64],
    r: &[f64],
    v: &mut [f64],
    w: &mut [f64],
) {
    pulp::Arch::new().dispatch(Fused {
        b,
        ld,
        k,
        c: &c[..k],
        r: &r[..k],
        v: &mut v[..k],
        w: &mut w[..k],
    });
}

impl pulp::WithSimd for Fused<'_> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        if S::F64_LANES == 4 {
            fused_wide(simd, self);
        } else {
            fused_narrow(self);
        }
    }
}

/// The columns `j..j + 4` of `B` and their weights `c_j` in [`Fused`]; past
/// the last column the last one stands in with weight 0 (its dot product
/// is dropped).
#[inline(always)]
fn group<'a>(f: &Fused<'a>, j: usize) -> ([&'a [f64]; 4], [f64; 4]) {
    let width = (f.k - j).min(4);
    let (b, ld, k) = (f.b, f.ld, f.k);
    let col = |t: usize| &b[(j + t.min(width - 1)) * ld..][..k];
    let weight = |t: usize| if t < width { f.c[j + t] } else { 0.0 };
    (
        [col(0), col(1), col(2), col(3)],
        [weight(0), weight(1), weight(2), weight(3)],
    )
}

/// One entry of `B c` for a group of columns: `acc + sum_t x_t c_t`.
#[inline(always)]
fn column_sum(x: [f64; 4], c: [f64; 4], acc: f64) -> f64 {
    let sum = x[0].mul_add(c[0], acc);
    let sum = x[1].mul_add(c[1], sum);
    let sum = x[2].mul_add(c[2], sum);
    x[3].mul_add(c[3], sum)
}

/// Rows `from..k` of a group (those past the last whole group of four),
/// into `v`, and the group's dot products: lanes `d` plus those rows.
#[inline(always)]
fn group_end(
    f: &mut Fused<'_>,
    j: usize,
    from: usize,
    cols: [&[f64]; 4],
    c: [f64; 4],
    d: [[f64; 4]; 4],
) {
    let mut tail = [0.0f64; 4];
    let rows = f.v[from..].iter_mut().zip(&f.r[from..]);
    for (i, (v, &r)) in (from..).zip(rows) {
        let x = cols.map(|col| col[i]);
        *v = column_sum(x, c, *v);
        for (sum, xt) in tail.iter_mut().zip(x) {
            *sum = xt.mul_add(r, *sum);
        }
    }
    let width = (f.k - j).min(4);
    for ((w, lanes), sum) in f.w[j..j + width].iter_mut().zip(d).zip(tail) {
        *w = ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + sum;
    }
}

/// [`fused_products`] in groups of four rows, for processors without
/// vectors of four lanes.
#[inline(always)]
fn fused_narrow(mut f: Fused<'_>) {
    f.v.fill(0.0);
    let whole = f.k / 4;
    for j in (0..f.k).step_by(4) {
        let (cols, c) = group(&f, j);
        let mut d = [[0.0f64; 4]; 4];
        let rows = f.v.as_chunks_mut::<4>().0.iter_mut().zip(four(f.r));
        for (i, (acc, r)) in rows.enumerate() {
            for l in 0..4 {
                let x = cols.map(|col| col[4 * i + l]);
                acc[l] = column_sum(x, c, acc[l]);
                for t in 0..4 {
                    d[t][l] = x[t].mul_add(r[l], d[t][l]);
                }
            }
        }
        group_end(&mut f, j, 4 * whole, cols, c, d);
    }
}

/// [`fused_products`] in vectors of four lanes (`S::F64_LANES == 4`): the
/// same operations in the same order at each entry.
#[inline(always)]
fn fused_wide<S: pulp::Simd>(simd: S, mut f: Fused<'_>) {
    f.v.fill(0.0);
    let whole = f.k / 4;
    for j in (0..f.k).step_by(4) {
        let (cols, c) = group(&f, j);
        let x = cols.map(|col| S::as_simd_f64s(col).0);
        let s = c.map(|ct| simd.splat_f64s(ct));
        let vr = S::as_simd_f64s(f.r).0;
        let va = S::as_mut_simd_f64s(f.v).0;
        let mut d = [simd.splat_f64s(0.0); 4];
        // Zipped, not indexed: no bounds check in the loop.
        let rows = va
            .iter_mut()
            .zip(vr)
            .zip(x[0])
            .zip(x[1])
            .zip(x[2])
            .zip(x[3]);
        for (((((a, &ri), &y0), &y1), &y2), &y3) in rows {
            let sum = simd.mul_add_e_f64s(y0, s[0], *a);
            let sum = simd.mul_add_e_f64s(y1, s[1], sum);
            let sum = simd.mul_add_e_f64s(y2, s[2], sum);
            *a = simd.mul_add_e_f64s(y3, s[3], sum);
            d[0] = simd.mul_add_e_f64s(y0, ri, d[0]);
            d[1] = simd.mul_add_e_f64s(y1, ri, d[1]);
            d[2] = simd.mul_add_e_f64s(y2, ri, d[2]);
            d[3] = simd.mul_add_e_f64s(y3, ri, d[3]);
        }
        let lanes = d.map(|dt| {
            let mut l = [0.0f64; 4];
            l.copy_from_slice(pulp::bytemuck::cast_slice(std::slice::from_ref(&dt)));
            l
        });
        group_end(&mut f, j, 4 * whole, cols, c, lanes);
    }
}

/// A pivot (Schur complement or diagonal entry of the inverse) below this
/// fraction of its scale makes an update unreliable: rebuild instead.
const PIVOT_TOL: f64 = 1e-8;

/// Room to grow left in each column of the inverse for a set of `k`
/// nodes (see [`SetInverse::relayout`]).
fn slack(k: usize) -> usize {
    (k / 8).max(8)
}

/// The most rank-one terms kept pending (see the module's documentation).
const MAX_TERMS: usize = 32;

/// Terms pending at which they are added to `B0`, for a set of `k` nodes:
/// a quarter of `k`, so that the pending terms cost at most about as much
/// as a pass over `B0` per change.
fn term_limit(k: usize) -> usize {
    (k / 4).clamp(1, MAX_TERMS)
}

/// `M_SS^-1` for the current slip set, column-major.
pub(crate) struct SetInverse {
    n: usize,
    /// The column stride of the inverse: `k` and a little room to grow,
    /// so that the inverse lies in one nearly contiguous block (about half
    /// again as fast to read at `k = 300` as columns `N` apart, which
    /// defeat the prefetcher). The pending terms have stride `N`.
    ld: usize,
    friction: f64,
    /// `B0`: the inverse is `B0 + U Z^T`; entry `(i, j)` at
    /// `inv[j * ld + i]`, positions `0..k`; room for `N x N`.
    inv: Vec<f64>,
    /// The pending terms: `u_t` at `terms_u[t * N..]` and `z_t` at
    /// `terms_z[t * N..]`, by position, `t < terms`.
    terms_u: Vec<f64>,
    terms_z: Vec<f64>,
    terms: usize,
    /// Scratch for the `terms` coefficients of a low-rank product.
    coef: Vec<f64>,
    /// Node and slip sign at each position.
    nodes: Vec<usize>,
    signs: Vec<f64>,
    /// Position of each node, or `NONE`.
    pos: Vec<usize>,
    valid: bool,
    /// The elastic pressure and shear per unit `x` and per unit `y`
    /// (`[p_x, q_x, p_y, q_y]`), once given: the right-hand sides of the
    /// two unit load directions, `b_a = -(q_a - s f p_a)` on the set.
    loads: Option<Box<[Vec<f64>; 4]>>,
    /// `M_SS^-1 b_a` for the two unit directions, by position, kept with
    /// the inverse through every update (`O(k)` each) while `loads` is set.
    sol: [Vec<f64>; 2],
    /// Updates since the last rebuild.
    updates: usize,
    /// Rebuilds from a factorisation (for the increment's statistics).
    pub(crate) rebuilds: usize,
    // Scratch.
    col: Vec<f64>,
    row: Vec<f64>,
    v: Vec<f64>,
    w: Vec<f64>,
    /// Nodes that stick or reverse in an update.
    changed: Vec<usize>,
    lu: DenseLu,
}

/// `a . b` in four lanes (a single running sum would not vectorise).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ac, bc) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ac
        .remainder()
        .iter()
        .zip(bc.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ac.zip(bc) {
        for i in 0..4 {
            acc[i] += x[i] * y[i];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// `a` as a column (`k x 1`).
fn column(a: &[f64]) -> MatRef<'_, f64> {
    MatRef::from_column_major_slice(a, a.len(), 1)
}

/// The leading `k x k` block of `inv` (column-major, stride `n`).
fn block(inv: &[f64], k: usize, n: usize) -> MatRef<'_, f64> {
    MatRef::from_column_major_slice_with_stride(&inv[..(k - 1) * n + k], k, k, n)
}

/// The same block, to write.
fn block_mut(inv: &mut [f64], k: usize, n: usize) -> MatMut<'_, f64> {
    MatMut::from_column_major_slice_with_stride_mut(&mut inv[..(k - 1) * n + k], k, k, n)
}

impl Clone for SetInverse {
    fn clone(&self) -> Self {
        // A cache: a clone starts empty and rebuilds on first use.
        let mut clone = SetInverse::new(self.n);
        clone.loads.clone_from(&self.loads);
        clone
    }
}

impl SetInverse {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            n,
            ld: 0,
            friction: f64::NAN,
            // The N x N buffers wait for the first rebuild: a cloned or
            // never-slipping contact does not pay for them.
            inv: Vec::new(),
            terms_u: Vec::new(),
            terms_z: Vec::new(),
            terms: 0,
            coef: vec![0.0; MAX_TERMS],
            nodes: Vec::with_capacity(n),
            signs: Vec::with_capacity(n),
            pos: vec![NONE; n],
            valid: false,
            loads: None,
            sol: [vec![0.0; n], vec![0.0; n]],
            updates: 0,
            rebuilds: 0,
            col: vec![0.0; n],
            row: vec![0.0; n],
            v: vec![0.0; n],
            w: vec![0.0; n],
            changed: Vec::with_capacity(n),
            lu: DenseLu::new(0),
        }
    }

    /// Size `k` of the set.
    pub(crate) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Keep the solutions for the two unit load directions from now on:
    /// `p_x`, `q_x`, `p_y`, `q_y` are the elastic tractions per unit `x` and
    /// `y` (model.md section 2.1). The next update rebuilds.
    pub(crate) fn set_loads(&mut self, loads: [&[f64]; 4]) {
        self.loads = Some(Box::new(loads.map(<[f64]>::to_vec)));
        self.valid = false;
    }

    /// The right-hand sides `b_x`, `b_y` at `node` with slip sign `sign`.
    #[inline]
    fn rhs(&self, node: usize, sign: f64) -> [f64; 2] {
        match &self.loads {
            Some(l) => {
                let f = self.friction;
                [
                    -(l[1][node] - sign * f * l[0][node]),
                    -(l[3][node] - sign * f * l[2][node]),
                ]
            }
            None => [0.0; 2],
        }
    }

    /// The slip rates of the set for the load direction `(ux, uy)`,
    /// `M_SS^-1 (ux b_x + uy b_y)`, from the kept solutions into `out` by
    /// node (other nodes untouched); false if not finite. Needs
    /// [`Self::set_loads`].
    pub(crate) fn rates(&self, ux: f64, uy: f64, out: &mut [f64]) -> bool {
        debug_assert!(self.loads.is_some(), "rates without loads");
        let k = self.len();
        let mut finite = true;
        let [sx, sy] = &self.sol;
        for ((&node, &x), &y) in self.nodes.iter().zip(&sx[..k]).zip(&sy[..k]) {
            let r = ux * x + uy * y;
            finite &= r.is_finite();
            out[node] = r;
        }
        finite
    }

    /// `M[row, col]` for a row with slip sign `sign`.
    #[inline]
    fn entry(ops: &Operators, friction: f64, row: usize, sign: f64, col: usize) -> f64 {
        -ops.abs_derivative(row, col) - friction * sign * ops.hilbert(row, col)
    }

    /// Make the inverse that of the slip set `target`, whose slipping nodes
    /// and signs in node order are `set`; false if `M_SS` is singular to
    /// working precision (the caller then has no responses).
    ///
    /// The changes are found from `set` and the inverse's own nodes, in
    /// `O(k)`, not by passes over all `N` nodes: at `N = 1024` three such
    /// passes were 4 % of a run's instructions.
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
        let k = self.len();
        // Nodes that enter, and nodes of the inverse that stick or reverse.
        let mut changed = std::mem::take(&mut self.changed);
        changed.clear();
        let mut entries = 0;
        for &(j, sign) in set {
            match self.pos[j] {
                NONE => entries += 1,
                p if self.signs[p] != sign => changed.push(j),
                _ => {}
            }
        }
        changed.extend(self.nodes.iter().filter(|&&j| !target[j].is_slipping()));
        let changes = entries + changed.len();
        if changes == 0 {
            self.changed = changed;
            return true;
        }
        // Past half the set (or many updates since the last factorisation)
        // a rebuild costs about as much and is cleaner. (With a quarter the
        // Fig. 3 map took 1 % more instructions; with the whole set, 0.2 %.)
        if 2 * changes > k.max(8) || self.updates + changes > k.max(16) {
            self.changed = changed;
            return self.rebuild(ops, friction, target);
        }
        // Leaves and flips first (the set shrinks), in node order, then
        // entries in node order.
        changed.sort_unstable();
        let mut ok = true;
        for &j in &changed {
            let p = self.pos[j];
            ok = if target[j].is_slipping() {
                self.flip(ops, p)
            } else {
                self.remove(p)
            };
            if !ok {
                break;
            }
        }
        self.changed = changed;
        if !ok {
            return self.rebuild(ops, friction, target);
        }
        for &(j, sign) in set {
            if self.pos[j] == NONE && !self.add(ops, j, sign) {
                return self.rebuild(ops, friction, target);
            }
        }
        self.updates += changes;
        true
    }

    /// A fresh inverse of `M_SS` from a pivoted LU.
    fn rebuild(&mut self, ops: &Operators, friction: f64, target: &[SlipDirection]) -> bool {
        for &node in &self.nodes {
            self.pos[node] = NONE;
        }
        self.nodes.clear();
        self.signs.clear();
        for (j, d) in target.iter().enumerate() {
            if d.is_slipping() {
                self.pos[j] = self.nodes.len();
                self.nodes.push(j);
                self.signs.push(d.sign());
            }
        }
        self.friction = friction;
        self.updates = 0;
        self.terms = 0;
        self.rebuilds += 1;
        self.valid = false;
        let k = self.len();
        if k == 0 {
            self.valid = true;
            return true;
        }
        if self.inv.len() < self.n * self.n {
            self.inv = vec![0.0; self.n * self.n];
            self.terms_u = vec![0.0; self.n * MAX_TERMS];
            self.terms_z = vec![0.0; self.n * MAX_TERMS];
            self.lu = DenseLu::new(self.n);
        }
        self.ld = (k + slack(k)).min(self.n);
        let n = self.ld;
        // Assemble M_SS column-major (k x k) and factorise it.
        for (b, &col) in self.nodes.iter().enumerate() {
            let hcol = ops.hilbert_col(col);
            let dcol = ops.abs_derivative_col(col);
            let out = &mut self.lu.lu[b * k..(b + 1) * k];
            for ((o, &row), &sign) in out.iter_mut().zip(&self.nodes).zip(&self.signs) {
                *o = -dcol[row] - friction * sign * hcol[row];
            }
        }
        self.lu.factorise(k);
        self.lu.inverse_into(&mut self.inv, n);
        for c in 0..k {
            if self.inv[c * n..c * n + k].iter().any(|v| !v.is_finite()) {
                return false;
            }
        }
        if self.loads.is_some() {
            // The two solutions afresh: x_a = B b_a.
            for i in 0..k {
                [self.col[i], self.row[i]] = self.rhs(self.nodes[i], self.signs[i]);
            }
            let b = block(&self.inv, k, n);
            for (sol, rhs) in self.sol.iter_mut().zip([&self.col, &self.row]) {
                let out = MatMut::from_column_major_slice_mut(&mut sol[..k], k, 1);
                matmul(out, Accum::Replace, b, column(&rhs[..k]), 1.0, Par::Seq);
            }
        }
        self.valid = true;
        true
    }

    /// Give the inverse the column stride `ld` (at most `N`), moving its
    /// columns: `O(k^2)`, once per `k / 8` entries at most.
    fn relayout(&mut self, ld: usize) {
        let (old, k) = (self.ld, self.len());
        let ld = ld.min(self.n);
        if ld > old {
            for j in (1..k).rev() {
                self.inv.copy_within(j * old..j * old + k, j * ld);
            }
        } else {
            for j in 1..k {
                self.inv.copy_within(j * old..j * old + k, j * ld);
            }
        }
        self.ld = ld;
    }

    /// The pending terms `U` (`which = 0`) or `Z` (`which = 1`) as a
    /// `k x terms` matrix.
    fn pending(&self, which: usize) -> MatRef<'_, f64> {
        let (n, k, t) = (self.n, self.len(), self.terms);
        let buf = if which == 0 {
            &self.terms_u
        } else {
            &self.terms_z
        };
        MatRef::from_column_major_slice_with_stride(&buf[..(t - 1) * n + k], k, t, n)
    }

    /// `out += X a`, `X` the pending `U` or `Z` (`which`), `a` the first
    /// `terms` entries of `coef`.
    fn add_pending(&self, which: usize, out: &mut [f64]) {
        let t = self.terms;
        let out = MatMut::from_column_major_slice_mut(out, self.len(), 1);
        matmul(
            out,
            Accum::Add,
            self.pending(which),
            column(&self.coef[..t]),
            1.0,
            Par::Seq,
        );
    }

    /// `coef = X^T x`, `X` the pending `U` or `Z` (`which`).
    fn pending_dots(&mut self, which: usize, x: &[f64]) {
        let t = self.terms;
        let mut coef = std::mem::take(&mut self.coef);
        let out = MatMut::from_column_major_slice_mut(&mut coef[..t], t, 1);
        matmul(
            out,
            Accum::Replace,
            self.pending(which).transpose(),
            column(x),
            1.0,
            Par::Seq,
        );
        self.coef = coef;
    }

    /// `coef` = row `p` of the pending `U` or `Z` (`which`).
    fn pending_row(&mut self, which: usize, p: usize) {
        let n = self.n;
        let buf = if which == 0 {
            &self.terms_u
        } else {
            &self.terms_z
        };
        for (t, c) in self.coef[..self.terms].iter_mut().enumerate() {
            *c = buf[t * n + p];
        }
    }

    /// Column `p` of `B` into `v` and, if `with_row`, row `p` of `B` into
    /// `w`.
    fn row_and_column(&mut self, p: usize, with_row: bool) {
        let (n, k) = (self.ld, self.len());
        let mut v = std::mem::take(&mut self.v);
        v[..k].copy_from_slice(&self.inv[p * n..p * n + k]);
        if self.terms > 0 {
            // B_:p = B0_:p + U z_p,:
            self.pending_row(1, p);
            self.add_pending(0, &mut v[..k]);
        }
        self.v = v;
        if with_row {
            let mut w = std::mem::take(&mut self.w);
            for (j, wj) in w[..k].iter_mut().enumerate() {
                *wj = self.inv[j * n + p];
            }
            if self.terms > 0 {
                // B_p,: = B0_p,: + Z u_p,:
                self.pending_row(0, p);
                self.add_pending(1, &mut w[..k]);
            }
            self.w = w;
        }
    }

    /// `v = B c` (`c` in `col`, if `with_column`) and `w = B^T r` (`r` in
    /// `row`): one pass over `B0` for both ([`fused_products`]), or for
    /// `w` alone, then the pending terms.
    fn products(&mut self, with_column: bool) {
        let (n, k) = (self.ld, self.len());
        let mut v = std::mem::take(&mut self.v);
        let mut w = std::mem::take(&mut self.w);
        if with_column {
            fused_products(&self.inv, n, k, &self.col, &self.row, &mut v, &mut w);
        } else {
            let w_out = MatMut::from_column_major_slice_mut(&mut w[..k], k, 1);
            matmul(
                w_out,
                Accum::Replace,
                block(&self.inv, k, n).transpose(),
                column(&self.row[..k]),
                1.0,
                Par::Seq,
            );
        }
        if self.terms > 0 {
            // B c = B0 c + U (Z^T c), B^T r = B0^T r + Z (U^T r).
            if with_column {
                let c = std::mem::take(&mut self.col);
                self.pending_dots(1, &c[..k]);
                self.col = c;
                self.add_pending(0, &mut v[..k]);
            }
            let r = std::mem::take(&mut self.row);
            self.pending_dots(0, &r[..k]);
            self.row = r;
            self.add_pending(1, &mut w[..k]);
        }
        self.v = v;
        self.w = w;
    }

    /// Add the pending terms to `B0`.
    fn flush(&mut self) {
        let (n, k) = (self.ld, self.len());
        if self.terms == 0 || k == 0 {
            self.terms = 0;
            return;
        }
        let mut inv = std::mem::take(&mut self.inv);
        matmul(
            block_mut(&mut inv, k, n),
            Accum::Add,
            self.pending(0),
            self.pending(1).transpose(),
            1.0,
            Par::Seq,
        );
        self.inv = inv;
        self.terms = 0;
    }

    /// `B += alpha v w^T` on the leading `k x k` block (`v`, `w` the
    /// scratch vectors), as a pending term.
    fn rank_one(&mut self, alpha: f64) {
        let (n, k) = (self.n, self.len());
        if k == 0 {
            return;
        }
        let t = self.terms;
        for (u, &vi) in self.terms_u[t * n..t * n + k].iter_mut().zip(&self.v[..k]) {
            *u = alpha * vi;
        }
        self.terms_z[t * n..t * n + k].copy_from_slice(&self.w[..k]);
        self.terms += 1;
        if self.terms >= term_limit(k) {
            self.flush();
        }
    }

    /// Node `a` enters with sign `sign`: the bordered inverse.
    fn add(&mut self, ops: &Operators, a: usize, sign: f64) -> bool {
        let (k, f) = (self.len(), self.friction);
        // Column M_Sa and row M_aS (H is odd and |D| even in theta, so the
        // row is read from column a).
        let hcol = ops.hilbert_col(a);
        let dcol = ops.abs_derivative_col(a);
        for i in 0..k {
            let node = self.nodes[i];
            self.col[i] = -dcol[node] - f * self.signs[i] * hcol[node];
            self.row[i] = -dcol[node] + f * sign * hcol[node];
        }
        let d0 = Self::entry(ops, f, a, sign, a);
        // v = B c, w^T = r^T B: the O(k^2) cost of an event at large N.
        if k > 0 {
            self.products(true);
        }
        let rv = dot(&self.row[..k], &self.v[..k]);
        let sigma = d0 - rv;
        let scale = d0.abs().max(rv.abs());
        if !sigma.is_finite() || sigma.abs() <= PIVOT_TOL * scale {
            return false;
        }
        if self.loads.is_some() {
            // The bordered system's solution: the new entry
            // xi = (beta - r^T x) / sigma, and x - xi v on the old set.
            let betas = self.rhs(a, sign);
            for (sol, beta) in self.sol.iter_mut().zip(betas) {
                let xi = (beta - dot(&self.row[..k], &sol[..k])) / sigma;
                for (x, &vi) in sol[..k].iter_mut().zip(&self.v[..k]) {
                    *x -= xi * vi;
                }
                sol[k] = xi;
            }
        }
        let inv_sigma = 1.0 / sigma;
        // B += v w^T / sigma; the new row is -w^T / sigma, the new column
        // -v / sigma, both in B0 (the pending terms are 0 there).
        for wj in self.w[..k].iter_mut() {
            *wj *= inv_sigma;
        }
        self.rank_one(1.0);
        let nt = self.n;
        for t in 0..self.terms {
            self.terms_u[t * nt + k] = 0.0;
            self.terms_z[t * nt + k] = 0.0;
        }
        if k == self.ld {
            self.relayout(k + slack(k));
        }
        let n = self.ld;
        let (v, w) = (&self.v[..k], &self.w[..k]);
        for (j, &wj) in w.iter().enumerate() {
            self.inv[j * n + k] = -wj;
        }
        for (i, &vi) in v.iter().enumerate() {
            self.inv[k * n + i] = -vi * inv_sigma;
        }
        self.inv[k * n + k] = inv_sigma;
        self.pos[a] = k;
        self.nodes.push(a);
        self.signs.push(sign);
        true
    }

    /// The node at position `p` leaves the set.
    fn remove(&mut self, p: usize) -> bool {
        let (n, k) = (self.ld, self.len());
        // Column r (v) and row r (w) of B, then B -= v w^T / B_rr.
        self.row_and_column(p, true);
        let brr = self.v[p];
        let scale = self.v[..k].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !brr.is_finite() || brr.abs() <= PIVOT_TOL * scale {
            return false;
        }
        for wj in &mut self.w[..k] {
            *wj /= brr;
        }
        if self.loads.is_some() {
            // Without node r the solution is x - B_:r x_r / B_rr (whose
            // entry r is 0).
            for sol in &mut self.sol {
                let c = sol[p] / brr;
                for (x, &vi) in sol[..k].iter_mut().zip(&self.v[..k]) {
                    *x -= c * vi;
                }
                sol[p] = sol[k - 1];
            }
        }
        self.rank_one(-1.0);
        // Move the last position into p (row and column r of B are now 0
        // and are dropped).
        let removed = self.nodes[p];
        self.pos[removed] = NONE;
        let last = k - 1;
        if p != last {
            for i in 0..k {
                self.inv[p * n + i] = self.inv[last * n + i];
            }
            for j in 0..k {
                self.inv[j * n + p] = self.inv[j * n + last];
            }
            self.inv[p * n + p] = self.inv[last * n + last];
            let nt = self.n;
            for t in 0..self.terms {
                self.terms_u[t * nt + p] = self.terms_u[t * nt + last];
                self.terms_z[t * nt + p] = self.terms_z[t * nt + last];
            }
            let moved = self.nodes[last];
            self.pos[moved] = p;
            self.nodes[p] = moved;
            self.signs[p] = self.signs[last];
        }
        self.nodes.pop();
        self.signs.pop();
        true
    }

    /// The node at position `p` reverses its direction.
    fn flip(&mut self, ops: &Operators, p: usize) -> bool {
        let (k, f) = (self.len(), self.friction);
        let node = self.nodes[p];
        let sign = self.signs[p];
        // Row p gains delta = 2 f s H[node, S]; H[node, c] = -H[c, node].
        let hcol = ops.hilbert_col(node);
        for i in 0..k {
            self.row[i] = -2.0 * f * sign * hcol[self.nodes[i]];
        }
        // w^T = delta^T B, u = B e_p.
        self.products(false);
        let denom = 1.0 + self.w[p];
        if !denom.is_finite() || denom.abs() <= PIVOT_TOL * (1.0 + self.w[p].abs()) {
            return false;
        }
        self.row_and_column(p, false);
        for vi in &mut self.v[..k] {
            *vi /= denom;
        }
        if self.loads.is_some() {
            // Row p of M gains delta and b_p changes by d: the solution
            // gains (d - delta^T x) B e_p / (1 + w_p) = (d - delta^T x) v.
            let (old, new) = (self.rhs(node, sign), self.rhs(node, -sign));
            for ((sol, b0), b1) in self.sol.iter_mut().zip(old).zip(new) {
                let c = (b1 - b0) - dot(&self.row[..k], &sol[..k]);
                for (x, &vi) in sol[..k].iter_mut().zip(&self.v[..k]) {
                    *x += c * vi;
                }
            }
        }
        self.rank_one(-1.0);
        self.signs[p] = -sign;
        true
    }

    /// `x = M_SS^-1 b` with `b` given per node by `rhs(node, sign)`; the
    /// result goes to `out` by node (other nodes untouched).
    #[cfg(test)]
    pub(crate) fn solve(&mut self, rhs: impl Fn(usize, f64) -> f64, out: &mut [f64]) -> bool {
        self.flush();
        let (n, k) = (self.ld, self.len());
        for (j, bj) in self.w[..k].iter_mut().enumerate() {
            *bj = rhs(self.nodes[j], self.signs[j]);
        }
        let x = &mut self.v[..k];
        if k > 0 {
            let x_out = MatMut::from_column_major_slice_mut(x, k, 1);
            let b = column(&self.w[..k]);
            matmul(
                x_out,
                Accum::Replace,
                block(&self.inv, k, n),
                b,
                1.0,
                Par::Seq,
            );
        }
        let x = &self.v[..k];
        let mut finite = true;
        for (&node, &xi) in self.nodes.iter().zip(x.iter()) {
            finite &= xi.is_finite();
            out[node] = xi;
        }
        finite
    }

    /// The set as slip directions by node.
    #[cfg(test)]
    fn directions(&self) -> Vec<SlipDirection> {
        let mut d = vec![SlipDirection::Stick; self.n];
        for (&node, &sign) in self.nodes.iter().zip(&self.signs) {
            d[node] = SlipDirection::from_sign(sign);
        }
        d
    }

    /// The set as `(node, sign)` in position order.
    #[cfg(test)]
    fn set(&self) -> Vec<(usize, f64)> {
        self.nodes
            .iter()
            .copied()
            .zip(self.signs.iter().copied())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`SetInverse::update_to`] with the set read off `d`.
    fn update(inv: &mut SetInverse, ops: &Operators, f: f64, d: &[SlipDirection]) -> bool {
        let set: Vec<(usize, f64)> = (0..d.len())
            .filter(|&j| d[j].is_slipping())
            .map(|j| (j, d[j].sign()))
            .collect();
        inv.update_to(ops, f, d, &set)
    }

    fn dirs(n: usize, zones: &[(usize, usize, f64)]) -> Vec<SlipDirection> {
        let mut d = vec![SlipDirection::Stick; n];
        for &(a, b, s) in zones {
            for x in &mut d[a..b] {
                *x = SlipDirection::from_sign(s);
            }
        }
        d
    }

    /// `M_SS x` for the set of `inv`, against the right-hand side.
    fn residual(ops: &Operators, f: f64, inv: &mut SetInverse, n: usize) -> f64 {
        let rhs = |node: usize, s: f64| ((node * 37 % 11) as f64 - 5.0) / 7.0 + s;
        let mut x = vec![0.0; n];
        assert!(inv.solve(rhs, &mut x));
        let set = inv.set();
        let mut worst = 0.0f64;
        for &(row, sign) in &set {
            let mx: f64 = set
                .iter()
                .map(|&(col, _)| SetInverse::entry(ops, f, row, sign, col) * x[col])
                .sum();
            worst = worst.max((mx - rhs(row, sign)).abs());
        }
        worst
    }

    /// The slip rates kept through entries, leaves and flips against a
    /// solve with the updated inverse, for three load directions.
    fn check_kept_rates(inv: &SetInverse, loads: &[Vec<f64>], f: f64, n: usize) {
        for (ux, uy) in [(1.0, 0.0), (0.0, 1.0), (0.6, -0.8)] {
            let mut kept = vec![0.0; n];
            assert!(inv.rates(ux, uy, &mut kept));
            let rhs = |j: usize, s: f64| {
                let p = ux * loads[0][j] + uy * loads[2][j];
                let q = ux * loads[1][j] + uy * loads[3][j];
                -(q - s * f * p)
            };
            let mut fresh = vec![0.0; n];
            let mut again = SetInverse::new(n);
            again.rebuild(&Operators::new(n), f, &inv.directions());
            assert!(again.solve(rhs, &mut fresh));
            let scale = fresh.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            for j in 0..n {
                let err = (kept[j] - fresh[j]).abs();
                assert!(err < 1e-10 * scale, "node {j}: {err:e}");
            }
        }
    }

    /// `v = B c`, `w = B^T r` of [`fused_products`] against faer's two
    /// products, for sizes around the groups of four, a stride wider than
    /// the block, and the narrow kernel against the dispatched one bit for
    /// bit.
    #[test]
    fn fused_products_match_two_products_on_every_instruction_set() {
        let value = |i: usize, j: usize| ((i * 31 + j * 17) % 23) as f64 / 7.0 - 1.5;
        for k in [1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 63, 130] {
            let ld = k + 5;
            let b: Vec<f64> = (0..ld * k).map(|e| value(e % ld, e / ld)).collect();
            let c: Vec<f64> = (0..k).map(|i| (i as f64 * 0.7).sin()).collect();
            let r: Vec<f64> = (0..k).map(|i| (i as f64 * 0.3).cos() - 0.2).collect();
            let (mut v, mut w) = (vec![f64::NAN; k], vec![f64::NAN; k]);
            fused_products(&b, ld, k, &c, &r, &mut v, &mut w);
            let block =
                MatRef::from_column_major_slice_with_stride(&b[..(k - 1) * ld + k], k, k, ld);
            let (mut v0, mut w0) = (vec![0.0; k], vec![0.0; k]);
            let out = MatMut::from_column_major_slice_mut(&mut v0, k, 1);
            matmul(out, Accum::Replace, block, column(&c), 1.0, Par::Seq);
            let out = MatMut::from_column_major_slice_mut(&mut w0, k, 1);
            matmul(
                out,
                Accum::Replace,
                block.transpose(),
                column(&r),
                1.0,
                Par::Seq,
            );
            for i in 0..k {
                assert!(
                    (v[i] - v0[i]).abs() < 1e-12 * (1.0 + v0[i].abs()),
                    "k {k}: v[{i}]"
                );
                assert!(
                    (w[i] - w0[i]).abs() < 1e-12 * (1.0 + w0[i].abs()),
                    "k {k}: w[{i}]"
                );
            }
            let (mut v1, mut w1) = (vec![f64::NAN; k], vec![f64::NAN; k]);
            fused_narrow(Fused {
                b: &b,
                ld,
                k,
                c: &c,
                r: &r,
                v: &mut v1,
                w: &mut w1,
            });
            let bits = |x: &[f64]| x.iter().map(|e| e.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&v1), bits(&v), "k {k}: B c");
            assert_eq!(bits(&w1), bits(&w), "k {k}: B^T r");
        }
    }

    #[test]
    fn updates_match_the_system() {
        let n = 64;
        let f = 0.1;
        let ops = Operators::new(n);
        let mut inv = SetInverse::new(n);
        // Elastic tractions per unit load: any smooth shapes will do.
        let shape = |j: usize, a: f64| (j as f64 * a).sin() + 0.3 * (j as f64 * 0.7).cos();
        let loads: Vec<Vec<f64>> = (1..=4)
            .map(|a| (0..n).map(|j| shape(j, f64::from(a) * 0.37)).collect())
            .collect();
        inv.set_loads([&loads[0], &loads[1], &loads[2], &loads[3]]);
        let steps: Vec<Vec<(usize, usize, f64)>> = vec![
            vec![(10, 40, 1.0)],
            vec![(10, 41, 1.0)],
            vec![(12, 41, 1.0)],
            vec![(12, 30, 1.0), (30, 42, -1.0)],
            vec![(12, 20, 1.0), (23, 42, -1.0), (50, 51, 1.0)],
            vec![(11, 20, 1.0), (23, 43, -1.0), (50, 52, 1.0)],
            vec![(11, 20, 1.0), (23, 43, -1.0), (50, 52, -1.0)],
            vec![(30, 60, -1.0)],
            vec![],
            vec![(0, 3, 1.0), (60, 64, 1.0)],
        ];
        for zones in &steps {
            assert!(update(&mut inv, &ops, f, &dirs(n, zones)));
            let got: Vec<(usize, f64)> = {
                let mut s = inv.set();
                s.sort_by_key(|&(j, _)| j);
                s
            };
            let want: Vec<(usize, f64)> = dirs(n, zones)
                .iter()
                .enumerate()
                .filter(|(_, d)| d.is_slipping())
                .map(|(j, d)| (j, d.sign()))
                .collect();
            assert_eq!(got, want);
            let r = residual(&ops, f, &mut inv, n);
            assert!(r < 1e-11, "residual {r} for {zones:?}");
            check_kept_rates(&inv, &loads, f, n);
        }
        assert!(inv.rebuilds < steps.len(), "small changes are updates");
    }

    #[test]
    fn long_runs_of_updates_with_pending_terms_match_the_system() {
        // A slip zone that grows one node at a time, as an advancing slip
        // zone does, with a node leaving now and then and the end node
        // reversing: every change an update, with terms pending, added to
        // the inverse and the inverse moved to a wider stride on the way.
        let n = 256;
        let f = 0.3;
        let ops = Operators::new(n);
        let mut inv = SetInverse::new(n);
        let shape = |j: usize, a: f64| (j as f64 * a).cos() - 0.2 * (j as f64 * 0.3).sin();
        let loads: Vec<Vec<f64>> = (1..=4)
            .map(|a| (0..n).map(|j| shape(j, f64::from(a) * 0.21)).collect())
            .collect();
        inv.set_loads([&loads[0], &loads[1], &loads[2], &loads[3]]);
        let mut d = dirs(n, &[(100, 140, 1.0)]);
        assert!(update(&mut inv, &ops, f, &d));
        let mut pending = 0;
        let mut wider = 0;
        let (forward, backward) = (
            SlipDirection::from_sign(1.0),
            SlipDirection::from_sign(-1.0),
        );
        for step in 0..90 {
            let end = 140 + step;
            d[end] = forward;
            if step % 7 == 3 {
                d[100 + step / 7] = SlipDirection::Stick;
            }
            let flipped = step % 11 == 5;
            if flipped {
                // The newest node reverses: a flip on the next update.
                assert!(update(&mut inv, &ops, f, &d));
                d[end] = backward;
            }
            let stride = inv.ld;
            assert!(update(&mut inv, &ops, f, &d));
            pending = pending.max(inv.terms);
            wider += usize::from(inv.ld > stride);
            if step % 10 == 9 || flipped {
                assert_eq!(inv.directions(), d);
                check_kept_rates(&inv, &loads, f, n);
                let r = residual(&ops, f, &mut inv, n);
                assert!(r < 1e-10, "residual {r} at step {step}");
            }
        }
        assert_eq!(inv.rebuilds, 1, "every change an update");
        assert!(pending > 1 && wider > 0, "pending {pending}, wider {wider}");
    }
}
