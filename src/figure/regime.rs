//! The regime map: the steady state over the `(lambda, phi)` plane, each
//! cell in its state's colour, shaded by `W` (darker is more dissipation,
//! on a log scale), with `lambda_2(phi)` from the linear programme drawn
//! over it and the lines of the paper's Figs. 3, 6 and 8 marked.

use std::f64::consts::PI;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{pow10_label, s, Figure, Frame, Key, Mark, Pattern, Pen, Sample};
use crate::analysis::regime::RegimeMap;
use crate::io::preset::RatchettingMarkers;
use crate::palette::{shade, Rgb, Shading};

/// The regime map of one initial transient.
pub struct RegimePlot<'a> {
    /// The states on the grid.
    pub map: &'a RegimeMap,
    /// `(phi, lambda_2)` pairs, ascending in `phi`.
    pub limit: &'a [(f64, f64)],
    /// Its style and title.
    pub frame: Frame,
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

impl RegimePlot<'_> {
    /// The marks of the states on the map, in key order.
    fn present(&self) -> Vec<Mark> {
        let map = self.map;
        let (nl, np) = (map.load_factors().len(), map.phases().len());
        let mut present = Vec::new();
        for j in 0..np {
            for i in 0..nl {
                if let Some(cell) = map.cell(i, j) {
                    let mark = Mark::of(cell.state, RatchettingMarkers::Monotonicity);
                    if !present.contains(&mark) {
                        present.push(mark);
                    }
                }
            }
        }
        Mark::ORDER
            .into_iter()
            .filter(|m| present.contains(m))
            .collect()
    }

    fn has_curve(&self) -> bool {
        self.limit.iter().any(|(_, l)| l.is_finite())
    }

    fn shading_note(&self) -> String {
        let shading = Shading::of(self.map);
        let whi = self.map.dissipation_range().map_or(1.0, |r| r.1);
        format!(
            "shading: darker is larger W, on a log scale from {} to {}",
            pow10_or_value(10f64.powf(shading.lo)),
            pow10_or_value(whi)
        )
    }
}

/// The state a mark stands for on the map (not for [`Mark::Failed`]).
fn state_of(mark: Mark) -> crate::stepping::steady::SteadyState {
    use crate::stepping::steady::SteadyState as S;
    match mark {
        Mark::Shakedown => S::Shakedown,
        Mark::CyclicSlip => S::CyclicSlip,
        Mark::Ratchetting | Mark::Monotonic => S::RatchettingMonotonic,
        Mark::NonMonotonic => S::RatchettingNonMonotonic,
        Mark::GrossSlip => S::GrossSlip,
        Mark::Separation => S::Separation,
        Mark::NotConverged | Mark::Failed => S::NotConverged,
    }
}

/// `10⁻⁵` for a power of ten, else the value rounded for reading.
fn pow10_or_value(v: f64) -> String {
    let p = pow10_label(&v);
    if p.is_empty() {
        super::style::readable(v)
    } else {
        p
    }
}

impl Figure for RegimePlot<'_> {
    fn frame(&self) -> &Frame {
        &self.frame
    }

    fn key(&self) -> Key {
        let mut key = Key::default();
        for mark in self.present() {
            let base = mark.map_colour();
            let sample = if crate::palette::is_shaded(match mark {
                Mark::Failed => None,
                _ => Some(state_of(mark)),
            }) {
                Sample::Ramp([
                    rgb(shade(base, 0.0)),
                    rgb(shade(base, 0.5)),
                    rgb(shade(base, 1.0)),
                ])
            } else {
                Sample::Swatch(rgb(base))
            };
            let label = match mark {
                Mark::GrossSlip => "gross slip",
                Mark::Separation => "separation",
                Mark::Failed => "failed numerically",
                m => m.label(),
            };
            key.push(sample, label);
        }
        if self.has_curve() {
            key.push(
                Sample::Line(Pattern::Solid, BLACK, 2.0),
                "λ₂(φ), linear programme",
            );
        }
        if self.paper_lines {
            key.push(
                Sample::Line(Pattern::Dotted, RGBColor(90, 90, 90), 1.0),
                "the lines of the paper's Figs. 3, 6 and 8",
            );
        }
        key.push(Sample::Text, self.shading_note());
        key
    }

    fn plots_aspect(&self) -> f64 {
        self.frame.one_column_or(0.8, 0.6)
    }

    fn caption_tail(&self) -> String {
        format!(
            ". Each cell is the steady state of one run, in its state's colour; {}. The solid line is λ₂(φ) of the linear programme.{}",
            self.shading_note(),
            if self.paper_lines {
                " Dotted: the lines of the paper's Figs. 3 (φ = 0), 6 (λ = 5.1) and 8 (φ = π/2)."
            } else {
                ""
            }
        )
    }

    fn draw_plots<DB: DrawingBackend>(
        &self,
        plots: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let map = self.map;
        let (nl, np) = (map.load_factors().len(), map.phases().len());
        if nl == 0 || np == 0 {
            return Err("the regime map has no runs".into());
        }
        let x0 = map.cell_bounds(0, 0).0 .0;
        let x1 = map.cell_bounds(nl - 1, 0).0 .1;
        let y0 = map.cell_bounds(0, 0).1 .0 / PI;
        let y1 = map.cell_bounds(0, np - 1).1 .1 / PI;
        let mut chart = pen
            .chart(plots)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc("λ")
            .y_desc("φ / π")
            .draw()
            .map_err(s)?;

        // Cells: the state's colour, darker for larger W (log scale).
        let shading = Shading::of(map);
        let mut rects = Vec::with_capacity(nl * np);
        for j in 0..np {
            for i in 0..nl {
                let Some(cell) = map.cell(i, j) else { continue };
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
            let style = pen.line(RGBColor(90, 90, 90), 1.0);
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
                let text = pen.tick().color(&RGBColor(50, 50, 50));
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
            chart
                .draw_series(LineSeries::new(curve.clone(), pen.line(BLACK, 2.0)))
                .map_err(s)?;
            chart
                .draw_series(
                    curve
                        .iter()
                        .map(|&c| Circle::new(c, pen.mark(0.6), BLACK.filled())),
                )
                .map_err(s)?;
        }
        Ok(())
    }
}
