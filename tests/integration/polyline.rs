//! Polyline cycles (`--cycle`, model.md section 5.4) against the physics:
//! the paper's ellipse written as its own load points gives the built-in
//! cycle's results, and a square, a figure-eight and a two-harmonic cycle
//! meet the closed forms of model.md section 2.3 (gross slip exactly where
//! the cycle reaches `y = 2 pi`; no slip while it stays in the stick
//! diamond).

use std::f64::consts::PI;

use crate::common::{scratch, shakedown, stderr};
use shakedown::analysis::limit::shakedown_limit;
use shakedown::io::cycle::{cycle_csv, inline_cycle};
use shakedown::prelude::*;
use shakedown::stepping::ShakedownProof;

const Y0: f64 = 0.75 * PI;

/// The paper's ellipse (`psi = 5/8`, phase `phi`) as `m` offsets at
/// `omega t = 2 pi k / m`, as a user would write them.
fn ellipse(phase: f64, m: usize) -> Vec<LoadPoint> {
    let psi: f64 = 0.625;
    let norm = (1.0 + psi * psi).sqrt();
    (0..m)
        .map(|k| {
            let t = 2.0 * PI * k as f64 / m as f64;
            LoadPoint::new(t.sin() / norm, psi * (t + phase).sin() / norm)
        })
        .collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn the_ellipse_as_its_400_load_points_gives_the_built_in_results() {
    for (load_factor, phase, initial) in [
        (5.5, 0.5 * PI, Initial::Direct),
        (5.5, 0.3 * PI, Initial::Via { a: 7, b: -7 }),
        (6.0, 0.0, Initial::Via { a: 7, b: -7 }),
    ] {
        let built_in = Case::builder()
            .load_factor(load_factor)
            .phase(phase)
            .initial(initial.clone())
            .nodes(64)
            .steps(400)
            .build()
            .unwrap();
        let polyline = inline_cycle(ellipse(phase, 400)).unwrap();
        let points = Case::builder()
            .load_factor(load_factor)
            .cycle(polyline)
            .initial(initial)
            .nodes(64)
            .steps(400)
            .build()
            .unwrap();
        let (a, b) = (built_in.run().unwrap(), points.run().unwrap());
        assert_eq!(a.state(), b.state(), "{load_factor} {phase}");
        assert_eq!(a.cycles, b.cycles, "{load_factor} {phase}");
        assert!(
            rel(a.dissipation, b.dissipation) < 1e-9,
            "{load_factor} {phase}: W {} against {}",
            a.dissipation,
            b.dissipation
        );
        // lambda_2 of the ellipse sampled at the same 400 instants: the
        // polyline's is exact for its chords, the ellipse's is this
        // sampling's bound.
        let sampled = shakedown_limit(
            &built_in.material(),
            built_in.cycle().center(),
            0.625,
            phase,
            &built_in.disc(),
            400,
        )
        .unwrap();
        let exact = points.limit().unwrap();
        assert!(
            rel(sampled.load_factor, exact.load_factor) < 1e-9,
            "{phase}: lambda_2 {} against {}",
            sampled.load_factor,
            exact.load_factor
        );
        assert_eq!(exact.lower_bound, exact.load_factor);
    }
}

/// A square, a figure-eight and a two-harmonic cycle: `(name, offsets)`,
/// each starting at an offset whose entry from `A` stays low.
fn shapes() -> Vec<(&'static str, Vec<LoadPoint>)> {
    let sampled = |m: usize, f: &dyn Fn(f64) -> (f64, f64)| -> Vec<LoadPoint> {
        (0..m)
            .map(|k| {
                let (u, v) = f(2.0 * PI * k as f64 / m as f64);
                LoadPoint::new(u, v)
            })
            .collect()
    };
    vec![
        (
            "square",
            [(1.0, -1.0), (1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0)]
                .iter()
                .map(|&(u, v)| LoadPoint::new(u, v))
                .collect(),
        ),
        ("figure-eight", sampled(40, &|t| (t.sin(), (2.0 * t).sin()))),
        (
            "two-harmonic",
            sampled(64, &|t| {
                (t.sin(), 0.6 * t.sin() + 0.4 * (2.0 * t + 0.7).sin())
            }),
        ),
    ]
}

fn run(vertices: &[LoadPoint], load_factor: f64, safe_state: bool) -> (Outcome, Vec<f64>) {
    let m = vertices.len();
    let case = Case::builder()
        .load_factor(load_factor)
        .cycle(inline_cycle(vertices.to_vec()).unwrap())
        .nodes(32)
        .steps(m * 64usize.div_ceil(m))
        .max_cycles(30)
        .safe_state(safe_state)
        .build()
        .unwrap();
    let mut stepper = case.stepper();
    let outcome = stepper.run_to_steady().unwrap();
    let history = stepper.history().iter().map(|r| r.dissipation).collect();
    (outcome, history)
}

/// Gross slip sets in exactly where the cycle reaches `y = 2 pi` (model.md
/// section 2.3), whatever the slip: on a polyline the highest point is a
/// vertex, so `lambda* = (2 pi - y0) / max v`, and the run ends at the
/// point of the first chord that crosses the line.
#[test]
fn gross_slip_iff_the_polyline_reaches_two_pi() {
    for (name, vertices) in shapes() {
        let top = vertices.iter().map(|p| p.y()).fold(f64::MIN, f64::max);
        let critical = (2.0 * PI - Y0) / top;
        let (below, _) = run(&vertices, critical * (1.0 - 1e-3), true);
        assert_ne!(below.state(), SteadyState::GrossSlip, "{name}: {below:?}");
        let load_factor = critical * (1.0 + 1e-3);
        let (above, _) = run(&vertices, load_factor, true);
        let Verdict::GrossSlip(g) = above.verdict else {
            panic!("{name}: {above:?}");
        };
        assert!((g.load.y() - 2.0 * PI).abs() < 1e-9, "{name}: {:?}", g.load);
        // The first chord that crosses y = 2 pi, and where it crosses.
        let m = vertices.len();
        let y = |k: usize| Y0 + load_factor * vertices[k % m].y();
        let k = (0..m).find(|&k| y(k + 1) >= 2.0 * PI).unwrap();
        let r = (2.0 * PI - y(k)) / (y(k + 1) - y(k));
        let a = vertices[k];
        let b = vertices[(k + 1) % m];
        let x = PI + load_factor * (a.x() + r * (b.x() - a.x()));
        assert!(
            (g.load.x() - x).abs() < 1e-9,
            "{name}: {} against {x}",
            g.load.x()
        );
        let t = 2.0 * PI * (k as f64 + r) / m as f64;
        assert!((g.time.unwrap() - t).abs() < 1e-9, "{name}: time");
    }
}

/// From `O` through `A`, a cycle that stays in the stick diamond
/// `|x| + |y| <= 2 pi` never slips (model.md section 2.3): the diamond is
/// convex, so its vertices decide. Just outside, the first cycle slips.
#[test]
fn no_slip_iff_the_polyline_stays_in_the_stick_diamond() {
    for (name, vertices) in shapes().into_iter().skip(1) {
        // Shifted to start at A, so that the entry A -> C is empty.
        let first = vertices[0];
        let vertices: Vec<LoadPoint> = vertices
            .iter()
            .map(|p| LoadPoint::new(p.x() - first.x(), p.y() - first.y()))
            .collect();
        // The largest lambda with every vertex in the diamond, by bisection
        // on the closed form.
        let inside = |l: f64| {
            vertices
                .iter()
                .all(|p| (PI + l * p.x()).abs() + (Y0 + l * p.y()).abs() <= 2.0 * PI)
        };
        let (mut lo, mut hi) = (0.0, 10.0);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if inside(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (below, history) = run(&vertices, lo * (1.0 - 1e-3), false);
        assert_eq!(
            below.verdict,
            Verdict::Shakedown(ShakedownProof::NoSlipCycle),
            "{name}"
        );
        assert_eq!((below.cycles, below.dissipation), (1, 0.0), "{name}");
        assert!(history.iter().all(|&w| w == 0.0), "{name}");
        let (_, history) = run(&vertices, lo * (1.0 + 1e-2), false);
        assert!(history[0] > 0.0, "{name}: {history:?}");
    }
}

#[test]
fn the_cli_records_the_cycle_and_refuses_what_it_cannot_use() {
    let dir = scratch("polyline-cli");
    let square = dir.join("square.csv");
    let text = "# a square round A\nu,v\n1,-1\n1,1\n-1,1\n-1,-1\n";
    std::fs::write(&square, text).unwrap();
    let f = square.to_str().unwrap();
    let out = dir.join("w.csv");
    let o = shakedown(&[
        "sweep",
        "--cycle",
        f,
        "--lambda",
        "2,3",
        "--nodes",
        "32",
        "--steps",
        "40",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let written = std::fs::read_to_string(&out).unwrap();
    let id = shakedown::io::hash::content_id(text.as_bytes());
    assert!(
        written.contains(&format!("# load-cycle = cycle:square.csv@sha256:{id}\n")),
        "{written}"
    );
    assert!(written.contains("# phi = none\n"), "{written}");
    // Refused, each on one line naming the flag: a phase, a slope, steps
    // that do not split the chords equally, too few vertices, a FIFO.
    let two = dir.join("two.csv");
    std::fs::write(&two, "u,v\n0,0\n1,1\n").unwrap();
    let fifo = dir.join("fifo.csv");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    let mut refused = vec![
        (vec!["run", "--cycle", f, "--phi", "0.5pi"], "--phi"),
        (vec!["run", "--cycle", f, "--psi", "1"], "--psi"),
        (vec!["run", "--cycle", f, "--steps", "42"], "--steps 42"),
        (vec!["sweep", "--cycle", f, "--phi", "0,1"], "--phi"),
        (vec!["limit", "--cycle", f, "--phi", "0.5pi"], "--phi"),
        (vec!["run", "--cycle", two.to_str().unwrap()], "--cycle"),
        (vec!["run", "--cycle", "no-such-cycle.csv"], "--cycle"),
    ];
    if made.is_ok_and(|s| s.success()) {
        refused.push((vec!["run", "--cycle", fifo.to_str().unwrap()], "--cycle"));
    }
    for (args, flag) in refused {
        let o = shakedown(&args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(
            e.starts_with("error: ") && e.contains(flag),
            "{args:?}: {e}"
        );
        assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_cycle_written_and_read_back_is_the_same_cycle() {
    let vertices = ellipse(0.3 * PI, 400);
    let text = cycle_csv(&vertices);
    assert_eq!(
        shakedown::io::cycle::parse_cycle_csv(&text).unwrap(),
        vertices
    );
}

/// The `biharmonic` preset shows what a second harmonic in the torque
/// does: with the in-phase cycle's amplitudes, its lambda_2 is lower, and
/// at its lambda the in-phase cycle shakes down or slips cyclically while
/// this one ratchets.
#[test]
fn the_biharmonic_preset_lowers_lambda_2_below_the_in_phase_cycle() {
    let p = shakedown::io::preset::load("biharmonic").unwrap();
    let polyline = p.params.cycle.clone().expect("a polyline cycle");
    assert_eq!(polyline.vertices().len(), 200);
    // Torque twice a force cycle: v(t + pi) = v(t), u(t + pi) = -u(t).
    let v = polyline.vertices();
    for k in 0..100 {
        assert!((v[k].y() - v[k + 100].y()).abs() < 1e-11);
        assert!((v[k].x() + v[k + 100].x()).abs() < 1e-11);
    }
    let case = Case::builder()
        .load_factor(p.params.load_factor)
        .cycle(polyline)
        .nodes(64)
        .steps(400)
        .build()
        .unwrap();
    let line = Case::builder().nodes(64).build().unwrap();
    let (two, one) = (case.limit().unwrap(), line.limit().unwrap());
    assert!(
        two.load_factor < 0.9 * one.load_factor,
        "{} against {}",
        two.load_factor,
        one.load_factor
    );
}
