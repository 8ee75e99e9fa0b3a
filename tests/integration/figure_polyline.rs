//! `figure --from` with a polyline cycle (`--cycle`, model.md section 5.4):
//! a file made from a polyline records the cycle by content
//! (`load-cycle = cycle:NAME@sha256:DIGEST`), and is redrawn with that
//! cycle, under any file name, or refused in one line naming both cycles;
//! never drawn as the paper's ellipse, nor with another cycle. One test per
//! reader: the slip map, a sweep figure, the memory figure, the regime
//! map's `_limit.csv` and the fretting profile.

use crate::common;

use std::path::{Path, PathBuf};

use common::{lambda_2, ok, scratch, shakedown, stderr};

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

/// The one line of a refused command (exit 2), which must contain every
/// one of `says`.
#[track_caller]
fn refused(args: &[&str], says: &[&str]) {
    let o = shakedown(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    for w in says {
        assert!(err.contains(w), "{args:?}: {err} lacks {w}");
    }
}

/// A test's folder with its cycle files: the square as `square.csv` and
/// again as `renamed.csv`, and another cycle as `other.csv`.
struct Scratch {
    dir: PathBuf,
    square: String,
    renamed: String,
    other: String,
}

impl Scratch {
    fn new(name: &str) -> Self {
        let dir = scratch(name);
        let file = |name: &str, text: &str| {
            let path = dir.join(name);
            std::fs::write(&path, text).unwrap();
            s(&path)
        };
        Self {
            square: file("square.csv", SQUARE),
            renamed: file("renamed.csv", SQUARE),
            other: file("other.csv", OTHER),
            dir,
        }
    }

    fn path(&self, name: &str) -> String {
        s(&self.dir.join(name))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The `load-cycle` a file's header records.
fn recorded_cycle(path: &str) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .find_map(|l| l.strip_prefix("# load-cycle = "))
        .unwrap_or_else(|| panic!("{path}: no load-cycle"))
        .to_string()
}

/// The plot and caption of `figure NAME` in folder `a` and in folder `b`
/// are the same, byte for byte.
#[track_caller]
fn same_figure(a: &str, b: &str, name: &str) {
    for ext in [".svg", ".caption.txt"] {
        let read = |dir: &str| std::fs::read(Path::new(dir).join(format!("{name}{ext}"))).unwrap();
        assert_eq!(read(a), read(b), "{name}{ext}");
    }
}

/// `figure NAME` (with the list flags `grid`) made from the square into
/// `made/` and from the ellipse into `ellipse/`; the square's CSV redrawn
/// without a cycle and with another one, and the ellipse's with the
/// square, each refused in one line naming the cycles; then the square's
/// redrawn with its cycle under another file name into `again/`: the same
/// plot and caption. The outputs of the first run and of the redraw.
fn made_and_redrawn(t: &Scratch, name: &str, grid: &[&str]) -> (String, String) {
    let (made, ellipse, again) = (t.path("made"), t.path("ellipse"), t.path("again"));
    let figure = [&["figure", name][..], grid].concat();
    let first = ok(&[
        &figure[..],
        &["--cycle", &t.square, "--out", &made],
        &COARSE,
    ]
    .concat());
    ok(&[&figure[..], &["--out", &ellipse], &COARSE].concat());
    let from = format!("{made}/{name}.csv");
    let recorded = recorded_cycle(&from);
    let redraw = [&figure[..], &["--out", &again]].concat();
    refused(
        &[&redraw[..], &["--from", &from]].concat(),
        &[&from, &recorded, "--cycle"],
    );
    refused(
        &[&redraw[..], &["--from", &from, "--cycle", &t.other]].concat(),
        &[&recorded, "cycle:other.csv@sha256:", "differ"],
    );
    let from_ellipse = format!("{ellipse}/{name}.csv");
    refused(
        &[
            &redraw[..],
            &["--from", &from_ellipse, "--cycle", &t.square],
        ]
        .concat(),
        &["ellipse", "cycle:square.csv@sha256:", "drop --cycle"],
    );
    // Nothing was written by the refusals.
    assert!(!Path::new(&again).exists());
    let redrawn = ok(&[&redraw[..], &["--from", &from, "--cycle", &t.renamed]].concat());
    same_figure(&made, &again, name);
    // The caption names the cycle as the file records it.
    let caption = std::fs::read_to_string(format!("{again}/{name}.caption.txt")).unwrap();
    assert!(caption.contains(&recorded), "{caption}");
    (first, redrawn)
}

#[test]
fn a_polyline_slip_map_is_redrawn_with_its_own_cycle() {
    let t = Scratch::new("poly-slip-map");
    made_and_redrawn(&t, "fig5", &[]);
    // The map is the square's: every load of its load table lies on the
    // square x = x0 + lambda u, y = y0 + lambda v with max(|u|, |v|) = 1/2
    // (fig5: lambda = 7, A = (pi, 3 pi / 4)).
    let load = std::fs::read_to_string(t.path("made/fig5_load.csv")).unwrap();
    let (x0, y0, lambda) = (std::f64::consts::PI, 0.75 * std::f64::consts::PI, 7.0);
    let mut rows = 0;
    for line in load.lines().skip_while(|l| l.starts_with('#')).skip(1) {
        let f: Vec<f64> = line.split(',').map(|t| t.parse().unwrap()).collect();
        let (u, v) = ((f[1] - x0) / lambda, (f[2] - y0) / lambda);
        assert!((u.abs().max(v.abs()) - 0.5).abs() < 1e-9, "{line}");
        rows += 1;
    }
    assert!(rows > 100, "{rows}");
}

#[test]
fn a_polyline_sweep_figure_is_redrawn_with_its_own_cycle() {
    let t = Scratch::new("poly-sweep");
    let (first, redrawn) =
        made_and_redrawn(&t, "fig3", &["--lambda", "4.5,5.5", "--initial", "OA"]);
    // The redraw's lambda_2 is the square's, as `limit` gives it for that
    // cycle (the LP at its vertices), not the ellipse's.
    let limit = ok(&["limit", "--cycle", &t.square, "--nodes", "32"]);
    assert_eq!(lambda_2(&redrawn), lambda_2(&first));
    assert!(
        (lambda_2(&redrawn) - lambda_2(&limit)).abs() < 2e-6,
        "{redrawn}\n{limit}"
    );
}

#[test]
fn a_polyline_memory_figure_is_redrawn_with_its_own_cycle() {
    let t = Scratch::new("poly-memory");
    made_and_redrawn(&t, "fig4", &["--lambda", "4.5,5.5"]);
}

/// The regime map is drawn over phi, which a polyline has not: it is not
/// made with one, a map of the ellipse is not redrawn with one, and a
/// stored `lambda_2(phi)` curve whose header claims a polyline is refused.
#[test]
fn the_regime_map_is_never_drawn_with_a_polyline() {
    let t = Scratch::new("poly-regime");
    let (made, again) = (t.path("made"), t.path("again"));
    let grid = ["--lambda", "4.5,5.5", "--phi", "0,pi/2"];
    refused(
        &[
            &["figure", "regime", "--cycle", &t.square, "--out", &made][..],
            &COARSE,
        ]
        .concat(),
        &["regime", "phi", "cycle:square.csv@sha256:", "drop --cycle"],
    );
    assert!(!Path::new(&made).exists());
    ok(&[&["figure", "regime", "--out", &made][..], &grid, &COARSE].concat());
    let from = format!("{made}/regime.csv");
    let redraw = [
        &["figure", "regime", "--from", &from, "--out", &again][..],
        &grid,
    ]
    .concat();
    refused(
        &[&redraw[..], &["--cycle", &t.square]].concat(),
        &["ellipse", "drop --cycle"],
    );
    // The curve beside it, edited to claim a polyline.
    let curve = format!("{made}/regime_limit.csv");
    let text = std::fs::read_to_string(&curve).unwrap();
    let claimed = text.replacen(
        "# table = limit-curve\n",
        "# table = limit-curve\n# load-cycle = cycle:square.csv@sha256:0123456789abcdef\n",
        1,
    );
    assert_ne!(claimed, text);
    std::fs::write(&curve, claimed).unwrap();
    refused(&redraw, &["regime_limit.csv", "load-cycle"]);
}

#[test]
fn a_polyline_profile_is_redrawn_without_a_cycle_but_not_with_another() {
    let t = Scratch::new("poly-profile");
    let (made, ellipse, again) = (t.path("made"), t.path("ellipse"), t.path("again"));
    let one = ["--lambda", "5", "--initial", "OA"];
    let figure = [&["figure", "profile"][..], &one, &COARSE].concat();
    ok(&[&figure[..], &["--cycle", &t.square, "--out", &made]].concat());
    ok(&[&figure[..], &["--out", &ellipse]].concat());
    let from = format!("{made}/profile.csv");
    let recorded = recorded_cycle(&from);
    // The profile is drawn from its per-node columns alone, and its caption
    // names the cycle from the header: no cycle is needed, and the one
    // given, under any name, must be that one.
    let redraw = [
        "figure", "profile", "--from", &from, "--out", &again, "--force",
    ];
    ok(&redraw);
    same_figure(&made, &again, "profile");
    let caption = std::fs::read_to_string(format!("{again}/profile.caption.txt")).unwrap();
    assert!(caption.contains(&recorded), "{caption}");
    refused(
        &[&redraw[..], &["--cycle", &t.other]].concat(),
        &[&recorded, "cycle:other.csv@sha256:"],
    );
    ok(&[&redraw[..], &["--cycle", &t.renamed]].concat());
    // Neither would a model or case flag change it: refused, not ignored.
    for flag in [
        &["--friction", "0.2"][..],
        &["--lambda", "6"],
        &["--run-out"],
    ] {
        refused(&[&redraw[..], flag].concat(), &[flag[0], "as it was run"]);
    }
    let from_ellipse = format!("{ellipse}/profile.csv");
    refused(
        &[
            "figure",
            "profile",
            "--from",
            &from_ellipse,
            "--out",
            &again,
            "--force",
            "--cycle",
            &t.square,
        ],
        &["ellipse", "drop --cycle"],
    );
}

/// The design figure is the paper's question on its ellipse: a polyline is
/// refused whether the frontier is to be made or redrawn.
#[test]
fn the_design_figure_refuses_a_polyline() {
    let t = Scratch::new("poly-design");
    let out = t.path("out");
    for from in [None, Some(t.path("frontier.csv"))] {
        let mut args = vec!["figure", "design", "--cycle", &t.square, "--out", &out];
        if let Some(f) = &from {
            args.extend(["--from", f.as_str()]);
        }
        refused(&args, &["--cycle", "square.csv", "drop --cycle"]);
    }
    assert!(!Path::new(&out).exists());
}

/// `design` itself refuses a polyline, from the flag or from a preset.
#[test]
fn design_refuses_a_polyline() {
    let t = Scratch::new("poly-design-run");
    refused(
        &["design", "--cycle", &t.square, "--lambda", "3"],
        &["--cycle", "square.csv", "elliptical"],
    );
    refused(
        &["design", "--preset", "biharmonic", "--lambda", "3"],
        &["--preset biharmonic", "elliptical"],
    );
}
