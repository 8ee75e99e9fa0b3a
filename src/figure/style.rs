//! What every figure shares: the bundled font, the [`Drawing`] trait and
//! the SVG + PNG writer, the paper's state markers (`Mark`), colours,
//! line patterns whose legend samples look like the lines, and the slip
//! direction names (model.md section 1.3).
//!
//! Text is laid out with the bundled DejaVu Sans (`assets/fonts`, under its
//! own permissive licence), so no system font library is needed.

use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use super::FigureError;
use crate::contact::SlipDirection;
use crate::io::preset::RatchettingMarkers;
use crate::stepping::steady::SteadyState;

static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Register the bundled font once; plotters needs it to lay out labels,
/// even for SVG.
fn ensure_font() -> Result<(), FigureError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| register_font(FAMILY, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok {
        Ok(())
    } else {
        Err(FigureError::Draw {
            file: "assets/fonts/DejaVuSans.ttf".into(),
            message: "the bundled font could not be read".into(),
        })
    }
}

/// A figure plotters can draw on any backend.
pub trait Drawing {
    /// Canvas size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draw the figure on `root` (already filled white).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

fn draw_err(file: &Path, message: impl std::fmt::Display) -> FigureError {
    FigureError::Draw {
        file: file.display().to_string(),
        message: message.to_string(),
    }
}

/// Draw `d` into an SVG file and a PNG file.
///
/// # Errors
///
/// [`FigureError::Draw`] when the font cannot be loaded or a backend fails
/// (for example an unwritable path).
pub fn write_svg_png<D: Drawing>(d: &D, svg: &Path, png: &Path) -> Result<(), FigureError> {
    ensure_font()?;
    {
        let root = SVGBackend::new(svg, d.size()).into_drawing_area();
        root.fill(&WHITE).map_err(|e| draw_err(svg, e))?;
        d.draw(&root).map_err(|e| draw_err(svg, e))?;
        root.present().map_err(|e| draw_err(svg, e))?;
    }
    let root = BitMapBackend::new(png, d.size()).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(png, e))?;
    d.draw(&root).map_err(|e| draw_err(png, e))?;
    root.present().map_err(|e| draw_err(png, e))?;
    Ok(())
}

pub(crate) fn font(size: f64) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

pub(crate) fn s<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// The legend box every plot uses, at `position`.
pub(crate) fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(font(14.0))
        .draw()
        .map_err(s)
}

/// The paper's normalised dissipation `W~` of eq. (16), spelled out
/// because the bitmap text renderer does not place combining accents.
pub(crate) const W_LABEL: &str = "Wμ / ((κ+1) p₀² a²)";

pub(crate) const GREY: RGBColor = RGBColor(120, 120, 120);
pub(crate) const LIGHT_GREY: RGBColor = RGBColor(200, 200, 200);
pub(crate) const AMBER: RGBColor = RGBColor(230, 140, 0);
pub(crate) const DARK_RED: RGBColor = RGBColor(200, 0, 0);
pub(crate) const DARK_BLUE: RGBColor = RGBColor(0, 60, 220);
pub(crate) const GREEN_LINE: RGBColor = RGBColor(0, 140, 60);
/// The optimal slip of the `lambda_2` programme.
pub(crate) const OPTIMAL: RGBColor = RGBColor(0, 150, 70);

/// Series colours (Okabe-Ito, safe for colour-blind readers, dark enough
/// on white).
pub(crate) const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(0, 0, 0),
];

/// A line pattern. The legend sample of a series is drawn with the same
/// pattern ([`Pattern::draw`]), so the legend looks like the plot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pattern {
    Solid,
    Dashed,
    Dotted,
    LongDashed,
}

impl Pattern {
    /// The patterns in the order series use them.
    pub(crate) const ALL: [Pattern; 4] = [
        Pattern::Solid,
        Pattern::Dashed,
        Pattern::Dotted,
        Pattern::LongDashed,
    ];

    /// Draw `points` as one line of this pattern.
    pub(crate) fn draw<'a, DB, CT>(
        self,
        chart: &mut ChartContext<'a, DB, CT>,
        points: Vec<(f64, f64)>,
        style: ShapeStyle,
    ) -> Result<(), String>
    where
        DB: DrawingBackend + 'a,
        CT: CoordTranslate<From = (f64, f64)>,
    {
        let w = style.stroke_width as i32;
        match self {
            Pattern::Solid => chart
                .draw_series(LineSeries::new(points, style))
                .map(|_| ()),
            Pattern::Dashed => chart
                .draw_series(DashedLineSeries::new(points, 4 * w + 2, 3 * w, style))
                .map(|_| ()),
            Pattern::LongDashed => chart
                .draw_series(DashedLineSeries::new(points, 9 * w + 4, 3 * w, style))
                .map(|_| ()),
            Pattern::Dotted => chart
                .draw_series(DottedLineSeries::new(points, 0, 3 * w + 1, move |c| {
                    Circle::new(c, w.max(1), style.filled())
                }))
                .map(|_| ()),
        }
        .map_err(s)
    }

    /// The four pieces of this pattern's legend sample, as x offsets
    /// from its centre (the sample is 28 pixels long, like the lines'
    /// dashes at width 2).
    pub(crate) fn pieces(self) -> [(i32, i32); 4] {
        match self {
            Pattern::Solid => [(-14, -7), (-7, 0), (0, 7), (7, 14)],
            Pattern::Dashed => [(-14, -6), (-2, 6), (10, 14), (14, 14)],
            Pattern::Dotted => [(-13, -12), (-5, -4), (3, 4), (11, 12)],
            Pattern::LongDashed => [(-14, 0), (0, 0), (5, 14), (14, 14)],
        }
    }
}

/// A legend sample of `$pattern` ([`Pattern`]) in `$style` at `$at`: four
/// pieces of line, so a dashed line has a dashed sample.
macro_rules! line_sample {
    ($pattern:expr, $at:expr, $style:expr) => {{
        let [a, b, c, d] = $pattern.pieces();
        let st: ShapeStyle = $style;
        EmptyElement::at($at)
            + PathElement::new(vec![(a.0, 0), (a.1, 0)], st)
            + PathElement::new(vec![(b.0, 0), (b.1, 0)], st)
            + PathElement::new(vec![(c.0, 0), (c.1, 0)], st)
            + PathElement::new(vec![(d.0, 0), (d.1, 0)], st)
    }};
}
pub(crate) use line_sample;

/// How one point is marked, in the paper's conventions: shakedown a black
/// circle, cyclic slip a red dot, ratchetting a red dot with a blue edge
/// (Fig. 3) or a blue circle, with a red dot when non-monotonic (Fig. 8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mark {
    Shakedown,
    CyclicSlip,
    Ratchetting,
    Monotonic,
    NonMonotonic,
    Ended,
    NotConverged,
}

impl Mark {
    /// The marks in drawing (and legend) order.
    pub(crate) const ORDER: [Mark; 7] = [
        Mark::Shakedown,
        Mark::CyclicSlip,
        Mark::Ratchetting,
        Mark::Monotonic,
        Mark::NonMonotonic,
        Mark::NotConverged,
        Mark::Ended,
    ];

    pub(crate) fn of(state: SteadyState, style: RatchettingMarkers) -> Mark {
        match state {
            SteadyState::Shakedown => Mark::Shakedown,
            SteadyState::CyclicSlip => Mark::CyclicSlip,
            SteadyState::RatchettingMonotonic | SteadyState::RatchettingNonMonotonic
                if style == RatchettingMarkers::Edge =>
            {
                Mark::Ratchetting
            }
            SteadyState::RatchettingMonotonic => Mark::Monotonic,
            SteadyState::RatchettingNonMonotonic => Mark::NonMonotonic,
            SteadyState::GrossSlip | SteadyState::Separation => Mark::Ended,
            SteadyState::NotConverged => Mark::NotConverged,
        }
    }

    pub(crate) fn label(self) -> &'static str {
        match self {
            Mark::Shakedown => "shakedown",
            Mark::CyclicSlip => "cyclic slip",
            Mark::Ratchetting => "ratchetting",
            Mark::Monotonic => "monotonic ratchetting",
            Mark::NonMonotonic => "non-monotonic ratchetting",
            Mark::Ended => "gross slip / separation (drawn at 0)",
            Mark::NotConverged => "not converged (cycle cap)",
        }
    }

    /// Two circles and a cross, drawn in this order: radius and style each;
    /// unused parts are transparent. `scale` shrinks the radii (for plots
    /// with lines, so the lines show between the marks).
    pub(crate) fn parts(self, small: bool) -> [(i32, ShapeStyle); 3] {
        let none = (0, TRANSPARENT.into());
        let r = |v: i32| if small { (v * 3 + 2) / 4 } else { v };
        match self {
            Mark::Shakedown => [(r(4), BLACK.stroke_width(1)), none, none],
            Mark::CyclicSlip => [none, (r(3), DARK_RED.filled()), none],
            Mark::Ratchetting => [
                (r(4), DARK_RED.filled()),
                (r(5), DARK_BLUE.stroke_width(2)),
                none,
            ],
            Mark::Monotonic => [(r(4), DARK_BLUE.stroke_width(2)), none, none],
            Mark::NonMonotonic => [
                (r(4), DARK_BLUE.stroke_width(2)),
                (r(2), DARK_RED.filled()),
                none,
            ],
            Mark::Ended => [none, none, (r(4), GREY.stroke_width(1))],
            Mark::NotConverged => [
                (r(4), AMBER.stroke_width(2)),
                none,
                (r(2) + 1, AMBER.stroke_width(1)),
            ],
        }
    }

    /// The fill colour of this state on a map (the regime map): the
    /// marker's dominant colour, so the map reads like the paper's plots
    /// ([`crate::palette::map_colour`], which the terminal shares).
    pub(crate) fn map_colour(self) -> crate::palette::Rgb {
        let state = match self {
            Mark::Shakedown => SteadyState::Shakedown,
            Mark::CyclicSlip => SteadyState::CyclicSlip,
            Mark::Ratchetting | Mark::Monotonic => SteadyState::RatchettingMonotonic,
            Mark::NonMonotonic => SteadyState::RatchettingNonMonotonic,
            Mark::Ended => SteadyState::GrossSlip,
            Mark::NotConverged => SteadyState::NotConverged,
        };
        crate::palette::map_colour(Some(state))
    }
}

/// The marker of `$mark` at `$at`: two circles and a cross (transparent
/// parts, which every backend skips, keep the element type the same).
macro_rules! glyph {
    ($mark:expr, $at:expr, $small:expr) => {{
        let [(r0, s0), (r1, s1), (r2, s2)] = $mark.parts($small);
        EmptyElement::at($at)
            + Circle::new((0, 0), r0, s0)
            + Circle::new((0, 0), r1, s1)
            + Cross::new((0, 0), r2, s2)
    }};
}
pub(crate) use glyph;

/// The marker of a run started from the optimal slip of the `lambda_2`
/// programme: a green diamond, hollow when the run shakes down, filled
/// when it slips.
macro_rules! optimal_glyph {
    ($slipping:expr, $at:expr) => {{
        let fill: ShapeStyle = if $slipping {
            $crate::figure::style::OPTIMAL.filled()
        } else {
            WHITE.filled()
        };
        let edge = $crate::figure::style::OPTIMAL.stroke_width(2);
        let d = 6;
        EmptyElement::at($at)
            + Polygon::new(vec![(0, -d), (d, 0), (0, d), (-d, 0)], fill)
            + PathElement::new(vec![(0, -d), (d, 0), (0, d), (-d, 0), (0, -d)], edge)
    }};
}
pub(crate) use optimal_glyph;

/// `(lo, hi)` widened by 3 % each side (or to a unit interval when empty).
pub(crate) fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-9 {
        return (lo - 0.5, hi + 0.5);
    }
    let pad = 0.03 * (hi - lo);
    (lo - pad, hi + pad)
}

/// An axis label for a value in units of pi: `0`, `π/4`, `−3π/4`, `2π`,
/// or two decimals when it is not a multiple of `pi/4`.
pub(crate) fn pi_label(v: &f64) -> String {
    let k = (v * 4.0).round() as i64;
    if (v * 4.0 - k as f64).abs() > 1e-6 {
        return format!("{v:.2}π");
    }
    let coef = |n: i64| match n {
        1 => String::new(),
        -1 => "−".into(),
        n if n < 0 => format!("−{}", -n),
        n => n.to_string(),
    };
    match k {
        0 => "0".into(),
        _ if k % 4 == 0 => format!("{}π", coef(k / 4)),
        _ if k % 2 == 0 => format!("{}π/2", coef(k / 2)),
        _ => format!("{}π/4", coef(k)),
    }
}

/// The paper's name of a slip direction (model.md section 1.3): forward is
/// `dh > 0`, that is `dg < 0`. The match is on the code's variant names,
/// so it stays right when they are renamed.
pub(crate) fn direction_label(d: SlipDirection) -> &'static str {
    match d {
        SlipDirection::Forward => "forward slip (paper's sense: dh > 0, dg < 0)",
        SlipDirection::Backward => "backward slip (paper's sense: dh < 0, dg > 0)",
        SlipDirection::Stick => "stick",
    }
}

/// The colour of a slip direction on the slip maps: the paper's forward
/// (the ratchet direction) red, backward blue.
pub(crate) fn direction_colour(d: SlipDirection) -> RGBColor {
    match d {
        SlipDirection::Forward => DARK_RED,
        SlipDirection::Backward => DARK_BLUE,
        SlipDirection::Stick => WHITE,
    }
}

/// The slip directions in legend order: the paper's forward first.
pub(crate) fn directions_forward_first() -> [SlipDirection; 2] {
    let mut d = [SlipDirection::Forward, SlipDirection::Backward];
    d.sort_by_key(|d| !direction_label(*d).starts_with("forward"));
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pi_labels() {
        assert_eq!(pi_label(&0.0), "0");
        assert_eq!(pi_label(&1.0), "π");
        assert_eq!(pi_label(&-1.0), "−π");
        assert_eq!(pi_label(&0.5), "π/2");
        assert_eq!(pi_label(&-0.75), "−3π/4");
        assert_eq!(pi_label(&2.5), "5π/2");
        assert_eq!(pi_label(&0.3), "0.30π");
    }

    #[test]
    fn forward_is_the_papers_forward() {
        // model.md section 1.3: the paper's forward slip is dg < 0.
        let f = directions_forward_first()[0];
        assert!(f.sign() < 0.0);
        assert!(direction_label(f).starts_with("forward"));
    }
}
