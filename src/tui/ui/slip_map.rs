//! Slip-zone evolution in the style of the paper's Figs. 5a and 7a: `theta`
//! down the side, increments along the bottom, newest on the right.
//!
//! A cell covers a band of nodes and a run of increments. It shows the
//! most telling thing that happened in it: a node sticking again (the
//! history being locked in), else the dominant slip direction, else stick.

use std::f64::consts::PI;

use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Modifier;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Widget;

use super::Theme;
use crate::tui::app::{node_theta, App, BACKWARD, DIRECTION_MASK, FORWARD, NEWLY_STUCK};

const GUTTER: u16 = 5;
pub const FORWARD_GLYPH: &str = ">";
pub const BACKWARD_GLYPH: &str = "<";
pub const STICK_GLYPH: &str = "·";
pub const STUCK_GLYPH: &str = "*";
/// The slip map widget.
pub struct SlipMap<'a> {
    pub app: &'a App,
    pub theme: &'a Theme,
}

impl Widget for SlipMap<'_> {
    fn render(self, area: Rect, buf: &mut Buffer) {
        render(buf, area, self.app, self.theme);
    }
}

fn render(buf: &mut Buffer, area: Rect, app: &App, theme: &Theme) {
    let boundary_glyph = theme.sym("┆", ":");
    let steps = app.case().disc().steps_per_cycle();
    // Words when there is room, the bare glyphs when there is not.
    let wide = area.width >= 72;
    let wider = area.width >= 100;
    let word = |long: &'static str, short: &'static str| {
        Span::styled(if wide { long } else { short }, theme.label())
    };
    // The paper's sense of forward (model.md section 1.3), when it fits.
    let sense = |longest: &'static str, long: &'static str, short: &'static str| {
        let text = if wider {
            longest
        } else if wide {
            long
        } else {
            short
        };
        Span::styled(text, theme.label())
    };
    let legend = Line::from(vec![
        Span::raw(" "),
        Span::styled(FORWARD_GLYPH, theme.forward()),
        sense(" forward (dh>0) ", " forward ", " fwd "),
        Span::styled(BACKWARD_GLYPH, theme.backward()),
        sense(" backward (dh<0) ", " backward ", " bwd "),
        Span::styled(STICK_GLYPH, theme.stick()),
        word(" stick ", " stick "),
        Span::styled(STUCK_GLYPH, theme.stuck_mark()),
        word(" stuck again ", " stuck "),
        Span::styled(boundary_glyph, theme.dim()),
        word(" cycle start ", " cycle "),
    ]);
    let block = theme.panel(theme.sym(
        " Slip zones: θ against increments ",
        " Slip zones: theta against increments ",
    ));
    let inner = block.inner(area);
    let per_column = increments_per_column(steps, inner.width.saturating_sub(GUTTER));
    let block = block.title_bottom(legend).title(
        Line::from(format!(" {per_column} incr/col "))
            .style(theme.label())
            .right_aligned(),
    );
    block.render(area, buf);
    if inner.width <= GUTTER + 2 || inner.height < 3 {
        return;
    }
    draw_map(buf, inner, app, theme, per_column, boundary_glyph);
}

/// About two cycles across the map, so a whole cycle is always in view.
fn increments_per_column(steps: usize, columns: u16) -> usize {
    let per_cycle = (usize::from(columns) / 2).max(1);
    steps.div_ceil(per_cycle).max(1)
}

fn draw_map(
    buf: &mut Buffer,
    inner: Rect,
    app: &App,
    theme: &Theme,
    per_column: usize,
    boundary_glyph: &str,
) {
    let rows = usize::from(inner.height - 1);
    let columns = usize::from(inner.width - GUTTER);
    let map_x = inner.x + GUTTER;
    let axis_y = inner.y + inner.height - 1;
    let nodes = app.case().disc().nodes();

    // theta runs from pi at the top to -pi at the bottom, as in the paper.
    let band = 2.0 * PI / rows as f64;
    let node_row: Vec<usize> = (0..nodes)
        .map(|j| (((PI - node_theta(j, nodes)) / band) as usize).min(rows - 1))
        .collect();
    let labels = if theme.ascii() {
        [
            ("pi", PI),
            ("pi/2", PI / 2.0),
            ("0", 0.0),
            ("-pi/2", -PI / 2.0),
            ("-pi", -PI),
        ]
    } else {
        [
            ("π", PI),
            ("π/2", PI / 2.0),
            ("0", 0.0),
            ("-π/2", -PI / 2.0),
            ("-π", -PI),
        ]
    };
    for (label, theta) in labels {
        if rows < 7 && label.contains('/') {
            continue;
        }
        let row = (((PI - theta) / band) as usize).min(rows - 1);
        let text = if label.chars().count() <= 4 {
            format!("{label:>4} ")
        } else {
            format!("{label:>5}")
        };
        buf.set_string(inner.x, inner.y + row as u16, text, theme.label());
    }
    buf.set_string(inner.x, axis_y, theme.sym(" θ↑ ", " th "), theme.label());

    let history = app.history();
    let Some(newest) = history.newest() else {
        buf.set_string(map_x, inner.y, "(no increments yet)", theme.dim());
        return;
    };
    // The newest increment at the right edge, unless the history cursor
    // is further back than the map reaches: then the cursor is.
    let cursor = app.cursor();
    let mut last_bin = newest.increment / per_column;
    if let Some(c) = cursor {
        let c_bin = c / per_column;
        if c_bin + columns <= last_bin + columns / 4 {
            last_bin = c_bin + columns / 4;
        }
    }
    let first_bin = last_bin.saturating_sub(columns - 1);

    #[derive(Clone, Copy, Default)]
    struct Cell {
        forward: u32,
        backward: u32,
        stuck: bool,
        seen: bool,
    }
    let mut cells = vec![Cell::default(); rows * columns];
    let mut boundary = vec![None; columns];
    let mut transient = vec![false; columns];
    for row in history.iter().rev() {
        let bin = row.increment / per_column;
        if bin > last_bin {
            continue;
        }
        if bin < first_bin {
            break;
        }
        let col = bin - first_bin;
        if row.cycle_start() {
            boundary[col] = Some(row.cycle());
        }
        if row.cycle() == 0 {
            transient[col] = true;
        }
        for (j, &code) in row.cells.iter().enumerate() {
            let cell = &mut cells[node_row[j] * columns + col];
            cell.seen = true;
            match code & DIRECTION_MASK {
                FORWARD => cell.forward += 1,
                BACKWARD => cell.backward += 1,
                _ => {}
            }
            if code & NEWLY_STUCK != 0 {
                cell.stuck = true;
            }
        }
    }

    // The column on screen (the history cursor's, or the newest), and the
    // nodes that stuck in its increment.
    let shown = app.shown();
    let shown_col = shown.and_then(|r| (r.increment / per_column).checked_sub(first_bin));
    let mut recent_rows = vec![false; rows];
    for &j in shown.map_or(&[][..], |r| &r.newly_stuck[..]) {
        if let Some(&r) = node_row.get(j) {
            recent_rows[r] = true;
        }
    }
    for r in 0..rows {
        for c in 0..columns {
            let cell = cells[r * columns + c];
            if !cell.seen {
                continue;
            }
            let (glyph, style): (&str, Style) = if cell.stuck {
                let style = if Some(c) == shown_col && recent_rows[r] {
                    theme.newly_stuck()
                } else {
                    theme.stuck_mark()
                };
                (STUCK_GLYPH, style)
            } else if cell.forward > 0 && cell.forward >= cell.backward {
                (FORWARD_GLYPH, theme.forward())
            } else if cell.backward > 0 {
                (BACKWARD_GLYPH, theme.backward())
            } else if boundary[c].is_some() {
                (boundary_glyph, theme.dim())
            } else {
                (STICK_GLYPH, theme.stick())
            };
            let style = if cursor.is_some() && Some(c) == shown_col {
                style.add_modifier(Modifier::REVERSED)
            } else {
                style
            };
            buf.set_string(map_x + c as u16, inner.y + r as u16, glyph, style);
        }
    }

    // The time axis: cycle numbers where cycles start, T over the transient.
    let mut free_from = 0;
    for c in 0..columns {
        if c < free_from {
            continue;
        }
        let label = match boundary[c] {
            Some(cycle) => format!("{}{cycle}", theme.sym("┴", "^")),
            None if transient[c] && c == 0 => "T".to_string(),
            None => continue,
        };
        let width = label.chars().count();
        if c + width <= columns {
            buf.set_string(map_x + c as u16, axis_y, &label, theme.label());
            free_from = c + width + 1;
        }
    }
    if let (Some(c), Some(col)) = (cursor, shown_col) {
        if col < columns {
            buf.set_string(
                map_x + col as u16,
                axis_y,
                theme.sym("▲", "^"),
                theme.alert(),
            );
            let _ = c;
        }
    }
    let right = match cursor {
        Some(c) => format!(" at incr {} of {} ", c + 1, newest.increment + 1),
        None => format!(" incr {} ", newest.increment + 1),
    };
    let x = (map_x + columns as u16).saturating_sub(right.chars().count() as u16);
    if x > map_x + free_from as u16 {
        buf.set_string(x, axis_y, right, theme.label());
    }
}
