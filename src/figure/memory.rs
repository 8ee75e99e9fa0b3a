//! The memory measures `R` and `r` against `lambda` (Fig. 4).

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{padded, readable, s, Figure, Frame, Key, Pattern, Pen, Sample, DARK_RED, GREY};
use crate::analysis::memory::{ratchetting_onset, MemoryPoint};

/// Points of one curve, `(lambda, value)`.
type Series = Vec<(f64, f64)>;

/// `R` and `r` against `lambda` (Fig. 4).
pub struct MemoryPlot<'a> {
    /// One point per `lambda`.
    pub points: &'a [MemoryPoint],
    /// Its style and title.
    pub frame: Frame,
    /// `lambda_2` to mark.
    pub limit: Option<f64>,
}

const R_LABEL: &str = "R = (max W − min W) / mean W  (eq. 17)";
const SMALL_R_LABEL: &str = "r: fraction slipped in OIA that stays stuck after A";

impl MemoryPlot<'_> {
    fn x_range(&self) -> (f64, f64) {
        let xs = self.points.iter().map(|p| p.load_factor);
        padded(
            xs.clone().fold(f64::MAX, f64::min),
            xs.fold(f64::MIN, f64::max),
        )
    }

    /// `lambda_2` and `lambda_3` where they fall inside the axis.
    fn marks(&self) -> Vec<(f64, &'static str)> {
        let (x0, x1) = self.x_range();
        [(self.limit, "λ₂"), (ratchetting_onset(self.points), "λ₃")]
            .into_iter()
            .filter_map(|(v, n)| v.filter(|v| *v > x0 && *v < x1).map(|v| (v, n)))
            .collect()
    }

    fn series(&self) -> (Series, Series) {
        let big_r = self
            .points
            .iter()
            .filter_map(|p| Some((p.load_factor, p.range?)))
            .collect();
        let small_r = self
            .points
            .iter()
            .filter(|p| p.shakedown == 0)
            .filter_map(|p| Some((p.load_factor, p.stuck_fraction?)))
            .collect();
        (big_r, small_r)
    }
}

impl Figure for MemoryPlot<'_> {
    fn frame(&self) -> &Frame {
        &self.frame
    }

    fn key(&self) -> Key {
        let (big_r, small_r) = self.series();
        let mut key = Key::default();
        if !big_r.is_empty() {
            key.push(Sample::Line(Pattern::Solid, BLACK, 1.5), R_LABEL);
        }
        if !small_r.is_empty() {
            key.push(Sample::Line(Pattern::Solid, DARK_RED, 1.5), SMALL_R_LABEL);
        }
        for (v, name) in self.marks() {
            key.push(
                Sample::Line(Pattern::Dashed, GREY, 1.0),
                format!("{name} = {}", readable(v)),
            );
        }
        key
    }

    fn plots_aspect(&self) -> f64 {
        self.frame.one_column_or(0.75, 0.55)
    }

    fn caption_tail(&self) -> String {
        let mut text = ". R, the spread of W over the transients (black, circles), and r, the fraction of the interface that slipped in OIA and stays stuck after A (red, triangles), against λ.".to_string();
        for (v, name) in self.marks() {
            text.push_str(&format!(" {name} = {}.", readable(v)));
        }
        text
    }

    fn draw_plots<DB: DrawingBackend>(
        &self,
        plots: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let (x0, x1) = self.x_range();
        let (big_r, small_r) = self.series();
        let ymax = big_r
            .iter()
            .chain(&small_r)
            .map(|p| p.1)
            .fold(0.0, f64::max)
            .max(0.1)
            * 1.05;
        let mut chart = pen
            .chart(plots)
            .build_cartesian_2d(x0..x1, 0.0..ymax)
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc("λ")
            .y_desc("R,  r")
            .draw()
            .map_err(s)?;
        let (r, black, red) = (pen.mark(0.8), pen.line(BLACK, 1.5), pen.line(DARK_RED, 1.5));
        chart
            .draw_series(LineSeries::new(big_r.clone(), black))
            .map_err(s)?;
        chart
            .draw_series(big_r.iter().map(|&p| Circle::new(p, r, BLACK.filled())))
            .map_err(s)?;
        chart
            .draw_series(LineSeries::new(small_r.clone(), red))
            .map_err(s)?;
        chart
            .draw_series(
                small_r
                    .iter()
                    .map(|&p| TriangleMarker::new(p, r + 1, DARK_RED.filled())),
            )
            .map_err(s)?;
        for (v, name) in self.marks() {
            Pattern::Dashed.draw(&mut chart, vec![(v, 0.0), (v, ymax)], pen.line(GREY, 1.0))?;
            chart
                .draw_series(std::iter::once(Text::new(
                    name,
                    (v + 0.01 * (x1 - x0), 0.55 * ymax),
                    pen.text(),
                )))
                .map_err(s)?;
        }
        Ok(())
    }
}
