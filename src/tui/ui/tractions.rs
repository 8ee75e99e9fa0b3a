//! Tractions: the shear `q(theta)` between the friction limits `+-f p`.
//! Slipping nodes sit on a limit and are marked with their direction;
//! nodes that just stuck again are marked with `*`.

use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType};
use ratatui::Frame;

use super::slip_map::{BACKWARD_GLYPH, FORWARD_GLYPH, STUCK_GLYPH};
use super::{nice_ceiling, theta_axis, theta_order, tick, Theme};
use crate::contact::SlipDirection;
use crate::tui::app::{node_theta, plural, App};

pub fn render(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let contact = app.stepper().contact();
    let n = contact.nodes();
    let f = contact.material().friction();
    let (p, q, dirs) = (contact.pressure(), contact.shear(), contact.directions());
    let order: Vec<usize> = theta_order(n).collect();
    let at = |j: usize, v: f64| (node_theta(j, n), v);
    let upper: Vec<(f64, f64)> = order.iter().map(|&j| at(j, f * p[j])).collect();
    let lower: Vec<(f64, f64)> = order.iter().map(|&j| at(j, -f * p[j])).collect();
    let shear: Vec<(f64, f64)> = order.iter().map(|&j| at(j, q[j])).collect();
    let marked = |d: SlipDirection| -> Vec<(f64, f64)> {
        order
            .iter()
            .filter(|&&j| dirs[j] == d)
            .map(|&j| at(j, q[j]))
            .collect()
    };
    let forward = marked(SlipDirection::Forward);
    let backward = marked(SlipDirection::Backward);
    let stuck: Vec<(f64, f64)> = app
        .recent_stuck()
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

    let datasets = vec![
        Dataset::default()
            .name("+fp")
            .data(&upper)
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(theme.fg(Color::Green)),
        Dataset::default()
            .name("-fp")
            .data(&lower)
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(theme.fg(Color::Green)),
        Dataset::default()
            .data(&shear)
            .marker(Marker::Braille)
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
    let bottom = match app.last_stick() {
        Some(s) if !app.recent_stuck().is_empty() => Line::from(vec![
            Span::raw(" "),
            Span::styled(
                if wide {
                    format!(
                        "{STUCK_GLYPH} just stuck: {}, {} sub-increments",
                        plural(s.nodes.len(), "node"),
                        s.substeps
                    )
                } else {
                    format!(
                        "{STUCK_GLYPH} {} stuck, {} sub-incr",
                        s.nodes.len(),
                        s.substeps
                    )
                },
                theme.newly_stuck(),
            ),
            Span::raw(" "),
        ]),
        Some(s) => Line::from(Span::styled(
            if wide {
                format!(
                    " last stick: increment {}, {} sub-increments ",
                    s.increment + 1,
                    s.substeps
                )
            } else {
                format!(" stuck @{}: {} sub-incr ", s.increment + 1, s.substeps)
            },
            theme.label(),
        )),
        None => Line::from(Span::styled(" > < slipping ", theme.label())),
    };
    let block = theme
        .panel(" Tractions q(θ), ±f p(θ) ")
        .title_bottom(bottom);
    let chart = Chart::new(datasets)
        .block(block)
        .legend_position(None)
        .x_axis(theta_axis(theme))
        .y_axis(
            Axis::default()
                .title(Span::styled("q", theme.label()))
                .bounds([-top, top])
                .labels([tick(-top), "0".into(), tick(top)])
                .style(theme.dim()),
        );
    frame.render_widget(chart, area);
}

fn glyph(s: &str) -> Marker {
    Marker::Custom(s.chars().next().unwrap_or('?'))
}
