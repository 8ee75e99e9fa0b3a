//! A catalogue of bad inputs. Each is rejected before any work starts with
//! exactly one line on stderr, `error: ...`, that names the flag or file
//! and what it accepts; exit status 2; no panic, no backtrace, nothing on
//! stdout.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

fn shakedown(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(args)
        .stdin(Stdio::null())
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("the binary runs")
}

/// Run `args`, expect the rejection, and check that the one error line
/// contains every piece of `names`. Returns the line.
#[track_caller]
fn rejected(args: &[&str], names: &[&str]) -> String {
    let out = shakedown(args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert_eq!(
        out.status.code(),
        Some(2),
        "{args:?}: status; stderr:\n{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{args:?}: panic:\n{stderr}");
    assert!(
        !stderr.contains("RUST_BACKTRACE"),
        "{args:?}: backtrace note:\n{stderr}"
    );
    assert!(!stderr.contains("stack backtrace"), "{args:?}:\n{stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: one line expected:\n{stderr}");
    assert!(lines[0].starts_with("error: "), "{args:?}: {}", lines[0]);
    for name in names {
        assert!(
            lines[0].contains(name),
            "{args:?}: '{name}' missing from: {}",
            lines[0]
        );
    }
    assert!(stdout.is_empty(), "{args:?}: stdout: {stdout}");
    lines[0].to_string()
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shakedown-bad-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

// ---------------------------------------------------------------------
// Case flags, through `run` and `sweep` alike.
// ---------------------------------------------------------------------

#[test]
fn negative_load_factor() {
    rejected(
        &["run", "--lambda", "-1"],
        &["--lambda -1", "0 <= lambda <= 1000"],
    );
    rejected(
        &["sweep", "--lambda", "-1:2:1"],
        &["--lambda -1:2:1", "0 <= lambda <= 1000"],
    );
    rejected(
        &["sweep", "--lambda", "3,x"],
        &["--lambda 3,x", "0 <= lambda <= 1000"],
    );
}

#[test]
fn friction_zero_and_not_a_number() {
    for cmd in ["run", "sweep"] {
        rejected(&[cmd, "--friction", "0"], &["--friction 0", "0 < f <= 10"]);
        rejected(
            &[cmd, "--friction", "nan"],
            &["--friction nan", "0 < f <= 10"],
        );
    }
    rejected(
        &["run", "--friction", "inf"],
        &["--friction inf", "0 < f <= 10"],
    );
}

#[test]
fn incompressible_poisson_ratio() {
    for cmd in ["run", "sweep"] {
        rejected(&[cmd, "--nu", "0.5"], &["--nu 0.5", "0 <= nu < 0.5"]);
    }
}

#[test]
fn node_counts() {
    for cmd in ["run", "sweep"] {
        for n in ["7", "100000", "8", "17", "-4", "many"] {
            let flag = format!("--nodes {n}");
            rejected(
                &[cmd, "--nodes", n],
                &[&flag, "even number from 16 to 4096"],
            );
        }
    }
}

#[test]
fn phase_that_is_not_an_angle() {
    rejected(
        &["run", "--phi", "abc"],
        &["--phi abc", "multiples of pi", "|phi| <= 1000"],
    );
    rejected(
        &["sweep", "--phi", "0:abc:1"],
        &["--phi 0:abc:1", "start:stop:step"],
    );
    rejected(&["run", "--phi", "pi/0"], &["--phi pi/0"]);
}

#[test]
fn initial_points_outside_the_paper_set() {
    for cmd in ["run", "sweep"] {
        rejected(
            &[cmd, "--initial", "9,9"],
            &["--initial 9,9", "3, 5 or 7", "|a|+|b| > 8"],
        );
        rejected(
            &[cmd, "--initial", "3,3"],
            &["--initial 3,3", "stick region", "|a|+|b| > 8"],
        );
        rejected(&[cmd, "--initial", "nowhere"], &["--initial nowhere", "OA"]);
    }
    rejected(
        &["sweep", "--initial", "OA,7"],
        &["--initial OA,7", "two numbers"],
    );
}

#[test]
fn other_case_flags() {
    rejected(&["run", "--steps", "3"], &["--steps 3", "16 to 100000"]);
    rejected(
        &["run", "--max-cycles", "0"],
        &["--max-cycles 0", "1 to 100000"],
    );
    rejected(
        &["run", "--plane", "membrane"],
        &["--plane membrane", "strain or stress"],
    );
    rejected(&["run", "--psi", "1e9"], &["--psi 1e9", "|psi| <= 1e6"]);
    rejected(
        &["run", "--center", "1"],
        &["--center 1", "|x0|, |y0| <= 1000"],
    );
    rejected(
        &["run", "--center", "1e4,0"],
        &["--center 1e4,0", "|x0|, |y0| <= 1000"],
    );
    rejected(
        &["run", "--lambda", "1e400"],
        &["--lambda 1e400", "0 <= lambda <= 1000"],
    );
}

#[test]
fn command_line_syntax_errors_are_one_line_too() {
    rejected(&["run", "--no-such-flag"], &["--no-such-flag"]);
    rejected(&["run", "--nodes"], &["--nodes"]);
    rejected(&["frobnicate"], &["frobnicate"]);
}

// ---------------------------------------------------------------------
// Files and batch flags.
// ---------------------------------------------------------------------

#[test]
fn unwritable_output_file() {
    let dir = temp_dir("out");
    let missing = dir.join("no-such-dir").join("map.csv");
    let missing = missing.to_str().unwrap();
    let line = rejected(&["sweep", "--out", missing], &["--out", "writable file"]);
    assert!(line.contains(missing), "{line}");
    // A directory is not a file either.
    rejected(
        &["sweep", "--out", dir.to_str().unwrap()],
        &["--out", "writable file"],
    );
    let shard = dir.join("s.csv");
    std::fs::write(
        &shard,
        "lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle\n7,0,\"OA\",shakedown,0,1,0\n",
    )
    .unwrap();
    rejected(
        &["merge", shard.to_str().unwrap(), "--out", missing],
        &["--out", "writable file"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_shards() {
    for s in ["0/4", "5/4", "1/0"] {
        let flag = format!("--shard {s}");
        rejected(&["sweep", "--shard", s], &[&flag, "1 <= K <= N"]);
    }
    rejected(&["sweep", "--shard", "two"], &["--shard two", "K/N"]);
}

#[test]
fn resume_needs_a_file_of_the_same_sweep() {
    rejected(&["sweep", "--resume"], &["--resume", "--out"]);
    let dir = temp_dir("resume");
    let foreign = dir.join("notes.csv");
    std::fs::write(&foreign, "these are my notes\n").unwrap();
    let path = foreign.to_str().unwrap();
    rejected(
        &["sweep", "--resume", "--out", path],
        &["--out", path, "header"],
    );
    // Untouched: a foreign file is never overwritten.
    assert_eq!(
        std::fs::read_to_string(&foreign).unwrap(),
        "these are my notes\n"
    );
    // Rows of another grid.
    let header = "lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle";
    let other = dir.join("other.csv");
    std::fs::write(&other, format!("{header}\n2,0,\"OA\",shakedown,0,1,0\n")).unwrap();
    rejected(
        &[
            "sweep",
            "--lambda",
            "3",
            "--resume",
            "--out",
            other.to_str().unwrap(),
        ],
        &["--out", "different flags"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn merge_of_missing_or_incomplete_shards() {
    let dir = temp_dir("merge");
    let missing = dir.join("missing.csv");
    let m = missing.to_str().unwrap();
    rejected(&["merge", m], &[m, "cannot read"]);
    let header = "lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle";
    let part = dir.join("part.csv");
    std::fs::write(&part, format!("{header}\n1,0,\"OA\",shakedown,0,1,0\n")).unwrap();
    let p = part.to_str().unwrap();
    rejected(
        &["merge", p, "--lambda", "1,2"],
        &["1 of 2 runs", "2,0,\"OA\""],
    );
    rejected(&["merge", p, p, "--lambda", "1,2"], &[p, "line 2", "twice"]);
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "x,y\n").unwrap();
    let b = bad.to_str().unwrap();
    rejected(&["merge", b], &[b, "header"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------------
// Presets: `--preset NAME|FILE` on `run`, `sweep` and `tui`. A preset has a
// required `description`, an optional `name`, and tables `[case]`,
// `[sweep]` and `[figure]` whose keys are the long flag names.
// ---------------------------------------------------------------------

fn preset_file(name: &str, text: &str) -> (PathBuf, String) {
    let dir = temp_dir(&format!("preset-{name}"));
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let shown = path.to_str().unwrap().to_string();
    (path, shown)
}

#[test]
fn unknown_preset() {
    rejected(
        &["run", "--preset", "no-such-preset"],
        &["--preset no-such-preset"],
    );
}

#[test]
fn preset_with_a_wrong_type() {
    let (_, path) = preset_file(
        "wrong-type",
        "description = \"d\"\n[case]\nlambda = \"seven\"\nphi = 0.0\n",
    );
    rejected(&["run", "--preset", &path], &[&path, "lambda"]);
}

#[test]
fn preset_with_a_missing_field() {
    // A preset must say what it is about: `description` is required.
    let (_, path) = preset_file("missing", "name = \"x\"\n[case]\nlambda = 5.1\n");
    rejected(
        &["run", "--preset", &path],
        &[&path, "missing", "description"],
    );
}

#[test]
fn preset_with_an_unknown_key() {
    let (_, path) = preset_file(
        "unknown-key",
        "description = \"d\"\n[case]\nlambda = 5.1\nlamda = 5.2\n",
    );
    rejected(&["run", "--preset", &path], &[&path, "lamda"]);
}

#[test]
fn preset_values_out_of_range_name_the_file() {
    let (_, path) = preset_file(
        "range",
        "description = \"d\"\n[case]\nlambda = 5.1\nnodes = 7\n",
    );
    rejected(&["run", "--preset", &path], &[&path, "nodes", "16 to 4096"]);
}

// ---------------------------------------------------------------------
// The terminal explorer. Here stdin is /dev/null and stdout a pipe, so
// neither is a terminal.
// ---------------------------------------------------------------------

#[test]
fn tui_without_a_terminal() {
    rejected(&["tui"], &["terminal", "stdin", "stdout"]);
    rejected(&[], &["terminal", "stdin", "stdout"]);
    // Bad flags are still reported first, as bad flags.
    rejected(&["tui", "--nodes", "7"], &["--nodes 7", "16 to 4096"]);
}
