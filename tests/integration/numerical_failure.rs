//! Numerical failure is explained, and nothing hangs: an increment whose
//! active set does not settle is a typed error naming the load point; a
//! sweep carries on. The hard case below, on which the finite-step
//! active-set iteration fails, is resolved by the exact increment, also
//! in a sweep.

use std::sync::Arc;

use shakedown::analysis::sweep::{RowState, SweepSpec};
use shakedown::io::batch::Interrupt;
use shakedown::model::path::Initial;
use shakedown::{
    Contact, ContactError, Cycle, Discretisation, LoadPoint, Material, Operators, Plane, StepError,
    StepOptions, Stepper,
};

/// A path on which the active set of a very rough interface (f = 10) does
/// not settle on 16 nodes when the transient is taken in big increments
/// (found by a search over random paths).
fn hard_case() -> (Material, Discretisation, Vec<LoadPoint>) {
    let m = Material::new(10.0, 0.3, Plane::Strain).unwrap();
    let disc = Discretisation::new(16, 16).unwrap();
    let path = vec![LoadPoint::new(-0.94, 5.37), LoadPoint::new(1.98, 3.7)];
    (m, disc, path)
}

fn no_bisection() -> StepOptions {
    StepOptions::builder()
        .failure_bisections(0)
        .build()
        .unwrap()
}

fn run_transient(options: StepOptions) -> Result<usize, StepError> {
    let (m, disc, path) = hard_case();
    let end = *path.last().unwrap();
    let cycle = Cycle::new(end, 0.0, 0.0, 0.0).unwrap();
    let contact = Contact::new(m, Arc::new(Operators::new(disc.nodes())));
    let mut s = Stepper::from_contact(contact, &path, cycle, disc, options);
    let mut steps = 0;
    while !s.is_finished() && s.history().is_empty() {
        s.step()?;
        steps += 1;
        assert!(steps < 10_000, "the run does not end");
    }
    Ok(steps)
}

#[test]
fn an_unsettled_active_set_is_a_typed_error_with_its_place() {
    // The finite-step active-set iteration (`Contact::solve`, which the
    // exact increment keeps as its last resort) does not settle on the
    // first increment of the second segment, from (-0.94, 5.37) towards
    // (1.98, 3.7), and says so with the load point.
    let (m, disc, path) = hard_case();
    let cycle = Cycle::new(path[0], 0.0, 0.0, 0.0).unwrap();
    let contact = Contact::new(m, Arc::new(Operators::new(disc.nodes())));
    let mut s = Stepper::from_contact(contact, &path[..1], cycle, disc, no_bisection());
    while s.history().is_empty() {
        s.step().unwrap();
    }
    let mut c = s.contact().clone();
    assert!(c.load().distance(path[0]) < 1e-12);
    let to = path[0].lerp(path[1], 1.0 / 3.0);
    let e = c.solve(to).unwrap_err();
    let ContactError::NotSettled { load, .. } = &e else {
        panic!("expected an unsettled active set, got {e:?}");
    };
    assert!(load.distance(to) < 1e-12);
    let message = e.to_string();
    assert!(message.contains("load point (0.0333, 4.8133)"), "{message}");
    // The exact, event-driven increment resolves the same path without any
    // bisection.
    assert!(run_transient(no_bisection()).is_ok());
}

#[test]
fn bisection_resolves_the_same_increment() {
    // With the default 12 bisections the same path runs through.
    assert!(run_transient(StepOptions::default()).is_ok());
}

/// A sweep with the path on which the finite step fails: every row runs
/// through (the exact increment resolves it) and the sweep completes.
#[test]
fn a_sweep_over_the_hard_path_runs_every_row_through() {
    let (m, disc, path) = hard_case();
    let end = *path.last().unwrap();
    let spec = SweepSpec::new(
        m,
        disc,
        no_bisection(),
        end,
        0.625,
        shakedown::analysis::sweep::SweepLists {
            load_factors: vec![0.0, 0.5],
            phases: vec![0.0],
            initials: vec![Initial::custom(path).unwrap(), Initial::Direct],
        },
    )
    .unwrap();
    let jobs = spec.jobs();
    let mut rows = Vec::new();
    let progress = spec
        .run_ordered(&jobs, &Interrupt::new(), |row| {
            rows.push(row);
            Ok::<_, ()>(())
        })
        .unwrap();
    assert!(progress.is_complete());
    assert_eq!(rows.len(), 4);
    // The path on which the finite-step solver failed now runs through
    // (the exact increment); no row fails.
    for row in &rows {
        assert_ne!(row.state(), RowState::Failed, "{row:?}");
        assert_ne!(row.state().to_string(), "failed");
    }
    // The old collecting entry point gives the same rows.
    let cancel = std::sync::atomic::AtomicBool::new(false);
    assert_eq!(spec.run(&jobs, &|_| {}, &cancel), rows);
}
