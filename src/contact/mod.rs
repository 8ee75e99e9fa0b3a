//! The contact: residual-traction operators and the incremental frictional
//! solver. Knows nothing of paths, cycles or any user interface.

mod operators;
mod reduced;
mod solver;

pub use operators::Operators;
pub use solver::{Contact, ContactError, SlipDirection, Trial};
