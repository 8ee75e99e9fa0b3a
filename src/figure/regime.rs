//! The regime map: the steady state over the `(lambda, phi)` plane, each
//! cell in its state's colour, shaded by `W` (darker is more dissipation,
//! on a log scale), with `lambda_2(phi)` from the linear programme drawn
//! over it and the lines of the paper's Figs. 3, 6 and 8 marked.

use std::f64::consts::PI;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{font, legend, line_sample, s, Drawing, Mark, Pattern};
use crate::analysis::regime::RegimeMap;
use crate::io::preset::RatchettingMarkers;
use crate::palette::{shade, Rgb, Shading};

/// The regime map of one initial transient.
pub struct RegimePlot<'a> {
    /// The states on the grid.
    pub map: &'a RegimeMap,
    /// `(phi, lambda_2)` pairs, ascending in `phi`.
    pub limit: &'a [(f64, f64)],
    /// The plot title.
    pub title: String,
    /// Mark the lines of the paper's Figs. 3 (`phi = 0`), 6 (`lambda = 5.1`)
    /// and 8 (`phi = pi/2`), where they cross the map.
    pub paper_lines: bool,
}

/// A paper figure's line on the map: name, ends, where its label goes.
type PaperLine = (&'static str, Vec<(f64, f64)>, (f64, f64));

/// plotters' colour of a palette colour.
fn rgb(c: Rgb) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

impl Drawing for RegimePlot<'_> {
    fn size(&self) -> (u32, u32) {
        (1100, 760)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let map = self.map;
        let (nl, np) = (map.load_factors().len(), map.phases().len());
        if nl == 0 || np == 0 {
            return Err("the regime map has no runs".into());
        }
        let x0 = map.cell_bounds(0, 0).0 .0;
        let x1 = map.cell_bounds(nl - 1, 0).0 .1;
        let y0 = map.cell_bounds(0, 0).1 .0 / PI;
        let y1 = map.cell_bounds(0, np - 1).1 .1 / PI;
        let root = root.titled(&self.title, font(22.0)).map_err(s)?;
        let (plot, key) = root.split_horizontally(800);
        let mut chart = ChartBuilder::on(&plot)
            .margin(14)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("λ")
            .y_desc("φ / π")
            .axis_desc_style(font(20.0))
            .label_style(font(14.0))
            .draw()
            .map_err(s)?;

        // Cells: the state's colour, darker for larger W (log scale).
        let whi = map.dissipation_range().map_or(1.0, |r| r.1);
        let shading = Shading::of(map);
        let mut rects = Vec::with_capacity(nl * np);
        let mut present = Vec::new();
        for j in 0..np {
            for i in 0..nl {
                let Some(cell) = map.cell(i, j) else { continue };
                let mark = match cell.state {
                    Some(st) => Mark::of(st, RatchettingMarkers::Monotonicity),
                    None => Mark::Ended,
                };
                if !present.contains(&mark) {
                    present.push(mark);
                }
                let ((a, b), (c, d)) = map.cell_bounds(i, j);
                rects.push(Rectangle::new(
                    [(a, c / PI), (b, d / PI)],
                    rgb(shading.colour(&cell)).filled(),
                ));
            }
        }
        chart.draw_series(rects).map_err(s)?;

        // The paper's figures as lines of the plane.
        if self.paper_lines {
            let style = BLACK.mix(0.55).stroke_width(1);
            let lines: [PaperLine; 3] = [
                (
                    "Fig. 3",
                    vec![(x0, 0.0), (x1, 0.0)],
                    (x0 + 0.01 * (x1 - x0), 0.015),
                ),
                (
                    "Fig. 6",
                    vec![(5.1, y0), (5.1, y1)],
                    (5.12, y1 - 0.04 * (y1 - y0)),
                ),
                (
                    "Fig. 8",
                    vec![(x0, 0.5), (x1, 0.5)],
                    (x0 + 0.01 * (x1 - x0), 0.515),
                ),
            ];
            for (name, pts, at) in lines {
                let inside = pts
                    .iter()
                    .all(|p| p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1);
                if !inside {
                    continue;
                }
                Pattern::Dotted.draw(&mut chart, pts, style)?;
                let grey = BLACK.mix(0.8);
                let text = font(14.0).color(&grey);
                chart
                    .draw_series(std::iter::once(Text::new(name, at, text)))
                    .map_err(s)?;
            }
        }

        // lambda_2(phi) over the map.
        let curve: Vec<(f64, f64)> = self
            .limit
            .iter()
            .filter(|(p, l)| l.is_finite() && p / PI >= y0 && p / PI <= y1)
            .map(|&(p, l)| (l.clamp(x0, x1), p / PI))
            .collect();
        if !curve.is_empty() {
            let style = BLACK.stroke_width(3);
            chart
                .draw_series(LineSeries::new(curve.clone(), style))
                .map_err(s)?
                .label("λ₂(φ), linear programme")
                .legend(move |c| line_sample!(Pattern::Solid, c, style));
            chart
                .draw_series(curve.iter().map(|&c| Circle::new(c, 3, BLACK.filled())))
                .map_err(s)?;
            legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        }

        // The key: one swatch per state, light to dark for small to large W.
        let mut y = 40;
        key.draw(&Text::new("steady state", (10, y), font(17.0)))
            .map_err(s)?;
        y += 30;
        for mark in Mark::ORDER {
            if !present.contains(&mark) {
                continue;
            }
            let shades: &[f64] = if matches!(mark, Mark::Shakedown | Mark::Ended) {
                &[0.0]
            } else {
                &[0.0, 0.5, 1.0]
            };
            for (k, &t) in shades.iter().enumerate() {
                let x = 10 + 18 * k as i32;
                key.draw(&Rectangle::new(
                    [(x, y), (x + 16, y + 16)],
                    rgb(shade(mark.map_colour(), t)).filled(),
                ))
                .map_err(s)?;
            }
            let label = if mark == Mark::Ended {
                "gross slip / separation / failed"
            } else {
                mark.label()
            };
            key.draw(&Text::new(label, (70, y), font(14.0)))
                .map_err(s)?;
            y += 28;
        }
        y += 14;
        for line in [
            "Shading: darker is larger W,".to_string(),
            format!(
                "log scale from {:.0e} to {:.0e}.",
                10f64.powf(shading.lo),
                whi
            ),
            "Dotted: the lines of the".to_string(),
            "paper's Figs. 3, 6 and 8.".to_string(),
        ] {
            key.draw(&Text::new(line, (10, y), font(14.0))).map_err(s)?;
            y += 20;
        }
        Ok(())
    }
}
