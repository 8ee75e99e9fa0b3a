//! `shakedown figure`: the files it writes are well formed, and the paper's
//! qualitative statements hold in reduced versions of the figures.

mod common;

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;

use common::{check_svg, png_size, read_csv, scratch, shakedown, stderr, stdout};
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
        shakedown::analysis::memory::MEMORY_HEADER,
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
    assert_eq!(rows.len(), 200 * 64);
    assert!(rows
        .iter()
        .all(|r| ["-1", "0", "1"].contains(&r[2].as_str())));
    let (header, rows) = read_csv(&dir.join("fig5_load.csv"));
    assert_eq!(header, ["omega_t", "x", "y", "radial", "torque"]);
    assert_eq!(rows.len(), 201);
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

#[test]
fn fig5_point_b_slips_back_and_forth() {
    let map = map_of(7.0, 0.0);
    assert_eq!(
        map.summary.state,
        shakedown::analysis::steady::SteadyState::RatchettingNonMonotonic
    );
    let dirs: Vec<SlipDirection> = map.rows.iter().flat_map(|r| r.directions.clone()).collect();
    assert!(dirs.contains(&SlipDirection::Forward) && dirs.contains(&SlipDirection::Backward));
}

#[test]
fn fig7_point_c_one_zone_splits_travels_and_merges() {
    let map = map_of(5.1, 0.5 * PI);
    assert_eq!(
        map.summary.state,
        shakedown::analysis::steady::SteadyState::RatchettingMonotonic
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
    assert!(holds(formed, n, -0.75 * PI), "formed at {formed:?} of {n}");
    assert!(holds(merged, n, 0.25 * PI), "merged at {merged:?} of {n}");
}
