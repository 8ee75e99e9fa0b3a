//! The `O(N)` passes of the exact increment ([`super::increment`]), run
//! with the widest vector instructions the processor has.
//!
//! Every pass over the nodes of an increment (the end margins of a segment,
//! the move along it, the rates of the slip set, the nodes at the friction
//! limit) is a plain loop over a few arrays. The release build targets the
//! baseline `x86_64` (SSE2, two lanes); each pass here is compiled once per
//! instruction set that [`pulp::Arch`] knows (AVX2 with four lanes among
//! them) and the best is chosen at run time, so one binary runs on any
//! `x86_64` and uses AVX2 where it exists. The two passes that dominate an
//! increment ([`end_margins`] and [`slide`]) are written in `pulp`'s
//! vectors, because the compiler does not vectorise them by itself; the
//! rest are loops it vectorises.
//!
//! Results do not depend on the instruction set: every lane does the scalar
//! operations in the scalar order (no fused multiply-add is formed: Rust
//! does not contract `a * b + c`), minima do not depend on order, and the
//! one sum (the dissipation of a move) is kept in four lanes on every
//! processor. The tests below compare the bits on the dispatched, the
//! scalar and emulated two- and four-lane instruction sets.

use super::solver::TRACTION_TOL;

/// Defines `pub(super) fn $name(args) -> out { body }` with `body` compiled
/// once for each instruction set [`pulp::Arch`] knows and the best chosen
/// at run time. The body goes into a [`pulp::WithSimd`] operation whose
/// `with_simd` is generic over the instruction set and always inlined, so
/// every copy is inlined into a function compiled for its instruction set
/// (a closure would be compiled once, for the baseline, and called from
/// each).
macro_rules! wide {
    ($(#[$doc:meta])* fn $name:ident<$lt:lifetime>($($arg:ident: $ty:ty),* $(,)?) -> $out:ty $body:block) => {
        $(#[$doc])*
        pub(super) fn $name<$lt>($($arg: $ty),*) -> $out {
            struct Op<$lt> {
                $($arg: $ty,)*
            }
            impl<$lt> pulp::WithSimd for Op<$lt> {
                type Output = $out;
                #[inline(always)]
                fn with_simd<S: pulp::Simd>(self, _: S) -> $out {
                    let Op { $($arg),* } = self;
                    $body
                }
            }
            pulp::Arch::new().dispatch(Op { $($arg),* })
        }
    };
}

wide! {
    /// The nodes where `f p - |q| + off <= TRACTION_TOL` into `out` (see
    /// [`at_limit_kernel`]).
    fn at_limit<'a>(p: &'a [f64], q: &'a [f64], off: &'a [f64], f: f64, out: &'a mut Vec<usize>) -> () {
        at_limit_kernel(p, q, off, f, out)
    }
}

wide! {
    /// `(max |r|, min s r)` over the nodes (see [`rate_extremes_kernel`]).
    fn rate_extremes<'a>(r: &'a [f64], sgn: &'a [f64]) -> (f64, f64) {
        rate_extremes_kernel(r, sgn)
    }
}

/// The end margins of a segment and the lowest (see
/// [`end_margins_kernel`]), in the widest vectors of this processor.
pub(super) fn end_margins(v: [&[f64]; 7], f: f64, ex: f64, ey: f64, out: &mut [f64]) -> f64 {
    struct Op<'a> {
        v: [&'a [f64]; 7],
        f: f64,
        ex: f64,
        ey: f64,
        out: &'a mut [f64],
    }
    impl pulp::WithSimd for Op<'_> {
        type Output = f64;
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, simd: S) -> f64 {
            end_margins_kernel(simd, self.v, self.f, self.ex, self.ey, self.out)
        }
    }
    pulp::Arch::new().dispatch(Op { v, f, ex, ey, out })
}

wide! {
    /// `out = a x + b y` at every node: the slip rates along a load
    /// direction from those along `u1` and `u2`, and the like.
    fn combine<'a>(out: &'a mut [f64], a: f64, x: &'a [f64], b: f64, y: &'a [f64]) -> () {
        for ((o, &x), &y) in out.iter_mut().zip(x).zip(y) {
            *o = a * x + b * y;
        }
    }
}

wide! {
    /// `out = (a x + b y) + h` at every node: a total response from the
    /// elastic responses `x`, `y` and the residual response `h`.
    fn combine_plus<'a>(out: &'a mut [f64], a: f64, x: &'a [f64], b: f64, y: &'a [f64], h: &'a [f64]) -> () {
        for (((o, &x), &y), &h) in out.iter_mut().zip(x).zip(y).zip(h) {
            *o = (a * x + b * y) + h;
        }
    }
}

wide! {
    /// `slip += t r`, and the positive and negative parts of `t r` into
    /// `forward` and `backward`, at every node: the slip of a sub-segment
    /// from its rates `r` (0 off the slip set, where this adds exactly
    /// nothing). Branch-free and in vectors, it costs less than a loop over
    /// the set's indices unless the set is a small part of the circle.
    fn add_slip<'a>(t: f64, r: &'a [f64], slip: &'a mut [f64], forward: &'a mut [f64], backward: &'a mut [f64]) -> () {
        let nodes = r.iter().zip(slip.iter_mut()).zip(forward.iter_mut()).zip(backward.iter_mut());
        for (((&r, g), fw), bw) in nodes {
            let dg = t * r;
            *g += dg;
            *fw += dg.max(0.0);
            *bw += (-dg).max(0.0);
        }
    }
}

/// The loads' part of the tractions at a load point: `p = 1 - pr sin` and
/// `q = -qt - qr cos` (model.md section 2), per unit of the radial force
/// and torque terms.
#[derive(Clone, Copy)]
pub(super) struct Elastic {
    pub(super) pr: f64,
    pub(super) qr: f64,
    pub(super) qt: f64,
}

wide! {
    /// `p` and `q` at every node from the elastic part and the residual
    /// part `[sin, cos, rp, rq]` (the residual does not change: nothing
    /// slips).
    fn tractions<'a>(el: Elastic, v: [&'a [f64]; 4], p: &'a mut [f64], q: &'a mut [f64]) -> () {
        let [sin, cos, rp, rq] = v;
        for ((p, &sn), &r) in p.iter_mut().zip(sin).zip(rp) {
            *p = 1.0 - el.pr * sn + r;
        }
        for ((q, &c), &r) in q.iter_mut().zip(cos).zip(rq) {
            *q = -el.qt - el.qr * c + r;
        }
    }
}

/// A move by `(tx, ty)` along the responses `u1`, `u2` with slip rates
/// `rg` along the segment, over the segment parameter `t`; see
/// [`slide_kernel`].
pub(super) struct Slide<'a> {
    pub(super) t: f64,
    pub(super) tx: f64,
    pub(super) ty: f64,
    pub(super) elastic: Elastic,
    /// `H g'` and `-|D| g'` along `u1` and `u2`: `[hpx, hpy, hqx, hqy]`.
    pub(super) responses: [&'a [f64]; 4],
    /// `[sin, cos]` at the nodes.
    pub(super) trig: [&'a [f64]; 2],
    /// Slip rates along the segment (0 off the slip set).
    pub(super) rates: &'a [f64],
}

/// Move the residual tractions `rp`, `rq` and the tractions `p`, `q`
/// (`v = [rp, rq, p, q]`) by `s`, and return
/// `sum |dg| (p before + p after)` in the four lanes of node `j mod 4`
/// (nodes past the last whole four in lane 0). Off the slip set the rate
/// is 0, so those nodes add exactly nothing.
pub(super) fn slide(s: &Slide, v: [&mut [f64]; 4]) -> [f64; 4] {
    struct Op<'a, 'b> {
        s: &'b Slide<'a>,
        v: [&'b mut [f64]; 4],
    }
    impl pulp::WithSimd for Op<'_, '_> {
        type Output = [f64; 4];
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, simd: S) -> [f64; 4] {
            // The sum is kept in four lanes whatever the vector width, so
            // that it is the same on every processor: in vectors of four
            // where they exist, else in groups of four.
            if S::F64_LANES == 4 {
                slide_wide(simd, self.s, self.v)
            } else {
                slide_kernel(self.s, self.v)
            }
        }
    }
    pulp::Arch::new().dispatch(Op { s, v })
}

/// [`slide_kernel`] in vectors of four lanes (`S::F64_LANES == 4`): the
/// same operations in the same order at each node.
#[inline(always)]
fn slide_wide<S: pulp::Simd>(simd: S, s: &Slide, [rp, rq, p, q]: [&mut [f64]; 4]) -> [f64; 4] {
    let n = p.len();
    let el = s.elastic;
    let [hpx, hpy, hqx, hqy] = s.responses;
    let [sin, cos] = s.trig;
    let (vhpx, _) = S::as_simd_f64s(&hpx[..n]);
    let (vhpy, _) = S::as_simd_f64s(&hpy[..n]);
    let (vhqx, _) = S::as_simd_f64s(&hqx[..n]);
    let (vhqy, _) = S::as_simd_f64s(&hqy[..n]);
    let (vsin, _) = S::as_simd_f64s(&sin[..n]);
    let (vcos, _) = S::as_simd_f64s(&cos[..n]);
    let (vrg, _) = S::as_simd_f64s(&s.rates[..n]);
    let (vrp, _) = S::as_mut_simd_f64s(&mut rp[..n]);
    let (vrq, _) = S::as_mut_simd_f64s(&mut rq[..n]);
    let (vp, _) = S::as_mut_simd_f64s(&mut p[..n]);
    let (vq, _) = S::as_mut_simd_f64s(&mut q[..n]);
    let splat = |x: f64| simd.splat_f64s(x);
    let (tx, ty, t) = (splat(s.tx), splat(s.ty), splat(s.t));
    let (one, pr, qr, mqt) = (splat(1.0), splat(el.pr), splat(el.qr), splat(-el.qt));
    let mut acc = splat(0.0);
    let whole = vp.len();
    for j in 0..whole {
        let dp = simd.add_f64s(simd.mul_f64s(tx, vhpx[j]), simd.mul_f64s(ty, vhpy[j]));
        let dq = simd.add_f64s(simd.mul_f64s(tx, vhqx[j]), simd.mul_f64s(ty, vhqy[j]));
        let r_p = simd.add_f64s(vrp[j], dp);
        let r_q = simd.add_f64s(vrq[j], dq);
        vrp[j] = r_p;
        vrq[j] = r_q;
        vq[j] = simd.add_f64s(simd.sub_f64s(mqt, simd.mul_f64s(qr, vcos[j])), r_q);
        let p_new = simd.add_f64s(simd.sub_f64s(one, simd.mul_f64s(pr, vsin[j])), r_p);
        let rate = simd.abs_f64s(simd.mul_f64s(t, vrg[j]));
        let dissipated = simd.mul_f64s(rate, simd.add_f64s(vp[j], p_new));
        vp[j] = p_new;
        acc = simd.add_f64s(acc, dissipated);
    }
    let mut lanes = [0.0f64; 4];
    lanes.copy_from_slice(pulp::bytemuck::cast_slice(std::slice::from_ref(&acc)));
    for j in 4 * whole..n {
        let c = cos[j];
        let sn = sin[j];
        rp[j] += s.tx * hpx[j] + s.ty * hpy[j];
        rq[j] += s.tx * hqx[j] + s.ty * hqy[j];
        q[j] = -el.qt - el.qr * c + rq[j];
        let p_new = 1.0 - el.pr * sn + rp[j];
        lanes[0] += (s.t * s.rates[j]).abs() * (p[j] + p_new);
        p[j] = p_new;
    }
    lanes
}

#[inline(always)]
fn slide_kernel(s: &Slide, [rp, rq, p, q]: [&mut [f64]; 4]) -> [f64; 4] {
    let (t, tx, ty, el) = (s.t, s.tx, s.ty, s.elastic);
    let [hpx, hpy, hqx, hqy] = s.responses;
    let [sin, cos] = s.trig;
    let n = p.len();
    let node = |rp: &mut f64, rq: &mut f64, p: &mut f64, q: &mut f64, v: [f64; 7]| {
        let [hpx, hpy, hqx, hqy, c, sn, rg] = v;
        *rp += tx * hpx + ty * hpy;
        *rq += tx * hqx + ty * hqy;
        *q = -el.qt - el.qr * c + *rq;
        let p_new = 1.0 - el.pr * sn + *rp;
        let dissipated = (t * rg).abs() * (*p + p_new);
        *p = p_new;
        dissipated
    };
    let mut acc = [0.0f64; 4];
    let whole = n - n % 4;
    let inputs = four(hpx)
        .iter()
        .zip(four(hpy))
        .zip(four(hqx))
        .zip(four(hqy))
        .zip(four(cos))
        .zip(four(sin))
        .zip(four(s.rates));
    let outputs = rp
        .as_chunks_mut::<4>()
        .0
        .iter_mut()
        .zip(rq.as_chunks_mut::<4>().0)
        .zip(p.as_chunks_mut::<4>().0)
        .zip(q.as_chunks_mut::<4>().0);
    for ((((rp, rq), p), q), ((((((hpx, hpy), hqx), hqy), c), sn), rg)) in outputs.zip(inputs) {
        for i in 0..4 {
            let v = [hpx[i], hpy[i], hqx[i], hqy[i], c[i], sn[i], rg[i]];
            acc[i] += node(&mut rp[i], &mut rq[i], &mut p[i], &mut q[i], v);
        }
    }
    for j in whole..n {
        let v = [hpx[j], hpy[j], hqx[j], hqy[j], cos[j], sin[j], s.rates[j]];
        acc[0] += node(&mut rp[j], &mut rq[j], &mut p[j], &mut q[j], v);
    }
    acc
}

/// The nodes where `f p - |q| + off <= TRACTION_TOL` (stick nodes at the
/// friction limit, `off` being infinite on slip nodes) into `out`, in node
/// order: a branch-free test of four nodes at a time, and a look at each
/// only in the rare groups that hold one.
#[inline(always)]
fn at_limit_kernel(p: &[f64], q: &[f64], off: &[f64], f: f64, out: &mut Vec<usize>) {
    out.clear();
    let slack = |j: usize| f * p[j] - q[j].abs() + off[j];
    let groups = four(p).iter().zip(four(q)).zip(four(off));
    for (g, ((p4, q4), o4)) in groups.enumerate() {
        let mut hit = [false; 4];
        for i in 0..4 {
            hit[i] = f * p4[i] - q4[i].abs() + o4[i] <= TRACTION_TOL;
        }
        if (hit[0] | hit[1]) | (hit[2] | hit[3]) {
            // A push per hit: an `extend` from a filter here was not
            // inlined, and took about 0.8 % of a sweep's time.
            for (i, &h) in hit.iter().enumerate() {
                if h {
                    out.push(4 * g + i);
                }
            }
        }
    }
    let whole = p.len() - p.len() % 4;
    out.extend((whole..p.len()).filter(|&j| slack(j) <= TRACTION_TOL));
}

/// `(max |r|, min s r)` over the nodes, in four lanes.
#[inline(always)]
fn rate_extremes_kernel(r: &[f64], sgn: &[f64]) -> (f64, f64) {
    let mut big = [0.0f64; 4];
    let mut low = [0.0f64; 4];
    let (rc, sc) = (r.chunks_exact(4), sgn.chunks_exact(4));
    let (rt, st) = (rc.remainder(), sc.remainder());
    for (rr, ss) in rc.zip(sc) {
        for i in 0..4 {
            let a = rr[i].abs();
            big[i] = if a > big[i] { a } else { big[i] };
            let v = ss[i] * rr[i];
            low[i] = if v < low[i] { v } else { low[i] };
        }
    }
    let mut scale = big.iter().fold(0.0f64, |m, &v| m.max(v));
    let mut worst = low.iter().fold(0.0f64, |m, &v| m.min(v));
    for (&r, &s) in rt.iter().zip(st) {
        scale = scale.max(r.abs());
        worst = worst.min(s * r);
    }
    (scale, worst)
}

wide! {
    /// The earliest event of each node on a segment into `out`, and the
    /// lowest (see [`event_time`]).
    fn event_times<'a>(v: [&'a [f64]; 7], along: [f64; 3], f: f64, rate_tol: f64, out: &'a mut [f64]) -> f64 {
        let [p, q, px, py, qx, qy, off] = v;
        let n = out.len();
        let nodes = p[..n]
            .iter()
            .zip(&q[..n])
            .zip(&px[..n])
            .zip(&py[..n])
            .zip(&qx[..n])
            .zip(&qy[..n])
            .zip(&off[..n]);
        for (o, ((((((&p, &q), &px), &py), &qx), &qy), &off)) in out.iter_mut().zip(nodes) {
            *o = event_time([p, q, px, py, qx, qy, off], along, f, rate_tol);
        }
        let mut low = [f64::INFINITY; 4];
        for t4 in four(out) {
            for i in 0..4 {
                low[i] = if t4[i] < low[i] { t4[i] } else { low[i] };
            }
        }
        let whole = n - n % 4;
        out[whole..]
            .iter()
            .chain(&low)
            .fold(f64::INFINITY, |m, &t| if t < m { t } else { m })
    }
}

/// The segment parameter at which a node meets its first event on a
/// segment along `(dx, dy)` with `remaining` of it left (`along = [dx, dy,
/// remaining]`), from its `[p, q, dp/dx, dp/dy, dq/dx, dq/dy, off]`
/// (`off` 0 on a stick node, infinite on a slip node): `p` reaching 0, or
/// on a stick node `f p -+ q` reaching 0 with the test and the numbers of
/// the exact test in the increment; infinite if none; `-1` if the node is
/// at the friction limit already with its slack falling (the rate problem
/// must decide it). Branch-free, so the compiler vectorises the pass.
#[inline(always)]
fn event_time(v: [f64; 7], along: [f64; 3], f: f64, rate_tol: f64) -> f64 {
    let [p, q, px, py, qx, qy, off] = v;
    let [dx, dy, remaining] = along;
    let a = dx * px + dy * py;
    let b = dx * qx + dy * qy;
    let p0 = if p < 0.0 { 0.0 } else { p };
    let mut t = if a < 0.0 { p0 / -a } else { f64::INFINITY };
    let mut need = false;
    for (h0, h1) in [(f * p - q + off, f * a - b), (f * p + q + off, f * a + b)] {
        let active = h1 < -rate_tol && h0 + remaining * h1 < -TRACTION_TOL;
        need |= active && h0 <= TRACTION_TOL;
        let te = if active { h0 / -h1 } else { f64::INFINITY };
        t = if te < t { te } else { t };
    }
    if need {
        -1.0
    } else {
        t
    }
}

/// A node whose end margin (below) is under this is tested exactly. The
/// margin is the exact test's quantity summed in another order, so a node a
/// round-off above zero is tested too.
pub(super) const SCREEN: f64 = 1e-9;

/// The margins at the end of the segment into `out`, and the lowest: at
/// each node the lower of its end pressure and its end slack `f p -+ q`
/// (plus `TRACTION_TOL`, and infinite on slip nodes through `off`).
/// Negative: the node may reach an event. Branch-free, in the lanes of
/// `simd`; every lane does the scalar operations in the scalar order, and
/// a minimum does not depend on the order it is taken in, so the result is
/// the same on every instruction set.
#[inline(always)]
fn end_margins_kernel<S: pulp::Simd>(
    simd: S,
    v: [&[f64]; 7],
    f: f64,
    ex: f64,
    ey: f64,
    out: &mut [f64],
) -> f64 {
    let [p, q, tpx, tpy, tqx, tqy, off] = v;
    let n = out.len();
    let (p, q, tpx, tpy, tqx, tqy, off) = (
        &p[..n],
        &q[..n],
        &tpx[..n],
        &tpy[..n],
        &tqx[..n],
        &tqy[..n],
        &off[..n],
    );
    let margin = |p: f64, q: f64, px: f64, py: f64, qx: f64, qy: f64, off: f64| {
        let ep = p + ex * px + ey * py;
        let eq = q + ex * qx + ey * qy;
        // The lower of the forward and backward slack `f p -+ q`: the same
        // bits as `min(f p - q, f p + q)`, in fewer operations.
        let m = f * ep - eq.abs() + off + TRACTION_TOL;
        if ep < m {
            ep
        } else {
            m
        }
    };
    let (vp, _) = S::as_simd_f64s(p);
    let (vq, _) = S::as_simd_f64s(q);
    let (vpx, _) = S::as_simd_f64s(tpx);
    let (vpy, _) = S::as_simd_f64s(tpy);
    let (vqx, _) = S::as_simd_f64s(tqx);
    let (vqy, _) = S::as_simd_f64s(tqy);
    let (voff, _) = S::as_simd_f64s(off);
    let (vout, _) = S::as_mut_simd_f64s(out);
    let whole = vout.len() * S::F64_LANES;
    let (sf, sx, sy, tol) = (
        simd.splat_f64s(f),
        simd.splat_f64s(ex),
        simd.splat_f64s(ey),
        simd.splat_f64s(TRACTION_TOL),
    );
    let min = |a: S::f64s, b: S::f64s| simd.select_f64s(simd.less_than_f64s(a, b), a, b);
    let mut low = simd.splat_f64s(f64::INFINITY);
    for j in 0..vout.len() {
        let ep = simd.add_f64s(
            simd.add_f64s(vp[j], simd.mul_f64s(sx, vpx[j])),
            simd.mul_f64s(sy, vpy[j]),
        );
        let eq = simd.add_f64s(
            simd.add_f64s(vq[j], simd.mul_f64s(sx, vqx[j])),
            simd.mul_f64s(sy, vqy[j]),
        );
        let m = simd.add_f64s(
            simd.add_f64s(
                simd.sub_f64s(simd.mul_f64s(sf, ep), simd.abs_f64s(eq)),
                voff[j],
            ),
            tol,
        );
        let m = min(ep, m);
        vout[j] = m;
        low = min(m, low);
    }
    let mut lowest = simd.reduce_min_f64s(low);
    for j in whole..n {
        let m = margin(p[j], q[j], tpx[j], tpy[j], tqx[j], tqy[j], off[j]);
        out[j] = m;
        lowest = lowest.min(m);
    }
    lowest
}

/// The whole groups of four of `s`, as arrays (no length checks in a loop
/// over them).
#[inline(always)]
pub(super) fn four(s: &[f64]) -> &[[f64; 4]] {
    s.as_chunks::<4>().0
}

#[cfg(test)]
mod tests {
    use super::*;
    use pulp::{Scalar, Scalar128b, Scalar256b, Simd, WithSimd};

    /// Reproducible values in `[-1, 1)` (a linear congruential sequence).
    fn values(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
            })
            .collect()
    }

    /// Runs `op` on one instruction set chosen by the test, not by the
    /// processor.
    fn on<S: Simd, R>(simd: S, op: impl WithSimd<Output = R>) -> R {
        op.with_simd(simd)
    }

    struct Margins<'a>(&'a [Vec<f64>], &'a mut Vec<f64>);
    impl WithSimd for Margins<'_> {
        type Output = f64;
        fn with_simd<S: Simd>(self, simd: S) -> f64 {
            let v = std::array::from_fn(|i| self.0[i].as_slice());
            end_margins_kernel(simd, v, 0.3, 0.7, -0.2, self.1)
        }
    }

    /// The end margins are the same bits on every instruction set and
    /// every vector width, tail included (131 nodes: not a multiple of 4).
    #[test]
    fn end_margins_do_not_depend_on_the_instruction_set() {
        let n = 131;
        let mut v: Vec<Vec<f64>> = (0..7).map(|i| values(n, i)).collect();
        // Slip nodes: an infinite offset, as the increment sets it.
        for j in (0..n).step_by(5) {
            v[6][j] = f64::INFINITY;
        }
        let mut out = vec![0.0; n];
        let dispatched = end_margins(
            std::array::from_fn(|i| v[i].as_slice()),
            0.3,
            0.7,
            -0.2,
            &mut out,
        );
        let mut runs = Vec::new();
        for width in 0..3 {
            let mut o = vec![0.0; n];
            let low = match width {
                0 => on(Scalar::new(), Margins(&v, &mut o)),
                1 => on(Scalar128b, Margins(&v, &mut o)),
                _ => on(Scalar256b, Margins(&v, &mut o)),
            };
            runs.push((low, o));
        }
        for (low, o) in runs {
            assert_eq!(low.to_bits(), dispatched.to_bits());
            assert!(o.iter().zip(&out).all(|(a, b)| a.to_bits() == b.to_bits()));
            assert_eq!(low, o.iter().fold(f64::INFINITY, |m, &x| m.min(x)));
        }
    }

    /// The nodes at the limit are those of a plain filter, in node order,
    /// tail included (131 nodes): stick nodes at `|q| = f p` exactly, one
    /// a round-off inside, several in one group of four, none in others;
    /// slip nodes (an infinite offset) never.
    #[test]
    fn at_limit_lists_the_stick_nodes_at_the_friction_limit() {
        let (n, f) = (131, 0.3);
        let p: Vec<f64> = values(n, 70).iter().map(|v| v + 1.5).collect();
        let mut q: Vec<f64> = values(n, 71)
            .iter()
            .zip(&p)
            .map(|(v, p)| v * f * p)
            .collect();
        let mut off = vec![0.0; n];
        for j in [0, 5, 6, 7, 64, 129, 130] {
            q[j] = if j % 2 == 0 { f * p[j] } else { -f * p[j] };
        }
        q[40] = f * p[40] - 0.5 * TRACTION_TOL;
        for j in [6, 90] {
            off[j] = f64::INFINITY;
            q[j] = f * p[j];
        }
        let mut out = vec![usize::MAX; 3];
        at_limit(&p, &q, &off, f, &mut out);
        let expected: Vec<usize> = (0..n)
            .filter(|&j| f * p[j] - q[j].abs() + off[j] <= TRACTION_TOL)
            .collect();
        assert_eq!(out, expected);
        assert_eq!(out, vec![0, 5, 7, 40, 64, 129, 130]);
    }

    /// The first-event pass gives, at every node (tail included: 131
    /// nodes), the bits of the scalar [`event_time`], and their minimum;
    /// and the times it gives are the roots of the affine slack and
    /// pressure it watches.
    #[test]
    fn event_times_are_the_scalar_first_events() {
        let (n, f) = (131, 0.3);
        let mut v: Vec<Vec<f64>> = (20..27).map(|i| values(n, i)).collect();
        // Pressures in [0.5, 1.5) and shears inside the friction cone;
        // slip nodes (an infinite offset) every fifth; stick nodes at the
        // friction limit every seventh.
        let (p, rest) = v.split_at_mut(1);
        for (j, (p, q)) in p[0].iter_mut().zip(&mut rest[0]).enumerate() {
            *p += 1.5;
            *q = if j % 7 == 0 { f * *p } else { *q * f * *p };
        }
        for (j, off) in v[6].iter_mut().enumerate() {
            *off = if j % 5 == 0 { f64::INFINITY } else { 0.0 };
        }
        let along = [0.8, -0.6, 1.0];
        let mut out = vec![0.0; n];
        let lowest = event_times(
            std::array::from_fn(|i| v[i].as_slice()),
            along,
            f,
            1e-13,
            &mut out,
        );
        let mut kinds = [0; 3];
        for j in 0..n {
            let node: [f64; 7] = std::array::from_fn(|i| v[i][j]);
            let t = event_time(node, along, f, 1e-13);
            assert_eq!(out[j].to_bits(), t.to_bits(), "node {j}");
            let [p, q, px, py, qx, qy, off] = node;
            let a = along[0] * px + along[1] * py;
            let b = along[0] * qx + along[1] * qy;
            if t == -1.0 {
                // At the limit, its slack falling on one side.
                kinds[0] += 1;
                assert!(off == 0.0 && (f * p - q.abs()).abs() < 1e-12, "node {j}");
            } else if t.is_finite() {
                kinds[1] += 1;
                // A root: the pressure, or a stick node's slack on a side.
                let roots = [
                    p + t * a,
                    f * (p + t * a) - (q + t * b),
                    f * (p + t * a) + (q + t * b),
                ];
                let hit = roots.iter().take(if off == 0.0 { 3 } else { 1 });
                assert!(
                    hit.into_iter().any(|r| r.abs() < 1e-9),
                    "node {j}: {roots:?}"
                );
            } else {
                kinds[2] += 1;
            }
        }
        assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
        let min = out.iter().fold(f64::INFINITY, |m, &x| m.min(x));
        assert_eq!(lowest, min);
    }

    /// The slip of a sub-segment by one pass over every node is, to the
    /// bit, that of a loop over the slip set's nodes (the rates are 0 off
    /// the set, where the pass must change nothing), tail included.
    #[test]
    fn add_slip_over_every_node_is_the_loop_over_the_set() {
        let n = 131;
        let mut rates = values(n, 50);
        let set: Vec<usize> = (0..n).filter(|j| j % 3 != 0).collect();
        for j in (0..n).step_by(3) {
            rates[j] = if j % 2 == 0 { 0.0 } else { -0.0 };
        }
        let start = [values(n, 51), values(n, 52), values(n, 53)];
        let t = 0.37;
        let [mut slip, mut fw, mut bw] = start.clone();
        add_slip(t, &rates, &mut slip, &mut fw, &mut bw);
        let [mut slip_set, mut fw_set, mut bw_set] = start.clone();
        for &j in &set {
            let dg = t * rates[j];
            slip_set[j] += dg;
            fw_set[j] += dg.max(0.0);
            bw_set[j] += (-dg).max(0.0);
        }
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&slip), bits(&slip_set));
        assert_eq!(bits(&fw), bits(&fw_set));
        assert_eq!(bits(&bw), bits(&bw_set));
        assert!(set.iter().any(|&j| slip[j] != start[0][j]));
    }

    /// A move along the slip set gives the same bits in vectors of four
    /// (the processor's and an emulated one) as in groups of four.
    #[test]
    fn slide_does_not_depend_on_the_instruction_set() {
        let n = 130;
        let inputs: Vec<Vec<f64>> = (10..17).map(|i| values(n, i)).collect();
        let mut rates = values(n, 20);
        for j in (0..n).step_by(3) {
            rates[j] = 0.0;
        }
        let s = Slide {
            t: 0.37,
            tx: 0.8,
            ty: -0.45,
            elastic: Elastic {
                pr: 1.3,
                qr: 0.6,
                qt: 0.2,
            },
            responses: std::array::from_fn(|i| inputs[i].as_slice()),
            trig: [&inputs[4], &inputs[5]],
            rates: &rates,
        };
        let start: Vec<Vec<f64>> = (30..34).map(|i| values(n, i)).collect();
        let mut results = Vec::new();
        for way in 0..3 {
            let mut v = start.clone();
            let [a, b, c, d] = &mut v[..] else {
                unreachable!()
            };
            let parts = [&mut a[..], &mut b[..], &mut c[..], &mut d[..]];
            let lanes = match way {
                0 => slide(&s, parts),
                1 => slide_kernel(&s, parts),
                _ => slide_wide(Scalar256b, &s, parts),
            };
            results.push((lanes, v));
        }
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        for (lanes, v) in &results[1..] {
            assert_eq!(bits(lanes), bits(&results[0].0));
            for (x, y) in v.iter().zip(&results[0].1) {
                assert_eq!(bits(x), bits(y));
            }
        }
        // And the sum is the dissipation it stands for.
        let (lanes, v) = &results[0];
        let direct: f64 = (0..n)
            .map(|j| (s.t * rates[j]).abs() * (start[2][j] + v[2][j]))
            .sum();
        let total: f64 = lanes.iter().sum();
        assert!((total - direct).abs() <= 1e-12 * direct.abs().max(1.0));
    }
}
