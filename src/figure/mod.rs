//! The paper's figures, and the regime map, drawn with plotters to SVG and
//! PNG. The data behind them come from [`crate::analysis`]; this module
//! only draws:
//!
//! * [`style`]: where a figure goes ([`FigureStyle`]: a one- or
//!   two-column journal figure or a slide, in points), the font, the SVG +
//!   PNG writer, the key beside the plot, axis labels as journals print
//!   them, the paper's state markers, colours, line patterns and the
//!   slip-direction names;
//! * [`dissipation`]: Figs. 3, 6, 8, 9, sweeps ([`crate::analysis::sweep`])
//!   of steady-state `W` with its state against `lambda` or `phi`, with a
//!   log panel of the memory of the transient;
//! * [`memory`]: Fig. 4, the memory measures ([`crate::analysis::memory`]);
//! * [`slip_map`]: Figs. 5 and 7, slip maps ([`crate::analysis::slip_map`]);
//! * [`regime`]: the state over the `(lambda, phi)` plane with `lambda_2(phi)`
//!   ([`crate::analysis::regime`]);
//! * [`data`]: the points a sweep figure draws, read from the runs or back
//!   from a figure's CSV.

mod axes;
pub mod data;
pub mod design;
pub mod dissipation;
mod marks;
pub mod memory;
pub mod profile;
pub mod regime;
pub mod slip_map;
pub mod style;

pub use data::SweepPoint;
pub use dissipation::DissipationPlot;
pub use memory::MemoryPlot;
pub use profile::ProfilePlot;
pub use regime::RegimePlot;
pub use slip_map::{SlipMapPlot, TimeOrigin};
pub use style::{write_svg_png, Drawing, FigureStyle, Frame, Pen};

use crate::analysis::limit::LimitError;
use crate::analysis::memory::MemoryError;
use crate::analysis::slip_map::SlipMapError;
use crate::stepping::StepError;

/// A figure that cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FigureError {
    /// A run behind the figure failed numerically.
    #[error(transparent)]
    Step(#[from] StepError),
    /// The `lambda_2` linear programme (model.md section 7.3) failed.
    #[error(transparent)]
    Limit(#[from] LimitError),
    /// The memory measures `R` and `r` (model.md sections 7.1, 7.2) could
    /// not be computed.
    #[error(transparent)]
    Memory(#[from] MemoryError),
    /// The slip map of a steady cycle could not be computed.
    #[error(transparent)]
    SlipMap(#[from] SlipMapError),
    /// The figure could not be drawn: the bundled font could not be
    /// loaded, or a plotters backend failed (e.g. on an unwritable path).
    #[error("cannot draw {file}: {message}")]
    Draw {
        /// The file being drawn (or the font file).
        file: String,
        /// What went wrong.
        message: String,
    },
    /// A file of the figure could not be written.
    #[error("cannot write {file}: {message}")]
    Write {
        /// The file that could not be written.
        file: String,
        /// What went wrong.
        message: String,
    },
}
