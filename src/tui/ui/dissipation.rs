//! Dissipation `W` per completed cycle, and the part of the current cycle
//! done so far: the steady state is where the dots level off.

use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType};
use ratatui::Frame;

use super::{nice_ceiling, tick, Theme};
use crate::stepping::Phase;
use crate::tui::app::{format_sci, App};

pub fn render(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let stepper = app.stepper();
    let completed: Vec<(f64, f64)> = stepper
        .history()
        .iter()
        .map(|r| (r.cycle as f64, r.dissipation))
        .collect();
    let in_cycle = matches!(stepper.phase(), Phase::Cycle { .. });
    let now_w = stepper.current_cycle().dissipation;
    let current: Vec<(f64, f64)> = if in_cycle && !stepper.is_finished() {
        vec![(stepper.current_cycle().cycle as f64, now_w)]
    } else {
        Vec::new()
    };
    let last_cycle = completed.len() + usize::from(!current.is_empty());
    let x_max = (last_cycle.max(2) + 1) as f64;
    let w_max = completed
        .iter()
        .chain(&current)
        .map(|&(_, w)| w)
        .fold(0.0, f64::max);
    let top = nice_ceiling(w_max.max(1e-6) * 1.05);

    let datasets = vec![
        Dataset::default()
            .data(&completed)
            .marker(Marker::Braille)
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
    let last = completed
        .last()
        .map_or("–".to_string(), |&(_, w)| format_sci(w));
    let block = theme.panel(" Dissipation W ").title_bottom(Line::from(vec![
        Span::styled(" o ", theme.fg(Color::LightCyan)),
        Span::styled(format!("{last} "), theme.value()),
        Span::styled("+ ", theme.alert()),
        Span::styled(format!("{} ", format_sci(now_w)), theme.value()),
    ]));
    let chart = Chart::new(datasets)
        .block(block)
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
    frame.render_widget(chart, area);
}
