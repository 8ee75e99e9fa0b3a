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
    std::fs::write(&shard, "").unwrap();
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
    // A file of another grid: the header names the differing key.
    let other = dir.join("other.csv");
    let made = shakedown(&[
        "sweep",
        "--lambda",
        "2",
        "--nodes",
        "16",
        "--steps",
        "32",
        "--out",
        other.to_str().unwrap(),
    ]);
    assert!(made.status.success());
    let before = std::fs::read(&other).unwrap();
    rejected(
        &[
            "sweep",
            "--lambda",
            "3",
            "--nodes",
            "16",
            "--steps",
            "32",
            "--resume",
            "--out",
            other.to_str().unwrap(),
        ],
        &["--out", "lambda = 2", "lambda = 3"],
    );
    assert_eq!(std::fs::read(&other).unwrap(), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn merge_of_missing_or_incomplete_shards() {
    let dir = temp_dir("merge");
    let missing = dir.join("missing.csv");
    let m = missing.to_str().unwrap();
    rejected(&["merge", m], &[m, "cannot read"]);
    let part = dir.join("part.csv");
    let grid = ["--lambda", "1,2", "--nodes", "16", "--steps", "32"];
    let made = shakedown(
        &[
            &["sweep", "--shard", "1/2", "--out", part.to_str().unwrap()][..],
            &grid,
        ]
        .concat(),
    );
    assert!(made.status.success());
    let p = part.to_str().unwrap();
    let first_row = std::fs::read_to_string(&part)
        .unwrap()
        .lines()
        .position(|l| l.starts_with("1,0,"))
        .unwrap()
        + 1;
    rejected(
        &[&["merge", p][..], &grid].concat(),
        &["1 of 2 runs", "2,0,\"OA\""],
    );
    let line = format!("line {first_row}");
    rejected(
        &[&["merge", p, p][..], &grid].concat(),
        &[p, &line, "twice"],
    );
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

// ---------------------------------------------------------------------
// Issue 11: batch output never mixes, destroys or loses results. Each
// case checks the exit status, the one-line message and that no file
// changed.
// ---------------------------------------------------------------------

/// A quick grid: 2 runs.
const QUICK: &[&str] = &[
    "--lambda",
    "3,4",
    "--initial",
    "OA",
    "--nodes",
    "16",
    "--steps",
    "32",
    "--max-cycles",
    "40",
];

/// Every file under `dir` with its bytes.
fn snapshot(dir: &std::path::Path) -> std::collections::BTreeMap<PathBuf, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let p = e.path();
            let Ok(meta) = std::fs::metadata(&p) else {
                continue;
            };
            if meta.is_dir() {
                out.extend(snapshot(&p));
            } else if meta.is_file() {
                out.insert(p.clone(), std::fs::read(&p).unwrap_or_default());
            }
        }
    }
    out
}

/// `rejected`, and nothing under `dir` changed.
#[track_caller]
fn rejected_untouched(dir: &std::path::Path, args: &[&str], names: &[&str]) -> String {
    let before = snapshot(dir);
    let line = rejected(args, names);
    assert_eq!(snapshot(dir), before, "{args:?} changed a file");
    line
}

/// Exit status 1 (an environment failure) with one `error:` line naming
/// every piece of `names`.
#[track_caller]
fn failed(args: &[&str], names: &[&str]) -> String {
    let out = shakedown(args);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors.len(), 1, "{args:?}: {stderr}");
    for name in names {
        assert!(errors[0].contains(name), "'{name}' missing: {}", errors[0]);
    }
    errors[0].to_string()
}

fn args_with<'a>(head: &[&'a str], tail: &[&'a str]) -> Vec<&'a str> {
    [head, tail].concat()
}

/// A finished quick sweep in `dir/name`, with `extra` flags.
fn quick_sweep(dir: &std::path::Path, name: &str, extra: &[&str]) -> PathBuf {
    let path = dir.join(name);
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--out", path.to_str().unwrap()]);
    let out = shakedown(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    path
}

fn cut_last_row(path: &std::path::Path) {
    let text = std::fs::read_to_string(path).unwrap();
    let keep = text.trim_end().rfind('\n').unwrap() + 1;
    std::fs::write(path, &text[..keep]).unwrap();
}

#[test]
fn issue11_01_resume_refuses_another_model() {
    let dir = temp_dir("i11-01");
    let f = quick_sweep(&dir, "f.csv", &[]);
    cut_last_row(&f);
    let p = f.to_str().unwrap();
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--friction", "0.2", "--resume", "--out", p]);
    rejected_untouched(&dir, &args, &[p, "friction = 0.2"]);
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--plane", "stress", "--resume", "--out", p]);
    rejected_untouched(&dir, &args, &[p, "plane = stress"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_02_merge_refuses_shards_of_another_model() {
    let dir = temp_dir("i11-02");
    let a = quick_sweep(&dir, "a.csv", &["--shard", "1/2"]);
    let b = quick_sweep(&dir, "b.csv", &["--shard", "2/2", "--friction", "0.2"]);
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    let out = dir.join("m.csv");
    let mut args = args_with(&["merge", a, b], QUICK);
    args.extend_from_slice(&["--out", out.to_str().unwrap()]);
    rejected_untouched(&dir, &args, &[b, "friction"]);
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_03_a_corrupt_row_is_refused_by_resume_and_merge() {
    let dir = temp_dir("i11-03");
    let f = quick_sweep(&dir, "f.csv", &[]);
    let text = std::fs::read_to_string(&f).unwrap();
    let comments = text.lines().filter(|l| l.starts_with('#')).count();
    let mut lines: Vec<&str> = text.lines().collect();
    let bad_line = comments + 2; // 1-based: the first row
    lines[bad_line - 1] = "3,0,\"7,-7\",GARBAGE,xx,yy,zz";
    std::fs::write(&f, lines.join("\n") + "\n").unwrap();
    let p = f.to_str().unwrap();
    let line = format!("line {bad_line}");
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--resume", "--out", p]);
    rejected_untouched(&dir, &args, &[p, &line, "GARBAGE"]);
    let args = args_with(&["merge", p], QUICK);
    rejected_untouched(&dir, &args, &[p, &line, "GARBAGE"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_04_an_existing_output_is_not_truncated() {
    let dir = temp_dir("i11-04");
    let f = quick_sweep(&dir, "f.csv", &[]);
    let p = f.to_str().unwrap();
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--out", p]);
    rejected_untouched(&dir, &args, &[p, "--resume", "--force"]);
    // --force replaces it (same flags, same bytes).
    let before = std::fs::read(&f).unwrap();
    args.push("--force");
    assert!(shakedown(&args).status.success());
    assert_eq!(std::fs::read(&f).unwrap(), before);
    // A preset is never its own output.
    let preset = dir.join("my.toml");
    std::fs::write(&preset, "description = \"d\"\n[sweep]\nlambda = [3]\n").unwrap();
    let pr = preset.to_str().unwrap();
    rejected_untouched(
        &dir,
        &["sweep", "--preset", pr, "--out", pr, "--force"],
        &["--out", "preset"],
    );
    // A figure made before is refused as a whole set.
    let figdir = dir.join("fig");
    std::fs::create_dir_all(&figdir).unwrap();
    std::fs::write(figdir.join("fig3.csv"), "my finished map\n").unwrap();
    rejected_untouched(
        &dir,
        &[
            "figure",
            "fig3",
            "--out",
            figdir.to_str().unwrap(),
            "--lambda",
            "4",
        ],
        &["fig3.csv", "--force"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_05_merge_onto_its_own_input_is_refused() {
    let dir = temp_dir("i11-05");
    let f = quick_sweep(&dir, "f.csv", &[]);
    let p = f.to_str().unwrap();
    let mut args = args_with(&["merge", p], QUICK);
    args.extend_from_slice(&["--out", p, "--force"]);
    rejected_untouched(&dir, &args, &["--out", p, "input"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_06_a_second_writer_is_refused() {
    let dir = temp_dir("i11-06");
    let f = dir.join("map.csv");
    let p = f.to_str().unwrap();
    let mut first = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args([
            "sweep",
            "--lambda",
            "3:7.4:0.1",
            "--initial",
            "all",
            "--nodes",
            "32",
            "--steps",
            "64",
            "--out",
            p,
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let lock = dir.join("map.csv.lock");
    let start = std::time::Instant::now();
    while std::fs::read_to_string(&lock).map_or(true, |t| t.trim().is_empty()) {
        assert!(start.elapsed().as_secs() < 30, "no lock appears");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--out", p, "--force"]);
    let line = rejected(&args, &[p, "map.csv.lock", "another process"]);
    assert!(line.contains(&first.id().to_string()), "{line}");
    let _ = first.kill();
    let _ = first.wait();
    // The lock dies with its holder, even killed: the next writer may go.
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--out", p, "--force"]);
    assert!(shakedown(&args).status.success());
    assert!(!lock.exists(), "the lock file is removed on exit");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_07_a_preset_name_cannot_leave_the_output_folder() {
    let dir = temp_dir("i11-07");
    // `/tmp/x.csv` is outside the test's own folder: another program may
    // have one, so the test asks that it is left as it was.
    let outside = std::path::Path::new("/tmp/x.csv");
    let stamp = || {
        std::fs::metadata(outside)
            .ok()
            .map(|m| (m.len(), m.modified().ok()))
    };
    let before = stamp();
    for name in ["../x", "/tmp/x", "a/b", "..", "x\u{1b}[2J"] {
        let preset = dir.join("evil.toml");
        std::fs::write(
            &preset,
            format!(
                "name = \"{}\"\ndescription = \"d\"\n[sweep]\nlambda = [3]\n[figure]\nkind = \"dissipation\"\n",
                name.replace('\u{1b}', "\\u001B")
            ),
        )
        .unwrap();
        let out = dir.join("out");
        let line = rejected_untouched(
            &dir,
            &[
                "figure",
                preset.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            &["name"],
        );
        assert!(!line.contains('\u{1b}'), "{line}");
        assert!(!dir.join("x.csv").exists());
        assert_eq!(stamp(), before, "{name}: /tmp/x.csv was written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_08_limit_writes_only_with_out_and_refuses_unused_flags() {
    let dir = temp_dir("i11-08");
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(["limit", "--nodes", "16"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(snapshot(&dir).is_empty(), "limit wrote a file unasked");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(!text.contains("use it with --initial optimal"), "{text}");
    for (flag, v) in [
        ("--lambda", "5"),
        ("--initial", "OA"),
        ("--max-cycles", "3"),
    ] {
        rejected_untouched(&dir, &["limit", flag, v], &[flag, "limit does not use it"]);
    }
    // Its file is read back by --initial-slip, checked against --nodes.
    let g = dir.join("g.csv");
    let gs = g.to_str().unwrap();
    assert!(shakedown(&["limit", "--nodes", "16", "--out", gs])
        .status
        .success());
    let text = std::fs::read_to_string(&g).unwrap();
    assert!(text.starts_with("# shakedown = ") && text.contains("\n# table = optimal-slip\n"));
    let run = shakedown(&[
        "run",
        "--nodes",
        "16",
        "--steps",
        "32",
        "--lambda",
        "3",
        "--initial-slip",
        gs,
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    rejected_untouched(
        &dir,
        &["run", "--nodes", "32", "--initial-slip", gs],
        &["--initial-slip", "16 nodes", "--nodes 32"],
    );
    std::fs::write(dir.join("nan.csv"), "theta,g\n0,NaN\n").unwrap();
    let nan = dir.join("nan.csv");
    rejected_untouched(
        &dir,
        &[
            "sweep",
            "--nodes",
            "16",
            "--initial-slip",
            nan.to_str().unwrap(),
        ],
        &["--initial-slip", "line 2", "finite"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_09_limit_ends_at_every_accepted_sample_count() {
    for m in 3..=8 {
        let m = m.to_string();
        let mut child = Command::new(env!("CARGO_BIN_EXE_shakedown"))
            .args(["limit", "--phi", "pi/2", "--samples", &m, "--nodes", "16"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        let status = loop {
            if let Some(s) = child.try_wait().unwrap() {
                break s;
            }
            if start.elapsed().as_secs() > 30 {
                let _ = child.kill();
                panic!("limit --samples {m} does not end");
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        };
        assert!(status.success(), "--samples {m}");
    }
}

#[test]
fn issue11_10_grids_and_preset_arrays_are_capped() {
    let dir = temp_dir("i11-10");
    rejected_untouched(
        &dir,
        &[
            "sweep",
            "--lambda",
            "0:99.99:0.01",
            "--phi",
            "0:9.99:0.01",
            "--initial",
            "all",
        ],
        &["10000000", "250000000 runs"],
    );
    let many = vec!["3"; 100_001];
    let preset = dir.join("big.toml");
    std::fs::write(
        &preset,
        format!(
            "description = \"d\"\n[sweep]\nlambda = [{}]\n",
            many.join(",")
        ),
    )
    .unwrap();
    rejected_untouched(
        &dir,
        &["sweep", "--preset", preset.to_str().unwrap()],
        &["big.toml", "at most 100000"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_11_files_are_read_through_a_cap_and_only_if_regular() {
    let dir = temp_dir("i11-11");
    rejected_untouched(
        &dir,
        &["run", "--preset", "/dev/zero"],
        &["/dev/zero", "not a regular file"],
    );
    let fifo = dir.join("p.toml");
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .map(|s| s.success());
    if made.is_ok_and(|ok| ok) {
        rejected_untouched(
            &dir,
            &["run", "--preset", fifo.to_str().unwrap()],
            &["p.toml", "not a regular file"],
        );
        std::fs::remove_file(&fifo).unwrap();
    }
    let big = dir.join("big.toml");
    std::fs::write(&big, vec![b'#'; 2 << 20]).unwrap();
    rejected_untouched(
        &dir,
        &["run", "--preset", big.to_str().unwrap()],
        &["big.toml", "larger than"],
    );
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--resume", "--out", "/dev/zero"]);
    rejected(&args, &["/dev/zero"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `sh -c script`: status and stderr.
fn shell(script: &str) -> (Option<i32>, String) {
    let out = Command::new("sh")
        .arg("-c")
        .arg(script)
        .env("SHAKEDOWN", env!("CARGO_BIN_EXE_shakedown"))
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

/// Run `args` with stdout a pipe whose reader reads `lines` lines and
/// closes it; the status and stderr.
fn closed_pipe(args: &[&str], lines: usize) -> (Option<i32>, String) {
    use std::io::{BufRead, BufReader, Read};
    let mut child = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut reader = BufReader::new(child.stdout.take().unwrap());
    for _ in 0..lines {
        let mut line = String::new();
        let _ = reader.read_line(&mut line);
    }
    drop(reader);
    let mut stderr = String::new();
    let _ = child.stderr.take().unwrap().read_to_string(&mut stderr);
    (child.wait().unwrap().code(), stderr)
}

#[test]
fn issue11_12_a_closed_pipe_ends_quietly() {
    let dir = temp_dir("i11-12");
    let f = dir.join("f");
    let f = f.to_str().unwrap();
    let cases: [(&[&str], usize); 3] = [
        (&["presets"], 0),
        (&["limit", "--nodes", "16"], 0),
        (
            &[
                "figure",
                "fig3",
                "--out",
                f,
                "--lambda",
                "4",
                "--initial",
                "OA",
                "--nodes",
                "16",
                "--steps",
                "32",
            ],
            1,
        ),
    ];
    for (args, lines) in cases {
        let (code, stderr) = closed_pipe(args, lines);
        assert!(
            matches!(code, Some(0) | Some(141)),
            "{args:?}: {code:?} {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!stderr.contains("error"), "{args:?}: {stderr}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_13_a_full_disk_is_exit_1_everywhere() {
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    let dir = temp_dir("i11-13");
    let mut args = args_with(&["sweep"], QUICK);
    args.extend_from_slice(&["--out", "/dev/full"]);
    failed(&args, &["/dev/full"]);
    let f = quick_sweep(&dir, "f.csv", &[]);
    let mut args = args_with(&["merge", f.to_str().unwrap()], QUICK);
    args.extend_from_slice(&["--out", "/dev/full"]);
    failed(&args, &["/dev/full"]);
    failed(
        &["limit", "--nodes", "16", "--out", "/dev/full"],
        &["/dev/full"],
    );
    let (code, stderr) = shell("\"$SHAKEDOWN\" limit --nodes 16 > /dev/full");
    assert_eq!(code, Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    let (code, stderr) = shell("\"$SHAKEDOWN\" presets > /dev/full");
    assert_eq!(code, Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_14a_initial_point_overflow() {
    rejected(
        &["run", "--initial", "-2147483648,7"],
        &["--initial -2147483648,7"],
    );
    rejected(
        &["sweep", "--initial", "-2147483648,-2147483648"],
        &["--initial"],
    );
}

#[test]
fn issue11_14b_a_product_without_a_coefficient_is_not_an_angle() {
    rejected(&["run", "--phi", "*pi"], &["--phi *pi"]);
    rejected(&["sweep", "--phi", "0,-*pi"], &["--phi 0,-*pi"]);
}

#[test]
fn issue11_14c_control_characters_from_a_file_are_escaped() {
    let (_, path) = preset_file(
        "controls",
        "description = \"d\"\n[case]\ninitial = \"\\u001B[2J\\u0007\"\n",
    );
    let line = rejected(&["run", "--preset", &path], &[&path, "\\u{1b}"]);
    assert!(!line.chars().any(|c| c.is_control()), "{line:?}");
}

#[test]
fn issue11_14d_huge_numbers_are_shown_in_exponent_form() {
    let line = rejected(
        &["run", "--lambda", "1e300"],
        &["--lambda 1e300", "0 <= lambda <= 1000"],
    );
    assert!(line.len() < 200, "{line}");
}

#[test]
fn issue11_14e_figure_flags_and_presets_agree() {
    let dir = temp_dir("i11-14e");
    let out = dir.join("fig");
    rejected_untouched(
        &dir,
        &[
            "figure",
            "fig4",
            "--phi",
            "0,1",
            "--out",
            out.to_str().unwrap(),
        ],
        &["--phi 0,1", "single phase"],
    );
    assert!(!out.join("fig4.csv").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn issue11_14f_a_missing_argument_is_named() {
    rejected(&["merge"], &["SHARD.csv", "(see shakedown merge --help)"]);
    rejected(&["figure"], &["NAME|FILE", "(see shakedown figure --help)"]);
}

#[test]
fn issue11_14g_large_discretisations_warn_with_a_time() {
    // Warned on one line with an expected time, before the work (shard
    // 2/2 of one run is empty, so the test is quick).
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args([
            "sweep", "--nodes", "4096", "--steps", "16", "--lambda", "3", "--shard", "2/2",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let warning: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("warning"))
        .collect();
    assert_eq!(warning.len(), 1, "{stderr}");
    assert!(
        warning[0].contains("--nodes 4096") && warning[0].contains("expect about"),
        "{stderr}"
    );
    // Out of phase the estimate is the slow case's, about 3 min (the issue's
    // `run --lambda 6 --phi pi/2 --nodes 4096` took 183 s of CPU), not a
    // range and not seconds.
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args([
            "sweep", "--nodes", "4096", "--lambda", "6", "--phi", "pi/2", "--shard", "2/2",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("expect about 3 min of CPU per run"),
        "{stderr}"
    );
}

/// A flag a subcommand does not have points to that subcommand's help
/// (where the flags it has are listed), and clap's hint of a near name
/// stays on the one line.
#[test]
fn an_unknown_flag_points_to_the_help_of_its_subcommand() {
    rejected(
        &["sweep", "--poisson", "0"],
        &["'--poisson'", "(see shakedown sweep --help)"],
    );
    rejected(
        &["run", "--lamda", "5"],
        &["'--lamda'", "'--lambda'", "(see shakedown run --help)"],
    );
    rejected(&["--bogus"], &["'--bogus'", "(see shakedown --help)"]);
    // A flag without its value, too.
    rejected(
        &["sweep", "--nodes"],
        &["'--nodes <N>'", "(see shakedown sweep --help)"],
    );
}

// ---------------------------------------------------------------------
// No way round the guarantees (issue 65): every case asserts the exit
// status, the one-line message and that no file changed.
// ---------------------------------------------------------------------

/// Every file of `dir` (recursively one level is enough here) with its
/// bytes, or the target of a symlink.
fn files_of(dir: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            let meta = std::fs::symlink_metadata(e.path()).unwrap();
            let bytes = if meta.file_type().is_symlink() {
                let t = std::fs::read_link(e.path()).unwrap();
                format!("-> {}", t.display()).into_bytes()
            } else if meta.is_dir() {
                b"<dir>".to_vec()
            } else {
                std::fs::read(e.path()).unwrap()
            };
            (name, bytes)
        })
        .collect();
    out.sort();
    out
}

/// [`rejected`], run in `dir`, and nothing in `dir` changed.
#[track_caller]
fn refused_in(dir: &std::path::Path, args: &[&str], names: &[&str]) -> String {
    let before = files_of(dir);
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: one line expected:\n{stderr}");
    assert!(lines[0].starts_with("error: "), "{}", lines[0]);
    for name in names {
        assert!(
            lines[0].contains(name),
            "'{name}' missing from: {}",
            lines[0]
        );
    }
    assert_eq!(files_of(dir), before, "{args:?} changed a file");
    lines[0].to_string()
}

/// Run `args` in `dir` and expect success.
#[track_caller]
fn ok_in(dir: &std::path::Path, args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

const TINY: [&str; 8] = [
    "--nodes",
    "32",
    "--steps",
    "100",
    "--phi",
    "0",
    "--initial",
    "OA",
];

fn tiny_sweep<'a>(lambda: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["sweep", "--lambda", lambda];
    v.extend_from_slice(&TINY);
    v.extend_from_slice(extra);
    v
}

#[cfg(unix)]
#[test]
fn the_lock_belongs_to_the_file_not_its_name() {
    let dir = temp_dir("lock-links");
    ok_in(&dir, &tiny_sweep("3", &["--out", "x.csv"]));
    std::os::unix::fs::symlink("x.csv", dir.join("y.csv")).unwrap();
    std::fs::hard_link(dir.join("x.csv"), dir.join("z.csv")).unwrap();
    // Another process writing x.csv holds its lock (here: this one).
    let lock = shakedown::io::output::OutputLock::acquire(&dir.join("x.csv")).unwrap();
    let sym = tiny_sweep("3", &["--friction", "0.2", "--out", "y.csv", "--force"]);
    refused_in(&dir, &sym, &["--out y.csv", "another process"]);
    let hard = tiny_sweep("3", &["--friction", "0.2", "--out", "z.csv", "--force"]);
    refused_in(&dir, &hard, &["--out z.csv", "under another name"]);
    drop(lock);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[cfg(unix)]
#[test]
fn a_lock_path_that_is_a_link_or_a_folder_is_never_written() {
    let dir = temp_dir("lock-odd");
    std::fs::write(dir.join("v.txt"), "keep").unwrap();
    std::os::unix::fs::symlink("v.txt", dir.join("o.csv.lock")).unwrap();
    refused_in(
        &dir,
        &tiny_sweep("3", &["--out", "o.csv"]),
        &["--out o.csv", "o.csv.lock", "not a regular file"],
    );
    std::fs::create_dir(dir.join("OUT.lock")).unwrap();
    refused_in(
        &dir,
        &tiny_sweep("3", &["--out", "OUT"]),
        &["--out OUT", "OUT.lock", "not a regular file"],
    );
    refused_in(
        &dir,
        &["limit", "--nodes", "32", "--out", "o.csv"],
        &["--out o.csv", "not a regular file"],
    );
    // A name too long for `.lock` to be added still works.
    let long = format!("{}.csv", "n".repeat(251));
    ok_in(&dir, &tiny_sweep("3", &["--out", &long]));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[cfg(unix)]
#[test]
fn an_input_is_never_the_output_under_any_name() {
    let dir = temp_dir("input-output");
    ok_in(&dir, &["limit", "--nodes", "32", "--out", "g.csv"]);
    std::os::unix::fs::symlink("g.csv", dir.join("h.csv")).unwrap();
    for out in ["g.csv", "h.csv"] {
        let args = tiny_sweep("3", &["--initial-slip", "g.csv", "--out", out, "--force"]);
        let mut args: Vec<&str> = args;
        // --initial-slip replaces --initial.
        let at = args.iter().position(|a| *a == "--initial").unwrap();
        args.drain(at..at + 2);
        refused_in(
            &dir,
            &args,
            &[&format!("--out {out}"), "--initial-slip file"],
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_replaced_initial_slip_is_not_resumed() {
    let dir = temp_dir("slip-hash");
    ok_in(&dir, &["limit", "--nodes", "32", "--out", "g.csv"]);
    let args = [
        "sweep",
        "--lambda",
        "3",
        "--phi",
        "0",
        "--nodes",
        "32",
        "--steps",
        "100",
        "--initial-slip",
        "g.csv",
        "--out",
        "s.csv",
    ];
    ok_in(&dir, &args);
    let head = std::fs::read_to_string(dir.join("s.csv")).unwrap();
    assert!(head.contains("# initial = slip:g.csv@sha256:"), "{head}");
    // Another slip under the same name.
    let other = [
        "limit",
        "--nodes",
        "32",
        "--friction",
        "0.3",
        "--out",
        "g.csv",
        "--force",
    ];
    ok_in(&dir, &other);
    let mut resume = args.to_vec();
    resume.push("--resume");
    refused_in(&dir, &resume, &["--resume --out s.csv", "initial"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn impossible_rows_are_refused_on_resume() {
    let dir = temp_dir("rows");
    ok_in(&dir, &tiny_sweep("2,3", &["--out", "s.csv"]));
    let good = std::fs::read_to_string(dir.join("s.csv")).unwrap();
    let last = good.lines().last().unwrap().to_string();
    let fields: Vec<&str> = last.split(',').collect();
    assert_eq!(fields[3], "shakedown", "{last}");
    let cases = [
        (
            format!(
                "{},{},{},cyclic-slip,-1,3,0",
                fields[0], fields[1], fields[2]
            ),
            "negative",
        ),
        (
            format!(
                "{},{},{},cyclic-slip,1,0,0",
                fields[0], fields[1], fields[2]
            ),
            "0 cycles",
        ),
        (
            format!(
                "{},{},{},cyclic-slip,1,2000000,0",
                fields[0], fields[1], fields[2]
            ),
            "cap",
        ),
        (
            format!(
                "{},{},{},shakedown,5.5,3,0",
                fields[0], fields[1], fields[2]
            ),
            "shakedown",
        ),
    ];
    for (row, why) in cases {
        let text = good.replace(&last, &row);
        std::fs::write(dir.join("s.csv"), &text).unwrap();
        refused_in(
            &dir,
            &tiny_sweep("2,3", &["--out", "s.csv", "--resume"]),
            &["s.csv", why],
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn figure_from_checks_the_header_and_completeness() {
    let dir = temp_dir("from");
    // A sweep CSV that is not fig3's table (other lambda list).
    ok_in(&dir, &tiny_sweep("3", &["--out", "other.csv"]));
    refused_in(
        &dir,
        &["figure", "fig3", "--from", "other.csv", "--out", "."],
        &["--from other.csv", "not this figure's table"],
    );
    refused_in(
        &dir,
        &["figure", "fig3", "--from", "/dev/zero", "--out", "."],
        &["--from /dev/zero", "not a regular file"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn limit_refuses_what_it_would_ignore() {
    let dir = temp_dir("limit-flags");
    refused_in(
        &dir,
        &["limit", "--nodes", "32", "--initial-path", "2pi,0"],
        &["--initial-path", "limit does not use it"],
    );
    refused_in(
        &dir,
        &["limit", "--nodes", "32", "--run-out"],
        &["--run-out", "limit does not use it"],
    );
    refused_in(
        &dir,
        &["limit", "--nodes", "32", "--phi", "0", "--samples", "64"],
        &["--samples 64", "phi = 0"],
    );
    refused_in(
        &dir,
        &["limit", "--samples", "4097"],
        &["--samples 4097", "3 to 4096"],
    );
    let out = ok_in(
        &dir,
        &[
            "limit", "--nodes", "32", "--phi", "0,pi/2", "--out", "c.csv",
        ],
    );
    let shown = String::from_utf8_lossy(&out.stdout);
    assert_eq!(shown.lines().count(), 1, "a summary, not the CSV: {shown}");
    let head = std::fs::read_to_string(dir.join("c.csv")).unwrap();
    for key in ["# lambda =", "# steps =", "# initial ="] {
        assert!(!head.contains(key), "{key} in\n{head}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_stderr_or_stdout_ends_with_status_1_and_no_panic() {
    let full = || {
        std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap()
    };
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(["sweep", "--lambda", "x"])
        .stderr(full())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    for flag in ["--help", "--version"] {
        let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
            .arg(flag)
            .stdout(full())
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{flag}");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    }
}

#[test]
fn huge_thread_counts_are_clamped_with_a_warning() {
    let out = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(tiny_sweep("3", &[]))
        .env("RAYON_NUM_THREADS", "100000")
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("RAYON_NUM_THREADS=100000"), "{err}");
}

#[test]
fn figure_from_refuses_a_flag_against_its_model_and_a_partial_table() {
    let dir = temp_dir("from-model");
    let grid = ["--lambda", "4.5,5", "--initial", "OA"];
    ok_in(
        &dir,
        &[
            &["figure", "fig3", "--out", "made", "--friction", "0.2"][..],
            &grid,
            &TINY[..4],
        ]
        .concat(),
    );
    // A model flag that contradicts the CSV's header.
    refused_in(
        &dir,
        &[
            &[
                "figure",
                "fig3",
                "--from",
                "made/fig3.csv",
                "--out",
                "re",
                "--friction",
                "0.1",
            ][..],
            &grid,
        ]
        .concat(),
        &["--from made/fig3.csv", "friction = 0.2", "drop --friction"],
    );
    // A partial table without --partial.
    let text = std::fs::read_to_string(dir.join("made/fig3.csv")).unwrap();
    let keep = text.trim_end().rfind('\n').unwrap() + 1;
    std::fs::write(dir.join("part.csv"), &text[..keep]).unwrap();
    refused_in(
        &dir,
        &[
            &["figure", "fig3", "--from", "part.csv", "--out", "re"][..],
            &grid,
        ]
        .concat(),
        &["--from part.csv", "partial: 1 of 2 runs", "--partial"],
    );
    // --partial only with --from.
    refused_in(
        &dir,
        &["figure", "fig3", "--out", "re", "--partial"],
        &["--from <FILE.csv>"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_figure_reader_checks_its_file() {
    let dir = temp_dir("from-readers");
    // The memory figure: a row whose counts do not add up.
    ok_in(
        &dir,
        &[
            "figure", "fig4", "--out", "m", "--lambda", "4,5", "--nodes", "32", "--steps", "100",
        ],
    );
    let memory = std::fs::read_to_string(dir.join("m/fig4.csv")).unwrap();
    let last = memory.trim_end().rfind('\n').unwrap() + 1;
    let mut row: Vec<String> = memory[last..]
        .trim_end()
        .split(',')
        .map(String::from)
        .collect();
    row[4] = (row[4].parse::<usize>().unwrap() + 1).to_string();
    std::fs::write(
        dir.join("bad4.csv"),
        format!("{}{}\n", &memory[..last], row.join(",")),
    )
    .unwrap();
    refused_in(
        &dir,
        &[
            "figure", "fig4", "--from", "bad4.csv", "--out", "m2", "--lambda", "4,5",
        ],
        &["--from bad4.csv", "do not add up"],
    );
    // The regime map's curve beside its CSV: a lambda_2 that is not positive.
    let regime = [
        "figure", "regime", "--out", "r", "--lambda", "4,5", "--phi", "0,pi/2", "--nodes", "32",
        "--steps", "100",
    ];
    ok_in(&dir, &regime);
    let curve = std::fs::read_to_string(dir.join("r/regime_limit.csv")).unwrap();
    let mut lines: Vec<String> = curve.lines().map(String::from).collect();
    let n = lines.len() - 1;
    let mut f: Vec<String> = lines[n].split(',').map(String::from).collect();
    f[1] = "-1".into();
    lines[n] = f.join(",");
    std::fs::write(dir.join("r/regime_limit.csv"), lines.join("\n") + "\n").unwrap();
    refused_in(
        &dir,
        &[
            "figure",
            "regime",
            "--from",
            "r/regime.csv",
            "--out",
            "r2",
            "--lambda",
            "4,5",
            "--phi",
            "0,pi/2",
        ],
        &["regime_limit.csv", "not positive"],
    );
    // A slip map whose load table is a FIFO or missing.
    ok_in(
        &dir,
        &[
            "figure", "fig7", "--out", "s", "--nodes", "32", "--steps", "100",
        ],
    );
    std::fs::remove_file(dir.join("s/fig7_load.csv")).unwrap();
    refused_in(
        &dir,
        &["figure", "fig7", "--from", "s/fig7.csv", "--out", "s2"],
        &["--from s/fig7.csv", "fig7_load.csv"],
    );
    #[cfg(unix)]
    {
        let fifo = Command::new("mkfifo")
            .arg(dir.join("s/fig7_load.csv"))
            .status();
        if fifo.is_ok_and(|s| s.success()) {
            refused_in(
                &dir,
                &["figure", "fig7", "--from", "s/fig7.csv", "--out", "s2"],
                &["fig7_load.csv", "not a regular file"],
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `--cycle` file is an input like any other: no command may write its
/// output over it, under its own name or a symlink's, even with `--force`.
#[test]
fn the_cycle_file_is_never_an_output() {
    let dir = temp_dir("cycle-as-output");
    let cycle = dir.join("c.csv");
    let text = "u,v\n1,0\n0,1\n-1,0\n0,-1\n";
    std::fs::write(&cycle, text).unwrap();
    let link = dir.join("link.csv");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&cycle, &link).unwrap();
    let c = cycle.to_str().unwrap();
    let grid = ["--lambda", "2", "--nodes", "32", "--steps", "400"];
    for out in [c, link.to_str().unwrap()] {
        let mut cases: Vec<Vec<&str>> = vec![
            vec!["sweep", "--cycle", c, "--out", out, "--force"],
            vec!["run", "--cycle", c, "--profile", out, "--force"],
            vec!["events", "--cycle", c, "--out", out, "--force"],
            vec!["limit", "--cycle", c, "--out", out, "--force"],
        ];
        for args in &mut cases {
            let flag = if args[0] == "run" {
                "--profile"
            } else {
                "--out"
            };
            if args[0] != "limit" {
                args.extend(grid);
            } else {
                args.extend(&grid[2..4]);
            }
            rejected(args, &[flag, "--cycle file"]);
            assert_eq!(std::fs::read_to_string(&cycle).unwrap(), text, "{args:?}");
        }
    }
}
