//! `shakedown events`: the event log of one run as a labelled CSV.

use crate::common;

use std::f64::consts::PI;

use common::{scratch, shakedown, stderr};

const SMALL: [&str; 4] = ["--nodes", "64", "--steps", "200"];

fn events(dir: &std::path::Path, name: &str, extra: &[&str]) -> (Vec<String>, Vec<Vec<String>>) {
    let out = dir.join(name);
    let o = shakedown(
        &[
            &["events", "--preset", "fig7", "--out", out.to_str().unwrap()][..],
            &SMALL,
            extra,
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with('#'), "the metadata header comes first");
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

/// Point C (Fig. 7) ratchets monotonically forward (model.md section 1.3:
/// forward is dg < 0): every slip episode that advancing stick ends has
/// locked in forward slip, every event of a cycle lies within the cycle,
/// and the log is the same when made twice.
#[test]
fn point_c_locks_in_forward_slip_within_the_cycle() {
    let dir = scratch("events");
    let (header, rows) = events(&dir, "all.csv", &[]);
    assert_eq!(header.join(","), shakedown::io::events::EVENTS_HEADER);
    let stick: Vec<&Vec<String>> = rows.iter().filter(|r| r[4] == "advancing-stick").collect();
    assert!(!stick.is_empty());
    for r in &stick {
        let max: f64 = r[8].parse().unwrap();
        let mean: f64 = r[9].parse().unwrap();
        assert!(max <= 0.0 && mean <= 0.0, "backward slip locked in: {r:?}");
        assert!(
            max <= mean,
            "the largest forward slip is at least the mean: {r:?}"
        );
    }
    for r in rows.iter().filter(|r| r[0] != "0" && !r[1].is_empty()) {
        let t: f64 = r[1].parse().unwrap();
        assert!((0.0..2.0 * PI).contains(&t), "{r:?}");
    }
    let (_, again) = events(&dir, "again.csv", &[]);
    assert_eq!(rows, again);
    let (_, big) = events(
        &dir,
        "big.csv",
        &["--kind", "advancing-stick", "--min-nodes", "2"],
    );
    let expected = stick
        .iter()
        .filter(|r| r[5].parse::<usize>().unwrap() >= 2)
        .count();
    assert_eq!(big.len(), expected);
}
