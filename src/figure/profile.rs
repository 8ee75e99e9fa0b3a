//! The fretting profile against `theta` (`figure profile`, model.md
//! section 4.1): what a fretting assessment reads off the interface over
//! the verdict cycle, in three panels sharing the `theta` axis.
//!
//! * tractions: the envelopes of `p` and `q` over the cycle;
//! * slip: its amplitude (half the range of `g`) and its path `sum |dg|`;
//! * damage measures: the dissipation density, the Ruiz parameter and the
//!   Archard wear, each over its own peak (their units differ), the peaks
//!   given in the key.

use std::f64::consts::PI;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{
    readable, s, Figure, Frame, Key, Pattern, Pen, Sample, DARK_BLUE, DARK_RED, GREEN_LINE,
};
use crate::analysis::profile::Profile;

/// The fretting profile of one run's verdict cycle against `theta`.
pub struct ProfilePlot<'a> {
    /// The profile (as `run --profile` writes it).
    pub profile: &'a Profile,
    /// The friction coefficient `f`, for the band `|q| <= f p`.
    pub friction: f64,
    /// Its style and title.
    pub frame: Frame,
}

/// One curve: its points `(theta / pi, value)`, colour and pattern.
type Curve = (Vec<(f64, f64)>, RGBColor, Pattern);

impl ProfilePlot<'_> {
    fn xy(&self, values: &[f64], scale: f64) -> Vec<(f64, f64)> {
        let p = self.profile;
        // The interface is closed: repeat the first node at theta = 2 pi.
        let mut out: Vec<(f64, f64)> = p
            .theta
            .iter()
            .zip(values)
            .map(|(&t, &v)| (t / PI, v * scale))
            .collect();
        if let Some(&v) = values.first() {
            out.push((2.0, v * scale));
        }
        out
    }

    /// The dissipation per unit `theta` (the column is per node arc).
    fn density(&self) -> Vec<f64> {
        let n = self.profile.theta.len().max(1) as f64;
        let arc = 2.0 * PI / n;
        self.profile.dissipation.iter().map(|w| w / arc).collect()
    }

    fn peak(values: &[f64]) -> f64 {
        values.iter().copied().fold(0.0, f64::max)
    }

    /// The damage measures over their peaks, with their labels.
    fn damage(&self) -> Vec<(Curve, String)> {
        let density = self.density();
        [
            (
                density,
                DARK_RED,
                Pattern::Solid,
                "dissipation density dW/dθ",
            ),
            (
                self.profile.ruiz.clone(),
                DARK_BLUE,
                Pattern::Dashed,
                "Ruiz  max|q| × slip amplitude",
            ),
            (
                self.profile.wear.clone(),
                GREEN_LINE,
                Pattern::Dotted,
                "wear  Σ p |Δg|",
            ),
        ]
        .into_iter()
        .map(|(values, colour, pattern, label)| {
            let peak = Self::peak(&values);
            let scale = if peak > 0.0 { 1.0 / peak } else { 0.0 };
            (
                (self.xy(&values, scale), colour, pattern),
                format!("{label}  (÷ peak {})", readable(peak)),
            )
        })
        .collect()
    }

    /// One panel: `curves` against `theta / pi` in `area`, labelled `y`.
    fn panel<DB: DrawingBackend>(
        area: &DrawingArea<DB, Shift>,
        pen: &Pen,
        curves: &[Curve],
        y: &str,
        x_label: bool,
    ) -> Result<(), String> {
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for (points, _, _) in curves {
            for &(_, v) in points {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        if !(lo.is_finite() && hi.is_finite()) || lo > hi {
            (lo, hi) = (0.0, 1.0);
        }
        let pad = 0.05 * (hi - lo).max(1e-12);
        let (lo, hi) = (lo - pad, hi + pad);
        let f = pen.text_pt();
        let mut chart = ChartBuilder::on(area)
            .margin(pen.px(0.6 * f))
            .margin_right(pen.px(1.6 * f))
            .x_label_area_size(pen.px(if x_label { 2.9 * f } else { 1.6 * f }))
            .y_label_area_size(pen.px(4.6 * f))
            .build_cartesian_2d(0.0..2.0, lo..hi)
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc(if x_label { "θ / π" } else { "" })
            .y_desc(y)
            .draw()
            .map_err(s)?;
        for (points, colour, pattern) in curves {
            pattern.draw(&mut chart, points.clone(), pen.line(*colour, 1.5))?;
        }
        Ok(())
    }
}

impl Figure for ProfilePlot<'_> {
    fn frame(&self) -> &Frame {
        &self.frame
    }

    fn key(&self) -> Key {
        let mut key = Key::default();
        key.push(
            Sample::Line(Pattern::Solid, BLACK, 1.5),
            "p: least and largest over the cycle",
        );
        key.push(
            Sample::Line(Pattern::Solid, DARK_RED, 1.5),
            "q: least and largest over the cycle",
        );
        key.push(Sample::Line(Pattern::Dashed, DARK_RED, 1.0), "±f p_max");
        key.push(
            Sample::Line(Pattern::Solid, BLACK, 1.5),
            "slip amplitude (half the range of g)",
        );
        key.push(
            Sample::Line(Pattern::Dashed, DARK_BLUE, 1.5),
            "slip path Σ|Δg|",
        );
        for ((_, colour, pattern), label) in self.damage() {
            key.push(Sample::Line(pattern, colour, 1.5), label);
        }
        key
    }

    fn plots_aspect(&self) -> f64 {
        self.frame.one_column_or(1.5, 1.0)
    }

    fn caption_tail(&self) -> String {
        format!(
            ". The fretting profile of cycle {} against θ: top, the envelopes of the contact pressure p and the shear q over the cycle, with the friction bound ±f p_max (f = {}); middle, the slip amplitude and the slip path; bottom, the dissipation density, the Ruiz parameter and the Archard wear, each over its own peak. W = {}.",
            self.profile.cycle,
            readable(self.friction),
            readable(self.profile.total_dissipation())
        )
    }

    fn draw_plots<DB: DrawingBackend>(
        &self,
        plots: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let panels = plots.split_evenly((3, 1));
        let p = self.profile;
        let bound: Vec<f64> = p.p_max.iter().map(|v| self.friction * v).collect();
        let minus: Vec<f64> = bound.iter().map(|v| -v).collect();
        let tractions = [
            (self.xy(&p.p_min, 1.0), BLACK, Pattern::Solid),
            (self.xy(&p.p_max, 1.0), BLACK, Pattern::Solid),
            (self.xy(&p.q_min, 1.0), DARK_RED, Pattern::Solid),
            (self.xy(&p.q_max, 1.0), DARK_RED, Pattern::Solid),
            (self.xy(&bound, 1.0), DARK_RED, Pattern::Dashed),
            (self.xy(&minus, 1.0), DARK_RED, Pattern::Dashed),
        ];
        Self::panel(&panels[0], pen, &tractions, "p, q  (÷ p₀)", false)?;
        let slip = [
            (self.xy(&p.slip_amplitude, 1.0), BLACK, Pattern::Solid),
            (
                self.xy(&p.slip_accumulated, 1.0),
                DARK_BLUE,
                Pattern::Dashed,
            ),
        ];
        Self::panel(&panels[1], pen, &slip, "slip g", false)?;
        let damage: Vec<Curve> = self.damage().into_iter().map(|(c, _)| c).collect();
        Self::panel(&panels[2], pen, &damage, "÷ peak", true)?;
        Ok(())
    }
}
