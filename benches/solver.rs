//! Speed of the physics core: one increment with a partial slip zone, one
//! run to the steady state, and the Fig. 3 sweep.
//!
//! `cargo bench --bench solver` (add `-- fig3` for the sweep alone).

use std::f64::consts::PI;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use shakedown::analysis::sweep::SweepSpec;
use shakedown::stepping::operators;
use shakedown::{
    Contact, Cycle, Discretisation, Initial, LoadPoint, Material, StepOptions, Stepper,
};

/// A contact in the middle of a partial slip zone: the disc loaded beyond
/// the stick diamond along the torque axis, so part of the interface slips.
fn partially_slipping() -> (Contact, LoadPoint) {
    let disc = Discretisation::default();
    let mut c = Contact::new(Material::paper(), operators(&disc));
    let target = LoadPoint::new(2.0, 5.5);
    let steps = 100;
    for i in 1..=steps {
        let t = c
            .solve(LoadPoint::ORIGIN.lerp(target, i as f64 / steps as f64))
            .unwrap();
        c.commit(t);
    }
    let slipping = c.directions().iter().filter(|d| d.is_slipping()).count();
    assert!(
        slipping > 10 && slipping < 128,
        "a partial slip zone: {slipping} nodes"
    );
    (c, LoadPoint::new(2.0, 5.52))
}

fn increment(cr: &mut Criterion) {
    let (contact, next) = partially_slipping();
    cr.bench_function("increment, partial slip, N = 128", |b| {
        b.iter_batched(
            || contact.clone(),
            |mut c| {
                let t = c.solve(next).unwrap();
                c.commit(t);
                c
            },
            BatchSize::SmallInput,
        )
    });
}

fn run_to_steady(cr: &mut Criterion) {
    let mut group = cr.benchmark_group("run to steady state");
    group.sample_size(20);
    for (name, load_factor, phase) in [
        (
            "lambda 5.5, phi pi/2 (monotonic ratchetting)",
            5.5,
            PI / 2.0,
        ),
        ("lambda 7, phi 0 (point B)", 7.0, 0.0),
        ("lambda 5.5, phi 0 (cyclic slip)", 5.5, 0.0),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut s = Stepper::new(
                    Material::paper(),
                    Discretisation::default(),
                    &Initial::Direct,
                    Cycle::paper(load_factor, phase).unwrap(),
                    StepOptions::default(),
                );
                s.run_to_steady().unwrap()
            })
        });
    }
    group.finish();
}

fn fig3(cr: &mut Criterion) {
    let spec = SweepSpec::new(
        Material::paper(),
        Discretisation::default(),
        StepOptions::default(),
        LoadPoint::new(PI, 0.75 * PI),
        0.625,
        shakedown::analysis::sweep::SweepLists {
            load_factors: (0..=90).map(|i| 3.0 + 0.05 * i as f64).collect(),
            phases: vec![0.0],
            initials: Initial::paper_set(),
        },
    )
    .unwrap();
    let jobs = spec.jobs();
    let mut group = cr.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("fig3: 25 transients x lambda 3..7.5 step 0.05", |b| {
        b.iter(|| spec.run(&jobs, &|_| {}, &AtomicBool::new(false)))
    });
    group.finish();
}

criterion_group!(benches, increment, run_to_steady, fig3);
criterion_main!(benches);
