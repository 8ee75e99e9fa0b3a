//! One case of the paper, built by name and run to its steady state:
//! Fig. 3's cycle at `lambda = 5.5` (give another on the command line).
//!
//! `cargo run --release --example one_case [LAMBDA]`

use shakedown::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let load_factor = match std::env::args().nth(1) {
        Some(text) => text.parse()?,
        None => 5.5,
    };
    let case = Case::builder()
        .load_factor(load_factor)
        .initial(Initial::Direct)
        .build()?;
    let outcome = case.run()?;

    println!("lambda     {load_factor}");
    println!("state      {}", outcome.state());
    println!("how        {}", outcome.approach());
    println!("W          {:.6e}", outcome.dissipation);
    println!("rotation   {:.6e} per cycle", outcome.rotation_per_cycle);
    println!("cycles     {}", outcome.cycles);
    if let Verdict::GrossSlip(end) = outcome.verdict {
        println!("ended at   {}", end.load);
    }
    Ok(())
}
