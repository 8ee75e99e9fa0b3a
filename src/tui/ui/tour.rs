//! The guided tour's caption panel: `Tour k/n: <title>` and two or three
//! sentences on what the case on screen shows.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Widget, Wrap};

use super::Theme;
use crate::tui::app::tour::{Stop, STOPS};

/// Rows the caption takes: its border and four lines of text.
pub const CAPTION_HEIGHT: u16 = 6;

/// The caption of stop `index`.
pub struct Caption<'a> {
    pub index: usize,
    pub stop: &'a Stop,
    pub theme: &'a Theme,
}

impl Widget for Caption<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let theme = self.theme;
        let title = format!(
            " Tour {}/{}: {} ",
            self.index + 1,
            STOPS.len(),
            self.stop.title
        );
        let hint = Line::from(Span::styled(
            " n next · N back · Space run/pause · Esc take over ",
            theme.label(),
        ));
        let block = theme.panel(title).title_bottom(hint.right_aligned());
        let text = if theme.ascii() {
            self.stop.caption.to_string()
        } else {
            greek(self.stop.caption)
        };
        Paragraph::new(text)
            .wrap(Wrap { trim: true })
            .block(block)
            .render(area, buf);
    }
}

/// The captions are written in ASCII (so `--ascii` shows them whole);
/// with Unicode they read with the paper's letters.
fn greek(text: &str) -> String {
    text.replace("lambda_1", "λ₁")
        .replace("lambda_2", "λ₂")
        .replace("lambda_3", "λ₃")
        .replace("lambda", "λ")
        .replace("phi", "φ")
        .replace("theta", "θ")
        .replace(" pi", " π")
        .replace("<=", "≤")
}
