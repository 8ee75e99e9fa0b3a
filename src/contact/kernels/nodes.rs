//! The `O(N)` node passes of the exact increment (see [`super`]).

use super::four;
use crate::contact::tolerances::TRACTION_TOL;

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
pub(in crate::contact) fn end_margins(
    v: [&[f64]; 7],
    f: f64,
    ex: f64,
    ey: f64,
    out: &mut [f64],
) -> f64 {
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

/// The fastest any node's end margin ([`end_margins_kernel`]) can fall
/// per unit of load along an axis whose total pressure and shear per unit
/// are `tp` and `tq`: the largest `|tp|` (the pressure of every node) and
/// `f |tp| + |tq|` (the lower slack `f p - |q|` of a stick node, `off` 0;
/// a slip node's, `off` infinite, is not watched). Infinite if a watched
/// rate is not finite, so that no bound is taken from it. Taken once per
/// slip set that outlives a segment, so it is written in vectors like the
/// passes of an increment (with the instruction set's `simd` in hand, as
/// [`end_margins`], which the `wide!` bodies do not have).
pub(in crate::contact) fn reach(tp: &[f64], tq: &[f64], off: &[f64], f: f64) -> f64 {
    struct Op<'a> {
        tp: &'a [f64],
        tq: &'a [f64],
        off: &'a [f64],
        f: f64,
    }
    impl pulp::WithSimd for Op<'_> {
        type Output = f64;
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, simd: S) -> f64 {
            reach_kernel(simd, self.tp, self.tq, self.off, self.f)
        }
    }
    pulp::Arch::new().dispatch(Op { tp, tq, off, f })
}

#[inline(always)]
pub(in crate::contact) fn reach_kernel<S: pulp::Simd>(
    simd: S,
    tp: &[f64],
    tq: &[f64],
    off: &[f64],
    f: f64,
) -> f64 {
    let n = tp.len();
    let (tq, off) = (&tq[..n], &off[..n]);
    let node = |p: f64, q: f64, off: f64| {
        let slack = if off < 1.0 {
            f * p.abs() + q.abs()
        } else {
            0.0
        };
        let v = if p.abs() < slack { slack } else { p.abs() };
        (v, p.abs() + slack)
    };
    let (vp, _) = S::as_simd_f64s(tp);
    let (vq, _) = S::as_simd_f64s(tq);
    let (voff, _) = S::as_simd_f64s(off);
    let (zero, one, sf) = (
        simd.splat_f64s(0.0),
        simd.splat_f64s(1.0),
        simd.splat_f64s(f),
    );
    let mut big = zero;
    // A NaN passes every comparison by: the sum keeps it.
    let mut sum = zero;
    for j in 0..vp.len() {
        let ap = simd.abs_f64s(vp[j]);
        let slack = simd.add_f64s(simd.mul_f64s(sf, ap), simd.abs_f64s(vq[j]));
        let slack = simd.select_f64s(simd.less_than_f64s(voff[j], one), slack, zero);
        let v = simd.select_f64s(simd.less_than_f64s(ap, slack), slack, ap);
        big = simd.select_f64s(simd.less_than_f64s(big, v), v, big);
        sum = simd.add_f64s(sum, simd.add_f64s(ap, slack));
    }
    let mut reach = simd.reduce_max_f64s(big);
    let mut total = simd.reduce_sum_f64s(sum);
    for j in vp.len() * S::F64_LANES..n {
        let (v, both) = node(tp[j], tq[j], off[j]);
        reach = reach.max(v);
        total += both;
    }
    if total.is_finite() {
        reach
    } else {
        f64::INFINITY
    }
}

/// The loads' part of the tractions at a load point: `p = 1 - pr sin` and
/// `q = -qt - qr cos` (model.md section 2), per unit of the radial force
/// and torque terms.
#[derive(Clone, Copy)]
pub(in crate::contact) struct Elastic {
    pub(in crate::contact) pr: f64,
    pub(in crate::contact) qr: f64,
    pub(in crate::contact) qt: f64,
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
pub(in crate::contact) struct Slide<'a> {
    pub(in crate::contact) t: f64,
    pub(in crate::contact) tx: f64,
    pub(in crate::contact) ty: f64,
    pub(in crate::contact) elastic: Elastic,
    /// `H g'` and `-|D| g'` along `u1` and `u2`: `[hpx, hpy, hqx, hqy]`.
    pub(in crate::contact) responses: [&'a [f64]; 4],
    /// `[sin, cos]` at the nodes.
    pub(in crate::contact) trig: [&'a [f64]; 2],
    /// Slip rates per unit `u1` and `u2` (0 off the slip set), or, with
    /// `along` `None`, the rates along the segment and an empty slice.
    pub(in crate::contact) rates: [&'a [f64]; 2],
    /// The segment's direction `(a1, a2)` in `u1`, `u2`: the rate of a
    /// node along it is `a1 gx + a2 gy`, the bits of [`combine`] (so the
    /// move need not wait for that pass); `None` if `rates[0]` holds them.
    pub(in crate::contact) along: Option<[f64; 2]>,
}

/// The slip of a move and its positive and negative parts, moved with it
/// in the same pass ([`slide`]): `slip += dg`, and `forward` and
/// `backward` added to or, if `fresh`, set to the positive and negative
/// parts of `dg` (they held an earlier increment's: setting them spares a
/// pass that clears them first). Off the slip set the rate is 0 and this
/// adds exactly nothing, so the pass gives the bits of a loop over the
/// set's nodes.
pub(in crate::contact) struct SlipOut<'a> {
    pub(in crate::contact) slip: &'a mut [f64],
    pub(in crate::contact) forward: &'a mut [f64],
    pub(in crate::contact) backward: &'a mut [f64],
    pub(in crate::contact) fresh: bool,
}

/// Move the residual tractions `rp`, `rq` and the tractions `p`, `q`
/// (`v = [rp, rq, p, q]`) by `s`, and return
/// `sum |dg| (p before + p after)` in the four lanes of node `j mod 4`
/// (nodes past the last whole four in lane 0). Off the slip set the rate
/// is 0, so those nodes add exactly nothing. With `slip`, the slip moves
/// in the same pass (a second pass over the rates cost a sixth of an
/// unchanged-set increment).
pub(in crate::contact) fn slide(s: &Slide, v: [&mut [f64]; 4], slip: Option<SlipOut>) -> [f64; 4] {
    struct Op<'a, 'b> {
        s: &'b Slide<'a>,
        v: [&'b mut [f64]; 4],
        slip: Option<SlipOut<'b>>,
    }
    impl pulp::WithSimd for Op<'_, '_> {
        type Output = [f64; 4];
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, simd: S) -> [f64; 4] {
            // The sum is kept in four lanes whatever the vector width, so
            // that it is the same on every processor: in vectors of four
            // where they exist, else in groups of four.
            let (s, v) = (self.s, self.v);
            let (slip, fresh) = match self.slip {
                Some(o) => ([o.slip, o.forward, o.backward], Some(o.fresh)),
                None => ([&mut [][..], &mut [], &mut []], None),
            };
            let combined = s.along.is_none();
            if S::F64_LANES == 4 {
                macro_rules! four_lanes {
                    ($one:literal) => {
                        match (combined, fresh) {
                            (true, None) => {
                                slide_wide::<S, $one, true, false, false>(simd, s, v, slip)
                            }
                            (true, Some(true)) => {
                                slide_wide::<S, $one, true, true, true>(simd, s, v, slip)
                            }
                            (true, Some(false)) => {
                                slide_wide::<S, $one, true, true, false>(simd, s, v, slip)
                            }
                            (false, None) => {
                                slide_wide::<S, $one, false, false, false>(simd, s, v, slip)
                            }
                            (false, Some(true)) => {
                                slide_wide::<S, $one, false, true, true>(simd, s, v, slip)
                            }
                            (false, Some(false)) => {
                                slide_wide::<S, $one, false, true, false>(simd, s, v, slip)
                            }
                        }
                    };
                }
                // A move along `u1` alone reads no response along `u2`.
                if s.ty == 0.0 {
                    four_lanes!(true)
                } else {
                    four_lanes!(false)
                }
            } else {
                match (combined, fresh) {
                    (true, None) => slide_kernel::<true, false, false>(s, v, slip),
                    (true, Some(true)) => slide_kernel::<true, true, true>(s, v, slip),
                    (true, Some(false)) => slide_kernel::<true, true, false>(s, v, slip),
                    (false, None) => slide_kernel::<false, false, false>(s, v, slip),
                    (false, Some(true)) => slide_kernel::<false, true, true>(s, v, slip),
                    (false, Some(false)) => slide_kernel::<false, true, false>(s, v, slip),
                }
            }
        }
    }
    pulp::Arch::new().dispatch(Op { s, v, slip })
}

/// The slip `dg` of one node into its slip and its positive and negative
/// parts ([`SlipOut`]), or with `FRESH` the parts set rather than added
/// to.
#[inline(always)]
pub(in crate::contact) fn slip_node<const FRESH: bool>(
    dg: f64,
    g: &mut f64,
    fw: &mut f64,
    bw: &mut f64,
) {
    *g += dg;
    let (pos, neg) = (
        if 0.0 < dg { dg } else { 0.0 },
        if dg < 0.0 { 0.0 - dg } else { 0.0 },
    );
    if FRESH {
        (*fw, *bw) = (pos, neg);
    } else {
        *fw += pos;
        *bw += neg;
    }
}

/// [`slide_kernel`] in vectors of four lanes (`S::F64_LANES == 4`): the
/// same operations in the same order at each node. With `ONE` (`ty = 0`,
/// a move along `u1` alone, as on every segment of a straight load path)
/// the responses along `u2` are not read: `0 h` would add only a zero,
/// and at `N = 1024`, where the pass streams its arrays from the second
/// level of the cache, two of them less are 15 % of its instructions.
#[inline(always)]
pub(in crate::contact) fn slide_wide<
    S: pulp::Simd,
    const ONE: bool,
    const COMBINED: bool,
    const SLIP: bool,
    const FRESH: bool,
>(
    simd: S,
    s: &Slide,
    [rp, rq, p, q]: [&mut [f64]; 4],
    [g, fw, bw]: [&mut [f64]; 3],
) -> [f64; 4] {
    let n = p.len();
    let el = s.elastic;
    let [hpx, hpy, hqx, hqy] = s.responses;
    let [sin, cos] = s.trig;
    let (vhpx, _) = S::as_simd_f64s(&hpx[..n]);
    let (vhpy, _) = S::as_simd_f64s(&hpy[..if ONE { 0 } else { n }]);
    let (vhqx, _) = S::as_simd_f64s(&hqx[..n]);
    let (vhqy, _) = S::as_simd_f64s(&hqy[..if ONE { 0 } else { n }]);
    let (vsin, _) = S::as_simd_f64s(&sin[..n]);
    let (vcos, _) = S::as_simd_f64s(&cos[..n]);
    // With `COMBINED`, `rates[0]` holds the rates along the segment.
    let (vgx, _) = S::as_simd_f64s(&s.rates[0][..n]);
    let (vgy, _) = S::as_simd_f64s(&s.rates[1][..if COMBINED { 0 } else { n }]);
    let [a1, a2] = s.along.unwrap_or([1.0, 0.0]);
    let (vrp, _) = S::as_mut_simd_f64s(&mut rp[..n]);
    let (vrq, _) = S::as_mut_simd_f64s(&mut rq[..n]);
    let (vp, _) = S::as_mut_simd_f64s(&mut p[..n]);
    let (vq, _) = S::as_mut_simd_f64s(&mut q[..n]);
    let m = if SLIP { n } else { 0 };
    let (vg, _) = S::as_mut_simd_f64s(&mut g[..m]);
    let (vfw, _) = S::as_mut_simd_f64s(&mut fw[..m]);
    let (vbw, _) = S::as_mut_simd_f64s(&mut bw[..m]);
    let splat = |x: f64| simd.splat_f64s(x);
    let (tx, ty, t) = (splat(s.tx), splat(s.ty), splat(s.t));
    let (va1, va2) = (splat(a1), splat(a2));
    let (one, pr, qr, mqt) = (splat(1.0), splat(el.pr), splat(el.qr), splat(-el.qt));
    let zero = splat(0.0);
    let mut acc = splat(0.0);
    let whole = vp.len();
    for j in 0..whole {
        let (dp, dq) = if ONE {
            (simd.mul_f64s(tx, vhpx[j]), simd.mul_f64s(tx, vhqx[j]))
        } else {
            (
                simd.add_f64s(simd.mul_f64s(tx, vhpx[j]), simd.mul_f64s(ty, vhpy[j])),
                simd.add_f64s(simd.mul_f64s(tx, vhqx[j]), simd.mul_f64s(ty, vhqy[j])),
            )
        };
        let r_p = simd.add_f64s(vrp[j], dp);
        let r_q = simd.add_f64s(vrq[j], dq);
        vrp[j] = r_p;
        vrq[j] = r_q;
        vq[j] = simd.add_f64s(simd.sub_f64s(mqt, simd.mul_f64s(qr, vcos[j])), r_q);
        let p_new = simd.add_f64s(simd.sub_f64s(one, simd.mul_f64s(pr, vsin[j])), r_p);
        let rate = if COMBINED {
            vgx[j]
        } else {
            simd.add_f64s(simd.mul_f64s(va1, vgx[j]), simd.mul_f64s(va2, vgy[j]))
        };
        let dg = simd.mul_f64s(t, rate);
        if SLIP {
            vg[j] = simd.add_f64s(vg[j], dg);
            let pos = simd.select_f64s(simd.less_than_f64s(zero, dg), dg, zero);
            let neg =
                simd.select_f64s(simd.less_than_f64s(dg, zero), simd.sub_f64s(zero, dg), zero);
            if FRESH {
                vfw[j] = pos;
                vbw[j] = neg;
            } else {
                vfw[j] = simd.add_f64s(vfw[j], pos);
                vbw[j] = simd.add_f64s(vbw[j], neg);
            }
        }
        let dissipated = simd.mul_f64s(simd.abs_f64s(dg), simd.add_f64s(vp[j], p_new));
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
        let rate = if COMBINED {
            s.rates[0][j]
        } else {
            a1 * s.rates[0][j] + a2 * s.rates[1][j]
        };
        let dg = s.t * rate;
        if SLIP {
            slip_node::<FRESH>(dg, &mut g[j], &mut fw[j], &mut bw[j]);
        }
        lanes[0] += dg.abs() * (p[j] + p_new);
        p[j] = p_new;
    }
    lanes
}

#[inline(always)]
pub(in crate::contact) fn slide_kernel<
    const COMBINED: bool,
    const SLIP: bool,
    const FRESH: bool,
>(
    s: &Slide,
    [rp, rq, p, q]: [&mut [f64]; 4],
    [g, fw, bw]: [&mut [f64]; 3],
) -> [f64; 4] {
    let (t, tx, ty, el) = (s.t, s.tx, s.ty, s.elastic);
    let [hpx, hpy, hqx, hqy] = s.responses;
    let [sin, cos] = s.trig;
    let n = p.len();
    let node = |j: usize, rp: &mut [f64], rq: &mut [f64], p: &mut [f64], q: &mut [f64]| {
        rp[j] += tx * hpx[j] + ty * hpy[j];
        rq[j] += tx * hqx[j] + ty * hqy[j];
        q[j] = -el.qt - el.qr * cos[j] + rq[j];
        let p_new = 1.0 - el.pr * sin[j] + rp[j];
        let rate = match s.along {
            Some([a1, a2]) if !COMBINED => a1 * s.rates[0][j] + a2 * s.rates[1][j],
            _ => s.rates[0][j],
        };
        let dg = t * rate;
        let dissipated = dg.abs() * (p[j] + p_new);
        p[j] = p_new;
        (dg, dissipated)
    };
    let mut acc = [0.0f64; 4];
    let whole = n - n % 4;
    for j in 0..n {
        let (dg, dissipated) = node(j, rp, rq, p, q);
        if SLIP {
            slip_node::<FRESH>(dg, &mut g[j], &mut fw[j], &mut bw[j]);
        }
        acc[if j < whole { j % 4 } else { 0 }] += dissipated;
    }
    acc
}

/// The nodes where `f p - |q| + off <= TRACTION_TOL` (stick nodes at the
/// friction limit, `off` being infinite on slip nodes) into `out`, in node
/// order: a branch-free test of four nodes at a time, and a look at each
/// only in the rare groups that hold one.
#[inline(always)]
pub(in crate::contact) fn at_limit_kernel(
    p: &[f64],
    q: &[f64],
    off: &[f64],
    f: f64,
    out: &mut Vec<usize>,
) {
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
pub(in crate::contact) fn rate_extremes_kernel(r: &[f64], sgn: &[f64]) -> (f64, f64) {
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
        if along[1] == 0.0 {
            // Along `u1` alone (a straight load path): the rates along
            // `u2` are not read (`0 py` adds nothing but the sign of a
            // zero, which no test below sees).
            let nodes = p[..n]
                .iter()
                .zip(&q[..n])
                .zip(&px[..n])
                .zip(&qx[..n])
                .zip(&off[..n]);
            for (o, ((((&p, &q), &px), &qx), &off)) in out.iter_mut().zip(nodes) {
                *o = event_time([p, q, px, 0.0, qx, 0.0, off], along, f, rate_tol);
            }
        } else {
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
pub(in crate::contact) fn event_time(v: [f64; 7], along: [f64; 3], f: f64, rate_tol: f64) -> f64 {
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

/// The margins at the end of the segment into `out`, and the lowest: at
/// each node the lower of its end pressure and its end slack `f p -+ q`
/// (plus `TRACTION_TOL`, and infinite on slip nodes through `off`).
/// Negative: the node may reach an event. Branch-free, in the lanes of
/// `simd`; every lane does the scalar operations in the scalar order, and
/// a minimum does not depend on the order it is taken in, so the result is
/// the same on every instruction set.
#[inline(always)]
pub(in crate::contact) fn end_margins_kernel<S: pulp::Simd>(
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
