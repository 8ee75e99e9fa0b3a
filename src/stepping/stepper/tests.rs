//! Tests of the stepper's straight runs.

use super::*;

fn stepper() -> Stepper {
    Stepper::new(
        Material::paper(),
        Discretisation::new(64, 200).unwrap(),
        &Initial::Direct,
        Cycle::paper(5.5, 0.0).unwrap(),
        StepOptions::default(),
    )
}

/// The events' `omega t` and load points, in order.
fn events(r: &StepReport, into: &mut Vec<(Option<f64>, LoadPoint)>) {
    for e in &r.events {
        if let Event::AdvancingStick { time, load, .. } | Event::SlipEntry { time, load, .. } = e {
            into.push((*time, *load));
        }
    }
}

#[test]
fn a_straight_run_that_does_not_settle_goes_on_one_increment_at_a_time() {
    let mut plain = stepper();
    let mut e1 = Vec::new();
    drive(
        &mut plain,
        Goal::Steady,
        &mut |_: &Stepper, r: &StepReport| {
            events(r, &mut e1);
            Control::Continue
        },
    )
    .unwrap();
    let a = plain.outcome().cloned().unwrap();
    // Each straight run gives up at its first event: the stepper takes
    // the rest of it one increment at a time, from that event.
    let mut refused = stepper();
    refused.contact.refuse_runs = true;
    refused.set_straight_runs(true);
    let (mut inside, mut steps, mut e2) = (0, 0, Vec::new());
    drive(
        &mut refused,
        Goal::Steady,
        &mut |s: &Stepper, r: &StepReport| {
            steps += 1;
            inside += usize::from(s.is_inside_increment());
            events(r, &mut e2);
            Control::Continue
        },
    )
    .unwrap();
    let b = refused.outcome().cloned().unwrap();
    assert!(
        inside > 10,
        "{inside} of {steps} steps stopped inside an increment"
    );
    assert!(steps < refused.increments(), "{steps} steps");
    assert_eq!((a.state(), a.cycles), (b.state(), b.cycles));
    assert_eq!(plain.increments(), refused.increments());
    let rel = (a.dissipation - b.dissipation).abs() / a.dissipation;
    assert!(rel < 1e-9, "W {} vs {}", a.dissipation, b.dissipation);
    // The same events at the same instants and load points.
    assert_eq!(e1.len(), e2.len());
    for ((t1, l1), (t2, l2)) in e1.iter().zip(&e2) {
        if let (Some(t1), Some(t2)) = (t1, t2) {
            assert!((t1 - t2).abs() < 1e-9, "{t1} vs {t2}");
        }
        assert!(l1.distance(*l2) < 1e-9, "{l1} vs {l2}");
    }
}
