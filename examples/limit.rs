//! The shakedown limit `lambda_2` (linear programme, model.md section 7.3)
//! at a few phases of the paper's cycle.
//!
//! `cargo run --release --example limit`

use std::f64::consts::PI;

use shakedown::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("{:>8}  {:>10}", "phi/pi", "lambda_2");
    for k in 0..=4 {
        let phase = k as f64 * PI / 8.0;
        let limit = Case::builder().phase(phase).build()?.limit()?;
        println!("{:>8.3}  {:>10.4}", phase / PI, limit.load_factor);
    }
    Ok(())
}
