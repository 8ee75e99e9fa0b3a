//! `Stepper::trim_history` (issue 12): dropping the per-node slip of old
//! cycles, so that a run stepped on for hours stays within its memory,
//! changes no verdict, no trend and no cycle count.

use shakedown::analysis::case::{Case, CaseParams};
use shakedown::stepping::steady::SETTLE_CYCLES;
use shakedown::{Outcome, Status, Stepper};

fn stepper(load_factor: f64, initial: &str, max_cycles: usize) -> Stepper {
    let params = CaseParams {
        load_factor,
        initial: shakedown::Initial::parse(initial).unwrap(),
        nodes: 32,
        steps: 200,
        max_cycles,
        ..CaseParams::default()
    };
    Case::from_params(&params).unwrap().stepper()
}

/// Run to the verdict cycle by cycle, trimming to `keep` after each cycle
/// when `keep` is given; then `extra` more cycles past it.
fn run(mut s: Stepper, keep: Option<usize>, extra: usize) -> (Outcome, Stepper) {
    while matches!(s.status(), Status::Running) {
        s.run_to_cycle_end().unwrap();
        if let Some(k) = keep {
            s.trim_history(k);
        }
    }
    for _ in 0..extra {
        s.run_to_cycle_end().unwrap();
        if let Some(k) = keep {
            s.trim_history(k);
        }
    }
    (*s.outcome().unwrap(), s)
}

#[test]
fn trimming_changes_no_verdict() {
    // A cyclic-slip run that settles by the 0.01 % rule after many cycles,
    // and one stopped by a small cap (its trend reads W of every cycle).
    for cap in [200, 12] {
        let (plain, full) = run(stepper(6.0, "7,-7", cap), None, 3);
        let (trimmed, kept) = run(stepper(6.0, "7,-7", cap), Some(0), 3);
        assert_eq!(plain, trimmed, "cap {cap}");
        let n = full.history().len();
        assert!(n > SETTLE_CYCLES + 4, "{plain:?}");
        assert!(plain.cycles >= 10 && plain.cycles + 3 == n, "{plain:?}");
        // Past the verdict only the last cycles are kept, whole.
        assert_eq!(kept.history(), &full.history()[n - SETTLE_CYCLES - 1..]);
        assert_eq!(kept.history().last().unwrap().cycle, n);
    }
}

#[test]
fn before_the_verdict_old_cycles_keep_their_scalars() {
    let mut s = stepper(6.0, "7,-7", 200);
    for _ in 0..7 {
        s.run_to_cycle_end().unwrap();
    }
    assert!(matches!(s.status(), Status::Running), "{:?}", s.status());
    let before = s.history().to_vec();
    let freed = s.trim_history(2);
    let trimmed = 7 - (SETTLE_CYCLES + 1);
    assert_eq!(freed, trimmed * 2 * 32 * std::mem::size_of::<f64>());
    assert_eq!(s.history().len(), 7);
    for (i, (a, b)) in before.iter().zip(s.history()).enumerate() {
        assert_eq!(
            (a.cycle, a.dissipation, a.rotation),
            (b.cycle, b.dissipation, b.rotation)
        );
        if i < trimmed {
            assert!(
                b.forward.is_empty() && b.backward.is_empty(),
                "cycle {}",
                b.cycle
            );
        } else {
            assert_eq!(a, b, "the last cycles keep their per-node slip");
        }
    }
    assert_eq!(s.trim_history(2), 0, "a second trim frees nothing");
    assert_eq!(s.trim_history(100), 0, "keeping more frees nothing");
}
