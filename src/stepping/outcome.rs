//! The typed outcome of a run, in the spirit of Clarabel's `SolverStatus`:
//! what state the run reached and how that was established, with the data
//! each state carries. Outcomes are results, not errors: errors are only
//! bad input and numerical failure ([`super::StepError`]).

use serde::Serialize;

use super::steady::{Approach, SteadyState};
use super::stepper::Summary;
use super::verdict::Trend;
use crate::model::LoadPoint;

/// How shakedown was established (model.md section 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShakedownProof {
    /// A whole cycle passed with no slip at any node: the next cycle starts
    /// from the same state under the same loads, so no cycle slips again.
    NoSlipCycle,
    /// A safe state close enough to the slip reached bounds all slip still
    /// to come, so the slip per cycle tends to zero (model.md section 6.4).
    SafeState,
    /// The paper's 0.01 % rule on a cycle that did not slip (kept for
    /// completeness; a cycle without slip is normally caught first).
    Converged,
}

/// What a run came to.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "kebab-case")]
pub enum Outcome {
    /// Slip stopped.
    Shakedown {
        /// How it was established.
        proof: ShakedownProof,
    },
    /// Slip goes on, but some nodes never slip in the steady cycle; no net
    /// rotation.
    CyclicSlip {
        /// `W` of the steady cycle.
        dissipation: f64,
    },
    /// Every node slips each cycle and the disc creeps round.
    Ratchetting {
        /// No node slips against the net rotation.
        monotonic: bool,
        /// `W` of the steady cycle.
        dissipation: f64,
        /// Net rigid rotation per cycle.
        rotation_per_cycle: f64,
    },
    /// The whole interface slid at once (`|y|` reached `2 pi`).
    GrossSlip {
        /// The load point where it happened.
        load: LoadPoint,
        /// `omega t` of that instant, when it was in the cycle.
        time: Option<f64>,
    },
    /// The pressure reached zero somewhere.
    Separation {
        /// The load point where it happened.
        load: LoadPoint,
        /// `omega t` of that instant, when it was in the cycle.
        time: Option<f64>,
        /// Angle of the node that separated.
        theta: f64,
    },
    /// The cycle cap was reached without a verdict: never rounded to a
    /// state.
    NotConverged {
        /// `W` of the last cycle.
        dissipation: f64,
        /// Where `W` was heading, with an estimate of its limit.
        trend: Option<Trend>,
    },
}

impl Outcome {
    /// The state word of this outcome (the `state` column of a sweep).
    pub fn state(&self) -> SteadyState {
        match self {
            Outcome::Shakedown { .. } => SteadyState::Shakedown,
            Outcome::CyclicSlip { .. } => SteadyState::CyclicSlip,
            Outcome::Ratchetting {
                monotonic: true, ..
            } => SteadyState::RatchettingMonotonic,
            Outcome::Ratchetting { .. } => SteadyState::RatchettingNonMonotonic,
            Outcome::GrossSlip { .. } => SteadyState::GrossSlip,
            Outcome::Separation { .. } => SteadyState::Separation,
            Outcome::NotConverged { .. } => SteadyState::NotConverged,
        }
    }
}

impl Summary {
    /// The typed outcome of this summary: the state with the data it
    /// carries.
    ///
    /// ```
    /// use shakedown::analysis::case::{Case, CaseParams};
    /// use shakedown::stepping::Outcome;
    ///
    /// let params = CaseParams { load_factor: 3.5, nodes: 32, steps: 200, ..CaseParams::default() };
    /// let summary = Case::from_params(&params).unwrap().stepper().run_to_steady().unwrap();
    /// assert!(matches!(summary.outcome(), Outcome::Shakedown { .. }));
    /// ```
    pub fn outcome(&self) -> Outcome {
        let load = self.terminal_load.unwrap_or_default();
        match self.state {
            SteadyState::Shakedown => Outcome::Shakedown {
                proof: match self.approach {
                    Approach::NoSlipCycle => ShakedownProof::NoSlipCycle,
                    Approach::SafeState => ShakedownProof::SafeState,
                    _ => ShakedownProof::Converged,
                },
            },
            SteadyState::CyclicSlip => Outcome::CyclicSlip {
                dissipation: self.dissipation,
            },
            SteadyState::RatchettingMonotonic | SteadyState::RatchettingNonMonotonic => {
                Outcome::Ratchetting {
                    monotonic: self.state == SteadyState::RatchettingMonotonic,
                    dissipation: self.dissipation,
                    rotation_per_cycle: self.rotation_per_cycle,
                }
            }
            SteadyState::GrossSlip => Outcome::GrossSlip {
                load,
                time: self.terminal_time,
            },
            SteadyState::Separation => Outcome::Separation {
                load,
                time: self.terminal_time,
                theta: self.terminal_theta.unwrap_or_default(),
            },
            SteadyState::NotConverged => Outcome::NotConverged {
                dissipation: self.dissipation,
                trend: self.trend,
            },
        }
    }
}
