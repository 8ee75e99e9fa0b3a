//! Slip episodes: what advancing stick locks in.
//!
//! A node's *slip episode* runs from the instant it starts to slip to the
//! instant it sticks again. At that instant (advancing stick, model.md
//! section 3.3) the slip `g` the node gathered during the episode is locked
//! in: it stays in the residual state until the node slips again. The
//! [`EpisodeTracker`] watches a run increment by increment (it is an
//! [`Observer`] of [`drive`](crate::stepping::drive), or is fed each
//! [`StepReport`] by hand) and remembers, for every node, `g` when its
//! current episode began. At an [`Event::AdvancingStick`] it gives, for the
//! nodes that just stuck, the slip of the episode that ends there
//! ([`EpisodeTracker::locked_slip`]) and, for comparison, `g` at the start
//! of the cycle.
//!
//! A stuck node's `g` does not move, so "`g` when the episode began" is the
//! node's `g` at the last observation where it was stuck. The values are
//! exact when every event is observed at its own instant (the stepper
//! pauses at events, [`Stepper::set_pause_at_events`]). Without pausing, a
//! node that sticks and slips again within one increment is seen only at the
//! increment's end, and its episode slip includes the slip after it slipped
//! again (at most that one increment's slip).

use std::f64::consts::PI;
use std::fmt;

use crate::contact::SlipDirection;
use crate::stepping::{Control, Event, Observer, StepReport, Stepper};

/// What the nodes of one advancing-stick event locked in.
#[derive(Debug, Clone, PartialEq)]
pub struct LockedSlip {
    /// The nodes that stuck, in increasing order.
    pub nodes: Vec<usize>,
    /// For each of `nodes`, the slip it gathered in the episode that ends
    /// here: `g` now minus `g` when the episode began (positive forward).
    pub per_node: Vec<f64>,
    /// For each of `nodes`, `g` now (the value locked in).
    pub g_now: Vec<f64>,
    /// For each of `nodes`, `g` at the start of the cycle (of the run, in
    /// the initial transient).
    pub g_cycle_start: Vec<f64>,
    /// The episode slip of largest magnitude, with its sign (0 with no
    /// nodes).
    pub max: f64,
    /// The mean episode slip, signed (0 with no nodes).
    pub mean: f64,
}

impl LockedSlip {
    fn new(
        nodes: Vec<usize>,
        per_node: Vec<f64>,
        g_now: Vec<f64>,
        g_cycle_start: Vec<f64>,
    ) -> Self {
        let max = per_node
            .iter()
            .copied()
            .fold(0.0_f64, |m, v| if v.abs() > m.abs() { v } else { m });
        let mean = if per_node.is_empty() {
            0.0
        } else {
            per_node.iter().sum::<f64>() / per_node.len() as f64
        };
        Self {
            nodes,
            per_node,
            g_now,
            g_cycle_start,
            max,
            mean,
        }
    }
}

/// Remembers, node by node, `g` when the current slip episode began (module
/// docs).
#[derive(Debug, Clone)]
pub struct EpisodeTracker {
    /// `g` of each node when its current (or next) slip episode began.
    episode_start: Vec<f64>,
    /// `g` at the start of the current cycle (of the run in the transient).
    cycle_start: Vec<f64>,
    /// `g` at the last observation.
    g: Vec<f64>,
    /// Slip directions at the last observation.
    directions: Vec<SlipDirection>,
    /// Episode slip of the nodes that stuck in the last observed step
    /// (valid for the nodes of that step's advancing-stick events).
    locked: Vec<f64>,
    /// `g` at the start of the episode that ended in the last observed
    /// step, for the same nodes.
    locked_from: Vec<f64>,
}

impl EpisodeTracker {
    /// A tracker for the run of `stepper`, starting from where it is now.
    /// Nodes slipping now are taken to have begun their episode now.
    pub fn new(stepper: &Stepper) -> Self {
        let contact = stepper.contact();
        Self::from_state(contact.slip(), contact.directions())
    }

    /// A tracker starting from slip `g` and directions `directions` (one per
    /// node).
    pub fn from_state(g: &[f64], directions: &[SlipDirection]) -> Self {
        Self {
            episode_start: g.to_vec(),
            cycle_start: g.to_vec(),
            g: g.to_vec(),
            directions: directions.to_vec(),
            locked: vec![0.0; g.len()],
            locked_from: g.to_vec(),
        }
    }

    /// Number of nodes tracked.
    pub fn nodes(&self) -> usize {
        self.g.len()
    }

    /// Take in one step: `g` and the directions after it, and what it
    /// reported. Call once per step, in order.
    pub fn update(&mut self, g: &[f64], directions: &[SlipDirection], report: &StepReport) {
        debug_assert_eq!(g.len(), self.g.len());
        for &j in &report.newly_stuck {
            if j < g.len() {
                self.locked[j] = g[j] - self.episode_start[j];
                self.locked_from[j] = self.episode_start[j];
                // Its next episode starts from what it locked in (even if
                // it slipped again before the step's end, see module docs).
                self.episode_start[j] = g[j];
            }
        }
        for (j, dir) in directions.iter().enumerate() {
            // A node stuck now holds its g until it next slips: the start
            // of its next episode. One stuck last time and slipping now
            // began its episode from the g it held while stuck, which is
            // `episode_start` already.
            if !dir.is_slipping() {
                self.episode_start[j] = g[j];
            }
        }
        self.g.copy_from_slice(g);
        self.directions.copy_from_slice(directions);
        let cycle_started = report
            .events
            .iter()
            .any(|e| matches!(e, Event::TransientFinished | Event::CycleCompleted { .. }));
        if cycle_started {
            self.cycle_start.copy_from_slice(g);
        }
    }

    /// What the nodes of `event` locked in, if it is an advancing-stick
    /// event of the step observed last.
    pub fn locked_slip(&self, event: &Event) -> Option<LockedSlip> {
        let Event::AdvancingStick { nodes, .. } = event else {
            return None;
        };
        let mut nodes: Vec<usize> = nodes
            .iter()
            .copied()
            .filter(|&j| j < self.nodes())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        let per_node = nodes.iter().map(|&j| self.locked[j]).collect();
        let g_now = nodes
            .iter()
            .map(|&j| self.locked_from[j] + self.locked[j])
            .collect();
        let g_cycle_start = nodes.iter().map(|&j| self.cycle_start[j]).collect();
        Some(LockedSlip::new(nodes, per_node, g_now, g_cycle_start))
    }

    /// `g` of every node at the start of the current cycle (of the run in
    /// the initial transient).
    pub fn cycle_start(&self) -> &[f64] {
        &self.cycle_start
    }

    /// `g` of every node when its current slip episode began (for a stuck
    /// node, its `g` now).
    pub fn episode_start(&self) -> &[f64] {
        &self.episode_start
    }

    /// The slip of every node in its current episode so far (0 on stuck
    /// nodes).
    pub fn episode_slip(&self) -> Vec<f64> {
        self.g
            .iter()
            .zip(&self.episode_start)
            .map(|(g, s)| g - s)
            .collect()
    }
}

impl Observer for EpisodeTracker {
    fn observe(&mut self, stepper: &Stepper, report: &StepReport) -> Control {
        let contact = stepper.contact();
        self.update(contact.slip(), contact.directions(), report);
        Control::Continue
    }
}

/// A range of node angles `theta` round the circle, from `from` to `to`
/// counter-clockwise, in `[-pi, pi)`. It `wraps` when it runs through
/// `theta = pi` (then `from > to`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThetaRange {
    /// First angle, counter-clockwise.
    pub from: f64,
    /// Last angle, counter-clockwise.
    pub to: f64,
}

impl ThetaRange {
    /// The shortest arc holding the nodes `nodes` of `n` equally spaced
    /// nodes (`theta_j = 2 pi j / n`, shown in `[-pi, pi)`): its ends are
    /// the nodes either side of the largest gap between them. `None` with
    /// no nodes.
    pub fn of_nodes(nodes: &[usize], n: usize) -> Option<Self> {
        let mut sorted: Vec<usize> = nodes.iter().copied().filter(|&j| j < n).collect();
        sorted.sort_unstable();
        sorted.dedup();
        let (&first, &last) = (sorted.first()?, sorted.last()?);
        // The gap after each node to the next, round the circle; the arc
        // starts just after the largest.
        let mut best_gap = first + n - last;
        let (mut from, mut to) = (first, last);
        for w in sorted.windows(2) {
            let gap = w[1] - w[0];
            if gap > best_gap {
                best_gap = gap;
                from = w[1];
                to = w[0];
            }
        }
        Some(Self {
            from: shown_theta(from, n),
            to: shown_theta(to, n),
        })
    }

    /// Whether the range runs through `theta = pi`.
    pub fn wraps(&self) -> bool {
        self.from > self.to
    }
}

/// `theta_j` of node `j` of `n`, in `[-pi, pi)`.
fn shown_theta(j: usize, n: usize) -> f64 {
    let t = 2.0 * PI * j as f64 / n as f64;
    if t >= PI {
        t - 2.0 * PI
    } else {
        t
    }
}

/// `theta / pi` to two decimals: `0.85..-0.90 (wraps)`, `-0.10..0.20`, or
/// one value when both ends agree.
impl fmt::Display for ThetaRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (a, b) = (self.from / PI, self.to / PI);
        if format!("{a:.2}") == format!("{b:.2}") {
            write!(f, "{a:.2}")
        } else if self.wraps() {
            write!(f, "{a:.2}..{b:.2} (wraps)")
        } else {
            write!(f, "{a:.2}..{b:.2}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stepping::{drive, Goal};
    use crate::{Cycle, Discretisation, Initial, Material, StepOptions};
    use SlipDirection::{Backward, Forward, Stick};

    fn stuck(nodes: Vec<usize>) -> StepReport {
        StepReport {
            newly_stuck: nodes.clone(),
            events: vec![Event::AdvancingStick {
                nodes,
                substeps: 1,
                time: None,
                load: crate::LoadPoint::new(0.0, 0.0),
            }],
            ..StepReport::default()
        }
    }

    #[test]
    fn the_episode_slip_is_g_now_minus_g_when_slip_began() {
        // Node 0 stuck at g = 1 until it slips, gathers 0.5, sticks.
        // Node 1 slips throughout from g = -2 and sticks at the same event.
        // Node 2 never slips.
        let mut t = EpisodeTracker::from_state(&[1.0, -2.0, 3.0], &[Stick, Backward, Stick]);
        t.update(
            &[1.0, -2.25, 3.0],
            &[Stick, Backward, Stick],
            &StepReport::default(),
        );
        t.update(
            &[1.2, -2.5, 3.0],
            &[Forward, Backward, Stick],
            &StepReport::default(),
        );
        let report = stuck(vec![1, 0]);
        t.update(&[1.5, -2.75, 3.0], &[Stick, Stick, Stick], &report);
        let locked = t.locked_slip(&report.events[0]).unwrap();
        assert_eq!(locked.nodes, vec![0, 1]);
        assert_eq!(locked.per_node, vec![0.5, -0.75]);
        assert_eq!(locked.g_now, vec![1.5, -2.75]);
        // No cycle began: the comparison is the run's start.
        assert_eq!(locked.g_cycle_start, vec![1.0, -2.0]);
        assert_eq!(locked.max, -0.75);
        assert_eq!(locked.mean, -0.125);
        // The next episode of node 0 begins where this one locked in.
        t.update(
            &[1.75, -2.75, 3.0],
            &[Forward, Stick, Stick],
            &StepReport::default(),
        );
        let report = stuck(vec![0]);
        t.update(&[2.0, -2.75, 3.0], &[Stick, Stick, Stick], &report);
        let locked = t.locked_slip(&report.events[0]).unwrap();
        assert_eq!(locked.per_node, vec![0.5]);
    }

    #[test]
    fn a_new_cycle_resets_the_comparison() {
        let mut t = EpisodeTracker::from_state(&[0.0], &[Forward]);
        let report = StepReport {
            events: vec![Event::TransientFinished],
            ..StepReport::default()
        };
        t.update(&[0.5], &[Forward], &report);
        assert_eq!(t.cycle_start(), &[0.5]);
        let report = stuck(vec![0]);
        t.update(&[0.75], &[Stick], &report);
        let locked = t.locked_slip(&report.events[0]).unwrap();
        assert_eq!(locked.per_node, vec![0.75]);
        assert_eq!(locked.g_cycle_start, vec![0.5]);
        assert!(t.locked_slip(&Event::TransientFinished).is_none());
    }

    #[test]
    fn on_a_run_each_episode_slip_sums_to_the_change_of_g() {
        // Pausing at events, every episode is seen at its own instants: the
        // episode slips locked in by a node over the run, plus the slip of
        // the episode in progress, add up to its change of g.
        let disc = Discretisation::new(32, 100).unwrap();
        let cycle = Cycle::paper(4.75, 0.0).unwrap();
        let mut stepper = Stepper::new(
            Material::paper(),
            disc,
            &Initial::Direct,
            cycle,
            StepOptions::default(),
        );
        stepper.set_pause_at_events(true);
        let g0 = stepper.contact().slip().to_vec();
        let mut tracker = EpisodeTracker::new(&stepper);
        let mut total = vec![0.0; 32];
        let mut events = 0;
        drive(
            &mut stepper,
            Goal::Increments(300),
            &mut |s: &Stepper, r: &StepReport| {
                tracker.observe(s, r);
                for e in &r.events {
                    if let Some(l) = tracker.locked_slip(e) {
                        events += 1;
                        for (j, v) in l.nodes.iter().zip(&l.per_node) {
                            total[*j] += v;
                        }
                    }
                }
                Control::Continue
            },
        )
        .unwrap();
        assert!(events > 0, "the case has advancing stick");
        let g = stepper.contact().slip();
        for j in 0..32 {
            let expected = g[j] - g0[j];
            let got = total[j] + tracker.episode_slip()[j];
            assert!(
                (got - expected).abs() <= 1e-12 * (1.0 + expected.abs()),
                "node {j}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn a_range_through_pi_is_shown_wrapped() {
        // 20 nodes 0.1 pi apart: nodes 9, 10, 11 are 0.9 pi, -pi, -0.9 pi.
        let r = ThetaRange::of_nodes(&[11, 9, 10], 20).unwrap();
        assert!(r.wraps());
        assert_eq!(r.to_string(), "0.90..-0.90 (wraps)");
        let r = ThetaRange::of_nodes(&[1, 2, 3], 20).unwrap();
        assert!(!r.wraps());
        assert_eq!(r.to_string(), "0.10..0.30");
        // Through node 0 it does not wrap: -0.1 pi .. 0.1 pi.
        assert_eq!(
            ThetaRange::of_nodes(&[19, 0, 1], 20).unwrap().to_string(),
            "-0.10..0.10"
        );
        assert_eq!(ThetaRange::of_nodes(&[4], 20).unwrap().to_string(), "0.40");
        assert!(ThetaRange::of_nodes(&[], 20).is_none());
    }
}
