//! The paper's figures drawn with plotters ([`draw`]). The data behind
//! them come from [`crate::analysis`]:
//!
//! * Figs. 3, 6, 8, 9 are sweeps ([`crate::analysis::sweep`]): steady-state
//!   `W` with its state, against `lambda` or `phi`.
//! * Fig. 4 draws the memory measures ([`crate::analysis::memory`]).
//! * Figs. 5 and 7 draw slip maps ([`crate::analysis::slip_map`]).

pub mod draw;

use crate::analysis::limit::LimitError;
use crate::analysis::memory::MemoryError;
use crate::analysis::slip_map::SlipMapError;
use crate::stepping::StepError;

/// A figure that cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FigureError {
    #[error(transparent)]
    Step(#[from] StepError),
    #[error(transparent)]
    Limit(#[from] LimitError),
    #[error(transparent)]
    Memory(#[from] MemoryError),
    #[error(transparent)]
    SlipMap(#[from] SlipMapError),
    #[error("cannot draw {file}: {message}")]
    Draw { file: String, message: String },
    #[error("cannot write {file}: {message}")]
    Write { file: String, message: String },
}
