//! The paper's figures: the data behind them, as tables and CSV, and their
//! drawing ([`draw`]).
//!
//! * Figs. 3, 6, 8, 9 are sweeps ([`crate::sweep`]): steady-state `W` with
//!   its state, against `lambda` or `phi`.
//! * Fig. 4 needs more than a sweep keeps: which nodes slipped during the
//!   transient `O -> I -> A` and which slip again afterwards
//!   ([`memory_runs`], [`memory_points`]).
//! * Figs. 5 and 7 follow one case through one steady cycle, increment by
//!   increment ([`slip_map`]).

pub mod draw;

use std::f64::consts::PI;
use std::sync::Arc;

use rayon::prelude::*;

use crate::case::Case;
use crate::contact::SlipDirection;
use crate::limit::LimitError;
use crate::params::{Cycle, LoadPoint, Material};
use crate::path::Initial;
use crate::steady::SteadyState;
use crate::stepper::{operators, Phase, Status, StepError, Stepper, Summary};
use crate::sweep::SweepSpec;

/// A figure that cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FigureError {
    #[error(transparent)]
    Step(#[from] StepError),
    #[error(transparent)]
    Limit(#[from] LimitError),
    #[error("the run ended in {state} before a steady cycle: there is no slip map to draw")]
    NoSteadyCycle { state: SteadyState },
    #[error(
        "the memory figure follows transients from O; '{0}' starts at A and has none: leave it out of the initial paths"
    )]
    NoTransient(String),
    #[error("cannot draw {file}: {message}")]
    Draw { file: String, message: String },
    #[error("cannot write {file}: {message}")]
    Write { file: String, message: String },
}

/// Slip smaller than this fraction of the largest counts as round-off, as
/// in the classification of a cycle.
const SLIP_FRACTION: f64 = 1e-6;

// ----- Fig. 4: memory ---------------------------------------------------------

/// One run of the memory figure: which nodes slipped before and after `A`.
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryRun {
    pub load_factor: f64,
    pub phase: f64,
    pub initial: String,
    pub outcome: Result<Summary, StepError>,
    /// Nodes that slipped during the transient `O -> I -> A`.
    pub transient_slip: Vec<bool>,
    /// Nodes that slipped at any time after `A` (the entry `A -> C` and
    /// every cycle, not only the steady one).
    pub slip_after_a: Vec<bool>,
}

/// `R` and `r` at one `lambda` (model.md section 7).
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryPoint {
    pub load_factor: f64,
    pub phase: f64,
    /// `R = (max W - min W) / mean W` over every run at this `lambda`;
    /// `None` unless every run reached a steady state with slip.
    pub range: Option<f64>,
    /// `r`: of the nodes that slipped during `O -> I -> A`, the fraction that
    /// never slips again, averaged over the transients that slipped at all;
    /// `None` when no transient slipped.
    pub stuck_fraction: Option<f64>,
    pub shakedown: usize,
    pub cyclic_slip: usize,
    pub ratchetting: usize,
    /// Gross slip, separation, not converged or failed.
    pub other: usize,
}

/// Nodes whose accumulated `|dg|` is above round-off.
fn slipped(total: &[f64], scale: f64) -> Vec<bool> {
    let tol = SLIP_FRACTION * scale;
    total.iter().map(|&v| v > tol).collect()
}

fn add_abs_change(total: &mut [f64], before: &[f64], after: &[f64]) {
    for ((t, b), a) in total.iter_mut().zip(before).zip(after) {
        *t += (a - b).abs();
    }
}

/// Run the memory figure's sweep: every `lambda x phi x initial` of `spec`,
/// tracking per node the slip before and after `A`. `done` is called once
/// per finished run. Runs go in parallel; the result is in job order.
pub fn memory_runs(
    spec: &SweepSpec,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<MemoryRun>, FigureError> {
    if let Some(i) = spec
        .initials
        .iter()
        .find(|i| matches!(i, Initial::Optimal | Initial::Slip { .. }))
    {
        return Err(FigureError::NoTransient(i.name()));
    }
    let ops = operators(&spec.disc);
    let n = spec.disc.nodes();
    // The transient to A does not depend on lambda or phi: run it once per
    // initial path, summing |dg| per node on the way.
    let prepared: Vec<_> = spec
        .initials
        .par_iter()
        .map(|initial| {
            let dummy = Cycle::new(spec.center, 0.0, 0.0, 0.0).expect("validated centre");
            let mut s = Stepper::with_operators(
                Arc::clone(&ops),
                spec.material,
                spec.disc,
                initial,
                dummy,
                spec.options,
            );
            let mut total = vec![0.0; n];
            while matches!(s.phase(), Phase::Transient { .. }) {
                let before = s.contact().slip().to_vec();
                s.step()?;
                add_abs_change(&mut total, &before, s.contact().slip());
                if let Status::Ended(summary) = s.status() {
                    return Ok((Err(summary.clone()), total));
                }
            }
            Ok((Ok(s.contact().clone()), total))
        })
        .collect::<Vec<Result<_, StepError>>>();

    let jobs = spec.jobs();
    let runs = jobs
        .par_iter()
        .map(|job| {
            let initial = spec.initials[job.initial].name();
            let (outcome, transient, after) = match &prepared[job.initial] {
                Err(e) => (Err(e.clone()), vec![0.0; n], vec![0.0; n]),
                Ok((Err(summary), total)) => (Ok(summary.clone()), total.clone(), vec![0.0; n]),
                Ok((Ok(contact), total)) => {
                    let cycle = Cycle::new(spec.center, job.load_factor, spec.slope, job.phase)
                        .expect("validated before the sweep");
                    let mut s =
                        Stepper::from_center(contact.clone(), cycle, spec.disc, spec.options);
                    let mut after = vec![0.0; n];
                    let mut outcome = None;
                    while matches!(s.status(), Status::Running) {
                        let before = s.contact().slip().to_vec();
                        if let Err(e) = s.step() {
                            outcome = Some(Err(e));
                            break;
                        }
                        add_abs_change(&mut after, &before, s.contact().slip());
                    }
                    let outcome =
                        outcome.unwrap_or_else(|| Ok(s.summary().cloned().expect("not running")));
                    (outcome, total.clone(), after)
                }
            };
            let scale = transient.iter().chain(&after).cloned().fold(0.0, f64::max);
            done();
            MemoryRun {
                load_factor: job.load_factor,
                phase: job.phase,
                initial,
                outcome,
                transient_slip: slipped(&transient, scale),
                slip_after_a: slipped(&after, scale),
            }
        })
        .collect();
    Ok(runs)
}

/// `R` and `r` for each `(lambda, phi)` of the runs, in order of first
/// appearance.
pub fn memory_points(runs: &[MemoryRun]) -> Vec<MemoryPoint> {
    let mut keys: Vec<(f64, f64)> = Vec::new();
    for r in runs {
        if !keys.iter().any(|k| k.0 == r.load_factor && k.1 == r.phase) {
            keys.push((r.load_factor, r.phase));
        }
    }
    keys.into_iter()
        .map(|(load_factor, phase)| {
            let group: Vec<&MemoryRun> = runs
                .iter()
                .filter(|r| r.load_factor == load_factor && r.phase == phase)
                .collect();
            let mut point = MemoryPoint {
                load_factor,
                phase,
                range: None,
                stuck_fraction: None,
                shakedown: 0,
                cyclic_slip: 0,
                ratchetting: 0,
                other: 0,
            };
            let mut w = Vec::new();
            for r in &group {
                match &r.outcome {
                    Ok(s) if s.state == SteadyState::Shakedown => point.shakedown += 1,
                    Ok(s) if s.state == SteadyState::CyclicSlip => {
                        point.cyclic_slip += 1;
                        w.push(s.dissipation);
                    }
                    Ok(s) if s.state.is_ratchetting() => {
                        point.ratchetting += 1;
                        w.push(s.dissipation);
                    }
                    _ => point.other += 1,
                }
            }
            if w.len() == group.len() && !w.is_empty() {
                let mean = w.iter().sum::<f64>() / w.len() as f64;
                let max = w.iter().cloned().fold(f64::MIN, f64::max);
                let min = w.iter().cloned().fold(f64::MAX, f64::min);
                if mean > 0.0 {
                    point.range = Some((max - min) / mean);
                }
            }
            let fractions: Vec<f64> = group
                .iter()
                .filter(|r| r.outcome.is_ok())
                .filter_map(|r| {
                    let slipped = r.transient_slip.iter().filter(|&&s| s).count();
                    (slipped > 0).then(|| {
                        let stuck = r
                            .transient_slip
                            .iter()
                            .zip(&r.slip_after_a)
                            .filter(|(&t, &a)| t && !a)
                            .count();
                        stuck as f64 / slipped as f64
                    })
                })
                .collect();
            if !fractions.is_empty() {
                point.stuck_fraction = Some(fractions.iter().sum::<f64>() / fractions.len() as f64);
            }
            point
        })
        .collect()
}

/// Columns of the memory figure's CSV.
pub const MEMORY_HEADER: &str = "lambda,phi,R,r,shakedown,cyclic_slip,ratchetting,other";

/// The memory figure's CSV; an undefined `R` or `r` is an empty field.
pub fn memory_csv(points: &[MemoryPoint]) -> String {
    let opt = |v: Option<f64>| v.map(|v| v.to_string()).unwrap_or_default();
    let mut out = format!("{MEMORY_HEADER}\n");
    for p in points {
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{}\n",
            p.load_factor,
            p.phase,
            opt(p.range),
            opt(p.stuck_fraction),
            p.shakedown,
            p.cyclic_slip,
            p.ratchetting,
            p.other
        ));
    }
    out
}

// ----- Figs. 5 and 7: slip map --------------------------------------------------

/// One increment of the steady cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct SlipMapRow {
    /// `omega t` at the start and end of the increment.
    pub t0: f64,
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
    pub material: Material,
    pub cycle: Cycle,
    pub nodes: usize,
    pub summary: Summary,
    /// The load at `t = 0` (the point `C`).
    pub start: LoadPoint,
    pub rows: Vec<SlipMapRow>,
}

/// Run `case` to its steady state, then through one more cycle, recording
/// the slip direction of every node at every increment.
pub fn slip_map(case: &Case) -> Result<SlipMap, FigureError> {
    let mut s = case.stepper();
    let summary = s.run_to_steady()?;
    if s.is_finished() {
        return Err(FigureError::NoSteadyCycle {
            state: summary.state,
        });
    }
    let start = s.contact().load();
    let target = s.history().len() + 1;
    let mut rows = Vec::with_capacity(case.disc.steps_per_cycle());
    while s.history().len() < target {
        let t0 = s.time().unwrap_or(0.0);
        s.step()?;
        if let Status::Ended(end) = s.status() {
            return Err(FigureError::NoSteadyCycle { state: end.state });
        }
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
    }
    Ok(SlipMap {
        material: case.material,
        cycle: case.cycle,
        nodes: case.disc.nodes(),
        summary,
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

    /// Long CSV: one line per increment and node, `direction` in
    /// `{-1, 0, 1}` (backward, stick, forward); `omega_t` is the end of the
    /// increment.
    pub fn csv(&self) -> String {
        let mut out = format!("{}\n", Self::HEADER);
        for r in &self.rows {
            for (j, d) in r.directions.iter().enumerate() {
                out.push_str(&format!("{},{},{}\n", r.t1, self.theta(j), d.sign()));
            }
        }
        out
    }

    /// Columns of [`SlipMap::load_csv`].
    pub const LOAD_HEADER: &'static str = "omega_t,x,y,radial,torque";

    /// The load over the cycle: load-plane `x = chi Pt / f`, `y = Tt / f`
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
