//! Helpers shared by the integration tests (included with `mod common`).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Run the `shakedown` binary.
pub fn shakedown(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Run the `shakedown` binary, which must succeed: its stdout.
#[track_caller]
pub fn ok(args: &[&str]) -> String {
    let o = shakedown(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stdout(&o)
}

/// The value of `lambda_2` in a command's output (`lambda_2 = 4.9 ...` of
/// `figure`, `lambda_2  4.9` of `limit`).
pub fn lambda_2(text: &str) -> f64 {
    text.lines()
        .filter_map(|l| l.trim_start().strip_prefix("lambda_2"))
        .find_map(|rest| {
            rest.trim_start_matches([' ', '='])
                .split_whitespace()
                .next()?
                .parse()
                .ok()
        })
        .unwrap_or_else(|| panic!("no lambda_2 in:\n{text}"))
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh, empty scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shakedown-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A CSV file as its header and rows of fields (no quoted commas occur in
/// this project's CSV except in the `initial` column, which is quoted).
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    // `# key = value` lines say what made the file; the table follows.
    let mut lines = text.lines().skip_while(|l| l.starts_with('#'));
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines.map(split_csv_line).collect();
    (header, rows)
}

fn split_csv_line(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut field)),
            _ => field.push(c),
        }
    }
    out.push(field);
    out
}

/// A light well-formedness check of an SVG document: the root is `<svg>`,
/// every start tag is closed in order, and nothing follows the root.
pub fn check_svg(text: &str) -> Result<(), String> {
    let body = text.trim_start();
    let body = if body.starts_with("<?xml") {
        &body[body.find("?>").ok_or("unterminated XML declaration")? + 2..]
    } else {
        body
    };
    let mut stack: Vec<String> = Vec::new();
    let mut rest = body.trim_start();
    if !rest.starts_with("<svg") {
        return Err("the document does not start with <svg".into());
    }
    let mut closed_root = false;
    while let Some(open) = rest.find('<') {
        if closed_root && !rest[..open].trim().is_empty() {
            return Err("content after the root element".into());
        }
        rest = &rest[open..];
        if rest.starts_with("<!--") {
            let end = rest.find("-->").ok_or("unterminated comment")?;
            rest = &rest[end + 3..];
            continue;
        }
        let end = rest.find('>').ok_or("unterminated tag")?;
        let tag = &rest[1..end];
        rest = &rest[end + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            let name = name.trim();
            match stack.pop() {
                Some(open) if open == name => {}
                Some(open) => return Err(format!("</{name}> closes <{open}>")),
                None => return Err(format!("</{name}> without a start tag")),
            }
            if stack.is_empty() {
                closed_root = true;
            }
        } else {
            if closed_root {
                return Err("a second root element".into());
            }
            let name: String = tag
                .chars()
                .take_while(|c| !c.is_whitespace() && *c != '/')
                .collect();
            if name.is_empty() {
                return Err("a tag without a name".into());
            }
            if !tag.ends_with('/') {
                stack.push(name);
            }
        }
    }
    if !stack.is_empty() {
        return Err(format!("unclosed elements: {stack:?}"));
    }
    if !closed_root {
        return Err("the root element is not closed".into());
    }
    Ok(())
}

/// Width and height of a PNG file, after checking its signature.
pub fn png_size(bytes: &[u8]) -> Option<(u32, u32)> {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    if bytes.len() < 24 || bytes[..8] != SIGNATURE || &bytes[12..16] != b"IHDR" {
        return None;
    }
    let w = u32::from_be_bytes(bytes[16..20].try_into().ok()?);
    let h = u32::from_be_bytes(bytes[20..24].try_into().ok()?);
    Some((w, h))
}

/// A sweep small enough for a test: 3 lambdas x 2 initial paths on a
/// coarse contact (32 nodes, 100 increments per cycle), seconds at most.
pub fn tiny_sweep_source() -> shakedown::tui::sweep::SweepSource {
    use shakedown::analysis::case::{Case, CaseParams};
    use shakedown::analysis::sweep::{Axis, SweepLists};
    use shakedown::model::path::Initial;
    let params = CaseParams {
        nodes: 32,
        steps: 100,
        ..CaseParams::default()
    };
    let case = Case::from_params(&params).expect("a valid tiny case");
    let lists = SweepLists {
        load_factors: vec![4.0, 5.5, 7.0],
        phases: vec![0.0],
        initials: vec![
            Initial::parse("OA").unwrap(),
            Initial::parse("7,-7").unwrap(),
        ],
    };
    shakedown::tui::sweep::SweepSource {
        name: "tiny".into(),
        spec: shakedown::analysis::sweep::SweepSpec::over(&case, &lists).expect("valid lists"),
        axis: Axis::Lambda,
    }
}

/// Deterministic rows for every job of `source`, as if the sweep had run:
/// the state and `W` cycle through a fixed pattern, one run failed.
pub fn fake_rows(
    source: &shakedown::tui::sweep::SweepSource,
) -> Vec<shakedown::analysis::sweep::Row> {
    use shakedown::analysis::sweep::{Row, RunError};
    use shakedown::stepping::steady::SteadyState;
    use shakedown::stepping::StepError;
    let jobs = source.spec.jobs();
    let n = jobs.len();
    jobs.into_iter()
        .map(|job| {
            let state = SteadyState::ALL[job.index % 5];
            let outcome = if job.index + 1 == n {
                Err(RunError::Step(StepError::NotSettled {
                    load: shakedown::model::LoadPoint::new(1.0, 2.0),
                    phase: "cycle 2".into(),
                    bisections: 8,
                }))
            } else {
                let dissipation = if state == SteadyState::Shakedown {
                    0.0
                } else {
                    1e-3 * job.load_factor * (1 + job.initial) as f64
                };
                Ok(fake_outcome(state, dissipation, 3 + job.index))
            };
            Row {
                job,
                initial: source.spec.initials()[job.initial].name(),
                outcome,
            }
        })
        .collect()
}

/// A regime map small enough for a test: 3 lambdas x 2 phases on a coarse
/// contact (32 nodes, 100 increments per cycle), seconds at most.
pub fn tiny_regime_source() -> shakedown::tui::regime::RegimeSource {
    use shakedown::analysis::case::{Case, CaseParams};
    let params = CaseParams {
        nodes: 32,
        steps: 100,
        ..CaseParams::default()
    };
    let case = Case::from_params(&params).expect("a valid tiny case");
    shakedown::tui::regime::RegimeSource::new(
        "tiny",
        &case,
        vec![4.0, 5.5, 7.0],
        vec![0.0, std::f64::consts::FRAC_PI_2],
    )
    .expect("a valid tiny grid")
}

/// A made-up outcome of `state` for the front ends' tests (no physics):
/// the 0.01 % rule for the steady states, a gross slip at `(1, 2pi)` in
/// the transient.
pub fn fake_outcome(
    state: shakedown::SteadyState,
    dissipation: f64,
    cycles: usize,
) -> shakedown::Outcome {
    use shakedown::stepping::{GrossSlip, Separation, ShakedownProof};
    use shakedown::{LoadPoint, SteadyState, Verdict};
    let load = LoadPoint::new(1.0, 2.0 * std::f64::consts::PI);
    let verdict = match state {
        SteadyState::Shakedown => Verdict::Shakedown(ShakedownProof::NoSlipCycle),
        SteadyState::CyclicSlip => Verdict::CyclicSlip,
        SteadyState::RatchettingMonotonic => Verdict::Ratchetting { monotonic: true },
        SteadyState::RatchettingNonMonotonic => Verdict::Ratchetting { monotonic: false },
        SteadyState::GrossSlip => Verdict::GrossSlip(GrossSlip { load, time: None }),
        SteadyState::Separation => Verdict::Separation(Separation {
            load,
            time: None,
            theta: 0.0,
        }),
        SteadyState::NotConverged => Verdict::NotConverged { trend: None },
    };
    shakedown::Outcome {
        verdict,
        dissipation,
        cycles,
        rotation_per_cycle: 0.0,
        level: None,
        steady_rotation: None,
    }
}
