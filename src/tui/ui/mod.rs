//! Layout and drawing. Each panel is one file; this one decides where the
//! panels go for the terminal's size and holds what they share.

mod dissipation;
mod event_log;
mod help;
mod load_plane;
mod profile;
mod regime_view;
mod slip;
mod slip_map;
mod status;
mod sweep_view;
mod tour;
mod tractions;

use ratatui::buffer::Buffer;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::{border, Marker};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, BorderType, Paragraph, Wrap};
use ratatui::Frame;

use super::app::{App, View};

/// The smallest terminal the layout is made for.
pub const MIN_WIDTH: u16 = 80;
/// The smallest terminal height the layout is made for (see [`MIN_WIDTH`]).
pub const MIN_HEIGHT: u16 = 24;

/// Draw the whole screen.
pub fn draw(frame: &mut Frame, app: &App) {
    let area = frame.area();
    let config = app.config();
    let theme = Theme::new(config.color)
        .with_ascii(config.ascii)
        .with_truecolor(config.truecolor);
    draw_screen(frame, area, app, &theme);
    if config.ascii {
        asciify(frame.buffer_mut());
    }
}

fn draw_screen(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        too_small(frame, area, theme);
        return;
    }
    // The tour's caption sits at the foot; the view draws above it.
    let area = match app.tour() {
        Some((index, stop)) => {
            let height = tour::caption_height(stop, area.width);
            let [view, caption] =
                Layout::vertical([Constraint::Fill(1), Constraint::Length(height)]).areas(area);
            frame.render_widget(tour::Caption { index, stop, theme }, caption);
            view
        }
        None => area,
    };
    if app.view() == View::Sweep {
        sweep_view::render(frame, area, app, theme);
    } else if app.view() == View::Regime {
        regime_view::render(frame, area, app, theme);
    } else {
        let areas = Areas::new(area);
        let (app, theme) = (app, theme);
        frame.render_widget(load_plane::LoadPlane { app, theme }, areas.load_plane);
        frame.render_widget(slip_map::SlipMap { app, theme }, areas.slip_map);
        if app.profile_panel().is_visible() {
            // The fretting profile of the last completed cycle in place of
            // the instant's profiles.
            frame.render_widget(profile::Envelopes { app, theme }, areas.tractions);
            frame.render_widget(profile::SlipAmplitude { app, theme }, areas.slip);
            frame.render_widget(
                profile::DissipationDensity { app, theme },
                areas.dissipation,
            );
        } else {
            frame.render_widget(tractions::Tractions { app, theme }, areas.tractions);
            frame.render_widget(slip::Slip { app, theme }, areas.slip);
            frame.render_widget(dissipation::Dissipation { app, theme }, areas.dissipation);
        }
        frame.render_widget(status::StatusLines { app, theme }, areas.status);
        if app.log_visible() {
            let [body, _] =
                Layout::vertical([Constraint::Fill(1), Constraint::Length(4)]).areas(area);
            frame.render_widget(event_log::EventLog { app, theme }, body);
        }
    }
    if app.help_visible() {
        frame.render_widget(
            help::Help {
                mode: app.mode(),
                theme,
            },
            area,
        );
    }
}

/// Replace what is not ASCII, as a last pass for terminals that have no
/// more (`--ascii`): Braille dots become `.`, lines `-`, `|` and `+`,
/// Greek letters their Latin initial.
pub fn asciify(buf: &mut Buffer) {
    for cell in buf.content.iter_mut() {
        let sym = cell.symbol();
        if sym.is_ascii() {
            continue;
        }
        let c = sym.chars().next().unwrap_or(' ');
        let r = match c {
            '\u{2800}' => " ",
            '\u{2801}'..='\u{28FF}' => ".",
            '─' | '━' | '┄' | '╌' | '–' | '—' => "-",
            '│' | '┃' | '┆' | '╎' => "|",
            '╭' | '╮' | '╰' | '╯' | '┌' | '┐' | '└' | '┘' | '┼' | '├' | '┤' | '┬' => {
                "+"
            }
            '┴' | '▲' => "^",
            '·' | '•' => ".",
            '×' | '✚' => "x",
            '●' | '◆' => "@",
            'π' => "p",
            'θ' => "t",
            'λ' => "l",
            'φ' => "f",
            'χ' => "c",
            'ḡ' => "g",
            '±' => "+",
            '«' | '»' => ">",
            '▶' => ">",
            '█' => "#",
            '░' => "-",
            '‖' => "|",
            '↑' => "^",
            '↓' => "v",
            '←' => "<",
            '→' => ">",
            '…' => ".",
            _ => "?",
        };
        cell.set_symbol(r);
    }
}

/// `spans` cut to `width` columns, with `…` where text was cut so that it
/// never looks complete when it is not (`..` is what `--ascii` makes of
/// it: `asciify` turns `…` into `.`).
pub fn fit_spans(spans: Vec<Span<'_>>, width: usize) -> Vec<Span<'_>> {
    let total: usize = spans.iter().map(Span::width).sum();
    if total <= width {
        return spans;
    }
    let mut out = Vec::new();
    let mut left = width.saturating_sub(1);
    for span in spans {
        let w = span.width();
        if w <= left {
            left -= w;
            out.push(span);
            continue;
        }
        let cut: String = span.content.chars().take(left).collect();
        out.push(Span::styled(format!("{}…", cut.trim_end()), span.style));
        return out;
    }
    out
}

/// The first of `lines` that fits in `width` columns, or the last cut to
/// fit: panels title their foot with the most that fits.
pub fn first_fitting(lines: Vec<Line<'_>>, width: usize) -> Line<'_> {
    let n = lines.len();
    for (i, line) in lines.into_iter().enumerate() {
        if line.width() <= width || i + 1 == n {
            if line.width() <= width {
                return line;
            }
            let style = line.style;
            return Line::from(fit_spans(line.spans, width)).style(style);
        }
    }
    Line::default()
}

/// Where each panel goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Areas {
    /// The load plane with the cycle and the load point, top left.
    pub load_plane: Rect,
    /// The slip map (node against increment), top right.
    pub slip_map: Rect,
    /// The pressure and shear profiles, bottom left.
    pub tractions: Rect,
    /// The slip profile `g` minus its mean, bottom middle.
    pub slip: Rect,
    /// The dissipation `W` per cycle, bottom right.
    pub dissipation: Rect,
    /// The three status lines and the footer of keys at the foot of the
    /// screen.
    pub status: Rect,
}

impl Areas {
    /// The slip map and the load plane share the top, the three profiles
    /// the bottom. The load plane is kept about as wide as it is tall on
    /// screen (a cell is about twice as tall as wide) so the diamond looks
    /// like one; the slip map takes the rest, because its width is time.
    pub fn new(area: Rect) -> Self {
        let status_height = 4;
        let [body, status] =
            Layout::vertical([Constraint::Fill(1), Constraint::Length(status_height)]).areas(area);
        // At least 11 rows for the load plane, unless the bottom row of
        // panels would keep fewer than 7 (a tour's caption takes room).
        let top_height = (body.height * 4)
            .div_ceil(7)
            .max(11)
            .min(body.height.saturating_sub(7));
        let [top, bottom] =
            Layout::vertical([Constraint::Length(top_height), Constraint::Fill(1)]).areas(body);
        let plane_width = (top.height * 5 / 2).clamp(24, top.width * 2 / 5);
        let [load_plane, slip_map] =
            Layout::horizontal([Constraint::Length(plane_width), Constraint::Fill(1)]).areas(top);
        let [tractions, slip, dissipation] = Layout::horizontal([
            Constraint::Fill(7),
            Constraint::Fill(7),
            Constraint::Fill(6),
        ])
        .areas(bottom);
        Self {
            load_plane,
            slip_map,
            tractions,
            slip,
            dissipation,
            status,
        }
    }
}

fn too_small(frame: &mut Frame, area: Rect, theme: &Theme) {
    let text = vec![
        Line::from(Span::styled(
            format!("terminal too small (need {MIN_WIDTH}x{MIN_HEIGHT})"),
            theme.alert(),
        )),
        Line::from(format!("this one is {}x{}", area.width, area.height)),
        Line::from("enlarge it, or press q to quit"),
    ];
    let top = area.height.saturating_sub(text.len() as u16) / 2;
    let rect = Rect::new(
        area.x,
        area.y + top,
        area.width,
        area.height.saturating_sub(top),
    );
    frame.render_widget(
        Paragraph::new(text)
            .alignment(Alignment::Center)
            .wrap(Wrap { trim: true }),
        rect,
    );
}

/// Colours with a monochrome fallback: without colour every distinction
/// the panels make is also carried by a glyph or a text label.
#[derive(Debug, Clone, Copy)]
pub struct Theme {
    color: bool,
    ascii: bool,
    truecolor: bool,
}

impl Theme {
    /// Colours (or none, when `color` is false), drawing Unicode.
    pub fn new(color: bool) -> Self {
        Self {
            color,
            ascii: false,
            truecolor: true,
        }
    }

    /// 24-bit colour, or the nearest of the 256 colours for terminals
    /// without it.
    pub fn with_truecolor(self, truecolor: bool) -> Self {
        Self { truecolor, ..self }
    }

    /// Whether colours are drawn (not under `NO_COLOR`).
    pub fn has_color(&self) -> bool {
        self.color
    }

    /// A palette colour ([`crate::palette`]) as the terminal can show it:
    /// exact in 24-bit colour, else the nearest of the 6x6x6 cube of the
    /// 256 colours.
    pub fn rgb(&self, c: crate::palette::Rgb) -> Color {
        if self.truecolor {
            Color::Rgb(c.0, c.1, c.2)
        } else {
            let level = |v: u8| (u16::from(v) * 5 + 127) / 255;
            let index = 16 + 36 * level(c.0) + 6 * level(c.1) + level(c.2);
            Color::Indexed(index as u8)
        }
    }

    /// A style with background `c`, or the plain style when colour is off.
    pub fn bg(&self, c: Color) -> Style {
        if self.color {
            Style::default().bg(c)
        } else {
            Style::default()
        }
    }

    /// ASCII-only drawing (`--ascii`).
    pub fn with_ascii(self, ascii: bool) -> Self {
        Self { ascii, ..self }
    }

    /// Whether drawing is ASCII only.
    pub fn ascii(&self) -> bool {
        self.ascii
    }

    /// `fancy`, or `plain` when drawing ASCII only.
    pub fn sym(&self, fancy: &'static str, plain: &'static str) -> &'static str {
        if self.ascii {
            plain
        } else {
            fancy
        }
    }

    /// Braille for curves, or plain dots when drawing ASCII only.
    pub fn line_marker(&self) -> Marker {
        if self.ascii {
            Marker::Custom('.')
        } else {
            Marker::Braille
        }
    }

    /// `c`, or the terminal's default when colour is off.
    pub fn color(&self, c: Color) -> Color {
        if self.color {
            c
        } else {
            Color::Reset
        }
    }

    /// A style with foreground `c`, or the plain style when colour is off.
    pub fn fg(&self, c: Color) -> Style {
        if self.color {
            Style::default().fg(c)
        } else {
            Style::default()
        }
    }

    /// Forward slip (`dh > 0`).
    pub fn forward(&self) -> Style {
        self.fg(Color::LightRed)
    }
    /// Backward slip (`dh < 0`).
    pub fn backward(&self) -> Style {
        self.fg(Color::LightBlue)
    }
    /// Stick.
    pub fn stick(&self) -> Style {
        self.fg(Color::DarkGray)
    }
    /// Nodes that just stuck: the locked-in history. Reversed video so it
    /// stands out in monochrome too.
    pub fn newly_stuck(&self) -> Style {
        self.fg(Color::LightMagenta)
            .add_modifier(Modifier::BOLD | Modifier::REVERSED)
    }
    /// Older advancing-stick marks in the slip map.
    pub fn stuck_mark(&self) -> Style {
        self.fg(Color::Magenta)
    }
    /// Panel titles: bold, in colour or not.
    pub fn title(&self) -> Style {
        Style::default().add_modifier(Modifier::BOLD)
    }
    /// Secondary text: borders, axes, hints.
    pub fn dim(&self) -> Style {
        self.fg(Color::DarkGray)
    }
    /// Labels of values and axes.
    pub fn label(&self) -> Style {
        self.fg(Color::Gray)
    }
    /// Values: bold.
    pub fn value(&self) -> Style {
        self.fg(Color::White).add_modifier(Modifier::BOLD)
    }
    /// Warnings that want attention: bold.
    pub fn alert(&self) -> Style {
        self.fg(Color::Yellow).add_modifier(Modifier::BOLD)
    }
    /// Errors (a failed solver, a missing sweep): bold.
    pub fn error(&self) -> Style {
        self.fg(Color::LightRed).add_modifier(Modifier::BOLD)
    }

    /// A bordered panel with its title.
    pub fn panel<'a>(&self, title: impl Into<Line<'a>>) -> Block<'a> {
        let block = Block::bordered();
        let block = if self.ascii {
            block.border_set(ASCII_BORDER)
        } else {
            block.border_type(BorderType::Rounded)
        };
        block
            .border_style(self.dim())
            .title(title.into().style(self.title()))
    }
}

/// Borders in ASCII.
const ASCII_BORDER: border::Set = border::Set {
    top_left: "+",
    top_right: "+",
    bottom_left: "+",
    bottom_right: "+",
    vertical_left: "|",
    vertical_right: "|",
    horizontal_top: "-",
    horizontal_bottom: "-",
};

/// The footer of `mode`'s keys (as gitui shows one), as many as fit in
/// `width`; `?` (every key) and `q` always stay.
pub fn footer_line<'a>(mode: crate::tui::keys::Mode, width: usize, theme: &Theme) -> Line<'a> {
    let items = crate::tui::keys::footer(mode);
    let item_width =
        |(k, w, _): &crate::tui::keys::FooterItem| k.chars().count() + w.chars().count() + 3;
    let mut keep: Vec<&crate::tui::keys::FooterItem> = items.iter().collect();
    // Drop from the end, but keep the last two (help and quit).
    while keep.len() > 2 && keep.iter().map(|i| item_width(i)).sum::<usize>() + 1 > width {
        keep.remove(keep.len() - 3);
    }
    let mut spans = vec![Span::raw(" ")];
    for (k, w, _) in keep {
        spans.push(Span::styled(
            k.to_string(),
            theme
                .label()
                .add_modifier(ratatui::style::Modifier::REVERSED),
        ));
        spans.push(Span::styled(format!(" {w}  "), theme.label()));
    }
    Line::from(fit_spans(spans, width))
}

/// A one-glyph marker.
pub fn glyph(s: &str) -> Marker {
    Marker::Custom(s.chars().next().unwrap_or('?'))
}

/// A round number at or above `v` (1, 2 or 5 times a power of ten), so
/// axes do not jitter with every increment.
pub fn nice_ceiling(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return 1.0;
    }
    let power = 10f64.powf(v.log10().floor());
    let m = v / power;
    let step = if m <= 1.0 + 1e-12 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    step * power
}

/// An axis tick label: short fixed notation for moderate values,
/// scientific otherwise.
pub fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (0.01..1000.0).contains(&a) {
        let s = format!("{v:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// Labels of the `theta` axis from `-pi` to `pi`.
/// The `theta` axis from -pi to pi shared by the panels plotted against theta.
pub fn theta_axis<'a>(theme: &Theme) -> ratatui::widgets::Axis<'a> {
    ratatui::widgets::Axis::default()
        .title(Span::styled(theme.sym("θ", "th"), theme.label()))
        .bounds([-std::f64::consts::PI, std::f64::consts::PI])
        .labels(if theme.ascii() {
            vec![Line::from("-pi"), Line::from("0"), Line::from("pi")]
        } else {
            theta_labels()
        })
        .style(theme.dim())
}

/// Labels of the `theta` axis with the Greek `π`: `-π`, `0`, `π`.
pub fn theta_labels<'a>() -> Vec<Line<'a>> {
    vec![Line::from("-π"), Line::from("0"), Line::from("π")]
}

/// Node indices in order of increasing angle in `[-pi, pi)`.
pub fn theta_order(n: usize) -> impl Iterator<Item = usize> {
    (n / 2..n).chain(0..n / 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_numbers() {
        assert_eq!(nice_ceiling(0.13), 0.2);
        assert_eq!(nice_ceiling(1.0), 1.0);
        assert_eq!(nice_ceiling(3.0e-3), 5.0e-3);
        assert_eq!(nice_ceiling(0.0), 1.0);
        assert_eq!(tick(0.2), "0.2");
        assert_eq!(tick(-0.05), "-0.05");
        assert_eq!(tick(0.002), "2e-3");
    }

    #[test]
    fn layout_fits_every_size() {
        for (w, h) in [
            (80, 24),
            (100, 30),
            (160, 48),
            (200, 60),
            (80, 60),
            (300, 24),
        ] {
            let a = Areas::new(Rect::new(0, 0, w, h));
            for r in [a.load_plane, a.slip_map, a.tractions, a.slip, a.dissipation] {
                assert!(r.width >= 20 && r.height >= 8, "{w}x{h}: {r:?}");
            }
            // Three status lines and the footer of the view's keys.
            assert_eq!(a.status.height, 4);
        }
    }
}
