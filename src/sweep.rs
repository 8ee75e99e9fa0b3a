//! Batch sweeps over `lambda`, `phi` and initial paths.
//!
//! Work is reused where the physics allows: the transient `O -> I -> A`
//! does not depend on `lambda` or `phi`, so the contact at the centre `A`
//! is computed once per initial path and cloned into every run. Runs go in
//! parallel (rayon); results come back in job order, so the output is the
//! same whatever the thread count. The `optimal` initial slip depends on
//! `phi`, so it is computed once per phase (one linear programme each).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use rayon::prelude::*;
use serde::Serialize;

use crate::contact::Contact;
use crate::limit::{shakedown_limit, LimitError, DEFAULT_SAMPLES};
use crate::params::{Cycle, Discretisation, LoadPoint, Material, ParamError};
use crate::path::Initial;
use crate::steady::SteadyState;
use crate::stepper::{operators, StepError, StepOptions, Stepper, Summary};

/// What a sweep runs: the product `load_factors x phases x initials`.
#[derive(Debug, Clone)]
pub struct SweepSpec {
    pub material: Material,
    pub disc: Discretisation,
    pub options: StepOptions,
    pub center: LoadPoint,
    pub slope: f64,
    pub load_factors: Vec<f64>,
    pub phases: Vec<f64>,
    pub initials: Vec<Initial>,
}

/// One run of a sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Job {
    /// Position in the full job list: the row order of the output.
    pub index: usize,
    pub load_factor: f64,
    pub phase: f64,
    /// Index into [`SweepSpec::initials`].
    pub initial: usize,
}

/// The state column of a row: a steady state, or a numerical failure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum RowState {
    Steady(SteadyState),
    Failed,
}

impl std::fmt::Display for RowState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RowState::Steady(s) => s.fmt(f),
            RowState::Failed => f.write_str("failed"),
        }
    }
}

/// Why a run of a sweep has no summary.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Step(#[from] StepError),
    #[error("initial path 'optimal' at phi = {phase}: {source}")]
    Optimal { phase: f64, source: LimitError },
}

/// One finished run.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub job: Job,
    pub initial: String,
    pub outcome: Result<Summary, RunError>,
}

/// Columns of a sweep's CSV, one [`Row::csv_line`] each.
pub const CSV_HEADER: &str = "lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle";

impl Row {
    pub fn state(&self) -> RowState {
        match &self.outcome {
            Ok(s) => RowState::Steady(s.state),
            Err(_) => RowState::Failed,
        }
    }

    /// One CSV line (no newline) under [`CSV_HEADER`]. Numbers use Rust's
    /// shortest round-trip form, so the bytes do not depend on the platform
    /// or the thread count.
    pub fn csv_line(&self) -> String {
        let (w, c, r) = match &self.outcome {
            Ok(s) => (s.dissipation, s.cycles, s.rotation_per_cycle),
            Err(_) => (f64::NAN, 0, f64::NAN),
        };
        format!(
            "{},{},\"{}\",{},{},{},{}",
            self.job.load_factor,
            self.job.phase,
            self.initial,
            self.state(),
            w,
            c,
            r
        )
    }
}

/// Where the runs of one initial path start.
enum Start {
    /// The transient's end state at `A` (or how the transient ended),
    /// shared by every `lambda` and `phi`.
    Shared(Box<Result<Result<Contact, Summary>, StepError>>),
    /// The optimal slip, which depends on `phi`: looked up per phase.
    PerPhase,
}

/// The optimal slip placed at `A`, per phase (keyed by the phase's bits).
type OptimalStarts = Vec<(u64, Result<Contact, LimitError>)>;

impl SweepSpec {
    /// Every run, in output order: `lambda` outermost, then `phi`, then the
    /// initial paths in their given order.
    pub fn jobs(&self) -> Vec<Job> {
        let mut jobs =
            Vec::with_capacity(self.load_factors.len() * self.phases.len() * self.initials.len());
        for &load_factor in &self.load_factors {
            for &phase in &self.phases {
                for initial in 0..self.initials.len() {
                    jobs.push(Job {
                        index: jobs.len(),
                        load_factor,
                        phase,
                        initial,
                    });
                }
            }
        }
        jobs
    }

    /// Check every cycle of the sweep before any work starts.
    pub fn validate(&self) -> Result<(), ParamError> {
        for &l in &self.load_factors {
            for &p in &self.phases {
                Cycle::new(self.center, l, self.slope, p)?;
            }
        }
        Ok(())
    }

    /// The contact at `A` for each initial path (in parallel), or the
    /// summary of a transient that already ended in gross slip or separation.
    fn prepare(&self) -> Vec<Start> {
        let ops = operators(&self.disc);
        self.initials
            .par_iter()
            .map(|initial| match initial {
                Initial::Optimal => Start::PerPhase,
                _ => Start::Shared(Box::new(Stepper::prepare_at_center(
                    Arc::clone(&ops),
                    self.material,
                    self.disc,
                    initial,
                    self.center,
                    self.options,
                ))),
            })
            .collect()
    }

    /// The optimal slip at `A` for every phase that `jobs` run it at: one
    /// linear programme per phase, in parallel.
    fn optimal_starts(&self, jobs: &[Job]) -> OptimalStarts {
        let mut phases: Vec<f64> = jobs
            .iter()
            .filter(|j| matches!(self.initials[j.initial], Initial::Optimal))
            .map(|j| j.phase)
            .collect();
        phases.sort_by(f64::total_cmp);
        phases.dedup_by(|a, b| a.to_bits() == b.to_bits());
        if phases.is_empty() {
            return Vec::new();
        }
        let ops = operators(&self.disc);
        phases
            .par_iter()
            .map(|&phase| {
                let start = shakedown_limit(
                    &self.material,
                    self.center,
                    self.slope,
                    phase,
                    &self.disc,
                    DEFAULT_SAMPLES,
                )
                .map(|limit| {
                    let mut c = Contact::new(self.material, Arc::clone(&ops));
                    c.set_slip(&limit.slip);
                    c.set_load_elastic(self.center);
                    c
                });
                (phase.to_bits(), start)
            })
            .collect()
    }

    /// Run `jobs` (a subset of [`SweepSpec::jobs`]) in parallel. `done` is
    /// called once per finished run, from any thread. When `cancel` is set,
    /// runs not yet started are skipped: the result then holds only the runs
    /// that finished, still in job order.
    pub fn run(&self, jobs: &[Job], done: &(dyn Fn(&Row) + Sync), cancel: &AtomicBool) -> Vec<Row> {
        let prepared = self.prepare();
        let optimal = self.optimal_starts(jobs);
        let mut rows: Vec<Row> = jobs
            .par_iter()
            .filter_map(|job| {
                if cancel.load(Ordering::Relaxed) {
                    return None;
                }
                let row = self.run_job(job, &prepared[job.initial], &optimal);
                done(&row);
                Some(row)
            })
            .collect();
        rows.sort_by_key(|r| r.job.index);
        rows
    }

    fn run_job(&self, job: &Job, start: &Start, optimal: &OptimalStarts) -> Row {
        let initial = self.initials[job.initial].name();
        let contact = match start {
            Start::Shared(shared) => match shared.as_ref() {
                Err(e) => Err(RunError::Step(e.clone())),
                Ok(Err(summary)) => Ok(Err(summary.clone())),
                Ok(Ok(contact)) => Ok(Ok(contact)),
            },
            Start::PerPhase => {
                let found = optimal
                    .iter()
                    .find(|(bits, _)| *bits == job.phase.to_bits())
                    .map(|(_, c)| c)
                    .expect("optimal_starts covers every phase of the jobs");
                match found {
                    Ok(contact) => Ok(Ok(contact)),
                    Err(e) => Err(RunError::Optimal {
                        phase: job.phase,
                        source: e.clone(),
                    }),
                }
            }
        };
        let outcome = contact.and_then(|c| match c {
            Err(summary) => Ok(summary),
            Ok(contact) => {
                let cycle = Cycle::new(self.center, job.load_factor, self.slope, job.phase)
                    .expect("validated before the sweep");
                let mut s = Stepper::from_center(contact.clone(), cycle, self.disc, self.options);
                s.run_to_steady().map_err(RunError::from)
            }
        });
        Row {
            job: *job,
            initial,
            outcome,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn job_order_is_lambda_phi_initial() {
        let spec = SweepSpec {
            material: Material::paper(),
            disc: Discretisation::default(),
            options: StepOptions::default(),
            center: LoadPoint::new(1.0, 1.0),
            slope: 0.5,
            load_factors: vec![1.0, 2.0],
            phases: vec![0.0, 0.5],
            initials: Initial::paper_set()[..3].to_vec(),
        };
        let jobs = spec.jobs();
        assert_eq!(jobs.len(), 12);
        assert_eq!(
            (jobs[3].load_factor, jobs[3].phase, jobs[3].initial),
            (1.0, 0.5, 0)
        );
        assert!(jobs.iter().enumerate().all(|(i, j)| j.index == i));
    }
}
