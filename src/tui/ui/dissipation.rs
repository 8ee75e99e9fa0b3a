//! Dissipation `W` per completed cycle up to the instant on screen, and
//! the part of its cycle done so far: the steady state is where the dots
//! level off. A pinned run's `W` is drawn with `x` for comparison.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Widget};

use super::{nice_ceiling, tick, Theme};
use crate::tui::app::{format_sci, App};

/// The dissipation widget.
pub struct Dissipation<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl Widget for Dissipation<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let shown = app.shown();
        let shown_cycle = shown.map_or(0, |r| r.cycle());
        let completed: Vec<(f64, f64)> = app
            .cycles()
            .iter()
            .filter(|&&(c, _)| shown.is_none() || c < shown_cycle || app.cursor().is_none())
            .map(|&(c, w)| (c as f64, w))
            .collect();
        let now_w = shown.map_or(0.0, |r| r.dissipation);
        let current: Vec<(f64, f64)> = match shown {
            Some(r) if r.cycle() > 0 && r.completed.is_none() => {
                vec![(r.cycle() as f64, r.dissipation)]
            }
            _ => Vec::new(),
        };
        let pinned: Vec<(f64, f64)> = app
            .pinned()
            .map(|p| p.cycles.iter().map(|&(c, w)| (c as f64, w)).collect())
            .unwrap_or_default();
        let last_cycle = completed
            .iter()
            .chain(&current)
            .chain(&pinned)
            .map(|&(c, _)| c as usize)
            .max()
            .unwrap_or(0);
        let x_max = (last_cycle.max(2) + 1) as f64;
        let w_max = completed
            .iter()
            .chain(&current)
            .chain(&pinned)
            .map(|&(_, w)| w)
            .fold(0.0, f64::max);
        let top = nice_ceiling(w_max.max(1e-6) * 1.05);
        let mut datasets = vec![
            Dataset::default()
                .data(&completed)
                .marker(theme.line_marker())
                .graph_type(GraphType::Line)
                .style(theme.fg(Color::LightCyan)),
            Dataset::default()
                .data(&completed)
                .marker(Marker::Custom('o'))
                .style(theme.fg(Color::LightCyan)),
            Dataset::default()
                .data(&current)
                .marker(Marker::Custom('+'))
                .style(theme.alert()),
        ];
        if !pinned.is_empty() {
            datasets.insert(
                0,
                Dataset::default()
                    .data(&pinned)
                    .marker(Marker::Custom('x'))
                    .style(theme.dim()),
            );
        }
        let last = completed
            .last()
            .map_or("–".to_string(), |&(_, w)| format_sci(w));
        let done = [
            Span::styled(" o ", theme.fg(Color::LightCyan)),
            Span::styled(format!("{last} "), theme.value()),
        ];
        let now = [
            Span::styled("+ ", theme.alert()),
            Span::styled(format!("{} ", format_sci(now_w)), theme.value()),
        ];
        let pin = pinned.last().map(|&(_, w)| {
            [
                Span::styled("x ", theme.dim()),
                Span::styled(format!("{} ", format_sci(w)), theme.value()),
            ]
        });
        // All three values if they fit; else the pinned run's last `W`
        // before the cycle in progress, which the plot shows anyway.
        let mut candidates = vec![Line::from(
            done.iter()
                .chain(&now)
                .chain(pin.iter().flatten())
                .cloned()
                .collect::<Vec<_>>(),
        )];
        if let Some(pin) = &pin {
            candidates.push(Line::from(
                done.iter().chain(pin).cloned().collect::<Vec<_>>(),
            ));
        }
        let bottom = super::first_fitting(candidates, area.width.saturating_sub(2) as usize);
        let chart = Chart::new(datasets)
            .block(theme.panel(" Dissipation W ").title_bottom(bottom))
            .legend_position(None)
            .x_axis(
                Axis::default()
                    .title(Span::styled("cycle", theme.label()))
                    .bounds([0.0, x_max])
                    .labels(["0".to_string(), format!("{}", x_max as usize)])
                    .style(theme.dim()),
            )
            .y_axis(
                Axis::default()
                    .title(Span::styled("W", theme.label()))
                    .bounds([0.0, top])
                    .labels(["0".to_string(), tick(top)])
                    .style(theme.dim()),
            );
        chart.render(area, buf);
    }
}
