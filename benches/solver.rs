//! Speed of the physics core: one increment with a partial slip zone (the
//! finite-step solve, and the exact advance with an unchanged slip set or
//! stick only), runs to the steady state (N = 128 and N = 1024), and the
//! Fig. 3 sweep.
//!
//! `cargo bench --bench solver` (add `-- fig3` for the sweep alone).

use std::f64::consts::PI;
use std::hint::black_box;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use shakedown::analysis::sweep::SweepSpec;
use shakedown::stepping::operators;
use shakedown::{
    Advanced, Contact, Cycle, Discretisation, Initial, LoadPoint, Material, StepOptions, Stepper,
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
            .unwrap()
            .trial()
            .expect("no physical end");
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
                let t = c.solve(next).unwrap().trial().expect("no physical end");
                c.commit(t);
                c
            },
            BatchSize::SmallInput,
        )
    });
}

/// A contact advanced exactly into a partial slip zone, and a next load
/// point close enough that the slip set does not change on the way.
fn unchanged_set() -> (Contact, LoadPoint) {
    let disc = Discretisation::default();
    let mut c = Contact::new(Material::paper(), operators(&disc));
    let target = LoadPoint::new(2.0, 5.5);
    let steps = 100;
    for i in 1..=steps {
        c.advance(LoadPoint::ORIGIN.lerp(target, i as f64 / steps as f64))
            .unwrap();
    }
    let mut dy = 0.02;
    loop {
        let next = LoadPoint::new(2.0, 5.5 + dy);
        let mut probe = c.clone();
        assert_eq!(probe.advance(next), Ok(Advanced::Reached));
        let inc = probe.last_increment();
        if inc.events.is_empty() && inc.segments == 1 && !inc.set_changed {
            // Warm the cached responses along this direction.
            return (c, next);
        }
        dy *= 0.5;
        assert!(dy > 1e-9, "no increment without an event");
    }
}

/// Time `iters` consecutive increments of `span / K` from `contact` along
/// the straight `span`, starting over (untimed clone) every `K` increments.
/// The first increment after each clone is not timed: a clone starts with
/// an empty reduced inverse and response cache, so it solves for the
/// response across the new direction once, which is not the cost of an
/// increment whose slip set holds.
fn consecutive(contact: &Contact, to: LoadPoint, iters: u64) -> Duration {
    const K: u64 = 100;
    let from = contact.load();
    let mut total = Duration::ZERO;
    let mut done = 0;
    while done < iters {
        let mut c = contact.clone();
        assert_eq!(
            c.advance(from.lerp(to, 1.0 / K as f64)),
            Ok(Advanced::Reached)
        );
        let chunk = (K - 1).min(iters - done);
        let start = Instant::now();
        for i in 2..=chunk + 1 {
            assert_eq!(
                c.advance(from.lerp(to, i as f64 / K as f64)),
                Ok(Advanced::Reached)
            );
        }
        total += start.elapsed();
        black_box(&c);
        done += chunk;
    }
    total
}

fn exact_increment(cr: &mut Criterion) {
    let (contact, next) = unchanged_set();
    let slipping = contact
        .directions()
        .iter()
        .filter(|d| d.is_slipping())
        .count();
    assert!(slipping > 10 && slipping < 128, "{slipping} nodes slipping");
    cr.bench_function("advance, unchanged partial slip set, N = 128", |b| {
        b.iter_custom(|iters| consecutive(&contact, next, iters))
    });
    let disc = Discretisation::default();
    let stick = Contact::new(Material::paper(), operators(&disc));
    let to = LoadPoint::new(0.5, 0.5);
    cr.bench_function("advance, stick only, N = 128", |b| {
        b.iter_custom(|iters| consecutive(&stick, to, iters))
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
    group.bench_function("lambda 5.5, phi 0, N = 1024", |b| {
        b.iter(|| {
            let mut s = Stepper::new(
                Material::paper(),
                Discretisation::new(1024, 400).unwrap(),
                &Initial::Direct,
                Cycle::paper(5.5, 0.0).unwrap(),
                StepOptions::default(),
            );
            s.run_to_steady().unwrap()
        })
    });
    group.finish();
}

/// The slowest asymptotic shakedown of `fig6` (`lambda = 5.1`,
/// `phi = 17 pi/48`, path `7,-5`): proven by a safe state, and run out to
/// its first cycle without slip (model.md section 6.4).
fn asymptotic_shakedown(cr: &mut Criterion) {
    let mut group = cr.benchmark_group("asymptotic shakedown");
    group.sample_size(10);
    for (name, safe_state) in [
        ("fig6 17pi/48 7,-5: safe state", true),
        ("fig6 17pi/48 7,-5: run out", false),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let options = StepOptions::default().with_safe_state(safe_state);
                let mut s = Stepper::new(
                    Material::paper(),
                    Discretisation::default(),
                    &Initial::parse("7,-5").unwrap(),
                    Cycle::paper(5.1, 17.0 * PI / 48.0).unwrap(),
                    options,
                );
                s.run_to_steady().unwrap()
            })
        });
    }
    group.finish();
}

fn fig3(cr: &mut Criterion) {
    let spec = SweepSpec::paper(shakedown::analysis::sweep::SweepLists {
        load_factors: (0..=90).map(|i| 3.0 + 0.05 * i as f64).collect(),
        phases: vec![0.0],
        initials: Initial::paper_set(),
    })
    .unwrap();
    let jobs = spec.jobs();
    let mut group = cr.benchmark_group("sweep");
    group.sample_size(10);
    group.bench_function("fig3: 25 transients x lambda 3..7.5 step 0.05", |b| {
        b.iter(|| spec.run(&jobs, &|_| {}, &AtomicBool::new(false)))
    });
    group.finish();
}

criterion_group!(
    benches,
    increment,
    exact_increment,
    run_to_steady,
    asymptotic_shakedown,
    fig3
);
criterion_main!(benches);
