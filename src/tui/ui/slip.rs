//! The locked-in slip `g(theta)`: the memory of the loading history, at
//! the instant on screen. Its mean is the rigid rotation, given as a
//! number; the curve is drawn about that mean, because the rotation grows
//! without bound when the disc ratchets and would flatten the shape that
//! carries the memory.
//!
//! At an advancing stick the panel zooms on the nodes that stuck (however
//! the instant was reached: a pause at the event, a step, the history): for
//! each it shows the slip it gathered in the slip episode that ends there
//! (its `g` now minus its `g` when the episode began, see
//! [`crate::analysis::episodes`]), and its `g` now minus its `g` at the
//! start of the cycle, on a scale fitted to these differences, which are
//! often a million times smaller than `g`. Elsewhere a pinned run's `g` is
//! drawn dimmed, and the scale is the largest `g` seen in this run, so it
//! does not jump.

use std::f64::consts::PI;

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Widget};

use super::slip_map::STUCK_GLYPH;
use super::{glyph, nice_ceiling, theta_axis, theta_order, tick, Theme};
use crate::analysis::episodes::{LockedSlip, ThetaRange};
use crate::tui::app::{format_sci, node_theta, App};

/// The locked-in slip widget.
pub struct Slip<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

fn curve(values: &[f32]) -> Vec<(f64, f64)> {
    let n = values.len();
    theta_order(n)
        .map(|j| (node_theta(j, n), f64::from(values[j])))
        .collect()
}

impl Widget for Slip<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let (app, theme) = (self.app, self.theme);
        let title = theme.sym(" Locked-in slip g(θ) - ḡ ", " Locked-in slip g - mean g ");
        let Some((record, detail)) = app.shown_detail() else {
            theme.panel(title).render(area, buf);
            return;
        };
        let n = detail.slip.len();
        if let Some(locked) = record.locked.as_deref().filter(|l| !l.nodes.is_empty()) {
            render_locked(locked, n, theme, area, buf);
            return;
        }
        let now = curve(&detail.slip);
        let before = detail.slip_before.as_deref().map(curve).unwrap_or_default();
        let stuck: Vec<(f64, f64)> = record
            .newly_stuck
            .iter()
            .filter(|&&j| j < n)
            .map(|&j| (node_theta(j, n), f64::from(detail.slip[j])))
            .collect();
        let pinned = app
            .pinned()
            .filter(|p| p.slip.len() == n)
            .map(|p| curve(&p.slip))
            .unwrap_or_default();
        let peak = pinned
            .iter()
            .map(|&(_, g)| g.abs())
            .fold(app.slip_scale(), f64::max);
        // A floor keeps an untouched interface from blowing round-off up.
        let scale = nice_ceiling(peak.max(1e-4) * 1.05);
        let line = theme.line_marker();
        let mut datasets = Vec::new();
        if !pinned.is_empty() {
            datasets.push(
                // Dots, not a line: the two curves differ in monochrome.
                Dataset::default()
                    .data(&pinned)
                    .marker(glyph(theme.sym("·", ".")))
                    .style(theme.dim()),
            );
        }
        if !before.is_empty() {
            datasets.push(
                Dataset::default()
                    .data(&before)
                    .marker(line)
                    .graph_type(GraphType::Line)
                    .style(theme.fg(Color::Gray)),
            );
        }
        datasets.push(
            Dataset::default()
                .data(&now)
                .marker(line)
                .graph_type(GraphType::Line)
                .style(theme.fg(Color::LightYellow)),
        );
        datasets.push(
            Dataset::default()
                .data(&stuck)
                .marker(glyph(STUCK_GLYPH))
                .style(theme.newly_stuck()),
        );
        let rotation = [
            Span::styled(theme.sym(" rotation ḡ = ", " rotation = "), theme.label()),
            Span::styled(format!("{} ", format_sci(record.rotation)), theme.value()),
        ];
        let bottom = match app.pinned().filter(|_| !pinned.is_empty()) {
            // Compare: both curves named, the live one first.
            Some(p) if stuck.is_empty() => {
                let names = vec![
                    Span::styled(
                        theme.sym(" ━ live ", " - live "),
                        theme.fg(Color::LightYellow),
                    ),
                    Span::styled(
                        format!("{} pinned {} ", theme.sym("·", "."), p.path),
                        theme.label(),
                    ),
                ];
                super::first_fitting(
                    vec![
                        Line::from(
                            names
                                .iter()
                                .cloned()
                                .chain(rotation.clone())
                                .collect::<Vec<_>>(),
                        ),
                        Line::from(names),
                    ],
                    area.width.saturating_sub(2) as usize,
                )
            }
            _ if stuck.is_empty() => Line::from(rotation.to_vec()),
            _ => {
                // The largest change a stuck node locked in.
                let change = record
                    .newly_stuck
                    .iter()
                    .filter_map(|&j| {
                        let b = detail.slip_before.as_ref()?.get(j)?;
                        Some(f64::from(detail.slip[j] - b).abs())
                    })
                    .fold(0.0, f64::max);
                let change = format!("{} ", format_sci(change));
                super::first_fitting(
                    vec![
                        Line::from(vec![
                            Span::styled(
                                format!(" {STUCK_GLYPH} locked in, dg up to "),
                                theme.newly_stuck(),
                            ),
                            Span::styled(change.clone(), theme.value()),
                            Span::styled("(grey: before) ", theme.label()),
                        ]),
                        Line::from(vec![
                            Span::styled(
                                format!(" {STUCK_GLYPH} locked in, dg up to "),
                                theme.newly_stuck(),
                            ),
                            Span::styled(change.clone(), theme.value()),
                        ]),
                        Line::from(vec![
                            Span::styled(format!(" {STUCK_GLYPH} dg up to "), theme.newly_stuck()),
                            Span::styled(change, theme.value()),
                        ]),
                    ],
                    area.width.saturating_sub(2) as usize,
                )
            }
        };
        let chart = Chart::new(datasets)
            .block(theme.panel(title).title_bottom(bottom))
            .legend_position(None)
            .x_axis(theta_axis(theme))
            .y_axis(
                Axis::default()
                    .title(Span::styled("g", theme.label()))
                    .bounds([-scale, scale])
                    .labels(vec![tick(-scale), "0".into(), tick(scale)])
                    .style(theme.dim()),
            );
        chart.render(area, buf);
    }
}

/// The zoom on what the nodes of an advancing stick locked in (module
/// docs). The `theta` axis runs along the arc of the stuck nodes, through
/// `theta = pi` when the arc wraps.
fn render_locked(locked: &LockedSlip, n: usize, theme: &Theme, area: Rect, buf: &mut Buffer) {
    let range = ThetaRange::of_nodes(&locked.nodes, n);
    let from = range.map_or(-1.0, |r| r.from / PI);
    // theta / pi along the arc from its first node, past 1 when it wraps.
    let along = |j: usize| from + (node_theta(j, n) / PI - from).rem_euclid(2.0);
    let mut episode: Vec<(f64, f64)> = Vec::with_capacity(locked.nodes.len());
    let mut since_cycle: Vec<(f64, f64)> = Vec::with_capacity(locked.nodes.len());
    for (k, &j) in locked.nodes.iter().enumerate() {
        let x = along(j);
        episode.push((x, locked.per_node[k]));
        since_cycle.push((x, locked.g_now[k] - locked.g_cycle_start[k]));
    }
    episode.sort_by(|a, b| a.0.total_cmp(&b.0));
    since_cycle.sort_by(|a, b| a.0.total_cmp(&b.0));
    let to = episode.last().map_or(from, |p| p.0);
    // Half a node spacing either side, so a single node has room.
    let pad = 1.0 / n.max(1) as f64;
    let (x0, x1) = (from - pad, to + pad);
    let peak = episode
        .iter()
        .chain(&since_cycle)
        .map(|p| p.1.abs())
        .fold(0.0, f64::max);
    // Fitted to the differences; a floor keeps all-zero values drawable.
    let scale = nice_ceiling(peak.max(1e-15) * 1.05);
    let wrap = |x: f64| if x >= 1.0 { x - 2.0 } else { x };
    let x_labels = vec![format!("{:.2}", wrap(from)), format!("{:.2}", wrap(to))];
    let datasets = vec![
        Dataset::default()
            .data(&since_cycle)
            .marker(theme.line_marker())
            .graph_type(GraphType::Line)
            .style(theme.fg(Color::Gray)),
        Dataset::default()
            .data(&episode)
            .marker(glyph(STUCK_GLYPH))
            .style(theme.newly_stuck()),
    ];
    let range_text = range.map(|r| r.to_string()).unwrap_or_default();
    let width = area.width.saturating_sub(2) as usize;
    let theta = theme.sym("θ/π", "theta/pi");
    let bottom = super::first_fitting(
        vec![
            Line::from(vec![
                Span::styled(
                    format!(" {STUCK_GLYPH} episode slip max "),
                    theme.newly_stuck(),
                ),
                Span::styled(format!("{} ", format_sci(locked.max)), theme.value()),
                Span::styled("mean ", theme.label()),
                Span::styled(format!("{} ", format_sci(locked.mean)), theme.value()),
                Span::styled("- grey: g - g(cycle start) ", theme.label()),
                Span::styled(format!("{theta} {range_text} "), theme.label()),
            ]),
            Line::from(vec![
                Span::styled(
                    format!(" {STUCK_GLYPH} episode slip max "),
                    theme.newly_stuck(),
                ),
                Span::styled(format!("{} ", format_sci(locked.max)), theme.value()),
                Span::styled("grey: g - g(cycle start) ", theme.label()),
            ]),
            Line::from(vec![
                Span::styled(
                    format!(" {STUCK_GLYPH} episode slip max "),
                    theme.newly_stuck(),
                ),
                Span::styled(format!("{} ", format_sci(locked.max)), theme.value()),
            ]),
            Line::from(vec![
                Span::styled(format!(" {STUCK_GLYPH} max "), theme.newly_stuck()),
                Span::styled(format!("{} ", format_sci(locked.max)), theme.value()),
            ]),
        ],
        width,
    );
    let stuck = locked.nodes.len();
    let title = super::first_fitting(
        vec![
            Line::from(format!(
                " Locked-in slip: episode of the {stuck} stuck, {theta} {range_text} "
            )),
            Line::from(format!(
                " Episode slip, {stuck} stuck, {theta} {range_text} "
            )),
            Line::from(format!(" Episode slip, {stuck} stuck ")),
        ],
        width,
    );
    let chart = Chart::new(datasets)
        .block(theme.panel(title).title_bottom(bottom))
        .legend_position(None)
        .x_axis(
            Axis::default()
                .bounds([x0, x1])
                .labels(x_labels)
                .style(theme.dim()),
        )
        .y_axis(
            Axis::default()
                .title(Span::styled("dg", theme.label()))
                .bounds([-scale, scale])
                .labels(vec![tick(-scale), "0".into(), tick(scale)])
                .style(theme.dim()),
        );
    chart.render(area, buf);
}
