//! Property tests of the incremental solver on random load paths
//! (model.md sections 2, 3 and 6).
//!
//! Random polylines in the load plane, cut into increments of random size,
//! are solved increment by increment through the public API
//! (`Contact::solve` and `commit`, and the `Stepper` with custom waypoints).
//! Paths that stay inside `|y| < 6` (gross slip needs `|y| > 2 pi`) and
//! `|x| < 0.9 x_sep` (`x_sep`: separation without slip,
//! `beta |Pt| / (2 pi) = 1`) must satisfy the friction law after every
//! increment; paths that leave that region must end in the typed outcome.

use std::f64::consts::PI;
use std::sync::Arc;

use proptest::prelude::*;
use shakedown::contact::{Solved, Trial};
use shakedown::{
    Contact, ContactEnd, ContactError, Cycle, Discretisation, LoadPoint, Material, Operators,
    Plane, SteadyState, StepOptions, Stepper,
};

/// Relative tolerance of the friction law, as the issue states it.
const REL: f64 = 1e-9;
/// Absolute floor, in units of `p0`: the solver's own tolerance on the
/// friction inequality (`TRACTION_TOL`). Tractions are sums of terms of
/// order 1, so near separation (`p -> 0`) a purely relative bound would
/// test round-off: a case with `p = 1e-6` exceeded `f p` by `1e-15`.
const ABS: f64 = 1e-12;

/// `|x|` at which the unslipped disc separates: `beta |Pt| / (2 pi) = 1`.
fn x_separation(m: &Material) -> f64 {
    2.0 * PI * m.chi() / (m.friction() * m.beta())
}

fn material() -> impl Strategy<Value = Material> {
    prop_oneof![
        3 => Just(Material::paper()),
        2 => (0.05f64..0.6, 0.0f64..0.49, prop::bool::ANY).prop_map(|(f, nu, stress)| {
            let plane = if stress { Plane::Stress } else { Plane::Strain };
            Material::new(f, nu, plane).expect("in range")
        }),
    ]
}

fn nodes() -> impl Strategy<Value = usize> {
    prop_oneof![Just(32usize), Just(64usize)]
}

/// Waypoints as fractions of the safe box `|x| < 0.9 x_sep`, `|y| < 6`.
fn inside_path() -> impl Strategy<Value = Vec<(f64, f64)>> {
    prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0), 1..6)
}

fn scale_inside(m: &Material, path: &[(f64, f64)]) -> Vec<LoadPoint> {
    let xs = 0.9 * x_separation(m);
    path.iter()
        .map(|&(a, b)| LoadPoint::new(a * xs, b * 6.0))
        .collect()
}

/// The load points of the increments along the polyline from the origin,
/// each at most `step` long.
fn increments(points: &[LoadPoint], step: f64) -> Vec<LoadPoint> {
    let mut out = Vec::new();
    let mut from = LoadPoint::ORIGIN;
    for &to in points {
        let n = (from.distance(to) / step).ceil().max(1.0) as usize;
        out.extend((1..=n).map(|i| from.lerp(to, i as f64 / n as f64)));
        from = to;
    }
    out
}

/// Every property of one solved increment, before it is committed.
fn check_trial(c: &Contact, trial: &Trial) -> Result<(), TestCaseError> {
    let m = c.material();
    let f = m.friction();
    let n = c.nodes();
    let (p, q, dg) = (&trial.pressure, &trial.shear, &trial.slip_increment);
    for j in 0..n {
        prop_assert!(p[j] > 0.0, "p = {} at node {j}", p[j]);
        prop_assert!(
            q[j].abs() <= f * p[j] * (1.0 + REL) + ABS,
            "friction law at node {j}: |q| = {:e} > f p = {:e}",
            q[j].abs(),
            f * p[j]
        );
        let dir = trial.directions[j];
        prop_assert_eq!(
            dir.is_slipping(),
            dg[j] != 0.0,
            "direction and slip disagree at node {}",
            j
        );
        if dg[j] != 0.0 {
            // Slip only at the limit, the way q pushes, so q dg >= 0.
            prop_assert!(
                (q[j].abs() - f * p[j]).abs() <= REL * f * p[j] + ABS,
                "slip below the limit at node {j}: |q| = {:e}, f p = {:e}, dg = {:e}",
                q[j].abs(),
                f * p[j],
                dg[j]
            );
            prop_assert!(q[j] * dg[j] > 0.0, "slip against q at node {j}");
            prop_assert_eq!(dir.sign(), dg[j].signum());
        }
    }
    prop_assert!(
        trial.dissipation >= 0.0,
        "dissipation {}",
        trial.dissipation
    );
    prop_assert!(trial.dissipation.is_finite());
    // The residual tractions carry no moment: mean q = -Tt / (2 pi).
    let torque = m.to_loads(trial.load).torque;
    let mean_q = q.iter().sum::<f64>() / n as f64;
    prop_assert!(
        (mean_q + torque / (2.0 * PI)).abs() <= 1e-10 * (1.0 + torque.abs()),
        "torque balance: mean q = {mean_q:e}, -Tt/2pi = {:e}",
        -torque / (2.0 * PI)
    );
    // Nor any force: mean p = 1 (p0).
    let mean_p = p.iter().sum::<f64>() / n as f64;
    prop_assert!((mean_p - 1.0).abs() <= 1e-10, "mean p = {mean_p}");
    Ok(())
}

/// Why a walk stopped: a physical end, or a numerical failure.
#[derive(Debug)]
enum Stop {
    End(ContactEnd),
    Failed(ContactError),
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stop::End(end) => write!(f, "{end}"),
            Stop::Failed(e) => write!(f, "{e}"),
        }
    }
}

/// Solve one increment, bisecting (up to 12 times, as the stepper does)
/// where the active set does not settle. Committed increments are checked.
fn advance(
    c: &mut Contact,
    to: LoadPoint,
    depth: usize,
    solved: &mut usize,
) -> Result<Result<(), Stop>, TestCaseError> {
    match c.solve(to) {
        Ok(Solved::Ended(end)) => Ok(Err(Stop::End(end))),
        Ok(Solved::Trial(trial)) => {
            check_trial(c, &trial)?;
            let before = c.slip().to_vec();
            let dg = trial.slip_increment.clone();
            let (p, q) = (trial.pressure.clone(), trial.shear.clone());
            c.commit(trial);
            *solved += 1;
            // Committing moves the state exactly there, and the stored
            // residual tractions agree with the new slip.
            let (p2, q2) = c.tractions_at(to);
            for j in 0..c.nodes() {
                prop_assert_eq!(c.slip()[j], before[j] + dg[j]);
                prop_assert_eq!(c.pressure()[j], p[j]);
                prop_assert_eq!(c.shear()[j], q[j]);
                prop_assert!((p2[j] - p[j]).abs() < 1e-9 && (q2[j] - q[j]).abs() < 1e-9);
            }
            Ok(Ok(()))
        }
        Err(ContactError::NotSettled { .. }) if depth < 12 => {
            let mid = c.load().lerp(to, 0.5);
            match advance(c, mid, depth + 1, solved)? {
                Ok(()) => advance(c, to, depth + 1, solved),
                e => Ok(e),
            }
        }
        Err(e) => Ok(Err(Stop::Failed(e))),
    }
}

fn walk(
    m: Material,
    n: usize,
    points: &[LoadPoint],
    step: f64,
) -> Result<(Contact, Result<(), Stop>, usize), TestCaseError> {
    let mut c = Contact::new(m, Arc::new(Operators::new(n)));
    let mut solved = 0;
    for to in increments(points, step) {
        if let Err(e) = advance(&mut c, to, 0, &mut solved)? {
            return Ok((c, Err(e), solved));
        }
    }
    Ok((c, Ok(()), solved))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Inside the safe box every increment solves and obeys the friction
    /// law, slips only at the limit in the direction of q, dissipates
    /// non-negatively and balances the torque.
    #[test]
    fn friction_law_holds_after_every_increment(
        m in material(),
        n in nodes(),
        path in inside_path(),
        step in 0.05f64..1.0,
    ) {
        let points = scale_inside(&m, &path);
        let (c, end, solved) = walk(m, n, &points, step)?;
        match end {
            Ok(()) => prop_assert!(c.load().distance(*points.last().unwrap()) < 1e-12),
            // Locked-in slip shifts the pressure: separation may come
            // before x_sep, but only as the typed outcome, with p < 0.
            Err(Stop::End(ContactEnd::Separation { pressure, load, .. })) => {
                prop_assert!(pressure < 0.0);
                prop_assert!(load.x().abs() > 0.5 * x_separation(&m), "separation at {load}");
            }
            Err(e) => prop_assert!(false, "{e} after {solved} increments inside the box"),
        }
    }

    /// Paths that end beyond |y| = 2 pi cannot get there: the friction
    /// torque is at most 2 pi f p0 a^2. They end in gross slip (or
    /// separation), as a typed outcome, before the torque limit is passed.
    #[test]
    fn beyond_the_torque_limit_is_gross_slip(
        m in material(),
        n in nodes(),
        path in inside_path(),
        end_x in -0.5f64..0.5,
        end_y in (2.0 * PI + 0.2)..12.0,
        sign in prop::bool::ANY,
        step in 0.1f64..1.0,
    ) {
        let mut points = scale_inside(&m, &path);
        let y = if sign { end_y } else { -end_y };
        points.push(LoadPoint::new(end_x * x_separation(&m), y));
        let (c, end, _) = walk(m, n, &points, step)?;
        match end {
            Err(Stop::End(ContactEnd::GrossSlip { load })) => {
                prop_assert!(load.y().abs() > 2.0 * PI * (1.0 - 1e-9), "gross slip at {load}");
                // The state before it still obeyed the torque limit.
                prop_assert!(c.load().y().abs() <= 2.0 * PI * (1.0 + 1e-9));
            }
            Err(Stop::End(ContactEnd::Separation { pressure, .. })) => prop_assert!(pressure < 0.0),
            other => prop_assert!(false, "reached {} with {other:?}", c.load()),
        }
    }

    /// Far beyond x_sep the disc separates: a typed outcome with p < 0.
    #[test]
    fn far_radial_load_separates(
        m in material(),
        n in nodes(),
        path in inside_path(),
        end_x in 1.05f64..3.0,
        end_y in -0.5f64..0.5,
        sign in prop::bool::ANY,
    ) {
        let mut points = scale_inside(&m, &path);
        let xs = x_separation(&m);
        let x = if sign { end_x * xs } else { -end_x * xs };
        points.push(LoadPoint::new(x, end_y * 6.0));
        let (c, end, _) = walk(m, n, &points, 0.3)?;
        match end {
            Err(Stop::End(ContactEnd::Separation { pressure, node, theta, .. })) => {
                prop_assert!(pressure < 0.0);
                prop_assert!(node < n);
                prop_assert!((theta - 2.0 * PI * node as f64 / n as f64).abs() < 1e-12);
            }
            Err(Stop::End(ContactEnd::GrossSlip { load })) => {
                prop_assert!(load.y().abs() > 2.0 * PI * (1.0 - 1e-9), "gross slip at {load}")
            }
            other => prop_assert!(false, "reached {} with {other:?}", c.load()),
        }
    }

    /// The stepper on a custom transient: after every step the friction
    /// law and the balance hold and the step's dissipation is
    /// non-negative; a transient into gross slip ends the run with the
    /// typed outcome and its load point, never a panic or an error.
    #[test]
    fn stepper_on_random_transients(
        m in material(),
        n in nodes(),
        path in inside_path(),
        escape in prop::option::of((-0.5f64..0.5, (2.0 * PI + 0.2)..10.0)),
    ) {
        let mut points = scale_inside(&m, &path);
        if let Some((x, y)) = escape {
            points.push(LoadPoint::new(x * x_separation(&m), y));
        }
        let last = *points.last().unwrap();
        // A small cycle round the last point, entered from it.
        let cycle = Cycle::new(last, 0.0, 0.625, 0.0).unwrap();
        let disc = Discretisation::new(n, 100).unwrap();
        let contact = Contact::new(m, Arc::new(Operators::new(n)));
        let mut s = Stepper::from_contact(contact, &points, cycle, disc, StepOptions::default());
        let f = m.friction();
        let mut steps = 0;
        while !s.is_finished() && s.history().is_empty() {
            let report = s.step();
            prop_assert!(report.is_ok(), "{:?}", report);
            let report = report.unwrap();
            steps += 1;
            prop_assert!(steps < 100_000, "the transient does not end");
            prop_assert!(report.dissipation >= 0.0);
            if s.is_finished() {
                break;
            }
            let c = s.contact();
            for j in 0..n {
                prop_assert!(c.shear()[j].abs() <= f * c.pressure()[j] * (1.0 + REL) + ABS);
            }
            let torque = m.to_loads(c.load()).torque;
            let mean_q = c.shear().iter().sum::<f64>() / n as f64;
            prop_assert!((mean_q + torque / (2.0 * PI)).abs() <= 1e-10 * (1.0 + torque.abs()));
        }
        let summary = s.outcome().cloned();
        match escape {
            Some(_) => {
                let summary = summary.expect("an escape ends the run");
                prop_assert!(
                    matches!(summary.state(), SteadyState::GrossSlip | SteadyState::Separation),
                    "{:?}", summary
                );
                prop_assert!(summary.terminal_load().is_some());
                if summary.state() == SteadyState::GrossSlip {
                    let y = summary.terminal_load().unwrap().y().abs();
                    prop_assert!(y > 2.0 * PI * (1.0 - 1e-9), "gross slip at |y| = {y}");
                }
            }
            None => {
                if s.is_finished() {
                    // Only the separation a locked-in slip can bring forward.
                    let summary = summary.expect("finished");
                    prop_assert_eq!(summary.state(), SteadyState::Separation, "{:?}", summary);
                } else {
                    // The transient ended where it was meant to.
                    prop_assert!(!s.history().is_empty() || s.outcome().is_some());
                    prop_assert!(s.contact().load().distance(last) < 1e-9);
                }
            }
        }
    }
}

/// The library sets no process-wide state: no source file calls faer's
/// global-parallelism setter (every faer call of the engine passes its own,
/// sequential, parallelism, and faer is built without its rayon feature).
#[test]
fn the_library_sets_no_global_parallelism() {
    fn walk(dir: &std::path::Path, hits: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, hits);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                if text.contains(concat!("set_global", "_parallelism")) {
                    hits.push(path.display().to_string());
                }
            }
        }
    }
    let mut hits = Vec::new();
    walk(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut hits,
    );
    assert!(hits.is_empty(), "process-wide faer state set in {hits:?}");
}
