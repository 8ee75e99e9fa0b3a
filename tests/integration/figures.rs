//! `shakedown figure`: the files it writes are well formed, and the paper's
//! qualitative statements hold in reduced versions of the figures.

use crate::common;

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;

use common::{check_svg, ok, png_size, read_csv, scratch, shakedown, stderr, stdout};
use shakedown::analysis::case::{Case, CaseParams};
use shakedown::analysis::slip_map::slip_map;
use shakedown::stepping::slip_zones;
use shakedown::SlipDirection;

const SMALL: [&str; 4] = ["--nodes", "64", "--steps", "200"];

fn figure(name: &str, dir: &Path, extra: &[&str]) {
    let out = dir.to_str().unwrap();
    let o = shakedown(&[&["figure", name, "--out", out][..], &SMALL, extra].concat());
    assert!(o.status.success(), "{name}: {}", stderr(&o));
    assert!(
        stdout(&o).contains(&format!("{name}.svg")),
        "{}",
        stdout(&o)
    );
}

fn check_plot_files(dir: &Path, name: &str) {
    let svg = std::fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap();
    check_svg(&svg).unwrap_or_else(|e| panic!("{name}.svg: {e}"));
    let png = std::fs::read(dir.join(format!("{name}.png"))).unwrap();
    let (w, h) = png_size(&png).unwrap_or_else(|| panic!("{name}.png is not a PNG"));
    assert!(w >= 640 && h >= 480, "{name}.png is {w}x{h}");
}

/// Rows of a sweep CSV grouped by lambda: (initial, state, W) each.
fn by_lambda(path: &Path) -> BTreeMap<String, Vec<(String, String, f64)>> {
    let (header, rows) = read_csv(path);
    assert_eq!(header.join(","), shakedown::analysis::sweep::CSV_HEADER);
    let mut out: BTreeMap<String, Vec<_>> = BTreeMap::new();
    for r in rows {
        out.entry(r[0].clone()).or_default().push((
            r[2].clone(),
            r[3].clone(),
            r[4].parse::<f64>().unwrap(),
        ));
    }
    out
}

fn same_w(runs: &[(String, String, f64)], rel: f64) -> bool {
    let max = runs.iter().map(|r| r.2).fold(f64::MIN, f64::max);
    let min = runs.iter().map(|r| r.2).fold(f64::MAX, f64::min);
    min > 0.0 && (max - min) <= rel * max
}

#[test]
fn fig3_files_are_well_formed_and_ratchetting_forgets_the_transient() {
    let dir = scratch("fig3");
    // Point B (lambda = 7) is in the ratchetting range; 4 is below every
    // shakedown limit.
    figure("fig3", &dir, &["--lambda", "4,7"]);
    check_plot_files(&dir, "fig3");
    let groups = by_lambda(&dir.join("fig3.csv"));
    assert_eq!(groups.len(), 2);
    for runs in groups.values() {
        // The 25 transients and the optimal slip.
        assert_eq!(runs.len(), 26);
        assert!(runs.iter().any(|r| r.0 == "optimal"));
        assert!(runs.iter().any(|r| r.0 == "OA"));
    }
    assert!(
        groups["4"].iter().all(|r| r.1 == "shakedown"),
        "{:?}",
        groups["4"]
    );
    let b = &groups["7"];
    assert!(b.iter().all(|r| r.1.starts_with("ratchetting")), "{b:?}");
    // In ratchetting every point slips each cycle: no memory is left, so
    // every initial condition gives the same W.
    assert!(same_w(b, 1e-3), "{b:?}");
    // lambda_2 is marked, and its optimal slip written.
    let (header, rows) = read_csv(&dir.join("fig3_limit.csv"));
    assert_eq!(header, ["theta", "g"]);
    assert_eq!(rows.len(), 64);
    let svg = std::fs::read_to_string(dir.join("fig3.svg")).unwrap();
    assert!(svg.contains("λ₂"));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn fig8_sequence_shakedown_monotonic_then_non_monotonic_ratchetting() {
    let dir = scratch("fig8");
    figure("fig8", &dir, &["--lambda", "4,5.5,7"]);
    check_plot_files(&dir, "fig8");
    let groups = by_lambda(&dir.join("fig8.csv"));
    let states = |l: &str| -> Vec<String> { groups[l].iter().map(|r| r.1.clone()).collect() };
    for (l, expected) in [
        ("4", "shakedown"),
        ("5.5", "ratchetting-monotonic"),
        ("7", "ratchetting-non-monotonic"),
    ] {
        assert_eq!(groups[l].len(), 25);
        assert!(
            states(l).iter().all(|s| s == expected),
            "{l}: {:?}",
            states(l)
        );
    }
    // Memory-free: W does not depend on the transient.
    assert!(same_w(&groups["5.5"], 1e-3), "{:?}", groups["5.5"]);
    assert!(same_w(&groups["7"], 1e-3), "{:?}", groups["7"]);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn fig4_memory_vanishes_in_ratchetting() {
    let dir = scratch("fig4");
    figure(
        "fig4",
        &dir,
        &["--lambda", "5.5,7", "--initial", "OA,7,-7,-7,7,3,7"],
    );
    check_plot_files(&dir, "fig4");
    let (header, rows) = read_csv(&dir.join("fig4.csv"));
    assert_eq!(
        header.join(","),
        shakedown::io::memory_csv::MEMORY_HEADER,
        "{header:?}"
    );
    assert_eq!(rows.len(), 2);
    let col = |r: &Vec<String>, k: usize| r[k].parse::<f64>().unwrap();
    // lambda = 5.5: cyclic slip, so some interface keeps its locked-in slip.
    let cyclic = &rows[0];
    assert_eq!(col(cyclic, 5) as usize, 4, "{cyclic:?}");
    assert!(col(cyclic, 2) > 0.0 && col(cyclic, 3) > 0.0, "{cyclic:?}");
    // lambda = 7: ratchetting, every point slips each cycle: R = r = 0.
    let ratchet = &rows[1];
    assert_eq!(col(ratchet, 6) as usize, 4, "{ratchet:?}");
    assert!(col(ratchet, 2) < 1e-3, "{ratchet:?}");
    assert_eq!(col(ratchet, 3), 0.0, "{ratchet:?}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn phase_sweeps_write_one_row_per_run() {
    let dir = scratch("fig9");
    figure("fig9", &dir, &["--lambda", "5,6", "--phi", "0,pi/2,pi"]);
    check_plot_files(&dir, "fig9");
    let (_, rows) = read_csv(&dir.join("fig9.csv"));
    assert_eq!(rows.len(), 6);
    assert!(rows.iter().all(|r| r[2] == "OA"));
    figure("fig6", &dir, &["--phi", "0,pi/2", "--initial", "OA,7,-7"]);
    check_plot_files(&dir, "fig6");
    let (_, rows) = read_csv(&dir.join("fig6.csv"));
    assert_eq!(rows.len(), 4);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn fig5_slip_map_files() {
    let dir = scratch("fig5");
    figure("fig5", &dir, &[]);
    check_plot_files(&dir, "fig5");
    let (header, rows) = read_csv(&dir.join("fig5.csv"));
    assert_eq!(header, ["omega_t", "theta", "direction"]);
    // One row per sub-segment: the 200 increments, split at events.
    let text = std::fs::read_to_string(dir.join("fig5.csv")).unwrap();
    let count: usize = text
        .lines()
        .find_map(|l| l.strip_prefix("# rows = "))
        .expect("the header gives the rows")
        .parse()
        .unwrap();
    assert!(count >= 200, "{count}");
    assert_eq!(rows.len(), count * 64);
    assert!(rows
        .iter()
        .all(|r| ["-1", "0", "1"].contains(&r[2].as_str())));
    let (header, rows) = read_csv(&dir.join("fig5_load.csv"));
    assert_eq!(header, ["omega_t", "x", "y", "radial", "torque"]);
    assert_eq!(rows.len(), count + 1);
    // In phase, the cycle is a line through A = (pi, 3 pi / 4) starting there.
    let x0: f64 = rows[0][1].parse().unwrap();
    let y0: f64 = rows[0][2].parse().unwrap();
    assert!((x0 - PI).abs() < 1e-9 && (y0 - 0.75 * PI).abs() < 1e-9);
    let _ = std::fs::remove_dir_all(dir);
}

fn map_of(lambda: f64, phase: f64) -> shakedown::analysis::slip_map::SlipMap {
    let params = CaseParams {
        load_factor: lambda,
        phase,
        nodes: 64,
        steps: 200,
        ..CaseParams::default()
    };
    slip_map(&Case::from_params(&params).unwrap()).unwrap()
}

/// Whether a zone `(first, len)` on `n` nodes holds the node nearest `theta`.
fn holds(zone: (usize, usize), n: usize, theta: f64) -> bool {
    let j = ((theta.rem_euclid(2.0 * PI)) / (2.0 * PI) * n as f64).round() as usize % n;
    (j + n - zone.0) % n < zone.1
}

/// Whether node `j` of `n` lies within `tol` of `theta` round the circle.
fn near(j: usize, n: usize, theta: f64, tol: f64) -> bool {
    let t = 2.0 * PI * (j % n) as f64 / n as f64;
    let d = (t - theta).rem_euclid(2.0 * PI);
    d.min(2.0 * PI - d) <= tol
}

#[test]
fn fig5_point_b_slips_back_and_forth() {
    let map = map_of(7.0, 0.0);
    assert_eq!(
        map.outcome.state(),
        shakedown::stepping::steady::SteadyState::RatchettingNonMonotonic
    );
    let dirs: Vec<SlipDirection> = map.rows.iter().flat_map(|r| r.directions.clone()).collect();
    assert!(dirs.contains(&SlipDirection::Forward) && dirs.contains(&SlipDirection::Backward));
}

#[test]
fn fig7_point_c_one_zone_splits_travels_and_merges() {
    let map = map_of(5.1, 0.5 * PI);
    assert_eq!(
        map.outcome.state(),
        shakedown::stepping::steady::SteadyState::RatchettingMonotonic
    );
    let n = map.nodes;
    let zones: Vec<Vec<shakedown::stepping::SlipZone>> =
        map.rows.iter().map(|r| slip_zones(&r.directions)).collect();
    // Monotonic: every slip of the cycle goes one way.
    let ways: std::collections::HashSet<_> = zones.iter().flatten().map(|z| z.direction).collect();
    assert_eq!(ways.len(), 1, "{ways:?}");
    let k = zones.len();
    let mut formed = None;
    let mut merged = None;
    let mut split = false;
    for i in 0..k {
        let (before, now) = (&zones[(i + k - 1) % k], &zones[i]);
        if before.is_empty() && now.len() == 1 {
            formed = Some((now[0].first, now[0].len));
        }
        if before.len() == 1 && now.len() == 2 {
            split = true;
        }
        if before.len() == 2 && now.len() == 1 {
            merged = Some((now[0].first, now[0].len));
        }
    }
    let formed = formed.expect("a slip zone forms after a slip-free interval");
    let merged = merged.expect("two slip zones merge");
    assert!(split, "the zone splits in two");
    // Where the first node starts to slip (the rows end at the exact event
    // times, so the zone is caught as it forms, one node wide).
    assert!(
        (0..formed.1).any(|k| near(formed.0 + k, n, -0.75 * PI, PI / 8.0)),
        "formed at {formed:?} of {n}"
    );
    assert!(holds(merged, n, 0.25 * PI), "merged at {merged:?} of {n}");
}

const TINY: [&str; 4] = ["--nodes", "32", "--steps", "200"];

#[test]
fn figure_from_csv_redraws_the_same_plot_without_running() {
    let dir = scratch("fig3_from");
    let d = dir.to_str().unwrap();
    // The list flags that made it, given again to redraw it: a CSV made
    // under other flags is refused, naming the key that differs.
    let grid = ["--lambda", "4.5,5,6.5", "--initial", "OA,7,-7,optimal"];
    ok(&[&["figure", "fig3", "--out", d][..], &grid, &TINY].concat());
    let svg = std::fs::read_to_string(dir.join("fig3.svg")).unwrap();
    let again = scratch("fig3_from_again");
    let csv = dir.join("fig3.csv");
    let out = ok(&[
        &[
            "figure",
            "fig3",
            "--from",
            csv.to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
        ][..],
        &grid,
        &TINY,
    ]
    .concat());
    assert!(out.contains("9 runs"), "{out}");
    assert_eq!(
        std::fs::read_to_string(again.join("fig3.svg")).unwrap(),
        svg
    );
    assert!(!again.join("fig3.csv").exists(), "--from writes no CSV");
    // The optimal-slip runs have their own legend entry, the dashed
    // lambda_2 line a dashed sample.
    assert!(
        svg.contains("optimal slip (λ₂ programme)"),
        "no optimal legend"
    );
    assert!(svg.contains("(b)"), "no log panel");
}

/// `figure fig5 --from` and `fig7 --from` read the slip map back from the
/// CSVs the figure wrote (nothing is run) and draw the same SVG, byte for
/// byte; the model flags do not matter then.
#[test]
fn slip_map_from_csv_redraws_the_same_plot_without_running() {
    for name in ["fig5", "fig7"] {
        let dir = scratch(&format!("{name}_from"));
        let d = dir.to_str().unwrap();
        ok(&[&["figure", name, "--out", d][..], &TINY].concat());
        let svg = std::fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap();
        let again = scratch(&format!("{name}_from_again"));
        let csv = dir.join(format!("{name}.csv"));
        let out = ok(&[
            "figure",
            name,
            "--from",
            csv.to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
            "--nodes",
            "16",
        ]);
        assert!(out.contains("steady state:"), "{out}");
        assert_eq!(
            std::fs::read_to_string(again.join(format!("{name}.svg"))).unwrap(),
            svg,
            "{name}: the redraw differs"
        );
        assert!(
            !again.join(format!("{name}.csv")).exists(),
            "--from writes no CSV"
        );
        assert!(!again.join(format!("{name}_load.csv")).exists());
        let _ = std::fs::remove_dir_all(&again);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// A CSV that is not a slip map of this version, or is cut short, is
/// refused in one line naming the file, with status 2.
#[test]
fn slip_map_from_a_bad_csv_is_a_one_line_error() {
    let dir = scratch("fig5_bad_from");
    let d = dir.to_str().unwrap();
    ok(&[&["figure", "fig5", "--out", d][..], &TINY].concat());
    let map = std::fs::read_to_string(dir.join("fig5.csv")).unwrap();
    let load = std::fs::read_to_string(dir.join("fig5_load.csv")).unwrap();
    let sweep = dir.join("sweep.csv");
    ok(&[
        "sweep",
        "--lambda",
        "5",
        "--nodes",
        "16",
        "--steps",
        "50",
        "--out",
        sweep.to_str().unwrap(),
    ]);
    let sweep = std::fs::read_to_string(&sweep).unwrap();
    let cut_lines: String = map.split_inclusive('\n').take(40).collect();
    let cases: [(&str, String, String, &str); 6] = [
        ("kind", sweep.clone(), sweep, "not a slip map"),
        (
            "version",
            map.replacen("# shakedown = ", "# shakedown = 0.0.0-", 1),
            load.clone(),
            "written by shakedown 0.0.0-",
        ),
        (
            "foreign",
            map.lines()
                .filter(|l| !l.starts_with('#'))
                .map(|l| format!("{l}\n"))
                .collect(),
            load.clone(),
            "not an output of shakedown",
        ),
        (
            "cut",
            map[..map.len() / 2].to_string(),
            load.clone(),
            "cut short",
        ),
        ("rows", cut_lines, load.clone(), "cut short or was edited"),
        (
            "other-run",
            map.clone(),
            load.replacen("# lambda = ", "# lambda = 1", 1),
            "differs from the map's",
        ),
    ];
    for (what, map_text, load_text, says) in cases {
        let file = dir.join(format!("{what}.csv"));
        std::fs::write(&file, map_text).unwrap();
        std::fs::write(dir.join(format!("{what}_load.csv")), load_text).unwrap();
        let o = shakedown(&[
            "figure",
            "fig5",
            "--from",
            file.to_str().unwrap(),
            "--out",
            d,
            "--force",
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{what}: {e}");
        assert_eq!(e.lines().count(), 1, "{what}: {e}");
        assert!(e.contains(what) && e.contains(says), "{what}: {e}");
    }
    // Without its load table beside it.
    std::fs::remove_file(dir.join("cut_load.csv")).unwrap();
    let cut = dir.join("cut.csv");
    let o = shakedown(&[
        "figure",
        "fig5",
        "--from",
        cut.to_str().unwrap(),
        "--out",
        d,
        "--force",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cut_load.csv"), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn figure_resume_finishes_an_interrupted_csv() {
    let dir = scratch("fig9_resume");
    let d = dir.to_str().unwrap();
    let args = [
        &[
            "figure",
            "fig9",
            "--out",
            d,
            "--lambda",
            "5,6",
            "--phi",
            "0:pi:pi/4",
        ][..],
        &TINY,
    ]
    .concat();
    ok(&args);
    let full = std::fs::read_to_string(dir.join("fig9.csv")).unwrap();
    // Cut the file after three rows and half of the fourth (the `#`
    // metadata lines and the column header come first).
    let head = full.lines().take_while(|l| l.starts_with('#')).count() + 1;
    let mut cut: Vec<&str> = full.split_inclusive('\n').take(head + 4).collect();
    let half = &cut[head + 3][..cut[head + 3].len() / 2];
    cut[head + 3] = half;
    std::fs::write(dir.join("fig9.csv"), cut.concat()).unwrap();
    let out = shakedown(&[&args[..], &["--resume"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("resuming: 3 of 10"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read_to_string(dir.join("fig9.csv")).unwrap(), full);
    check_plot_files(&dir, "fig9");
}

#[test]
fn regime_map_writes_csv_svg_png_and_the_limit_curve() {
    let dir = scratch("regime");
    let d = dir.to_str().unwrap();
    ok(&[
        &[
            "figure",
            "regime",
            "--out",
            d,
            "--lambda",
            "4.5,5.5,7",
            "--phi",
            "0,pi/2",
        ][..],
        &TINY,
    ]
    .concat());
    check_plot_files(&dir, "regime");
    let (header, rows) = read_csv(&dir.join("regime.csv"));
    assert_eq!(header.join(","), shakedown::analysis::sweep::CSV_HEADER);
    assert_eq!(rows.len(), 6);
    let (h, curve) = read_csv(&dir.join("regime_limit.csv"));
    assert_eq!(h.join(","), "phi,lambda_2,lower_bound");
    assert_eq!(curve.len(), 2);
    let l2: f64 = curve[0][1].parse().unwrap();
    assert!((l2 - 4.9).abs() < 0.05, "{l2}");
    // Two transients make no regime map.
    let o = shakedown(&["figure", "regime", "--out", d, "--initial", "OA,7,-7"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn limit_prints_lambda_2_against_phi() {
    let dir = scratch("limit_curve");
    let file = dir.join("curve.csv");
    let out = ok(&[
        "limit",
        "--phi",
        "0:pi:pi/2",
        "--nodes",
        "32",
        "--samples",
        "16",
        "--out",
        file.to_str().unwrap(),
    ]);
    // With --out the terminal gets a one-line summary, the file the table:
    // the model and grid first as `#` lines, then the rows.
    assert_eq!(out.lines().count(), 1, "{out}");
    assert!(out.contains("3 of 3 phases"), "{out}");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("# friction = 0.1"), "{text}");
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines[0], "phi,lambda_2,lower_bound");
    assert_eq!(lines.len(), 4, "{text}");
}

#[test]
fn slip_map_time_origin_option() {
    let dir = scratch("fig7_origin");
    let d = dir.to_str().unwrap();
    let out = ok(&[
        &["figure", "fig7", "--out", d, "--time-origin", "0"][..],
        &TINY,
    ]
    .concat());
    assert!(out.contains("drawn from omega t = 0.0000 pi"), "{out}");
    let o = shakedown(&["figure", "fig7", "--out", d, "--time-origin", "soon"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stderr(&o).lines().count(), 1, "{}", stderr(&o));
}

#[test]
fn custom_path_through_7_minus_7_is_the_paper_point() {
    let via = shakedown::model::path::Initial::Via { a: 7, b: -7 };
    let params = CaseParams {
        nodes: 32,
        steps: 200,
        load_factor: 5.5,
        ..CaseParams::default()
    };
    let mut case = Case::from_params(&params).unwrap();
    case.set_initial(via).unwrap();
    let a = case.stepper().run_to_steady().unwrap();
    let points = shakedown::io::parse::parse_points("1.75pi,-1.75pi").unwrap();
    let points = points
        .into_iter()
        .map(|(x, y)| shakedown::LoadPoint::new(x, y))
        .collect();
    case.set_initial(
        shakedown::model::path::Initial::custom_for(points, &case.material()).unwrap(),
    )
    .unwrap();
    let b = case.stepper().run_to_steady().unwrap();
    assert_eq!(a, b);
    // The same from the command line.
    let flags = [
        "--lambda", "5.5", "--nodes", "32", "--steps", "200", "--json",
    ];
    let via = ok(&[&["run", "--initial", "7,-7"][..], &flags].concat());
    let path = ok(&[&["run", "--initial-path", "1.75pi,-1.75pi"][..], &flags].concat());
    let w = |s: &str| {
        let v: serde_json::Value = serde_json::from_str(s).unwrap();
        v["dissipation"].clone()
    };
    assert_eq!(w(&via), w(&path));
}

#[test]
fn bad_custom_points_are_one_line_errors() {
    for bad in ["0,7", "0,nan", "13,0", "1,2;3", ""] {
        let o = shakedown(&["run", "--initial-path", bad, "--nodes", "32"]);
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        let e = stderr(&o);
        assert_eq!(e.lines().count(), 1, "{bad}: {e}");
        assert!(e.contains("--initial-path"), "{bad}: {e}");
    }
    let e = stderr(&shakedown(&["run", "--initial-path", "0,7"]));
    assert!(e.contains("gross slip"), "{e}");
    let e = stderr(&shakedown(&["run", "--initial-path", "13,0"]));
    assert!(e.contains("separat"), "{e}");
    // A sweep runs the custom path (named by its points in the CSV).
    let o = ok(&[
        "sweep",
        "--lambda",
        "5",
        "--initial-path",
        "1.75pi,-1.75pi",
        "--nodes",
        "32",
        "--steps",
        "200",
    ]);
    assert!(o.contains("\"path:1.75pi,-1.75pi\""), "{o}");
}
