//! Speed of the shakedown limit `lambda_2` (model.md section 7.3): the
//! programme on the ellipse `phi = pi/2` (64 samples) and on the line
//! `phi = 0`, at N = 128 and N = 1024.
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
    let mut group = c.benchmark_group("limit");
    group.sample_size(10);
    for nodes in [128, 1024] {
        let disc = Discretisation::new(nodes, 400).unwrap();
        for (name, phase) in [("phi_half_pi", 0.5 * PI), ("phi_0", 0.0)] {
            group.bench_function(format!("n{nodes}_{name}"), |b| {
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
    }
    group.finish();
}

criterion_group!(benches, limit);
criterion_main!(benches);
