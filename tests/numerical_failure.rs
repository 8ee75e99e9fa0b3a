//! Numerical failure is explained, and nothing hangs: an increment whose
//! active set does not settle, even after bisection, ends the run with a
//! typed error naming the load point and the increment; a sweep records
//! it as a `failed` row and carries on.

use std::sync::Arc;

use shakedown::analysis::sweep::{RowState, SweepSpec};
use shakedown::io::batch::Interrupt;
use shakedown::model::path::Initial;
use shakedown::{
    Contact, Cycle, Discretisation, LoadPoint, Material, Operators, Plane, StepError, StepOptions,
    Stepper,
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
    StepOptions {
        failure_bisections: 0,
        ..StepOptions::default()
    }
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
    let e = run_transient(no_bisection()).unwrap_err();
    let StepError::NotSettled {
        load,
        phase,
        bisections,
    } = &e
    else {
        panic!("expected an unsettled active set, got {e:?}");
    };
    assert_eq!(*bisections, 0);
    // The first increment of the second segment, from (-0.94, 5.37)
    // towards (1.98, 3.7).
    assert_eq!(phase, "transient segment 2, increment 1");
    let on_segment = (load.x() + 0.94) / (1.98 + 0.94);
    assert!(on_segment > 0.0 && on_segment < 1.0, "{load}");
    assert!((load.y() - (5.37 + on_segment * (3.7 - 5.37))).abs() < 1e-9);
    let message = e.to_string();
    assert!(message.contains("load point (0.0333, 4.8133)"), "{message}");
    assert!(message.contains("increment 1"), "{message}");
}

#[test]
fn bisection_resolves_the_same_increment() {
    // With the default 12 bisections the same path runs through.
    assert!(run_transient(StepOptions::default()).is_ok());
}

#[test]
fn a_sweep_records_the_failure_and_carries_on() {
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
    for row in &rows {
        let custom = row.job.initial == 0;
        assert_eq!(row.state() == RowState::Failed, custom, "{row:?}");
        assert_eq!(row.state().to_string() == "failed", custom);
        if let Err(e) = &row.outcome {
            assert!(e.to_string().contains("transient segment 2, increment 1"));
        }
    }
    // The old collecting entry point gives the same rows.
    let cancel = std::sync::atomic::AtomicBool::new(false);
    assert_eq!(spec.run(&jobs, &|_| {}, &cancel), rows);
}
