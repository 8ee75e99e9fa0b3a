//! The event log overlay: every event with its increment, cycle, `omega t`,
//! load point and `theta` range, wrapped rather than cut, scrolled so the
//! selected event is in view.

use std::f64::consts::PI;

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph, Widget};

use super::Theme;
use crate::tui::app::App;
use crate::tui::log::{format_theta, LogEntry};

/// The event log widget.
pub struct EventLog<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

/// The columns before the text, and the text.
fn columns(e: &LogEntry) -> (String, String) {
    let time = e
        .time
        .map_or("  –  ".to_string(), |t| format!("{:5.3}", t / PI));
    let head = format!(
        "{:>7} {:>4} {time} ({:6.2},{:6.2}) {:<11} ",
        format!("#{}", e.increment + 1),
        if e.cycle == 0 {
            "T".to_string()
        } else {
            e.cycle.to_string()
        },
        e.load.0,
        e.load.1,
        format_theta(e.theta),
    );
    (head, e.text.clone())
}

/// `text` in pieces of at most `width` characters, at spaces when it can.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let width = width.max(8);
    let mut out = vec![String::new()];
    for word in text.split(' ') {
        let last = out.last_mut().expect("never empty");
        let need = last.chars().count() + usize::from(!last.is_empty()) + word.chars().count();
        if need <= width || last.is_empty() {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        } else {
            out.push(word.to_string());
        }
    }
    out
}

impl Widget for EventLog<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let entries = app.log_entries();
        let filter = app.filter();
        let dropped = app.log_dropped();
        let title = format!(
            " Event log: {} of {} · {} ",
            entries.len(),
            app.log().len() + dropped,
            if filter.kind.is_some() {
                filter.describe()
            } else {
                "all kinds".into()
            }
        );
        let block = theme.panel(title).title_bottom(Line::from(Span::styled(
            " ↑↓ PgUp PgDn Home End move · Enter shows it · k kind · m size · L closes ",
            theme.label(),
        )));
        let inner = block.inner(area);
        Clear.render(area, buf);
        block.render(area, buf);
        if inner.height < 2 || inner.width < 20 {
            return;
        }
        let header = Line::from(Span::styled(
            format!(
                "{:>7} {:>4} {:5} ({:>6},{:>6}) {:<11} what",
                "incr", "cyc", "wt/pi", "x", "y", "theta/pi"
            ),
            theme.title(),
        ));
        let width = usize::from(inner.width);
        let rows = usize::from(inner.height) - 1;
        let selected = app.log_selected().min(entries.len().saturating_sub(1));
        // Lines of the entries around the selection, wrapped.
        let mut lines: Vec<Line> = Vec::new();
        let mut sel_line = 0;
        let start = selected.saturating_sub(rows);
        for (i, e) in entries.iter().enumerate().skip(start).take(2 * rows + 1) {
            let (head, text) = columns(e);
            let head_w = head.chars().count();
            let (first_w, indent) = if width > head_w + 16 {
                (width - head_w, head_w)
            } else {
                (width, 2)
            };
            let style = if i == selected {
                theme
                    .value()
                    .add_modifier(ratatui::style::Modifier::REVERSED)
            } else {
                theme.label()
            };
            if i == selected {
                sel_line = lines.len();
            }
            let pieces = if first_w == width {
                lines.push(Line::from(Span::styled(head.clone(), style)));
                wrap(&text, width - indent)
            } else {
                let mut p = wrap(&text, first_w);
                let first = p.remove(0);
                lines.push(Line::from(vec![
                    Span::styled(head.clone(), style),
                    Span::styled(first, style),
                ]));
                let rest = p.join(" ");
                if rest.is_empty() {
                    Vec::new()
                } else {
                    wrap(&rest, width - indent)
                }
            };
            for piece in pieces {
                lines.push(Line::from(Span::styled(
                    format!("{}{piece}", " ".repeat(indent)),
                    style,
                )));
            }
        }
        if entries.is_empty() {
            lines.push(Line::from(Span::styled(
                " no events of this kind yet",
                theme.dim(),
            )));
        }
        let skip = sel_line.saturating_sub(rows.saturating_sub(2));
        let mut shown: Vec<Line> = vec![header];
        shown.extend(lines.into_iter().skip(skip).take(rows));
        if dropped > 0 {
            shown.truncate(rows);
            shown.push(Line::from(Span::styled(
                format!(" ({dropped} older events dropped)"),
                theme.alert(),
            )));
        }
        Paragraph::new(shown).render(inner, buf);
    }
}

#[cfg(test)]
mod tests {
    use super::wrap;

    #[test]
    fn wrap_keeps_every_word() {
        let text = "backward slip zone split (2 zones now) and more words here";
        let pieces = wrap(text, 12);
        assert!(pieces.iter().all(|p| p.chars().count() <= 12));
        assert_eq!(pieces.join(" "), text);
    }
}
