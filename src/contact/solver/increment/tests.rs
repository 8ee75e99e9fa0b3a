//! Tests of the exact increment's engine: the change of set, responses
//! read in place in the cache, and the bounds that spare passes.

use super::Engine;
use crate::contact::solver::tests::direction;
use proptest::prelude::*;

proptest! {
    /// After any sequence of changes, few or many, the set and the
    /// per-node views are those a pass over every node gives.
    #[test]
    fn a_change_of_set_gives_what_a_pass_over_every_node_gives(
        n in 1usize..70,
        steps in proptest::collection::vec(
            (proptest::collection::vec((any::<prop::sample::Index>(), direction()), 0..6),
             proptest::option::weighted(0.2, proptest::collection::vec(direction(), 70))),
            1..12,
        ),
    ) {
        let mut e = Engine::new(n);
        for (edits, whole) in steps {
            if let Some(whole) = whole {
                e.trial.copy_from_slice(&whole[..n]);
            }
            for (at, d) in edits {
                e.trial[at.index(n)] = d;
            }
            e.change_set_to_trial();
            let expected: Vec<(usize, f64)> = e
                .trial
                .iter()
                .enumerate()
                .filter(|(_, d)| d.is_slipping())
                .map(|(j, d)| (j, d.sign()))
                .collect();
            prop_assert_eq!(&e.set, &expected);
            prop_assert_eq!(&e.dirs, &e.trial);
            for (j, d) in e.trial.iter().enumerate() {
                let slips = d.is_slipping();
                prop_assert_eq!(e.stick[j], !slips);
                prop_assert_eq!(e.sgn[j], if slips { d.sign() } else { 0.0 });
                prop_assert_eq!(e.off[j], if slips { f64::INFINITY } else { 0.0 });
            }
        }
    }
}

/// Two back-and-forth cycles of a load that slips, at `N = 128`: the
/// second meets the sets of the first, and reads their kept responses
/// in place in the cache. A clone made there, and the contact after its
/// cache is taken and given back, hold the very responses the contact
/// read, in their own arrays (a clone's cache starts empty: read in
/// place, its responses would be out of bounds or another set's).
#[test]
fn responses_read_in_place_survive_a_clone_and_a_handed_cache() {
    use crate::model::{Discretisation, LoadPoint, Material};
    use crate::Contact;
    let own = |c: &Contact| -> Vec<Vec<f64>> {
        let e = &c.work.as_ref().expect("advanced").engine;
        e.responses().iter().map(|r| r.to_vec()).collect()
    };
    let disc = Discretisation::default();
    let mut c = Contact::new(Material::paper(), crate::stepping::operators(&disc));
    let mut lent_seen = 0;
    for i in 1..=800 {
        let t = i as f64 / 400.0 * 2.0 * std::f64::consts::PI;
        c.advance(LoadPoint::new(2.0 * t.sin(), 5.8 * t.sin()))
            .expect("advances");
        let lent = c.work.as_ref().expect("advanced").engine.lent;
        if i <= 400 || lent[0].is_none() {
            continue;
        }
        lent_seen += 1;
        let read = own(&c);
        let clone = c.clone();
        let ce = &clone.work.as_ref().expect("cloned").engine;
        assert_eq!(ce.lent, [None, None]);
        assert_eq!(own(&clone), read);
        let cache = c.take_response_cache().expect("a cache");
        assert_eq!(c.work.as_ref().expect("advanced").engine.lent, [None, None]);
        assert_eq!(own(&c), read);
        c.give_response_cache(cache);
    }
    assert!(lent_seen > 10, "{lent_seen} increments read a hit in place");
}

/// The bounds that spare an increment its passes over the rates and the
/// end margins change nothing: along cycles of several phases, from a
/// straight transient, with increments of several sizes and a
/// reversal, a contact that uses them and one that makes every pass
/// reach the same state, slip, events and dissipation, to the bit,
/// after every increment; and the bounds spare passes.
#[test]
fn bounds_that_spare_passes_change_no_bit() {
    use crate::model::{Discretisation, LoadPoint, Material};
    use crate::{Advanced, Contact};
    use std::f64::consts::PI;
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let disc = Discretisation::default();
    let ops = crate::stepping::operators(&disc);
    #[cfg(feature = "counters")]
    let mut spared = [0; 2];
    #[cfg(feature = "counters")]
    let mut increments = 0;
    for (phase, lambda, steps) in [
        (0.5, 5.5, 400),
        (0.25, 6.0, 160),
        (0.0, 5.0, 400),
        (0.375, 4.5, 1000),
    ] {
        let mut bounded = Contact::new(Material::paper(), ops.clone());
        let mut unbounded = bounded.clone();
        unbounded.unbounded = true;
        // A transient, two cycles round the ellipse of `phase`, then a
        // straight run out and back.
        let transient = (1..=50).map(|i| LoadPoint::new(-0.04 * i as f64, 0.04 * i as f64));
        let cycle = (1..=2 * steps).map(move |i| {
            let t = 2.0 * PI * i as f64 / steps as f64;
            LoadPoint::new(0.4 * lambda * (t - phase * PI).sin(), lambda * t.sin())
        });
        let end = LoadPoint::new(0.4 * lambda * (-phase * PI).sin(), 0.0);
        let out = (1..=100).map(move |i| end.lerp(LoadPoint::new(2.0, 5.5), i as f64 / 100.0));
        let back = (1..=100)
            .map(|i| LoadPoint::new(2.0, 5.5).lerp(LoadPoint::new(-1.0, -4.0), i as f64 / 100.0));
        for load in transient.chain(cycle).chain(out).chain(back) {
            let a = bounded.advance(load);
            let b = unbounded.advance(load);
            assert_eq!(a, b, "at {load:?}");
            #[cfg(feature = "counters")]
            {
                increments += 1;
            }
            let (ia, ib) = (bounded.last_increment(), unbounded.last_increment());
            assert_eq!(ia.dissipation.to_bits(), ib.dissipation.to_bits());
            assert_eq!(bits(&ia.forward), bits(&ib.forward));
            assert_eq!(bits(&ia.backward), bits(&ib.backward));
            assert_eq!(ia.events, ib.events);
            assert_eq!(bits(bounded.slip()), bits(unbounded.slip()));
            assert_eq!(bits(bounded.pressure()), bits(unbounded.pressure()));
            assert_eq!(bits(bounded.shear()), bits(unbounded.shear()));
            assert_eq!(bounded.directions(), unbounded.directions());
            if !matches!(a, Ok(Advanced::Reached)) {
                break;
            }
        }
        #[cfg(feature = "counters")]
        {
            let e = &bounded.work.as_ref().expect("advanced").engine;
            spared[0] += e.spared[0];
            spared[1] += e.spared[1];
            let u = &unbounded.work.as_ref().expect("advanced").engine;
            assert_eq!(u.spared, [0, 0]);
        }
    }
    // The end margins of most increments; the rates of a few (those
    // of straight runs whose set holds: along an ellipse the direction
    // turns too far between increments).
    // The bounds spare passes (counted with the `counters` feature).
    #[cfg(feature = "counters")]
    assert!(
        2 * spared[1] > increments && spared[0] > 20,
        "{spared:?} of {increments} increments' passes spared"
    );
}
