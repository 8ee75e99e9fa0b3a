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

/// One increment of the steady cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct SlipMapRow {
    /// `omega t` at the start of the increment, in `[0, 2 pi)`.
    pub t0: f64,
    /// `omega t` at the end of the increment, in `(0, 2 pi]` (the last
    /// increment ends at `2 pi`, not 0).
    pub t1: f64,
    /// The load at the end of the increment.
    pub load: LoadPoint,
    /// Slip direction of each node during the increment (of its last
    /// sub-increment when it was bisected).
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
    /// One row per increment of the mapped cycle, in time order.
    pub rows: Vec<SlipMapRow>,
}

/// Run `case` to its steady state, then through one more cycle, recording
/// the slip direction of every node at every increment.
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
    let mut s = case.stepper();
    let outcome = s.run_to_steady()?;
    if s.is_finished() {
        return Err(SlipMapError::NoSteadyCycle {
            state: outcome.state(),
        });
    }
    // The mapped cycle one increment at a time.
    s.set_straight_runs(false);
    let start = s.contact().load();
    let mut rows = Vec::with_capacity(case.disc.steps_per_cycle());
    let mut t0 = s.time().unwrap_or(0.0);
    drive(
        &mut s,
        Goal::CycleEnd,
        &mut |s: &Stepper, _: &StepReport| {
            let t1 = match s.phase() {
                Phase::Cycle { increment: 0, .. } => 2.0 * PI,
                _ => s.time().unwrap_or(2.0 * PI),
            };
            rows.push(SlipMapRow {
                t0,
                t1,
                load: s.contact().load(),
                directions: s.contact().directions().to_vec(),
            });
            t0 = t1 % (2.0 * PI);
            Control::Continue
        },
    )?;
    if let Status::Ended(end) = s.status() {
        return Err(SlipMapError::NoSteadyCycle { state: end.state() });
    }
    Ok(SlipMap {
        material: case.material,
        cycle: case.cycle.clone(),
        nodes: case.disc.nodes(),
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
