//! The guided tour's caption panel: `Tour k/n: <title>` and two or three
//! sentences on what the case on screen shows.

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::{Borders, Padding, Paragraph, Widget, Wrap};

use super::Theme;
use crate::tui::app::tour::{Stop, STOPS};

/// Rows the caption of `stop` takes at `width` columns: its title line and
/// its text wrapped, at most four lines.
pub fn caption_height(stop: &Stop, width: u16) -> u16 {
    let width = usize::from(width.saturating_sub(2)).max(20);
    let (mut lines, mut used) = (1usize, 0usize);
    for word in stop.caption.split_whitespace() {
        let w = word.chars().count();
        if used > 0 && used + 1 + w > width {
            lines += 1;
            used = w;
        } else {
            used += w + usize::from(used > 0);
        }
    }
    1 + lines.min(4) as u16
}

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
        // A rule with the title over the text: the footer just above
        // gives the tour's keys.
        let block = theme.panel(title).borders(Borders::TOP);
        let text = if theme.ascii() {
            self.stop.caption.to_string()
        } else {
            greek(self.stop.caption)
        };
        Paragraph::new(text)
            .wrap(Wrap { trim: true })
            .block(block.padding(Padding::horizontal(1)))
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
