//! `figure --from` with a polyline cycle (`--cycle`, model.md section 5.4):
//! a file made from a polyline records the cycle by content
//! (`load-cycle = cycle:NAME@sha256:DIGEST`), and is redrawn with that
//! cycle, under any file name, or refused in one line naming both cycles;
//! never drawn as the paper's ellipse, nor with another cycle. One test per
//! reader: the slip map, a sweep figure, the memory figure, the regime
//! map's `_limit.csv` and the fretting profile.

use crate::common;

use std::path::{Path, PathBuf};

use common::{scratch, shakedown, stderr, stdout};

/// Coarse grids: 100 increments, a multiple of the square's 4 vertices.
const COARSE: [&str; 4] = ["--nodes", "32", "--steps", "100"];

/// A square of half-side 1/2 round the centre, in time order: at the
/// presets' lambda it stays inside `|y| < 2 pi`, so no run slides grossly.
const SQUARE: &str = "u,v\n0.5,0.5\n-0.5,0.5\n-0.5,-0.5\n0.5,-0.5\n";

/// Another cycle: the square with one vertex moved.
const OTHER: &str = "u,v\n0.5,0.5\n-0.5,0.5\n-0.5,-0.5\n0.6,-0.5\n";

fn s(p: &Path) -> String {
    p.to_str().unwrap().to_string()
}

#[track_caller]
fn ok(args: &[&str]) -> String {
    let o = shakedown(args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stdout(&o)
}

/// The one line of a refused command (exit 2), which must contain every
/// one of `says`.
#[track_caller]
fn refused(args: &[&str], says: &[&str]) -> String {
    let o = shakedown(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    for w in says {
        assert!(err.contains(w), "{args:?}: {err} lacks {w}");
    }
    err
}

/// The cycle files of a test: the square as `square.csv` and again under
/// another name, and another cycle.
struct Cycles {
    square: PathBuf,
    renamed: PathBuf,
    other: PathBuf,
}

impl Cycles {
    fn in_dir(dir: &Path) -> Self {
        let c = Self {
            square: dir.join("square.csv"),
            renamed: dir.join("renamed.csv"),
            other: dir.join("other.csv"),
        };
        std::fs::write(&c.square, SQUARE).unwrap();
        std::fs::write(&c.renamed, SQUARE).unwrap();
        std::fs::write(&c.other, OTHER).unwrap();
        c
    }
}

/// The `load-cycle` a file's header records.
fn recorded_cycle(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .find_map(|l| l.strip_prefix("# load-cycle = "))
        .unwrap_or_else(|| panic!("{}: no load-cycle", path.display()))
        .to_string()
}

/// The redraw of `made/NAME` into `again` draws the same plot and caption.
#[track_caller]
fn same_figure(made: &Path, again: &Path, name: &str) {
    for ext in [".svg", ".caption.txt"] {
        let file = format!("{name}{ext}");
        assert_eq!(
            std::fs::read(made.join(&file)).unwrap(),
            std::fs::read(again.join(&file)).unwrap(),
            "{file}"
        );
    }
}

/// The refusals every `figure NAME --from FILE` of a polyline file gives:
/// without a cycle, with another one; and the file made from the ellipse
/// `ellipse` is refused with a cycle.
fn refusals(head: &[&str], from: &Path, ellipse: &Path, cycles: &Cycles, out: &Path) {
    let recorded = recorded_cycle(from);
    let from = s(from);
    let out = s(out);
    let with = |extra: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = head.iter().map(|a| a.to_string()).collect();
        v.extend(["--from".into(), from.clone(), "--out".into(), out.clone()]);
        v.extend(extra.iter().map(|a| a.to_string()));
        v
    };
    let args = with(&[]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(&args, &[&from, &recorded, "--cycle"]);
    let other = s(&cycles.other);
    let args = with(&["--cycle", &other]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(&args, &[&recorded, "cycle:other.csv@sha256:", "differ"]);
    let square = s(&cycles.square);
    let mut args: Vec<String> = head.iter().map(|a| a.to_string()).collect();
    args.extend([
        "--from".into(),
        s(ellipse),
        "--out".into(),
        out,
        "--cycle".into(),
        square,
    ]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(
        &args,
        &["ellipse", "cycle:square.csv@sha256:", "drop --cycle"],
    );
}

#[test]
fn a_polyline_slip_map_is_redrawn_with_its_own_cycle() {
    let dir = scratch("poly-slip-map");
    let cycles = Cycles::in_dir(&dir);
    let (made, ellipse, again) = (dir.join("made"), dir.join("ellipse"), dir.join("again"));
    let square = s(&cycles.square);
    ok(&[
        &["figure", "fig5", "--cycle", &square, "--out", &s(&made)][..],
        &COARSE,
    ]
    .concat());
    ok(&[&["figure", "fig5", "--out", &s(&ellipse)][..], &COARSE].concat());

    // The map is the square's: every load of its load table lies on the
    // square x = x0 + lambda u, y = y0 + lambda v with max(|u|, |v|) = 1/2
    // (fig5: lambda = 7, A = (pi, 3 pi / 4)).
    let load = std::fs::read_to_string(made.join("fig5_load.csv")).unwrap();
    let (x0, y0, lambda) = (std::f64::consts::PI, 0.75 * std::f64::consts::PI, 7.0);
    let mut rows = 0;
    for line in load.lines().skip_while(|l| l.starts_with('#')).skip(1) {
        let f: Vec<f64> = line.split(',').map(|t| t.parse().unwrap()).collect();
        let (u, v) = ((f[1] - x0) / lambda, (f[2] - y0) / lambda);
        assert!((u.abs().max(v.abs()) - 0.5).abs() < 1e-9, "{line}");
        rows += 1;
    }
    assert!(rows > 100, "{rows}");

    let from = made.join("fig5.csv");
    refusals(
        &["figure", "fig5"],
        &from,
        &ellipse.join("fig5.csv"),
        &cycles,
        &again,
    );
    // Nothing was written by the refusals.
    assert!(!again.exists());
    // With its cycle under another file name: the same figure, whose
    // caption names the cycle as the file records it.
    let renamed = s(&cycles.renamed);
    ok(&[
        "figure",
        "fig5",
        "--from",
        &s(&from),
        "--cycle",
        &renamed,
        "--out",
        &s(&again),
    ]);
    same_figure(&made, &again, "fig5");
    let caption = std::fs::read_to_string(again.join("fig5.caption.txt")).unwrap();
    assert!(caption.contains(&recorded_cycle(&from)), "{caption}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The value of `lambda_2` in a command's output (`lambda_2 = 4.9 ...` of
/// `figure`, `lambda_2  4.9` of `limit`).
fn lambda_2(text: &str) -> f64 {
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

#[test]
fn a_polyline_sweep_figure_is_redrawn_with_its_own_cycle() {
    let dir = scratch("poly-sweep");
    let cycles = Cycles::in_dir(&dir);
    let (made, ellipse, again) = (dir.join("made"), dir.join("ellipse"), dir.join("again"));
    let grid = ["--lambda", "4.5,5.5", "--initial", "OA"];
    let square = s(&cycles.square);
    let first = ok(&[
        &["figure", "fig3", "--cycle", &square, "--out", &s(&made)][..],
        &grid,
        &COARSE,
    ]
    .concat());
    ok(&[
        &["figure", "fig3", "--out", &s(&ellipse)][..],
        &grid,
        &COARSE,
    ]
    .concat());
    let head = [&["figure", "fig3"][..], &grid].concat();
    refusals(
        &head,
        &made.join("fig3.csv"),
        &ellipse.join("fig3.csv"),
        &cycles,
        &again,
    );
    let redrawn = ok(&[
        &[
            "figure",
            "fig3",
            "--from",
            &s(&made.join("fig3.csv")),
            "--cycle",
            &s(&cycles.renamed),
            "--out",
            &s(&again),
        ][..],
        &grid,
    ]
    .concat());
    same_figure(&made, &again, "fig3");
    // The redraw's lambda_2 is the square's, as `limit` gives it for that
    // cycle (the LP at its vertices), not the ellipse's.
    let limit = ok(&[&["limit", "--cycle", &square][..], &COARSE[..2]].concat());
    assert_eq!(lambda_2(&redrawn), lambda_2(&first));
    assert!(
        (lambda_2(&redrawn) - lambda_2(&limit)).abs() < 2e-6,
        "{redrawn}\n{limit}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_polyline_memory_figure_is_redrawn_with_its_own_cycle() {
    let dir = scratch("poly-memory");
    let cycles = Cycles::in_dir(&dir);
    let (made, ellipse, again) = (dir.join("made"), dir.join("ellipse"), dir.join("again"));
    let grid = ["--lambda", "4.5,5.5"];
    let square = s(&cycles.square);
    ok(&[
        &["figure", "fig4", "--cycle", &square, "--out", &s(&made)][..],
        &grid,
        &COARSE,
    ]
    .concat());
    ok(&[
        &["figure", "fig4", "--out", &s(&ellipse)][..],
        &grid,
        &COARSE,
    ]
    .concat());
    let head = [&["figure", "fig4"][..], &grid].concat();
    refusals(
        &head,
        &made.join("fig4.csv"),
        &ellipse.join("fig4.csv"),
        &cycles,
        &again,
    );
    ok(&[
        &[
            "figure",
            "fig4",
            "--from",
            &s(&made.join("fig4.csv")),
            "--cycle",
            &s(&cycles.renamed),
            "--out",
            &s(&again),
        ][..],
        &grid,
    ]
    .concat());
    same_figure(&made, &again, "fig4");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The regime map is drawn over phi, which a polyline has not: it is not
/// made with one, a map of the ellipse is not redrawn with one, and a
/// stored `lambda_2(phi)` curve whose header claims a polyline is refused.
#[test]
fn the_regime_map_is_never_drawn_with_a_polyline() {
    let dir = scratch("poly-regime");
    let cycles = Cycles::in_dir(&dir);
    let (made, again) = (dir.join("made"), dir.join("again"));
    let grid = ["--lambda", "4.5,5.5", "--phi", "0,pi/2"];
    let square = s(&cycles.square);
    refused(
        &[
            &["figure", "regime", "--cycle", &square, "--out", &s(&made)][..],
            &COARSE,
        ]
        .concat(),
        &["regime", "phi", "cycle:square.csv@sha256:", "drop --cycle"],
    );
    assert!(!made.exists());
    ok(&[
        &["figure", "regime", "--out", &s(&made)][..],
        &grid,
        &COARSE,
    ]
    .concat());
    let from = s(&made.join("regime.csv"));
    let again = s(&again);
    let head = [
        &["figure", "regime", "--from", &from, "--out", &again][..],
        &grid,
    ]
    .concat();
    refused(
        &[&head[..], &["--cycle", &square]].concat(),
        &["ellipse", "drop --cycle"],
    );
    // The curve beside it, edited to claim a polyline.
    let curve = made.join("regime_limit.csv");
    let text = std::fs::read_to_string(&curve).unwrap();
    let claimed = text.replacen(
        "# table = limit-curve\n",
        "# table = limit-curve\n# load-cycle = cycle:square.csv@sha256:0123456789abcdef\n",
        1,
    );
    assert_ne!(claimed, text);
    std::fs::write(&curve, claimed).unwrap();
    refused(&head, &["regime_limit.csv", "load-cycle"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_polyline_profile_is_redrawn_without_a_cycle_but_not_with_another() {
    let dir = scratch("poly-profile");
    let cycles = Cycles::in_dir(&dir);
    let (made, ellipse, again) = (dir.join("made"), dir.join("ellipse"), dir.join("again"));
    let square = s(&cycles.square);
    let one = ["--lambda", "5", "--initial", "OA"];
    ok(&[
        &["figure", "profile", "--cycle", &square, "--out", &s(&made)][..],
        &one,
        &COARSE,
    ]
    .concat());
    ok(&[
        &["figure", "profile", "--out", &s(&ellipse)][..],
        &one,
        &COARSE,
    ]
    .concat());
    let from = made.join("profile.csv");
    let recorded = recorded_cycle(&from);
    // The profile is drawn from its per-node columns alone, and its caption
    // names the cycle from the header: no cycle is needed, and the one
    // given, under any name, must be that one.
    ok(&[
        "figure",
        "profile",
        "--from",
        &s(&from),
        "--out",
        &s(&again),
    ]);
    same_figure(&made, &again, "profile");
    let caption = std::fs::read_to_string(again.join("profile.caption.txt")).unwrap();
    assert!(caption.contains(&recorded), "{caption}");
    let (other, renamed) = (s(&cycles.other), s(&cycles.renamed));
    let again_s = s(&again);
    let from_s = s(&from);
    let redraw = |extra: &[&str]| -> Vec<String> {
        [
            &[
                "figure", "profile", "--from", &from_s, "--out", &again_s, "--force",
            ][..],
            extra,
        ]
        .concat()
        .iter()
        .map(|a| a.to_string())
        .collect()
    };
    let args = redraw(&["--cycle", &other]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    refused(&args, &[&recorded, "cycle:other.csv@sha256:"]);
    let args = redraw(&["--cycle", &renamed]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    ok(&args);
    refused(
        &[
            "figure",
            "profile",
            "--from",
            &s(&ellipse.join("profile.csv")),
            "--out",
            &again_s,
            "--force",
            "--cycle",
            &square,
        ],
        &["ellipse", "drop --cycle"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
