//! `lambda_2` by linear programming (model.md section 7) against the
//! simulation: the optimal slip shakes down just below it and slips just
//! above it, and no transient shakes down above it.

use crate::common;

use std::f64::consts::PI;

use common::{read_csv, scratch, shakedown, stderr, stdout};
use shakedown::analysis::case::{Case, CaseParams};
use shakedown::analysis::limit::{shakedown_limit, Limit, DEFAULT_SAMPLES};
use shakedown::analysis::sweep::SweepSpec;
use shakedown::model::path::Initial;
use shakedown::model::{Discretisation, LoadPoint, Material};
use shakedown::stepping::steady::SteadyState;
use shakedown::stepping::{Outcome, StepOptions};

const NODES: usize = 64;
const STEPS: usize = 200;

fn limit(phase: f64) -> Limit {
    shakedown_limit(
        &Material::paper(),
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        phase,
        &Discretisation::new(NODES, STEPS).unwrap(),
        DEFAULT_SAMPLES,
    )
    .unwrap()
}

fn run_optimal(lambda: f64, phase: f64) -> Outcome {
    let params = CaseParams {
        load_factor: lambda,
        phase,
        initial: shakedown::Initial::Optimal,
        nodes: NODES,
        steps: STEPS,
        ..CaseParams::default()
    };
    Case::from_params(&params)
        .unwrap()
        .stepper()
        .run_to_steady()
        .unwrap()
}

#[test]
fn optimal_slip_shakes_down_below_lambda_2_and_slips_above_in_phase() {
    let l = limit(0.0);
    assert!(l.line);
    let below = run_optimal(l.load_factor - 0.05, 0.0);
    assert_eq!(below.state(), SteadyState::Shakedown, "{below:?}");
    // The optimal slip holds on the whole cycle: not a single increment slips.
    assert_eq!(below.cycles, 1, "{below:?}");
    let above = run_optimal(l.load_factor + 0.05, 0.0);
    assert_ne!(above.state(), SteadyState::Shakedown, "{above:?}");
    assert!(above.dissipation > 0.0, "{above:?}");
}

#[test]
fn optimal_slip_shakes_down_below_lambda_2_and_slips_above_out_of_phase() {
    let l = limit(0.5 * PI);
    assert!(!l.line);
    // The sampled optimum brackets the true limit of the ellipse.
    assert!(l.load_factor - l.lower_bound < 0.05);
    let below = run_optimal(l.lower_bound - 0.05, 0.5 * PI);
    assert_eq!(below.state(), SteadyState::Shakedown, "{below:?}");
    assert_eq!(below.cycles, 1, "{below:?}");
    let above = run_optimal(l.load_factor + 0.05, 0.5 * PI);
    assert_ne!(above.state(), SteadyState::Shakedown, "{above:?}");
}

#[test]
fn lambda_2_lies_right_of_every_transient_shakedown() {
    // If a transient shakes down at lambda, its locked-in slip keeps the
    // friction law on the whole cycle, so lambda <= lambda_2. The paper
    // observes more: the optimal slip's points lie to the right of all 25.
    let l = limit(0.0);
    let mut load_factors: Vec<f64> = (0..=6).map(|k| 4.0 + 0.25 * k as f64).collect();
    load_factors.push(l.load_factor + 0.02);
    let options = StepOptions::default();
    let spec = SweepSpec::new(
        Material::paper(),
        Discretisation::new(NODES, STEPS).unwrap(),
        options,
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        shakedown::analysis::sweep::SweepLists {
            load_factors,
            phases: vec![0.0],
            initials: Initial::paper_set(),
        },
    )
    .unwrap();
    let rows = spec.run(&spec.jobs(), &|_| {}, &Default::default());
    let shaken: Vec<f64> = rows
        .iter()
        .filter(|r| matches!(&r.outcome, Ok(s) if s.state() == SteadyState::Shakedown))
        .map(|r| r.job.load_factor)
        .collect();
    assert!(
        !shaken.is_empty(),
        "some transient shakes down at lambda = 4"
    );
    let largest = shaken.iter().cloned().fold(f64::MIN, f64::max);
    assert!(
        largest < l.load_factor,
        "a transient shakes down at lambda = {largest} > lambda_2 = {}",
        l.load_factor
    );
    assert!(rows.iter().all(|r| r.outcome.is_ok()));
}

#[test]
fn a_phase_sweep_resolves_the_optimal_slip_per_phase() {
    // lambda_2 is 4.90 in phase and 5.02 at phi = pi/2: at lambda = 4.96 the
    // optimal slip of each phase shakes down out of phase only, which it
    // can only do if the slip was recomputed for that phase.
    let (l0, l1) = (limit(0.0), limit(0.5 * PI));
    let lambda = 0.5 * (l0.load_factor + l1.lower_bound);
    assert!(l0.load_factor < lambda - 0.02 && lambda + 0.02 < l1.lower_bound);
    let spec = SweepSpec::new(
        Material::paper(),
        Discretisation::new(NODES, STEPS).unwrap(),
        StepOptions::default(),
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        shakedown::analysis::sweep::SweepLists {
            load_factors: vec![lambda],
            phases: vec![0.0, 0.5 * PI],
            initials: vec![Initial::Optimal],
        },
    )
    .unwrap();
    let rows = spec.run(&spec.jobs(), &|_| {}, &Default::default());
    assert_eq!(rows.len(), 2);
    assert!(rows.iter().all(|r| r.initial == "optimal"));
    let state = |k: usize| rows[k].outcome.as_ref().unwrap().state();
    assert_ne!(state(0), SteadyState::Shakedown, "{:?}", rows[0]);
    assert_eq!(state(1), SteadyState::Shakedown, "{:?}", rows[1]);
}

#[test]
fn limit_command_prints_lambda_2_and_writes_the_slip() {
    let dir = scratch("limit-cli");
    let csv = dir.join("g.csv");
    let o = shakedown(&[
        "limit",
        "--nodes",
        "64",
        "--json",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let l2 = v["lambda_2"].as_f64().unwrap();
    assert!((l2 - limit(0.0).load_factor).abs() < 1e-6);
    assert_eq!(v["line"], true);
    let (header, rows) = read_csv(&csv);
    assert_eq!(header, ["theta", "g"]);
    assert_eq!(rows.len(), 64);

    // An ellipse reports the convergence in the sample count.
    let o = shakedown(&[
        "limit",
        "--nodes",
        "32",
        "--phi",
        "pi/2",
        "--samples",
        "32",
        "--json",
        "--force",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let conv = v["convergence"].as_array().unwrap();
    assert_eq!(
        conv.iter()
            .map(|c| c["samples"].as_u64().unwrap())
            .collect::<Vec<_>>(),
        [4, 8, 16, 32]
    );
    // Finer samplings only add constraints: lambda_M never increases, and
    // every lower bound stays below every upper bound.
    let upper: Vec<f64> = conv
        .iter()
        .map(|c| c["lambda_2"].as_f64().unwrap())
        .collect();
    let lower: Vec<f64> = conv
        .iter()
        .map(|c| c["lower_bound"].as_f64().unwrap())
        .collect();
    for w in upper.windows(2) {
        assert!(w[1] <= w[0] + 1e-6, "{upper:?}");
    }
    let min_upper = upper.iter().cloned().fold(f64::MAX, f64::min);
    assert!(lower.iter().all(|&lo| lo <= min_upper + 1e-6), "{lower:?}");

    let o = shakedown(&["limit", "--phi", "pi/2", "--samples", "2"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("samples"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_optimal_path_is_resolved_in_one_place() {
    use shakedown::analysis::sweep::SweepLists;
    use shakedown::model::Cycle;
    use shakedown::stepping::{StepError, Stepper};
    let l = limit(0.0);
    let lambda = l.load_factor + 0.05;
    // A stepper cannot solve the linear programme (it sits below the
    // analysis layer): given the unresolved path it says so, typed.
    let mut direct = Stepper::new(
        Material::paper(),
        Discretisation::new(NODES, STEPS).unwrap(),
        &Initial::Optimal,
        Cycle::paper(lambda, 0.0).unwrap(),
        StepOptions::default(),
    );
    assert_eq!(direct.run_to_steady(), Err(StepError::UnresolvedOptimal));
    // A case and a sweep resolve it through the same function and agree.
    let resolved = run_optimal(lambda, 0.0);
    let spec = SweepSpec::new(
        Material::paper(),
        Discretisation::new(NODES, STEPS).unwrap(),
        StepOptions::default(),
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        SweepLists {
            load_factors: vec![lambda],
            phases: vec![0.0],
            initials: vec![Initial::Optimal],
        },
    )
    .unwrap();
    let rows = spec.run(&spec.jobs(), &|_| {}, &Default::default());
    let swept = rows[0].outcome.as_ref().unwrap();
    assert_eq!(swept.state(), resolved.state());
    assert!((swept.dissipation - resolved.dissipation).abs() <= 1e-9 * resolved.dissipation);
}
