//! The contact: residual-traction operators and the incremental frictional
//! solver. Knows nothing of paths, cycles or any user interface.

mod cache;
pub(crate) use cache::ResponseCache;
mod inverse;
mod kernels;
mod operators;
mod solver;
mod tolerances;

pub use operators::{FftScratch, Operators};
pub use solver::{
    Advanced, Contact, ContactEnd, ContactError, ContactEvent, ContactEventKind, Increment,
    SlipDirection, Solved, Trial,
};
