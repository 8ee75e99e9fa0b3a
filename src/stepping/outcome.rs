//! The one result of a run, in the spirit of Clarabel's single
//! `SolverStatus`: the state reached with how it was established
//! ([`Verdict`]), and the numbers of the steady cycle ([`Outcome`]).
//! Outcomes are results, not errors: errors are only bad input and
//! numerical failure ([`super::StepError`]). The plain words a table
//! prints ([`SteadyState`], [`Approach`]) are derived from it.

use serde::Serialize;

use super::safe_state::Certificate;
use super::steady::{Approach, SteadyState};
use super::verdict::Trend;
use crate::model::LoadPoint;

/// The whole interface slides: `|y|` reached `2 pi` (model.md section 2.3).
/// The payload of [`super::Event::GrossSlip`] and of
/// [`Verdict::GrossSlip`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GrossSlip {
    /// The load point `(x, y)` where `|y| = 2 pi` (exact, interpolated
    /// within the increment).
    pub load: LoadPoint,
    /// `omega t` in `[0, 2 pi)` in the cycle; `None` in the transient.
    pub time: Option<f64>,
}

/// The pressure reached zero somewhere (model.md section 2.3). The payload
/// of [`super::Event::Separation`] and of [`Verdict::Separation`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Separation {
    /// The load point `(x, y)` where the pressure `p` reached zero.
    pub load: LoadPoint,
    /// `omega t` in `[0, 2 pi)` in the cycle; `None` in the transient.
    pub time: Option<f64>,
    /// The angle `theta` of the node where `p` reached zero.
    pub theta: f64,
}

/// A steady value estimated from the cycles run, with a two-sided bound:
/// the value lies in `[value - uncertainty, value + uncertainty]`
/// (model.md section 6.1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Level {
    /// The estimate.
    pub value: f64,
    /// Half the width of the interval that holds the value.
    pub uncertainty: f64,
}

/// How shakedown was established (model.md section 6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShakedownProof {
    /// A whole cycle passed with no slip at any node: the next cycle starts
    /// from the same state under the same loads, so no cycle slips again.
    NoSlipCycle,
    /// A safe state close enough to the slip reached bounds all slip still
    /// to come, so the slip per cycle tends to zero (model.md section 6.4).
    SafeState(Certificate),
    /// The paper's 0.01 % rule on a cycle that did not slip (kept for
    /// completeness; a cycle without slip is normally caught first).
    Converged,
}

/// The state a run reached, with how it was established and the data that
/// state alone carries.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Slip stopped.
    Shakedown(ShakedownProof),
    /// Slip goes on, but some nodes never slip in the steady cycle; no net
    /// rotation. Established by the 0.01 % rule.
    CyclicSlip,
    /// Every node slips each cycle and the disc creeps round. Established
    /// by the 0.01 % rule.
    Ratchetting {
        /// No node slips against the net rotation.
        monotonic: bool,
    },
    /// The whole interface slid at once: the run ended there.
    GrossSlip(GrossSlip),
    /// The pressure reached zero somewhere: the run ended there.
    Separation(Separation),
    /// The cycle cap was reached without a verdict: never rounded to a
    /// state.
    NotConverged {
        /// Where `W` was heading, with an estimate of its limit and the
        /// uncertainty of that estimate (`None` when too few cycles ran to
        /// tell).
        trend: Option<Trend>,
    },
}

/// What a run came to: the [`Verdict`] and the numbers of the steady (or
/// last) cycle.
///
/// ```
/// use shakedown::analysis::case::{Case, CaseParams};
/// use shakedown::{SteadyState, Verdict};
///
/// let params = CaseParams { load_factor: 3.5, nodes: 32, steps: 200, ..CaseParams::default() };
/// let outcome = Case::from_params(&params)?.stepper().run_to_steady()?;
/// assert!(matches!(outcome.verdict, Verdict::Shakedown(_)));
/// assert_eq!(outcome.state(), SteadyState::Shakedown);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Outcome {
    /// The state, with how it was established.
    pub verdict: Verdict,
    /// `W` of the steady cycle: of the last complete cycle, or 0 for
    /// shakedown proven by a safe state (`W` tends to zero; the last
    /// cycle's `W` is in the certificate). Model.md section 4.
    pub dissipation: f64,
    /// Net rigid rotation of the last complete cycle: the change of the
    /// mean of the slip `g` (0 with a safe state).
    pub rotation_per_cycle: f64,
    /// Complete cycles run.
    pub cycles: usize,
    /// The steady level of `W` that the cycles approach, with its bound,
    /// for cyclic slip and ratchetting (`None` otherwise): `dissipation`
    /// is the last cycle's `W`, which the 0.01 % rule leaves up to a few
    /// tenths of a per cent from the level where `W` approaches it slowly
    /// (model.md section 6.1).
    pub level: Option<Level>,
    /// The steady net rotation per cycle, for cyclic slip and ratchetting
    /// (`None` otherwise): 0 for cyclic slip, where the nodes that never
    /// slip hold the mean of `g` (model.md section 6.2); the level the
    /// rotation per cycle approaches for ratchetting. The last cycle's
    /// drift apart from it is [`Outcome::rotation_drift`].
    pub steady_rotation: Option<Level>,
}

impl Outcome {
    /// The plain state word (the `state` column of a sweep).
    pub fn state(&self) -> SteadyState {
        match self.verdict {
            Verdict::Shakedown(_) => SteadyState::Shakedown,
            Verdict::CyclicSlip => SteadyState::CyclicSlip,
            Verdict::Ratchetting { monotonic: true } => SteadyState::RatchettingMonotonic,
            Verdict::Ratchetting { monotonic: false } => SteadyState::RatchettingNonMonotonic,
            Verdict::GrossSlip(_) => SteadyState::GrossSlip,
            Verdict::Separation(_) => SteadyState::Separation,
            Verdict::NotConverged { .. } => SteadyState::NotConverged,
        }
    }

    /// The plain word for how the verdict was reached (model.md section
    /// 6.1).
    pub fn approach(&self) -> Approach {
        match self.verdict {
            Verdict::Shakedown(ShakedownProof::NoSlipCycle) => Approach::NoSlipCycle,
            Verdict::Shakedown(ShakedownProof::SafeState(_)) => Approach::SafeState,
            Verdict::Shakedown(ShakedownProof::Converged)
            | Verdict::CyclicSlip
            | Verdict::Ratchetting { .. } => Approach::Converged,
            Verdict::GrossSlip(_) | Verdict::Separation(_) => Approach::Terminal,
            Verdict::NotConverged { .. } => Approach::Cap,
        }
    }

    /// Whether the run ended physically (gross slip or separation): no
    /// further step is possible.
    pub fn is_terminal(&self) -> bool {
        matches!(self.verdict, Verdict::GrossSlip(_) | Verdict::Separation(_))
    }

    /// How far the last cycle's rotation is from the steady rotation (the
    /// cycles' approach to the steady cycle, not part of it), when there is
    /// one.
    pub fn rotation_drift(&self) -> Option<f64> {
        self.steady_rotation
            .map(|r| self.rotation_per_cycle - r.value)
    }

    /// The safe state that proved shakedown, if it was proven so.
    pub fn certificate(&self) -> Option<&Certificate> {
        match &self.verdict {
            Verdict::Shakedown(ShakedownProof::SafeState(c)) => Some(c),
            _ => None,
        }
    }

    /// Where `W` was heading when the cycle cap was reached.
    pub fn trend(&self) -> Option<&Trend> {
        match &self.verdict {
            Verdict::NotConverged { trend } => trend.as_ref(),
            _ => None,
        }
    }

    /// The load point where gross slip or separation ended the run.
    pub fn terminal_load(&self) -> Option<LoadPoint> {
        match self.verdict {
            Verdict::GrossSlip(g) => Some(g.load),
            Verdict::Separation(s) => Some(s.load),
            _ => None,
        }
    }

    /// `omega t` of the terminal point, when it was in the cycle.
    pub fn terminal_time(&self) -> Option<f64> {
        match self.verdict {
            Verdict::GrossSlip(g) => g.time,
            Verdict::Separation(s) => s.time,
            _ => None,
        }
    }

    /// The angle `theta` of the node that separated.
    pub fn terminal_theta(&self) -> Option<f64> {
        match self.verdict {
            Verdict::Separation(s) => Some(s.theta),
            _ => None,
        }
    }
}

impl std::fmt::Display for Outcome {
    /// The state word, then what a reader wants to know beside it:
    /// `shakedown after 12 cycles (a cycle without slip)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let cycles = self.cycles;
        let s = if cycles == 1 { "" } else { "s" };
        match &self.verdict {
            Verdict::Shakedown(proof) => {
                let how = match proof {
                    ShakedownProof::NoSlipCycle => "a cycle without slip",
                    ShakedownProof::SafeState(_) => "a safe state",
                    ShakedownProof::Converged => "the 0.01 % rule",
                };
                write!(f, "shakedown after {cycles} cycle{s} ({how})")
            }
            Verdict::GrossSlip(GrossSlip { load, .. }) => {
                write!(f, "gross slip at {load} after {cycles} cycle{s}")
            }
            Verdict::Separation(Separation { load, theta, .. }) => write!(
                f,
                "separation at {load}, theta = {theta:.4}, after {cycles} cycle{s}"
            ),
            Verdict::NotConverged { .. } => {
                write!(f, "not converged after {cycles} cycle{s}")
            }
            _ => write!(f, "{} after {cycles} cycle{s}", self.state()),
        }
    }
}
