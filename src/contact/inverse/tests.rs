//! The kept inverse against fresh factorisations of the system.

use super::*;
use crate::contact::kernels::*;

/// [`SetInverse::update_to`] with the set read off `d`, after noting
/// exactly the nodes whose direction differs from the inverse's set.
fn update(inv: &mut SetInverse, ops: &Operators, f: f64, d: &[SlipDirection]) -> bool {
    let set: Vec<(usize, f64)> = (0..d.len())
        .filter(|&j| d[j].is_slipping())
        .map(|j| (j, d[j].sign()))
        .collect();
    let now = inv.directions();
    let differ: Vec<usize> = (0..d.len()).filter(|&j| now[j] != d[j]).collect();
    inv.note_changes(&differ);
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

/// The operators of `n` nodes and a solver given elastic tractions per
/// unit load (any smooth shapes will do): `shape(j, a * scale)` for
/// `a = 1..4` as `p_x`, `q_x`, `p_y`, `q_y`.
fn loaded(
    n: usize,
    shape: impl Fn(usize, f64) -> f64,
    scale: f64,
) -> (Operators, SetInverse, Vec<Vec<f64>>) {
    let mut inv = SetInverse::new(n);
    let loads: Vec<Vec<f64>> = (1..=4)
        .map(|a| (0..n).map(|j| shape(j, f64::from(a) * scale)).collect())
        .collect();
    inv.set_loads([&loads[0], &loads[1], &loads[2], &loads[3]]);
    (Operators::new(n), inv, loads)
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

/// The factors' columns start on 32-byte boundaries: the array does,
/// and the stride is a whole number of vectors of four (below `N`).
#[test]
fn factor_columns_are_aligned() {
    for len in [1, 5, 64, 1000] {
        let a = Aligned::zeros(len);
        assert_eq!(a.len(), len);
        assert_eq!(a.as_ptr() as usize % 32, 0);
        assert!(a.iter().all(|&x| x == 0.0));
    }
    for k in 1..300 {
        let ld = stride(k, 1024);
        assert!(ld.is_multiple_of(4) && ld >= k + slack(k) && ld < k + slack(k) + 4);
        assert_eq!(stride(k, k + 2), k + 2);
    }
}

/// The passes against plain substitution and products, for sizes
/// around the blocks of four and a stride wider than the block, and the
/// dispatched kernels against the narrow ones bit for bit.
#[test]
fn passes_match_substitution_on_every_instruction_set() {
    let value = |i: usize, j: usize| ((i * 31 + j * 17) % 23) as f64 / 23.0 - 0.5;
    for k in [1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 63, 130] {
        let ld = k + 5;
        // Unit L below the diagonal, W with a dominant diagonal on and
        // above it.
        let lu: Vec<f64> = (0..ld * k)
            .map(|e| {
                let (i, j) = (e % ld, e / ld);
                if i == j {
                    3.0 + value(i, j)
                } else {
                    value(i, j) / 4.0
                }
            })
            .collect();
        let at = |i: usize, j: usize| lu[j * ld + i];
        let c: Vec<f64> = (0..k).map(|i| (i as f64 * 0.7).sin()).collect();
        let r: Vec<f64> = (0..k).map(|i| (i as f64 * 0.3).cos() - 0.2).collect();
        // Plain: u = L^-1 c by substitution, l = W^T r, v = W u, x = W c.
        let mut u0 = c.clone();
        for i in 0..k {
            for j in 0..i {
                u0[i] -= at(i, j) * u0[j];
            }
        }
        let upper = |x: &[f64]| -> Vec<f64> {
            (0..k)
                .map(|i| (i..k).map(|j| at(i, j) * x[j]).sum())
                .collect()
        };
        let l0: Vec<f64> = (0..k)
            .map(|j| (0..=j).map(|i| at(i, j) * r[i]).sum())
            .collect();
        let v0 = upper(&u0);
        let x0 = upper(&c);
        let f = Factors { lu: &lu, ld, k };
        let close = |a: &[f64], b: &[f64], what: &str| {
            for i in 0..k {
                assert!(
                    (a[i] - b[i]).abs() < 1e-12 * (1.0 + b[i].abs()),
                    "k {k}: {what}[{i}]"
                );
            }
        };
        let bits = |x: &[f64]| x.iter().map(|e| e.to_bits()).collect::<Vec<_>>();
        let run = |pass: Pass<'_>, narrow: bool| {
            let t = Triangular { f, pass };
            if narrow {
                t.run(Narrow);
            } else {
                pulp::Arch::new().dispatch(t);
            }
        };
        let mut outs = Vec::new();
        for narrow in [false, true] {
            let (mut u, mut l, mut v) = (c.clone(), vec![f64::NAN; k], vec![f64::NAN; k]);
            run(
                Pass::Border {
                    u: &mut u,
                    r: &r,
                    l: &mut l,
                    v: &mut v,
                },
                narrow,
            );
            close(&u, &u0, "L^-1 c");
            close(&l, &l0, "W^T r");
            close(&v, &v0, "W L^-1 c");
            let mut x = c.clone();
            run(Pass::Inverse { y: &mut x }, narrow);
            close(&x, &x0, "W c");
            let mut y = c.clone();
            run(Pass::Lower { y: &mut y, from: 0 }, narrow);
            close(&y, &u0, "L^-1 c (lower)");
            outs.push([bits(&u), bits(&l), bits(&v), bits(&x), bits(&y)]);
        }
        assert_eq!(outs[0], outs[1], "k {k}: wide and narrow differ");
    }
}

#[test]
fn updates_match_the_system() {
    let n = 64;
    let f = 0.1;
    let shape = |j: usize, a: f64| (j as f64 * a).sin() + 0.3 * (j as f64 * 0.7).cos();
    let (ops, mut inv, loads) = loaded(n, shape, 0.37);
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
fn long_runs_of_updates_with_pinned_and_reversed_nodes_match_the_system() {
    // A slip zone that grows one node at a time, as an advancing slip
    // zone does, with a node leaving now and then and the end node
    // reversing: nearly every change an update, with pinned and reversed
    // nodes in the correction and the factors moved to a wider stride
    // on the way.
    let n = 256;
    let f = 0.3;
    let shape = |j: usize, a: f64| (j as f64 * a).cos() - 0.2 * (j as f64 * 0.3).sin();
    let (ops, mut inv, loads) = loaded(n, shape, 0.21);
    let mut d = dirs(n, &[(100, 140, 1.0)]);
    assert!(update(&mut inv, &ops, f, &d));
    let mut special = 0;
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
        special = special.max(inv.special.len());
        wider += usize::from(inv.ld > stride);
        if step % 10 == 9 || flipped {
            assert_eq!(inv.directions(), d);
            check_kept_rates(&inv, &loads, f, n);
            let r = residual(&ops, f, &mut inv, n);
            assert!(r < 1e-10, "residual {r} at step {step}");
        }
    }
    // The correction holds a few nodes (`special_limit`), so the 13
    // pinned and 8 reversed nodes make a few factorisations.
    assert!(inv.rebuilds <= 6, "{} factorisations", inv.rebuilds);
    assert!(special > 1 && wider > 0, "special {special}, wider {wider}");
}

/// Three arcs, two of one sign and one of the other, grow one node at
/// a time at their six edges, past the size where the structured
/// borderings take over: the kept rates agree with a fresh
/// factorisation all along, also after a node that sticks at an edge,
/// one that enters on its own far from the edges (a fourth arc) and one
/// that reverses inside an arc sent the factors after the set.
#[test]
fn structured_borderings_of_growing_arcs_match_a_fresh_factorisation() {
    let n = 512;
    let f = 0.25;
    let shape = |j: usize, a: f64| (j as f64 * a).sin() + 0.3 * (j as f64 * 0.11).cos();
    let (ops, mut inv, loads) = loaded(n, shape, 0.013);
    let mut d = dirs(n, &[(20, 90, 1.0), (180, 250, -1.0), (340, 400, 1.0)]);
    assert!(update(&mut inv, &ops, f, &d));
    let mut edges = [
        (19usize, 0usize),
        (90, 1),
        (179, 0),
        (250, 1),
        (339, 0),
        (400, 1),
    ];
    let signs = [1.0, 1.0, -1.0, -1.0, 1.0, 1.0];
    let mut structured = 0;
    let mut last = 0;
    let rebuilds = inv.rebuilds;
    for step in 0..150 {
        let e = (step * 7 + step / 5) % 6;
        let (node, side) = edges[e];
        d[node] = SlipDirection::from_sign(signs[e]);
        if step == 60 {
            last = node;
        }
        edges[e].0 = if side == 1 {
            node + 1
        } else {
            (node + n - 1) % n
        };
        match step {
            // The node that entered at step 60, an edge still, sticks.
            61 => d[last] = SlipDirection::Stick,
            90 => d[470] = SlipDirection::Forward,
            120 => d[200] = SlipDirection::Backward,
            _ => {}
        }
        assert!(update(&mut inv, &ops, f, &d));
        structured += usize::from(inv.structured.is_some());
        if step % 10 == 9 || matches!(step, 61 | 62 | 90 | 91 | 120 | 121) {
            assert_eq!(inv.directions(), d);
            check_kept_rates(&inv, &loads, f, n);
        }
    }
    assert!(structured > 100, "{structured} structured borderings");
    assert!(
        inv.rebuilds - rebuilds <= 1,
        "{} factorisations",
        inv.rebuilds - rebuilds
    );
    // And the factors, bordered up to the set, solve its system.
    assert!(inv.catch_up(&ops));
    let r = residual(&ops, f, &mut inv, n);
    assert!(r < 1e-10, "residual {r}");
}

/// Two arcs of one sign grow towards each other and merge, while the
/// far edge of one sticks node after node inwards (each new pinned
/// node's column shifted from the last one's) and a node enters on its
/// own (its column made by a walk of shifts from the nearest edge):
/// the kept rates agree with a fresh factorisation all along, and the
/// dense factors are never needed.
#[test]
fn structured_merges_and_retreats_match_a_fresh_factorisation() {
    let n = 512;
    let f = 0.3;
    let shape = |j: usize, a: f64| (j as f64 * a).cos() + 0.2 * (j as f64 * 0.05).sin();
    let (ops, mut inv, loads) = loaded(n, shape, 0.011);
    let mut d = dirs(n, &[(60, 200, -1.0), (230, 330, -1.0)]);
    assert!(update(&mut inv, &ops, f, &d));
    // One bordering through the factors, then structured ones.
    let back = SlipDirection::from_sign(-1.0);
    d[200] = back;
    assert!(update(&mut inv, &ops, f, &d));
    assert!(inv.structured.is_some());
    let factored = inv.perm.len();
    for step in 0..29 {
        // 201.. from the left, 229.. down from the right: they meet.
        d[201 + step.min(14)] = back;
        d[229 - step.min(14)] = back;
        if step < 12 {
            d[60 + step] = SlipDirection::Stick;
        }
        if step >= 15 {
            // The merged arc grows at the end it took from the other.
            d[330 + (step - 15)] = back;
        }
        if step >= 20 {
            // A node on its own, then an arc growing both ways, which
            // meets the merged arc (at 340) and merges with it.
            d[345 + (step - 20)] = back;
            d[345 - (step - 20)] = back;
        }
        assert!(update(&mut inv, &ops, f, &d));
        assert_eq!(inv.directions(), d);
        check_kept_rates(&inv, &loads, f, n);
        assert_eq!(inv.perm.len(), factored, "dense factors at step {step}");
        assert!(inv.structured.is_some(), "structured at step {step}");
    }
    assert!(inv.catch_up(&ops));
    let r = residual(&ops, f, &mut inv, n);
    assert!(r < 1e-10, "residual {r}");
}

use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random walks of slip sets, one to three nodes entering,
    /// sticking or reversing at a step and now and then many at once:
    /// the kept rates and the solve agree with a fresh factorisation
    /// of the set after every step, whatever mix of borderings,
    /// pinned and reversed nodes and rebuilds got there, and whether
    /// or not nodes that did not change were noted as changed.
    #[test]
    fn random_walks_of_slip_sets_match_a_fresh_factorisation(
        friction in 0.05..0.6f64,
        start in 0..48usize,
        steps in proptest::collection::vec(
            proptest::collection::vec((0..48usize, 0..3u8), 1..4),
            1..40,
        ),
    ) {
        let n = 48;
        let shape = |j: usize, a: f64| (j as f64 * a).sin() + 0.4 * (j as f64 * 0.9).cos();
        let (ops, mut inv, loads) = loaded(n, shape, 0.29);
        let mut d = vec![SlipDirection::Stick; n];
        for j in start..start + 12 {
            d[j % n] = SlipDirection::Forward;
        }
        for (t, changes) in steps.iter().enumerate() {
            for &(j, what) in changes {
                d[j] = match what {
                    0 => SlipDirection::Stick,
                    1 => SlipDirection::Forward,
                    _ => SlipDirection::Backward,
                };
            }
            if t % 13 == 12 {
                // Many at once: the zone moves by a quarter turn.
                d.rotate_right(n / 4);
            }
            // Nodes noted that did not change (set to what they were)
            // do no harm: `update` notes the ones that did.
            let touched: Vec<usize> = changes.iter().map(|&(j, _)| j).collect();
            inv.note_changes(&touched);
            if !update(&mut inv, &ops, friction, &d) {
                // Singular to working precision: nothing to compare.
                continue;
            }
            prop_assert_eq!(inv.directions(), d.clone());
            check_kept_rates(&inv, &loads, friction, n);
            let r = residual(&ops, friction, &mut inv, n);
            prop_assert!(r < 1e-9, "residual {} at step {}", r, t);
        }
    }
}
