//! Tests of the parent module.

use super::*;

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
