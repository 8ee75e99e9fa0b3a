//! Dissipation `W` per completed cycle up to the instant on screen, and
//! the part of its cycle done so far: the steady state is where the dots
//! level off. A pinned run's `W` is drawn with `x` for comparison: then
//! both runs are named in a legend with their states, and `W` goes on a
//! log axis, where runs that differ by orders of magnitude both show (a
//! `W` of zero, shakedown, sits on the axis's floor).

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Widget};

use super::{nice_ceiling, tick, Theme};
use crate::stepping::Status;
use crate::tui::app::{format_load_factor, format_phase, format_sci, App, Pinned};

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
        // Compare: decades of W, from a floor below the smallest positive
        // W (zero sits on it) to a power of ten above the largest.
        let log = (!pinned.is_empty())
            .then(|| log_bounds(completed.iter().chain(&current).chain(&pinned)));
        let (completed, current, pinned) = match log {
            Some((lo, _)) => {
                let to_log = |v: &[(f64, f64)]| -> Vec<(f64, f64)> {
                    v.iter()
                        .map(|&(c, w)| (c, if w > 0.0 { w.log10().max(lo) } else { lo }))
                        .collect()
                };
                (to_log(&completed), to_log(&current), to_log(&pinned))
            }
            None => (completed, current, pinned),
        };
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
        let last = app
            .cycles()
            .last()
            .filter(|_| !completed.is_empty())
            .map_or("–".to_string(), |&(_, w)| format_sci(w));
        let done = [
            Span::styled(" o ", theme.fg(Color::LightCyan)),
            Span::styled(format!("{last} "), theme.value()),
        ];
        let now = [
            Span::styled("+ ", theme.alert()),
            Span::styled(format!("{} ", format_sci(now_w)), theme.value()),
        ];
        let pin = app.pinned().and_then(|p| p.cycles.last()).map(|&(_, w)| {
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
        let (y_bounds, y_labels, y_title) = match log {
            Some((lo, hi)) => (
                [lo, hi],
                vec![format!("1e{lo}"), format!("1e{hi}")],
                "W log",
            ),
            None => ([0.0, top], vec!["0".to_string(), tick(top)], "W"),
        };
        let block = theme.panel(" Dissipation W ").title_bottom(bottom);
        let inner = block.inner(area);
        block.render(area, buf);
        let chart_area = match app.pinned() {
            Some(p) if inner.height > 6 => {
                let [legend, chart] =
                    Layout::vertical([Constraint::Length(2), Constraint::Fill(1)]).areas(inner);
                render_legend(app, p, theme, legend, buf);
                chart
            }
            _ => inner,
        };
        let chart = Chart::new(datasets)
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
                    .title(Span::styled(y_title, theme.label()))
                    .bounds(y_bounds)
                    .labels(y_labels)
                    .style(theme.dim()),
            );
        chart.render(chart_area, buf);
    }
}

/// `log10` bounds of a log axis over `values`' positive `W`: whole decades,
/// at most twelve, and at least one.
fn log_bounds<'a>(values: impl Iterator<Item = &'a (f64, f64)>) -> (f64, f64) {
    let (min, max) = values
        .map(|&(_, w)| w)
        .filter(|&w| w > 0.0 && w.is_finite())
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), w| {
            (lo.min(w), hi.max(w))
        });
    if max <= 0.0 {
        return (-9.0, -8.0);
    }
    let hi = max.log10().ceil();
    let hi = if hi == max.log10() { hi + 1.0 } else { hi };
    let lo = (min.log10().floor() - 1.0).max(hi - 12.0).min(hi - 1.0);
    (lo, hi)
}

/// What a run has become, in the words of the state line.
fn state_of(status: &Status) -> String {
    match status {
        Status::Running => "not yet steady".into(),
        Status::Steady(s) | Status::Ended(s) => s.state().as_str().into(),
    }
}

/// The two runs of a comparison, each with its glyph, its case and its
/// state: the longest form that fits.
fn render_legend(app: &App, pinned: &Pinned, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let width = area.width as usize;
    let live_label = format!(
        "λ {} φ {} {}",
        format_load_factor(app.load_factor()),
        format_phase(app.phase()),
        app.initial().name()
    );
    let live_state = state_of(app.status());
    let rows = [
        (
            " o ",
            theme.fg(Color::LightCyan),
            "live",
            live_label,
            app.initial().name(),
            live_state,
        ),
        (
            " x ",
            theme.dim(),
            "pinned",
            pinned.label.replace("lambda", "λ").replace("phi", "φ"),
            pinned.path.clone(),
            pinned.state.clone(),
        ),
    ];
    for (k, (glyph, style, who, label, path, state)) in rows.into_iter().enumerate() {
        let forms = [
            format!("{who} {label}: {state}"),
            format!("{who} {path}: {state}"),
            format!("{path}: {state}"),
        ];
        let lines = forms
            .into_iter()
            .map(|f| {
                Line::from(vec![
                    Span::styled(glyph, style),
                    Span::styled(f, theme.label()),
                ])
            })
            .collect();
        let line = super::first_fitting(lines, width);
        let row = Rect::new(area.x, area.y + k as u16, area.width, 1);
        ratatui::widgets::Paragraph::new(line).render(row, buf);
    }
}
