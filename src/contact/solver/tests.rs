//! Property tests of the slip-direction helpers and the elastic margins.

use super::{push_differences, same_directions, SlipDirection};
use proptest::prelude::*;

/// Any of the three directions of a node.
pub(in crate::contact) fn direction() -> impl Strategy<Value = SlipDirection> {
    prop_oneof![
        Just(SlipDirection::Stick),
        Just(SlipDirection::Forward),
        Just(SlipDirection::Backward),
    ]
}

proptest! {
    /// The branch-free comparison agrees with slice equality, on equal
    /// sets, sets that differ at one node, and sets of other lengths.
    #[test]
    fn same_directions_is_slice_equality(
        a in proptest::collection::vec(direction(), 0..300),
        at in any::<prop::sample::Index>(),
        other in direction(),
        b in proptest::collection::vec(direction(), 0..300),
    ) {
        prop_assert!(same_directions(&a, &a));
        let mut changed = a.clone();
        if !changed.is_empty() {
            let j = at.index(changed.len());
            changed[j] = other;
        }
        prop_assert_eq!(same_directions(&a, &changed), a == changed);
        prop_assert_eq!(same_directions(&a, &b), a == b);
    }

    /// The chunked differences are the nodes where the sets differ,
    /// in node order, after what the list held: for sets that differ
    /// at a few nodes (as at an event) and for unrelated sets, of any
    /// length (whole chunks of 16 and a tail).
    #[test]
    fn push_differences_lists_the_differing_nodes(
        a in proptest::collection::vec(direction(), 0..300),
        changes in proptest::collection::vec((any::<prop::sample::Index>(), direction()), 0..6),
        b in proptest::collection::vec(direction(), 0..300),
    ) {
        let mut changed = a.clone();
        if !changed.is_empty() {
            for (at, d) in &changes {
                let j = at.index(changed.len());
                changed[j] = *d;
            }
        }
        // `b` at the length of `a` (`a` itself where `b` is empty).
        let b: Vec<SlipDirection> = (0..a.len())
            .map(|j| if b.is_empty() { a[j] } else { b[j % b.len()] })
            .collect();
        for other in [&changed, &b] {
            let expected: Vec<usize> = (0..a.len()).filter(|&j| a[j] != other[j]).collect();
            let mut out = vec![usize::MAX];
            push_differences(&a, other, &mut out);
            prop_assert_eq!(out[0], usize::MAX);
            prop_assert_eq!(&out[1..], &expected[..]);
        }
    }

    /// The least elastic margins from the affine form agree with the
    /// tractions at each point.
    #[test]
    fn least_elastic_margins_are_the_least_over_the_points(
        points in proptest::collection::vec((-9.0..9.0f64, -9.0..9.0f64), 1..20),
        friction in 0.05..0.8f64,
    ) {
        use crate::model::{LoadPoint, Material, Plane};
        let material = Material::new(friction, 0.3, Plane::Strain).unwrap();
        let contact = super::Contact::new(material, std::sync::Arc::new(crate::contact::Operators::new(32)));
        let loads: Vec<LoadPoint> = points.iter().map(|&(x, y)| LoadPoint::new(x, y)).collect();
        let least = contact.least_elastic_margins(loads.iter().copied());
        for j in 0..32 {
            let mut expected = [f64::INFINITY; 2];
            for &load in &loads {
                let (p, q) = contact.elastic_tractions(load);
                expected[0] = expected[0].min(friction * p[j] - q[j]);
                expected[1] = expected[1].min(friction * p[j] + q[j]);
            }
            for s in 0..2 {
                prop_assert!((least[j][s] - expected[s]).abs() < 1e-12, "{j} {s}: {} {}", least[j][s], expected[s]);
            }
        }
    }
}
