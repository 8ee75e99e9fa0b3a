//! The help overlay, generated from the key table that dispatches keys.

use ratatui::layout::{Constraint, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Row, Table};
use ratatui::Frame;

use super::Theme;
use crate::tui::keys::{bindings_for, Binding, View};

/// The keys of `view` only: the arrows mean different things per view.
pub fn render(frame: &mut Frame, area: Rect, theme: &Theme, view: View) {
    let bindings: Vec<&Binding> = bindings_for(view).collect();
    let key_width = bindings
        .iter()
        .map(|b| b.label.chars().count())
        .max()
        .unwrap_or(0) as u16;
    let help_width = bindings
        .iter()
        .map(|b| b.help.chars().count())
        .max()
        .unwrap_or(0) as u16;
    let width = (key_width + help_width + 7).min(area.width);
    let height = (bindings.len() as u16 + 2).min(area.height);
    let rect = Rect::new(
        area.x + (area.width - width) / 2,
        area.y + (area.height - height) / 2,
        width,
        height,
    );
    let rows = bindings.iter().map(|b| {
        Row::new(vec![
            Line::from(Span::styled(b.label, theme.value())).right_aligned(),
            Line::from(Span::styled(b.help, theme.label())),
        ])
    });
    let table = Table::new(rows, [Constraint::Length(key_width), Constraint::Fill(1)])
        .column_spacing(2)
        .block(
            theme
                .panel(match view {
                    View::Stepping => " Keys: stepping view ",
                    View::Sweep => " Keys: sweep view ",
                })
                .title_bottom(Line::from(Span::styled(" ? or Esc closes ", theme.label()))),
        );
    frame.render_widget(Clear, rect);
    frame.render_widget(table, rect);
}
