//! Tractions: the shear `q(theta)` between the friction limits `+-f p` at
//! the instant on screen. Slipping nodes sit on a limit and are marked
//! with their direction; nodes that just stuck again are marked with `*`.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Widget};

use super::slip_map::{BACKWARD_GLYPH, FORWARD_GLYPH, STUCK_GLYPH};
use super::{glyph, nice_ceiling, theta_axis, theta_order, tick, Theme};
use crate::tui::app::{node_theta, plural, App, BACKWARD, DIRECTION_MASK, FORWARD};

/// The tractions widget.
pub struct Tractions<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl Widget for Tractions<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let title = theme.sym(
            " Tractions q(θ), ±f p(θ) ",
            " Tractions q(theta), +-f p(theta) ",
        );
        let Some((record, detail)) = app.shown_detail() else {
            theme.panel(title).render(area, buf);
            return;
        };
        let n = detail.pressure.len();
        let f = app.friction();
        let (p, q) = (&detail.pressure, &detail.shear);
        let cells = &record.cells;
        let order: Vec<usize> = theta_order(n).collect();
        let at = |j: usize, v: f32| (node_theta(j, n), f64::from(v));
        let upper: Vec<(f64, f64)> = order.iter().map(|&j| at(j, f as f32 * p[j])).collect();
        let lower: Vec<(f64, f64)> = order.iter().map(|&j| at(j, -f as f32 * p[j])).collect();
        let shear: Vec<(f64, f64)> = order.iter().map(|&j| at(j, q[j])).collect();
        let marked = |d: u8| -> Vec<(f64, f64)> {
            order
                .iter()
                .filter(|&&j| cells.get(j).is_some_and(|c| c & DIRECTION_MASK == d))
                .map(|&j| at(j, q[j]))
                .collect()
        };
        let forward = marked(FORWARD);
        let backward = marked(BACKWARD);
        let stuck: Vec<(f64, f64)> = record
            .newly_stuck
            .iter()
            .filter(|&&j| j < n)
            .map(|&j| at(j, q[j]))
            .collect();
        let limit = upper
            .iter()
            .chain(&lower)
            .chain(&shear)
            .map(|&(_, v)| v.abs())
            .fold(0.0, f64::max);
        let top = nice_ceiling(limit * 1.05);
        let line = theme.line_marker();
        let datasets = vec![
            Dataset::default()
                .data(&upper)
                .marker(line)
                .graph_type(GraphType::Line)
                .style(theme.fg(Color::Green)),
            Dataset::default()
                .data(&lower)
                .marker(line)
                .graph_type(GraphType::Line)
                .style(theme.fg(Color::Green)),
            Dataset::default()
                .data(&shear)
                .marker(line)
                .graph_type(GraphType::Line)
                .style(theme.fg(Color::White)),
            Dataset::default()
                .data(&forward)
                .marker(glyph(FORWARD_GLYPH))
                .style(theme.forward()),
            Dataset::default()
                .data(&backward)
                .marker(glyph(BACKWARD_GLYPH))
                .style(theme.backward()),
            Dataset::default()
                .data(&stuck)
                .marker(glyph(STUCK_GLYPH))
                .style(theme.newly_stuck()),
        ];
        let wide = area.width >= 48;
        let bottom = if record.newly_stuck.is_empty() {
            Line::from(Span::styled(" > < slipping ", theme.label()))
        } else {
            let k = record.newly_stuck.len();
            Line::from(Span::styled(
                if wide {
                    format!(
                        " {STUCK_GLYPH} just stuck: {}, {} ",
                        plural(k, "node"),
                        plural(record.substeps, "sub-segment")
                    )
                } else {
                    format!(" {STUCK_GLYPH} {k} stuck, {} sub-seg ", record.substeps)
                },
                theme.newly_stuck(),
            ))
        };
        let chart = Chart::new(datasets)
            .block(theme.panel(title).title_bottom(bottom))
            .legend_position(None)
            .x_axis(theta_axis(theme))
            .y_axis(
                Axis::default()
                    .title(Span::styled("q", theme.label()))
                    .bounds([-top, top])
                    .labels([tick(-top), "0".into(), tick(top)])
                    .style(theme.dim()),
            );
        chart.render(area, buf);
    }
}
