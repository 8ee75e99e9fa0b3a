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
    // Every setting is checked where the case is built, against the
    // ranges of `shakedown::model::ranges`.
    let case = Case::builder()
        .load_factor(load_factor)
        .initial(Initial::Direct)
        .max_cycles(500)
        .build()?;
    let outcome = case.run()?;

    let disc = case.disc();
    println!("lambda     {}", case.cycle().load_factor());
    println!(
        "model      N = {}, {} increments a cycle, at most {} cycles",
        disc.nodes(),
        disc.steps_per_cycle(),
        case.options().convergence().max_cycles()
    );
    println!("state      {}", outcome.state());
    println!("how        {}", outcome.approach());
    println!("W          {:.6e}", outcome.dissipation);
    println!("rotation   {:.6e} per cycle", outcome.rotation_per_cycle);
    println!("cycles     {}", outcome.cycles);
    if let Verdict::GrossSlip(end) = outcome.verdict {
        println!("ended at   {}", end.load);
    }
    // A setting out of range is refused with the range it breaks.
    if let Err(e) = Case::builder().nodes(127).build() {
        println!("refused    {e}");
    }
    Ok(())
}
