//! `W` against `lambda` or `phi` with the steady state of every run
//! (Figs. 3, 6, 8, 9). Against `lambda` with several transients, a second
//! panel shows `W` on a log axis over the range where the transients
//! disagree (`lambda_1` to `lambda_3`): the memory of the initial
//! transient, the paper's main result, which a linear axis hides.

use std::f64::consts::PI;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::data::SweepPoint;
use super::style::{
    decades, glyph, optimal_glyph, padded, pow10_label, readable, s, Figure, FigureStyle, Frame,
    Key, LinearAxis, Mark, Pattern, Pen, Sample, GREY, LIGHT_GREY, PALETTE, W_LABEL,
};
use crate::analysis::sweep::Axis;
use crate::io::preset::RatchettingMarkers;
use crate::stepping::steady::SteadyState;

/// `W` against `lambda` or `phi` (Figs. 3, 6, 8, 9).
pub struct DissipationPlot<'a> {
    /// The runs.
    pub points: &'a [SweepPoint],
    /// The horizontal axis.
    pub axis: Axis,
    /// How ratchetting is marked.
    pub ratchetting: RatchettingMarkers,
    /// Join the points of each series (same other variable and initial),
    /// each value of the other variable in its own colour and line pattern;
    /// a second panel then shows `W` on a log axis, so every series can be
    /// read.
    pub lines: bool,
    /// Its style and title.
    pub frame: Frame,
    /// `lambda_2` to mark (against `lambda` only).
    pub limit: Option<f64>,
}

/// A point as drawn: x, W (0 for a run that ended), its mark, the run.
type Drawn<'p> = (f64, f64, Mark, &'p SweepPoint);

/// The `lambda` range where the transients disagree: from the first
/// `lambda` at which some transient (other than the optimal slip) slips,
/// to `lambda_3`, from which every transient ratchets or ends. `None` when
/// there is a single transient or none slips.
pub fn memory_window(points: &[SweepPoint]) -> Option<(f64, f64)> {
    let transients: Vec<&SweepPoint> = points.iter().filter(|p| !p.is_optimal()).collect();
    let mut names: Vec<&str> = transients.iter().map(|p| p.initial.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    if names.len() < 2 {
        return None;
    }
    let mut lambdas: Vec<f64> = transients.iter().map(|p| p.load_factor).collect();
    lambdas.sort_by(f64::total_cmp);
    lambdas.dedup();
    let slips = |p: &SweepPoint| {
        !matches!(
            p.state,
            Some(SteadyState::Shakedown) | Some(SteadyState::NotConverged) | None
        ) && p.dissipation > 0.0
    };
    let ratchets = |p: &SweepPoint| {
        matches!(
            p.state,
            Some(
                SteadyState::RatchettingMonotonic
                    | SteadyState::RatchettingNonMonotonic
                    | SteadyState::GrossSlip
                    | SteadyState::Separation
            )
        )
    };
    let at = |l: f64| transients.iter().filter(move |p| p.load_factor == l);
    let first = *lambdas.iter().find(|&&l| at(l).any(|p| slips(p)))?;
    // lambda_3: the first lambda from which every later one all ratchets.
    let mut onset = None;
    for &l in lambdas.iter().rev() {
        if at(l).all(|p| ratchets(p)) {
            onset = Some(l);
        } else {
            break;
        }
    }
    let last = onset.unwrap_or(*lambdas.last()?);
    (last > first).then_some((first, last))
}

impl DissipationPlot<'_> {
    fn x_of(&self, p: &SweepPoint) -> f64 {
        match self.axis {
            Axis::Lambda => p.load_factor,
            Axis::Phi => p.phase / PI,
        }
    }
    fn other_of(&self, p: &SweepPoint) -> f64 {
        match self.axis {
            Axis::Lambda => p.phase,
            Axis::Phi => p.load_factor,
        }
    }

    /// The log panel's `lambda` range, when the plot has one.
    fn window(&self) -> Option<(f64, f64)> {
        if self.axis != Axis::Lambda || self.lines {
            return None;
        }
        let (a, b) = memory_window(self.points)?;
        // A little either side, so the edges of the spread show.
        let pad = 0.1 * (b - a).max(0.2);
        Some((a - pad, b + pad))
    }

    /// Whether there is a second panel: the memory window, or `W` of the
    /// lines on a log axis.
    fn two_panels(&self) -> bool {
        self.window().is_some() || (self.lines && self.drawn().iter().any(|p| p.1 > 0.0))
    }

    fn drawn(&self) -> Vec<Drawn<'_>> {
        self.points
            .iter()
            .map(|p| {
                let mark = Mark::of(p.state, self.ratchetting);
                let w = if mark.at_zero() { 0.0 } else { p.dissipation };
                (self.x_of(p), w, mark, p)
            })
            .collect()
    }

    fn x_range(&self) -> (f64, f64) {
        let xs = self.points.iter().map(|p| self.x_of(p));
        padded(
            xs.clone().fold(f64::MAX, f64::min),
            xs.fold(f64::MIN, f64::max),
        )
    }

    fn x_desc(&self) -> &'static str {
        match self.axis {
            Axis::Lambda => "λ",
            Axis::Phi => "φ / π",
        }
    }

    /// The values of the other variable, each a line of its own.
    fn others(&self) -> Vec<f64> {
        let mut others: Vec<f64> = self.points.iter().map(|p| self.other_of(p)).collect();
        others.sort_by(f64::total_cmp);
        others.dedup();
        others
    }

    fn line_name(&self, other: f64) -> String {
        match self.axis {
            Axis::Lambda => format!("φ = {} π", readable(other / PI)),
            Axis::Phi => format!("λ = {other}"),
        }
    }

    /// `lambda_2` when it is drawn.
    fn limit_drawn(&self) -> Option<f64> {
        let (x0, x1) = self.x_range();
        match (self.limit, self.axis) {
            (Some(l2), Axis::Lambda) if l2 > x0 && l2 < x1 => Some(l2),
            _ => None,
        }
    }

    /// `lambda_3` when the log panel draws it.
    fn lambda_3_drawn(&self) -> Option<f64> {
        let (a, b) = self.window()?;
        let (_, l3) = memory_window(self.points)?;
        (l3 > a && l3 < b).then_some(l3)
    }

    /// Whether `p` is drawn as an optimal-slip diamond: runs that end or
    /// do not converge keep their state's mark.
    fn diamond(&self, p: &Drawn<'_>) -> bool {
        p.3.is_optimal() && !(p.2.at_zero() || p.2 == Mark::NotConverged)
    }

    /// Height of a panel over the figure's width, on paper.
    fn panel_aspect(&self) -> f64 {
        match self.frame.style {
            // Two panels and the key in about 90 x 110 mm.
            FigureStyle::Paper1Col if self.two_panels() => 0.44,
            FigureStyle::Paper1Col => 0.72,
            _ => 0.5,
        }
    }
}

impl Figure for DissipationPlot<'_> {
    fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The key: exactly what the figure shows.
    fn key(&self) -> Key {
        let mut key = Key::default();
        let pts = self.drawn();
        // A journal column fits two columns of key only with short labels;
        // the caption says what they abbreviate.
        let short = self.frame.style == FigureStyle::Paper1Col;
        let text = |long: &'static str, brief: &'static str| if short { brief } else { long };
        if self.lines {
            for (k, other) in self.others().iter().enumerate() {
                key.push(
                    Sample::Line(
                        Pattern::ALL[k % Pattern::ALL.len()],
                        PALETTE[k % PALETTE.len()],
                        1.5,
                    ),
                    self.line_name(*other),
                );
            }
        }
        for slipping in [false, true] {
            if pts
                .iter()
                .any(|p| self.diamond(p) && (p.2 != Mark::Shakedown) == slipping)
            {
                let label = if slipping {
                    text("optimal slip (λ₂ programme): slips", "optimal slip: slips")
                } else {
                    text(
                        "optimal slip (λ₂ programme): shakedown",
                        "optimal slip: shakedown",
                    )
                };
                key.push(Sample::Optimal(slipping), label);
            }
        }
        for mark in Mark::ORDER {
            if pts.iter().any(|p| p.2 == mark && !self.diamond(p)) {
                let label = if short {
                    mark.short_label()
                } else {
                    mark.label()
                };
                key.push(Sample::Mark(mark, self.lines), label);
            }
        }
        if let Some(l2) = self.limit_drawn() {
            key.push(
                Sample::Line(Pattern::Dashed, BLACK, 1.0),
                format!(
                    "λ₂ = {} ({})",
                    readable(l2),
                    text("linear programme", "lin. prog.")
                ),
            );
        }
        if self.window().is_some() {
            key.push(
                Sample::Swatch(RGBColor(225, 225, 225)),
                "range enlarged in (b)",
            );
            key.push(
                Sample::Bar(LIGHT_GREY, 5.0),
                text("spread of W over the transients", "spread over transients"),
            );
        }
        if let Some(l3) = self.lambda_3_drawn() {
            key.push(
                Sample::Line(Pattern::Dotted, GREY, 2.0),
                format!(
                    "λ₃ = {l3}: {}",
                    text("every transient ratchets from here", "all ratchet")
                ),
            );
        }
        key
    }

    fn plots_aspect(&self) -> f64 {
        let panels = if self.two_panels() { 2.0 } else { 1.0 };
        panels * self.panel_aspect()
    }

    fn caption_tail(&self) -> String {
        let mut text = ".".to_string();
        if let Some((a, b)) = self.window() {
            text.push_str(&format!(
                " (a) W on a linear axis, as in the paper. (b) W on a log axis over λ = {} to {}, where the transients disagree; shakedown (W = 0) is not shown there.",
                readable(a),
                readable(b)
            ));
        } else if self.two_panels() {
            text.push_str(
                " (a) W on a linear axis, as in the paper. (b) The same on a log axis, so that every line can be read; W = 0 is not shown there.",
            );
        }
        if let Some(l2) = self.limit_drawn() {
            text.push_str(&format!(
                " The dashed line is the shakedown limit λ₂ = {} of the linear programme.",
                readable(l2)
            ));
        }
        if self.drawn().iter().any(|p| p.2.at_zero()) {
            text.push_str(" Runs that end (gross slip, separation) or fail have no steady W and are drawn at W = 0.");
        }
        text
    }

    fn draw_plots<DB: DrawingBackend>(
        &self,
        plots: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        if !self.two_panels() {
            return self.linear(plots, pen, None, false);
        }
        let (a, b) = if self.frame.style == FigureStyle::Slide {
            plots.split_horizontally(plots.dim_in_pixel().0 / 2)
        } else {
            let ph = plots.dim_in_pixel().1;
            plots.split_vertically(ph / 2)
        };
        match self.window() {
            Some(window) => {
                self.linear(&a, pen, Some(window), true)?;
                self.log_panel(&b, pen, window)
            }
            None => {
                self.linear(&a, pen, None, true)?;
                self.log_lines(&b, pen)
            }
        }
    }
}

impl DissipationPlot<'_> {
    /// A chart's frame: margins, label areas and panel letter in `pen`.
    fn frame<'a, DB: DrawingBackend>(
        area: &'a DrawingArea<DB, Shift>,
        pen: &Pen,
        letter: &str,
    ) -> ChartBuilder<'a, 'a, DB> {
        let f = pen.text_pt();
        let mut b = pen.chart(area);
        b.y_label_area_size(pen.px(4.6 * f));
        if !letter.is_empty() {
            b.caption(letter, pen.text());
        }
        b
    }

    /// The paper's plot: `W` on a linear axis, from 0 to just above the
    /// largest `W`. `window` is shaded (the range the log panel enlarges).
    fn linear<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pen: &Pen,
        window: Option<(f64, f64)>,
        lettered: bool,
    ) -> Result<(), String> {
        let pts = self.drawn();
        let (x0, x1) = self.x_range();
        let wmax = pts
            .iter()
            .map(|p| p.1)
            .filter(|w| w.is_finite())
            .fold(0.0, f64::max);
        let axis = LinearAxis::fit(wmax);
        let y1 = axis.top;
        let letter = if lettered { "(a)" } else { "" };
        let mut chart = Self::frame(area, pen, letter)
            .build_cartesian_2d(x0..x1, 0.0..y1)
            .map_err(s)?;
        let y_desc = axis.title(W_LABEL);
        pen.axes(&mut chart.configure_mesh())
            .x_desc(self.x_desc())
            .y_desc(y_desc)
            .y_labels(axis.ticks)
            .y_label_formatter(&|v| axis.label(*v))
            .draw()
            .map_err(s)?;

        if let Some((a, b)) = window {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(a.max(x0), 0.0), (b.min(x1), y1)],
                    RGBColor(236, 236, 236).filled(),
                )))
                .map_err(s)?;
        }
        if self.lines {
            self.draw_lines(&mut chart, pen, &pts, false)?;
        }
        if let Some(l2) = self.limit_drawn() {
            self.draw_limit(&mut chart, pen, l2, 0.0, y1, (x0, x1), 0.55 * y1)?;
        }
        self.draw_marks(&mut chart, pen, &pts)
    }

    /// One line per value of the other variable and initial path, each
    /// value in its own colour and pattern; the lines are drawn before the
    /// (smaller) marks so they show between them. On a log axis (`log`),
    /// each line is broken where `W` is 0.
    fn draw_lines<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        pen: &Pen,
        pts: &[Drawn<'_>],
        log: bool,
    ) -> Result<(), String> {
        for (k, other) in self.others().iter().enumerate() {
            let colour = PALETTE[k % PALETTE.len()];
            let pattern = Pattern::ALL[k % Pattern::ALL.len()];
            let style = pen.line(colour, 1.5);
            let mut initials: Vec<&str> = Vec::new();
            for p in self.points {
                if self.other_of(p) == *other && !initials.contains(&p.initial.as_str()) {
                    initials.push(&p.initial);
                }
            }
            for initial in &initials {
                let mut line: Vec<(f64, f64)> = pts
                    .iter()
                    .filter(|p| self.other_of(p.3) == *other && p.3.initial == *initial)
                    .filter(|p| p.1.is_finite())
                    .map(|p| (p.0, p.1))
                    .collect();
                line.sort_by(|a, b| a.0.total_cmp(&b.0));
                if log {
                    for piece in line.split(|p| p.1 <= 0.0) {
                        if piece.len() > 1 {
                            pattern.draw(chart, piece.to_vec(), style)?;
                        }
                    }
                } else {
                    pattern.draw(chart, line, style)?;
                }
            }
        }
        Ok(())
    }

    /// `lambda_2` as a dashed vertical line, named beside it.
    #[allow(clippy::too_many_arguments)]
    fn draw_limit<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        pen: &Pen,
        l2: f64,
        y0: f64,
        y1: f64,
        (x0, x1): (f64, f64),
        label_y: f64,
    ) -> Result<(), String> {
        Pattern::Dashed.draw(chart, vec![(l2, y0), (l2, y1)], pen.line(BLACK, 1.0))?;
        chart
            .draw_series(std::iter::once(Text::new(
                "λ₂",
                (l2 + 0.008 * (x1 - x0), label_y),
                pen.text(),
            )))
            .map_err(s)?;
        Ok(())
    }

    /// The state marks, rings first and dots after ([`Mark::ORDER`]), then
    /// the optimal-slip runs as open green diamonds round their marks, so
    /// that where runs coincide every state stays visible.
    fn draw_marks<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        pen: &Pen,
        pts: &[Drawn<'_>],
    ) -> Result<(), String> {
        let small = self.lines;
        for mark in Mark::ORDER {
            let at: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.2 == mark)
                .map(|p| (p.0, p.1))
                .collect();
            chart
                .draw_series(at.into_iter().map(|c| glyph!(mark, c, pen, small)))
                .map_err(s)?;
        }
        for slipping in [false, true] {
            let at: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| self.diamond(p))
                .filter(|p| (p.2 != Mark::Shakedown) == slipping)
                .map(|p| (p.0, p.1))
                .collect();
            chart
                .draw_series(at.into_iter().map(|c| optimal_glyph!(slipping, c, pen)))
                .map_err(s)?;
        }
        Ok(())
    }

    /// A log-`W` chart over `x0..x1` for the points `pts` (`W > 0`).
    fn log_chart<'a, DB: DrawingBackend>(
        area: &'a DrawingArea<DB, Shift>,
        pen: &Pen,
        (x0, x1): (f64, f64),
        (y0, y1): (f64, f64),
        x_desc: &str,
    ) -> Result<
        ChartContext<
            'a,
            DB,
            Cartesian2d<
                plotters::coord::types::RangedCoordf64,
                plotters::coord::combinators::LogCoord<f64>,
            >,
        >,
        String,
    > {
        let mut chart = Self::frame(area, pen, "(b)")
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc(x_desc)
            .y_desc(W_LABEL)
            .y_label_formatter(&pow10_label)
            .draw()
            .map_err(s)?;
        Ok(chart)
    }

    /// (b) of a plot with lines: the same lines with `W` on a log axis.
    fn log_lines<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let all = self.drawn();
        let wmax = all
            .iter()
            .map(|p| p.1)
            .filter(|w| w.is_finite())
            .fold(0.0, f64::max);
        let floor = (wmax * 1e-8).max(1e-14);
        // A point the log axis cannot show (W = 0: shakedown, or below the
        // floor) breaks its line there, so no line bridges the runs that
        // do not slip.
        let lines: Vec<Drawn<'_>> = all
            .iter()
            .cloned()
            .map(|mut p| {
                if p.1.is_finite() && p.1 < floor {
                    p.1 = 0.0;
                }
                p
            })
            .collect();
        let pts: Vec<Drawn<'_>> = all
            .into_iter()
            .filter(|p| p.1.is_finite() && p.1 >= floor)
            .collect();
        let wmin = pts.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        if pts.is_empty() {
            return Ok(());
        }
        let mut chart = Self::log_chart(
            area,
            pen,
            self.x_range(),
            decades(wmin, wmax),
            self.x_desc(),
        )?;
        self.draw_lines(&mut chart, pen, &lines, true)?;
        self.draw_marks(&mut chart, pen, &pts)
    }

    /// (b): `W` on a log axis over `window`, each `lambda`'s spread over the
    /// transients as a grey bar.
    fn log_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pen: &Pen,
        (a, b): (f64, f64),
    ) -> Result<(), String> {
        let inside = |p: &Drawn<'_>| p.0 >= a && p.0 <= b && p.1 > 0.0 && p.1.is_finite();
        let pts: Vec<Drawn<'_>> = self.drawn().into_iter().filter(inside).collect();
        let wmax = pts.iter().map(|p| p.1).fold(0.0, f64::max);
        // Tiny W (runs creeping to shakedown at the cycle cap) would
        // stretch the axis over decades that carry no information.
        let floor = (wmax * 1e-6).max(1e-12);
        let pts: Vec<Drawn<'_>> = pts.into_iter().filter(|p| p.1 >= floor).collect();
        let wmin = pts.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        if pts.is_empty() || wmax <= 0.0 {
            return Ok(());
        }
        let (y0, y1) = decades(wmin, wmax);
        let mut chart = Self::log_chart(area, pen, (a, b), (y0, y1), "λ")?;

        // The spread between the transients at each lambda.
        let mut lambdas: Vec<f64> = pts.iter().map(|p| p.0).collect();
        lambdas.sort_by(f64::total_cmp);
        lambdas.dedup();
        let bars: Vec<(f64, f64, f64)> = lambdas
            .iter()
            .filter_map(|&l| {
                let ws = pts
                    .iter()
                    .filter(|p| p.0 == l && !p.3.is_optimal())
                    .map(|p| p.1);
                let lo = ws.clone().fold(f64::MAX, f64::min);
                let hi = ws.fold(0.0, f64::max);
                (hi > lo).then_some((l, lo, hi))
            })
            .collect();
        let bar = pen.line(LIGHT_GREY, 5.0);
        chart
            .draw_series(
                bars.iter()
                    .map(|&(l, lo, hi)| PathElement::new(vec![(l, lo), (l, hi)], bar)),
            )
            .map_err(s)?;

        if let Some(l2) = self.limit_drawn().filter(|l| *l > a && *l < b) {
            self.draw_limit(&mut chart, pen, l2, y0, y1, (a, b), (y0 * y1).sqrt())?;
        }
        if let Some(l3) = self.lambda_3_drawn() {
            Pattern::Dotted.draw(&mut chart, vec![(l3, y0), (l3, y1)], pen.line(GREY, 2.0))?;
            chart
                .draw_series(std::iter::once(Text::new(
                    "λ₃",
                    (l3 + 0.008 * (b - a), (y0 * y1).sqrt()),
                    pen.text(),
                )))
                .map_err(s)?;
        }
        self.draw_marks(&mut chart, pen, &pts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::Drawing;

    fn p(l: f64, initial: &str, state: SteadyState, w: f64) -> SweepPoint {
        SweepPoint {
            load_factor: l,
            phase: 0.0,
            initial: initial.into(),
            state: Some(state),
            dissipation: w,
        }
    }

    #[test]
    fn window_runs_from_first_slip_to_lambda_3() {
        use SteadyState::*;
        let pts = vec![
            p(4.0, "OA", Shakedown, 0.0),
            p(4.0, "7,-7", Shakedown, 0.0),
            p(5.0, "OA", Shakedown, 0.0),
            p(5.0, "7,-7", CyclicSlip, 1e-3),
            p(6.0, "OA", CyclicSlip, 1e-2),
            p(6.0, "7,-7", RatchettingNonMonotonic, 2e-2),
            p(7.0, "OA", RatchettingNonMonotonic, 3e-2),
            p(7.0, "7,-7", RatchettingNonMonotonic, 3e-2),
            p(7.5, "OA", GrossSlip, 0.0),
            p(7.5, "7,-7", GrossSlip, 0.0),
            p(3.0, "optimal", CyclicSlip, 1.0),
        ];
        assert_eq!(memory_window(&pts), Some((5.0, 7.0)));
        assert_eq!(memory_window(&pts[..1]), None);
    }

    #[test]
    fn a_full_key_fits_a_journal_column() {
        use SteadyState::*;
        // Every entry fig3's key can have: both optimal diamonds, every
        // mark, lambda_2, the enlarged range, the spread and lambda_3.
        let mut pts = vec![
            p(4.0, "OA", Shakedown, 0.0),
            p(4.0, "7,-7", Shakedown, 0.0),
            p(4.0, "optimal", Shakedown, 0.0),
            p(5.0, "OA", CyclicSlip, 1e-4),
            p(5.0, "7,-7", NotConverged, 1e-3),
            p(5.0, "optimal", CyclicSlip, 1e-4),
            p(6.0, "OA", RatchettingMonotonic, 1e-2),
            p(6.0, "7,-7", Separation, 0.0),
            p(7.0, "OA", RatchettingNonMonotonic, 3e-2),
            p(7.0, "7,-7", RatchettingNonMonotonic, 3e-2),
            p(7.5, "OA", GrossSlip, 0.0),
            p(7.5, "7,-7", GrossSlip, 0.0),
        ];
        pts.push(SweepPoint {
            state: None,
            ..p(4.0, "3,7", Shakedown, 0.0)
        });
        let plot = |style, ratchetting| DissipationPlot {
            points: &pts,
            axis: Axis::Lambda,
            ratchetting,
            lines: false,
            frame: Frame {
                title: "Fig. 3".into(),
                show_title: false,
                style,
            },
            limit: Some(4.5),
        };
        let one = plot(FigureStyle::Paper1Col, RatchettingMarkers::Monotonicity);
        assert!(one.two_panels() && one.lambda_3_drawn().is_some());
        assert!(one.key().entries.len() >= 12, "{:?}", one.key());
        // At most about 90 x 110 mm.
        assert!(one.aspect() <= 110.0 / 90.0, "{}", one.aspect());
        // The two-column page keeps the full labels.
        let two = plot(FigureStyle::Paper2Col, RatchettingMarkers::Edge);
        assert!(two
            .key()
            .entries
            .iter()
            .any(|e| e.1.contains("linear programme")));
    }
}
