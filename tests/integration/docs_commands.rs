//! The documentation's commands still work: every fenced block marked
//! ```` ```sh runnable ```` in `README.md`, `ARCHITECTURE.md` and `docs/`
//! is run, as a shell script, against the binary this test was built with,
//! in a scratch folder of its own; the test fails naming the file and the
//! block's line when one exits non-zero. Blocks meant to be read, not run
//! (long maps, the explorer, cluster jobs), are plain ```` ```sh ````.
//!
//! Runnable blocks write `shakedown`, not `cargo run --release --`; keep
//! them to small grids, since the whole set must stay well under a minute.
#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A runnable block: where it is, and its text.
struct Block {
    file: PathBuf,
    line: usize,
    script: String,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown files a user or maintainer reads: the top-level pages and
/// everything under `docs/`.
fn doc_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = ["README.md", "ARCHITECTURE.md", "CHANGELOG.md"]
        .iter()
        .map(|f| root().join(f))
        .filter(|p| p.is_file())
        .collect();
    let mut stack = vec![root().join("docs")];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The blocks of `text` whose opening fence's info string has the word
/// `runnable`.
fn runnable_blocks(file: &Path, text: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    let mut open: Option<(usize, bool, Vec<&str>)> = None;
    for (i, line) in text.lines().enumerate() {
        let fence = line.trim_start().starts_with("```");
        match (&mut open, fence) {
            (None, true) => {
                let info = line.trim_start().trim_start_matches('`');
                let runnable = info.split_whitespace().any(|w| w == "runnable");
                open = Some((i + 1, runnable, Vec::new()));
            }
            (Some((start, runnable, lines)), true) => {
                if *runnable {
                    blocks.push(Block {
                        file: file.to_path_buf(),
                        line: *start,
                        script: lines.join("\n"),
                    });
                }
                open = None;
            }
            (Some((_, _, lines)), false) => lines.push(line),
            (None, false) => {}
        }
    }
    blocks
}

/// Run one block with `sh -e` in a fresh folder, `shakedown` on the PATH
/// being the binary under test. Err with what went wrong.
fn run_block(block: &Block, scratch: &Path) -> Result<(), String> {
    let bin = scratch.join("bin");
    std::fs::create_dir_all(&bin).map_err(|e| e.to_string())?;
    let link = bin.join("shakedown");
    if !link.exists() {
        std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_shakedown"), &link)
            .map_err(|e| e.to_string())?;
    }
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut child = Command::new("sh")
        .arg("-e")
        .arg("-c")
        .arg(&block.script)
        .current_dir(scratch)
        .env("PATH", path)
        .env("NO_COLOR", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("sh did not start: {e}"))?;
    // A block that hangs fails instead of holding up the suite.
    let limit = Duration::from_secs(120);
    let started = Instant::now();
    loop {
        if child.try_wait().map_err(|e| e.to_string())?.is_some() {
            break;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {} s", limit.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{}\nstderr:\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

fn relative(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}

#[test]
fn every_runnable_command_in_the_docs_succeeds() {
    let blocks: Vec<Block> = doc_files()
        .iter()
        .flat_map(|f| runnable_blocks(f, &std::fs::read_to_string(f).unwrap()))
        .collect();
    // The README's tour is runnable, so markers cannot all vanish unnoticed.
    assert!(
        blocks.iter().any(|b| b.file.ends_with("README.md")),
        "README.md has no ```sh runnable block"
    );
    let mut failures = Vec::new();
    for (k, block) in blocks.iter().enumerate() {
        let name = format!("{}:{}", relative(&block.file), block.line);
        assert!(
            !block.script.contains("cargo "),
            "{name}: a runnable block calls `shakedown` itself, not cargo"
        );
        let scratch = super::common::scratch(&format!("docs-{k}"));
        if let Err(why) = run_block(block, &scratch) {
            failures.push(format!("{name}: {why}"));
        }
        let _ = std::fs::remove_dir_all(&scratch);
    }
    assert!(
        failures.is_empty(),
        "{} of {} runnable blocks failed:\n{}",
        failures.len(),
        blocks.len(),
        failures.join("\n")
    );
}

/// The harness itself: a block that breaks is reported, one that works is
/// not, and only blocks marked runnable are taken.
#[test]
fn a_broken_command_fails_and_unmarked_blocks_are_not_run() {
    let text = "```sh runnable\nshakedown run --lambda seven\n```\n\
                ```sh\nexit 1\n```\n\
                ```sh runnable\nshakedown presets > list.txt\ntest -s list.txt\n```\n";
    let blocks = runnable_blocks(Path::new("example.md"), text);
    assert_eq!(blocks.len(), 2);
    assert_eq!(blocks[0].line, 1);
    assert_eq!(blocks[1].line, 7);
    let scratch = super::common::scratch("docs-harness");
    let broken = run_block(&blocks[0], &scratch).unwrap_err();
    assert!(broken.contains("--lambda"), "{broken}");
    run_block(&blocks[1], &scratch).unwrap();
    let _ = std::fs::remove_dir_all(&scratch);
}

/// No page names a path on the machine it was written on, or keeps a work
/// log's dates of measurement rounds.
#[test]
fn the_docs_name_no_machine_paths() {
    for file in doc_files() {
        let text = std::fs::read_to_string(&file).unwrap();
        // Folders of a developer's machine, spelt from their names so that
        // this file does not name them itself.
        let mut bad: Vec<String> = ["work", "tmp", "home"]
            .iter()
            .map(|d| format!("/{d}/"))
            .collect();
        bad.push(["dev", "notes"].join("-"));
        for (i, line) in text.lines().enumerate() {
            for bad in &bad {
                assert!(
                    !line.contains(bad),
                    "{}:{}: names `{bad}`: {line}",
                    relative(&file),
                    i + 1
                );
            }
        }
    }
}

/// The README's promise that `cargo test` after `cargo build` compiles no
/// dependency twice: every package the normal build uses has the same
/// features when the dev-dependencies join (Cargo's resolver 2 builds a
/// package once per feature set; docs/decisions/0007-build-once.md).
#[test]
fn test_builds_reuse_every_dependency_of_the_normal_build() {
    let tree = |edges: &str| {
        let out = Command::new(env!("CARGO"))
            .args([
                "tree",
                "--offline",
                "--prefix",
                "none",
                "-f",
                "{p}|{f}",
                "-e",
                edges,
            ])
            .current_dir(root())
            .output()
            .expect("cargo runs");
        assert!(
            out.status.success(),
            "cargo tree -e {edges}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        // A package can appear more than once (built for the host and the
        // target): keep every feature set it is built with.
        let mut sets =
            std::collections::BTreeMap::<String, std::collections::BTreeSet<String>>::new();
        for line in String::from_utf8_lossy(&out.stdout).lines() {
            if let Some((package, features)) = line.trim_end_matches(" (*)").split_once('|') {
                sets.entry(package.to_string())
                    .or_default()
                    .insert(features.to_string());
            }
        }
        sets
    };
    let normal = tree("normal,build");
    let with_dev = tree("normal,build,dev");
    let split: Vec<String> = normal
        .iter()
        .filter_map(|(package, features)| {
            let dev = with_dev.get(package)?;
            (dev != features)
                .then(|| format!("{package}: {features:?}, but {dev:?} with the dev-dependencies"))
        })
        .collect();
    assert!(
        split.is_empty(),
        "built twice (turn these features on in [dependencies]):\n{}",
        split.join("\n")
    );
}
