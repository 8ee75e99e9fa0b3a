//! The locked-in slip `g(theta)`: the memory of the loading history, at
//! the instant on screen. Its mean is the rigid rotation, given as a
//! number; the curve is drawn about that mean, because the rotation grows
//! without bound when the disc ratchets and would flatten the shape that
//! carries the memory.
//!
//! At an advancing stick the nodes that stuck are marked, and `g` before
//! the increment is drawn too, so what they locked in shows as the gap
//! between the two curves there. A pinned run's `g` is drawn dimmed. The
//! scale is the largest `g` seen in this run, so it does not jump.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Widget};

use super::slip_map::STUCK_GLYPH;
use super::{glyph, nice_ceiling, theta_axis, theta_order, tick, Theme};
use crate::tui::app::{format_sci, node_theta, App};

/// The locked-in slip widget.
pub struct Slip<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

fn curve(values: &[f32]) -> Vec<(f64, f64)> {
    let n = values.len();
    theta_order(n)
        .map(|j| (node_theta(j, n), f64::from(values[j])))
        .collect()
}

impl Widget for Slip<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let title = theme.sym(" Locked-in slip g(θ) - ḡ ", " Locked-in slip g - mean g ");
        let Some((record, detail)) = app.shown_detail() else {
            theme.panel(title).render(area, buf);
            return;
        };
        let n = detail.slip.len();
        let now = curve(&detail.slip);
        let before = detail.slip_before.as_deref().map(curve).unwrap_or_default();
        let stuck: Vec<(f64, f64)> = record
            .newly_stuck
            .iter()
            .filter(|&&j| j < n)
            .map(|&j| (node_theta(j, n), f64::from(detail.slip[j])))
            .collect();
        let pinned = app
            .pinned()
            .filter(|p| p.slip.len() == n)
            .map(|p| curve(&p.slip))
            .unwrap_or_default();
        let peak = pinned
            .iter()
            .map(|&(_, g)| g.abs())
            .fold(app.slip_scale(), f64::max);
        // A floor keeps an untouched interface from blowing round-off up.
        let scale = nice_ceiling(peak.max(1e-4) * 1.05);
        let line = theme.line_marker();
        let mut datasets = Vec::new();
        if !pinned.is_empty() {
            datasets.push(
                Dataset::default()
                    .data(&pinned)
                    .marker(line)
                    .graph_type(GraphType::Line)
                    .style(theme.dim()),
            );
        }
        if !before.is_empty() {
            datasets.push(
                Dataset::default()
                    .data(&before)
                    .marker(line)
                    .graph_type(GraphType::Line)
                    .style(theme.fg(Color::Gray)),
            );
        }
        datasets.push(
            Dataset::default()
                .data(&now)
                .marker(line)
                .graph_type(GraphType::Line)
                .style(theme.fg(Color::LightYellow)),
        );
        datasets.push(
            Dataset::default()
                .data(&stuck)
                .marker(glyph(STUCK_GLYPH))
                .style(theme.newly_stuck()),
        );
        let bottom = if stuck.is_empty() {
            Line::from(vec![
                Span::styled(theme.sym(" rotation ḡ = ", " rotation = "), theme.label()),
                Span::styled(format!("{} ", format_sci(record.rotation)), theme.value()),
            ])
        } else {
            // The largest change a stuck node locked in.
            let change = record
                .newly_stuck
                .iter()
                .filter_map(|&j| {
                    let b = detail.slip_before.as_ref()?.get(j)?;
                    Some(f64::from(detail.slip[j] - b).abs())
                })
                .fold(0.0, f64::max);
            let change = format!("{} ", format_sci(change));
            super::first_fitting(
                vec![
                    Line::from(vec![
                        Span::styled(
                            format!(" {STUCK_GLYPH} locked in, dg up to "),
                            theme.newly_stuck(),
                        ),
                        Span::styled(change.clone(), theme.value()),
                        Span::styled("(grey: before) ", theme.label()),
                    ]),
                    Line::from(vec![
                        Span::styled(
                            format!(" {STUCK_GLYPH} locked in, dg up to "),
                            theme.newly_stuck(),
                        ),
                        Span::styled(change.clone(), theme.value()),
                    ]),
                    Line::from(vec![
                        Span::styled(format!(" {STUCK_GLYPH} dg up to "), theme.newly_stuck()),
                        Span::styled(change, theme.value()),
                    ]),
                ],
                area.width.saturating_sub(2) as usize,
            )
        };
        let chart = Chart::new(datasets)
            .block(theme.panel(title).title_bottom(bottom))
            .legend_position(None)
            .x_axis(theta_axis(theme))
            .y_axis(
                Axis::default()
                    .title(Span::styled("g", theme.label()))
                    .bounds([-scale, scale])
                    .labels(vec![tick(-scale), "0".into(), tick(scale)])
                    .style(theme.dim()),
            );
        chart.render(area, buf);
    }
}
