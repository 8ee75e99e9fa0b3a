//! Frictional shakedown of a shrink-fitted disc: the physics of Cwiekala,
//! Barber & Hills (see `shared/model.md`), a stepper that advances it one
//! increment at a time, batch drivers and a terminal explorer.
//!
//! Layout: [`params`] (inputs), [`contact`] (operators and the incremental
//! solver), [`path`] (transients and the cycle), [`stepper`] (one increment
//! at a time, with events), [`steady`] (convergence and classification),
//! [`sweep`] (batch runs), [`limit`] (`lambda_2` by linear programming),
//! [`preset`] (the paper's cases as TOML) and [`figure`] (their plots).

pub mod batch;
pub mod case;
pub mod contact;
pub mod figure;
pub mod limit;
pub mod params;
pub mod parse;
pub mod path;
pub mod preset;
pub mod steady;
pub mod stepper;
pub mod sweep;
pub mod tui;
pub mod verdict;

pub use contact::{Contact, ContactError, Operators, SlipDirection};
pub use params::{Cycle, Discretisation, LoadPoint, Loads, Material, ParamError, Plane};
pub use path::{Initial, PathError};
pub use steady::{Approach, Convergence, CycleRecord, SteadyState};
pub use stepper::{Event, Phase, Status, StepError, StepOptions, StepReport, Stepper, Summary};
pub use verdict::Trend;
