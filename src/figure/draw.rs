//! Drawing the figures with plotters, to SVG and PNG, in the paper's
//! conventions: shakedown a black circle, cyclic slip a red dot,
//! ratchetting a red dot with a blue edge (Fig. 3) or a blue circle,
//! with a red dot when non-monotonic (Fig. 8).
//!
//! Text is laid out with the bundled DejaVu Sans (`assets/fonts`, under its
//! own permissive licence), so no system font library is needed.

use std::f64::consts::PI;
use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use super::FigureError;
use crate::analysis::memory::{ratchetting_onset, MemoryPoint};
use crate::analysis::slip_map::SlipMap;
use crate::analysis::steady::SteadyState;
use crate::analysis::sweep::Axis;
use crate::analysis::sweep::Row;
use crate::contact::SlipDirection;
use crate::io::preset::RatchettingMarkers;

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
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

fn draw_err(file: &Path, message: impl std::fmt::Display) -> FigureError {
    FigureError::Draw {
        file: file.display().to_string(),
        message: message.to_string(),
    }
}

/// Draw `d` into an SVG file and a PNG file.
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

fn font(size: f64) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

fn s<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// The legend box every plot uses, at `position`.
fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(font(14.0))
        .draw()
        .map_err(s)
}

/// The paper's normalised dissipation `W~` of eq. (16), spelled out
/// because the bitmap text renderer does not place combining accents.
const W_LABEL: &str = "Wμ / ((κ+1) p₀² a²)";

const GREY: RGBColor = RGBColor(120, 120, 120);
const AMBER: RGBColor = RGBColor(230, 140, 0);
const DARK_RED: RGBColor = RGBColor(200, 0, 0);
const DARK_BLUE: RGBColor = RGBColor(0, 60, 220);
const GREEN_LINE: RGBColor = RGBColor(0, 140, 60);

/// How one point is marked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mark {
    Shakedown,
    CyclicSlip,
    Ratchetting,
    Monotonic,
    NonMonotonic,
    Ended,
    NotConverged,
}

impl Mark {
    fn of(state: SteadyState, style: RatchettingMarkers) -> Mark {
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

    fn label(self) -> &'static str {
        match self {
            Mark::Shakedown => "shakedown",
            Mark::CyclicSlip => "cyclic slip",
            Mark::Ratchetting => "ratchetting",
            Mark::Monotonic => "monotonic ratchetting",
            Mark::NonMonotonic => "non-monotonic ratchetting",
            Mark::Ended => "gross slip / separation (drawn at 0)",
            Mark::NotConverged => "not converged",
        }
    }

    /// Two circles and a cross, drawn in this order: radius and style each;
    /// unused parts are transparent.
    fn parts(self) -> [(i32, ShapeStyle); 3] {
        let none = (0, TRANSPARENT.into());
        match self {
            Mark::Shakedown => [(4, BLACK.stroke_width(1)), none, none],
            Mark::CyclicSlip => [none, (3, DARK_RED.filled()), none],
            Mark::Ratchetting => [(4, DARK_RED.filled()), (5, DARK_BLUE.stroke_width(2)), none],
            Mark::Monotonic => [(4, DARK_BLUE.stroke_width(2)), none, none],
            Mark::NonMonotonic => [(4, DARK_BLUE.stroke_width(2)), (2, DARK_RED.filled()), none],
            Mark::Ended => [none, none, (4, GREY.stroke_width(1))],
            Mark::NotConverged => [(4, AMBER.stroke_width(1)), none, (2, AMBER.stroke_width(1))],
        }
    }
}

/// The marker of `$mark` at `$at`: two circles and a cross (transparent
/// parts, which every backend skips, keep the element type the same).
macro_rules! glyph {
    ($mark:expr, $at:expr) => {{
        let [(r0, s0), (r1, s1), (r2, s2)] = $mark.parts();
        EmptyElement::at($at)
            + Circle::new((0, 0), r0, s0)
            + Circle::new((0, 0), r1, s1)
            + Cross::new((0, 0), r2, s2)
    }};
}

/// `W` against `lambda` or `phi` with the steady state of every run
/// (Figs. 3, 6, 8, 9).
pub struct DissipationPlot<'a> {
    pub rows: &'a [Row],
    pub axis: Axis,
    pub ratchetting: RatchettingMarkers,
    /// Join the points of each series (same other variable and initial).
    pub lines: bool,
    pub title: String,
    /// `lambda_2` to mark (against `lambda` only).
    pub limit: Option<f64>,
}

impl DissipationPlot<'_> {
    fn x_of(&self, r: &Row) -> f64 {
        match self.axis {
            Axis::Lambda => r.job.load_factor,
            Axis::Phi => r.job.phase / PI,
        }
    }
    fn other_of(&self, r: &Row) -> f64 {
        match self.axis {
            Axis::Lambda => r.job.phase,
            Axis::Phi => r.job.load_factor,
        }
    }
}

fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-9 {
        return (lo - 0.5, hi + 0.5);
    }
    let pad = 0.03 * (hi - lo);
    (lo - pad, hi + pad)
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(23, 190, 207),
];

impl Drawing for DissipationPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (960, 640)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let pts: Vec<(f64, f64, Mark, &Row)> = self
            .rows
            .iter()
            .filter_map(|r| {
                let s = r.outcome.as_ref().ok()?;
                let mark = Mark::of(s.state, self.ratchetting);
                let w = if mark == Mark::Ended {
                    0.0
                } else {
                    s.dissipation
                };
                Some((self.x_of(r), w, mark, r))
            })
            .collect();
        let xs = self.rows.iter().map(|r| self.x_of(r));
        let (x0, x1) = padded(
            xs.clone().fold(f64::MAX, f64::min),
            xs.fold(f64::MIN, f64::max),
        );
        let wmax = pts.iter().map(|p| p.1).fold(0.0, f64::max);
        // Against phi the points span the whole width: leave headroom for
        // the legend above them.
        let headroom = match self.axis {
            Axis::Lambda => 1.08,
            Axis::Phi => 1.5,
        };
        let y1 = if wmax > 0.0 { headroom * wmax } else { 1e-3 };

        // Enough decimals for two significant digits at the top of the axis.
        let decimals = ((-y1.log10()).ceil().max(0.0) as usize + 1).min(12);
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, font(20.0))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(90)
            .build_cartesian_2d(x0..x1, 0.0..y1)
            .map_err(s)?;
        let x_desc = match self.axis {
            Axis::Lambda => "λ",
            Axis::Phi => "φ / π",
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(x_desc)
            .y_desc(W_LABEL)
            .axis_desc_style(font(20.0))
            .label_style(font(14.0))
            .y_label_formatter(&|v| format!("{v:.decimals$}"))
            .draw()
            .map_err(s)?;

        if self.lines {
            let mut others: Vec<f64> = self.rows.iter().map(|r| self.other_of(r)).collect();
            others.sort_by(f64::total_cmp);
            others.dedup();
            for (k, other) in others.iter().enumerate() {
                let colour = PALETTE[k % PALETTE.len()];
                let mut initials: Vec<&str> = Vec::new();
                for r in self.rows {
                    if self.other_of(r) == *other && !initials.contains(&r.initial.as_str()) {
                        initials.push(&r.initial);
                    }
                }
                for (i, initial) in initials.iter().enumerate() {
                    let mut line: Vec<(f64, f64)> = pts
                        .iter()
                        .filter(|p| self.other_of(p.3) == *other && p.3.initial == *initial)
                        .map(|p| (p.0, p.1))
                        .collect();
                    line.sort_by(|a, b| a.0.total_cmp(&b.0));
                    let series = chart
                        .draw_series(LineSeries::new(line, colour.stroke_width(1)))
                        .map_err(s)?;
                    if i == 0 {
                        let name = match self.axis {
                            Axis::Lambda => format!("φ = {:.4} π", other / PI),
                            Axis::Phi => format!("λ = {other}"),
                        };
                        series.label(name).legend(move |(x, y)| {
                            PathElement::new(vec![(x - 8, y), (x + 8, y)], colour.stroke_width(2))
                        });
                    }
                }
            }
        }

        if let (Some(l2), Axis::Lambda) = (self.limit, self.axis) {
            if l2 > x0 && l2 < x1 {
                let style = BLACK.stroke_width(1);
                chart
                    .draw_series(DashedLineSeries::new(
                        vec![(l2, 0.0), (l2, y1)],
                        6,
                        4,
                        style,
                    ))
                    .map_err(s)?
                    .label(format!("λ₂ = {l2:.4} (linear programme)"))
                    .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], style));
                chart
                    .draw_series(std::iter::once(Text::new(
                        "λ₂",
                        (l2 + 0.01 * (x1 - x0), 0.5 * y1),
                        font(18.0),
                    )))
                    .map_err(s)?;
            }
        }

        let order = [
            Mark::Shakedown,
            Mark::CyclicSlip,
            Mark::Ratchetting,
            Mark::Monotonic,
            Mark::NonMonotonic,
            Mark::NotConverged,
            Mark::Ended,
        ];
        for mark in order {
            let at: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.2 == mark)
                .map(|p| (p.0, p.1))
                .collect();
            if at.is_empty() {
                continue;
            }
            chart
                .draw_series(at.into_iter().map(|c| glyph!(mark, c)))
                .map_err(s)?
                .label(mark.label())
                .legend(move |c| glyph!(mark, c));
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    }
}

/// `R` and `r` against `lambda` (Fig. 4).
pub struct MemoryPlot<'a> {
    pub points: &'a [MemoryPoint],
    pub title: String,
    pub limit: Option<f64>,
}

impl Drawing for MemoryPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (960, 640)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let xs = self.points.iter().map(|p| p.load_factor);
        let (x0, x1) = padded(
            xs.clone().fold(f64::MAX, f64::min),
            xs.fold(f64::MIN, f64::max),
        );
        let big_r: Vec<(f64, f64)> = self
            .points
            .iter()
            .filter_map(|p| Some((p.load_factor, p.range?)))
            .collect();
        let small_r: Vec<(f64, f64)> = self
            .points
            .iter()
            .filter(|p| p.shakedown == 0)
            .filter_map(|p| Some((p.load_factor, p.stuck_fraction?)))
            .collect();
        let ymax = big_r
            .iter()
            .chain(&small_r)
            .map(|p| p.1)
            .fold(0.0, f64::max)
            .max(0.1)
            * 1.1;
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, font(20.0))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(x0..x1, 0.0..ymax)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("λ")
            .y_desc("R,  r")
            .axis_desc_style(font(20.0))
            .label_style(font(14.0))
            .draw()
            .map_err(s)?;
        let black = BLACK.stroke_width(2);
        chart
            .draw_series(LineSeries::new(big_r.clone(), black))
            .map_err(s)?
            .label("R = (max W − min W) / mean W  (eq. 17)")
            .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], black));
        chart
            .draw_series(big_r.iter().map(|&p| Circle::new(p, 3, BLACK.filled())))
            .map_err(s)?;
        let red = DARK_RED.stroke_width(2);
        chart
            .draw_series(LineSeries::new(small_r.clone(), red))
            .map_err(s)?
            .label("r: fraction slipped in OIA that stays stuck after A")
            .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], red));
        chart
            .draw_series(
                small_r
                    .iter()
                    .map(|&p| TriangleMarker::new(p, 4, DARK_RED.filled())),
            )
            .map_err(s)?;
        let marks = [(self.limit, "λ₂"), (ratchetting_onset(self.points), "λ₃")];
        for (value, name) in marks {
            let Some(v) = value else { continue };
            if v <= x0 || v >= x1 {
                continue;
            }
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(v, 0.0), (v, ymax)],
                    6,
                    4,
                    GREY.stroke_width(1),
                ))
                .map_err(s)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("{name} = {v:.3}"),
                    (v + 0.01 * (x1 - x0), 0.55 * ymax),
                    font(15.0),
                )))
                .map_err(s)?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// Slip zones over one steady cycle next to the load variation
/// (Figs. 5, 7).
pub struct SlipMapPlot<'a> {
    pub map: &'a SlipMap,
    pub title: String,
}

fn pi_label(v: &f64) -> String {
    let k = (v * 4.0).round() as i64;
    if (v * 4.0 - k as f64).abs() > 1e-6 {
        return format!("{v:.2}π");
    }
    match k {
        0 => "0".into(),
        4 => "π".into(),
        -4 => "−π".into(),
        _ if k % 4 == 0 => format!("{}π", k / 4),
        _ if k % 2 == 0 => format!(
            "{}π/2",
            if k / 2 == 1 {
                String::new()
            } else if k / 2 == -1 {
                "−".into()
            } else {
                (k / 2).to_string()
            }
        ),
        _ => format!(
            "{}π/4",
            if k == 1 {
                String::new()
            } else if k == -1 {
                "−".into()
            } else {
                k.to_string()
            }
        ),
    }
}

impl Drawing for SlipMapPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (1100, 640)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let map = self.map;
        let title = format!(
            "{}: {}, dissipation {:.4e} per cycle",
            self.title, map.summary.state, map.summary.dissipation
        );
        let root = root.titled(&title, font(20.0)).map_err(s)?;
        let (left, right) = root.split_horizontally(660);

        // (a) the slip map: theta across, omega t up, in units of pi.
        let mut chart = ChartBuilder::on(&left)
            .caption(
                "(a) slip over one steady cycle: forward (red), backward (blue)",
                font(16.0),
            )
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(-1.0..1.0, 0.0..2.0)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("θ")
            .y_desc("ωt")
            .axis_desc_style(font(20.0))
            .label_style(font(14.0))
            .x_labels(9)
            .y_labels(9)
            .x_label_formatter(&pi_label)
            .y_label_formatter(&pi_label)
            .draw()
            .map_err(s)?;
        let n = map.nodes;
        let half = 1.0 / n as f64;
        // Nodes in display order from theta = -pi up; runs of one direction
        // become one rectangle.
        let order: Vec<usize> = (0..n).map(|k| (k + n / 2) % n).collect();
        let mut cells = Vec::new();
        for r in &map.rows {
            let mut k = 0;
            while k < n {
                let d = r.directions[order[k]];
                let mut end = k + 1;
                while end < n && r.directions[order[end]] == d {
                    end += 1;
                }
                if d.is_slipping() {
                    let lo = map.theta(order[k]) / PI - half;
                    let hi = map.theta(order[end - 1]) / PI + half;
                    cells.push((lo, hi, r.t0 / PI, r.t1 / PI, d));
                }
                k = end;
            }
        }
        for (dir, colour) in [
            (SlipDirection::Forward, DARK_RED),
            (SlipDirection::Backward, DARK_BLUE),
        ] {
            chart
                .draw_series(
                    cells
                        .iter()
                        .filter(|c| c.4 == dir)
                        .map(|c| Rectangle::new([(c.0, c.2), (c.1, c.3)], colour.filled())),
                )
                .map_err(s)?;
        }

        // (b) the load variation against the same omega t.
        let mut load: Vec<(f64, f64, f64)> = vec![(0.0, map.start.x(), map.start.y())];
        load.extend(map.rows.iter().map(|r| (r.t1 / PI, r.load.x(), r.load.y())));
        let lo = load.iter().map(|p| p.1.min(p.2)).fold(f64::MAX, f64::min);
        let hi = load.iter().map(|p| p.1.max(p.2)).fold(f64::MIN, f64::max);
        let (lo, hi) = padded(lo, hi);
        let mut chart = ChartBuilder::on(&right)
            .caption("(b) load: χP/(f p₀ a) black, T/(f p₀ a²) green", font(16.0))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(52)
            .build_cartesian_2d(lo..hi, 0.0..2.0)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("load")
            .y_desc("ωt")
            .axis_desc_style(font(18.0))
            .label_style(font(14.0))
            .y_labels(9)
            .y_label_formatter(&pi_label)
            .draw()
            .map_err(s)?;
        // The series are named in the caption: a legend box would cover
        // the curves, which fill the panel.
        chart
            .draw_series(LineSeries::new(
                load.iter().map(|p| (p.1, p.0)),
                BLACK.stroke_width(2),
            ))
            .map_err(s)?;
        chart
            .draw_series(LineSeries::new(
                load.iter().map(|p| (p.2, p.0)),
                GREEN_LINE.stroke_width(2),
            ))
            .map_err(s)?;
        Ok(())
    }
}
