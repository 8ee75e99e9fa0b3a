//! The status lines: the case, the instant on screen, what the run has
//! become, what was lost from history, and what just happened.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Widget};

use super::Theme;
use crate::stepping::{Phase, Status};
use crate::tui::app::{format_load_factor, format_phase, format_sci, App, Confirm, Goal};
use crate::tui::log::format_theta;

/// Columns of an event's text kept, at least, when a notice shares its
/// line (the event log has it whole).
const EVENT_MIN: usize = 20;

/// The status lines widget.
pub struct StatusLines<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl Widget for StatusLines<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        render(buf, area, self.app, self.theme);
    }
}

fn render(buf: &mut Buffer, area: Rect, app: &App, theme: &Theme) {
    let case = app.case();
    let label = |s: &str| Span::styled(s.to_string(), theme.label());
    let value = |s: String| Span::styled(s, theme.value());
    let sep = || Span::styled(theme.sym("  │ ", "  | "), theme.dim());

    let wide = area.width >= 100;
    let width = area.width as usize;
    let path = &app.paths()[app.path_index()];
    let mut line1 = Line::from(vec![
        label(" lambda = "),
        value(format_load_factor(app.load_factor())),
        label("  phi = "),
        value(format_phase(app.phase())),
        label("  psi = "),
        value(format!("{}", case.cycle().slope())),
        label("  path "),
        value(path.name()),
        label(format!(" ({}/{})", app.path_index() + 1, app.paths().len()).as_str()),
    ]);
    if wide {
        line1
            .spans
            .extend([sep(), label("N "), value(case.disc().nodes().to_string())]);
    }

    let shown = app.shown();
    let steps = case.disc().steps_per_cycle();
    // One counter: live or in the history, where the run is after the
    // increment on screen (increments done in the cycle, and in all).
    let (history_at, after) = match (app.cursor(), shown) {
        (Some(_), Some(r)) => (true, r.after),
        _ => (false, app.stepper_phase()),
    };
    let (where_label, mut where_value) = match after {
        Phase::Transient { segment, increment } => (
            " transient ",
            format!(
                "seg {}/{} incr {}",
                segment + 1,
                app.transient().len().max(1),
                increment
            ),
        ),
        Phase::Cycle { cycle, increment } => {
            (" cycle ", format!("{cycle}  incr {increment}/{steps}"))
        }
    };
    let where_label = if history_at {
        where_value = format!("{}{where_value}", where_label.trim_start());
        " history "
    } else {
        where_label
    };
    // Paused at an event inside an increment: say where, exactly.
    let inside = match (app.cursor(), shown) {
        (None, Some(r)) => r.partial.map(|_| r.load),
        _ => None,
    };
    let (state, state_style) = match app.status() {
        Status::Running => ("unclassified".to_string(), theme.label()),
        Status::Steady(s) if wide => (
            format!("{} (cycle {})", s.state().as_str(), s.cycles),
            theme.alert(),
        ),
        Status::Steady(s) => (s.state().as_str().to_string(), theme.alert()),
        Status::Ended(s) => {
            let at = s
                .terminal_load()
                .map(|p| format!(" at ({:.2}, {:.2})", p.x(), p.y()))
                .unwrap_or_default();
            (format!("{}{at}", s.state().as_str()), theme.error())
        }
    };
    let mut line2 = Line::from(vec![label(where_label), value(where_value)]);
    if let Some((x, y)) = inside {
        line2
            .spans
            .extend([label(" + event at "), value(format!("({x:.4}, {y:.4})"))]);
    }
    if wide {
        // The same count live and in the history.
        let total = match (app.cursor(), shown) {
            (Some(_), Some(r)) => r.increment + usize::from(r.partial.is_none()),
            _ => app.increments(),
        };
        line2
            .spans
            .extend([label("  total "), value(total.to_string())]);
    }
    line2
        .spans
        .extend([sep(), label("state "), Span::styled(state, state_style)]);
    let history = app.history();
    let lost = match (history.dropped_before(), history.thinned_before()) {
        (Some(d), _) => Some(format!("history from #{}", d + 1)),
        (None, Some((t, k))) => Some(format!("before #{} detail 1/{k}", t + 1)),
        _ => None,
    };
    if let Some(l) = lost {
        line2.spans.extend([sep(), Span::styled(l, theme.alert())]);
    }
    if let Some(p) = app.pinned() {
        // The pinned run's state is the point of the comparison; its label
        // (lambda, phi, path) was said when it was pinned.
        let room = width.saturating_sub(line2.width() + 12);
        let text = [
            format!("{}: {}", p.label, p.state),
            format!("{}: {}", p.path, p.state),
        ]
        .into_iter()
        .find(|t| t.chars().count() <= room)
        .unwrap_or_else(|| format!("{}: {}", p.path, p.state));
        line2.spans.extend([sep(), label("pinned "), value(text)]);
    }
    let line2 = Line::from(super::fit_spans(line2.spans, width));

    let mode = match (app.goal(), app.is_running()) {
        (Some(Goal::Steady), _) => match app.steady_progress() {
            // k of about n cycles, and the change of W the rule watches.
            Some(p) => {
                let mut text = format!("» steady: cycle {}", p.cycles);
                if let Some(k) = p.cycles_left {
                    text = format!(
                        "» steady {} cycle {}/~{}",
                        super::sweep_view::gauge(p.cycles, p.cycles + k, 8),
                        p.cycles,
                        p.cycles + k
                    );
                }
                if let Some(c) = p.change {
                    text.push_str(&format!(
                        ", dW/W {} (to {})",
                        format_sci(c),
                        format_sci(p.tolerance)
                    ));
                }
                if let Some(t) = p.left {
                    text.push_str(&format!(
                        ", about {} left",
                        super::sweep_view::format_duration(t)
                    ));
                }
                text
            }
            None => "» steady".to_string(),
        },
        (Some(Goal::CycleEnd(_)), _) => "» cycle end".to_string(),
        (Some(Goal::TransientEnd), _) => "» transient end".to_string(),
        (None, true) => format!("▶ {}/frame", app.speed()),
        (None, false) => format!("‖ paused {}/frame", app.speed()),
    };
    let mode = if theme.ascii() {
        mode.replace('»', ">>").replace('▶', ">").replace('‖', "||")
    } else {
        mode
    };
    let mut spans = vec![
        Span::raw(" "),
        Span::styled(
            mode,
            if app.is_running() || app.goal().is_some() {
                theme.fg(Color::LightGreen)
            } else {
                theme.alert()
            },
        ),
        label(if app.pauses_on_events() {
            " e:on"
        } else {
            " e:off"
        }),
        sep(),
    ];
    if let Some(c) = app.confirm() {
        spans.push(Span::styled(
            match c {
                Confirm::Quit(_) => "the sweep map is not saved: quit anyway? y/n",
                Confirm::RestartSweep => "discard the sweep map and rerun? y/n",
                Confirm::Overwrite => "the file exists: overwrite? y/N",
            },
            theme.error(),
        ));
    } else if let Some(text) = app.entry() {
        let room = width.saturating_sub(spans.iter().map(Span::width).sum());
        let prompt = [
            format!(": {text}_  (lambda = 5.13, phi = pi/4, path = OA; Enter, Esc)"),
            format!(": {text}_  (lambda = 5.13, phi = pi/4, path = OA)"),
            format!(": {text}_  (lambda = 5.13, phi, path)"),
        ]
        .into_iter()
        .find(|p| p.chars().count() <= room)
        .unwrap_or_else(|| format!(": {text}_"));
        spans.extend(super::fit_spans(
            vec![Span::styled(prompt, theme.alert())],
            room,
        ));
    } else if let Some(f) = app.failure() {
        spans.push(Span::styled(format!("solver failed: {f}"), theme.error()));
    } else {
        // At a history instant, its own events; live, the last one.
        let event = match (app.cursor(), shown) {
            (Some(_), Some(r)) => r
                .events
                .first()
                .map(|e| format!("{} (theta/pi {})", e.text, format_theta(e.theta))),
            _ => app.last_event().map(str::to_string),
        }
        .unwrap_or_else(|| "–".into());
        // One column spare: a line that reaches the edge reads as cut.
        let room = width.saturating_sub(spans.iter().map(Span::width).sum::<usize>() + 1);
        let notice = app.notice().unwrap_or_default();
        let (n, e) = (notice.chars().count(), event.chars().count());
        let sep_width = sep().width();
        let all = if notice.is_empty() { 0 } else { n + sep_width };
        if all + "event: ".len() + e <= room {
            if !notice.is_empty() {
                spans.push(Span::styled(notice.to_string(), theme.alert()));
                spans.push(sep());
            }
            spans.push(label("event: "));
            spans.push(Span::raw(event));
        } else {
            // Too long for the line: no "event: " label, and if that is
            // not enough, the notice takes at most half and the event the
            // rest, each cut with `…` (the event log has every event whole).
            let mut rest = room;
            if !notice.is_empty() {
                // The notice answers the last key: whole if the event
                // keeps a readable start.
                let keep = if all + e.min(EVENT_MIN) <= room {
                    n
                } else {
                    n.min(
                        (room / 2)
                            .saturating_sub(sep_width)
                            .max(room.saturating_sub(e + sep_width)),
                    )
                };
                let cut =
                    super::fit_spans(vec![Span::styled(notice.to_string(), theme.alert())], keep);
                rest = rest.saturating_sub(cut.iter().map(Span::width).sum::<usize>() + sep_width);
                spans.extend(cut);
                spans.push(sep());
            }
            spans.extend(super::fit_spans(vec![Span::raw(event)], rest));
        }
    }
    let line3 = Line::from(spans);

    let footer = super::footer_line(app.mode(), width, theme);
    Paragraph::new(vec![line1, line2, line3, footer]).render(area, buf);
    let _ = format_sci;
}
