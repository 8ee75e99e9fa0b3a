//! The exact, event-driven increment (`Contact::advance`, issue 9): events
//! located to round-off, the cheap path equal to a full solve, and the
//! terminal events at the right instant.

use std::f64::consts::PI;
use std::sync::Arc;

use shakedown::contact::{ContactEventKind, Increment};
use shakedown::{
    Advanced, Contact, ContactEnd, Cycle, Discretisation, Event, Initial, LoadPoint, Material,
    Operators, Plane, SteadyState, StepOptions, StepReport, Stepper,
};

fn contact(n: usize) -> Contact {
    Contact::new(Material::paper(), Arc::new(Operators::new(n)))
}

/// The load parameter `r` at which a node first reaches `|q| = f p` on the
/// ray `r (dx, dy)` from the unloaded state, from the elastic tractions of
/// model.md section 2 written out here independently of the solver.
fn first_entry(m: &Material, n: usize, dx: f64, dy: f64) -> f64 {
    let (f, a, b) = (m.friction(), m.alpha(), m.beta());
    // Pt = f x / chi, Tt = f y.
    let mut best = f64::INFINITY;
    for j in 0..n {
        let th = 2.0 * PI * j as f64 / n as f64;
        // Per unit r: q = -(f dy + a Pt' cos)/(2 pi), f p = f - f b Pt' sin/(2 pi).
        let pt = f * dx / m.chi();
        let q1 = -(f * dy + a * pt * th.cos()) / (2.0 * PI);
        let fp1 = -f * b * pt * th.sin() / (2.0 * PI);
        for sigma in [1.0, -1.0] {
            // sigma q = f p: r (sigma q1 - fp1) = f.
            let rate = sigma * q1 - fp1;
            if rate > 0.0 {
                best = best.min(f / rate);
            }
        }
    }
    best
}

fn first_event(inc: &Increment, kind: ContactEventKind) -> Option<(f64, LoadPoint, Vec<usize>)> {
    inc.events
        .iter()
        .find(|e| e.kind == kind)
        .map(|e| (e.fraction, e.load, e.nodes.clone()))
}

#[test]
fn entry_into_slip_is_located_to_round_off_on_the_diamond() {
    let m = Material::paper();
    let n = 128;
    for k in 0..12 {
        let angle = 2.0 * PI * (k as f64 + 0.37) / 12.0;
        let (dx, dy) = (angle.cos(), angle.sin());
        let r = first_entry(&m, n, dx, dy);
        // The discrete onset lies on or just outside the diamond
        // |x| + |y| = 2 pi, by at most the node spacing (exactly on it where
        // a node sits at the critical angle).
        let diamond = 2.0 * PI / (dx.abs() + dy.abs());
        assert!(r >= diamond * (1.0 - 1e-12), "{r} vs {diamond}");
        assert!(
            r * (2.0 * PI / n as f64).cos() <= diamond,
            "{r} vs {diamond}"
        );
        // One increment from the origin to well past the onset.
        let mut c = contact(n);
        let to = LoadPoint::new(1.3 * r * dx, 1.3 * r * dy);
        if to.y().abs() >= 2.0 * PI {
            continue;
        }
        assert_eq!(c.advance(to), Ok(Advanced::Reached));
        let (fraction, load, nodes) =
            first_event(c.last_increment(), ContactEventKind::SlipEntry).expect("slip entry");
        assert!(!nodes.is_empty());
        assert!(
            (fraction * 1.3 - 1.0).abs() < 1e-12,
            "entry at fraction {fraction}, expected {}",
            1.0 / 1.3
        );
        assert!((load.x() - r * dx).abs() < 1e-12 && (load.y() - r * dy).abs() < 1e-12);
    }
}

#[test]
fn entry_exactly_on_the_diamond_where_a_node_sits_at_the_critical_angle() {
    // Pure radial load: x cos(theta - theta*) = 2 pi with theta* the angle
    // of alpha cos + f beta sin. For f -> 0 (alpha only) theta* = 0, a node.
    let m = Material::new(1e-9, 0.3, Plane::Strain).unwrap();
    let mut c = Contact::new(m, Arc::new(Operators::new(64)));
    assert_eq!(c.advance(LoadPoint::new(-9.0, 0.0)), Ok(Advanced::Reached));
    let (_, load, nodes) =
        first_event(c.last_increment(), ContactEventKind::SlipEntry).expect("slip entry");
    // theta = 0 and pi, on either side of the friction cone.
    assert_eq!(nodes, vec![0, 32]);
    assert!(
        (load.x().abs() + load.y().abs() - 2.0 * PI).abs() < 1e-8,
        "{load}"
    );
}

#[test]
fn gross_slip_is_at_the_torque_limit_exactly() {
    for (x, y) in [(0.0, 9.0), (1.5, 7.0), (-2.0, -8.0)] {
        let mut c = contact(64);
        let to = LoadPoint::new(x, y);
        match c.advance(to) {
            Ok(Advanced::Ended(ContactEnd::GrossSlip { load })) => {
                assert!(load.y().abs() > 2.0 * PI, "{load}");
                assert!(load.y().abs() - 2.0 * PI < 1e-14, "{load}");
                // On the segment from the origin.
                let r = 2.0 * PI / y.abs();
                assert!((load.x() - r * x).abs() < 1e-12, "{load}");
                assert!((c.last_increment().reached - r).abs() < 1e-12);
                // The state there still obeys the friction law.
                let f = c.material().friction();
                for j in 0..64 {
                    assert!(c.shear()[j].abs() <= f * c.pressure()[j] * (1.0 + 1e-9) + 1e-12);
                }
            }
            other => panic!("expected gross slip, got {other:?}"),
        }
    }
}

/// A contact with a partial slip zone, reached along a straight path.
fn partially_slipping(n: usize) -> Contact {
    let mut c = contact(n);
    assert_eq!(c.advance(LoadPoint::new(2.0, 5.0)), Ok(Advanced::Reached));
    let slipping = c.directions().iter().filter(|d| d.is_slipping()).count();
    assert!(slipping > 4 && slipping < n, "{slipping}");
    c
}

#[test]
fn the_cheap_path_equals_a_full_solve() {
    let n = 128;
    let c = partially_slipping(n);
    // Small steps in a few directions: where the set does not change, the
    // O(N) path and the finite-step active-set solve agree to round-off.
    let mut compared = 0;
    for (dx, dy) in [(0.0, 1e-3), (1e-3, 1e-3), (-1e-3, 5e-4), (0.0, -1e-3)] {
        let to = LoadPoint::new(c.load().x() + dx, c.load().y() + dy);
        let mut fast = c.clone();
        assert_eq!(fast.advance(to), Ok(Advanced::Reached));
        let inc = fast.last_increment();
        if !inc.events.is_empty() || inc.segments != 1 {
            continue;
        }
        compared += 1;
        let mut full = c.clone();
        let trial = full.solve(to).unwrap().trial().expect("no physical end");
        let dissipation = trial.dissipation;
        full.commit(trial);
        for j in 0..n {
            assert!((fast.slip()[j] - full.slip()[j]).abs() < 1e-13, "g at {j}");
            assert!((fast.pressure()[j] - full.pressure()[j]).abs() < 1e-12);
            assert!((fast.shear()[j] - full.shear()[j]).abs() < 1e-12);
        }
        assert!(
            (inc.dissipation - dissipation).abs() <= 1e-9 * dissipation,
            "{} vs {dissipation}",
            inc.dissipation
        );
    }
    assert!(compared >= 2, "only {compared} steps without an event");
}

#[test]
fn an_event_does_not_depend_on_how_the_segment_is_cut() {
    // Unload part of the way after a partial slip: the slip zone sticks
    // (advancing stick) and the other side may enter. Walking the segment
    // in one call or in two must give the same events and end state.
    let n = 128;
    let c = partially_slipping(n);
    let to = LoadPoint::new(2.6, 4.3);
    let mut one = c.clone();
    assert_eq!(one.advance(to), Ok(Advanced::Reached));
    let events = one.last_increment().events.clone();
    assert!(!events.is_empty(), "the turn must cause an event");
    let stick = events
        .iter()
        .find(|e| e.kind == ContactEventKind::AdvancingStick)
        .expect("advancing stick at the turn");
    assert_eq!(stick.fraction, 0.0, "stick at the turning point");
    // An entry strictly inside the segment, cut at an arbitrary point.
    for cut in [0.3, 0.71] {
        let mid = c.load().lerp(to, cut);
        let mut two = c.clone();
        assert_eq!(two.advance(mid), Ok(Advanced::Reached));
        let mut found: Vec<(LoadPoint, Vec<usize>)> = two
            .last_increment()
            .events
            .iter()
            .filter(|e| e.fraction > 0.0)
            .map(|e| (e.load, e.nodes.clone()))
            .collect();
        assert_eq!(two.advance(to), Ok(Advanced::Reached));
        found.extend(
            two.last_increment()
                .events
                .iter()
                .filter(|e| e.fraction > 0.0)
                .map(|e| (e.load, e.nodes.clone())),
        );
        let inside: Vec<_> = events.iter().filter(|e| e.fraction > 0.0).collect();
        assert_eq!(inside.len(), found.len(), "cut at {cut}");
        for (e, (load, nodes)) in inside.iter().zip(&found) {
            assert_eq!(&e.nodes, nodes);
            assert!(e.load.distance(*load) < 1e-12, "{} vs {load}", e.load);
        }
        for j in 0..n {
            assert!((one.slip()[j] - two.slip()[j]).abs() < 1e-12);
            assert!((one.shear()[j] - two.shear()[j]).abs() < 1e-12);
        }
    }
}

#[test]
fn advancing_stick_is_where_the_slip_rate_vanishes() {
    // At the advancing-stick point the stuck nodes have slipped up to it
    // and a tiny further step of the finite-step solver moves them no more.
    let n = 128;
    let c = partially_slipping(n);
    let to = LoadPoint::new(2.6, 4.3);
    let mut one = c.clone();
    assert_eq!(one.advance(to), Ok(Advanced::Reached));
    let ev = one
        .last_increment()
        .events
        .iter()
        .find(|e| e.kind == ContactEventKind::AdvancingStick)
        .cloned()
        .unwrap();
    let mut at = c.clone();
    assert_eq!(at.advance(ev.load), Ok(Advanced::Reached));
    let step = c.load().lerp(to, 1e-6);
    let dir = LoadPoint::new(step.x() - c.load().x(), step.y() - c.load().y());
    let beyond = LoadPoint::new(ev.load.x() + dir.x(), ev.load.y() + dir.y());
    let trial = at
        .clone()
        .solve(beyond)
        .unwrap()
        .trial()
        .expect("no physical end");
    for &j in &ev.nodes {
        assert_eq!(trial.slip_increment[j], 0.0, "node {j} still slips");
    }
}

#[test]
fn straight_cycles_do_not_depend_on_the_increment_count() {
    // phi = 0: the load moves on a straight line, so the exact increment
    // has no time-discretisation error at all.
    let run = |steps| {
        let mut s = Stepper::new(
            Material::paper(),
            Discretisation::new(64, steps).unwrap(),
            &Initial::Direct,
            Cycle::paper(5.5, 0.0).unwrap(),
            StepOptions::default(),
        );
        s.run_to_steady().unwrap()
    };
    let (a, b) = (run(100), run(700));
    assert_eq!(a.state(), b.state());
    assert!(
        (a.dissipation - b.dissipation).abs() < 1e-9 * a.dissipation,
        "{} vs {}",
        a.dissipation,
        b.dissipation
    );
}

#[test]
fn just_below_the_torque_limit_is_not_gross_slip() {
    // The cycle's highest y is 2 pi - 1.6e-5.
    let cycle = Cycle::paper(7.4094, 0.0).unwrap();
    let top = (0..100_000)
        .map(|i| cycle.at(2.0 * PI * i as f64 / 100_000.0).y())
        .fold(f64::MIN, f64::max);
    assert!(top < 2.0 * PI && top > 2.0 * PI - 1e-4, "{top}");
    let mut s = Stepper::new(
        Material::paper(),
        Discretisation::new(64, 200).unwrap(),
        &Initial::Direct,
        cycle,
        StepOptions::default(),
    );
    let summary = s.run_to_steady().unwrap();
    assert_ne!(summary.state(), SteadyState::GrossSlip, "{summary:?}");
    // Just above it, gross slip at |y| = 2 pi.
    let mut s = Stepper::new(
        Material::paper(),
        Discretisation::new(64, 200).unwrap(),
        &Initial::Direct,
        Cycle::paper(7.42, 0.0).unwrap(),
        StepOptions::default(),
    );
    let summary = s.run_to_steady().unwrap();
    assert_eq!(summary.state(), SteadyState::GrossSlip);
    let load = summary.terminal_load().unwrap();
    assert!((load.y() - 2.0 * PI).abs() < 1e-14, "{load}");
}

#[test]
fn terminal_time_and_load_are_the_same_instant() {
    let m = Material::new(0.2, 0.3, Plane::Strain).unwrap();
    let steps = 400;
    let cycle = Cycle::paper(5.0, 0.0).unwrap();
    let mut s = Stepper::new(
        m,
        Discretisation::new(128, steps).unwrap(),
        &Initial::Direct,
        cycle.clone(),
        StepOptions::default(),
    );
    let summary = s.run_to_steady().unwrap();
    assert_eq!(summary.state(), SteadyState::Separation);
    let (t, load) = (
        summary.terminal_time().unwrap(),
        summary.terminal_load().unwrap(),
    );
    // The load point lies on the chord of the increment containing t, at
    // the fraction of t within it.
    let u = t * steps as f64 / (2.0 * PI);
    let k = u.floor();
    let (a, b) = (
        cycle.at(2.0 * PI * k / steps as f64),
        cycle.at(2.0 * PI * (k + 1.0) / steps as f64),
    );
    let on_chord = a.lerp(b, u - k);
    assert!(on_chord.distance(load) < 1e-9, "{on_chord} vs {load}");
    // And the pressure vanishes there.
    let p_min = s
        .contact()
        .pressure()
        .iter()
        .copied()
        .fold(f64::MAX, f64::min);
    assert!(p_min.abs() < 1e-12, "p = {p_min}");
}

#[test]
fn dissipation_is_half_q_dot_dg() {
    // On a sub-segment q = s f p on the slip nodes and both vary linearly,
    // so 1/2 int q dg (trapezoid of q) is f/2 int p |dg|.
    let n = 128;
    let mut d = partially_slipping(n);
    let dtheta = 2.0 * PI / n as f64;
    let mut checked = 0;
    for i in 1..=200 {
        let to = LoadPoint::new(2.0 + 0.002 * i as f64, 5.0 + 0.001 * i as f64);
        let q0 = d.shear().to_vec();
        let g0 = d.slip().to_vec();
        assert_eq!(d.advance(to), Ok(Advanced::Reached));
        let inc = d.last_increment();
        if inc.segments != 1 || !inc.slipped {
            continue;
        }
        checked += 1;
        let w: f64 = (0..n)
            .map(|j| 0.5 * 0.5 * (q0[j] + d.shear()[j]) * (d.slip()[j] - g0[j]))
            .sum::<f64>()
            * dtheta;
        assert!(w > 0.0);
        assert!(
            (w - inc.dissipation).abs() < 1e-9 * w,
            "{w} vs {}",
            inc.dissipation
        );
    }
    assert!(checked > 20, "{checked}");
}

#[test]
fn pausing_at_events_stops_at_each_event_and_changes_nothing() {
    // The explorer pauses at events: the contact stops at each event's
    // load point, and going on reaches the same state as one call.
    let n = 128;
    let c = partially_slipping(n);
    // Unload the torque through zero and beyond: the slip zone sticks at
    // the turn and reverse slip enters node by node.
    let to = LoadPoint::new(2.0, -5.0);
    let mut one = c.clone();
    assert_eq!(one.advance(to), Ok(Advanced::Reached));
    let events = one.last_increment().events.clone();
    assert!(events.len() >= 3, "{events:?}");
    let mut paused = c.clone();
    paused.set_pause_at_events(true);
    let mut seen = Vec::new();
    for _ in 0..=4 * n {
        let r = paused.advance(to);
        let inc = paused.last_increment();
        if let Some(last) = inc.events.last() {
            if r == Ok(Advanced::Paused) {
                // Stopped exactly where the event is.
                assert_eq!(paused.load(), last.load, "{last:?}");
            }
        }
        seen.extend(inc.events.iter().map(|e| (e.kind, e.load, e.nodes.clone())));
        if r == Ok(Advanced::Reached) {
            break;
        }
        assert_eq!(r, Ok(Advanced::Paused));
    }
    assert_eq!(paused.load(), to);
    assert_eq!(seen.len(), events.len());
    for (e, (kind, load, nodes)) in events.iter().zip(&seen) {
        assert_eq!((e.kind, &e.nodes), (*kind, nodes));
        assert!(e.load.distance(*load) < 1e-12, "{} vs {load}", e.load);
    }
    for j in 0..n {
        assert!((one.slip()[j] - paused.slip()[j]).abs() < 1e-12);
        assert!((one.pressure()[j] - paused.pressure()[j]).abs() < 1e-12);
        assert!((one.shear()[j] - paused.shear()[j]).abs() < 1e-12);
    }
}

#[test]
fn a_stepper_paused_at_events_reaches_the_same_steady_state() {
    let run = |pause: bool| {
        let mut s = Stepper::new(
            Material::paper(),
            Discretisation::new(64, 200).unwrap(),
            &Initial::Direct,
            Cycle::paper(5.5, 0.5 * PI).unwrap(),
            StepOptions::default(),
        );
        s.set_pause_at_events(pause);
        let (mut partial, mut whole) = (0, 0);
        while !s.is_finished() && matches!(s.status(), shakedown::Status::Running) {
            let report = s.step().unwrap();
            match report.partial {
                Some(at) => {
                    partial += 1;
                    assert!((0.0..=1.0).contains(&at), "{at}");
                    assert!(s.is_inside_increment());
                    // The stepper's time and the contact's load are those
                    // of the last event.
                    let last = report.events.iter().rev().find_map(|e| match e {
                        shakedown::stepping::Event::AdvancingStick { time, load, .. }
                        | shakedown::stepping::Event::SlipEntry { time, load, .. } => {
                            Some((*time, *load))
                        }
                        _ => None,
                    });
                    let (time, load) = last.expect("a pause is at an event");
                    assert_eq!(s.contact().load(), load);
                    assert_eq!(s.time(), time);
                }
                None => whole += 1,
            }
        }
        (
            s.outcome().cloned().unwrap(),
            partial,
            whole,
            s.increments(),
        )
    };
    let (plain, p0, w0, i0) = run(false);
    let (paused, p1, w1, i1) = run(true);
    assert_eq!(p0, 0);
    assert!(p1 > 0, "no pause at all");
    assert_eq!((w0, i0), (w1, i1), "the same increments");
    assert_eq!(plain.state(), paused.state());
    assert_eq!(plain.cycles, paused.cycles);
    let rel = (plain.dissipation - paused.dissipation).abs() / plain.dissipation;
    assert!(
        rel < 1e-9,
        "W {} vs {}",
        plain.dissipation,
        paused.dissipation
    );
}

/// `Stepper::step_into` with one report handed back each time (as the
/// driver does, reusing its buffers) reports exactly what `step` reports
/// with a fresh one, events and their nodes included, step by step.
#[test]
fn a_reused_report_says_what_a_fresh_one_says() {
    let stepper = || {
        Stepper::new(
            Material::paper(),
            Discretisation::new(64, 200).unwrap(),
            &Initial::Direct,
            Cycle::paper(5.5, 0.5 * PI).unwrap(),
            StepOptions::default(),
        )
    };
    let (mut fresh, mut reused) = (stepper(), stepper());
    let mut report = shakedown::StepReport::default();
    let (mut steps, mut with_nodes) = (0, 0);
    while !fresh.is_finished() && matches!(fresh.status(), shakedown::Status::Running) {
        let expected = fresh.step().unwrap();
        reused.step_into(&mut report).unwrap();
        assert_eq!(report, expected, "step {steps}");
        with_nodes += usize::from(expected.events.iter().any(|e| {
            matches!(
                e,
                shakedown::stepping::Event::AdvancingStick { .. }
                    | shakedown::stepping::Event::SlipEntry { .. }
            )
        }));
        steps += 1;
    }
    assert_eq!(reused.outcome(), fresh.outcome());
    // The comparison covered reports whose events carry node lists.
    assert!(with_nodes > 10, "{with_nodes} steps with slip events");
}

/// Every step of a run to its steady state, with straight runs taken at
/// once or not: the summary, the increments and the events (kind, nodes,
/// `omega t`, load point) in order, and the steps taken.
#[allow(clippy::type_complexity)]
fn stepped(
    cycle: Cycle,
    steps: usize,
    straight: bool,
) -> (
    shakedown::Outcome,
    usize,
    Vec<(bool, Vec<usize>, Option<f64>, LoadPoint)>,
    usize,
) {
    use shakedown::stepping::{drive, Control, Goal};
    let mut s = Stepper::new(
        Material::paper(),
        Discretisation::new(64, steps).unwrap(),
        &Initial::Direct,
        cycle,
        StepOptions::default(),
    );
    s.set_straight_runs(straight);
    let mut events = Vec::new();
    let mut taken = 0;
    drive(&mut s, Goal::Steady, &mut |_: &Stepper, r: &StepReport| {
        taken += 1;
        for e in &r.events {
            match e {
                Event::AdvancingStick {
                    nodes, time, load, ..
                } => events.push((true, nodes.clone(), *time, *load)),
                Event::SlipEntry { nodes, time, load } => {
                    events.push((false, nodes.clone(), *time, *load))
                }
                _ => {}
            }
        }
        Control::Continue
    })
    .unwrap();
    (s.outcome().cloned().unwrap(), s.increments(), events, taken)
}

/// The same events, in the same order, at the same instant and load point
/// (to round-off).
fn same_events(
    e1: &[(bool, Vec<usize>, Option<f64>, LoadPoint)],
    e2: &[(bool, Vec<usize>, Option<f64>, LoadPoint)],
) {
    assert_eq!(e1.len(), e2.len());
    for (a, b) in e1.iter().zip(e2) {
        assert_eq!((a.0, &a.1), (b.0, &b.1), "{a:?} vs {b:?}");
        match (a.2, b.2) {
            (Some(ta), Some(tb)) => assert!((ta - tb).abs() < 1e-9, "{a:?} vs {b:?}"),
            (ta, tb) => assert_eq!(ta, tb),
        }
        assert!(a.3.distance(b.3) < 1e-9, "{a:?} vs {b:?}");
    }
}

#[test]
fn a_straight_run_of_increments_taken_at_once_meets_the_same_events() {
    // phi = 0: each half cycle is one straight run, the transient's
    // segments are straight, and a step takes each whole.
    let cycle = Cycle::paper(5.5, 0.0).unwrap();
    let (one, i1, e1, steps1) = stepped(cycle.clone(), 200, false);
    let (run, i2, e2, steps2) = stepped(cycle, 200, true);
    assert_eq!(one.state(), SteadyState::CyclicSlip);
    assert_eq!((one.state(), one.cycles), (run.state(), run.cycles));
    assert_eq!(i1, i2, "the same increments");
    let rel = (one.dissipation - run.dissipation).abs() / one.dissipation;
    assert!(rel < 1e-9, "W {} vs {}", one.dissipation, run.dissipation);
    assert!(e1.len() > 100, "{}", e1.len());
    same_events(&e1, &e2);
    // Three steps a cycle (out, back through the centre, back to it).
    assert_eq!(steps1, i1);
    assert!(steps2 <= 3 * run.cycles + 10, "{steps2} steps");
}

#[test]
fn only_straight_runs_are_taken_at_once() {
    // An odd increment count: the turning points fall between vertices,
    // and the two vertices beside each lie on the line to round-off.
    let cycle = Cycle::paper(5.5, 0.0).unwrap();
    let (one, i1, e1, _) = stepped(cycle.clone(), 201, false);
    let (run, i2, e2, steps2) = stepped(cycle, 201, true);
    assert_eq!((one.state(), one.cycles, i1), (run.state(), run.cycles, i2));
    same_events(&e1, &e2);
    assert!(steps2 <= 4 * run.cycles + 10, "{steps2} steps");
    // An ellipse (phi = pi/2) has no two chords in line: one increment a
    // step, exactly as without straight runs.
    let cycle = Cycle::paper(5.5, 0.5 * PI).unwrap();
    let (one, i1, e1, steps1) = stepped(cycle.clone(), 200, false);
    let (run, i2, e2, steps2) = stepped(cycle, 200, true);
    assert_eq!((one.state(), one.cycles, i1), (run.state(), run.cycles, i2));
    let rel = (one.dissipation - run.dissipation).abs() / one.dissipation;
    assert!(rel < 1e-9, "W {} vs {}", one.dissipation, run.dissipation);
    same_events(&e1, &e2);
    // The transient's segments are still taken whole.
    assert!(steps2 < steps1, "{steps2} vs {steps1}");
    assert!(steps2 >= run.cycles * 200, "{steps2}");
}

/// The load path of a random property case that used to end in a false
/// gross slip: `f = 0.0714`, `nu = 0`, `N = 32`, out to `x = 0.62 x_sep`
/// and then across towards `x = -1.05 x_sep` at `y ~ 0.5`. With `nu = 0`
/// the radial shear `alpha P cos(theta) / (2 pi)` passes `f p` at every
/// node but those near `theta = pi/2`, so all nodes but one slip, in two
/// zones of opposite sign, before the disc separates at `theta = 3 pi/2`.
fn every_node_but_one_path(m: &Material) -> [LoadPoint; 2] {
    let x_sep = 2.0 * PI * m.chi() / (m.friction() * m.beta());
    [
        LoadPoint::new(
            0.687_155_809_855_606_9 * 0.9 * x_sep,
            0.557_061_705_097_542_6,
        ),
        LoadPoint::new(-1.05 * x_sep, 0.482_346_524_908_109_3),
    ]
}

/// The contact after `steps` increments along each leg of `path` (or at
/// its end, if one comes first), with every event of the way.
fn walk_exactly(
    m: Material,
    n: usize,
    path: &[LoadPoint],
    steps: usize,
) -> (
    Contact,
    Vec<shakedown::contact::ContactEvent>,
    Option<ContactEnd>,
) {
    let mut c = Contact::new(m, Arc::new(Operators::new(n)));
    let mut events = Vec::new();
    let mut from = LoadPoint::ORIGIN;
    for &to in path {
        for i in 1..=steps {
            let at = from.lerp(to, i as f64 / steps as f64);
            let done = c
                .advance(at)
                .unwrap_or_else(|e| panic!("{e} on the way to {at}"));
            events.extend(c.last_increment().events.iter().cloned());
            match done {
                Advanced::Reached => {}
                Advanced::Ended(end) => return (c, events, Some(end)),
                other => panic!("{other:?} at {at}"),
            }
        }
        from = to;
    }
    (c, events, None)
}

/// Where the last stick node reaches the limit beside a zone slipping the
/// other way, not every node can slip off the torque limit (the slip rates
/// of all `N` nodes are fixed only up to a rigid rotation, so the set's
/// equations have no solution): its neighbour on the other side sticks
/// instead, at the same instant, and the stick node moves over by one
/// (model.md section 3.2). Both solvers go on past it, obeying the friction
/// law, to the separation at `theta = 3 pi/2`; the exact one reports each
/// move as an entry and an advancing stick of neighbouring nodes at one
/// load point, and separates at the same point however the path is cut.
#[test]
fn the_last_stick_node_moves_over_where_every_other_node_slips() {
    let m = Material::new(0.071_361_574_552_635_32, 0.0, Plane::Strain).unwrap();
    let (n, f) = (32, m.friction());
    let path = every_node_but_one_path(&m);
    let (c, events, end) = walk_exactly(m, n, &path, 500);
    let mut moves = 0;
    for pair in events.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a.kind == ContactEventKind::AdvancingStick
            && b.kind == ContactEventKind::SlipEntry
            && a.load == b.load
            && a.nodes.len() == 1
            && b.nodes.len() == 1
        {
            let (stuck, entered) = (a.nodes[0], b.nodes[0]);
            if (stuck + 1) % n == entered || (entered + 1) % n == stuck {
                moves += 1;
            }
        }
    }
    assert!(moves >= 1, "no move of the stick node in {events:?}");
    let sticking = (0..n).filter(|&j| !c.directions()[j].is_slipping()).count();
    assert_eq!(sticking, 1, "{:?}", c.directions());
    let (p, q) = (c.pressure(), c.shear());
    for j in 0..n {
        assert!(
            q[j].abs() <= f * p[j].max(0.0) * (1.0 + 1e-9) + 1e-12,
            "node {j}"
        );
    }
    let torque = m.to_loads(c.load()).torque;
    let mean_q = q.iter().sum::<f64>() / n as f64;
    assert!((mean_q + torque / (2.0 * PI)).abs() < 1e-10);
    let Some(ContactEnd::Separation {
        load,
        node,
        pressure,
        ..
    }) = end
    else {
        panic!("{end:?}");
    };
    assert_eq!(node, 3 * n / 4);
    assert!(pressure.abs() < 1e-12, "{pressure}");
    // Cut twice as fine, the exact increment meets the same events.
    let (fine, _, fine_end) = walk_exactly(m, n, &path, 1000);
    let Some(ContactEnd::Separation {
        load: fine_load,
        node: fine_node,
        ..
    }) = fine_end
    else {
        panic!("{fine_end:?}");
    };
    assert_eq!(fine_node, node);
    assert!(fine_load.distance(load) < 1e-9, "{fine_load} {load}");
    for j in 0..n {
        assert!((fine.slip()[j] - c.slip()[j]).abs() < 1e-9, "node {j}");
    }
    assert_eq!(fine.directions(), c.directions());
    // The finite-step solver, increment by increment, goes past the moves
    // too, and separates within a step of the same point.
    let mut finite = Contact::new(m, Arc::new(Operators::new(n)));
    let mut from = LoadPoint::ORIGIN;
    let mut finite_end = None;
    'path: for &to in &path {
        for i in 1..=500 {
            let at = from.lerp(to, i as f64 / 500.0);
            match finite.solve(at) {
                Ok(shakedown::contact::Solved::Trial(t)) => {
                    for j in 0..n {
                        assert!(t.shear[j].abs() <= f * t.pressure[j] * (1.0 + 1e-9) + 1e-12);
                    }
                    finite.commit(t)
                }
                Ok(shakedown::contact::Solved::Ended(end)) => {
                    finite_end = Some(end);
                    break 'path;
                }
                Err(e) => panic!("{e} at {at}"),
            }
        }
        from = to;
    }
    let step = path[0].distance(path[1]) / 500.0;
    match finite_end {
        Some(ContactEnd::Separation {
            load: at, node: j, ..
        }) => {
            assert_eq!(j, node);
            assert!(at.distance(load) <= 1.01 * step, "{at} {load}");
        }
        other => panic!("{other:?}"),
    }
}
