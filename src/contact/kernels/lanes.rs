//! Dense multiply-adds in a fixed order for the kept inverse of the slip
//! set ([`crate::contact::inverse`]): dot products, updates and the
//! triangular passes over its factors, in the widest lanes the processor
//! has and with the same numbers on every instruction set.

/// Multiply-adds on slices in a fixed order: vectors of four lanes where
/// the processor has them ([`Wide`]), else groups of four ([`Narrow`]),
/// with [`f64::mul_add`] (one rounding) everywhere, so the numbers do not
/// depend on the instruction set.
///
/// The triangular passes go four columns at a time ([`Lanes::axpy4`],
/// [`Lanes::dot4`]): each entry of the vector they update is loaded and
/// stored once per four columns, not once per column, and the four dot
/// products are four independent chains of multiply-adds, so a pass runs
/// at the speed the factors stream from memory.
pub(in crate::contact) trait Lanes: Copy {
    /// `y -= a x`.
    fn axpy(self, y: &mut [f64], x: &[f64], a: f64);
    /// `y -= a_0 x_0 + a_1 x_1 + a_2 x_2 + a_3 x_3`, in that order at each
    /// entry, from the first entry to the last or, if `down`, from the
    /// last to the first (the same numbers: a back substitution then has
    /// its next unknowns first).
    fn axpy4(self, y: &mut [f64], x: [&[f64]; 4], a: [f64; 4], down: bool);
    /// `a_t . b` for four columns `a_t`, each in four lanes added as
    /// `(l0 + l1) + (l2 + l3)`, then the entries past the last group of
    /// four.
    fn dot4(self, a: [&[f64]; 4], b: &[f64]) -> [f64; 4];
    /// [`Lanes::dot4`] of the columns `a` with `b` and, in the same pass
    /// over them, [`Lanes::axpy4`] of them into `y` (upward), each with the
    /// numbers the two would give apart: the columns are read once for
    /// both.
    fn dot4_axpy4(self, a: [&[f64]; 4], b: &[f64], y: &mut [f64], c: [f64; 4]) -> [f64; 4];
}

#[derive(Clone, Copy)]
pub(in crate::contact) struct Wide<S>(S);

#[derive(Clone, Copy)]
pub(in crate::contact) struct Narrow;

/// One entry of [`Lanes::axpy4`].
#[inline(always)]
pub(in crate::contact) fn axpy4_entry(y: f64, x: [f64; 4], a: [f64; 4]) -> f64 {
    let y = x[0].mul_add(-a[0], y);
    let y = x[1].mul_add(-a[1], y);
    let y = x[2].mul_add(-a[2], y);
    x[3].mul_add(-a[3], y)
}

/// One vector of [`Lanes::axpy4`]: `y + x_0 na_0 + ... + x_3 na_3` in that
/// order (`na` the negated weights).
#[inline(always)]
pub(in crate::contact) fn fma4<S: pulp::Simd>(
    simd: S,
    y: S::f64s,
    x: [S::f64s; 4],
    na: [S::f64s; 4],
) -> S::f64s {
    let acc = simd.mul_add_e_f64s(x[0], na[0], y);
    let acc = simd.mul_add_e_f64s(x[1], na[1], acc);
    let acc = simd.mul_add_e_f64s(x[2], na[2], acc);
    simd.mul_add_e_f64s(x[3], na[3], acc)
}

/// The lanes of a [`Lanes::dot4`] product and its tail, added.
#[inline(always)]
pub(in crate::contact) fn lane_sum(l: [f64; 4], tail: f64) -> f64 {
    ((l[0] + l[1]) + (l[2] + l[3])) + tail
}

/// The four dot products of [`Lanes::dot4`] from their vector lanes `d`
/// and the entries past the last whole vector (`tails` of the columns,
/// `bt` of the other vector).
#[inline(always)]
pub(in crate::contact) fn dot4_sums<V: pulp::bytemuck::Pod>(
    d: [V; 4],
    tails: [&[f64]; 4],
    bt: &[f64],
) -> [f64; 4] {
    let mut out = [0.0; 4];
    for t in 0..4 {
        let mut l = [0.0f64; 4];
        l.copy_from_slice(&pulp::bytemuck::cast_slice::<V, f64>(std::slice::from_ref(&d[t]))[..4]);
        let mut tail = 0.0f64;
        for (&x, &y) in tails[t].iter().zip(bt) {
            tail = x.mul_add(y, tail);
        }
        out[t] = lane_sum(l, tail);
    }
    out
}

impl<S: pulp::Simd> Lanes for Wide<S> {
    #[inline(always)]
    fn axpy(self, y: &mut [f64], x: &[f64], a: f64) {
        let simd = self.0;
        let (xh, xt) = S::as_simd_f64s(&x[..y.len()]);
        let (yh, yt) = S::as_mut_simd_f64s(y);
        let minus_a = simd.splat_f64s(-a);
        for (yv, &xv) in yh.iter_mut().zip(xh) {
            *yv = simd.mul_add_e_f64s(xv, minus_a, *yv);
        }
        for (yv, &xv) in yt.iter_mut().zip(xt) {
            *yv = xv.mul_add(-a, *yv);
        }
    }

    #[inline(always)]
    fn axpy4(self, y: &mut [f64], x: [&[f64]; 4], a: [f64; 4], down: bool) {
        let simd = self.0;
        let m = y.len();
        let x = x.map(|c| S::as_simd_f64s(&c[..m]));
        let (yh, yt) = S::as_mut_simd_f64s(y);
        let na = a.map(|t| simd.splat_f64s(-t));
        // Plain `for` loops over zips, no closures: a closure or an
        // iterator's `fold` is not always inlined, and out of line the
        // intrinsics lose their instruction set.
        let rows = yh
            .iter_mut()
            .zip(x[0].0)
            .zip(x[1].0)
            .zip(x[2].0)
            .zip(x[3].0);
        let (tails, t) = (x.map(|c| c.1), yt.len());
        if down {
            for i in (0..t).rev() {
                yt[i] = axpy4_entry(
                    yt[i],
                    [tails[0][i], tails[1][i], tails[2][i], tails[3][i]],
                    a,
                );
            }
            for ((((yv, &x0), &x1), &x2), &x3) in rows.rev() {
                *yv = fma4(simd, *yv, [x0, x1, x2, x3], na);
            }
        } else {
            for ((((yv, &x0), &x1), &x2), &x3) in rows {
                *yv = fma4(simd, *yv, [x0, x1, x2, x3], na);
            }
            for i in 0..t {
                yt[i] = axpy4_entry(
                    yt[i],
                    [tails[0][i], tails[1][i], tails[2][i], tails[3][i]],
                    a,
                );
            }
        }
    }

    #[inline(always)]
    fn dot4(self, a: [&[f64]; 4], b: &[f64]) -> [f64; 4] {
        let simd = self.0;
        let m = b.len();
        let a = a.map(|c| S::as_simd_f64s(&c[..m]));
        let (bh, bt) = S::as_simd_f64s(b);
        let mut d = [simd.splat_f64s(0.0); 4];
        let rows = bh.iter().zip(a[0].0).zip(a[1].0).zip(a[2].0).zip(a[3].0);
        for ((((&bv, &a0), &a1), &a2), &a3) in rows {
            d[0] = simd.mul_add_e_f64s(a0, bv, d[0]);
            d[1] = simd.mul_add_e_f64s(a1, bv, d[1]);
            d[2] = simd.mul_add_e_f64s(a2, bv, d[2]);
            d[3] = simd.mul_add_e_f64s(a3, bv, d[3]);
        }
        dot4_sums(d, a.map(|c| c.1), bt)
    }

    #[inline(always)]
    fn dot4_axpy4(self, a: [&[f64]; 4], b: &[f64], y: &mut [f64], c: [f64; 4]) -> [f64; 4] {
        let simd = self.0;
        let m = b.len();
        let a = a.map(|col| S::as_simd_f64s(&col[..m]));
        let (bh, bt) = S::as_simd_f64s(b);
        let (yh, yt) = S::as_mut_simd_f64s(&mut y[..m]);
        let nc = c.map(|t| simd.splat_f64s(-t));
        let mut d = [simd.splat_f64s(0.0); 4];
        let rows = yh
            .iter_mut()
            .zip(bh)
            .zip(a[0].0)
            .zip(a[1].0)
            .zip(a[2].0)
            .zip(a[3].0);
        for (((((yv, &bv), &a0), &a1), &a2), &a3) in rows {
            d[0] = simd.mul_add_e_f64s(a0, bv, d[0]);
            d[1] = simd.mul_add_e_f64s(a1, bv, d[1]);
            d[2] = simd.mul_add_e_f64s(a2, bv, d[2]);
            d[3] = simd.mul_add_e_f64s(a3, bv, d[3]);
            *yv = fma4(simd, *yv, [a0, a1, a2, a3], nc);
        }
        for (i, yv) in yt.iter_mut().enumerate() {
            *yv = axpy4_entry(*yv, [a[0].1[i], a[1].1[i], a[2].1[i], a[3].1[i]], c);
        }
        dot4_sums(d, a.map(|c| c.1), bt)
    }
}

impl Lanes for Narrow {
    #[inline(always)]
    fn axpy(self, y: &mut [f64], x: &[f64], a: f64) {
        for (yv, &xv) in y.iter_mut().zip(x) {
            *yv = xv.mul_add(-a, *yv);
        }
    }

    #[inline(always)]
    fn axpy4(self, y: &mut [f64], x: [&[f64]; 4], a: [f64; 4], down: bool) {
        let entry = |(i, yv): (usize, &mut f64)| *yv = axpy4_entry(*yv, x.map(|c| c[i]), a);
        if down {
            y.iter_mut().enumerate().rev().for_each(entry);
        } else {
            y.iter_mut().enumerate().for_each(entry);
        }
    }

    #[inline(always)]
    fn dot4(self, a: [&[f64]; 4], b: &[f64]) -> [f64; 4] {
        let whole = b.len() / 4 * 4;
        std::array::from_fn(|t| {
            let mut l = [0.0f64; 4];
            for (x, y) in a[t][..whole]
                .chunks_exact(4)
                .zip(b[..whole].chunks_exact(4))
            {
                for lane in 0..4 {
                    l[lane] = x[lane].mul_add(y[lane], l[lane]);
                }
            }
            let mut tail = 0.0f64;
            for (&x, &y) in a[t][whole..b.len()].iter().zip(&b[whole..]) {
                tail = x.mul_add(y, tail);
            }
            lane_sum(l, tail)
        })
    }

    #[inline(always)]
    fn dot4_axpy4(self, a: [&[f64]; 4], b: &[f64], y: &mut [f64], c: [f64; 4]) -> [f64; 4] {
        let d = self.dot4(a, b);
        self.axpy4(&mut y[..b.len()], a, c, false);
        d
    }
}

/// A pass over the factors of the base (`k x k`, column stride `ld`):
/// `L` of `P A = L U` strictly below the diagonal (unit diagonal) and
/// `W = U^-1` on and above it, dispatched once to the widest [`Lanes`].
pub(in crate::contact) enum Pass<'a> {
    /// `y = L^-1 y`, `y` zero above row `from`.
    Lower { y: &'a mut [f64], from: usize },
    /// `y = W y = U^-1 y`.
    Inverse { y: &'a mut [f64] },
    /// [`border_pass`].
    Border {
        u: &'a mut [f64],
        r: &'a [f64],
        l: &'a mut [f64],
        v: &'a mut [f64],
    },
}

/// The factors of the base: `L` and `W = U^-1` packed in one `k x k`
/// array of column stride `ld` (see [`Pass`]).
#[derive(Clone, Copy)]
pub(in crate::contact) struct Factors<'a> {
    pub(in crate::contact) lu: &'a [f64],
    pub(in crate::contact) ld: usize,
    pub(in crate::contact) k: usize,
}

pub(in crate::contact) struct Triangular<'a> {
    pub(in crate::contact) f: Factors<'a>,
    pub(in crate::contact) pass: Pass<'a>,
}

impl pulp::WithSimd for Triangular<'_> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) {
        if S::F64_LANES == 4 {
            self.run(Wide(simd));
        } else {
            self.run(Narrow);
        }
    }
}

/// Columns `jb..jb + w` of the factors (`w <= 4`, `k` rows, stride `ld`);
/// past the last the last stands in (with weight 0 in a product, or its
/// dot product dropped).
#[inline(always)]
pub(in crate::contact) fn columns(
    lu: &[f64],
    ld: usize,
    k: usize,
    jb: usize,
    w: usize,
) -> [&[f64]; 4] {
    // Written out: `std::array::from_fn` here stayed a call per block (a
    // seventieth of a sweep's instructions).
    let col = |t: usize| {
        let c = jb + t.min(w - 1);
        &lu[c * ld..c * ld + k]
    };
    [col(0), col(1), col(2), col(3)]
}

/// The block's own entries, `b[i][t]` at row `jb + i` and column
/// `jb + t`, zero outside its `w x w` square; and the matching entries of a
/// vector. Fixed sizes, so that the small triangles below unroll.
#[inline(always)]
pub(in crate::contact) fn block(cols: [&[f64]; 4], jb: usize, w: usize) -> [[f64; 4]; 4] {
    let mut b = [[0.0; 4]; 4];
    if w == 4 {
        // A whole block (all but the last): one bounds check a column.
        for (t, col) in cols.iter().enumerate() {
            let c: &[f64; 4] = col[jb..jb + 4].try_into().expect("four rows");
            for (row, &v) in b.iter_mut().zip(c) {
                row[t] = v;
            }
        }
        return b;
    }
    for t in 0..w {
        for (i, row) in b.iter_mut().enumerate().take(w) {
            row[t] = cols[t][jb + i];
        }
    }
    b
}

#[inline(always)]
pub(in crate::contact) fn block_of(x: &[f64], jb: usize, w: usize) -> [f64; 4] {
    // Fixed sizes: a copy of a length known only at run time is a call to
    // `memcpy` (LLVM makes one of a plain loop over `w` entries, and merges
    // it with the copy of four), five of them a block, a tenth of a pass
    // at N = 128. The short tail is copied entry by entry under a test.
    if w == 4 {
        return x[jb..jb + 4].try_into().expect("four rows");
    }
    // The first `w` (< 4) entries, each in its own load.
    let mut b = [0.0; 4];
    for (i, bi) in b.iter_mut().enumerate().take(3) {
        if i < w {
            *bi = x[jb + i];
        }
    }
    b
}

/// The first `w` entries of `b` into `x` from row `jb` (the inverse of
/// [`block_of`]).
#[inline(always)]
pub(in crate::contact) fn set_block(x: &mut [f64], jb: usize, w: usize, b: &[f64; 4]) {
    if w == 4 {
        let to: &mut [f64; 4] = (&mut x[jb..jb + 4]).try_into().expect("four rows");
        *to = *b;
        return;
    }
    // The first `w` (< 4) entries, each in its own store.
    for (i, &bi) in b.iter().enumerate().take(3) {
        if i < w {
            x[jb + i] = bi;
        }
    }
}

/// `W x` over the block's own upper triangle: `sum_(t >= i) b[i][t] x[t]`.
#[inline(always)]
pub(in crate::contact) fn block_upper(b: &[[f64; 4]; 4], x: [f64; 4]) -> [f64; 4] {
    let mut y = [0.0; 4];
    for i in 0..4 {
        for t in i..4 {
            y[i] = b[i][t].mul_add(x[t], y[i]);
        }
    }
    y
}

impl Triangular<'_> {
    #[inline(always)]
    pub(in crate::contact) fn run<V: Lanes>(self, lanes: V) {
        let Factors { lu, ld, k } = self.f;
        match self.pass {
            Pass::Lower { y, from } => {
                // Column-oriented: column j of L is contiguous. (Only for
                // a correction column, once per pinned or reversed node.)
                for j in from..k {
                    let (head, tail) = y[..k].split_at_mut(j + 1);
                    let yj = head[j];
                    if yj != 0.0 {
                        lanes.axpy(tail, &lu[j * ld + j + 1..j * ld + k], yj);
                    }
                }
            }
            Pass::Inverse { y } => {
                // In place, four columns at a time from the first: the rows
                // above a block have taken their earlier terms, the block's
                // own rows still hold the input.
                for jb in (0..k).step_by(4) {
                    let w = (k - jb).min(4);
                    let cols = columns(lu, ld, k, jb, w);
                    let x = block_of(y, jb, w);
                    lanes.axpy4(&mut y[..jb], cols.map(|c| &c[..jb]), x.map(|e| -e), false);
                    let own = block_upper(&block(cols, jb, w), x);
                    set_block(y, jb, w, &own);
                }
            }
            Pass::Border { u, r, l, v } => {
                for jb in (0..k).step_by(4) {
                    let w = (k - jb).min(4);
                    let cols = columns(lu, ld, k, jb, w);
                    let b = block(cols, jb, w);
                    // u = L^-1 u: the block's triangle first, so that its
                    // entries are final.
                    let mut ub = block_of(u, jb, w);
                    for t in 1..4 {
                        for i in 0..t {
                            ub[t] = b[t][i].mul_add(-ub[i], ub[t]);
                        }
                    }
                    set_block(u, jb, w, &ub);
                    // Above the block, in one pass over the columns:
                    // l = W^T r (dot products) and v = W u (updates).
                    let s = lanes.dot4_axpy4(
                        cols.map(|c| &c[..jb]),
                        &r[..jb],
                        &mut v[..jb],
                        ub.map(|e| -e),
                    );
                    // The block's own rows.
                    let rb = block_of(r, jb, w);
                    let mut lb = s;
                    for (t, acc) in lb.iter_mut().enumerate() {
                        for i in 0..=t {
                            *acc = b[i][t].mul_add(rb[i], *acc);
                        }
                    }
                    set_block(l, jb, w, &lb);
                    let vb = block_upper(&b, ub);
                    set_block(v, jb, w, &vb);
                    // Below the block, four columns of L at once.
                    lanes.axpy4(&mut u[jb + w..k], cols.map(|c| &c[jb + w..k]), ub, false);
                }
            }
        }
    }
}

/// Run one [`Pass`] over the factors.
pub(in crate::contact) fn triangular(f: Factors<'_>, pass: Pass<'_>) {
    if f.k > 0 {
        pulp::Arch::new().dispatch(Triangular { f, pass });
    }
}

/// The three products of a bordering in one pass over the factors, column
/// by column: `u = L^-1 u` (the column of `L` below the diagonal), then
/// `l = W^T r = U^-T r` and `v = W u = U^-1 L^-1 u` (the column of `W` on
/// and above it). Each column is read once for all three, which at
/// `N = 1024` is what a bordering costs: the factors do not fit in the
/// cache, so the passes stream them from memory.
pub(in crate::contact) fn border_pass(
    f: Factors<'_>,
    u: &mut [f64],
    r: &[f64],
    l: &mut [f64],
    v: &mut [f64],
) {
    triangular(f, Pass::Border { u, r, l, v });
}

/// `a . b` in four lanes (a single running sum would not vectorise).
#[inline]
pub(in crate::contact) fn dot(a: &[f64], b: &[f64]) -> f64 {
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

/// The `O(k)` products of a bordering's follow (the structured
/// borderings', [`structured`], and those of the kept solutions) in the
/// widest lanes ([`Lanes`]: fused multiply-adds in a fixed order, the same
/// numbers on every instruction set), four vectors a pass where they share
/// the other operand. With the plain loops of [`dot`] (two lanes, a
/// multiply and an add) the dot products and updates of the structured
/// borderings were a sixth of the `N = 1024` run's instructions.
pub(in crate::contact) enum Kernel<'a> {
    /// `[a_0 . b, ..., a_3 . b]`.
    Dots { a: [&'a [f64]; 4], b: &'a [f64] },
    /// `y -= a_0 x_0 + ... + a_3 x_3`.
    Axpy4 {
        y: &'a mut [f64],
        x: [&'a [f64]; 4],
        a: [f64; 4],
    },
    /// `y -= a x`.
    Axpy {
        y: &'a mut [f64],
        x: &'a [f64],
        a: f64,
    },
}

impl pulp::WithSimd for Kernel<'_> {
    type Output = [f64; 4];
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> [f64; 4] {
        if S::F64_LANES == 4 {
            self.run(Wide(simd))
        } else {
            self.run(Narrow)
        }
    }
}

impl Kernel<'_> {
    #[inline(always)]
    pub(in crate::contact) fn run<V: Lanes>(self, lanes: V) -> [f64; 4] {
        match self {
            Kernel::Dots { a, b } => lanes.dot4(a, b),
            Kernel::Axpy4 { y, x, a } => {
                lanes.axpy4(y, x, a, false);
                [0.0; 4]
            }
            Kernel::Axpy { y, x, a } => {
                lanes.axpy(y, x, a);
                [0.0; 4]
            }
        }
    }
}

/// The dot products of the vectors `a` with `b` into `out`, four a pass
/// over `b`.
pub(in crate::contact) fn dots(arch: pulp::Arch, a: &[&[f64]], b: &[f64], out: &mut [f64]) {
    for (ac, oc) in a.chunks(4).zip(out.chunks_mut(4)) {
        // A short last group repeats its first vector (its products
        // dropped).
        let pick = |t: usize| ac[t.min(ac.len() - 1)];
        let d = arch.dispatch(Kernel::Dots {
            a: [pick(0), pick(1), pick(2), pick(3)],
            b,
        });
        oc.copy_from_slice(&d[..oc.len()]);
    }
}

/// `y -= sum_t c_t x_t` over the vectors `x`, four a pass over `y`.
pub(in crate::contact) fn axpys(arch: pulp::Arch, y: &mut [f64], x: &[&[f64]], c: &[f64]) {
    for (xc, cc) in x.chunks(4).zip(c.chunks(4)) {
        // A short last group repeats its first vector with weight 0.
        let pick = |t: usize| xc[t.min(xc.len() - 1)];
        let weight = |t: usize| cc.get(t).copied().unwrap_or(0.0);
        arch.dispatch(Kernel::Axpy4 {
            y: &mut *y,
            x: [pick(0), pick(1), pick(2), pick(3)],
            a: [weight(0), weight(1), weight(2), weight(3)],
        });
    }
}
