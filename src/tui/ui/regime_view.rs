//! The regime map in the sweep view: the steady state over the
//! `(lambda, phi)` plane for one transient, one block of cells per run in
//! the paper's state colours ([`crate::palette`], the figure's), darker
//! for more dissipation, with a letter per state so that it reads without
//! colour; `lambda_2(phi)` from the linear programme is a bar in each row,
//! and the cursor's cell is detailed beside the map.

use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Widget, Wrap};
use ratatui::Frame;

use super::sweep_view::{progress_spans, render_status_lines};
use super::Theme;
use crate::analysis::regime::RegimeCell;
use crate::palette::{map_colour, Rgb, Shading};
use crate::stepping::steady::SteadyState;
use crate::tui::app::{format_load_factor, format_phase, format_sci, App};
use crate::tui::regime::{CurveState, Regime};

/// Width of the legend and details column.
const SIDE_WIDTH: u16 = 32;
/// Height of the legend: the states, "not run yet" and `lambda_2`, bordered.
const LEGEND_HEIGHT: u16 = 12;

/// Every state a cell can show, in legend order: its letter (so the map
/// reads without colour, and in ASCII) and its name.
const STATES: [(Option<SteadyState>, char, &str); 8] = [
    (Some(SteadyState::Shakedown), 'S', "shakedown"),
    (Some(SteadyState::CyclicSlip), 'C', "cyclic slip"),
    (
        Some(SteadyState::RatchettingMonotonic),
        'M',
        "ratchetting, monotonic",
    ),
    (
        Some(SteadyState::RatchettingNonMonotonic),
        'N',
        "ratchetting, non-mono.",
    ),
    (Some(SteadyState::GrossSlip), 'G', "gross slip"),
    (Some(SteadyState::Separation), 'X', "separation"),
    (Some(SteadyState::NotConverged), '?', "not converged"),
    (None, '!', "solver failed"),
];

/// The letter and name of a cell's state.
fn state_of(state: Option<SteadyState>) -> (char, &'static str) {
    STATES
        .iter()
        .find(|s| s.0 == state)
        .map_or(('!', "solver failed"), |s| (s.1, s.2))
}

pub fn render(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let [body, status] = Layout::vertical([Constraint::Fill(1), Constraint::Length(3)]).areas(area);
    let [plot, side] =
        Layout::horizontal([Constraint::Fill(1), Constraint::Length(SIDE_WIDTH)]).areas(body);
    let [legend, details] =
        Layout::vertical([Constraint::Length(LEGEND_HEIGHT), Constraint::Fill(1)]).areas(side);
    match app.regime() {
        Ok(regime) => {
            frame.render_widget(MapPanel { regime, theme }, plot);
            render_legend(frame, legend, regime, theme);
            render_details(frame, details, regime, theme);
        }
        Err(e) => {
            let text = Paragraph::new(Span::styled(format!("no regime map: {e}"), theme.error()))
                .wrap(Wrap { trim: true })
                .block(theme.panel(" Regime map "));
            frame.render_widget(text, body);
        }
    }
    render_status(frame, status, app, theme);
}

/// Text that reads on `colour`: black on light, white on dark.
fn ink(colour: Rgb) -> Color {
    if colour.luminance() > 0.5 {
        Color::Black
    } else {
        Color::White
    }
}

/// The style of a cell in `cell`'s state: its colour as background, the
/// letter dark or light to read on it.
fn cell_style(theme: &Theme, shading: &Shading, cell: &RegimeCell) -> Style {
    let colour = shading.colour(cell);
    theme.bg(theme.rgb(colour)).patch(theme.fg(ink(colour)))
}

/// The map: a block of `w x h` terminal cells per run.
struct MapPanel<'a> {
    regime: &'a Regime,
    theme: &'a Theme,
}

impl Widget for MapPanel<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (regime, theme) = (self.regime, self.theme);
        let progress = if regime.is_running() {
            format!("{}/{} runs, running", regime.done(), regime.total())
        } else {
            format!("{}/{} runs", regime.done(), regime.total())
        };
        let title = format!(" Regime map · {} · {} ", regime.initial().name(), progress);
        let block = theme.panel(title).title_bottom(
            Line::from(theme.sym(" λ →  φ ↑ ", " lambda ->  phi ^ ")).style(theme.label()),
        );
        let inner = block.inner(area);
        block.render(area, buf);
        if let Some(e) = regime.error() {
            Paragraph::new(Span::styled(
                format!("no map for this transient: {e}"),
                theme.error(),
            ))
            .wrap(Wrap { trim: true })
            .render(inner, buf);
            return;
        }
        let map = regime.map();
        let (lambdas, phases) = (map.load_factors(), map.phases());
        let (nl, np) = (lambdas.len(), phases.len());
        // φ labels: the multiples of pi/4, and the ends.
        let labels: Vec<Option<String>> = phases
            .iter()
            .enumerate()
            .map(|(j, &p)| {
                let quarter = (p / (std::f64::consts::PI / 4.0)).round();
                let on_quarter = (p - quarter * std::f64::consts::PI / 4.0).abs() < 1e-9;
                (on_quarter || j == 0 || j + 1 == np).then(|| format_phase(p))
            })
            .collect();
        let label_width = labels.iter().flatten().map(|l| l.len()).max().unwrap_or(1) as u16;
        // Labels, a gap for the row marker, the cells; below them the
        // caret row and the lambda labels.
        let left = label_width + 1;
        let avail_w = inner.width.saturating_sub(left) as usize;
        let avail_h = inner.height.saturating_sub(2) as usize;
        let (w, h) = (avail_w / nl.max(1), avail_h / np.max(1));
        if w == 0 || h == 0 {
            Paragraph::new(Span::styled(
                format!("enlarge the terminal: the map has {nl} x {np} cells"),
                theme.alert(),
            ))
            .wrap(Wrap { trim: true })
            .render(inner, buf);
            return;
        }
        // Wider cells than three times their height look stretched.
        let w = w.min(3 * h + 3);
        let x0 = inner.x + left;
        // Row j (phi ascending) from the bottom.
        let top_of = |j: usize| inner.y + ((np - 1 - j) * h) as u16;
        let shading = Shading::of(map);
        let (ci, cj) = regime.cursor();
        let letter_dx = (w - 1) / 2;
        let letter_dy = (h - 1) / 2;
        for j in 0..np {
            for i in 0..nl {
                let x = x0 + (i * w) as u16;
                let y = top_of(j);
                let cell = map.cell(i, j);
                let (style, letter) = match &cell {
                    Some(c) => (cell_style(theme, &shading, c), state_of(c.state).0),
                    None => (
                        theme.dim(),
                        theme.sym("·", ".").chars().next().unwrap_or('.'),
                    ),
                };
                let style = if (i, j) == (ci, cj) {
                    style.add_modifier(Modifier::REVERSED | Modifier::BOLD)
                } else {
                    style
                };
                for dy in 0..h {
                    for dx in 0..w {
                        let c = &mut buf[(x + dx as u16, y + dy as u16)];
                        c.set_style(style);
                        let sym = if (dx, dy) == (letter_dx, letter_dy) {
                            letter
                        } else {
                            ' '
                        };
                        c.set_char(sym);
                    }
                }
            }
        }
        // lambda_2(phi): a bar in each row where it falls, beside the
        // letters rather than over them, each drawn as soon as it is solved.
        if w >= 2 {
            let curve = regime.curve().points();
            let lo = map.cell_bounds(0, 0).0 .0;
            let hi = map.cell_bounds(nl - 1, 0).0 .1;
            let span = (nl * w) as f64;
            for (j, l2) in curve.iter().enumerate().take(np) {
                let Some(l2) = l2.filter(|l| (lo..hi).contains(l)) else {
                    continue;
                };
                let pos = (l2 - lo) / (hi - lo) * span;
                let mut col = (pos.floor() as usize).min(nl * w - 1);
                if col % w == letter_dx {
                    col = if pos - col as f64 >= 0.5 && col + 1 < nl * w {
                        col + 1
                    } else {
                        col.saturating_sub(1)
                    };
                }
                // Dark or light to read on the cell it crosses.
                let ink = map
                    .cell(col / w, j)
                    .filter(|_| (col / w, j) != (ci, cj))
                    .map(|c| theme.color(ink(shading.colour(&c))));
                for dy in 0..h {
                    let c = &mut buf[(x0 + col as u16, top_of(j) + dy as u16)];
                    c.set_symbol(theme.sym("┃", "|"));
                    c.modifier.insert(Modifier::BOLD);
                    if let Some(ink) = ink {
                        c.fg = ink;
                    }
                }
            }
        }
        // The phi labels and the cursor's row marker.
        for (j, label) in labels.iter().enumerate() {
            let y = top_of(j) + letter_dy as u16;
            if let Some(l) = label {
                let x = inner.x + label_width - l.len() as u16;
                buf.set_string(x, y, l, theme.label());
            }
            if j == cj {
                buf.set_string(inner.x + label_width, y, theme.sym("▶", ">"), theme.value());
            }
        }
        // Below: a caret under the cursor's column, then the lambda
        // labels at the whole numbers, and the axis name at the end.
        let below = inner.y + (np * h) as u16;
        let centre = |i: usize| x0 + (i * w + letter_dx) as u16;
        buf.set_string(centre(ci), below, theme.sym("▲", "^"), theme.value());
        let mut free = x0;
        for (i, &l) in lambdas.iter().enumerate() {
            if (l - l.round()).abs() > 1e-9 {
                continue;
            }
            let text = format!("{l}");
            let x = centre(i).saturating_sub((text.len() as u16).saturating_sub(1) / 2);
            if x >= free && x + text.len() as u16 <= inner.x + inner.width {
                buf.set_string(x, below + 1, &text, theme.label());
                free = x + text.len() as u16 + 1;
            }
        }
        let name = "lambda";
        let end = x0 + (nl * w) as u16;
        if end > free + name.len() as u16 && end <= inner.x + inner.width {
            buf.set_string(end - name.len() as u16, below + 1, name, theme.title());
        }
    }
}

fn render_legend(frame: &mut Frame, area: Rect, regime: &Regime, theme: &Theme) {
    let map = regime.map();
    let mut counts = [0usize; STATES.len()];
    for j in 0..map.phases().len() {
        for i in 0..map.load_factors().len() {
            if let Some(c) = map.cell(i, j) {
                if let Some(k) = STATES.iter().position(|s| s.0 == c.state) {
                    counts[k] += 1;
                }
            }
        }
    }
    let mut lines: Vec<Line> = STATES
        .iter()
        .zip(counts)
        .map(|(&(state, letter, name), n)| {
            let colour = map_colour(state);
            let swatch = theme.bg(theme.rgb(colour)).patch(theme.fg(ink(colour)));
            Line::from(vec![
                Span::raw(" "),
                Span::styled(format!(" {letter} "), swatch),
                Span::styled(format!(" {name:<22}"), theme.label()),
                Span::styled(format!("{n:>3}"), theme.value()),
            ])
        })
        .collect();
    let pending = regime.total() - regime.done();
    lines.push(Line::from(vec![
        Span::styled(format!("  {} ", theme.sym("·", ".")), theme.dim()),
        Span::styled(format!(" {:<22}", "not run yet"), theme.label()),
        Span::styled(format!("{pending:>3}"), theme.value()),
    ]));
    let curve = match regime.curve() {
        c @ CurveState::Computing(_) => {
            let (k, n) = c.solved();
            format!(" {k}/{n}…")
        }
        CurveState::Known(_) => String::new(),
    };
    lines.push(Line::from(vec![
        Span::styled(format!("  {} ", theme.sym("┃", "|")), theme.value()),
        Span::styled(" lambda_2(phi)", theme.label()),
        Span::styled(curve, theme.dim()),
    ]));
    // Shades only speak in colour: without it the letters name the states.
    let title = if theme.has_color() {
        theme.sym(" Legend: darker is more W ", " Legend: darker = more W ")
    } else {
        " Legend: letters are states "
    };
    frame.render_widget(Paragraph::new(lines).block(theme.panel(title)), area);
}

fn render_details(frame: &mut Frame, area: Rect, regime: &Regime, theme: &Theme) {
    let label = |s: &str| Span::styled(format!(" {s:<6} "), theme.label());
    let value = |s: String| Span::styled(s, theme.value());
    let (lambda, phi) = regime.selected();
    let mut lines = vec![
        Line::from(vec![label("lambda"), value(format_load_factor(lambda))]),
        Line::from(vec![label("phi"), value(format_phase(phi))]),
        Line::from(vec![label("path"), value(regime.initial().name())]),
    ];
    match regime.selected_cell() {
        None => lines.push(Line::from(vec![
            label("state"),
            Span::styled(
                if regime.is_running() {
                    "running…"
                } else {
                    "not run yet"
                },
                theme.dim(),
            ),
        ])),
        Some(c) => {
            lines.push(Line::from(vec![
                label("state"),
                value(state_of(c.state).1.into()),
            ]));
            let w = if c.dissipation.is_finite() {
                format_sci(c.dissipation)
            } else {
                "–".to_string()
            };
            lines.push(Line::from(vec![label("W"), value(w)]));
        }
    }
    let l2 = match regime.curve() {
        CurveState::Computing(points) => match points.get(regime.cursor().1) {
            Some(Some(Some(l))) => format!("{l:.3}"),
            Some(Some(None)) => "failed".to_string(),
            _ => "computing…".to_string(),
        },
        CurveState::Known(curve) => curve
            .get(regime.cursor().1)
            .copied()
            .flatten()
            .map_or_else(|| "failed".to_string(), |l| format!("{l:.3}")),
    };
    lines.push(Line::from(vec![
        Span::styled(" lambda_2 = ", theme.label()),
        value(l2),
    ]));
    frame.render_widget(
        Paragraph::new(lines)
            .wrap(Wrap { trim: false })
            .block(theme.panel(" Cell: Enter opens it ")),
        area,
    );
}

fn render_status(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let label = |s: &str| Span::styled(s.to_string(), theme.label());
    let mut line1 = vec![label(" regime map")];
    if let Ok(r) = app.regime() {
        line1.extend(progress_spans(
            theme,
            " of ",
            r.initial().name(),
            (r.done(), r.total()),
            (r.is_running(), r.started()),
            ("computing in the background", "stopped (r computes it)"),
            r.time_left(),
        ));
    }
    let hint = if area.width >= 110 {
        " Esc g back  ←→ lambda  ↑↓ phi  PgUp PgDn Home End  Enter open  [ ] path  r rerun  ? help  q quit"
    } else {
        " Esc g back  ←→ lambda  ↑↓ phi  Enter open  [ ] path  r rerun  ? help  q quit"
    };
    render_status_lines(frame, area, app, theme, line1, hint);
}
