//! What a run will cost: the interactive range, the measured CPU time of a
//! run by node count, and the one-line warning before a slow grid.

use super::*;

/// Largest `--nodes` and `--steps` of the interactive range: a run takes
/// well under a second up to here.
pub const INTERACTIVE_NODES: usize = 512;
/// See [`INTERACTIVE_NODES`].
pub const INTERACTIVE_STEPS: usize = 2000;

/// CPU seconds of one run to its verdict at 400 increments per cycle, by
/// node count, measured for a fast case (`--lambda 5.5 --phi 0`, cyclic
/// slip) and a slow one (`--lambda 6 --phi pi/2`, out of phase,
/// ratchetting): `(nodes, fast, slow)`. Between the two lie the cases
/// tried; the cost is the events of each cycle (about `N^2` while the
/// slip zones are a few arcs) times the cycles to a verdict, and out of
/// phase both grow faster with `N`.
const RUN_SECONDS: [(f64, f64, f64); 4] = [
    (512.0, 0.12, 0.08),
    (1024.0, 0.49, 0.72),
    (2048.0, 2.22, 22.7),
    (4096.0, 12.35, 182.6),
];

/// The expected CPU time of one run, `(fast, slow)` in seconds: the
/// measured times of [`RUN_SECONDS`] interpolated in `log N` (as `N^2.1`
/// below 512 nodes), plus the increments beyond 400 a cycle (about
/// `2.5e-10 N^2` s each: 0.36 s more at 1024 nodes and 1600 increments).
pub fn expected_run_seconds(nodes: usize, steps: usize) -> (f64, f64) {
    let n = nodes as f64;
    let at = |pick: fn(&(f64, f64, f64)) -> f64| {
        let first = &RUN_SECONDS[0];
        if n <= first.0 {
            return pick(first) * (n / first.0).powf(2.1);
        }
        for w in RUN_SECONDS.windows(2) {
            if n <= w[1].0 {
                let f = (n / w[0].0).ln() / (w[1].0 / w[0].0).ln();
                return pick(&w[0]) * (pick(&w[1]) / pick(&w[0])).powf(f);
            }
        }
        let last = &RUN_SECONDS[RUN_SECONDS.len() - 1];
        pick(last) * (n / last.0).powi(3)
    };
    let extra = 2.5e-10 * n * n * steps.saturating_sub(400) as f64;
    (at(|r| r.1) + extra, at(|r| r.2) + extra)
}

/// A time for a warning: `about 3 s`, `about 2 min`.
fn readable_time(t: f64) -> String {
    if t < 0.5 {
        "under a second".to_string()
    } else if t < 10.0 {
        format!("about {t:.1} s")
    } else if t < 60.0 {
        format!("about {t:.0} s")
    } else if t < 3600.0 {
        format!("about {:.0} min", t / 60.0)
    } else {
        format!("about {:.1} h", t / 3600.0)
    }
}

/// Which of the measured cases of [`RUN_SECONDS`] the runs ahead are like:
/// an in-phase cycle (a straight line, `phi = 0` or `pi`) costs like the
/// fast case, an elliptical one like the slow case; a sweep over both, or
/// a polyline cycle, gets the range between them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CostClass {
    /// Every cycle is a straight line.
    Line,
    /// Every cycle is an ellipse.
    Ellipse,
    /// Some of each, or a polyline.
    Mixed,
}

impl CostClass {
    /// The class of the cycles of `params` over the phases `phases`.
    pub fn of(params: &CaseParams, phases: &[f64]) -> Self {
        if params.cycle.is_some() {
            return Self::Mixed;
        }
        let line = |phi: f64| shakedown::analysis::limit::is_line(params.slope, phi);
        match (
            phases.iter().all(|&p| line(p)),
            phases.iter().any(|&p| line(p)),
        ) {
            (true, _) => Self::Line,
            (false, false) => Self::Ellipse,
            _ => Self::Mixed,
        }
    }
}

/// Warn on stderr (one line) when `--nodes` or `--steps` is above the
/// interactive range, with the expected time per run
/// ([`expected_run_seconds`]): that of the measured case the runs are
/// like ([`CostClass`]), or the range from the fast case to the slow one.
pub fn warn_if_slow(nodes: usize, steps: usize, class: CostClass) {
    if nodes <= INTERACTIVE_NODES && steps <= INTERACTIVE_STEPS {
        return;
    }
    let (fast, slow) = expected_run_seconds(nodes, steps);
    let (lo, hi) = match class {
        CostClass::Line => (fast, fast),
        CostClass::Ellipse => (slow, slow),
        CostClass::Mixed => (fast.min(slow), fast.max(slow)),
    };
    let time = if hi < 2.0 * lo || hi < 0.5 {
        format!("{} of CPU per run", readable_time(hi))
    } else {
        format!(
            "{} to {} of CPU per run (out of phase, ratchetting runs take longest)",
            readable_time(lo),
            readable_time(hi).trim_start_matches("about ")
        )
    };
    errln!(
        "warning: --nodes {nodes} --steps {steps} is above the interactive range (nodes <= {INTERACTIVE_NODES}, steps <= {INTERACTIVE_STEPS}): expect {time}"
    );
}
