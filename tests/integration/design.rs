//! `shakedown design` (docs/model.md section 10): the path it reports
//! reproduces its state through `run`, a search is deterministic for a seed
//! and any thread count, a shakedown it reports is proven, its paths stay in
//! the admissible region, and no path shakes down above `lambda_2`.

use std::f64::consts::PI;

use serde_json::Value;
use shakedown::analysis::case::{Case, CaseParams};
use shakedown::analysis::design::{search, Budget, Family, Region, Runner, Shape};
use shakedown::analysis::limit::shakedown_limit;
use shakedown::analysis::ordered::Interrupt;

use super::common::{shakedown, stdout};

/// A coarse grid keeps each run to a few milliseconds.
const GRID: [&str; 4] = ["--nodes", "32", "--steps", "100"];

fn design(extra: &[&str]) -> Value {
    let mut args = vec!["design", "--json"];
    args.extend(GRID);
    args.extend(extra);
    let o = shakedown(&args);
    assert!(o.status.success(), "{}", super::common::stderr(&o));
    serde_json::from_str(&stdout(&o)).unwrap()
}

fn check_proven(v: &Value) {
    if v["state"] == "shakedown" {
        match v["approach"].as_str().unwrap() {
            "no-slip-cycle" => {}
            "safe-state" => {
                let c = &v["certificate"];
                let margin = c["margin"].as_f64().unwrap();
                let bound = c["coupling"].as_f64().unwrap() * c["distance"].as_f64().unwrap();
                assert!(margin > bound, "{c}");
            }
            other => panic!("shakedown by {other}"),
        }
    }
}

fn check_region(v: &Value) {
    for p in v["path"].as_array().unwrap() {
        let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
        assert!(y.abs() < 2.0 * PI, "({x}, {y}) beyond gross slip");
        assert!(x.abs() <= v["region"]["x_max"].as_f64().unwrap());
    }
}

#[test]
fn the_designed_path_reproduces_its_state_through_run() {
    let v = design(&[
        "--lambda",
        "4.3",
        "--vertices",
        "2",
        "--particles",
        "4",
        "--iterations",
        "2",
    ]);
    assert_eq!(v["reproduced"], true);
    assert_eq!(v["state"], "shakedown", "{v}");
    check_proven(&v);
    check_region(&v);
    assert_eq!(v["path"].as_array().unwrap().len(), 2);
    // The same text through `run` itself.
    let text = v["initial_path"].as_str().unwrap();
    let mut args = vec!["run", "--json", "--lambda", "4.3", "--initial-path", text];
    args.extend(GRID);
    let o = shakedown(&args);
    assert!(o.status.success());
    let r: Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(r["state"], v["state"]);
    assert_eq!(r["dissipation"], v["dissipation"]);
    assert_eq!(r["cycles"], v["cycles"]);
}

#[test]
fn a_search_is_deterministic_for_a_seed_and_any_thread_count() {
    // Above lambda_2 of this grid nothing shakes down, so the search runs
    // its whole budget and the least W decides.
    let flags = [
        "--lambda",
        "5.3",
        "--vertices",
        "2",
        "--particles",
        "6",
        "--iterations",
        "2",
        "--seed",
        "7",
        "--family",
        "decaying",
    ];
    let run = |threads: &str| {
        let mut args = vec!["design", "--json"];
        args.extend(GRID);
        args.extend(flags);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_shakedown"))
            .args(&args)
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<Value>(&o.stdout).unwrap()
    };
    let (a, b) = (run("1"), run("2"));
    assert_eq!(a["initial_path"], b["initial_path"]);
    assert_eq!(a["dissipation"], b["dissipation"]);
    assert_eq!(a["evaluations"], 18);
    assert_ne!(a["state"], "shakedown");
    assert_eq!(a["reproduced"], true);
    check_region(&a);
}

#[test]
fn no_path_shakes_down_above_lambda_2() {
    let params = CaseParams {
        nodes: 32,
        steps: 100,
        ..CaseParams::default()
    };
    let case = Case::from_params(&params).unwrap();
    let c = &case.cycle();
    let limit = shakedown_limit(
        &case.material(),
        c.center(),
        c.slope(),
        c.phase(),
        &case.disc(),
        64,
    )
    .unwrap();
    let runner = Runner::new(&case);
    let shape = Shape::new(
        Family::Free,
        2,
        Region::for_material(&case.material()),
        c.center(),
    )
    .unwrap();
    let budget = Budget::new(8, 2, 3).unwrap();
    let stop = Interrupt::new();
    let found = search(
        &runner,
        shape,
        limit.load_factor * 1.01,
        budget,
        &[],
        &stop,
        &|_| {},
    )
    .unwrap();
    let best = found.best.unwrap();
    assert!(!best.shakes_down(), "{:?}", best.path);
    assert_eq!(found.evaluations, 24);
    // Below it the paper's best transients find shakedown at once.
    let found = search(
        &runner,
        shape,
        0.9 * limit.load_factor,
        budget,
        &[],
        &stop,
        &|_| {},
    )
    .unwrap();
    assert!(found.best.unwrap().shakes_down());
}

/// `--gross-gap G` keeps every vertex at least `G` inside the gross-slip
/// line, and the report's region says so.
#[test]
fn a_wider_gross_gap_keeps_every_vertex_inside_it() {
    let v = design(&[
        "--lambda",
        "4.3",
        "--vertices",
        "3",
        "--particles",
        "6",
        "--iterations",
        "2",
        "--gross-gap",
        "1.5",
    ]);
    let y_max = v["region"]["y_max"].as_f64().unwrap();
    assert!((y_max - (2.0 * PI - 1.5)).abs() < 1e-12, "{y_max}");
    for p in v["path"].as_array().unwrap() {
        assert!(p[1].as_f64().unwrap().abs() <= y_max, "{p}");
    }
}

#[test]
fn design_refuses_bad_input() {
    for (args, flag) in [
        (vec!["design"], "--lambda"),
        (
            vec!["design", "--lambda", "4.8", "--vertices", "0"],
            "--vertices",
        ),
        (
            vec!["design", "--lambda", "4.8", "--family", "spiral"],
            "--family",
        ),
        (
            vec!["design", "--lambda", "4.8", "--initial", "7,-7"],
            "--initial",
        ),
        (vec!["design", "--frontier", "--lambda", "4.8"], "--lambda"),
        (
            vec!["design", "--lambda", "4.8", "--gross-gap", "0"],
            "--gross-gap",
        ),
        (
            vec!["design", "--lambda", "4.8", "--gross-gap", "nan"],
            "--gross-gap",
        ),
    ] {
        let o = shakedown(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = super::common::stderr(&o);
        assert!(err.contains(flag), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}

/// `figure design --from` reads only the frontier's own table, through the
/// capped reader: another table, a FIFO and a missing file are refused
/// with one line and exit 2, and nothing is drawn.
#[test]
fn figure_design_refuses_what_is_not_a_frontier_table() {
    let dir = super::common::scratch("figure_design_from");
    let other = dir.join("other.csv");
    std::fs::write(
        &other,
        "# shakedown = 0.1.0\n# table = sweep\nlambda,phi,initial\n",
    )
    .unwrap();
    let missing = dir.join("missing.csv");
    for from in [&other, &missing, &std::path::PathBuf::from("/dev/zero")] {
        let o = shakedown(&["figure", "design", "--from", from.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{from:?}");
        let err = super::common::stderr(&o);
        assert!(err.contains("--from"), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    assert!(!dir.join("design.svg").exists());
}
