//! What every figure shares: the bundled font, the [`Drawing`] trait and
//! the SVG + PNG writer, the paper's state markers (`Mark`), colours,
//! line patterns whose legend samples look like the lines, and the slip
//! direction names (model.md section 1.3).
//!
//! Text is laid out with the bundled DejaVu Sans (`assets/fonts`, under its
//! own permissive licence), so no system font library is needed.

use std::path::Path;
use std::sync::OnceLock;

use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{register_font, FontStyle};

pub(crate) use super::axes::{decades, padded, pi_label, pow10_label, readable, LinearAxis};
pub(crate) use super::marks::Mark;
use super::FigureError;
use crate::contact::SlipDirection;

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

/// Where a figure goes, which sets its size, fonts, line widths and the
/// resolution of its PNG (`--style`).
///
/// Everything is laid out in points (1/72 inch) at the figure's printed
/// size; the SVG is written at that size (96 px to the inch, as SVG's user
/// unit is), the PNG at 600 dpi for a journal (line art) or at 1920 x 1080
/// pixels for a slide.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FigureStyle {
    /// A one-column journal figure: 90 mm wide, 7.5 pt text, 600 dpi.
    Paper1Col,
    /// A two-column (full-width) journal figure: 190 mm wide, 8.5 pt
    /// text, 600 dpi.
    #[default]
    Paper2Col,
    /// A 16:9 slide: 1920 x 1080 pixels, 18 pt text, thick lines.
    Slide,
}

impl FigureStyle {
    /// What `--style` accepts.
    pub const ACCEPTS: &'static str = "paper-1col, paper-2col or slide";

    /// The name `--style` takes.
    pub fn name(self) -> &'static str {
        match self {
            FigureStyle::Paper1Col => "paper-1col",
            FigureStyle::Paper2Col => "paper-2col",
            FigureStyle::Slide => "slide",
        }
    }

    /// Width in points: 90 mm, 190 mm, or a 960 x 540 pt slide.
    pub fn width_pt(self) -> f64 {
        match self {
            FigureStyle::Paper1Col => 90.0 / 25.4 * 72.0,
            FigureStyle::Paper2Col => 190.0 / 25.4 * 72.0,
            FigureStyle::Slide => 960.0,
        }
    }

    /// Height in points of a figure of `aspect` (height / width): a slide
    /// is always 16:9.
    pub fn height_pt(self, aspect: f64) -> f64 {
        match self {
            FigureStyle::Slide => 540.0,
            _ => self.width_pt() * aspect,
        }
    }

    /// PNG pixels per point: 600 dpi for a journal's line art, 2 for a
    /// 1920 x 1080 slide.
    pub fn png_px_per_pt(self) -> f64 {
        match self {
            FigureStyle::Paper1Col | FigureStyle::Paper2Col => 600.0 / 72.0,
            FigureStyle::Slide => 2.0,
        }
    }

    /// Text (axis titles, key) in points.
    pub fn font_pt(self) -> f64 {
        match self {
            FigureStyle::Paper1Col => 7.5,
            FigureStyle::Paper2Col => 8.5,
            FigureStyle::Slide => 18.0,
        }
    }

    /// Tick labels in points.
    pub fn tick_pt(self) -> f64 {
        match self {
            FigureStyle::Paper1Col => 6.5,
            FigureStyle::Paper2Col => 7.5,
            FigureStyle::Slide => 16.0,
        }
    }

    /// Line width in points.
    pub fn line_pt(self) -> f64 {
        match self {
            FigureStyle::Paper1Col => 0.6,
            FigureStyle::Paper2Col => 0.75,
            FigureStyle::Slide => 1.6,
        }
    }

    /// Marker radius in points.
    pub fn mark_pt(self) -> f64 {
        match self {
            FigureStyle::Paper1Col => 1.9,
            FigureStyle::Paper2Col => 2.3,
            FigureStyle::Slide => 4.5,
        }
    }
}

impl std::str::FromStr for FigureStyle {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        match text.trim() {
            "paper-1col" => Ok(FigureStyle::Paper1Col),
            "paper-2col" => Ok(FigureStyle::Paper2Col),
            "slide" => Ok(FigureStyle::Slide),
            _ => Err(format!("expected {}", FigureStyle::ACCEPTS)),
        }
    }
}

/// Points to pixels for one backend: every length a figure draws goes
/// through it, so the SVG and the PNG are the same figure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pen {
    /// The figure's style.
    pub style: FigureStyle,
    /// Pixels per point.
    pub scale: f64,
}

impl Pen {
    /// `pt` points in pixels.
    pub fn px(&self, pt: f64) -> i32 {
        (pt * self.scale).round() as i32
    }
    /// `pt` points in pixels, at least one.
    pub fn upx(&self, pt: f64) -> u32 {
        self.px(pt).max(1) as u32
    }
    /// Text of `pt` points.
    pub fn font(&self, pt: f64) -> TextStyle<'static> {
        font(pt * self.scale)
    }
    /// The style's text (axis titles, key).
    pub fn text(&self) -> TextStyle<'static> {
        self.font(self.style.font_pt())
    }
    /// The style's tick labels.
    pub fn tick(&self) -> TextStyle<'static> {
        self.font(self.style.tick_pt())
    }
    /// A chart on `area` laid out as every figure's: small margins, room
    /// on the right for the last tick label, and label areas for the
    /// style's fonts (a caller may widen them).
    pub(crate) fn chart<'a, 'b, DB: DrawingBackend>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
    ) -> ChartBuilder<'a, 'b, DB> {
        let f = self.text_pt();
        let mut chart = ChartBuilder::on(area);
        chart
            .margin(self.px(0.8 * f))
            .margin_right(self.px(1.6 * f))
            .x_label_area_size(self.px(2.9 * f))
            .y_label_area_size(self.px(4.0 * f));
        chart
    }

    /// A chart's axes as every figure draws them: no grid lines, the
    /// style's fonts, thin black axis lines and short ticks; the caller
    /// adds its descriptions and labels, then draws.
    pub(crate) fn axes<'m, 'a, 'b, X: Ranged, Y: Ranged, DB: DrawingBackend>(
        &self,
        mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
    ) -> &'m mut MeshStyle<'a, 'b, X, Y, DB> {
        mesh.disable_mesh()
            .axis_desc_style(self.text())
            .label_style(self.tick())
            .axis_style(self.line(BLACK, 1.0))
            .set_all_tick_mark_size(self.px(0.35 * self.text_pt()))
    }
    /// The text size in points.
    pub fn text_pt(&self) -> f64 {
        self.style.font_pt()
    }
    /// A line `factor` times the style's width.
    pub fn line(&self, colour: RGBColor, factor: f64) -> ShapeStyle {
        colour.stroke_width(self.upx(self.style.line_pt() * factor))
    }
    /// A marker radius `factor` times the style's, in pixels.
    pub fn mark(&self, factor: f64) -> i32 {
        self.px(self.style.mark_pt() * factor).max(1)
    }
    /// The canvas of a figure of `aspect` (height / width), in pixels.
    pub fn size(&self, aspect: f64) -> (u32, u32) {
        (
            self.upx(self.style.width_pt()),
            self.upx(self.style.height_pt(aspect)),
        )
    }
}

/// What every figure has besides its data: where it goes, and the title
/// that starts its caption (drawn on it only with `show_title`).
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// The caption's first sentence, and the title drawn with `show_title`.
    pub title: String,
    /// Draw the title on the figure (for slides).
    pub show_title: bool,
    /// Where the figure goes.
    pub style: FigureStyle,
}

/// What each of this crate's figures supplies; its [`Drawing`] follows:
/// the key goes below the plots (never over the data), the height is the
/// plots' and the key's, and the caption starts with the title.
pub(crate) trait Figure {
    /// The style and title.
    fn frame(&self) -> &Frame;
    /// The key, listing only what the figure shows.
    fn key(&self) -> Key;
    /// Height over width of the plots above the key.
    fn plots_aspect(&self) -> f64;
    /// What the caption says after the title, from the punctuation that
    /// ends the title (`. (a) ...`).
    fn caption_tail(&self) -> String;
    /// Draw the plots on `plots`, the area above the key.
    fn draw_plots<DB: DrawingBackend>(
        &self,
        plots: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String>;
}

impl Frame {
    /// `one_column` in a journal column (`paper-1col`), else `wider`: a
    /// narrow figure needs its plots taller for their width.
    pub(crate) fn one_column_or(&self, one_column: f64, wider: f64) -> f64 {
        match self.style {
            FigureStyle::Paper1Col => one_column,
            _ => wider,
        }
    }
}

impl<F: Figure> Drawing for F {
    fn style(&self) -> FigureStyle {
        self.frame().style
    }

    fn aspect(&self) -> f64 {
        let frame = self.frame();
        self.key()
            .figure_aspect(frame.style, self.plots_aspect(), frame.show_title)
    }

    fn caption(&self) -> String {
        let title = self.frame().title.trim_end_matches('.');
        format!("{title}{}", self.caption_tail())
    }

    fn title(&self) -> Option<&str> {
        let frame = self.frame();
        frame.show_title.then_some(frame.title.as_str())
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let plots = self.key().draw_below(root, self.frame().style, pen)?;
        self.draw_plots(&plots, pen)
    }
}

/// A figure plotters can draw on any backend.
pub trait Drawing {
    /// Where the figure goes.
    fn style(&self) -> FigureStyle;
    /// Height over width on paper (a slide is always 16:9).
    fn aspect(&self) -> f64;
    /// The caption: what an in-figure title would say, written beside the
    /// figure (`NAME.caption.txt`), as journals want.
    fn caption(&self) -> String;
    /// The title drawn on the figure (`--title`, for slides); none by
    /// default.
    fn title(&self) -> Option<&str>;
    /// Draw the figure on `root` (already filled white, the title drawn).
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String>;
}

fn draw_err(file: &Path, message: impl std::fmt::Display) -> FigureError {
    FigureError::Draw {
        file: file.display().to_string(),
        message: message.to_string(),
    }
}

/// Draw `d` on `root` with `pen`: its title when it has one, then the
/// figure.
/// `text` with every control character replaced by a space.
pub(crate) fn printable(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

fn draw_on<D: Drawing, DB: DrawingBackend>(
    d: &D,
    root: &DrawingArea<DB, Shift>,
    pen: &Pen,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(s)?;
    match d.title() {
        Some(t) if !t.is_empty() => {
            // XML 1.0 has no place for control characters (plotters escapes
            // `<`, `>` and `&` but passes them through), so a title from a
            // preset or a flag would make an SVG that is not well-formed.
            let t = printable(t);
            let titled = root.titled(&t, pen.font(pen.text_pt() * 1.35)).map_err(s)?;
            d.draw(&titled, pen)
        }
        _ => d.draw(root, pen),
    }
}

/// Draw `d` into an SVG file (at its printed size) and a PNG file (at the
/// style's resolution).
///
/// # Errors
///
/// [`FigureError::Draw`] when the font cannot be loaded or a backend fails
/// (for example an unwritable path).
pub fn write_svg_png<D: Drawing>(d: &D, svg: &Path, png: &Path) -> Result<(), FigureError> {
    ensure_font()?;
    let style = d.style();
    {
        // SVG's user unit is the CSS pixel, 1/96 inch.
        let pen = Pen {
            style,
            scale: 96.0 / 72.0,
        };
        let root = SVGBackend::new(svg, pen.size(d.aspect())).into_drawing_area();
        draw_on(d, &root, &pen).map_err(|e| draw_err(svg, e))?;
        root.present().map_err(|e| draw_err(svg, e))?;
    }
    let pen = Pen {
        style,
        scale: style.png_px_per_pt(),
    };
    let root = BitMapBackend::new(png, pen.size(d.aspect())).into_drawing_area();
    draw_on(d, &root, &pen).map_err(|e| draw_err(png, e))?;
    root.present().map_err(|e| draw_err(png, e))?;
    Ok(())
}

pub(crate) fn font(size: f64) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

pub(crate) fn s<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
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

/// The marker of `$mark` at `$at`, in pixels of `$pen`: two circles, a
/// cross and an outline (transparent or empty parts, which every backend
/// skips, keep the element type the same).
macro_rules! glyph {
    ($mark:expr, $at:expr, $pen:expr, $small:expr) => {{
        let ([(r0, s0), (r1, s1), (r2, s2)], (path, s3)) = $mark.parts($pen, $small);
        EmptyElement::at($at)
            + Circle::new((0, 0), r0, s0)
            + Circle::new((0, 0), r1, s1)
            + Cross::new((0, 0), r2, s2)
            + PathElement::new(path, s3)
    }};
}
pub(crate) use glyph;

/// The marker of a run started from the optimal slip of the `lambda_2`
/// programme: a green diamond round the state's mark, open when the run
/// shakes down, with a green centre when it slips. It is drawn over the
/// state marks and is large enough that a mark at the same point shows
/// inside it.
macro_rules! optimal_glyph {
    ($slipping:expr, $at:expr, $pen:expr) => {{
        let pen: &$crate::figure::style::Pen = $pen;
        let colour = $crate::figure::style::OPTIMAL;
        let d = pen.mark(1.9);
        let c = if $slipping { pen.mark(0.35) } else { 0 };
        let edge = colour.stroke_width(pen.upx(pen.style.line_pt()));
        EmptyElement::at($at)
            + PathElement::new(vec![(0, -d), (d, 0), (0, d), (-d, 0), (0, -d)], edge)
            + Circle::new((0, 0), c, colour.filled())
    }};
}
pub(crate) use optimal_glyph;

/// One entry of a figure's key: what its sample shows.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Sample {
    /// A state mark.
    Mark(Mark, bool),
    /// The optimal slip's diamond (slipping or not).
    Optimal(bool),
    /// A line of a pattern, colour and width factor.
    Line(Pattern, RGBColor, f64),
    /// A vertical bar (the spread of W).
    Bar(RGBColor, f64),
    /// A filled swatch.
    Swatch(RGBColor),
    /// Three swatches, light to dark (a state shaded by `W`).
    Ramp([RGBColor; 3]),
    /// No sample: a line of text.
    Text,
}

/// A figure's key, drawn beside the plot (never over the data) and
/// listing only what the figure shows.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Key {
    pub(crate) entries: Vec<(Sample, String)>,
}

impl Key {
    pub(crate) fn push(&mut self, sample: Sample, label: impl Into<String>) {
        let label = label.into();
        if !self.entries.iter().any(|e| e.0 == sample && e.1 == label) {
            self.entries.push((sample, label));
        }
    }

    fn sample_w(pen: &Pen) -> i32 {
        pen.px(pen.text_pt() * 2.6)
    }

    fn row_h(pen: &Pen) -> i32 {
        pen.px(pen.text_pt() * 1.45)
    }

    /// A label's width in pixels: estimated from its length (DejaVu
    /// Sans averages about 0.5 em a character), so that the SVG and the
    /// PNG lay the key out alike and its height is known before drawing.
    fn label_w(pen: &Pen, label: &str) -> i32 {
        pen.px(pen.text_pt() * 0.5 * label.chars().count() as f64)
    }

    /// Columns, rows and column width of the key in `width` pixels.
    fn grid(&self, pen: &Pen, width: i32) -> (usize, usize, i32) {
        let widest = self
            .entries
            .iter()
            .map(|e| Self::label_w(pen, &e.1))
            .max()
            .unwrap_or(0);
        let col = Self::sample_w(pen) + pen.px(pen.text_pt() * 2.0) + widest;
        let cols = ((width / col.max(1)) as usize).clamp(1, self.entries.len().max(1));
        let rows = self.entries.len().div_ceil(cols);
        (cols, rows, width / cols as i32)
    }

    /// Height over width of a figure whose panels are `panel` of its width
    /// high, with this key below them and, when shown, a title above.
    pub(crate) fn figure_aspect(&self, style: FigureStyle, panel: f64, show_title: bool) -> f64 {
        let width = style.width_pt();
        let title = if show_title {
            2.0 * style.font_pt()
        } else {
            0.0
        };
        panel + (self.height_pt(style, width) + title) / width
    }

    /// The height in points the key needs in a figure `width_pt` wide.
    pub(crate) fn height_pt(&self, pen_style: FigureStyle, width_pt: f64) -> f64 {
        if self.entries.is_empty() {
            return 0.0;
        }
        // At the scale of a 720 dpi PNG, so the rounding is that of a
        // drawing.
        let pen = Pen {
            style: pen_style,
            scale: 10.0,
        };
        let (_, rows, _) = self.grid(&pen, (width_pt * 10.0) as i32);
        rows as f64 * pen.text_pt() * 1.45 + pen.text_pt() * 0.8
    }

    /// Draw the key below the plots of a `style` figure on `root`, and
    /// give back the area left above it for the plots: every figure puts
    /// its key there, never over the data.
    pub(crate) fn draw_below<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        style: FigureStyle,
        pen: &Pen,
    ) -> Result<DrawingArea<DB, Shift>, String> {
        let h = root.dim_in_pixel().1;
        let key_h = pen.px(self.height_pt(style, style.width_pt())) as u32;
        let (plots, key_area) = root.split_vertically(h.saturating_sub(key_h));
        self.draw(&key_area, pen)?;
        Ok(plots)
    }

    /// Draw the key in `area`, in columns, entries filled by rows.
    pub(crate) fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let width = area.dim_in_pixel().0 as i32;
        let (cols, _, col_w) = self.grid(pen, width);
        let sw = Self::sample_w(pen);
        let left = pen.px(pen.text_pt() * 0.8);
        for (k, (sample, label)) in self.entries.iter().enumerate() {
            let (row, col) = (k / cols, k % cols);
            let x = left + col as i32 * col_w;
            let y =
                pen.px(pen.text_pt() * 0.3) + row as i32 * Self::row_h(pen) + Self::row_h(pen) / 2;
            let at = (x + sw / 2, y);
            match sample {
                Sample::Mark(m, small) => area.draw(&glyph!(*m, at, pen, *small)),
                Sample::Optimal(slipping) => area.draw(&optimal_glyph!(*slipping, at, pen)),
                Sample::Line(pattern, colour, f) => {
                    let st = pen.line(*colour, *f);
                    let half = sw / 2;
                    let pieces: Vec<PathElement<(i32, i32)>> = pattern
                        .pieces()
                        .iter()
                        .map(|&(a, b)| {
                            PathElement::new(
                                vec![(at.0 + a * half / 14, y), (at.0 + b * half / 14, y)],
                                st,
                            )
                        })
                        .collect();
                    pieces.iter().try_for_each(|p| area.draw(p))
                }
                Sample::Bar(colour, f) => {
                    let h = pen.px(pen.text_pt() * 0.55);
                    area.draw(&PathElement::new(
                        vec![(at.0, y - h), (at.0, y + h)],
                        pen.line(*colour, *f),
                    ))
                }
                Sample::Swatch(colour) => {
                    let h = pen.px(pen.text_pt() * 0.45);
                    area.draw(&Rectangle::new(
                        [(at.0 - sw / 3, y - h), (at.0 + sw / 3, y + h)],
                        colour.filled(),
                    ))
                }
                Sample::Ramp(colours) => {
                    let h = pen.px(pen.text_pt() * 0.45);
                    let third = sw / 3;
                    colours.iter().enumerate().try_for_each(|(k, c)| {
                        let x0 = x + k as i32 * third;
                        area.draw(&Rectangle::new(
                            [(x0, y - h), (x0 + third, y + h)],
                            c.filled(),
                        ))
                    })
                }
                Sample::Text => Ok(()),
            }
            .map_err(s)?;
            let tx = if *sample == Sample::Text {
                x
            } else {
                x + sw + pen.px(pen.text_pt() * 0.5)
            };
            area.draw(&Text::new(
                label.clone(),
                (tx, y),
                pen.text().pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(s)?;
        }
        Ok(())
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
    fn titles_lose_their_control_characters() {
        assert_eq!(printable("a\u{7}b\nc <&>"), "a b c <&>");
    }

    #[test]
    fn axis_labels_read_as_a_journal_prints_them() {
        assert_eq!(pow10_label(&1e-5), "10⁻⁵");
        assert_eq!(pow10_label(&100.0), "10²");
        assert_eq!(pow10_label(&2e-5), "");
        let a = LinearAxis::fit(8.2e-4);
        assert_eq!(a.exponent, -4);
        assert!(a.top >= 8.2e-4 && a.top <= 1.0e-3, "{a:?}");
        assert_eq!(a.label(4e-4), "4");
        assert_eq!(a.title("W"), "W  (×10⁻⁴)");
        assert_eq!(LinearAxis::fit(0.5).exponent, 0);
        assert_eq!(readable(2.7662e-4), "2.77 × 10⁻⁴");
        assert_eq!(readable(5.1), "5.10");
        assert_eq!(decades(3e-6, 2e-4), (1e-6, 1e-3));
    }

    #[test]
    fn styles_parse_and_size() {
        for st in [
            FigureStyle::Paper1Col,
            FigureStyle::Paper2Col,
            FigureStyle::Slide,
        ] {
            assert_eq!(st.name().parse::<FigureStyle>(), Ok(st));
        }
        assert!("a4".parse::<FigureStyle>().is_err());
        let pen = Pen {
            style: FigureStyle::Paper1Col,
            scale: FigureStyle::Paper1Col.png_px_per_pt(),
        };
        // 90 mm at 600 dpi.
        assert_eq!(pen.size(0.75).0, (90.0 / 25.4 * 600.0_f64).round() as u32);
        let pen = Pen {
            style: FigureStyle::Slide,
            scale: FigureStyle::Slide.png_px_per_pt(),
        };
        assert_eq!(pen.size(1.3), (1920, 1080));
    }

    #[test]
    fn forward_is_the_papers_forward() {
        // model.md section 1.3: the paper's forward slip is dg < 0.
        let f = directions_forward_first()[0];
        assert!(f.sign() < 0.0);
        assert!(direction_label(f).starts_with("forward"));
    }
}
