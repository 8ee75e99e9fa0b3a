//! A small sweep in the manner of the paper's Fig. 3: the steady state and
//! dissipation `W` of three transients at a few load factors, in one call.
//!
//! `cargo run --release --example small_sweep`

use shakedown::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The paper's material, centre and slope, in phase (phi = 0).
    let case = Case::builder().build()?;
    let lists = SweepLists {
        load_factors: vec![4.0, 5.0, 6.0, 7.0],
        phases: vec![0.0],
        initials: Initial::paper_set().into_iter().take(3).collect(),
    };
    let rows = SweepSpec::over(&case, &lists)?.run_all(None, None);

    println!(
        "{:>6}  {:>7}  {:<26} {:>12}",
        "lambda", "initial", "state", "W"
    );
    for row in &rows {
        match &row.outcome {
            Ok(o) => println!(
                "{:>6}  {:>7}  {:<26} {:>12}",
                row.job.load_factor,
                row.initial,
                o.state().as_str(),
                readable(o.dissipation)
            ),
            Err(e) => println!(
                "{:>6}  {:>7}  failed: {e}",
                row.job.load_factor, row.initial
            ),
        }
    }
    Ok(())
}

/// `W` as a person reads it: a plain 0 where nothing slips (shakedown), four
/// significant figures otherwise.
fn readable(w: f64) -> String {
    if w == 0.0 {
        "0".to_string()
    } else {
        format!("{w:.3e}")
    }
}
