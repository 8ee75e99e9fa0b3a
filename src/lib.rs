//! Frictional shakedown of a shrink-fitted disc (Cwiekala, Barber & Hills,
//! *Frictional shakedown of a coupled continuous contact*).
//!
//! A disc is shrink-fitted into a hole in a plate of the same material; a radial
//! force and a torque vary periodically, and Coulomb friction acts at the
//! interface. Because slip changes the contact pressure (normal-tangential
//! coupling), the steady state (shakedown, cyclic slip, monotonic or
//! non-monotonic ratchetting, gross slip, separation) and the energy dissipated
//! per cycle depend on the loading history before the cycle. This crate steps
//! the interface through a history, one load increment at a time, runs it to
//! its steady state, classifies it, and sweeps load factor, phase and initial
//! transient; it also computes the shakedown limit `lambda_2` by linear
//! programming. The equations, conventions and numerical method are in
//! `docs/model.md` in the repository; section numbers quoted in the docs
//! ("model.md section 3") refer to it.
//!
//! # Glossary
//!
//! | paper | meaning | in the code |
//! |---|---|---|
//! | λ | load factor, eq. (12) | `load_factor` |
//! | φ | phase of the torque against the force | `phase` |
//! | ψ | slope of the load line, eq. (13) | `slope` |
//! | (χP̃₀/f, T̃₀/f) = A | centre of the cycle | `center` |
//! | (χP̃/f, T̃/f) | a point of the load plane (Fig. 2) | `LoadPoint` (`x`, `y`) |
//! | P̃, T̃ | scaled force and torque, eq. (3) | `Loads { radial, torque }` |
//! | f | friction coefficient | `friction` |
//! | ν | Poisson's ratio | `poisson` |
//! | plane strain / stress | | `plane` (`Plane`) |
//! | κ, χ | Kolosov's constant; eq. (4) | `kappa`, `chi` (with `alpha`, `beta`) |
//! | h | locked-in slip, plate minus disc | `slip` = g ∝ −h (model.md §1.2) |
//! | p, q | contact pressure and shear, scaled by p₀ | `pressure`, `shear` |
//! | forward / backward slip | Figs. 5 and 7 | `SlipDirection` (model.md §1.3) |
//! | W̃ | dissipation per cycle, eq. (16) | `dissipation` |
//! | — | rigid rotation, mean of g; its change per cycle | `rotation`, `rotation_per_cycle` |
//! | steady-state modes | shakedown, cyclic slip, ratchetting, … | `SteadyState` |
//! | OA, OIA | initial transients (Fig. 2) | `Initial` (`initial`) |
//! | N | interface nodes | `nodes` |
//! | — | increments per cycle | `steps` (`Discretisation::steps_per_cycle`) |
//! | 0.01 % | convergence of W̃ | `Convergence::tolerance` |
//! | R | relative range of W̃, eq. (17) | `range` |
//! | r | fraction that stays stuck after A (Fig. 4) | `stuck_fraction` |
//! | λ₂ | shakedown limit (linear programme) | `shakedown_limit` → `Limit::load_factor` |
//! | optimal slip | initial condition of the λ₂ problem | `optimal_initial`, initial path `optimal` |
//!
//! # Modules
//!
//! * [`model`]: material and its constants, the load plane, the cycle of
//!   eq. (11) or any closed polyline, the discretisation, the initial transients and the `A -> C`
//!   entry. Everything is validated on construction.
//! * [`contact`]: the operators `H` and `|D|`, the reduced solver with its
//!   factorisation reuse, and one increment of the frictional problem.
//! * [`stepping`]: the stepper (one increment at a time, with events: slip
//!   set changes, advancing stick, slip zones appearing, splitting, merging,
//!   vanishing, gross slip, separation) and the one driver, `drive`, which runs
//!   a case to its steady state and calls an observer on every increment and
//!   event (an observer can stop the run).
//! * [`analysis`]: the steady state and its classification (`Outcome`),
//!   sweeps over λ, φ and transients, λ₂ and the optimal initial slip, the
//!   memory measures R and r, and slip maps.
//! * [`io`]: parsing of numbers and angles, presets, the one CSV codec, and
//!   batch runs (ordered output, shards, resume, merge).
//! * `figure` (feature `plot`): the paper's figures as SVG/PNG.
//! * `tui` (feature `tui`): the terminal explorer.
//! * `palette` (with `plot` or `tui`): the paper's state colours, which the
//!   figures and the terminal share.
//!
//! With `default-features = false` the crate is the headless physics and
//! analysis only. Dependencies point one way: the front ends (`cli`, `figure`,
//! `tui`) use `io` and `analysis`, which use `stepping`, `contact` and `model`.
//!
//! # Example
//!
//! ```
//! use shakedown::analysis::case::{Case, CaseParams};
//!
//! // Fig. 3's material and cycle, well inside the shakedown range, on a
//! // coarse grid so that the example runs quickly.
//! let params = CaseParams { load_factor: 3.5, nodes: 32, steps: 200, ..CaseParams::default() };
//! let case = Case::from_params(&params).unwrap();
//! let outcome = case.stepper().run_to_steady().unwrap();
//! assert_eq!(outcome.state(), shakedown::SteadyState::Shakedown);
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod contact;
#[cfg(feature = "plot")]
pub mod figure;
pub mod io;
pub mod model;
#[cfg(any(feature = "plot", feature = "tui"))]
pub mod palette;
pub mod stepping;
#[cfg(feature = "tui")]
pub mod tui;

pub use analysis::case::{Case, CaseBuilder, CaseError};
pub use contact::{Advanced, Contact, ContactEnd, ContactError, Operators, SlipDirection};
pub use model::PathError;
pub use model::{
    Cycle, Discretisation, Initial, LoadPoint, Loads, Material, ParamError, Plane, Polyline, Shape,
};
pub use stepping::steady::{Approach, Convergence, CycleRecord, SteadyState};
pub use stepping::Trend;
pub use stepping::{
    Event, Outcome, Phase, Status, StepError, StepOptions, StepReport, Stepper, Verdict,
};

/// What a script needs: `use shakedown::prelude::*;`.
pub mod prelude {
    pub use crate::analysis::case::{Case, CaseBuilder, CaseError};
    pub use crate::analysis::limit::Limit;
    pub use crate::analysis::sweep::{Row, SweepLists, SweepSpec};
    pub use crate::io::cycle::{inline_cycle, read_cycle_file};
    pub use crate::model::{Cycle, Initial, LoadPoint, Material, Plane, Polyline, Shape};
    pub use crate::stepping::steady::{Approach, SteadyState};
    pub use crate::stepping::{GrossSlip, Outcome, Separation, ShakedownProof, Verdict};
}
