//! Tests of the parent module.

use super::*;
use crate::analysis::case::CaseParams;

fn shape(family: Family, k: usize) -> Shape {
    let case = Case::from_params(&CaseParams::default()).unwrap();
    Shape::new(
        family,
        k,
        Region::for_material(&case.material()),
        case.cycle().center(),
    )
    .unwrap()
}

#[test]
fn every_path_of_the_box_is_admissible() {
    for s in [shape(Family::Free, 3), shape(Family::Decaying, 6)] {
        let (lo, hi) = s.bounds();
        // Corners and points beyond the box are clamped into it.
        for t in [-0.5, 0.0, 0.3, 1.0, 1.5] {
            let p: Vec<f64> = lo.iter().zip(&hi).map(|(l, u)| l + t * (u - l)).collect();
            for v in s.path(&p) {
                assert!(s.region.contains(v), "{v:?}");
                assert!(v.y().abs() < 2.0 * PI);
            }
        }
    }
}

#[test]
fn decaying_zig_zag_alternates_and_shrinks() {
    let s = shape(Family::Decaying, 4);
    let a = s.center;
    let p = s.path(&[a.x() + 2.0, a.y() - 1.0, 0.5, PI]);
    let d: Vec<(f64, f64)> = p.iter().map(|v| (v.x() - a.x(), v.y() - a.y())).collect();
    for k in 1..4 {
        assert!((d[k].0 + 0.5 * d[k - 1].0).abs() < 1e-12);
        assert!((d[k].1 + 0.5 * d[k - 1].1).abs() < 1e-12);
    }
}

#[test]
fn paper_points_and_padding_are_members() {
    let s = shape(Family::Free, 3);
    let i = LoadPoint::new(-7.0 * PI / 4.0, -7.0 * PI / 4.0);
    let p = s.path(&s.through(i));
    assert_eq!(p[0], i);
    assert_eq!(p[1], s.center);
    assert_eq!(s.padded(&[i]).unwrap(), s.through(i));
    let d = shape(Family::Decaying, 3);
    let q = d.path(&d.through(i));
    assert_eq!(q[0], i);
    assert_eq!(q[2], d.center);
}

#[test]
fn initial_path_text_reads_back_exactly() {
    let path = vec![
        LoadPoint::new(-5.99194483519952, -6.194142565165114),
        LoadPoint::new(1.0 / 3.0, PI),
    ];
    let text = initial_path_text(&path);
    let back = crate::io::parse::parse_points(&text).unwrap();
    for (p, (x, y)) in path.iter().zip(back) {
        assert_eq!(p.x().to_bits(), x.to_bits());
        assert_eq!(p.y().to_bits(), y.to_bits());
    }
}

/// The search's settings are checked against their ranges where they are
/// made: a budget, a region's gap, a shape's vertex count.
#[test]
fn budgets_regions_and_shapes_are_checked_against_their_ranges() {
    use crate::model::ranges::{GROSS_GAP, ITERATIONS, PARTICLES, VERTICES};
    let (p, i) = (PARTICLES, ITERATIONS);
    assert!(Budget::new(p.min, i.min as u64, 1).is_ok());
    assert!(Budget::new(p.max, i.max as u64, 1).is_ok());
    assert!(Budget::new(p.min - 1, 0, 1).is_err());
    assert!(Budget::new(p.max + 1, 0, 1).is_err());
    assert!(Budget::new(p.min, i.max as u64 + 1, 1).is_err());
    assert!(Budget::new(p.min, u64::MAX, 1).is_err());
    let m = Material::paper();
    for gap in [GROSS_GAP.low, GROSS_GAP.high] {
        let r = Region::with_gross_gap(&m, gap).unwrap();
        assert_eq!(r.y_max(), 2.0 * PI - gap);
    }
    for gap in [
        GROSS_GAP.low.next_down(),
        GROSS_GAP.high.next_up(),
        f64::NAN,
    ] {
        assert!(Region::with_gross_gap(&m, gap).is_err());
    }
    let region = Region::for_material(&m);
    let at = LoadPoint::ORIGIN;
    assert!(Shape::new(Family::Free, VERTICES.min, region, at).is_ok());
    assert!(Shape::new(Family::Free, VERTICES.max, region, at).is_ok());
    assert!(Shape::new(Family::Free, VERTICES.max + 1, region, at).is_err());
    assert!(Shape::new(Family::Free, VERTICES.min - 1, region, at).is_err());
}
