//! Tests of the parent module.

use clap::CommandFactory;

use super::*;

#[test]
fn command_line_definition_is_consistent() {
    // Duplicate flags and the like panic here rather than at run time.
    Cli::command().debug_assert();
}

/// The one-line error of `argv` refused by clap's value parsers, as
/// `main` shows it.
fn refused<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(argv: &[S]) -> String {
    let e = Cli::try_parse_from(argv).expect_err(&format!("{argv:?}"));
    values::render(&e).unwrap_or_else(|| panic!("{argv:?}: not a value error: {e}"))
}

fn parses<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(argv: &[S]) {
    if let Err(e) = Cli::try_parse_from(argv) {
        panic!("{argv:?}: {e}");
    }
}

/// The values just inside and just beyond each end of `range`: an open
/// end is itself beyond.
fn real_ends(range: ranges::RealRange) -> ([f64; 2], [f64; 2]) {
    let (low, high) = (range.low, range.high);
    let inside = [
        if range.low_open { low.next_up() } else { low },
        if range.high_open {
            high.next_down()
        } else {
            high
        },
    ];
    let beyond = [
        if range.low_open { low } else { low.next_down() },
        if range.high_open {
            high
        } else {
            high.next_up()
        },
    ];
    (inside, beyond)
}

/// Each numeric flag's parser is built from its range in `model::ranges`:
/// it accepts the range's ends and refuses the values just beyond them,
/// at parse time, with one line naming the flag, the value and the
/// range's own words. The values come from the constants.
#[test]
fn each_flag_parser_accepts_its_range_and_refuses_just_beyond() {
    let reals = [
        ("run", "--lambda", ranges::LAMBDA),
        ("run", "--phi", ranges::PHI),
        ("run", "--psi", ranges::PSI),
        ("run", "--friction", ranges::FRICTION),
        ("run", "--nu", ranges::NU),
        ("sweep", "--friction", ranges::FRICTION),
        ("limit", "--nu", ranges::NU),
        ("tui", "--lambda", ranges::LAMBDA),
        ("design", "--phi", ranges::PHI),
        ("design", "--gross-gap", ranges::GROSS_GAP),
    ];
    for (command, flag, range) in reals {
        let (inside, beyond) = real_ends(range);
        for v in inside {
            parses(&["shakedown", command, flag, &v.to_string()]);
        }
        for v in beyond {
            let text = v.to_string();
            let line = refused(&["shakedown", command, flag, &text]);
            assert!(line.starts_with(&format!("{flag} {text}: ")), "{line}");
            assert!(line.contains(range.expected), "{line}");
        }
    }
    // The swept lists: every value of a list or a range is checked.
    for (flag, range) in [("--lambda", ranges::LAMBDA), ("--phi", ranges::PHI)] {
        let (inside, beyond) = real_ends(range);
        for command in ["sweep", "figure"] {
            let head: &[&str] = if command == "figure" {
                &["shakedown", "figure", "fig3"]
            } else {
                &["shakedown", "sweep"]
            };
            let with = |value: &str| {
                let mut argv = head.to_vec();
                argv.extend([flag, value]);
                argv.iter().map(|s| s.to_string()).collect::<Vec<_>>()
            };
            parses(&with(&format!("{},{}", inside[0], inside[1])));
            for v in beyond {
                let text = format!("{},{v}", inside[0]);
                let line = refused(&with(&text));
                assert!(line.starts_with(&format!("{flag} {text}: ")), "{line}");
                assert!(line.contains(range.expected), "{line}");
            }
        }
        let range_text = format!("{}:{}:{}", inside[0], inside[1], inside[1] - inside[0]);
        parses(&["shakedown", "sweep", flag, &range_text]);
    }
    // The centre: each coordinate.
    let (inside, beyond) = real_ends(ranges::CENTER);
    parses(&[
        "shakedown",
        "run",
        "--center",
        &format!("{},{}", inside[0], inside[1]),
    ]);
    for v in beyond {
        let text = format!("0,{v}");
        let line = refused(&["shakedown", "run", "--center", &text]);
        assert!(line.starts_with(&format!("--center {text}: ")), "{line}");
        assert!(line.contains(ranges::CENTER.expected), "{line}");
    }
    let counts = [
        ("run", "--nodes", ranges::NODES),
        ("sweep", "--nodes", ranges::NODES),
        ("run", "--steps", ranges::STEPS),
        ("run", "--max-cycles", ranges::MAX_CYCLES),
        ("limit", "--samples", ranges::SAMPLES),
        ("design", "--vertices", ranges::VERTICES),
        ("design", "--particles", ranges::PARTICLES),
        ("design", "--iterations", ranges::ITERATIONS),
    ];
    for (command, flag, range) in counts {
        // An even-only range's neighbours are odd: step over them.
        let gap = if range.even { 2 } else { 1 };
        for v in [range.min, range.max] {
            parses(&["shakedown", command, flag, &v.to_string()]);
        }
        let mut beyond = vec![range.max + gap];
        if range.min >= gap {
            beyond.push(range.min - gap);
        }
        for v in beyond {
            let text = v.to_string();
            let line = refused(&["shakedown", command, flag, &text]);
            assert!(line.starts_with(&format!("{flag} {text}: ")), "{line}");
            assert!(line.contains(range.expected), "{line}");
        }
    }
}

/// A value that does not read as a number is refused by the same parser,
/// with what the flag accepts.
#[test]
fn unreadable_values_quote_the_range() {
    for (flag, value, range) in [
        ("--friction", "nan", ranges::FRICTION.expected),
        ("--nodes", "x", ranges::NODES.expected),
        ("--phi", "abc", ranges::PHI.expected),
        ("--max-cycles", "-1", ranges::MAX_CYCLES.expected),
    ] {
        let line = refused(&["shakedown", "run", flag, value]);
        assert!(line.starts_with(&format!("{flag} {value}: ")), "{line}");
        assert!(line.contains(range), "{flag}: {line}");
    }
}

/// The slow-grid warning quotes the measured case the runs are like: an
/// in-phase cycle the fast one, an ellipse the slow one, and a sweep over
/// both (or a polyline) the range between them.
#[test]
fn the_cost_class_follows_the_phases() {
    use std::f64::consts::PI;
    let p = CaseParams::default();
    assert_eq!(CostClass::of(&p, &[0.0]), CostClass::Line);
    assert_eq!(CostClass::of(&p, &[0.0, PI]), CostClass::Line);
    assert_eq!(CostClass::of(&p, &[0.5 * PI]), CostClass::Ellipse);
    assert_eq!(CostClass::of(&p, &[0.0, 0.5 * PI]), CostClass::Mixed);
    // Each class's figure is that of its measured case at 4096 nodes.
    let (fast, slow) = expected_run_seconds(4096, 400);
    assert!((fast - 12.35).abs() < 1e-9 && (slow - 182.6).abs() < 1e-9);
}
