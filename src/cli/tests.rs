//! Tests of the parent module.

use clap::CommandFactory;

use super::*;

#[test]
fn command_line_definition_is_consistent() {
    // Duplicate flags and the like panic here rather than at run time.
    Cli::command().debug_assert();
}

fn run_case(args: &[&str]) -> Result<(CaseParams, Case)> {
    let mut argv = vec!["shakedown", "run"];
    argv.extend_from_slice(args);
    match Cli::try_parse_from(argv).unwrap().command {
        Some(Command::Run(a)) => a.case.case(CaseParams::default()),
        _ => unreachable!(),
    }
}

/// Every case flag's error names the flag and the value, and quotes the
/// range the library checked (`model::ranges`, the one place it is
/// written): a value just outside it is refused by the library itself.
#[test]
fn flag_errors_quote_the_range_the_library_checked() {
    let cases = [
        ("lambda", "-1"),
        ("phi", "2000"),
        ("psi", "1e7"),
        ("center", "2000,0"),
        ("friction", "0"),
        ("friction", "11"),
        ("nu", "0.5"),
        ("nu", "-0.1"),
        ("nodes", "7"),
        ("steps", "3"),
        ("max-cycles", "0"),
    ];
    for (flag, value) in cases {
        let long = format!("--{flag}");
        let e = run_case(&[&long, value]).unwrap_err();
        assert!(is_input_error(&e), "{flag}");
        let message = one_line(&e);
        assert!(
            message.starts_with(&format!("--{flag} {value}: ")),
            "{message}"
        );
        let library = message.split("expected ").nth(1).expect(&message);
        let ours = accepted(flag).unwrap();
        assert!(ours.contains(library), "{flag}: '{ours}' vs '{library}'");
    }
}

#[test]
fn unreadable_values_quote_the_range() {
    for (flag, value) in [("friction", "nan"), ("nodes", "x"), ("phi", "abc")] {
        let long = format!("--{flag}");
        let e = run_case(&[&long, value]).unwrap_err();
        let message = one_line(&e);
        assert!(is_input_error(&e));
        assert!(
            message.contains(accepted(flag).unwrap()),
            "{flag}: {message}"
        );
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
