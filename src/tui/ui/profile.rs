//! The fretting profile of the last completed cycle (`f`), in the bottom
//! row of the stepping view, one widget per panel: the envelopes of `q`
//! and `p` with the friction bound `±f p_max`; the slip amplitude; and the
//! dissipation density `dW/dθ` with the hot spot (the largest Ruiz
//! parameter) named in words (model.md section 4.1).

use std::f64::consts::PI;

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph, Widget, Wrap};

use super::{first_fitting, glyph, nice_ceiling, theta_axis, theta_order, tick, Theme};
use crate::analysis::profile::Profile;
use crate::tui::app::profile_view::{hot_spot, hot_spot_text};
use crate::tui::app::{format_sci, node_theta, App};

/// What each profile panel draws from.
fn profile_or_message<'a>(
    app: &'a App,
    title: Line<'a>,
    area: Rect,
    buf: &mut Buffer,
    theme: &Theme,
) -> Option<&'a Profile> {
    let panel = app.profile_panel();
    if let Some(p) = panel.profile() {
        return Some(p);
    }
    let text = match (panel.missing(), app.cycles().last()) {
        (_, Some(&(c, _))) if panel.is_pending() => {
            format!("computing the profile of cycle {c}…")
        }
        (Some(why), _) => why.to_string(),
        (None, _) => "the profile comes when the first cycle completes".into(),
    };
    Paragraph::new(Span::styled(text, theme.dim()))
        .wrap(Wrap { trim: true })
        .block(theme.panel(title))
        .render(area, buf);
    None
}

/// `(theta, v_j)` in order of increasing `theta` in `[-pi, pi)`.
fn against_theta(values: &[f64], scale: f64) -> Vec<(f64, f64)> {
    let n = values.len();
    theta_order(n)
        .map(|j| (node_theta(j, n), scale * values[j]))
        .collect()
}

fn line<'a>(data: &'a [(f64, f64)], theme: &Theme, color: Color) -> Dataset<'a> {
    Dataset::default()
        .data(data)
        .marker(theme.line_marker())
        .graph_type(GraphType::Line)
        .style(theme.fg(color))
}

fn y_axis<'a>(name: &'a str, lo: f64, hi: f64, theme: &Theme) -> Axis<'a> {
    // A middle tick only where it is a round 0: `tick` would round half
    // of 5e-3 to 3e-3.
    let labels = if lo < 0.0 {
        vec![tick(lo), "0".to_string(), tick(hi)]
    } else {
        vec![tick(lo), tick(hi)]
    };
    Axis::default()
        .title(Span::styled(name, theme.label()))
        .bounds([lo, hi])
        .labels(labels)
        .style(theme.dim())
}

/// `q_min`, `q_max` between `±f p_max`, and `f p_min`: the envelopes of
/// the tractions over the cycle, in the friction bound's scale.
pub struct Envelopes<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl Widget for Envelopes<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let cycle = app.profile_panel().profile().map(|p| p.cycle);
        let width = area.width.saturating_sub(2) as usize;
        let title = first_fitting(
            vec![
                Line::from(match cycle {
                    Some(c) => format!(" Cycle {c}: q and p envelopes "),
                    None => " Fretting profile ".into(),
                }),
                Line::from(match cycle {
                    Some(c) => format!(" Cycle {c}: q, p "),
                    None => " Profile ".into(),
                }),
            ],
            width,
        );
        let Some(p) = profile_or_message(app, title.clone(), area, buf, theme) else {
            return;
        };
        let f = app.friction();
        let upper = against_theta(&p.p_max, f);
        let lower = against_theta(&p.p_max, -f);
        let p_min = against_theta(&p.p_min, f);
        let q_max = against_theta(&p.q_max, 1.0);
        let q_min = against_theta(&p.q_min, 1.0);
        let limit = upper
            .iter()
            .chain(&q_min)
            .chain(&q_max)
            .map(|&(_, v)| v.abs())
            .fold(0.0, f64::max);
        let top = nice_ceiling(limit * 1.05);
        let datasets = vec![
            line(&upper, theme, Color::Green),
            line(&lower, theme, Color::Green),
            Dataset::default()
                .data(&p_min)
                .marker(glyph(theme.sym("·", ".")))
                .style(theme.dim()),
            line(&q_max, theme, Color::LightRed),
            line(&q_min, theme, Color::LightBlue),
        ];
        let bottom = first_fitting(
            vec![
                Line::from(Span::styled(
                    theme.sym(
                        " q max, min within ±f p_max; · f p_min ",
                        " q max, min within +-f p_max; . f p_min ",
                    ),
                    theme.label(),
                )),
                Line::from(Span::styled(
                    theme.sym(" q in ±f p_max, · f p_min ", " q in +-f p_max, . f p_min "),
                    theme.label(),
                )),
            ],
            width,
        );
        Chart::new(datasets)
            .block(theme.panel(title).title_bottom(bottom))
            .legend_position(None)
            .x_axis(theta_axis(theme))
            .y_axis(y_axis("q", -top, top, theme))
            .render(area, buf);
    }
}

/// The slip amplitude (half the range of `g` over the cycle).
pub struct SlipAmplitude<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl Widget for SlipAmplitude<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let width = area.width.saturating_sub(2) as usize;
        let title = first_fitting(
            vec![
                Line::from(" Slip amplitude (range of g / 2) "),
                Line::from(" Slip amplitude "),
            ],
            width,
        );
        let Some(p) = profile_or_message(app, title.clone(), area, buf, theme) else {
            return;
        };
        let amplitude = against_theta(&p.slip_amplitude, 1.0);
        let peak = p.slip_amplitude.iter().copied().fold(0.0, f64::max);
        let top = nice_ceiling(peak * 1.05);
        let bottom = Line::from(Span::styled(
            format!(" largest {} ", format_sci(peak)),
            theme.label(),
        ));
        Chart::new(vec![line(&amplitude, theme, Color::LightRed)])
            .block(theme.panel(title).title_bottom(bottom))
            .legend_position(None)
            .x_axis(theta_axis(theme))
            .y_axis(y_axis("g", 0.0, top, theme))
            .render(area, buf);
    }
}

/// The dissipation density `dW/dθ`, with the hot spot (the node of the
/// largest Ruiz parameter) marked and named.
pub struct DissipationDensity<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl Widget for DissipationDensity<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let width = area.width.saturating_sub(2) as usize;
        let w_of_cycle = app.profile_w().map(format_sci);
        let title = first_fitting(
            vec![
                // The column sums to the cycle's W (model.md 4.1).
                Line::from(match &w_of_cycle {
                    Some(w) => format!(" Dissipation dW/dθ, total W {w} "),
                    None => " Dissipation dW/dθ ".into(),
                }),
                Line::from(theme.sym(" Dissipation dW/dθ ", " Dissipation dW/dtheta ")),
                Line::from(theme.sym(" dW/dθ ", " dW/dth ")),
            ],
            width,
        );
        let Some(p) = profile_or_message(app, title.clone(), area, buf, theme) else {
            return;
        };
        let n = p.dissipation.len();
        let per_radian = n as f64 / (2.0 * PI);
        let density = against_theta(&p.dissipation, per_radian);
        let peak = density.iter().map(|&(_, v)| v).fold(0.0, f64::max);
        let top = nice_ceiling(peak * 1.05);
        let hot: Vec<(f64, f64)> = hot_spot(p)
            .map(|j| (node_theta(j, n), per_radian * p.dissipation[j]))
            .into_iter()
            .collect();
        // `--ascii` makes t and p of the Greek letters (`asciify`).
        let words = hot_spot_text(p);
        let bottom = first_fitting(
            vec![
                Line::from(Span::styled(format!(" ◆ {words} "), theme.alert())),
                Line::from(Span::styled(
                    format!(" ◆ {} ", words.replace("(max Ruiz) at ", "")),
                    theme.alert(),
                )),
                Line::from(Span::styled(
                    format!(" ◆ {} ", words.replace("spot (max Ruiz) at ", "")),
                    theme.alert(),
                )),
            ],
            width,
        );
        Chart::new(vec![
            line(&density, theme, Color::Yellow),
            Dataset::default()
                .data(&hot)
                .marker(glyph(theme.sym("◆", "@")))
                .style(theme.alert()),
        ])
        .block(theme.panel(title).title_bottom(bottom))
        .legend_position(None)
        .x_axis(theta_axis(theme))
        .y_axis(y_axis("dW", 0.0, top, theme))
        .render(area, buf);
    }
}
