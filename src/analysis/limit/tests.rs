//! Tests of the `lambda_2` programme.

use super::*;

fn paper(phase: f64, nodes: usize, samples: usize) -> Limit {
    shakedown_limit(
        &Material::paper(),
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        phase,
        &Discretisation::new(nodes, 400).unwrap(),
        samples,
    )
    .unwrap()
}

#[test]
fn optimum_is_admissible_and_tight() {
    let l = paper(0.0, 64, 0);
    assert!(l.line);
    assert!(l.max_violation < 1e-6, "{}", l.max_violation);
    assert!(l.slip.iter().sum::<f64>().abs() < 1e-9);
    // Below the gross-slip bound: |y| reaches 2 pi at lambda = 7.41.
    let gross = 1.25 * PI * (1.0f64 + 0.625 * 0.625).sqrt() / 0.625;
    assert!(l.load_factor > 0.0 && l.load_factor < gross);
    // Beyond lambda_2 the returned slip cannot hold the friction law.
    let mut c = Contact::new(Material::paper(), Arc::new(Operators::new(64)));
    c.set_slip(&l.slip);
    let cycle = Cycle::paper(1.05 * l.load_factor, 0.0).unwrap();
    let worst = [0.5 * PI, 1.5 * PI]
        .iter()
        .map(|&t| {
            let (p, q) = c.tractions_at(cycle.at(t));
            p.iter()
                .zip(&q)
                .map(|(p, q)| q.abs() - 0.1 * p)
                .fold(f64::MIN, f64::max)
        })
        .fold(f64::MIN, f64::max);
    assert!(worst > 0.0);
}

#[test]
fn without_slip_the_limit_is_the_elastic_one() {
    // With g = 0 the limit is where the line leaves the stick diamond
    // |x| + |y| <= 2 pi; slip can only raise it.
    let l = paper(0.0, 64, 0);
    let norm = (1.0f64 + 0.625 * 0.625).sqrt();
    let elastic = (2.0 * PI - 1.75 * PI) * norm / (1.0 + 0.625);
    assert!(l.load_factor >= elastic - 1e-6);
}

#[test]
fn ellipse_bounds_bracket_a_finer_sampling() {
    let coarse = paper(0.5 * PI, 32, 8);
    let fine = paper(0.5 * PI, 32, 64);
    assert!(!coarse.line);
    assert!(fine.load_factor <= coarse.load_factor + 1e-6);
    assert!(fine.load_factor >= coarse.lower_bound - 1e-6);
}

/// The `2 N` rows that can bind give the optimum of all `2 N M` rows
/// (the programme as first stated), on several cycles and grids.
#[test]
fn reduced_rows_give_the_full_programme_optimum() {
    let material = Material::paper();
    let center = LoadPoint::new(PI, 0.75 * PI);
    for (nodes, phase, samples) in [
        (16, 0.0, 2),
        (16, 0.3 * PI, 12),
        (32, 0.5 * PI, 16),
        (24, 0.9 * PI, 9),
    ] {
        let unit = Cycle::new(center, 1.0, 0.625, phase).unwrap();
        let times: Vec<f64> = (0..samples)
            .map(|k| 0.5 * PI + 2.0 * PI * k as f64 / samples as f64)
            .collect();
        let ops = Arc::new(Operators::new(nodes));
        let contact = Contact::new(material, Arc::clone(&ops));
        let lp = Programme::new(&contact, &ops, center, times.iter().map(|&t| unit.at(t)));
        let (_, full, _) = lp.solve(&lp.all_rows(), TIGHT).unwrap();
        let (slip, reduced, _) = lp.solve(&lp.reduced_rows(), TIGHT).unwrap();
        assert!(
            (full - reduced).abs() <= 1e-9 * full,
            "N = {nodes}, phi = {phase}: {full} against {reduced}"
        );
        assert!(lp.max_violation(&slip, reduced) < 1e-8);
    }
}

#[test]
fn bad_sample_count_is_an_error() {
    let r = shakedown_limit(
        &Material::paper(),
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        1.0,
        &Discretisation::default(),
        2,
    );
    assert_eq!(r, Err(LimitError::Samples(2)));
}

/// Clarabel's tolerance for a reference optimum: good to about `1e-12`.
const TIGHT: f64 = 1e-12;

/// A programme on `nodes` nodes with the friction law at `points` (offsets
/// from the paper's centre `A`).
fn programme_points(phase: Option<f64>, polygon: &[(f64, f64)]) -> Vec<LoadPoint> {
    let center = LoadPoint::new(PI, 0.75 * PI);
    match phase {
        Some(phase) => {
            let unit = Cycle::new(center, 1.0, 0.625, phase).unwrap();
            let m = if is_line(0.625, phase) { 2 } else { 64 };
            (0..m)
                .map(|k| unit.at(0.5 * PI + 2.0 * PI * k as f64 / m as f64))
                .collect()
        }
        None => polygon
            .iter()
            .map(|&(u, v)| LoadPoint::new(center.x() + u, center.y() + v))
            .collect(),
    }
}

/// The certified vertex is the optimum of the programme: it agrees with
/// the interior-point solution at tight tolerance to `1e-9` (the issue's
/// bound; in fact to about `1e-13`), on a line, ellipses, a square and a
/// two-harmonic polyline, on grids solved directly and on grids whose
/// guess comes from half the nodes.
#[test]
fn the_vertex_is_the_interior_point_optimum() {
    let material = Material::paper();
    let center = LoadPoint::new(PI, 0.75 * PI);
    let square = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)];
    let two_harmonic: Vec<(f64, f64)> = (0..40)
        .map(|k| {
            let t = 2.0 * PI * k as f64 / 40.0;
            (0.6 * t.cos(), 0.5 * (2.0 * t).sin())
        })
        .collect();
    // (nodes, phase of an ellipse or None, polygon offsets)
    type Case<'a> = (usize, Option<f64>, &'a [(f64, f64)]);
    let cases: Vec<Case> = vec![
        (64, Some(0.0), &[]),
        (128, Some(0.0), &[]),
        (128, Some(0.5 * PI), &[]),
        (96, Some(0.75 * PI), &[]),
        (256, Some(0.3 * PI), &[]),
        (128, None, &square),
        (128, None, &two_harmonic),
    ];
    for (nodes, phase, polygon) in cases {
        let points = programme_points(phase, polygon);
        let found = optimum(&material, center, &points, nodes).unwrap();
        let ops = Arc::new(Operators::new(nodes));
        let contact = Contact::new(material, Arc::clone(&ops));
        let lp = Programme::new(&contact, &ops, center, points.iter().copied());
        let (_, reference, _) = lp.solve(&lp.reduced_rows(), TIGHT).unwrap();
        assert!(
            (found.load_factor - reference).abs() <= 1e-9 * reference,
            "N = {nodes}, phi = {phase:?}: vertex {} against {reference}",
            found.load_factor
        );
        // The vertex holds every row to round-off.
        assert!(found.max_violation < 1e-12, "{}", found.max_violation);
    }
}

/// Pivots reach the optimum even from the worst guess (every node's other
/// sign), through the shifted objective and the primal pivots.
#[test]
fn pivots_reach_the_optimum_from_the_worst_guess() {
    let material = Material::paper();
    let center = LoadPoint::new(PI, 0.75 * PI);
    for phase in [0.0, 0.5 * PI] {
        let points = programme_points(Some(phase), &[]);
        let ops = Arc::new(Operators::new(64));
        let contact = Contact::new(material, Arc::clone(&ops));
        let lp = Programme::new(&contact, &ops, center, points.iter().copied());
        let rows = lp.reduced_rows();
        let (slip, reference, _) = lp.solve(&rows, TIGHT).unwrap();
        let worst = lp
            .guess(&rows, &slip, reference)
            .iter()
            .map(|r| r ^ 1)
            .collect();
        let v = lp.vertex(&rows, worst).expect("a certified vertex");
        assert!(
            (v.load_factor - reference).abs() <= 1e-9 * reference,
            "phi = {phase}: {} against {reference}",
            v.load_factor
        );
        assert!(v.pivots >= 32, "{} pivots", v.pivots);
    }
}

/// Trigonometric interpolation reproduces a trigonometric polynomial
/// below the coarse grid's Nyquist harmonic exactly.
#[test]
fn interpolation_is_exact_on_low_harmonics() {
    let f = |t: f64| 0.3 + (t).cos() - 0.5 * (3.0 * t).sin() + 0.25 * (7.0 * t).cos();
    let coarse: Vec<f64> = (0..32).map(|j| f(2.0 * PI * j as f64 / 32.0)).collect();
    let fine = interpolate(&coarse, 64);
    for (j, g) in fine.iter().enumerate() {
        assert!((g - f(2.0 * PI * j as f64 / 64.0)).abs() < 1e-12);
    }
}
