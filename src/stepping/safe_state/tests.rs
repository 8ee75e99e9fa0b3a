//! Tests of the safe-state search: the shared setup, the coupling bound,
//! the search's optimum and the basis.

use super::*;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A setup handed on is taken only by a search of the cycle, material
/// and grid it was made for; any other makes its own, with the margins
/// a fresh search has.
#[test]
fn a_shared_setup_is_taken_only_where_it_fits() {
    use crate::model::{Material, Plane};
    let contact = |f: f64, n: usize| {
        let material = Material::new(f, 0.3, Plane::Strain).unwrap();
        Contact::new(material, std::sync::Arc::new(Operators::new(n)))
    };
    let (c, cycle) = (contact(0.1, 64), Cycle::paper(5.0, 0.0).unwrap());
    let first = SafeStateSearch::new(&c, &cycle, 200);
    let shared = || Some(Arc::clone(first.setup()));
    let same = SafeStateSearch::sharing(shared(), &c, &cycle, 200);
    assert!(Arc::ptr_eq(same.setup(), first.setup()));
    let others = [
        (contact(0.1, 64), Cycle::paper(5.5, 0.0).unwrap(), 200),
        (contact(0.1, 64), Cycle::paper(5.0, 0.3).unwrap(), 200),
        (contact(0.2, 64), cycle.clone(), 200),
        (contact(0.1, 32), cycle.clone(), 200),
        (contact(0.1, 64), cycle.clone(), 400),
    ];
    for (c, cycle, steps) in &others {
        let search = SafeStateSearch::sharing(shared(), c, cycle, *steps);
        assert!(!Arc::ptr_eq(search.setup(), first.setup()));
        let fresh = SafeStateSearch::new(c, cycle, *steps);
        assert_eq!(search.setup().elastic, fresh.setup().elastic);
    }
}

#[test]
fn coupling_bounds_the_pressure_of_any_slip_and_is_attained() {
    let n = 64;
    let ops = Operators::new(n);
    let c = coupling_constant(1.0, n);
    // Random-ish slips obey the bound.
    for seed in 1..20u64 {
        let e: Vec<f64> = (0..n)
            .map(|j| ((j as u64 * 2654435761 + seed * 97) % 1000) as f64 / 500.0 - 1.0)
            .collect();
        let he = ops.residual_pressure(&e);
        let de = ops.residual_shear(&e);
        let norm = (-dot(&e, &de)).sqrt();
        let peak = he.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(peak <= c * norm * (1.0 + 1e-12), "{peak} > {c} {norm}");
    }
    // The extremal slip: modes 1/|n| in phase at node 0, so that
    // (H e)_0 = sum 1/|n| and e^T |D| e = N sum 1/|n|.
    let e: Vec<f64> = (0..n)
        .map(|j| {
            let theta = 2.0 * PI * j as f64 / n as f64;
            (1..n / 2)
                .map(|k| -2.0 * (k as f64 * theta).sin() / k as f64)
                .sum()
        })
        .collect();
    let he = ops.residual_pressure(&e);
    let de = ops.residual_shear(&e);
    let norm = (-dot(&e, &de)).sqrt();
    assert!(
        (he[0].abs() / (c * norm) - 1.0).abs() < 1e-9,
        "{} vs {}",
        he[0],
        c * norm
    );
}

/// A full search from the rows that can bind, adding those its answer
/// violates, ends where a search on every row does: where neither
/// proves anything (both run to the optimum) with the same value
/// `delta - f C R`, recomputed exactly over every row; where one
/// proves, so does the other.
#[test]
fn a_search_from_the_binding_rows_ends_at_the_optimum_over_every_row() {
    use crate::model::{Material, Plane};
    let n = 64;
    let material = Material::new(0.1, 0.3, Plane::Strain).unwrap();
    let ops = Arc::new(Operators::new(n));
    let contact = Contact::new(material, Arc::clone(&ops));
    let search = SafeStateSearch::new(&contact, &Cycle::paper(5.0, 0.0).unwrap(), 200);
    let columns = search.basis().size;
    // delta - f C R of the safe state g + z for margins `m` at g.
    let value = |m: &[[f64; 2]], z: &[f64]| {
        let (p, d) = (ops.residual_pressure(z), ops.residual_shear(z));
        let delta = (0..n)
            .flat_map(|j| {
                let f = search.friction;
                [m[j][0] + f * p[j] - d[j], m[j][1] + f * p[j] + d[j]]
            })
            .fold(f64::INFINITY, f64::min);
        delta - search.coupling * (-dot(z, &d)).max(0.0).sqrt()
    };
    let (mut proving, mut not) = (0, 0);
    for (level, dip, width) in [
        (0.02, 0.03, 3.0),
        (0.02, 0.06, 8.0),
        (0.01, 0.2, 5.0),
        (0.005, 0.5, 12.0),
        (0.03, 1.0, 2.0),
    ] {
        // Margins with a dip about node n/4 (sign +) and n/2 (sign -).
        let margins: Vec<[f64; 2]> = (0..n)
            .map(|j| {
                let bump = |at: f64| (-((j as f64 - at) / width).powi(2)).exp();
                let wave = 0.01 * (2.0 * PI * 3.0 * j as f64 / n as f64).cos();
                [
                    level + wave - dip * bump(n as f64 / 4.0),
                    level - wave - 0.5 * dip * bump(n as f64 / 2.0),
                ]
            })
            .collect();
        let from_some = search.solve_from(&margins, columns, START_ROWS).unwrap();
        let from_all = search.solve_from(&margins, columns, f64::INFINITY).unwrap();
        let (a, b) = (value(&margins, &from_some), value(&margins, &from_all));
        assert_eq!(a > PROOF_TOLERANCE, b > PROOF_TOLERANCE, "{a} vs {b}");
        if b > PROOF_TOLERANCE {
            proving += 1;
        } else {
            not += 1;
            assert!((a - b).abs() <= 1e-6 * b.abs().max(1e-3), "{a} vs {b}");
        }
    }
    // Both kinds were met.
    assert!(proving > 0 && not > 0, "{proving} proving, {not} not");
}

#[test]
fn basis_columns_carry_their_operators_and_unit_energy() {
    let n = 32;
    let ops = Operators::new(n);
    let b = Basis::harmonics(n);
    assert_eq!(b.size, n - 1);
    for col in 0..b.size {
        let z = &b.slip[col * n..(col + 1) * n];
        let relief: Vec<f64> = ops.residual_shear(z).iter().map(|v| -v).collect();
        let pressure = ops.residual_pressure(z);
        for j in 0..n {
            assert!(
                (relief[j] - b.relief[col * n + j]).abs() < 1e-12,
                "column {col}"
            );
            assert!(
                (pressure[j] - b.pressure[col * n + j]).abs() < 1e-12,
                "column {col}"
            );
        }
        for other in 0..b.size {
            let y = &b.slip[other * n..(other + 1) * n];
            let energy = dot(y, &relief);
            let expected = if other == col { 1.0 } else { 0.0 };
            assert!((energy - expected).abs() < 1e-12, "{col} {other}: {energy}");
        }
    }
}
