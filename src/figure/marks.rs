//! The paper's state markers: which mark each steady state gets, in what
//! order they are drawn (so that none hides another where runs coincide),
//! and how each is drawn in points.

use plotters::prelude::*;

use super::style::{Pen, AMBER, DARK_BLUE, DARK_RED, GREY};
use crate::io::preset::RatchettingMarkers;
use crate::stepping::steady::SteadyState;

/// How one point is marked, in the paper's conventions: shakedown a black
/// circle, cyclic slip a red dot, ratchetting a red dot with a blue edge
/// (Fig. 3) or a blue circle, with a red dot when non-monotonic (Fig. 8).
/// The runs that end (gross slip, separation) and the runs that failed
/// each have their own mark, drawn at `W = 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mark {
    Shakedown,
    CyclicSlip,
    Ratchetting,
    Monotonic,
    NonMonotonic,
    GrossSlip,
    Separation,
    NotConverged,
    Failed,
}

/// The brown of separation.
pub(crate) const BROWN: RGBColor = RGBColor(140, 85, 20);
/// The magenta of a run that failed numerically.
pub(crate) const MAGENTA: RGBColor = RGBColor(170, 0, 140);

impl Mark {
    /// The marks in drawing (and key) order: the open rings first, the
    /// filled dots after, so a dot is never hidden under a ring where
    /// runs of two states share a point.
    pub(crate) const ORDER: [Mark; 9] = [
        Mark::Shakedown,
        Mark::Monotonic,
        Mark::NonMonotonic,
        Mark::Ratchetting,
        Mark::CyclicSlip,
        Mark::NotConverged,
        Mark::GrossSlip,
        Mark::Separation,
        Mark::Failed,
    ];

    /// The mark of a run in `state` (`None`: it failed numerically).
    pub(crate) fn of(state: Option<SteadyState>, style: RatchettingMarkers) -> Mark {
        match state {
            None => Mark::Failed,
            Some(SteadyState::Shakedown) => Mark::Shakedown,
            Some(SteadyState::CyclicSlip) => Mark::CyclicSlip,
            Some(SteadyState::RatchettingMonotonic | SteadyState::RatchettingNonMonotonic)
                if style == RatchettingMarkers::Edge =>
            {
                Mark::Ratchetting
            }
            Some(SteadyState::RatchettingMonotonic) => Mark::Monotonic,
            Some(SteadyState::RatchettingNonMonotonic) => Mark::NonMonotonic,
            Some(SteadyState::GrossSlip) => Mark::GrossSlip,
            Some(SteadyState::Separation) => Mark::Separation,
            Some(SteadyState::NotConverged) => Mark::NotConverged,
        }
    }

    /// Whether the run has no steady `W` (drawn at 0).
    pub(crate) fn at_zero(self) -> bool {
        matches!(self, Mark::GrossSlip | Mark::Separation | Mark::Failed)
    }

    pub(crate) fn label(self) -> &'static str {
        match self {
            Mark::Shakedown => "shakedown",
            Mark::CyclicSlip => "cyclic slip",
            Mark::Ratchetting => "ratchetting",
            Mark::Monotonic => "monotonic ratchetting",
            Mark::NonMonotonic => "non-monotonic ratchetting",
            Mark::GrossSlip => "gross slip (drawn at 0)",
            Mark::Separation => "separation (drawn at 0)",
            Mark::NotConverged => "not converged (cycle cap)",
            Mark::Failed => "failed numerically (drawn at 0)",
        }
    }

    /// Two circles, a cross and a closed outline, drawn in this order:
    /// radius (or outline) and style each, in pixels of `pen`; unused
    /// parts are transparent or empty. `small` shrinks the marks (for
    /// plots with lines, so the lines show between them).
    #[allow(clippy::type_complexity)]
    pub(crate) fn parts(
        self,
        pen: &Pen,
        small: bool,
    ) -> ([(i32, ShapeStyle); 3], (Vec<(i32, i32)>, ShapeStyle)) {
        let none = (0, TRANSPARENT.into());
        let k = if small { 0.8 } else { 1.0 };
        let r = |f: f64| pen.mark(f * k);
        let w = |f: f64| pen.upx(pen.style.line_pt() * f);
        let no_path = (Vec::new(), TRANSPARENT.into());
        let circles = match self {
            Mark::Shakedown => [(r(1.0), BLACK.stroke_width(w(1.0))), none, none],
            Mark::CyclicSlip => [none, (r(0.6), DARK_RED.filled()), none],
            Mark::Ratchetting => [
                (r(0.75), DARK_RED.filled()),
                (r(1.1), DARK_BLUE.stroke_width(w(1.4))),
                none,
            ],
            Mark::Monotonic => [(r(1.0), DARK_BLUE.stroke_width(w(1.4))), none, none],
            Mark::NonMonotonic => [
                (r(1.0), DARK_BLUE.stroke_width(w(1.4))),
                (r(0.45), DARK_RED.filled()),
                none,
            ],
            Mark::GrossSlip => [none, none, (r(1.0), GREY.stroke_width(w(1.2)))],
            Mark::NotConverged => [
                (r(1.0), AMBER.stroke_width(w(1.4))),
                none,
                (r(0.5), AMBER.stroke_width(w(1.0))),
            ],
            Mark::Separation | Mark::Failed => [none, none, none],
        };
        let path = match self {
            // A triangle pointing down: the contact opens.
            Mark::Separation => {
                let d = r(1.2);
                (
                    vec![(-d, -d * 2 / 3), (d, -d * 2 / 3), (0, d), (-d, -d * 2 / 3)],
                    BROWN.stroke_width(w(1.2)),
                )
            }
            // A square.
            Mark::Failed => {
                let d = r(0.9);
                (
                    vec![(-d, -d), (d, -d), (d, d), (-d, d), (-d, -d)],
                    MAGENTA.stroke_width(w(1.2)),
                )
            }
            _ => no_path,
        };
        (circles, path)
    }

    /// The fill colour of this state on a map (the regime map): the
    /// marker's dominant colour, so the map reads like the paper's plots
    /// ([`crate::palette::map_colour`], which the terminal shares).
    pub(crate) fn map_colour(self) -> crate::palette::Rgb {
        let state = match self {
            Mark::Shakedown => Some(SteadyState::Shakedown),
            Mark::CyclicSlip => Some(SteadyState::CyclicSlip),
            Mark::Ratchetting | Mark::Monotonic => Some(SteadyState::RatchettingMonotonic),
            Mark::NonMonotonic => Some(SteadyState::RatchettingNonMonotonic),
            Mark::GrossSlip => Some(SteadyState::GrossSlip),
            Mark::Separation => Some(SteadyState::Separation),
            Mark::NotConverged => Some(SteadyState::NotConverged),
            Mark::Failed => None,
        };
        crate::palette::map_colour(state)
    }
}
