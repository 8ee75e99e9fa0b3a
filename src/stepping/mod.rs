//! Stepping: advances the contact one load increment at a time along an
//! initial transient and then the steady cycle, and reports what happened as
//! events. Every consumer (the TUI, `run`, `sweep`, `figure`) goes through
//! the one [`Stepper`] and the one driver [`drive`].

mod driver;
mod options;
mod outcome;
mod report;
pub mod safe_state;
pub mod steady;
mod stepper;
pub mod verdict;
mod zones;

pub use driver::{drive, Control, Driven, Goal, Observer, Silent};
pub use options::{StepError, StepOptions, StepOptionsBuilder};
pub use outcome::{GrossSlip, Level, Outcome, Separation, ShakedownProof, Verdict};
pub use report::{AtCenter, Event, Phase, Status, StepReport};
pub use safe_state::Certificate;
pub use stepper::{operators, Stepper};
pub use verdict::Trend;
pub use zones::{slip_zones, zone_changes, SlipZone, ZoneChange};
