//! The sweep view: `W` against `lambda` (or `phi`) for every run of a
//! sweep, filling in as the runs arrive, with `lambda_2`, a legend, the
//! cursor's run and a status line.

use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CanvasLine};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use super::{nice_ceiling, tick, Theme};
use crate::analysis::sweep::Axis;
use crate::analysis::sweep::{Row, RowState};
use crate::stepping::steady::SteadyState;
use crate::tui::app::{format_load_factor, format_phase, format_sci, App};
use crate::tui::sweep::{LimitState, Sweep};

/// Width of the legend and details column.
const SIDE_WIDTH: u16 = 35;
/// Height of the legend: the states, failures and `lambda_2`, bordered.
const LEGEND_HEIGHT: u16 = 11;

/// Every state a marker can show, in legend order.
const STATES: [RowState; 8] = [
    RowState::Steady(SteadyState::Shakedown),
    RowState::Steady(SteadyState::CyclicSlip),
    RowState::Steady(SteadyState::RatchettingMonotonic),
    RowState::Steady(SteadyState::RatchettingNonMonotonic),
    RowState::Steady(SteadyState::GrossSlip),
    RowState::Steady(SteadyState::Separation),
    RowState::Steady(SteadyState::NotConverged),
    RowState::Failed,
];

/// A marker's glyph, colour and legend text. The glyphs differ from each
/// other so the map reads without colour (`NO_COLOR`).
fn marker(state: RowState) -> (&'static str, Color, &'static str) {
    match state {
        RowState::Steady(s) => match s {
            SteadyState::Shakedown => ("o", Color::LightGreen, "shakedown"),
            SteadyState::CyclicSlip => ("•", Color::Yellow, "cyclic slip"),
            SteadyState::RatchettingMonotonic => ("◆", Color::LightBlue, "ratchetting, monotonic"),
            SteadyState::RatchettingNonMonotonic => {
                ("✚", Color::LightMagenta, "ratchetting, non-monot.")
            }
            SteadyState::GrossSlip => ("x", Color::LightRed, "gross slip"),
            SteadyState::Separation => ("#", Color::Red, "separation"),
            SteadyState::NotConverged => ("?", Color::Gray, "not converged"),
        },
        RowState::Failed => ("!", Color::LightRed, "solver failed (at W=0)"),
    }
}

pub fn render(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let [body, status] = Layout::vertical([Constraint::Fill(1), Constraint::Length(3)]).areas(area);
    let [plot, side] =
        Layout::horizontal([Constraint::Fill(1), Constraint::Length(SIDE_WIDTH)]).areas(body);
    let [legend, details] =
        Layout::vertical([Constraint::Length(LEGEND_HEIGHT), Constraint::Fill(1)]).areas(side);
    match app.sweep() {
        Ok(sweep) => {
            render_plot(frame, plot, sweep, theme, app.sweep_log_w());
            render_legend(frame, legend, sweep, theme);
            render_details(frame, details, sweep, theme);
        }
        Err(e) => {
            let block = theme.panel(" Sweep ");
            let text = Paragraph::new(Span::styled(format!("no sweep: {e}"), theme.error()))
                .wrap(ratatui::widgets::Wrap { trim: true })
                .block(block);
            frame.render_widget(text, body);
        }
    }
    render_status(frame, status, app, theme);
}

/// The horizontal axis's name and a value's label on it.
fn axis_name(axis: Axis) -> &'static str {
    match axis {
        Axis::Lambda => "lambda",
        Axis::Phi => "phi",
    }
}

fn x_label(axis: Axis, v: f64) -> String {
    match axis {
        Axis::Lambda => tick(v),
        Axis::Phi => format_phase(v),
    }
}

fn render_plot(frame: &mut Frame, area: Rect, sweep: &Sweep, theme: &Theme, log: bool) {
    let axis = sweep.axis();
    let progress = if sweep.is_running() {
        format!("{}/{} runs, running", sweep.done(), sweep.total())
    } else if !sweep.started() && sweep.done() == 0 {
        "not started".to_string()
    } else {
        format!("{}/{} runs", sweep.done(), sweep.total())
    };
    // The most that fits between the corners; never cut silently.
    let room = usize::from(area.width).saturating_sub(2);
    let name = &sweep.source().name;
    let title = [
        format!(" W against {} · {name} · {progress} ", axis_name(axis)),
        format!(
            " W against {} · {name} · {}/{} ",
            axis_name(axis),
            sweep.done(),
            sweep.total()
        ),
        format!(" W · {name} · {}/{} ", sweep.done(), sweep.total()),
    ]
    .into_iter()
    .find(|t| t.chars().count() <= room)
    .unwrap_or_else(|| {
        let short = format!(" W · {name} ");
        super::fit_spans(vec![Span::raw(short)], room)
            .iter()
            .map(|s| s.content.to_string())
            .collect()
    });
    let block = theme.panel(title);
    let inner = block.inner(area);
    let _ = theme.ascii();
    frame.render_widget(block, area);
    if inner.width < 12 || inner.height < 4 {
        return;
    }

    let xs = sweep.xs();
    let (x0, x1) = match (xs.first(), xs.last()) {
        (Some(&a), Some(&b)) if b > a => (a, b),
        // One value (or none): centre it in a unit-wide window.
        (Some(&a), _) => (a - 0.5, a + 0.5),
        _ => (0.0, 1.0),
    };
    let w_max = sweep
        .rows()
        .filter_map(|r| r.outcome.as_ref().ok().map(|s| s.dissipation))
        .filter(|w| w.is_finite())
        .fold(0.0, f64::max);
    // A round top that only changes when W outgrows it, so the map does
    // not rescale with every run that arrives.
    let y1 = nice_ceiling(w_max);
    // On the log axis the decades from the smallest positive W up: the
    // spread between transients in cyclic slip (1e-5 to 1e-4) shows.
    let w_min = sweep
        .rows()
        .filter_map(|r| r.outcome.as_ref().ok().map(|s| s.dissipation))
        .filter(|w| w.is_finite() && *w > 0.0)
        .fold(f64::INFINITY, f64::min);
    let (d0, d1) = if w_min.is_finite() {
        (
            w_min.log10().floor(),
            w_max.log10().ceil().max(w_min.log10().floor() + 1.0),
        )
    } else {
        (-6.0, -1.0)
    };
    let y_of = move |w: f64| -> f64 {
        if log {
            if w > 0.0 {
                w.log10().max(d0)
            } else {
                d0
            }
        } else {
            w
        }
    };
    let (yb0, yb1) = if log { (d0, d1) } else { (0.0, y1) };
    let y_labels = if log {
        [
            format!("1e{}", d1 as i32),
            format!("1e{}", ((d0 + d1) / 2.0).round() as i32),
            format!("<1e{}", d0 as i32),
        ]
    } else {
        [w_label(y1), w_label(y1 / 2.0), "0".to_string()]
    };
    let label_width = y_labels
        .iter()
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(1) as u16
        + 1;
    let [y_axis, right] =
        Layout::horizontal([Constraint::Length(label_width), Constraint::Fill(1)]).areas(inner);
    let [canvas_area, x_axis] =
        Layout::vertical([Constraint::Fill(1), Constraint::Length(1)]).areas(right);

    // W labels at the top, middle and bottom rows of the canvas.
    let rows = canvas_area.height as usize;
    let mut lines = vec![Line::default(); rows];
    for (row, text) in [
        (0, &y_labels[0]),
        (rows / 2, &y_labels[1]),
        (rows - 1, &y_labels[2]),
    ] {
        lines[row] = Line::from(Span::styled(text.clone(), theme.label())).right_aligned();
    }
    if rows >= 4 {
        // The axis name, between the top and middle labels.
        lines[1] = Line::from(Span::styled(if log { "log W" } else { "W" }, theme.title()))
            .right_aligned();
    }
    frame.render_widget(
        Paragraph::new(lines),
        Rect::new(
            y_axis.x,
            y_axis.y,
            y_axis.width.saturating_sub(1),
            rows as u16,
        ),
    );

    // x labels: the ends, the axis name, and a caret under the cursor so
    // the column shows even before its runs arrive.
    let width = x_axis.width as usize;
    let mut row: Vec<char> = vec![' '; width];
    let mut put = |at: usize, text: &str| {
        for (i, c) in text.chars().enumerate() {
            if let Some(cell) = row.get_mut(at + i) {
                *cell = c;
            }
        }
    };
    let left = x_label(axis, x0);
    let right_text = x_label(axis, x1);
    put(0, &left);
    put(
        width.saturating_sub(right_text.chars().count()),
        &right_text,
    );
    let name = axis_name(axis);
    put((width.saturating_sub(name.len())) / 2, name);
    let col = |x: f64| -> usize {
        let t = ((x - x0) / (x1 - x0)).clamp(0.0, 1.0);
        (t * (width.saturating_sub(1)) as f64).round() as usize
    };
    let cursor_x = sweep.selected().map(|(job, _)| sweep.x_of(job));
    let text: String = row.into_iter().collect();
    let mut spans = vec![Span::styled(text, theme.label())];
    if let Some(x) = cursor_x {
        // Split the label row at the caret so it can carry its own style.
        let c = col(x);
        let chars: Vec<char> = spans[0].content.chars().collect();
        let before: String = chars[..c.min(chars.len())].iter().collect();
        let after: String = chars
            .get(c + 1..)
            .map_or(String::new(), |s| s.iter().collect());
        // On a tick label the caret is that character in reverse video, so
        // the label stays readable; elsewhere a ▲.
        let caret = match chars.get(c) {
            Some(&ch) if ch != ' ' => Span::styled(
                ch.to_string(),
                theme.value().add_modifier(Modifier::REVERSED),
            ),
            _ => Span::styled("▲", theme.value()),
        };
        spans = vec![
            Span::styled(before, theme.label()),
            caret,
            Span::styled(after, theme.label()),
        ];
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), x_axis);

    let limit = match sweep.limit() {
        LimitState::Known(l) => Some(l.load_factor),
        _ => None,
    };
    let limit_style = theme.fg(Color::LightCyan);
    let limit_color = theme.color(Color::LightCyan);
    let selected = sweep.selected().and_then(|(_, r)| r);
    let canvas = Canvas::default()
        .marker(Marker::Braille)
        .x_bounds([x0, x1])
        .y_bounds([yb0, yb1])
        .paint(move |ctx| {
            if let Some(l2) = limit.filter(|l| (x0..=x1).contains(l)) {
                ctx.draw(&CanvasLine::new(l2, yb0, l2, yb1, limit_color));
            }
            ctx.layer();
            // Markers are text, printed over the lines in the order given;
            // the selected run goes last so nothing hides it.
            for row in sweep.rows() {
                let (x, y) = point(sweep, row);
                let (glyph, color, _) = marker(row.state());
                ctx.print(x, y_of(y), Span::styled(glyph, theme.fg(color)));
            }
            if let Some(l2) = limit.filter(|l| (x0..=x1).contains(l)) {
                ctx.print(l2, yb1, Span::styled(format!("λ2={l2:.2}"), limit_style));
            }
            if let Some(row) = selected {
                let (x, y) = point(sweep, row);
                let (glyph, color, _) = marker(row.state());
                let style = theme
                    .fg(color)
                    .add_modifier(Modifier::REVERSED | Modifier::BOLD);
                ctx.print(x, y_of(y), Span::styled(glyph, style));
            }
        });
    frame.render_widget(canvas, canvas_area);
}

/// A `W` tick: [`tick`] unless it would round (2.5e-3 is not 3e-3).
fn w_label(v: f64) -> String {
    let t = tick(v);
    match t.parse::<f64>() {
        Ok(p) if (p - v).abs() <= 1e-9 * v.abs().max(1e-300) => t,
        _ => format!("{v:.1e}"),
    }
}

/// Where a run's marker goes; a failed run has no `W` and sits on the axis.
fn point(sweep: &Sweep, row: &Row) -> (f64, f64) {
    let w = match &row.outcome {
        Ok(s) if s.dissipation.is_finite() => s.dissipation,
        _ => 0.0,
    };
    (sweep.x_of(&row.job), w)
}

fn render_legend(frame: &mut Frame, area: Rect, sweep: &Sweep, theme: &Theme) {
    let mut counts = [0usize; STATES.len()];
    for row in sweep.rows() {
        if let Some(i) = STATES.iter().position(|s| *s == row.state()) {
            counts[i] += 1;
        }
    }
    let mut lines: Vec<Line> = STATES
        .iter()
        .zip(counts)
        .map(|(&state, n)| {
            let (glyph, color, text) = marker(state);
            Line::from(vec![
                Span::styled(format!(" {glyph} "), theme.fg(color)),
                Span::styled(format!("{text:<24}"), theme.label()),
                Span::styled(format!("{n:>3}"), theme.value()),
            ])
        })
        .collect();
    let limit = match sweep.limit() {
        LimitState::NotShown => "not a line on this map".to_string(),
        LimitState::Computing => "computing…".to_string(),
        LimitState::Known(l) => format_load_factor((l.load_factor * 1e3).round() / 1e3),
        LimitState::Failed(e) => format!("failed: {e}"),
    };
    lines.push(Line::from(vec![
        Span::styled(" │ ", theme.fg(Color::LightCyan)),
        Span::styled("lambda_2 = ", theme.label()),
        Span::styled(limit, theme.value()),
    ]));
    frame.render_widget(Paragraph::new(lines).block(theme.panel(" Legend ")), area);
}

fn render_details(frame: &mut Frame, area: Rect, sweep: &Sweep, theme: &Theme) {
    let label = |s: &str| Span::styled(format!(" {s:<7}"), theme.label());
    let value = |s: String| Span::styled(s, theme.value());
    let mut lines = Vec::new();
    if let Some((job, row)) = sweep.selected() {
        let initials = sweep.source().spec.initials().len();
        lines.push(Line::from(vec![
            label("lambda"),
            value(format_load_factor(job.load_factor)),
            Span::styled("  phi ", theme.label()),
            value(format_phase(job.phase)),
        ]));
        lines.push(Line::from(vec![
            label("path"),
            value(sweep.initial(job).name()),
            Span::styled(format!(" ({}/{initials})", job.initial + 1), theme.label()),
        ]));
        match row.map(|r| &r.outcome) {
            None => lines.push(Line::from(vec![
                label("state"),
                Span::styled("not run yet", theme.dim()),
            ])),
            Some(Ok(s)) => {
                let (glyph, color, name) = marker(RowState::Steady(s.state()));
                lines.push(Line::from(vec![
                    label("state"),
                    Span::styled(format!("{glyph} "), theme.fg(color)),
                    value(name.to_string()),
                ]));
                lines.push(Line::from(vec![
                    label("W"),
                    value(format_sci(s.dissipation)),
                    Span::styled("  cycles ", theme.label()),
                    value(s.cycles.to_string()),
                ]));
            }
            Some(Err(e)) => {
                lines.push(Line::from(vec![
                    label("state"),
                    Span::styled("! failed", theme.error()),
                ]));
                lines.push(Line::from(Span::styled(format!(" {e}"), theme.dim())));
            }
        }
        // W of every transient at this x: the spread the paper reads.
        // The table scrolls with the selection: it is never off screen.
        let x = sweep.x_of(job);
        let column: Vec<_> = sweep.jobs().iter().filter(|j| sweep.x_of(j) == x).collect();
        let rows = usize::from(area.height.saturating_sub(2))
            .saturating_sub(lines.len() + 1)
            .max(1);
        let at = column
            .iter()
            .position(|j| j.index == job.index)
            .unwrap_or(0);
        let first = at
            .saturating_sub(rows / 2)
            .min(column.len().saturating_sub(rows));
        let last = (first + rows).min(column.len());
        lines.push(Line::from(Span::styled(
            if column.len() > rows {
                format!(" at this x ({}-{last} of {}):", first + 1, column.len())
            } else {
                " at this x:".to_string()
            },
            theme.label(),
        )));
        for other in &column[first..last] {
            let row = sweep.rows().find(|r| r.job.index == other.index);
            let (glyph, w) = match row.map(|r| (&r.outcome, r.state())) {
                None => (" ", "…".to_string()),
                Some((Ok(s), st)) => (marker(st).0, format_sci(s.dissipation)),
                Some((Err(_), st)) => (marker(st).0, "failed".into()),
            };
            let mark = if other.index == job.index { ">" } else { " " };
            lines.push(Line::from(vec![
                Span::styled(
                    format!(" {mark}{:<8}", sweep.initial(other).name()),
                    theme.label(),
                ),
                Span::styled(format!("{glyph} "), theme.value()),
                Span::styled(w, theme.value()),
            ]));
        }
    } else {
        lines.push(Line::from(Span::styled(" no runs", theme.dim())));
    }
    frame.render_widget(
        Paragraph::new(lines)
            .wrap(ratatui::widgets::Wrap { trim: false })
            .block(theme.panel(" Selected run ")),
        area,
    );
}

fn render_status(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let label = |s: &str| Span::styled(s.to_string(), theme.label());
    let mut line1 = vec![label(" sweep view")];
    if let Ok(s) = app.sweep() {
        line1.extend(progress_spans(
            theme,
            ": ",
            s.source().name.clone(),
            (s.done(), s.total()),
            (s.is_running(), s.started()),
            ("running in the background", "stopped"),
            s.time_left(),
        ));
    }
    let used: usize = line1.iter().map(Span::width).sum();
    let regime = "   g: regime map over (lambda, phi)";
    line1.push(label(if used + regime.len() <= usize::from(area.width) {
        regime
    } else {
        "   g: regime map"
    }));
    let hint = if area.width >= 100 {
        " Esc back  ←→ PgUp PgDn Home End x  ↑↓ run  Enter open  w log W  s save  r rerun  ? help  q quit"
    } else {
        " Esc back  ←→ x  ↑↓ run  Enter open  w log W  s save  r rerun  ? help  q quit"
    };
    render_status_lines(frame, area, app, theme, line1, hint);
}

/// What a background computation has done: `join`, its `name`, a gauge
/// with `done` of `total` runs and, while it runs, about how long the rest
/// will take (`left`); else its state: done, stopped (the second of
/// `words`) or not started.
pub(super) fn progress_spans(
    theme: &Theme,
    join: &str,
    name: String,
    (done, total): (usize, usize),
    (running, started): (bool, bool),
    words: (&str, &str),
    left: Option<std::time::Duration>,
) -> Vec<Span<'static>> {
    let label = |s: String| Span::styled(s, theme.label());
    let state = if running {
        Span::styled(
            match left {
                Some(t) => format!("about {} left", format_duration(t)),
                None => words.0.to_string(),
            },
            theme.fg(Color::LightGreen),
        )
    } else if done == total {
        Span::styled("done", theme.value())
    } else if started {
        Span::styled(words.1.to_string(), theme.alert())
    } else {
        Span::styled("not started", theme.alert())
    };
    let mut spans = vec![
        label(join.to_string()),
        Span::styled(name, theme.value()),
        label(", ".to_string()),
    ];
    if running {
        spans.push(Span::styled(
            gauge(done, total, 10),
            theme.fg(Color::LightGreen),
        ));
        spans.push(label(" ".to_string()));
    }
    spans.push(label(format!("{done}/{total} runs, ")));
    spans.push(state);
    spans
}

/// A bar of `width` cells, filled in proportion to `done` of `total`.
pub fn gauge(done: usize, total: usize, width: usize) -> String {
    let filled = (done * width).checked_div(total).unwrap_or(0).min(width);
    format!("{}{}", "█".repeat(filled), "░".repeat(width - filled))
}

/// `45 s`, `3 min 20 s`, `1 h 5 min`: a time left, to the second that
/// matters.
pub fn format_duration(t: std::time::Duration) -> String {
    let s = t.as_secs();
    match s {
        0..=59 => format!("{s} s"),
        60..=3599 => format!("{} min {} s", s / 60, s % 60),
        _ => format!("{} h {} min", s / 3600, (s % 3600) / 60),
    }
}

/// The three status lines of the sweep view and its regime map: `line1`
/// (what is running), the question waiting for `y` or the last notice,
/// and the keys (`hint`).
pub(super) fn render_status_lines(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    theme: &Theme,
    line1: Vec<Span>,
    hint: &str,
) {
    let line2 = match app.confirm() {
        Some(crate::tui::app::Confirm::Quit(_)) => Line::from(Span::styled(
            " the sweep map is not saved (s saves): quit anyway? y/n",
            theme.error(),
        )),
        Some(crate::tui::app::Confirm::RestartSweep) => Line::from(Span::styled(
            " discard this map and rerun the sweep? y/n",
            theme.error(),
        )),
        Some(crate::tui::app::Confirm::Overwrite) => Line::from(Span::styled(
            format!(
                " {} exists: overwrite? y/N",
                app.save_path()
                    .map_or(String::new(), |p| p.display().to_string())
            ),
            theme.error(),
        )),
        None => match app.save_entry() {
            Some(name) => Line::from(vec![
                Span::styled(" save as: ", theme.label()),
                Span::styled(format!("{name}_"), theme.value()),
                Span::styled("  (Enter saves, Esc cancels)", theme.label()),
            ]),
            None => Line::from(Span::styled(
                format!(" {}", app.notice().unwrap_or("")),
                theme.alert(),
            )),
        },
    };
    // While the tour has the keys, its keys are the ones to show.
    let line3 = if app.mode() == crate::tui::keys::Mode::Tour {
        super::footer_line(app.mode(), usize::from(area.width), theme)
    } else {
        Line::from(Span::styled(hint.to_string(), theme.label()))
    };
    // Each line cut with an ellipsis where it does not fit.
    let width = usize::from(area.width);
    let lines = [Line::from(line1), line2, line3]
        .into_iter()
        .map(|line| Line::from(super::fit_spans(line.spans, width)))
        .collect::<Vec<_>>();
    frame.render_widget(Paragraph::new(lines).style(Style::default()), area);
}
