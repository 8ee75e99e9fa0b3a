//! The fretting profile: per node, what the interface does over one steady
//! cycle (model.md section 4.1). A fatigue or wear assessment asks where on
//! the interface the slip amplitude and the shear are largest and where the
//! energy goes; `W` alone does not say.
//!
//! [`ProfileObserver`] watches a run through [`crate::stepping::drive`] and
//! keeps the profile of the last complete cycle. The run must be stepped
//! one sub-segment at a time (pausing at events, no straight runs:
//! [`profile_run`] sets both), so that over each step every node's slip
//! moves one way at a uniform rate and `p` is affine in it: the trapezoid
//! `(p_before + p_after) / 2 |dg|` is then the exact `integral p |dg|`, the
//! same sum the stepper makes for `W`.

use std::f64::consts::PI;

use serde::Serialize;

use crate::stepping::steady::SteadyState;
use crate::stepping::Outcome;
use crate::stepping::{drive, Control, Goal, Observer, Phase, StepError, StepReport, Stepper};

/// Per node `theta_j`, over one cycle: the fretting quantities of model.md
/// section 4.1, in the paper's scaling (tractions in units of `p0`, slip
/// in that of `g`, dissipation in that of `W~`, eq. 16).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Profile {
    /// The cycle these are from (1-based).
    pub cycle: usize,
    /// Node angles `theta_j = 2 pi j / N`.
    pub theta: Vec<f64>,
    /// Least and largest contact pressure `p` over the cycle.
    pub p_min: Vec<f64>,
    /// Largest contact pressure over the cycle.
    pub p_max: Vec<f64>,
    /// Least shear traction `q` over the cycle.
    pub q_min: Vec<f64>,
    /// Largest shear traction over the cycle.
    pub q_max: Vec<f64>,
    /// Half the range of the slip `g` over the cycle.
    pub slip_amplitude: Vec<f64>,
    /// `sum |dg|` over the cycle: the slip path length.
    pub slip_accumulated: Vec<f64>,
    /// The node's share of the cycle's `W`: `(f / 2) integral p |dg|` times
    /// the node's arc `2 pi / N`, so that the column sums to `W`.
    pub dissipation: Vec<f64>,
    /// The Ruiz parameter: `max |q| x slip_amplitude`.
    pub ruiz: Vec<f64>,
    /// The Archard measure of wear: `integral p |dg|` over the cycle.
    pub wear: Vec<f64>,
}

impl Profile {
    /// `sum_j dissipation_j`: the cycle's `W`.
    pub fn total_dissipation(&self) -> f64 {
        self.dissipation.iter().sum()
    }
}

/// What is gathered over the cycle in progress.
#[derive(Debug, Clone, Default)]
struct Gather {
    cycle: usize,
    p_min: Vec<f64>,
    p_max: Vec<f64>,
    q_min: Vec<f64>,
    q_max: Vec<f64>,
    g_min: Vec<f64>,
    g_max: Vec<f64>,
    slip: Vec<f64>,
    work: Vec<f64>,
}

impl Gather {
    /// A cycle starting with pressure `p`, shear `q` and slip `g`.
    fn start(cycle: usize, p: &[f64], q: &[f64], g: &[f64]) -> Self {
        let n = p.len();
        Self {
            cycle,
            p_min: p.to_vec(),
            p_max: p.to_vec(),
            q_min: q.to_vec(),
            q_max: q.to_vec(),
            g_min: g.to_vec(),
            g_max: g.to_vec(),
            slip: vec![0.0; n],
            work: vec![0.0; n],
        }
    }

    fn finish(self, friction: f64) -> Profile {
        let n = self.p_min.len();
        let dtheta = 2.0 * PI / n as f64;
        let slip_amplitude: Vec<f64> = self
            .g_min
            .iter()
            .zip(&self.g_max)
            .map(|(lo, hi)| 0.5 * (hi - lo))
            .collect();
        let ruiz = (0..n)
            .map(|j| self.q_min[j].abs().max(self.q_max[j].abs()) * slip_amplitude[j])
            .collect();
        Profile {
            cycle: self.cycle,
            theta: (0..n).map(|j| j as f64 * dtheta).collect(),
            dissipation: self
                .work
                .iter()
                .map(|w| 0.5 * friction * w * dtheta)
                .collect(),
            p_min: self.p_min,
            p_max: self.p_max,
            q_min: self.q_min,
            q_max: self.q_max,
            slip_amplitude,
            slip_accumulated: self.slip,
            ruiz,
            wear: self.work,
        }
    }
}

/// Watches a run and keeps the [`Profile`] of its last complete cycle.
#[derive(Debug, Clone)]
pub struct ProfileObserver {
    friction: f64,
    /// The stepper's phase before the step being observed.
    phase: Phase,
    /// Pressure and slip after the last step observed.
    pressure: Vec<f64>,
    slip: Vec<f64>,
    current: Option<Gather>,
    last: Option<Profile>,
}

impl ProfileObserver {
    /// An observer of `stepper` from where it is now.
    pub fn new(stepper: &Stepper) -> Self {
        let c = stepper.contact();
        let current = match stepper.phase() {
            Phase::Cycle {
                cycle,
                increment: 0,
            } if !stepper.is_inside_increment() => {
                Some(Gather::start(cycle, c.pressure(), c.shear(), c.slip()))
            }
            _ => None,
        };
        Self {
            friction: c.material().friction(),
            phase: stepper.phase(),
            pressure: c.pressure().to_vec(),
            slip: c.slip().to_vec(),
            current,
            last: None,
        }
    }

    /// The profile of the last complete cycle seen, if any.
    pub fn last(&self) -> Option<&Profile> {
        self.last.as_ref()
    }

    /// The profile of the last complete cycle seen, if any.
    pub fn into_last(self) -> Option<Profile> {
        self.last
    }
}

impl Observer for ProfileObserver {
    fn observe(&mut self, stepper: &Stepper, _: &StepReport) -> Control {
        let c = stepper.contact();
        let (p, q, g) = (c.pressure(), c.shear(), c.slip());
        if let (Phase::Cycle { .. }, Some(cur)) = (self.phase, self.current.as_mut()) {
            for j in 0..p.len() {
                let dg = (g[j] - self.slip[j]).abs();
                cur.slip[j] += dg;
                cur.work[j] += 0.5 * (self.pressure[j] + p[j]) * dg;
                cur.p_min[j] = cur.p_min[j].min(p[j]);
                cur.p_max[j] = cur.p_max[j].max(p[j]);
                cur.q_min[j] = cur.q_min[j].min(q[j]);
                cur.q_max[j] = cur.q_max[j].max(q[j]);
                cur.g_min[j] = cur.g_min[j].min(g[j]);
                cur.g_max[j] = cur.g_max[j].max(g[j]);
            }
        }
        let now = stepper.phase();
        let before = std::mem::replace(&mut self.phase, now);
        if let Phase::Cycle { cycle, .. } = now {
            let new_cycle = match before {
                Phase::Cycle { cycle: was, .. } => was != cycle,
                Phase::Transient { .. } => true,
            };
            if new_cycle {
                if let Some(done) = self.current.take() {
                    if matches!(before, Phase::Cycle { .. }) {
                        self.last = Some(done.finish(self.friction));
                    }
                }
                self.current = Some(Gather::start(cycle, p, q, g));
            }
        }
        self.pressure.clear();
        self.pressure.extend_from_slice(p);
        self.slip.clear();
        self.slip.extend_from_slice(g);
        Control::Continue
    }
}

/// Run `stepper` to its verdict and return its summary with the profile of
/// its last complete cycle (the verdict cycle; `None` when the run ended
/// before completing a cycle). The run is stepped a sub-segment at a time
/// (see the module notes); its path, events and `W` are those of
/// [`Stepper::run_to_steady`] up to round-off.
///
/// # Errors
///
/// A numerical failure of an increment.
pub fn profile_run(stepper: &mut Stepper) -> Result<(Outcome, Option<Profile>), StepError> {
    stepper.set_straight_runs(false);
    stepper.set_pause_at_events(true);
    stepper.set_zone_events(false);
    let mut observer = ProfileObserver::new(stepper);
    let summary = loop {
        if let Some(summary) = stepper.outcome() {
            break *summary;
        }
        drive(stepper, Goal::Steady, &mut observer)?;
    };
    stepper.set_pause_at_events(false);
    let mut profile = observer.into_last();
    // Shakedown is the statement that the steady cycle does not slip (a
    // proof, section 6.4, when the last cycle run still slipped a little).
    if summary.state() == SteadyState::Shakedown {
        if let Some(p) = profile.as_mut() {
            for col in [
                &mut p.slip_amplitude,
                &mut p.slip_accumulated,
                &mut p.dissipation,
                &mut p.ruiz,
                &mut p.wear,
            ] {
                col.iter_mut().for_each(|v| *v = 0.0);
            }
        }
    }
    Ok((summary, profile))
}

/// The profile of the cycle `stepper` is about to run: it must stand at
/// the start of a cycle (increment 0, not inside an increment), as a copy
/// of a live run's stepper kept there does. The copy is stepped through
/// that one cycle a sub-segment at a time (see the module notes); `None`
/// when it does not stand at a cycle's start, the run ends within the
/// cycle, or `cancel` is raised (checked after every step).
///
/// # Errors
///
/// A numerical failure of an increment.
pub fn profile_cycle(
    stepper: &mut Stepper,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<Option<Profile>, StepError> {
    use std::sync::atomic::Ordering;
    stepper.set_straight_runs(false);
    stepper.set_pause_at_events(true);
    stepper.set_zone_events(false);
    let mut observer = ProfileObserver::new(stepper);
    if observer.current.is_none() {
        return Ok(None);
    }
    let mut watch = |s: &Stepper, r: &StepReport| {
        if cancel.load(Ordering::Relaxed) {
            return Control::Stop;
        }
        observer.observe(s, r)
    };
    drive(stepper, Goal::CycleEnd, &mut watch)?;
    if cancel.load(Ordering::Relaxed) {
        return Ok(None);
    }
    Ok(observer.into_last())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Cycle, Discretisation, Initial, Material};
    use crate::stepping::StepOptions;

    fn run(
        load_factor: f64,
        phase: f64,
        initial: &str,
        nodes: usize,
        steps: usize,
    ) -> (Outcome, Profile, f64) {
        let disc = Discretisation::new(nodes, steps).unwrap();
        let initial = Initial::parse(initial).unwrap();
        let mut stepper = Stepper::new(
            Material::paper(),
            disc,
            &initial,
            Cycle::paper(load_factor, phase).unwrap(),
            StepOptions::default(),
        );
        let (summary, profile) = profile_run(&mut stepper).unwrap();
        let profile = profile.expect("a complete cycle");
        let w = stepper
            .history()
            .iter()
            .find(|r| r.cycle == profile.cycle)
            .expect("the profile's cycle is in the history")
            .dissipation;
        (summary, profile, w)
    }

    /// The dissipation column sums to the cycle's `W` (section 4), and the
    /// wear column is the same integral without the factor `f dtheta / 2`.
    #[test]
    fn dissipation_sums_to_w() {
        for (lambda, phase, initial) in [(5.5, 0.0, "7,-7"), (5.2, 0.5 * PI, "OA")] {
            let (summary, profile, w) = run(lambda, phase, initial, 32, 100);
            assert!(w > 0.0, "{summary:?}");
            let sum = profile.total_dissipation();
            assert!((sum - w).abs() <= 1e-9 * w, "{sum} against W = {w}");
            let wear: f64 = profile.wear.iter().sum();
            let scale = 0.5 * 0.1 * 2.0 * PI / 32.0;
            assert!((wear * scale - w).abs() <= 1e-9 * w);
            for j in 0..32 {
                assert!(profile.slip_accumulated[j] >= 2.0 * profile.slip_amplitude[j] - 1e-12);
                assert!(profile.p_min[j] <= profile.p_max[j]);
                assert!(
                    profile.q_max[j].abs().max(profile.q_min[j].abs())
                        <= 0.1 * profile.p_max[j] + 1e-9
                );
            }
        }
    }

    /// Doubling the nodes and the increments moves the profile little:
    /// the tractions' extremes at the common nodes, the largest slip
    /// amplitude and the total `W`.
    #[test]
    fn grid_doubling_moves_the_profile_little() {
        let (_, coarse, w1) = run(5.5, 0.0, "7,-7", 32, 100);
        let (_, fine, w2) = run(5.5, 0.0, "7,-7", 64, 200);
        assert!((w1 - w2).abs() <= 0.02 * w2, "W {w1} against {w2}");
        for j in 0..32 {
            for (a, b) in [
                (coarse.p_max[j], fine.p_max[2 * j]),
                (coarse.p_min[j], fine.p_min[2 * j]),
                (coarse.q_max[j], fine.q_max[2 * j]),
                (coarse.q_min[j], fine.q_min[2 * j]),
            ] {
                assert!((a - b).abs() <= 0.02, "node {j}: {a} against {b}");
            }
        }
        let peak = |p: &Profile| p.slip_amplitude.iter().copied().fold(0.0, f64::max);
        let (a, b) = (peak(&coarse), peak(&fine));
        assert!(b > 0.0 && (a - b).abs() <= 0.05 * b, "{a} against {b}");
    }

    /// A copy of a live run kept at the start of a cycle profiles that
    /// cycle: its column sums to the `W` the live run (straight runs and
    /// all) records for the same cycle. Mid-cycle there is nothing to
    /// profile, and a raised cancel gives nothing.
    #[test]
    fn a_copy_at_a_cycles_start_profiles_that_cycle() {
        let disc = Discretisation::new(32, 100).unwrap();
        let mut live = Stepper::new(
            Material::paper(),
            disc,
            &Initial::parse("7,-7").unwrap(),
            Cycle::paper(5.5, 0.0).unwrap(),
            StepOptions::default(),
        );
        let mut silent = crate::stepping::Silent;
        drive(&mut live, Goal::TransientEnd, &mut silent).unwrap();
        drive(&mut live, Goal::CycleEnd, &mut silent).unwrap();
        let copy = live.clone();
        drive(&mut live, Goal::CycleEnd, &mut silent).unwrap();
        let w = live.history().last().unwrap().dissipation;
        let never = std::sync::atomic::AtomicBool::new(false);
        let profile = profile_cycle(&mut copy.clone(), &never)
            .unwrap()
            .expect("a cycle's start");
        assert_eq!(profile.cycle, 2);
        assert!(w > 0.0);
        let sum = profile.total_dissipation();
        assert!((sum - w).abs() <= 1e-9 * w, "{sum} against W = {w}");
        let cancelled = std::sync::atomic::AtomicBool::new(true);
        assert_eq!(profile_cycle(&mut copy.clone(), &cancelled).unwrap(), None);
        drive(&mut live, Goal::Increments(3), &mut silent).unwrap();
        assert_eq!(profile_cycle(&mut live, &never).unwrap(), None);
    }

    /// Below the elastic limit nothing slips: every slip column is zero.
    #[test]
    fn shakedown_has_no_slip() {
        let (summary, profile, _) = run(1.0, 0.0, "OA", 32, 100);
        assert_eq!(summary.state(), SteadyState::Shakedown);
        for col in [
            &profile.slip_amplitude,
            &profile.slip_accumulated,
            &profile.dissipation,
            &profile.ruiz,
            &profile.wear,
        ] {
            assert!(col.iter().all(|v| *v == 0.0));
        }
    }
}
