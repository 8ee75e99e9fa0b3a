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
    font, glyph, legend, line_sample, optimal_glyph, padded, s, Drawing, Mark, Pattern, GREY,
    LIGHT_GREY, PALETTE, W_LABEL,
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
    /// each value of the other variable in its own colour and line pattern.
    pub lines: bool,
    /// The plot title.
    pub title: String,
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

    fn drawn(&self) -> Vec<Drawn<'_>> {
        self.points
            .iter()
            .filter_map(|p| {
                let state = p.state?;
                let mark = Mark::of(state, self.ratchetting);
                let w = if mark == Mark::Ended {
                    0.0
                } else {
                    p.dissipation
                };
                Some((self.x_of(p), w, mark, p))
            })
            .collect()
    }
}

impl Drawing for DissipationPlot<'_> {
    fn size(&self) -> (u32, u32) {
        if self.window().is_some() {
            (1000, 1160)
        } else {
            (1000, 660)
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let root = root.titled(&self.title, font(22.0)).map_err(s)?;
        match self.window() {
            None => self.linear(&root, None),
            Some(window) => {
                let (top, bottom) = root.split_vertically(560);
                self.linear(&top, Some(window))?;
                self.log_panel(&bottom, window)
            }
        }
    }
}

impl DissipationPlot<'_> {
    /// The paper's plot: `W` on a linear axis. `window` is shaded (the
    /// range the log panel enlarges).
    fn linear<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        window: Option<(f64, f64)>,
    ) -> Result<(), String> {
        let pts = self.drawn();
        let xs = self.points.iter().map(|p| self.x_of(p));
        let (x0, x1) = padded(
            xs.clone().fold(f64::MAX, f64::min),
            xs.fold(f64::MIN, f64::max),
        );
        let wmax = pts
            .iter()
            .map(|p| p.1)
            .filter(|w| w.is_finite())
            .fold(0.0, f64::max);
        // Against phi the points span the whole width: leave headroom for
        // the legend above them.
        let headroom = match (self.axis, self.lines) {
            (Axis::Lambda, _) => 1.08,
            (Axis::Phi, true) => 1.75,
            (Axis::Phi, false) => 1.5,
        };
        let y1 = if wmax > 0.0 { headroom * wmax } else { 1e-3 };
        // Enough decimals for two significant digits at the top of the axis.
        let decimals = ((-y1.log10()).ceil().max(0.0) as usize + 1).min(12);
        let caption = if window.is_some() {
            "(a) linear axis, as in the paper"
        } else {
            ""
        };
        let mut chart = ChartBuilder::on(area)
            .caption(caption, font(16.0))
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

        if let Some((a, b)) = window {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(a.max(x0), 0.0), (b.min(x1), y1)],
                    RGBColor(240, 240, 240).filled(),
                )))
                .map_err(s)?
                .label("range enlarged in (b)")
                .legend(|(x, y)| {
                    Rectangle::new(
                        [(x - 12, y - 6), (x + 12, y + 6)],
                        RGBColor(225, 225, 225).filled(),
                    )
                });
        }

        if self.lines {
            self.draw_lines(&mut chart, &pts)?;
        }
        self.draw_limit(&mut chart, 0.0, y1, (x0, x1), 0.5 * y1)?;
        self.draw_marks(&mut chart, &pts, |_| true)?;
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    }

    /// One line per value of the other variable and initial path, each
    /// value in its own colour and pattern; the lines are drawn before the
    /// (smaller) marks so they show between them.
    fn draw_lines<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        pts: &[Drawn<'_>],
    ) -> Result<(), String> {
        let mut others: Vec<f64> = self.points.iter().map(|p| self.other_of(p)).collect();
        others.sort_by(f64::total_cmp);
        others.dedup();
        for (k, other) in others.iter().enumerate() {
            let colour = PALETTE[k % PALETTE.len()];
            let pattern = Pattern::ALL[k % Pattern::ALL.len()];
            let style = colour.stroke_width(2);
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
                pattern.draw(chart, line, style)?;
            }
            let name = match self.axis {
                Axis::Lambda => format!("φ = {:.4} π", other / PI),
                Axis::Phi => format!("λ = {other}"),
            };
            // An empty series carries the legend entry, drawn as the line is.
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(s)?
                .label(name)
                .legend(move |c| line_sample!(pattern, c, style));
        }
        Ok(())
    }

    /// `lambda_2` as a dashed vertical line, with a dashed legend sample.
    fn draw_limit<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        y0: f64,
        y1: f64,
        (x0, x1): (f64, f64),
        label_y: f64,
    ) -> Result<(), String> {
        let (Some(l2), Axis::Lambda) = (self.limit, self.axis) else {
            return Ok(());
        };
        if l2 <= x0 || l2 >= x1 {
            return Ok(());
        }
        let style = BLACK.stroke_width(1);
        Pattern::Dashed.draw(chart, vec![(l2, y0), (l2, y1)], style)?;
        chart
            .draw_series(std::iter::once(Text::new(
                "λ₂",
                (l2 + 0.008 * (x1 - x0), label_y),
                font(18.0),
            )))
            .map_err(s)?
            .label(format!("λ₂ = {l2:.4} (linear programme)"))
            .legend(move |c| line_sample!(Pattern::Dashed, c, style));
        Ok(())
    }

    /// The state marks (the optimal-slip runs as green diamonds), each
    /// kind with its legend entry.
    fn draw_marks<'a, DB: DrawingBackend + 'a, CT: CoordTranslate<From = (f64, f64)>>(
        &self,
        chart: &mut ChartContext<'a, DB, CT>,
        pts: &[Drawn<'_>],
        keep: impl Fn(&Drawn<'_>) -> bool,
    ) -> Result<(), String> {
        // The optimal-slip runs first, as diamonds a little larger than the
        // state marks, so that where every run has the same W (ratchetting)
        // the transients' marks sit inside them and both show. Runs that
        // end or do not converge keep the state's mark.
        let diamond =
            |p: &Drawn<'_>| p.3.is_optimal() && !matches!(p.2, Mark::Ended | Mark::NotConverged);
        for slipping in [false, true] {
            let at: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| diamond(p) && keep(p))
                .filter(|p| (p.2 != Mark::Shakedown) == slipping)
                .map(|p| (p.0, p.1))
                .collect();
            if at.is_empty() {
                continue;
            }
            let label = if slipping {
                "optimal slip of the λ₂ programme: slips"
            } else {
                "optimal slip of the λ₂ programme: shakedown"
            };
            chart
                .draw_series(at.into_iter().map(|c| optimal_glyph!(slipping, c)))
                .map_err(s)?
                .label(label)
                .legend(move |c| optimal_glyph!(slipping, c));
        }
        let small = self.lines;
        for mark in Mark::ORDER {
            let at: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.2 == mark && !diamond(p) && keep(p))
                .map(|p| (p.0, p.1))
                .collect();
            if at.is_empty() {
                continue;
            }
            chart
                .draw_series(at.into_iter().map(|c| glyph!(mark, c, small)))
                .map_err(s)?
                .label(mark.label())
                .legend(move |c| glyph!(mark, c, small));
        }
        Ok(())
    }

    /// (b): `W` on a log axis over `window`, each `lambda`'s spread over the
    /// transients as a grey bar.
    fn log_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
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
        let (y0, y1) = (wmin / 2.0, wmax * 2.0);
        let mut chart = ChartBuilder::on(area)
            .caption(
                "(b) the memory: W on a log axis where the transients disagree (shakedown, W = 0, not shown)",
                font(16.0),
            )
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(90)
            .build_cartesian_2d(a..b, (y0..y1).log_scale())
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("λ")
            .y_desc(W_LABEL)
            .axis_desc_style(font(20.0))
            .label_style(font(14.0))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(s)?;

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
        let bar = LIGHT_GREY.stroke_width(5);
        chart
            .draw_series(
                bars.iter()
                    .map(|&(l, lo, hi)| PathElement::new(vec![(l, lo), (l, hi)], bar)),
            )
            .map_err(s)?
            .label("spread of W over the transients")
            .legend(move |(x, y)| PathElement::new(vec![(x, y - 7), (x, y + 7)], bar));

        self.draw_limit(&mut chart, y0, y1, (a, b), (y0 * y1).sqrt())?;
        if let Some((_, l3)) = memory_window(self.points) {
            if l3 > a && l3 < b {
                let style = GREY.stroke_width(2);
                Pattern::Dotted.draw(&mut chart, vec![(l3, y0), (l3, y1)], style)?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        "λ₃",
                        (l3 + 0.008 * (b - a), (y0 * y1).sqrt()),
                        font(18.0),
                    )))
                    .map_err(s)?
                    .label(format!(
                        "λ₃ = {l3}: from here every transient ratchets, same W"
                    ))
                    .legend(move |c| line_sample!(Pattern::Dotted, c, style));
            }
        }
        self.draw_marks(&mut chart, &pts, |_| true)?;
        legend(&mut chart, SeriesLabelPosition::LowerRight)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
