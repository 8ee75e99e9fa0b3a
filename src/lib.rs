//! Frictional shakedown of a shrink-fitted disc: the physics of Cwiekala,
//! Barber & Hills (see `docs/model.md`), a stepper that advances it one
//! increment at a time, analysis of steady states and sweeps, batch
//! input/output, and (behind features) figures and a terminal explorer.
//!
//! Layers, from the bottom up; each depends only on those above it in
//! this list:
//!
//! * [`model`]: material, load plane, cycle, discretisation, load paths;
//! * [`contact`]: residual-traction operators and the incremental
//!   frictional solver;
//! * [`stepping`]: the [`Stepper`], its events, slip zones and the one
//!   driver [`stepping::drive`];
//! * [`analysis`]: steady state and classification, cases, sweeps,
//!   `lambda_2`, the memory measures `R` and `r`, slip maps;
//! * [`io`]: parsing, presets, the batch machinery;
//! * `figure` (feature `plot`) and `tui` (feature `tui`) on top.

pub mod analysis;
pub mod contact;
#[cfg(feature = "plot")]
pub mod figure;
pub mod io;
pub mod model;
pub mod stepping;
#[cfg(feature = "tui")]
pub mod tui;

pub use analysis::steady::{Approach, Convergence, CycleRecord, SteadyState};
pub use contact::{Contact, ContactError, Operators, SlipDirection};
pub use model::PathError;
pub use model::{Cycle, Discretisation, Initial, LoadPoint, Loads, Material, ParamError, Plane};
pub use stepping::{Event, Phase, Status, StepError, StepOptions, StepReport, Stepper, Summary};
