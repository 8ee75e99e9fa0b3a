//! The design frontier (docs/model.md section 10): on the left the highest
//! `lambda` at which a found path shakes down against its number of vertices
//! `K`, per family, beside `lambda_1`, the best of the paper's 25 transients
//! and `lambda_2`; on the right the best paths on the load plane, with the
//! initial stick diamond, the gross-slip lines and the paper's 25 turning
//! points.

use std::f64::consts::PI;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{
    font, legend, line_sample, padded, pi_label, s, Drawing, Pattern, GREY, LIGHT_GREY, PALETTE,
};
use crate::io::design::FrontierRecord;
use crate::model::path::Initial;
use crate::model::LoadPoint;

/// The frontier table of `design --frontier`, drawn.
pub struct DesignPlot<'a> {
    /// The rows of the table.
    pub rows: &'a [FrontierRecord],
    /// The cycle centre `A`.
    pub center: LoadPoint,
    /// The slope `psi` of the load line (the cycle of the best path is drawn
    /// for `phi = 0`).
    pub slope: f64,
    /// The plot title.
    pub title: String,
}

impl DesignPlot<'_> {
    fn reference(&self, name: &str) -> Option<&FrontierRecord> {
        self.rows
            .iter()
            .find(|r| r.row == "reference" && r.family == name)
    }

    fn family(&self, name: &str) -> Vec<&FrontierRecord> {
        self.rows
            .iter()
            .filter(|r| r.row == "frontier" && r.family == name)
            .collect()
    }

    fn best(&self, name: &str) -> Option<&FrontierRecord> {
        // The first (fewest vertices) of the highest: a larger K that only
        // pads the same path with vertices at A gains nothing.
        self.family(name)
            .into_iter()
            .reduce(|a, b| if b.lambda > a.lambda { b } else { a })
    }

    fn frontier<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let kmax = self
            .rows
            .iter()
            .filter_map(|r| r.vertices)
            .max()
            .unwrap_or(1)
            .max(2) as f64;
        let lambdas = self.rows.iter().map(|r| r.lambda);
        let (y0, y1) = padded(
            lambdas.clone().fold(f64::MAX, f64::min),
            lambdas.fold(f64::MIN, f64::max),
        );
        let mut chart = ChartBuilder::on(area)
            .caption("highest λ at which a found path shakes down", font(17.0))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(0.5..kmax + 0.5, y0..y1)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("vertices K of O → P1 → … → PK → A")
            .y_desc("λ")
            .x_labels(kmax as usize)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .axis_desc_style(font(17.0))
            .label_style(font(14.0))
            .draw()
            .map_err(s)?;
        for (k, (name, label)) in [
            ("lambda_2", "λ₂ (optimal slip, LP)"),
            ("best_of_25", "best of the paper's 25"),
            ("lambda_1", "λ₁ (all 25 shake down)"),
        ]
        .into_iter()
        .enumerate()
        {
            let Some(r) = self.reference(name) else {
                continue;
            };
            let style = GREY.stroke_width(1 + (k == 1) as u32);
            let pattern = [Pattern::Dashed, Pattern::Solid, Pattern::Dotted][k];
            pattern.draw(
                &mut chart,
                vec![(0.5, r.lambda), (kmax + 0.5, r.lambda)],
                style,
            )?;
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(s)?
                .label(format!("{label} = {:.4}", r.lambda))
                .legend(move |c| line_sample!(pattern, c, style));
        }
        for (k, (name, label)) in [("free", "free vertices"), ("decaying", "decaying zig-zag")]
            .into_iter()
            .enumerate()
        {
            let pts: Vec<(f64, f64)> = self
                .family(name)
                .iter()
                .filter_map(|r| Some((r.vertices? as f64, r.lambda)))
                .collect();
            if pts.is_empty() {
                continue;
            }
            let colour = PALETTE[k];
            let style = colour.stroke_width(2);
            chart
                .draw_series(LineSeries::new(pts.clone(), style))
                .map_err(s)?
                .label(label)
                .legend(move |c| {
                    EmptyElement::at(c)
                        + PathElement::new(vec![(-12, 0), (12, 0)], style)
                        + Circle::new((0, 0), 4, colour.filled())
                });
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                .map_err(s)?;
        }
        legend(&mut chart, SeriesLabelPosition::LowerRight)
    }

    fn plane<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let two_pi = 2.0 * PI;
        let xr = self
            .rows
            .iter()
            .flat_map(|r| r.path.iter().map(|p| p.x().abs()))
            .fold(two_pi, f64::max)
            * 1.05;
        let mut chart = ChartBuilder::on(area)
            .caption("the best paths on the load plane", font(17.0))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(-xr..xr, -1.1 * two_pi..1.1 * two_pi)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x (force)")
            .y_desc("y (torque)")
            .x_label_formatter(&|v| pi_label(&(v / PI)))
            .y_label_formatter(&|v| pi_label(&(v / PI)))
            .axis_desc_style(font(17.0))
            .label_style(font(13.0))
            .draw()
            .map_err(s)?;
        let diamond = vec![
            (two_pi, 0.0),
            (0.0, two_pi),
            (-two_pi, 0.0),
            (0.0, -two_pi),
            (two_pi, 0.0),
        ];
        chart
            .draw_series(std::iter::once(Polygon::new(
                diamond.clone(),
                LIGHT_GREY.mix(0.4).filled(),
            )))
            .map_err(s)?
            .label("initial stick |x| + |y| ≤ 2π")
            .legend(|c| {
                Rectangle::new(
                    [(c.0 - 8, c.1 - 5), (c.0 + 8, c.1 + 5)],
                    LIGHT_GREY.filled(),
                )
            });
        let gross = GREY.stroke_width(1);
        for y in [two_pi, -two_pi] {
            Pattern::Dashed.draw(&mut chart, vec![(-xr, y), (xr, y)], gross)?;
        }
        chart
            .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
            .map_err(s)?
            .label("gross slip |y| = 2π")
            .legend(move |c| line_sample!(Pattern::Dashed, c, gross));
        let a = (self.center.x(), self.center.y());
        let turning: Vec<(f64, f64)> = Initial::paper_set()
            .iter()
            .skip(1)
            .map(|i| {
                let p = i.waypoints_to(self.center)[1];
                (p.x(), p.y())
            })
            .collect();
        chart
            .draw_series(
                turning
                    .iter()
                    .map(|&p| Cross::new(p, 4, GREY.stroke_width(1))),
            )
            .map_err(s)?
            .label("the paper's 24 turning points (and OA)")
            .legend(|c| Cross::new(c, 4, GREY.stroke_width(1)));
        for (k, name) in ["free", "decaying"].into_iter().enumerate() {
            let Some(best) = self.best(name) else {
                continue;
            };
            let mut pts = vec![(0.0, 0.0)];
            pts.extend(best.path.iter().map(|p| (p.x(), p.y())));
            pts.push(a);
            let colour = PALETTE[k];
            let style = colour.stroke_width(2);
            chart
                .draw_series(LineSeries::new(pts.clone(), style))
                .map_err(s)?
                .label(format!(
                    "{name}, K = {}: shakes down at λ = {:.4}",
                    best.vertices.unwrap_or(0),
                    best.lambda
                ))
                .legend(move |c| {
                    EmptyElement::at(c) + PathElement::new(vec![(-12, 0), (12, 0)], style)
                });
            chart
                .draw_series(
                    pts[1..pts.len() - 1]
                        .iter()
                        .map(|&p| Circle::new(p, 3, colour.filled())),
                )
                .map_err(s)?;
        }
        // The steady cycle of the best path (phi = 0: a segment through A).
        if let Some(l) = self
            .rows
            .iter()
            .filter(|r| r.row == "frontier")
            .map(|r| r.lambda)
            .reduce(f64::max)
        {
            let n = (1.0 + self.slope * self.slope).sqrt();
            let (dx, dy) = (l / n, l * self.slope / n);
            let style = BLACK.stroke_width(3);
            chart
                .draw_series(LineSeries::new(
                    vec![(a.0 - dx, a.1 - dy), (a.0 + dx, a.1 + dy)],
                    style,
                ))
                .map_err(s)?
                .label(format!("the cycle at λ = {l:.4} (φ = 0)"))
                .legend(move |c| {
                    EmptyElement::at(c) + PathElement::new(vec![(-12, 0), (12, 0)], style)
                });
        }
        chart
            .draw_series([
                Circle::new((0.0, 0.0), 4, BLACK.filled()),
                Circle::new(a, 5, BLACK.filled()),
            ])
            .map_err(s)?;
        chart
            .draw_series([
                Text::new("O", (0.15, -0.5), font(15.0)),
                Text::new("A", (a.0 + 0.15, a.1 - 0.5), font(15.0)),
            ])
            .map_err(s)?;
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    }
}

impl Drawing for DesignPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (1500, 700)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let root = root.titled(&self.title, font(20.0)).map_err(s)?;
        let (left, right) = root.split_horizontally(700);
        self.frontier(&left)?;
        self.plane(&right)
    }
}
