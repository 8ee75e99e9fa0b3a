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
    padded, pi_label, s, Figure, FigureStyle, Frame, Key, Pattern, Pen, Sample, GREY, LIGHT_GREY,
    PALETTE,
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
    /// Its style and title.
    pub frame: Frame,
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

    fn frontier<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
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
        let mut chart = pen
            .chart(area)
            .build_cartesian_2d(0.5..kmax + 0.5, y0..y1)
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc("vertices K of O → P1 → … → PK → A")
            .y_desc("λ")
            .x_labels(kmax as usize)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .draw()
            .map_err(s)?;
        for (k, (name, _)) in Self::REFS.into_iter().enumerate() {
            let Some(r) = self.reference(name) else {
                continue;
            };
            let style = pen.line(GREY, Self::REF_WIDTH[k]);
            let pattern = Self::REF_PATTERN[k];
            pattern.draw(
                &mut chart,
                vec![(0.5, r.lambda), (kmax + 0.5, r.lambda)],
                style,
            )?;
        }
        for (k, (name, _)) in Self::FAMILIES.into_iter().enumerate() {
            let pts: Vec<(f64, f64)> = self
                .family(name)
                .iter()
                .filter_map(|r| Some((r.vertices? as f64, r.lambda)))
                .collect();
            if pts.is_empty() {
                continue;
            }
            let colour = PALETTE[k];
            chart
                .draw_series(LineSeries::new(pts.clone(), pen.line(colour, 2.0)))
                .map_err(s)?;
            let r = pen.mark(1.0);
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, r, colour.filled())))
                .map_err(s)?;
        }
        Ok(())
    }

    fn plane<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let two_pi = 2.0 * PI;
        let xr = self
            .rows
            .iter()
            .flat_map(|r| r.path.iter().map(|p| p.x().abs()))
            .fold(two_pi, f64::max)
            * 1.05;
        let mut chart = pen
            .chart(area)
            // Coordinates in units of pi, so that the ticks fall on whole
            // multiples of pi and the gross-slip lines sit on a tick.
            .build_cartesian_2d(-xr / PI..xr / PI, -2.2..2.2)
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc("x (force)")
            .y_desc("y (torque)")
            .x_labels(2 * (xr / PI).floor() as usize + 1)
            .y_labels(5)
            .x_label_formatter(&pi_label)
            .y_label_formatter(&pi_label)
            .draw()
            .map_err(s)?;
        let diamond = vec![(2.0, 0.0), (0.0, 2.0), (-2.0, 0.0), (0.0, -2.0), (2.0, 0.0)];
        chart
            .draw_series(std::iter::once(Polygon::new(
                diamond.clone(),
                LIGHT_GREY.mix(0.4).filled(),
            )))
            .map_err(s)?;
        let gross = pen.line(GREY, 1.0);
        for y in [2.0, -2.0] {
            Pattern::Dashed.draw(&mut chart, vec![(-xr / PI, y), (xr / PI, y)], gross)?;
        }
        let a = (self.center.x() / PI, self.center.y() / PI);
        let turning: Vec<(f64, f64)> = Initial::paper_set()
            .iter()
            .skip(1)
            .map(|i| {
                let p = i.waypoints_to(self.center)[1];
                (p.x() / PI, p.y() / PI)
            })
            .collect();
        chart
            .draw_series(
                turning
                    .iter()
                    .map(|&p| Cross::new(p, pen.mark(1.0), pen.line(GREY, 1.0))),
            )
            .map_err(s)?;
        for (k, name) in ["free", "decaying"].into_iter().enumerate() {
            let Some(best) = self.best(name) else {
                continue;
            };
            let mut pts = vec![(0.0, 0.0)];
            pts.extend(best.path.iter().map(|p| (p.x() / PI, p.y() / PI)));
            pts.push(a);
            let colour = PALETTE[k];
            chart
                .draw_series(LineSeries::new(pts.clone(), pen.line(colour, 2.0)))
                .map_err(s)?;
            let r = pen.mark(0.8);
            chart
                .draw_series(
                    pts[1..pts.len() - 1]
                        .iter()
                        .map(|&p| Circle::new(p, r, colour.filled())),
                )
                .map_err(s)?;
        }
        // The steady cycle of the best path (phi = 0: a segment through A).
        if let Some(l) = self.best_lambda() {
            let n = (1.0 + self.slope * self.slope).sqrt();
            let (dx, dy) = (l / n / PI, l * self.slope / n / PI);
            chart
                .draw_series(LineSeries::new(
                    vec![(a.0 - dx, a.1 - dy), (a.0 + dx, a.1 + dy)],
                    pen.line(BLACK, 3.0),
                ))
                .map_err(s)?;
        }
        chart
            .draw_series([
                Circle::new((0.0, 0.0), pen.mark(1.0), BLACK.filled()),
                Circle::new(a, pen.mark(1.2), BLACK.filled()),
            ])
            .map_err(s)?;
        chart
            .draw_series([
                Text::new("O", (0.05, -0.16), pen.text()),
                Text::new("A", (a.0 + 0.05, a.1 - 0.16), pen.text()),
            ])
            .map_err(s)?;
        Ok(())
    }

    /// The references drawn on the left: name, key label, pattern, width.
    const REFS: [(&'static str, &'static str); 3] = [
        ("lambda_2", "λ₂ (optimal slip, LP)"),
        ("best_of_25", "best of the paper's 25"),
        ("lambda_1", "λ₁ (all 25 shake down)"),
    ];
    const REF_PATTERN: [Pattern; 3] = [Pattern::Dashed, Pattern::Solid, Pattern::Dotted];
    const REF_WIDTH: [f64; 3] = [1.0, 2.0, 1.0];
    const FAMILIES: [(&'static str, &'static str); 2] =
        [("free", "free vertices"), ("decaying", "decaying zig-zag")];

    fn best_lambda(&self) -> Option<f64> {
        self.rows
            .iter()
            .filter(|r| r.row == "frontier")
            .map(|r| r.lambda)
            .reduce(f64::max)
    }
}

impl Figure for DesignPlot<'_> {
    fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The key: only what the two panels show.
    fn key(&self) -> Key {
        let mut key = Key::default();
        for (k, (name, label)) in Self::REFS.into_iter().enumerate() {
            if let Some(r) = self.reference(name) {
                key.push(
                    Sample::Line(Self::REF_PATTERN[k], GREY, Self::REF_WIDTH[k]),
                    format!("{label} = {:.4}", r.lambda),
                );
            }
        }
        for (k, (name, label)) in Self::FAMILIES.into_iter().enumerate() {
            if let Some(best) = self.best(name) {
                key.push(
                    Sample::Line(Pattern::Solid, PALETTE[k], 2.0),
                    format!(
                        "{label}; best K = {}: λ = {:.4}",
                        best.vertices.unwrap_or(0),
                        best.lambda
                    ),
                );
            }
        }
        if let Some(l) = self.best_lambda() {
            key.push(
                Sample::Line(Pattern::Solid, BLACK, 3.0),
                format!("the cycle at λ = {l:.4} (φ = 0)"),
            );
        }
        key.push(Sample::Swatch(LIGHT_GREY), "initial stick |x| + |y| ≤ 2π");
        key.push(
            Sample::Line(Pattern::Dashed, GREY, 1.0),
            "gross slip |y| = 2π",
        );
        key.push(Sample::Text, "×  the paper's 24 turning points");
        key
    }

    fn plots_aspect(&self) -> f64 {
        self.frame.one_column_or(1.6, 0.45)
    }

    fn caption_tail(&self) -> String {
        ". Left: the highest λ at which a found path O → P1 → … → PK → A shakes down, against its number of vertices K, per family, beside λ₁, the best of the paper's 25 transients and λ₂. Right: the best path of each family on the load plane, with the initial stick region, the gross-slip lines, the paper's 24 turning points (crosses) and the steady cycle at the highest λ found.".to_string()
    }

    fn draw_plots<DB: DrawingBackend>(
        &self,
        plots: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let w = plots.dim_in_pixel().0;
        // One column: the panels one above the other.
        let (first, second) = if self.frame.style == FigureStyle::Paper1Col {
            plots.split_vertically(plots.dim_in_pixel().1 / 2)
        } else {
            plots.split_horizontally(w / 2)
        };
        self.frontier(&first, pen)?;
        self.plane(&second, pen)
    }
}
