//! What a run of the stepper is asked ([`StepOptions`]) and how it fails
//! ([`StepError`]).

use serde::Serialize;

use super::steady::Convergence;
use crate::model::{ranges, LoadPoint, ParamError};

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

/// Options of the stepper, validated by [`StepOptionsBuilder::build`]
/// (in the manner of Clarabel's settings builder).
///
/// ```
/// use shakedown::stepping::StepOptions;
///
/// let options = StepOptions::builder().max_cycles(300).safe_state(false).build()?;
/// assert_eq!(options.convergence().max_cycles(), 300);
/// assert!(!options.convergence().safe_state());
/// assert_eq!(options.failure_bisections(), StepOptions::default().failure_bisections());
/// assert!(StepOptions::builder().max_cycles(0).build().is_err());
/// assert!(StepOptions::builder().tolerance(0.0).build().is_err());
/// # Ok::<(), shakedown::model::ParamError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepOptions {
    failure_bisections: usize,
    convergence: Convergence,
}

/// The default of [`StepOptions::failure_bisections`]: an increment is cut
/// down to about 1/4000 of its length before the stepper gives up.
const DEFAULT_FAILURE_BISECTIONS: usize = 12;

impl Default for StepOptions {
    fn default() -> Self {
        Self {
            failure_bisections: DEFAULT_FAILURE_BISECTIONS,
            convergence: Convergence::default(),
        }
    }
}

impl StepOptions {
    /// A builder at the defaults: set what differs, then
    /// [`StepOptionsBuilder::build`] checks.
    pub fn builder() -> StepOptionsBuilder {
        StepOptions::default().to_builder()
    }
    /// A builder holding these options, to change some of them.
    pub fn to_builder(self) -> StepOptionsBuilder {
        StepOptionsBuilder {
            failure_bisections: self.failure_bisections,
            tolerance: self.convergence.tolerance(),
            max_cycles: self.convergence.max_cycles(),
            safe_state: self.convergence.safe_state(),
        }
    }
    /// Bisections of an increment whose active set does not settle.
    pub fn failure_bisections(&self) -> usize {
        self.failure_bisections
    }
    /// When the run has reached its steady state: the 0.01 % rule on the
    /// dissipation `W` and the cycle cap (model.md section 6.1).
    pub fn convergence(&self) -> Convergence {
        self.convergence
    }
    /// These options with other convergence criteria (already checked by
    /// [`Convergence::new`]).
    pub fn with_convergence(self, convergence: Convergence) -> Self {
        Self {
            convergence,
            ..self
        }
    }
    /// These options with the safe-state search on or off (model.md
    /// section 6.4), which carries no invariant.
    pub fn with_safe_state(self, on: bool) -> Self {
        Self {
            convergence: self.convergence.with_safe_state(on),
            ..self
        }
    }
}

/// Named settings of [`StepOptions`], checked together by
/// [`StepOptionsBuilder::build`] against [`crate::model::ranges`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepOptionsBuilder {
    failure_bisections: usize,
    tolerance: f64,
    max_cycles: usize,
    safe_state: bool,
}

impl StepOptionsBuilder {
    /// Bisections of an increment whose active set does not settle
    /// ([`ranges::FAILURE_BISECTIONS`]).
    pub fn failure_bisections(mut self, bisections: usize) -> Self {
        self.failure_bisections = bisections;
        self
    }
    /// The relative change of `W` below which the run has settled
    /// ([`ranges::TOLERANCE`]; the paper's 0.01 % is `1e-4`).
    pub fn tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
    /// Cycles run at most before the run is reported not converged
    /// ([`ranges::MAX_CYCLES`]).
    pub fn max_cycles(mut self, max_cycles: usize) -> Self {
        self.max_cycles = max_cycles;
        self
    }
    /// Prove shakedown by a safe state before the first cycle without slip
    /// (model.md section 6.4).
    pub fn safe_state(mut self, on: bool) -> Self {
        self.safe_state = on;
        self
    }
    /// The checked options.
    ///
    /// # Errors
    ///
    /// The first setting out of its range, as a [`ParamError`] naming it.
    pub fn build(self) -> Result<StepOptions, ParamError> {
        Ok(StepOptions {
            failure_bisections: ranges::FAILURE_BISECTIONS.check(self.failure_bisections)?,
            convergence: Convergence::new(self.tolerance, self.max_cycles, self.safe_state)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_builder_checks_each_setting_against_its_range() {
        let b = ranges::FAILURE_BISECTIONS;
        let bisections = |k| StepOptions::builder().failure_bisections(k).build();
        assert_eq!(bisections(b.min).unwrap().failure_bisections(), b.min);
        assert_eq!(bisections(b.max).unwrap().failure_bisections(), b.max);
        assert!(matches!(
            bisections(b.max + 1),
            Err(ParamError::BadCount {
                name: "failure-bisections",
                ..
            })
        ));
        let m = ranges::MAX_CYCLES;
        assert!(StepOptions::builder()
            .max_cycles(m.max + 1)
            .build()
            .is_err());
        assert!(StepOptions::builder().tolerance(f64::NAN).build().is_err());
        assert_eq!(StepOptions::builder().build(), Ok(StepOptions::default()));
        let o = StepOptions::builder().max_cycles(7).build().unwrap();
        assert_eq!(o.to_builder().build(), Ok(o));
    }
}
