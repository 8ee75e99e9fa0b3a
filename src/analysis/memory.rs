//! The memory measures of Fig. 4 (model.md section 7): `R`, the spread of
//! the steady `W` over the initial transients (eq. 17), and `r`, the share
//! of the interface that slipped during the transient `O -> I -> A` and
//! never slips again at any time after `A`.

use std::sync::Arc;

use rayon::prelude::*;

use crate::analysis::sweep::SweepSpec;
use crate::model::path::Initial;
use crate::model::Cycle;
use crate::stepping::steady::SteadyState;
use crate::stepping::{
    drive, operators, Control, Driven, Goal, Observer, Outcome, Status, StepError, StepReport,
    Stepper,
};

/// Why the memory runs cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MemoryError {
    /// An increment failed numerically.
    #[error(transparent)]
    Step(#[from] StepError),
    /// An initial path with no transient from `O`.
    #[error(
        "the memory figure follows transients from O; '{0}' starts at A and has none: leave it out of the initial paths"
    )]
    NoTransient(String),
    /// A cycle of the sweep is invalid.
    #[error(transparent)]
    Param(#[from] crate::model::ParamError),
}

/// Slip smaller than this fraction of the largest counts as round-off, as
/// in the classification of a cycle.
const SLIP_FRACTION: f64 = 1e-6;

/// One run of the memory figure: which nodes slipped before and after `A`.
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryRun {
    /// `lambda` of the run.
    pub load_factor: f64,
    /// `phi` of the run, radians.
    pub phase: f64,
    /// The initial path's stable name ([`Initial::name`]).
    pub initial: String,
    /// The run's outcome, or the numerical failure that stopped it.
    pub outcome: Result<Outcome, StepError>,
    /// Nodes that slipped during the transient `O -> I -> A`, one flag per
    /// node. Slip below `1e-6` of the largest accumulated `|dg|` of the run
    /// counts as round-off (model.md section 6.2).
    pub transient_slip: Vec<bool>,
    /// Nodes that slipped at any time after `A` (the entry `A -> C` and
    /// every cycle, not only the steady one).
    pub slip_after_a: Vec<bool>,
}

/// `R` and `r` at one `lambda` (model.md section 7).
#[derive(Debug, Clone, PartialEq)]
pub struct MemoryPoint {
    /// `lambda` of the runs.
    pub load_factor: f64,
    /// `phi` of the runs, radians.
    pub phase: f64,
    /// `R = (max W - min W) / mean W` over every run at this `lambda`;
    /// `None` unless every run reached a steady state with slip.
    pub range: Option<f64>,
    /// `r`: of the nodes that slipped during `O -> I -> A`, the fraction that
    /// never slips again, averaged over the transients that slipped at all;
    /// `None` when no transient slipped. Runs that failed numerically are
    /// left out.
    pub stuck_fraction: Option<f64>,
    /// Runs that shook down.
    pub shakedown: usize,
    /// Runs that ended in cyclic slip.
    pub cyclic_slip: usize,
    /// Runs that ratchet, monotonically or not.
    pub ratchetting: usize,
    /// Gross slip, separation, not converged or failed.
    pub other: usize,
}

/// Nodes whose accumulated `|dg|` is above round-off.
fn slipped(total: &[f64], scale: f64) -> Vec<bool> {
    let tol = SLIP_FRACTION * scale;
    total.iter().map(|&v| v > tol).collect()
}

/// An observer that adds up `|dg|` per node over the increments it sees.
struct SlipTally {
    last: Vec<f64>,
    total: Vec<f64>,
}

impl SlipTally {
    fn new(slip: &[f64]) -> Self {
        Self {
            last: slip.to_vec(),
            total: vec![0.0; slip.len()],
        }
    }
}

impl Observer for SlipTally {
    fn observe(&mut self, stepper: &Stepper, _: &StepReport) -> Control {
        let now = stepper.contact().slip();
        for ((t, b), a) in self.total.iter_mut().zip(&mut self.last).zip(now) {
            *t += (a - *b).abs();
            *b = *a;
        }
        Control::Continue
    }
}

/// Run the memory figure's sweep: every `lambda x phi x initial` of `spec`,
/// tracking per node the slip before and after `A`. `done` is called once
/// per finished run. Runs go in parallel; the result is in job order.
///
/// Each transient to `A` is run once and shared by every `lambda` and `phi`.
/// A run whose transient failed numerically, or ended in gross slip or
/// separation, is still returned (with that outcome), so that one bad
/// transient does not lose the rest of the figure.
///
/// # Errors
///
/// [`MemoryError::NoTransient`] if an initial path of `spec` starts at `A`
/// (`optimal` or a prescribed slip), checked before any work;
/// [`MemoryError::Param`] if the cycle of a job is invalid. Numerical
/// failures of single runs are in [`MemoryRun::outcome`], not errors here.
pub fn memory_runs(
    spec: &SweepSpec,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<MemoryRun>, MemoryError> {
    if let Some(i) = spec
        .initials()
        .iter()
        .find(|i| matches!(i, Initial::Optimal | Initial::Slip { .. }))
    {
        return Err(MemoryError::NoTransient(i.name()));
    }
    let ops = operators(&spec.disc());
    let n = spec.disc().nodes();
    // The transient to A does not depend on lambda or phi: run it once per
    // initial path, summing |dg| per node on the way.
    let dummy = Cycle::new(spec.center(), 0.0, 0.0, 0.0)?;
    let prepared: Vec<_> = spec
        .initials()
        .par_iter()
        .map(|initial| {
            let mut s = Stepper::with_operators(
                Arc::clone(&ops),
                spec.material(),
                spec.disc(),
                initial,
                dummy.clone(),
                spec.options(),
            );
            let mut total = SlipTally::new(s.contact().slip());
            drive(&mut s, Goal::TransientEnd, &mut total)?;
            if let Status::Ended(outcome) = s.status() {
                return Ok((Err(*outcome), total.total));
            }
            Ok((Ok(s.contact().clone()), total.total))
        })
        .collect::<Vec<Result<_, StepError>>>();

    let jobs = spec.jobs();
    let cycles = jobs
        .iter()
        .map(|j| spec.cycle(j))
        .collect::<Result<Vec<_>, _>>()?;
    let runs = jobs
        .par_iter()
        .map(|job| {
            let initial = spec.initials()[job.initial].name();
            let (outcome, transient, after) = match &prepared[job.initial] {
                Err(e) => (Err(e.clone()), vec![0.0; n], vec![0.0; n]),
                Ok((Err(outcome), total)) => (Ok(*outcome), total.clone(), vec![0.0; n]),
                Ok((Ok(contact), total)) => {
                    let cycle = cycles[job.index].clone();
                    // r counts every node that slips after A up to the
                    // verdict, so asymptotic shakedown is run out to its
                    // first cycle without slip: a safe state bounds the
                    // slip still to come but not where it happens.
                    let options = spec.options().with_safe_state(false);
                    let mut s = Stepper::from_center(contact.clone(), cycle, spec.disc(), options);
                    let mut after = SlipTally::new(s.contact().slip());
                    let outcome = loop {
                        match drive(&mut s, Goal::Steady, &mut after) {
                            Ok(Driven::Finished(outcome)) => break Ok(outcome),
                            // The tally never stops the run.
                            Ok(Driven::Reached | Driven::Stopped) => {}
                            Err(e) => break Err(e),
                        }
                    };
                    (outcome, total.clone(), after.total)
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
/// appearance, with the count of each steady state (model.md sections 7.1
/// and 7.2).
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
                    Ok(s) if s.state() == SteadyState::Shakedown => point.shakedown += 1,
                    Ok(s) if s.state() == SteadyState::CyclicSlip => {
                        point.cyclic_slip += 1;
                        w.push(s.dissipation);
                    }
                    Ok(s) if s.state().is_ratchetting() => {
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

/// The smallest `lambda` from which every run ratchets, up to the largest
/// `lambda` of `points`: the paper's `lambda_3`. `None` when the largest
/// `lambda` does not ratchet for every transient.
pub fn ratchetting_onset(points: &[MemoryPoint]) -> Option<f64> {
    let total = |p: &MemoryPoint| p.shakedown + p.cyclic_slip + p.ratchetting + p.other;
    let mut onset = None;
    for p in points.iter().rev() {
        if p.ratchetting == total(p) && p.ratchetting > 0 {
            onset = Some(p.load_factor);
        } else if onset.is_some() {
            break;
        }
    }
    onset
}
