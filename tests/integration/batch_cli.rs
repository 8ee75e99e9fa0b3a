//! Interrupted, resumed, sharded and merged sweeps give the same file, byte
//! for byte, as one uninterrupted run; a closed stdout is not a crash.

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const HEADER: &str = "lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle";

/// A small sweep: 10 x 2 x 25 = 500 quick runs with every kind of state.
const GRID: &[&str] = &[
    "--lambda",
    "3:7.5:0.5",
    "--phi",
    "0,pi/2",
    "--initial",
    "all",
    "--nodes",
    "16",
    "--steps",
    "32",
    "--max-cycles",
    "40",
];

/// A longer sweep for the Ctrl-C tests: 2250 runs, a few seconds.
const LONG_GRID: &[&str] = &[
    "--lambda",
    "3:7.4:0.1",
    "--phi",
    "0,pi/2",
    "--initial",
    "all",
    "--nodes",
    "32",
    "--steps",
    "64",
    "--max-cycles",
    "60",
];

/// The column header: the first line after the `# key = value` comments.
fn columns(text: &str) -> Option<&str> {
    text.lines().find(|l| !l.starts_with('#'))
}

/// Lines that are not comments: the column header and the rows.
fn table_lines(bytes: &[u8]) -> usize {
    bytes
        .split_inclusive(|b| *b == b'\n')
        .filter(|l| l.ends_with(b"\n") && !l.starts_with(b"#"))
        .count()
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_shakedown"));
    c.stdin(Stdio::null());
    c
}

fn shakedown(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("shakedown-batch-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[track_caller]
fn ok(out: &Output) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "status {:?}: {stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// `sweep GRID extra... --out path`.
fn sweep(grid: &[&str], extra: &[&str], out: &Path) -> Output {
    let mut args = vec!["sweep"];
    args.extend_from_slice(grid);
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--out", out.to_str().unwrap()]);
    shakedown(&args)
}

fn reference(grid: &[&str], d: &Path) -> Vec<u8> {
    let path = d.join("reference.csv");
    ok(&sweep(grid, &[], &path));
    std::fs::read(path).unwrap()
}

/// Every line complete, and the whole a prefix of the full output.
#[track_caller]
fn assert_complete_prefix(part: &[u8], full: &[u8]) {
    assert!(full.starts_with(part), "not a prefix of the full output");
    assert!(
        part.is_empty() || part.ends_with(b"\n"),
        "incomplete last line"
    );
}

#[test]
fn sweep_streams_the_same_bytes_to_stdout_and_file() {
    let d = dir("stdout");
    let full = reference(GRID, &d);
    let text = String::from_utf8(full.clone()).unwrap();
    assert_eq!(columns(&text), Some(HEADER));
    assert_eq!(table_lines(&full), 1 + 10 * 2 * 25);
    for key in [
        "# shakedown = ",
        "# friction = ",
        "# nodes = 16",
        "# lambda = 3,3.5",
    ] {
        assert!(text.contains(key), "no '{key}' in the header");
    }
    for state in ["shakedown", "cyclic-slip", "ratchetting", "gross-slip"] {
        assert!(text.contains(state), "no {state} in the test grid");
    }
    let mut args = vec!["sweep"];
    args.extend_from_slice(GRID);
    let out = shakedown(&args);
    ok(&out);
    assert_eq!(out.stdout, full);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn resume_completes_any_cut_of_the_file_to_the_same_bytes() {
    let d = dir("resume");
    let full = reference(GRID, &d);
    let path = d.join("cut.csv");
    let line_ends: Vec<usize> = full
        .iter()
        .enumerate()
        .filter(|(_, b)| **b == b'\n')
        .map(|(i, _)| i + 1)
        .collect();
    // Empty, inside the header, after the header, mid-row, at a row end,
    // one byte short of the end, complete.
    let cuts = [
        0,
        10,
        line_ends[0],
        line_ends[3] + 7,
        line_ends[100],
        full.len() - 1,
        full.len(),
    ];
    for cut in cuts {
        std::fs::write(&path, &full[..cut]).unwrap();
        let out = sweep(GRID, &["--resume"], &path);
        ok(&out);
        assert_eq!(
            std::fs::read(&path).unwrap(),
            full,
            "resumed from byte {cut}"
        );
    }
    // A file that does not exist yet is started afresh.
    std::fs::remove_file(&path).unwrap();
    ok(&sweep(GRID, &["--resume"], &path));
    assert_eq!(std::fs::read(&path).unwrap(), full);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn shards_merge_into_the_unsharded_file() {
    let d = dir("shards");
    let full = reference(GRID, &d);
    let n = 3;
    let mut shards = Vec::new();
    for k in 1..=n {
        let path = d.join(format!("shard-{k}.csv"));
        let spec = format!("{k}/{n}");
        ok(&sweep(GRID, &["--shard", &spec], &path));
        shards.push(path);
    }
    // Disjoint: together they hold each row once.
    let rows: usize = shards
        .iter()
        .map(|p| table_lines(&std::fs::read(p).unwrap()) - 1)
        .sum();
    assert_eq!(rows, 500);
    // Interrupt one shard by cutting its file mid-row, and resume it.
    let cut = std::fs::read(&shards[1]).unwrap();
    std::fs::write(&shards[1], &cut[..cut.len() / 2]).unwrap();
    ok(&sweep(GRID, &["--shard", "2/3", "--resume"], &shards[1]));
    assert_eq!(std::fs::read(&shards[1]).unwrap(), cut);
    // Merge, in any order of the files.
    let merged = d.join("merged.csv");
    let mut args = vec!["merge"];
    let names: Vec<String> = shards
        .iter()
        .rev()
        .map(|p| p.to_str().unwrap().to_string())
        .collect();
    args.extend(names.iter().map(String::as_str));
    args.extend_from_slice(GRID);
    args.extend_from_slice(&["--out", merged.to_str().unwrap()]);
    ok(&shakedown(&args));
    assert_eq!(std::fs::read(&merged).unwrap(), full);
    // To stdout as well.
    args.truncate(args.len() - 2);
    let out = shakedown(&args);
    ok(&out);
    assert_eq!(out.stdout, full);
    std::fs::remove_dir_all(&d).unwrap();
}

/// Start a long sweep into `path`, wait for `rows` rows, send `signals`
/// SIGINTs, and return the finished process's output.
fn interrupted(path: &Path, rows: usize, signals: usize) -> (Output, Duration) {
    let mut args = vec!["sweep"];
    args.extend_from_slice(LONG_GRID);
    args.extend_from_slice(&["--out", path.to_str().unwrap()]);
    interrupt_command(&args, path, rows, signals)
}

/// Run `args`, wait until `path` has `rows` lines, send `signals` SIGINTs.
fn interrupt_command(
    args: &[&str],
    path: &Path,
    rows: usize,
    signals: usize,
) -> (Output, Duration) {
    let child = bin()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        let done = std::fs::read(path).map(|c| table_lines(&c)).unwrap_or(0);
        if done > rows {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "no rows appear");
        std::thread::sleep(Duration::from_millis(2));
    }
    for _ in 0..signals {
        let status = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        std::thread::sleep(Duration::from_millis(5));
    }
    let sent = Instant::now();
    let out = wait(child);
    (out, sent.elapsed())
}

fn wait(child: Child) -> Output {
    child.wait_with_output().unwrap()
}

#[test]
fn ctrl_c_during_a_figure_leaves_complete_rows_and_no_plot() {
    let d = dir("figure-ctrlc");
    let out_dir = d.join("fig");
    let csv = out_dir.join("fig8.csv");
    let args = [
        "figure",
        "fig8",
        "--out",
        out_dir.to_str().unwrap(),
        "--lambda",
        "4:7.4:0.02",
        "--nodes",
        "64",
        "--steps",
        "200",
    ];
    let (out, took) = interrupt_command(&args, &csv, 10, 1);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(took < Duration::from_secs(20), "stopping took {took:?}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(columns(&text), Some(HEADER));
    assert!(text.ends_with('\n'), "incomplete last line");
    let rows = table_lines(text.as_bytes()) - 1;
    assert!((10..171 * 25).contains(&rows), "{rows} rows");
    assert!(
        stderr.contains(&format!("interrupted: {rows} of ")),
        "{stderr}"
    );
    assert!(
        !out_dir.join("fig8.svg").exists(),
        "no plot of a partial sweep"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn ctrl_c_stops_cleanly_and_resume_finishes_the_same_file() {
    let d = dir("ctrlc");
    let reference = reference(LONG_GRID, &d);
    let path = d.join("map.csv");
    for signals in [1, 2] {
        let _ = std::fs::remove_file(&path);
        let (out, took) = interrupted(&path, 20, signals);
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(130), "{signals} Ctrl-C: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(stderr.contains("--resume"), "{stderr}");
        assert!(took < Duration::from_secs(20), "stopping took {took:?}");
        let part = std::fs::read(&path).unwrap();
        let text = String::from_utf8(part.clone()).unwrap();
        assert_eq!(columns(&text), Some(HEADER));
        assert!(part.ends_with(b"\n"), "incomplete last line");
        let rows = table_lines(&part) - 1;
        assert!(rows > 20, "{rows} rows");
        // The message says how far it got.
        assert!(
            stderr.contains(&format!("interrupted: {rows} of ")),
            "{stderr}"
        );
        let resumed = sweep(LONG_GRID, &["--resume"], &path);
        ok(&resumed);
        let msg = String::from_utf8_lossy(&resumed.stderr);
        assert!(msg.contains(&format!("resuming: {rows} of")), "{msg}");
        let full = std::fs::read(&path).unwrap();
        assert_complete_prefix(&part, &full);
        assert_eq!(full, reference, "resumed file differs from one run");
    }
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_closed_stdout_is_not_a_crash() {
    // `shakedown sweep | head -3`
    let mut args = vec!["sweep"];
    args.extend_from_slice(GRID);
    let mut child = bin()
        .args(&args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut reader = BufReader::new(child.stdout.take().unwrap());
    let mut first = String::new();
    reader.read_line(&mut first).unwrap();
    assert!(first.starts_with("# shakedown = "), "{first}");
    drop(reader);
    let mut stderr = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    // `shakedown run | true`: the pipe is closed before anything is written.
    let mut child = bin()
        .args(["run", "--nodes", "16", "--steps", "32", "--lambda", "2"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
    assert!(!stderr.contains("panicked"), "{stderr}");
}
