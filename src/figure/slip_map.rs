//! Slip zones over one steady cycle next to the load variation (Figs. 5,
//! 7). The cycle is drawn from a chosen time origin ([`TimeOrigin`]); the
//! default starts it at a slip-free instant, so that no slip event is cut
//! in two by the ends of the axis.

use std::f64::consts::PI;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{
    direction_colour, direction_label, directions_forward_first, font, padded, pi_label, s,
    Drawing, GREEN_LINE,
};
use crate::analysis::slip_map::SlipMap;
use crate::io::parse::{parse_angle, ParseError};

/// Where the drawn cycle starts (`omega t` at the bottom of the axes).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum TimeOrigin {
    /// In the middle of the longest slip-free stretch of the cycle, else
    /// at the instant with the least slip ([`auto_origin`]).
    #[default]
    Auto,
    /// At this `omega t` (radians).
    At(f64),
}

impl std::str::FromStr for TimeOrigin {
    type Err = ParseError;
    /// `auto`, or an angle as `--phi` takes it (`0`, `pi/2`, `1.2`).
    fn from_str(text: &str) -> Result<Self, ParseError> {
        if text.trim().eq_ignore_ascii_case("auto") {
            return Ok(TimeOrigin::Auto);
        }
        parse_angle(text).map(|t| TimeOrigin::At(t.rem_euclid(2.0 * PI)))
    }
}

impl TimeOrigin {
    /// The origin for `map`, in `[0, 2 pi)`.
    pub fn resolve(self, map: &SlipMap) -> f64 {
        match self {
            TimeOrigin::At(t) => t.rem_euclid(2.0 * PI),
            TimeOrigin::Auto => auto_origin(map),
        }
    }
}

/// The middle of the longest slip-free stretch of the cycle (taken round
/// the cycle, so a stretch may wrap through `2 pi`): the slip events then
/// sit whole in the middle of the axis. When every increment has slip
/// somewhere, the start of the one in which the fewest nodes slip.
pub fn auto_origin(map: &SlipMap) -> f64 {
    let n = map.rows.len();
    let slipping = |k: usize| {
        map.rows[k % n]
            .directions
            .iter()
            .filter(|d| d.is_slipping())
            .count()
    };
    if n == 0 {
        return 0.0;
    }
    // The longest circular run of slip-free increments.
    let mut best: Option<(usize, usize)> = None;
    let mut k = 0;
    while k < n {
        if slipping(k) == 0 {
            let mut len = 0;
            while len < n && slipping(k + len) == 0 {
                len += 1;
            }
            if best.is_none_or(|(_, l)| len > l) {
                best = Some((k, len));
            }
            k += len.max(1);
        } else {
            k += 1;
        }
    }
    let k = match best {
        Some((start, len)) => (start + len / 2) % n,
        None => (0..n).min_by_key(|&k| (slipping(k), k)).unwrap_or(0),
    };
    map.rows[k].t0.rem_euclid(2.0 * PI)
}

/// The pieces of `[t0, t1]` drawn on the axis `[origin, origin + 2 pi]`:
/// one, or two when the interval straddles the origin.
fn shifted(t0: f64, t1: f64, origin: f64) -> Vec<(f64, f64)> {
    let eps = 1e-9;
    let lift = |t: f64| if t < origin - eps { t + 2.0 * PI } else { t };
    if t0 < origin - eps && t1 > origin + eps {
        vec![(origin, t1), (t0 + 2.0 * PI, origin + 2.0 * PI)]
    } else {
        let a = lift(t0);
        // An increment that ends exactly at the origin ends the axis.
        let b = if t1 <= origin + eps && t0 < origin - eps {
            t1 + 2.0 * PI
        } else {
            lift(t1).max(a)
        };
        vec![(a, b)]
    }
}

/// Slip zones over one steady cycle next to the load variation
/// (Figs. 5, 7).
pub struct SlipMapPlot<'a> {
    /// The slip map.
    pub map: &'a SlipMap,
    /// The plot title.
    pub title: String,
    /// Where the drawn cycle starts.
    pub origin: TimeOrigin,
}

impl Drawing for SlipMapPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (1100, 680)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let map = self.map;
        let origin = self.origin.resolve(map);
        let (o0, o1) = (origin / PI, origin / PI + 2.0);
        let title = format!(
            "{}: {}, dissipation {:.4e} per cycle",
            self.title,
            map.outcome.state(),
            map.outcome.dissipation
        );
        let root = root.titled(&title, font(20.0)).map_err(s)?;
        let (key, root) = root.split_vertically(34);
        // The key of the slip directions, in the paper's words.
        let mut x = 80;
        for d in directions_forward_first() {
            key.draw(&Rectangle::new(
                [(x, 10), (x + 22, 26)],
                direction_colour(d).filled(),
            ))
            .map_err(s)?;
            let label = direction_label(d);
            key.draw(&Text::new(label, (x + 30, 10), font(15.0)))
                .map_err(s)?;
            x += 40 + 8 * label.chars().count() as i32;
        }
        let (left, right) = root.split_horizontally(660);

        // (a) the slip map: theta across, omega t up, in units of pi.
        let mut chart = ChartBuilder::on(&left)
            .caption("(a) slip over one steady cycle", font(16.0))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(-1.0..1.0, o0..o1)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("θ")
            .y_desc("ωt")
            .axis_desc_style(font(20.0))
            .label_style(font(14.0))
            .x_labels(9)
            .y_labels(9)
            .x_label_formatter(&pi_label)
            .y_label_formatter(&pi_label)
            .draw()
            .map_err(s)?;
        let n = map.nodes;
        let half = 1.0 / n as f64;
        // Nodes in display order from theta = -pi up; runs of one direction
        // become one rectangle.
        let order: Vec<usize> = (0..n).map(|k| (k + n / 2) % n).collect();
        let mut cells = Vec::new();
        for r in &map.rows {
            let mut k = 0;
            while k < n {
                let d = r.directions[order[k]];
                let mut end = k + 1;
                while end < n && r.directions[order[end]] == d {
                    end += 1;
                }
                if d.is_slipping() {
                    let lo = map.theta(order[k]) / PI - half;
                    let hi = map.theta(order[end - 1]) / PI + half;
                    for (a, b) in shifted(r.t0, r.t1, origin) {
                        cells.push((lo, hi, a / PI, b / PI, d));
                    }
                }
                k = end;
            }
        }
        for dir in directions_forward_first() {
            let colour = direction_colour(dir);
            chart
                .draw_series(
                    cells
                        .iter()
                        .filter(|c| c.4 == dir)
                        .map(|c| Rectangle::new([(c.0, c.2), (c.1, c.3)], colour.filled())),
                )
                .map_err(s)?;
        }

        // (b) the load variation against the same omega t.
        let mut load: Vec<(f64, f64, f64)> = vec![(0.0, map.start.x(), map.start.y())];
        load.extend(map.rows.iter().map(|r| (r.t1, r.load.x(), r.load.y())));
        let mut drawn: Vec<(f64, f64, f64)> = load
            .iter()
            .map(|&(t, x, y)| {
                let t = if t < origin - 1e-9 { t + 2.0 * PI } else { t };
                (t / PI, x, y)
            })
            .collect();
        drawn.sort_by(|a, b| a.0.total_cmp(&b.0));
        let lo = load.iter().map(|p| p.1.min(p.2)).fold(f64::MAX, f64::min);
        let hi = load.iter().map(|p| p.1.max(p.2)).fold(f64::MIN, f64::max);
        let (lo, hi) = padded(lo, hi);
        let mut chart = ChartBuilder::on(&right)
            .caption("(b) load: χP/(f p₀ a) black, T/(f p₀ a²) green", font(16.0))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(52)
            .build_cartesian_2d(lo..hi, o0..o1)
            .map_err(s)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("load")
            .y_desc("ωt")
            .axis_desc_style(font(18.0))
            .label_style(font(14.0))
            .y_labels(9)
            .y_label_formatter(&pi_label)
            .draw()
            .map_err(s)?;
        // The series are named in the caption: a legend box would cover
        // the curves, which fill the panel.
        chart
            .draw_series(LineSeries::new(
                drawn.iter().map(|p| (p.1, p.0)),
                BLACK.stroke_width(2),
            ))
            .map_err(s)?;
        chart
            .draw_series(LineSeries::new(
                drawn.iter().map(|p| (p.2, p.0)),
                GREEN_LINE.stroke_width(2),
            ))
            .map_err(s)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_across_the_origin_split() {
        let o = 1.0;
        assert_eq!(shifted(1.0, 1.5, o), vec![(1.0, 1.5)]);
        assert_eq!(shifted(0.5, 1.0, o), vec![(0.5 + 2.0 * PI, 1.0 + 2.0 * PI)]);
        assert_eq!(shifted(0.5, 1.5, o).len(), 2);
        assert_eq!(shifted(0.0, 0.1, 0.0), vec![(0.0, 0.1)]);
    }

    #[test]
    fn origin_parses() {
        assert_eq!("auto".parse::<TimeOrigin>().unwrap(), TimeOrigin::Auto);
        assert_eq!("0".parse::<TimeOrigin>().unwrap(), TimeOrigin::At(0.0));
        assert!("x".parse::<TimeOrigin>().is_err());
    }
}
