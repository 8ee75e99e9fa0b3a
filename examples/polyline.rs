//! Any closed load cycle, as `--cycle FILE` gives it: the paper's in-phase
//! amplitudes with the torque at twice the frequency of the force (the
//! `biharmonic` preset's figure-eight), against the paper's own in-phase
//! cycle, at a few load factors through the transient `7,-7`.
//!
//! `cargo run --release --example polyline`

use std::f64::consts::PI;

use shakedown::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // One period of offsets (u, v) from the centre A, equal time per chord
    // (docs/model.md section 5.4): 200 vertices, so --steps 400 gives two
    // increments a chord.
    let psi: f64 = 0.625;
    let norm = (1.0 + psi * psi).sqrt();
    let vertices: Vec<LoadPoint> = (0..200)
        .map(|k| {
            let t = 2.0 * PI * k as f64 / 200.0;
            LoadPoint::new(t.sin() / norm, psi * (2.0 * t).sin() / norm)
        })
        .collect();
    let figure_eight = inline_cycle(vertices)?;
    println!("cycle        {}", figure_eight.name());

    let biharmonic = |load_factor: f64| {
        Case::builder()
            .load_factor(load_factor)
            .cycle(figure_eight.clone())
            .initial(Initial::Via { a: 7, b: -7 })
            .nodes(64)
            .steps(400)
            .build()
    };
    let in_phase = |load_factor: f64| {
        Case::builder()
            .load_factor(load_factor)
            .initial(Initial::Via { a: 7, b: -7 })
            .nodes(64)
            .steps(400)
            .build()
    };
    // lambda_2 does not depend on lambda: any load factor will do.
    let (two, one) = (biharmonic(1.0)?.limit()?, in_phase(1.0)?.limit()?);
    println!(
        "lambda_2     {:.4} (torque at twice the frequency)   {:.4} (in phase)",
        two.load_factor, one.load_factor
    );
    println!();
    println!(
        "{:>6}   {:<26} {:>12}   {:<26} {:>12}",
        "lambda", "twice the frequency", "W", "in phase", "W"
    );
    for load_factor in [4.0, 4.5, 5.0, 5.5] {
        let a = biharmonic(load_factor)?.run()?;
        let b = in_phase(load_factor)?.run()?;
        println!(
            "{:>6.2}   {:<26} {:>12.4e}   {:<26} {:>12.4e}",
            load_factor,
            a.state().to_string(),
            a.dissipation,
            b.state().to_string(),
            b.dissipation
        );
    }
    Ok(())
}
