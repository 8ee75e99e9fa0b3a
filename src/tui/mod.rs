//! The terminal explorer.

use crate::case::{Case, CaseParams};

/// The case the explorer opens on.
pub fn default_params() -> CaseParams {
    CaseParams {
        load_factor: 5.5,
        ..CaseParams::default()
    }
}

/// Errors of the terminal explorer.
#[derive(Debug, thiserror::Error)]
pub enum TuiError {
    #[error("the terminal explorer is being built")]
    Unavailable,
}

pub fn run(_case: Case) -> Result<(), TuiError> {
    Err(TuiError::Unavailable)
}
