//! The kernels give the same bits on every instruction set.

use super::nodes::*;

use crate::contact::tolerances::TRACTION_TOL;
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
    // Along both axes, and along `u1` alone (the pass then reads no
    // rate along `u2`).
    for along in [[0.8, -0.6, 1.0], [0.8, 0.0, 1.0]] {
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
}

/// The reach is the largest fall rate of a watched margin: `|tp|` at
/// every node, `f |tp| + |tq|` at the stick nodes only (a slip node's
/// large shear rate does not count), tail included; infinite if a
/// watched rate is not finite.
#[test]
fn reach_is_the_fastest_fall_of_a_watched_margin() {
    let n = 131;
    let (tp, mut tq) = (values(n, 60), values(n, 61));
    let off: Vec<f64> = (0..n)
        .map(|j| if j % 3 == 0 { f64::INFINITY } else { 0.0 })
        .collect();
    let f = 0.3;
    let direct = |tp: &[f64], tq: &[f64]| {
        (0..n)
            .map(|j| {
                let slack = if j % 3 == 0 {
                    0.0
                } else {
                    f * tp[j].abs() + tq[j].abs()
                };
                tp[j].abs().max(slack)
            })
            .fold(0.0f64, f64::max)
    };
    assert_eq!(reach(&tp, &tq, &off, f), direct(&tp, &tq));
    // A slip node's shear rate, however large, is not watched; a stick
    // node's is, in the tail too.
    tq[3] = 1e6;
    assert_eq!(reach(&tp, &tq, &off, f), direct(&tp, &tq));
    assert!(reach(&tp, &tq, &off, f) < 1e6);
    tq[130] = 1e6;
    assert_eq!(reach(&tp, &tq, &off, f), 1e6 + f * tp[130].abs());
    tq[7] = f64::NAN;
    assert_eq!(reach(&tp, &tq, &off, f), f64::INFINITY);
}

/// A move along the slip set gives the same bits in vectors of four
/// (the processor's and an emulated one) as in groups of four, with
/// and without the slip moved in the same pass, and the slip it moves
/// is, to the bit, that of a loop over the slip set's nodes (the rates
/// are 0 off the set, where the pass must change nothing), tail
/// included: added to `forward` and `backward`, or set there when
/// they are `fresh`.
#[test]
fn slide_does_not_depend_on_the_instruction_set() {
    let n = 131;
    let inputs: Vec<Vec<f64>> = (10..17).map(|i| values(n, i)).collect();
    let (mut gx, mut gy) = (values(n, 20), values(n, 21));
    let set: Vec<usize> = (0..n).filter(|j| j % 3 != 0).collect();
    for j in (0..n).step_by(3) {
        gx[j] = if j % 2 == 0 { 0.0 } else { -0.0 };
        gy[j] = 0.0;
    }
    let along = [0.9, -0.3];
    let rates: Vec<f64> = (0..n)
        .map(|j| along[0] * gx[j] + along[1] * gy[j])
        .collect();
    // Two axes, and one (`ty = 0`: the pass then reads no response
    // along `u2`, and gives the scalar pass's bits still).
    let slide_along = |combined: bool, ty: f64| Slide {
        t: 0.37,
        tx: 0.8,
        ty,
        elastic: Elastic {
            pr: 1.3,
            qr: 0.6,
            qt: 0.2,
        },
        responses: std::array::from_fn(|i| inputs[i].as_slice()),
        trig: [&inputs[4], &inputs[5]],
        rates: if combined { [&rates, &[]] } else { [&gx, &gy] },
        along: (!combined).then_some(along),
    };
    let s = slide_along(false, -0.45);
    let start: Vec<Vec<f64>> = (30..34).map(|i| values(n, i)).collect();
    let slip_start = [values(n, 51), values(n, 52), values(n, 53)];
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    for (slip, ty) in [None, Some(false), Some(true)]
        .into_iter()
        .flat_map(|slip| [(slip, -0.45), (slip, 0.0)])
    {
        let mut results = Vec::new();
        // The rates along the segment given, or made in the pass from
        // those per unit `u1` and `u2`.
        for (combined, way) in [false, true]
            .into_iter()
            .flat_map(|c| (0..3).map(move |w| (c, w)))
        {
            let s = slide_along(combined, ty);
            let mut v = start.clone();
            let [a, b, c, d] = &mut v[..] else {
                unreachable!()
            };
            let parts = [&mut a[..], &mut b[..], &mut c[..], &mut d[..]];
            let mut moved = slip_start.clone();
            let [g, fw, bw] = &mut moved;
            let none: [&mut [f64]; 3] = [&mut [], &mut [], &mut []];
            macro_rules! by_way {
                ($o:literal, $c:literal) => {
                    match (way, slip) {
                        (0, _) => {
                            let out = slip.map(|fresh| SlipOut {
                                slip: g,
                                forward: fw,
                                backward: bw,
                                fresh,
                            });
                            slide(&s, parts, out)
                        }
                        (1, None) => slide_kernel::<$c, false, false>(&s, parts, none),
                        (1, Some(false)) => slide_kernel::<$c, true, false>(&s, parts, [g, fw, bw]),
                        (1, Some(true)) => slide_kernel::<$c, true, true>(&s, parts, [g, fw, bw]),
                        (_, None) => {
                            slide_wide::<_, $o, $c, false, false>(Scalar256b, &s, parts, none)
                        }
                        (_, Some(false)) => {
                            slide_wide::<_, $o, $c, true, false>(Scalar256b, &s, parts, [g, fw, bw])
                        }
                        (_, Some(true)) => {
                            slide_wide::<_, $o, $c, true, true>(Scalar256b, &s, parts, [g, fw, bw])
                        }
                    }
                };
            }
            let lanes = match (ty == 0.0, combined) {
                (true, true) => by_way!(true, true),
                (true, false) => by_way!(true, false),
                (false, true) => by_way!(false, true),
                (false, false) => by_way!(false, false),
            };
            results.push((lanes, v, moved));
        }
        for (lanes, v, moved) in &results[1..] {
            assert_eq!(bits(lanes), bits(&results[0].0));
            for (x, y) in v.iter().zip(&results[0].1) {
                assert_eq!(bits(x), bits(y));
            }
            for (x, y) in moved.iter().zip(&results[0].2) {
                assert_eq!(bits(x), bits(y));
            }
        }
        // The slip moved is the loop over the set's.
        let [mut g, mut fw, mut bw] = slip_start.clone();
        if slip == Some(true) {
            fw.fill(0.0);
            bw.fill(0.0);
        }
        if slip.is_some() {
            for &j in &set {
                let dg = s.t * rates[j];
                g[j] += dg;
                fw[j] += dg.max(0.0);
                bw[j] += (-dg).max(0.0);
            }
        }
        let moved = &results[0].2;
        assert_eq!(bits(&moved[0]), bits(&g));
        assert_eq!(bits(&moved[1]), bits(&fw));
        assert_eq!(bits(&moved[2]), bits(&bw));
        let changed = set.iter().any(|&j| moved[0][j] != slip_start[0][j]);
        assert_eq!(slip.is_some(), changed);
        // And the sum is the dissipation it stands for.
        let (lanes, v, _) = &results[0];
        let direct: f64 = (0..n)
            .map(|j| (s.t * rates[j]).abs() * (start[2][j] + v[2][j]))
            .sum();
        let total: f64 = lanes.iter().sum();
        assert!((total - direct).abs() <= 1e-12 * direct.abs().max(1.0));
    }
}
