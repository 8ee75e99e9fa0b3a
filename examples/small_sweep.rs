//! A small sweep in the manner of the paper's Fig. 3: the steady-state
//! dissipation `W` of five transients at a few load factors, beside the
//! shakedown limit `lambda_2` of the linear programme.
//!
//! `cargo run --release --example small_sweep`

use std::sync::atomic::AtomicBool;

use shakedown::analysis::case::{Case, CaseParams};
use shakedown::analysis::limit::{shakedown_limit, DEFAULT_SAMPLES};
use shakedown::analysis::sweep::{SweepLists, SweepSpec};
use shakedown::Initial;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The paper's material, centre and slope, in phase (phi = 0).
    let case = Case::from_params(&CaseParams::default())?;
    let limit = shakedown_limit(
        &case.material,
        case.cycle.center(),
        case.cycle.slope(),
        0.0,
        &case.disc,
        DEFAULT_SAMPLES,
    )?;
    println!("lambda_2 = {:.4} (linear programme)", limit.load_factor);

    let lists = SweepLists {
        load_factors: vec![4.0, 4.5, 5.0, 5.5, 6.0, 7.0],
        phases: vec![0.0],
        initials: Initial::paper_set().into_iter().take(5).collect(),
    };
    let spec = SweepSpec::over(&case, &lists)?;
    let rows = spec.run(&spec.jobs(), &|_| {}, &AtomicBool::new(false));
    println!(
        "{:>6}  {:>8}  {:<28} {:>12}",
        "lambda", "initial", "state", "W"
    );
    for row in &rows {
        match &row.outcome {
            Ok(s) => println!(
                "{:>6}  {:>8}  {:<28} {:>12.4e}",
                row.job.load_factor, row.initial, s.state, s.dissipation
            ),
            Err(e) => println!(
                "{:>6}  {:>8}  failed: {e}",
                row.job.load_factor, row.initial
            ),
        }
    }
    Ok(())
}
