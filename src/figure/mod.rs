//! The paper's figures, and the regime map, drawn with plotters to SVG and
//! PNG. The data behind them come from [`crate::analysis`]; this module
//! only draws:
//!
//! * [`style`]: the font, the SVG + PNG writer, the paper's state markers,
//!   colours, line patterns and the slip-direction names;
//! * [`dissipation`]: Figs. 3, 6, 8, 9, sweeps ([`crate::analysis::sweep`])
//!   of steady-state `W` with its state against `lambda` or `phi`, with a
//!   log panel of the memory of the transient;
//! * [`memory`]: Fig. 4, the memory measures ([`crate::analysis::memory`]);
//! * [`slip_map`]: Figs. 5 and 7, slip maps ([`crate::analysis::slip_map`]);
//! * [`regime`]: the state over the `(lambda, phi)` plane with `lambda_2(phi)`
//!   ([`crate::analysis::regime`]);
//! * [`data`]: the points a sweep figure draws, read from the runs or back
//!   from a figure's CSV.

pub mod data;
pub mod dissipation;
pub mod memory;
pub mod regime;
pub mod slip_map;
pub mod style;

pub use data::SweepPoint;
pub use dissipation::DissipationPlot;
pub use memory::MemoryPlot;
pub use regime::RegimePlot;
pub use slip_map::{SlipMapPlot, TimeOrigin};
pub use style::{write_svg_png, Drawing};

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
