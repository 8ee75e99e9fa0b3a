//! Slip maps (Figs. 5 and 7): the slip direction of every node at every
//! increment of one steady cycle.
//!
//! The map shows where the slip zones form, travel, split and merge, and in
//! which direction each node slips (forward and backward, model.md section
//! 1.3): at point B (Fig. 5) some nodes slip back and forth, at point C
//! (Fig. 7) none slips against the ratchet.

use std::f64::consts::PI;

use crate::analysis::case::Case;
use crate::contact::SlipDirection;
use crate::model::{Cycle, LoadPoint, Material};
use crate::stepping::steady::SteadyState;
use crate::stepping::{
    drive, Control, Goal, Outcome, Phase, Status, StepError, StepReport, Stepper,
};

/// Why a slip map cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SlipMapError {
    /// An increment failed numerically.
    #[error(transparent)]
    Step(#[from] StepError),
    /// The run ended (gross slip, separation) before a steady cycle.
    #[error("the run ended in {state} before a steady cycle: there is no slip map to draw")]
    NoSteadyCycle {
        /// The state it ended in.
        state: SteadyState,
    },
}

/// One straight sub-segment of the steady cycle: an increment, or the part
/// of one between two events (a node entering slip, an advancing stick).
/// The slip set is fixed over it, so the map's cell edges in time are the
/// exact event times, not the increment grid.
#[derive(Debug, Clone, PartialEq)]
pub struct SlipMapRow {
    /// `omega t` at the start of the sub-segment, in `[0, 2 pi)`.
    pub t0: f64,
    /// `omega t` at its end, in `(0, 2 pi]` (the last one ends at `2 pi`,
    /// not 0).
    pub t1: f64,
    /// The load at the end of the sub-segment.
    pub load: LoadPoint,
    /// Slip direction of each node during the sub-segment.
    pub directions: Vec<SlipDirection>,
}

/// The slip zones of one steady cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct SlipMap {
    /// The case's material (for the conversion to scaled loads).
    pub material: Material,
    /// The case's cycle.
    pub cycle: Cycle,
    /// The number `N` of interface nodes.
    pub nodes: usize,
    /// The outcome of the run to its steady state, before the mapped cycle.
    pub outcome: Outcome,
    /// The load at `t = 0` (the point `C`).
    pub start: LoadPoint,
    /// One row per straight sub-segment of the mapped cycle, in time
    /// order.
    pub rows: Vec<SlipMapRow>,
}

/// Run `case` to its steady state, then through one more cycle, recording
/// the slip direction of every node over every straight sub-segment: the
/// mapped cycle is stepped pausing at each event, so a row ends at an
/// increment's end or at the exact time of an event inside it (the run is
/// the same either way, [`Stepper::set_pause_at_events`]).
///
/// The mapped cycle is one more cycle after the verdict, so it shows the
/// steady cycle itself (for a run that is not converged, simply the next
/// cycle).
///
/// # Errors
///
/// [`SlipMapError::NoSteadyCycle`] when the run ends (gross slip,
/// separation) before or during the mapped cycle, so there is no steady
/// cycle to map; [`SlipMapError::Step`] when an increment fails
/// numerically.
pub fn slip_map(case: &Case) -> Result<SlipMap, SlipMapError> {
    map_cycle(case, true)
}

/// [`slip_map`], with rows at the exact event times (`exact`) or one row
/// per increment (the increment grid, for the tests' comparison).
fn map_cycle(case: &Case, exact: bool) -> Result<SlipMap, SlipMapError> {
    let mut s = case.stepper();
    let outcome = s.run_to_steady()?;
    if s.is_finished() {
        return Err(SlipMapError::NoSteadyCycle {
            state: outcome.state(),
        });
    }
    // The mapped cycle one sub-segment at a time.
    s.set_straight_runs(false);
    s.set_pause_at_events(exact);
    let start = s.contact().load();
    let mut rows = Vec::with_capacity(case.disc().steps_per_cycle());
    let mut t0 = s.time().unwrap_or(0.0);
    // A paused step leaves the contact at the event with the slip set
    // decided there, for the sub-segment that follows: each row has the
    // set as it was at the row's start.
    let mut current = s.contact().directions().to_vec();
    drive(
        &mut s,
        Goal::CycleEnd,
        &mut |s: &Stepper, _: &StepReport| {
            // Back at increment 0 and not paused inside it: the cycle's end.
            let t1 = match s.phase() {
                Phase::Cycle { increment: 0, .. } if !s.is_inside_increment() => 2.0 * PI,
                _ => s.time().unwrap_or(2.0 * PI),
            };
            let next = s.contact().directions().to_vec();
            if !exact {
                // The set at the increment's end: that of its last
                // sub-segment.
                current.clone_from(&next);
            }
            // Two events at one instant (or a set decided at an
            // increment's start) give no row of their own.
            if t1 > t0 {
                rows.push(SlipMapRow {
                    t0,
                    t1,
                    load: s.contact().load(),
                    directions: std::mem::replace(&mut current, next),
                });
                t0 = t1 % (2.0 * PI);
            } else {
                current = next;
            }
            Control::Continue
        },
    )?;
    s.set_pause_at_events(false);
    if let Status::Ended(end) = s.status() {
        return Err(SlipMapError::NoSteadyCycle { state: end.state() });
    }
    Ok(SlipMap {
        material: case.material(),
        cycle: case.cycle().clone(),
        nodes: case.disc().nodes(),
        outcome,
        start,
        rows,
    })
}

impl SlipMap {
    /// `theta` of node `j` in `[-pi, pi)`, as the paper draws it.
    pub fn theta(&self, j: usize) -> f64 {
        let t = 2.0 * PI * j as f64 / self.nodes as f64;
        if t >= PI {
            t - 2.0 * PI
        } else {
            t
        }
    }

    /// Columns of [`SlipMap::csv`].
    pub const HEADER: &'static str = "omega_t,theta,direction";

    /// Long CSV under [`SlipMap::HEADER`]: one line per increment and node,
    /// `direction` the node's [`SlipDirection::paper_sign`]: `1` forward,
    /// `-1` backward in the paper's sense (model.md section 1.3), `0`
    /// stick; `omega_t` is the end of the increment and `theta` is in
    /// `[-pi, pi)`.
    pub fn csv(&self) -> String {
        let mut out = format!("{}\n", Self::HEADER);
        for r in &self.rows {
            for (j, d) in r.directions.iter().enumerate() {
                out.push_str(&format!("{},{},{}\n", r.t1, self.theta(j), d.paper_sign()));
            }
        }
        out
    }

    /// Columns of [`SlipMap::load_csv`].
    pub const LOAD_HEADER: &'static str = "omega_t,x,y,radial,torque";

    /// The load over the cycle, under [`SlipMap::LOAD_HEADER`]: load-plane
    /// `x = chi Pt / f`, `y = Tt / f`
    /// and the scaled loads `Pt`, `Tt`, at `t = 0` and the end of every
    /// increment.
    pub fn load_csv(&self) -> String {
        let mut out = format!("{}\n", Self::LOAD_HEADER);
        let mut line = |t: f64, p: LoadPoint| {
            let l = self.material.to_loads(p);
            out.push_str(&format!(
                "{},{},{},{},{}\n",
                t,
                p.x(),
                p.y(),
                l.radial,
                l.torque
            ));
        };
        line(0.0, self.start);
        for r in &self.rows {
            line(r.t1, r.load);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::case::CaseParams;

    /// Point C of Fig. 7 on a coarse grid.
    fn point_c() -> Case {
        let params = CaseParams {
            load_factor: 5.1,
            phase: PI / 2.0,
            nodes: 32,
            steps: 100,
            ..CaseParams::default()
        };
        Case::from_params(&params).unwrap()
    }

    #[test]
    fn rows_end_at_the_exact_event_times_and_agree_with_the_increment_grid() {
        let case = point_c();
        let exact = slip_map(&case).unwrap();
        let grid = map_cycle(&case, false).unwrap();
        let steps = case.disc().steps_per_cycle();
        assert_eq!(grid.rows.len(), steps);
        assert!(exact.rows.len() > steps, "no event inside an increment");
        // The rows tile the cycle, in order.
        let mut t = exact.rows[0].t0;
        for r in &exact.rows {
            assert!((r.t0 - t % (2.0 * PI)).abs() < 1e-12 && r.t1 > r.t0);
            t = r.t1;
        }
        assert!((t - 2.0 * PI).abs() < 1e-12 || (t - exact.rows[0].t0 - 2.0 * PI).abs() < 1e-9);
        // The last sub-segment of each increment has the set the increment
        // grid reports at its end, and the increment ends are kept.
        for g in &grid.rows {
            let last = exact
                .rows
                .iter()
                .find(|r| (r.t1 - g.t1).abs() < 1e-12)
                .expect("increment end kept");
            assert_eq!(last.directions, g.directions, "at omega t = {}", g.t1);
        }
        // An event ends a row only where the slip set changes.
        let on_grid = |t: f64| grid.rows.iter().any(|g| (g.t1 - t).abs() < 1e-12);
        for w in exact.rows.windows(2) {
            if !on_grid(w[0].t1) {
                assert_ne!(w[0].directions, w[1].directions, "at omega t = {}", w[0].t1);
            }
        }
        assert_eq!(exact.outcome, grid.outcome);
    }
}
