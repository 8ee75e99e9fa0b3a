//! The help overlay, generated from the key table that dispatches keys.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Row, Table, Widget};

use super::Theme;
use crate::tui::keys::{bindings_for, Binding, Mode};

/// The keys of one mode: the arrows mean different things per mode.
pub struct Help<'a> {
    pub mode: Mode,
    pub theme: &'a Theme,
}

impl Widget for Help<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let theme = self.theme;
        let bindings: Vec<&Binding> = bindings_for(self.mode).collect();
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
        let width = (key_width + help_width + 3).min(area.width);
        let height = (bindings.len() as u16 + 2).min(area.height);
        let rect = Rect::new(
            area.x + (area.width - width) / 2,
            area.y + (area.height - height) / 2,
            width,
            height,
        );
        // Two columns when the list does not fit the height.
        let rows = bindings.iter().map(|b| {
            Row::new(vec![
                Line::from(Span::styled(b.label, theme.value())).right_aligned(),
                Line::from(Span::styled(b.help, theme.label())),
            ])
        });
        let two = bindings.len() as u16 + 2 > area.height
            && area.width >= 2 * (key_width + help_width) + 5;
        let (rect, rows): (Rect, Vec<Row>) = if bindings.len() as u16 + 2 > area.height
            && area.width >= 2 * (key_width + help_width) + 5
        {
            let half = bindings.len().div_ceil(2);
            let w2 = 2 * (key_width + help_width) + 5;
            let r = Rect::new(
                area.x + (area.width - w2) / 2,
                area.y + (area.height - (half as u16 + 2).min(area.height)) / 2,
                w2,
                (half as u16 + 2).min(area.height),
            );
            let pairs = (0..half)
                .map(|i| {
                    let cell = |j: usize| {
                        bindings
                            .get(j)
                            .map_or((Line::from(""), Line::from("")), |b| {
                                (
                                    Line::from(Span::styled(b.label, theme.value()))
                                        .right_aligned(),
                                    Line::from(Span::styled(b.help, theme.label())),
                                )
                            })
                    };
                    let (a, b) = cell(i);
                    let (c, d) = cell(i + half);
                    Row::new(vec![a, b, c, d])
                })
                .collect();
            (r, pairs)
        } else {
            (rect, rows.collect())
        };
        let widths: Vec<Constraint> = if two {
            vec![
                Constraint::Length(key_width),
                Constraint::Length(help_width),
                Constraint::Length(key_width),
                Constraint::Fill(1),
            ]
        } else {
            vec![Constraint::Length(key_width), Constraint::Fill(1)]
        };
        let title = match self.mode {
            Mode::Stepping => " Keys: stepping view ",
            Mode::Sweep => " Keys: sweep view ",
            Mode::Log => " Keys: event log ",
            Mode::Regime => " Keys: regime map ",
            Mode::Tour => " Keys: guided tour ",
        };
        // The mouse wheel is no key, but says what it does here too.
        let wheel = match self.mode {
            Mode::Stepping => " wheel: history · ? or Esc closes ",
            Mode::Sweep => " wheel: transients · ? or Esc closes ",
            Mode::Log => " wheel: the log · ? or Esc closes ",
            Mode::Regime => " wheel: phi rows · ? or Esc closes ",
            Mode::Tour => " ? closes · Esc leaves the tour ",
        };
        let foot = super::first_fitting(
            vec![
                Line::from(Span::styled(wheel, theme.label())),
                Line::from(Span::styled(" ? or Esc closes ", theme.label())),
            ],
            rect.width.saturating_sub(2) as usize,
        );
        let table = Table::new(rows, widths)
            .column_spacing(1)
            .block(theme.panel(title).title_bottom(foot));
        Clear.render(rect, buf);
        table.render(rect, buf);
    }
}
