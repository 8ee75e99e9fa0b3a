//! One case of the paper: point B of Fig. 3 (`lambda = 7`, `phi = 0`, the
//! direct path `OA`), run to its steady state, with every event of the
//! first cycles printed as it happens.
//!
//! `cargo run --release --example one_case [LAMBDA]`

use shakedown::analysis::case::{Case, CaseParams};
use shakedown::stepping::{drive, Control, Goal};
use shakedown::{Event, StepReport, Stepper};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let load_factor = match std::env::args().nth(1) {
        Some(text) => text.parse()?,
        None => 7.0,
    };
    let params = CaseParams {
        load_factor,
        ..CaseParams::default()
    };
    let case = Case::from_params(&params)?;
    let mut stepper = case.stepper();

    // An observer: print what happens during the transient and the first
    // two cycles, then watch quietly.
    let mut printed = 0;
    let mut observer = |s: &Stepper, report: &StepReport| {
        for event in &report.events {
            if printed < 40 && !matches!(event, Event::SlipSetChanged { .. }) {
                println!("{:>6} increments  {event:?}", s.increments());
                printed += 1;
            }
        }
        Control::Continue
    };
    drive(&mut stepper, Goal::Steady, &mut observer)?;

    let summary = stepper.run_to_steady()?;
    println!(
        "lambda = {load_factor}: {} after {} cycles, W = {:.6e}, rotation per cycle = {:.3e}",
        summary.state, summary.cycles, summary.dissipation, summary.rotation_per_cycle
    );
    Ok(())
}
