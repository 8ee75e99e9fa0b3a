//! What a run of the stepper is asked ([`StepOptions`]) and how it fails
//! ([`StepError`]).

use serde::Serialize;

use super::steady::Convergence;
use crate::model::LoadPoint;

/// A numerical failure of the stepper. Physical end states (gross slip,
/// separation) are not errors: they are outcomes.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// The active set of an increment did not settle (model.md section 3.3,
    /// robustness), even after bisecting the increment
    /// [`StepOptions::failure_bisections`] times: a numerical failure, kept
    /// apart from the physical outcomes.
    #[error(
        "the active set did not settle at load point {load} ({phase}), even with the increment bisected {bisections} times"
    )]
    NotSettled {
        /// The load point `(x, y)` of the load plane where the active set
        /// failed to settle.
        load: LoadPoint,
        /// Where on the path it happened, in words (transient segment or
        /// cycle, and increment, both 1-based).
        phase: String,
        /// Bisections tried, [`StepOptions::failure_bisections`].
        bisections: usize,
    },
    /// The stepper was given [`Initial::Optimal`], whose slip comes from the
    /// `lambda_2` linear programme: resolve it first with
    /// [`crate::analysis::limit::optimal_initial`] (or build the run
    /// through [`crate::analysis::case::Case`]).
    #[error("initial path 'optimal' was not resolved to a slip distribution")]
    UnresolvedOptimal,
    /// A parameter of the run is out of range.
    #[error(transparent)]
    Param(#[from] crate::model::ParamError),
}

/// Options of the stepper.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepOptions {
    /// Bisections of an increment whose active set does not settle.
    pub failure_bisections: usize,
    /// When the run has reached its steady state: the 0.01 % rule on the
    /// dissipation `W` and the cycle cap (model.md section 6.1).
    pub convergence: Convergence,
}

impl Default for StepOptions {
    fn default() -> Self {
        Self {
            failure_bisections: 12,
            convergence: Convergence::default(),
        }
    }
}
