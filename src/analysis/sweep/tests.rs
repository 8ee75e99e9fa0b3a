//! Tests of the parent module.

use super::*;
use std::f64::consts::PI;

#[test]
fn job_order_is_lambda_phi_initial() {
    let spec = SweepSpec::new(
        Material::paper(),
        Discretisation::default(),
        StepOptions::default(),
        LoadPoint::new(1.0, 1.0),
        0.5,
        SweepLists {
            load_factors: vec![1.0, 2.0],
            phases: vec![0.0, 0.5],
            initials: Initial::paper_set()[..3].to_vec(),
        },
    )
    .unwrap();
    let jobs = spec.jobs();
    assert_eq!(jobs.len(), 12);
    assert_eq!(
        (jobs[3].load_factor, jobs[3].phase, jobs[3].initial),
        (1.0, 0.5, 0)
    );
    assert!(jobs.iter().enumerate().all(|(i, j)| j.index == i));
    // The groups: one per (lambda, phi), each with every initial path.
    let groups = groups(&jobs);
    assert_eq!(groups.len(), 4);
    for g in &groups {
        assert_eq!(g.len(), 3);
        assert!(jobs[g.clone()]
            .iter()
            .all(|j| same_group(j, &jobs[g.start])));
        assert_eq!(jobs[g.start].initial, 0);
    }
    assert_eq!(groups.last().unwrap().end, jobs.len());
}

/// A job made elsewhere that names a path the sweep lacks gets a row that
/// says so, and the sweep's own jobs still run.
#[test]
fn a_foreign_job_naming_a_missing_path_is_a_row_not_a_panic() {
    let spec = SweepSpec::new(
        Material::paper(),
        Discretisation::new(16, 64).unwrap(),
        StepOptions::default(),
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        SweepLists {
            load_factors: vec![1.0],
            phases: vec![0.0],
            initials: vec![Initial::Direct],
        },
    )
    .unwrap();
    let mut jobs = spec.jobs();
    jobs.push(Job {
        index: 1,
        load_factor: 1.0,
        phase: 0.0,
        initial: 7,
    });
    let rows = spec.run(&jobs, &|_| {}, &AtomicBool::new(false));
    assert_eq!(rows.len(), 2);
    assert_eq!(
        rows[1].outcome,
        Err(RunError::Initial { index: 7, paths: 1 })
    );
    assert!(rows[0].outcome.is_ok());
}
