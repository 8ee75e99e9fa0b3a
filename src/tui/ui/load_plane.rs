//! The load plane (the paper's Fig. 2): where the loads are, relative to
//! the stick diamond and the gross-slip lines.

use std::f64::consts::PI;

use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier};
use ratatui::text::{Line as TextLine, Span};
use ratatui::widgets::canvas::{Canvas, Line};

use super::Theme;
use crate::model::path::Initial;
use crate::tui::app::App;

const TWO_PI: f64 = 2.0 * PI;
/// Samples of the cycle's ellipse: smooth at any panel size.
const CYCLE_SAMPLES: usize = 96;

/// The load plane widget.
pub struct LoadPlane<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl ratatui::widgets::Widget for LoadPlane<'_> {
    fn render(self, area: Rect, buf: &mut ratatui::buffer::Buffer) {
        render(buf, area, self.app, self.theme);
    }
}

fn render(buf: &mut ratatui::buffer::Buffer, area: Rect, app: &App, theme: &Theme) {
    let cycle = app.case().cycle().clone();
    let cycle_points: Vec<(f64, f64)> = match cycle.as_polyline() {
        // A polyline is drawn through its own vertices, closed, so that no
        // corner is cut (model.md section 5.4).
        Some(polyline) => {
            let m = polyline.vertices().len();
            (0..=m)
                .map(|k| {
                    let p = cycle.at(TWO_PI * (k % m) as f64 / m as f64);
                    (p.x(), p.y())
                })
                .collect()
        }
        None => (0..=CYCLE_SAMPLES)
            .map(|i| {
                let p = cycle.at(TWO_PI * i as f64 / CYCLE_SAMPLES as f64);
                (p.x(), p.y())
            })
            .collect(),
    };
    let segments: Vec<(f64, f64, f64, f64)> = app
        .transient()
        .iter()
        .map(|s| (s.from().x(), s.from().y(), s.to().x(), s.to().y()))
        .collect();
    let (load_x, load_y) = app.shown().map_or((0.0, 0.0), |r| r.load);
    // Where gross slip (or separation) ended the run, when it did.
    let terminal = match app.status() {
        crate::stepping::Status::Ended(s) => s.terminal_load().map(|p| (p.x(), p.y())),
        _ => None,
    };
    let selected = match app.initial() {
        Initial::Via { a, b } => Some((*a, *b)),
        _ => None,
    };
    // The points of a custom transient `O -> points -> A` (--initial-path).
    let waypoints: Vec<(f64, f64)> = match app.initial() {
        Initial::Custom(points) => points.iter().map(|p| (p.x(), p.y())).collect(),
        _ => Vec::new(),
    };

    let block = theme.panel(" Load plane ").title_bottom(
        TextLine::from(theme.sym(" x = χP/f, y = T/f ", " x = chi P/f, y = T/f "))
            .style(theme.label()),
    );
    let inner = block.inner(area);
    let (x_bounds, y_bounds) = bounds(
        inner,
        cycle_points
            .iter()
            .copied()
            .chain(segments.iter().flat_map(|s| [(s.0, s.1), (s.2, s.3)]))
            .chain(std::iter::once((load_x, load_y)))
            .chain(waypoints.iter().copied())
            .chain(terminal),
    );

    let axis = theme.color(Color::DarkGray);
    let diamond = theme.color(Color::Green);
    let gross = theme.color(Color::Red);
    let cycle_color = theme.color(Color::LightCyan);
    let path_color = theme.color(Color::Yellow);
    let point_style = theme.fg(Color::LightMagenta).add_modifier(Modifier::BOLD);
    let cross_style = theme.dim();
    let selected_style = theme.fg(Color::Yellow).add_modifier(Modifier::BOLD);
    let label_style = theme.label();
    let gross_style = theme.error();
    // On a small panel the label would hide most of the line it names.
    let roomy = inner.width >= 40;

    let canvas = Canvas::default()
        .marker(theme.line_marker())
        .block(block)
        .x_bounds(x_bounds)
        .y_bounds(y_bounds)
        .paint(move |ctx| {
            ctx.draw(&Line::new(x_bounds[0], 0.0, x_bounds[1], 0.0, axis));
            ctx.draw(&Line::new(0.0, y_bounds[0], 0.0, y_bounds[1], axis));
            ctx.layer();
            let corners = [(TWO_PI, 0.0), (0.0, TWO_PI), (-TWO_PI, 0.0), (0.0, -TWO_PI)];
            for i in 0..4 {
                let (a, b) = (corners[i], corners[(i + 1) % 4]);
                ctx.draw(&Line::new(a.0, a.1, b.0, b.1, diamond));
            }
            for y in [TWO_PI, -TWO_PI] {
                ctx.draw(&Line::new(x_bounds[0], y, x_bounds[1], y, gross));
            }
            ctx.layer();
            for &(x1, y1, x2, y2) in &segments {
                ctx.draw(&Line::new(x1, y1, x2, y2, path_color));
            }
            for w in cycle_points.windows(2) {
                ctx.draw(&Line::new(w[0].0, w[0].1, w[1].0, w[1].1, cycle_color));
            }
            // Text goes on top of every layer, in the order printed.
            ctx.print(x_bounds[1], 0.0, Span::styled("x", label_style));
            ctx.print(0.0, y_bounds[1], Span::styled("y", label_style));
            ctx.print(
                TWO_PI,
                0.0,
                Span::styled(theme.sym("2π", "2pi"), label_style),
            );
            if roomy {
                ctx.print(x_bounds[0], TWO_PI, Span::styled("gross slip", label_style));
            }
            for a in [-7, -5, -3, 3, 5, 7] {
                for b in [-7, -5, -3, 3, 5, 7] {
                    if i32::abs(a) + i32::abs(b) > 8 {
                        let style = if selected == Some((a, b)) {
                            selected_style
                        } else {
                            cross_style
                        };
                        let (x, y) = (a as f64 * PI / 4.0, b as f64 * PI / 4.0);
                        ctx.print(x, y, Span::styled(theme.sym("×", "x"), style));
                    }
                }
            }
            ctx.print(
                cycle.center().x(),
                cycle.center().y(),
                Span::styled("A", label_style),
            );
            ctx.print(0.0, 0.0, Span::styled("O", label_style));
            // The custom path's points, numbered in path order when there
            // are several.
            let numbered = waypoints.len() > 1;
            for (k, &(x, y)) in waypoints.iter().enumerate() {
                let mark = theme.sym("◆", "*");
                let text = if numbered {
                    format!("{mark}{}", k + 1)
                } else {
                    mark.to_string()
                };
                ctx.print(x, y, Span::styled(text, selected_style));
            }
            if let Some((x, y)) = terminal {
                ctx.print(x, y, Span::styled("G", gross_style));
            }
            ctx.print(
                load_x,
                load_y,
                Span::styled(theme.sym("●", "@"), point_style),
            );
        });
    ratatui::widgets::Widget::render(canvas, area, buf);
}

/// Bounds that hold the diamond, the gross-slip lines and every point, with
/// the shorter side stretched so one unit looks the same along both axes
/// (a terminal cell is about twice as tall as it is wide).
fn bounds(inner: Rect, points: impl Iterator<Item = (f64, f64)>) -> ([f64; 2], [f64; 2]) {
    let pad = 0.8;
    let (mut x0, mut x1, mut y0, mut y1) = (-TWO_PI, TWO_PI, -TWO_PI, TWO_PI);
    for (x, y) in points {
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    let (mut x0, mut x1, mut y0, mut y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    let width = f64::from(inner.width.max(1));
    let height = 2.0 * f64::from(inner.height.max(1));
    let (sx, sy) = ((x1 - x0) / width, (y1 - y0) / height);
    if sx > sy {
        let grow = (sx * height - (y1 - y0)) / 2.0;
        y0 -= grow;
        y1 += grow;
    } else {
        let grow = (sy * width - (x1 - x0)) / 2.0;
        x0 -= grow;
        x1 += grow;
    }
    ([x0, x1], [y0, y1])
}
