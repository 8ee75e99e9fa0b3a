//! `W` at its level (`docs/model.md` section 6.1): the stopping rule does
//! not stop where `W` turns, the level reported beside the last cycle's `W`
//! is that of the same run taken on to round-off, and the `not-converged`
//! interval holds the level whether `W` rises or falls to it. Every
//! reference level is computed here, by running the same case on.

use std::f64::consts::PI;

use shakedown::analysis::case::{Case, CaseParams};
use shakedown::stepping::StepOptions;
use shakedown::{Outcome, SteadyState, Verdict};

fn case(load_factor: f64, phase: f64, initial: &str, poisson: f64) -> Case {
    Case::from_params(&CaseParams {
        load_factor,
        phase,
        initial: shakedown::model::path::Initial::parse(initial).unwrap(),
        poisson,
        ..CaseParams::default()
    })
    .unwrap()
}

/// The run at the defaults, with the cycle cap `max_cycles`.
fn run(case: &Case, max_cycles: usize) -> Outcome {
    let options = case.options().to_builder().max_cycles(max_cycles);
    let case = case.clone().with_options(options.build().unwrap());
    case.stepper().run_to_steady().unwrap()
}

/// The same case run on until `W` changes by less than `1e-10` over three
/// cycles: its last `W` (the level to about `1e-9`) and every cycle's `W`.
fn run_out(case: &Case) -> (f64, Vec<f64>) {
    let options = StepOptions::builder()
        .tolerance(1e-10)
        .max_cycles(5000)
        .safe_state(false);
    let case = case.clone().with_options(options.build().unwrap());
    let mut stepper = case.stepper();
    let outcome = stepper.run_to_steady().unwrap();
    assert_ne!(outcome.state(), SteadyState::NotConverged, "{outcome:?}");
    let w: Vec<f64> = stepper.history().iter().map(|r| r.dissipation).collect();
    (*w.last().unwrap(), w)
}

#[test]
fn a_turning_point_of_w_is_not_its_level() {
    // The case: W falls to a minimum and rises on to a level
    // 0.11 % above the W of the cycle where the 0.01 % rule first holds.
    let case = case(5.728, 0.8952 * PI, "-5,7", 0.2);
    let (level, w) = run_out(&case);
    let minimum = (1..w.len() - 1)
        .find(|&k| w[k] < w[k - 1] && w[k] <= w[k + 1])
        .expect("W turns");
    assert!(w[minimum] < level * (1.0 - 5e-4), "{} {level}", w[minimum]);

    let s = run(&case, 2000);
    assert_eq!(s.verdict, Verdict::CyclicSlip, "{s:?}");
    assert!(
        s.cycles > minimum + 1,
        "stopped at {} by the minimum at {}",
        s.cycles,
        minimum + 1
    );
    let l = s.level.expect("cyclic slip has a level");
    assert!(
        (l.value / level - 1.0).abs() < 5e-4,
        "{l:?} against {level}"
    );
    assert!(
        (l.value - level).abs() <= l.uncertainty,
        "{l:?} against {level}"
    );
    // The steady rotation of cyclic slip is 0; the last cycle still drifts.
    let r = s
        .steady_rotation
        .expect("cyclic slip has a steady rotation");
    assert_eq!(r.value, 0.0);
    assert_eq!(s.rotation_drift(), Some(s.rotation_per_cycle));
}

#[test]
fn a_level_approached_slowly_is_extrapolated() {
    // fig6 at phi = pi/6 from 3,7: the changes of W shrink by about 0.96 a
    // cycle, and the last W under the 0.01 % rule sits about 0.1 % above
    // the level.
    let case = case(5.1, PI / 6.0, "3,7", 0.3);
    let (level, _) = run_out(&case);
    let s = run(&case, 2000);
    assert_eq!(s.state(), SteadyState::CyclicSlip, "{s:?}");
    let l = s.level.expect("cyclic slip has a level");
    assert!(
        (l.value / level - 1.0).abs() < 5e-4,
        "{l:?} against {level}"
    );
    assert!(
        (l.value - level).abs() <= l.uncertainty,
        "{l:?} against {level}"
    );
}

#[test]
fn ratchetting_has_its_steady_rotation() {
    // W falls to 1.1e-5 and levels off at 7.49e-6, turning by -2.6e-5 a
    // cycle.
    let case = case(5.1, 0.375 * PI, "-5,5", 0.3);
    let options = case
        .options()
        .to_builder()
        .tolerance(1e-10)
        .max_cycles(5000);
    let out = case.clone().with_options(options.build().unwrap());
    let mut stepper = out.stepper();
    stepper.run_to_steady().unwrap();
    let rotation = stepper.history().last().unwrap().rotation;
    let level = stepper.history().last().unwrap().dissipation;
    let s = run(&case, 2000);
    assert_eq!(s.state(), SteadyState::RatchettingMonotonic, "{s:?}");
    let l = s.level.expect("ratchetting has a level");
    assert!(
        (l.value - level).abs() <= l.uncertainty,
        "{l:?} against {level}"
    );
    let r = s.steady_rotation.expect("a steady rotation");
    assert!(
        (r.value - rotation).abs() <= r.uncertainty,
        "{r:?} against {rotation}"
    );
    assert!(
        (r.value / rotation - 1.0).abs() < 5e-4,
        "{r:?} against {rotation}"
    );
}

/// `not-converged` at `cap` and the run taken on: the trend's interval
/// holds the level, and `W` moved towards it in the direction `rising`.
fn the_interval_holds_the_level(case: &Case, cap: usize, rising: bool) {
    let (level, w) = run_out(case);
    assert!(w.len() > cap + 10, "{} cycles", w.len());
    assert_eq!((w[cap - 1] < level), rising, "{} {level}", w[cap - 1]);
    let s = run(case, cap);
    assert_eq!(s.state(), SteadyState::NotConverged, "{s:?}");
    let t = s.trend().expect("a trend at the cap");
    assert!(
        (t.limit - level).abs() <= t.uncertainty,
        "{t:?} against {level}"
    );
    // A geometric approach is bounded: the interval is not all of [0, 2 W].
    assert!(t.uncertainty < 0.05 * level, "{t:?}");
}

#[test]
fn not_converged_holds_a_level_that_w_rises_to() {
    // The case: W rises to its level at the cap.
    the_interval_holds_the_level(&case(5.1, 18.0 * PI / 48.0, "5,-7", 0.3), 54, true);
}

#[test]
fn not_converged_holds_a_level_that_w_falls_to() {
    the_interval_holds_the_level(&case(5.1, PI / 8.0, "-7,-5", 0.3), 30, false);
}
