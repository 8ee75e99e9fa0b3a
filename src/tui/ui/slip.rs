//! The locked-in slip `g(theta)`: the memory of the loading history. Its
//! mean is the rigid rotation, given as a number; the curve is drawn about
//! that mean, because the rotation grows without bound when the disc
//! ratchets and would flatten the shape that carries the memory (the
//! tractions see `g` only through operators that ignore its mean).

use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType};
use ratatui::Frame;

use super::{nice_ceiling, theta_axis, theta_order, tick, Theme};
use crate::tui::app::{format_sci, node_theta, App};

pub fn render(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let contact = app.stepper().contact();
    let n = contact.nodes();
    let slip = contact.slip();
    let rotation = contact.rotation();
    let points: Vec<(f64, f64)> = theta_order(n)
        .map(|j| (node_theta(j, n), slip[j] - rotation))
        .collect();
    let (lo, hi) = points
        .iter()
        .fold((0.0f64, 0.0f64), |(lo, hi), &(_, g)| (lo.min(g), hi.max(g)));
    // Symmetric about zero unless the slip is all one sign; a floor keeps
    // an untouched interface from blowing round-off up to full height.
    let scale = nice_ceiling(lo.abs().max(hi.abs()).max(1e-4) * 1.05);
    let bottom = if lo >= 0.0 { 0.0 } else { -scale };
    let top = if hi <= 0.0 && lo < 0.0 { 0.0 } else { scale };

    let datasets = vec![Dataset::default()
        .data(&points)
        .marker(Marker::Braille)
        .graph_type(GraphType::Line)
        .style(theme.fg(Color::LightYellow))];
    let block = theme
        .panel(" Locked-in slip g(θ) - ḡ ")
        .title_bottom(Line::from(vec![
            Span::styled(" rotation ḡ = ", theme.label()),
            Span::styled(format!("{} ", format_sci(rotation)), theme.value()),
        ]));
    let chart = Chart::new(datasets)
        .block(block)
        .legend_position(None)
        .x_axis(theta_axis(theme))
        .y_axis(
            Axis::default()
                .title(Span::styled("g-ḡ", theme.label()))
                .bounds([bottom, top])
                .labels(if bottom < 0.0 && top > 0.0 {
                    vec![tick(bottom), "0".into(), tick(top)]
                } else {
                    vec![tick(bottom), tick(top)]
                })
                .style(theme.dim()),
        );
    frame.render_widget(chart, area);
}
