//! Sweep output must not depend on the number of threads.

use std::f64::consts::PI;
use std::process::Command;

fn sweep(threads: usize) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args([
            "sweep",
            "--lambda",
            "4.8,5.5,7",
            "--phi",
            "0,pi/2",
            "--initial",
            "OA,7,-7,-5,7",
            "--nodes",
            "64",
            "--steps",
            "200",
        ])
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

#[test]
fn same_bytes_whatever_the_thread_count() {
    let one = sweep(1);
    let two = sweep(2);
    let three = sweep(3);
    assert_eq!(one, two);
    assert_eq!(one, three);
    let text = String::from_utf8(one).unwrap();
    // The `# key = value` header says what made the file.
    assert!(text.starts_with("# shakedown = "));
    assert!(text.contains("\n# initial = OA 7,-7 -5,7\n"), "{text}");
    let mut lines = text.lines().skip_while(|l| l.starts_with('#'));
    assert_eq!(
        lines.next(),
        Some("lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 3 * 2 * 3);
    // Row order: lambda outermost, then phi, then the initial paths.
    assert!(rows[0].starts_with("4.8,0,\"OA\","));
    assert!(rows[3].starts_with(&format!("4.8,{},\"OA\",", PI / 2.0)));
    assert!(rows[6].starts_with("5.5,0,\"OA\","));
}

/// The data rows of `shakedown sweep` with `args` (header and metadata
/// left out), on two threads.
fn sweep_rows(args: &[&str]) -> Vec<String> {
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .arg("sweep")
        .args(args)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .expect("the binary runs");
    assert!(out.status.success());
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .skip_while(|l| l.starts_with('#'))
        .skip(1)
        .map(str::to_string)
        .collect()
}

/// A row's `lambda`, `phi`, initial path and the fields after it:
/// `state,dissipation,cycles,rotation_per_cycle`.
fn fields(row: &str) -> (&str, &str, &str, Vec<&str>) {
    let (head, rest) = row.split_once(",\"").unwrap();
    let (initial, rest) = rest.split_once("\",").unwrap();
    let (lambda, phi) = head.split_once(',').unwrap();
    (lambda, phi, initial, rest.split(',').collect())
}

/// `shakedown run --json` of one case.
fn run_json(lambda: &str, phi: &str, initial: &str) -> serde_json::Value {
    let run = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(["run", "--lambda", lambda, "--phi", phi, "--json"])
        .arg(format!("--initial={initial}"))
        .output()
        .expect("the binary runs");
    assert!(run.status.success(), "{lambda} {phi} {initial}");
    serde_json::from_slice(&run.stdout).unwrap()
}

fn number(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| panic!("a number: '{s}'"))
}

/// `shakedown run` of one case gives that case's row in a sweep: the same
/// state and cycles, and for the first initial path of each `lambda` and
/// `phi` the very numbers (the sweep starts every `lambda` and `phi` of an
/// initial path from one contact prepared at `A`, and a run from `O` passes
/// through the same state there, solver caches included). A later path of
/// the group starts with the slip rates its predecessors cached, which a
/// hit gives to round-off of a new solve: its `W` and rotation agree to
/// round-off, not to the bit. (The cases are ones whose `W` differed in the
/// last digits while a run kept the caches of its initial path and the
/// sweep did not.)
#[test]
fn a_run_gives_the_numbers_of_its_sweep_row() {
    let rows = sweep_rows(&[
        "--lambda",
        "5.05,6.85,7.05",
        "--phi",
        "0,0.3pi",
        "--initial",
        "7,-7,-5,5,-7,3",
    ]);
    assert_eq!(rows.len(), 3 * 2 * 3);
    for row in &rows {
        let (lambda, phi, initial, fields) = fields(row);
        let json = run_json(lambda, phi, initial);
        assert_eq!(json["state"], fields[0], "{row}");
        assert_eq!(json["cycles"], number(fields[2]) as u64, "{row}");
        for (key, text) in [
            ("dissipation", fields[1]),
            ("rotation_per_cycle", fields[3]),
        ] {
            let (from_run, from_sweep) = (json[key].as_f64().unwrap(), number(text));
            if initial == "7,-7" {
                assert_eq!(
                    from_run.to_bits(),
                    from_sweep.to_bits(),
                    "{key} of {row}: run gives {from_run:e}"
                );
            } else {
                assert!(
                    (from_run - from_sweep).abs() <= 1e-8 * from_sweep.abs() + 1e-16,
                    "{key} of {row}: run gives {from_run:e}"
                );
            }
        }
    }
}

/// Runs of a group that meet (at `lambda = 5`, `phi = 0` these four
/// transients start cycle 2 in one state, `docs/model.md` section 3.3)
/// take the cycles of the first of them in a sweep, and `shakedown run`
/// steps each of them alone: the rows have the state and cycles `run`
/// gives, and its `W` and rotation to round-off.
#[test]
fn runs_that_meet_keep_the_rows_run_gives() {
    let rows = sweep_rows(&["--lambda", "5", "--phi", "0", "--initial=OA,7,3,5,5,-7,-3"]);
    assert_eq!(rows.len(), 4);
    let mut dissipations = Vec::new();
    for row in &rows {
        let (lambda, phi, initial, fields) = fields(row);
        let json = run_json(lambda, phi, initial);
        assert_eq!(json["state"], fields[0], "{row}");
        assert_eq!(json["state"], "cyclic-slip", "{row}");
        assert_eq!(json["cycles"], number(fields[2]) as u64, "{row}");
        let w = number(fields[1]);
        let from_run = json["dissipation"].as_f64().unwrap();
        assert!(
            (from_run - w).abs() <= 1e-10 * w,
            "{row}: run gives {from_run:e}"
        );
        let from_run = json["rotation_per_cycle"].as_f64().unwrap();
        assert!(
            (from_run - number(fields[3])).abs() <= 1e-10 * w,
            "{row}: run gives {from_run:e}"
        );
        dissipations.push(w);
    }
    // The rows of the runs that met carry the first run's W.
    assert!(
        dissipations.iter().all(|&w| w == dissipations[0]),
        "{dissipations:?}"
    );
}
