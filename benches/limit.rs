//! Speed of the shakedown limit `lambda_2` (model.md section 7.3): the
//! programme at N = 128 on the ellipse `phi = pi/2` (64 samples) and on the
//! line `phi = 0`.
//!
//! `cargo bench --bench limit`.

use std::f64::consts::PI;
use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use shakedown::analysis::limit::{shakedown_limit, DEFAULT_SAMPLES};
use shakedown::{Discretisation, LoadPoint, Material};

fn limit(c: &mut Criterion) {
    let material = Material::paper();
    let center = LoadPoint::new(PI, 0.75 * PI);
    let disc = Discretisation::new(128, 400).unwrap();
    let mut group = c.benchmark_group("limit");
    group.sample_size(10);
    for (name, phase) in [("n128_phi_half_pi", 0.5 * PI), ("n128_phi_0", 0.0)] {
        group.bench_function(name, |b| {
            b.iter(|| {
                shakedown_limit(
                    &material,
                    center,
                    0.625,
                    black_box(phase),
                    &disc,
                    DEFAULT_SAMPLES,
                )
                .unwrap()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, limit);
criterion_main!(benches);
