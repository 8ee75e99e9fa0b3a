//! The shakedown limit `lambda_2` by linear programming (model.md section 7).

use crate::params::{Cycle, Discretisation, Material};
use crate::path::Initial;

/// The limit analysis failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitError {
    #[error("the lambda_2 linear programme is not built yet")]
    Unavailable,
}

/// The optimal slip of the `lambda_2` problem as an initial condition.
pub fn optimal_initial(
    _material: &Material,
    _cycle: &Cycle,
    _disc: &Discretisation,
) -> Result<Initial, LimitError> {
    Err(LimitError::Unavailable)
}
