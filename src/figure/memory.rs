//! The memory measures `R` and `r` against `lambda` (Fig. 4).

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{font, legend, line_sample, padded, s, Drawing, Pattern, DARK_RED, GREY};
use crate::analysis::memory::{ratchetting_onset, MemoryPoint};

/// `R` and `r` against `lambda` (Fig. 4).
pub struct MemoryPlot<'a> {
    /// One point per `lambda`.
    pub points: &'a [MemoryPoint],
    /// The plot title.
    pub title: String,
    /// `lambda_2` to mark.
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
            .legend(move |c| {
                EmptyElement::at(c)
                    + PathElement::new(vec![(-12, 0), (12, 0)], black)
                    + Circle::new((0, 0), 3, BLACK.filled())
            });
        chart
            .draw_series(big_r.iter().map(|&p| Circle::new(p, 3, BLACK.filled())))
            .map_err(s)?;
        let red = DARK_RED.stroke_width(2);
        chart
            .draw_series(LineSeries::new(small_r.clone(), red))
            .map_err(s)?
            .label("r: fraction slipped in OIA that stays stuck after A")
            .legend(move |c| {
                EmptyElement::at(c)
                    + PathElement::new(vec![(-12, 0), (12, 0)], red)
                    + TriangleMarker::new((0, 0), 4, DARK_RED.filled())
            });
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
            let style = GREY.stroke_width(1);
            Pattern::Dashed.draw(&mut chart, vec![(v, 0.0), (v, ymax)], style)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("{name} = {v:.3}"),
                    (v + 0.01 * (x1 - x0), 0.55 * ymax),
                    font(15.0),
                )))
                .map_err(s)?
                .label(format!("{name} = {v:.3}"))
                .legend(move |c| line_sample!(Pattern::Dashed, c, style));
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}
