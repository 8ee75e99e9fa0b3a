//! Slip zones over one steady cycle next to the load variation (Figs. 5,
//! 7). The cycle is drawn from a chosen time origin ([`TimeOrigin`]); the
//! default starts it at a slip-free instant, so that no slip event is cut
//! in two by the ends of the axis.

use std::f64::consts::PI;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{
    direction_colour, direction_label, directions_forward_first, padded, pi_label, readable, s,
    Figure, Frame, Key, Pattern, Pen, Sample, GREEN_LINE,
};
use crate::analysis::slip_map::SlipMap;
use crate::contact::SlipDirection;
use crate::io::parse::{parse_angle, ParseError};

/// Where the drawn cycle starts (`omega t` at the bottom of the axes).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum TimeOrigin {
    /// At `omega t = 0` when no slip event runs through it, else in the
    /// middle of the longest slip-free stretch of the cycle, else at the
    /// instant with the least slip ([`auto_origin`]).
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

/// `0` when the rows either side of `omega t = 0` are slip-free, so no
/// slip event is cut there; else the middle (in time) of the longest
/// slip-free stretch of the cycle (taken round the cycle, so a stretch may
/// wrap through `2 pi`): the slip events then sit whole in the middle of
/// the axis. When every row has slip somewhere, the start of the one in
/// which the fewest nodes slip.
pub fn auto_origin(map: &SlipMap) -> f64 {
    let n = map.rows.len();
    if n == 0 {
        return 0.0;
    }
    let slipping = |k: usize| {
        map.rows[k % n]
            .directions
            .iter()
            .filter(|d| d.is_slipping())
            .count()
    };
    if slipping(0) == 0 && slipping(n - 1) == 0 {
        return 0.0;
    }
    let span = |k: usize| {
        let r = &map.rows[k % n];
        r.t1 - r.t0
    };
    // The longest circular run of slip-free rows, by time.
    let mut best: Option<(usize, f64)> = None;
    let mut k = 0;
    while k < n {
        if slipping(k) == 0 {
            let (mut len, mut time) = (0, 0.0);
            while len < n && slipping(k + len) == 0 {
                time += span(k + len);
                len += 1;
            }
            if best.is_none_or(|(_, t)| time > t) {
                best = Some((k, time));
            }
            k += len.max(1);
        } else {
            k += 1;
        }
    }
    match best {
        Some((start, time)) => (map.rows[start].t0 + 0.5 * time).rem_euclid(2.0 * PI),
        None => {
            let k = (0..n).min_by_key(|&k| (slipping(k), k)).unwrap_or(0);
            map.rows[k].t0.rem_euclid(2.0 * PI)
        }
    }
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
    /// Its style and title.
    pub frame: Frame,
    /// Where the drawn cycle starts.
    pub origin: TimeOrigin,
}

/// A slip zone in one increment: `theta / pi` from `lo` to `hi`, its
/// direction.
type Run = (f64, f64, SlipDirection);

/// The slipping runs of one row, in display order from `theta = -pi`.
fn runs(map: &SlipMap, directions: &[SlipDirection]) -> Vec<Run> {
    let n = map.nodes;
    let half = 1.0 / n as f64;
    let order: Vec<usize> = (0..n).map(|k| (k + n / 2) % n).collect();
    let mut out = Vec::new();
    let mut k = 0;
    while k < n {
        let d = directions[order[k]];
        let mut end = k + 1;
        while end < n && directions[order[end]] == d {
            end += 1;
        }
        if d.is_slipping() {
            out.push((
                map.theta(order[k]) / PI - half,
                map.theta(order[end - 1]) / PI + half,
                d,
            ));
        }
        k = end;
    }
    out
}

/// A zone over one row: `(t0, t1, lo, hi)`.
type Segment = (f64, f64, f64, f64);

/// The slip zones as smooth bands, one polygon per zone from where it
/// appears (or splits off) to where it vanishes (or merges).
///
/// The rows are the cycle's sub-segments, which end at the exact event
/// times (a node entering slip or sticking), not the increment grid; a
/// zone's edge steps by one node at such a time. The band's edge runs
/// straight from one step to the next through the middle of each step, at
/// the step's exact time, so it follows the zone without the staircase of
/// the discrete nodes. `rows` are `(t0, t1, runs)` in drawn time (units of
/// pi), in order.
fn bands(rows: &[(f64, f64, Vec<Run>)]) -> Vec<(Vec<(f64, f64)>, SlipDirection)> {
    // A zone continues in the next row when the two touch or overlap.
    let continues = |a: &Run, b: &Run| {
        let tol = 0.5 * (a.1 - a.0).min(b.1 - b.0).min(0.05) + 1e-9;
        a.2 == b.2 && a.0 <= b.1 + tol && b.0 <= a.1 + tol
    };
    // Each zone's rows: (t0, t1, lo, hi), chained while it continues one
    // to one.
    let mut chains: Vec<(SlipDirection, Vec<Segment>)> = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    for (k, (t0, t1, runs)) in rows.iter().enumerate() {
        // Adjacent rows only: not across a gap (the ends of the axis).
        let prev = k
            .checked_sub(1)
            .map(|j| &rows[j].2)
            .filter(|_| (rows[k - 1].1 - t0).abs() < 1e-9);
        let mut now = Vec::with_capacity(runs.len());
        for run in runs {
            let preds: Vec<usize> = prev
                .map(|p| (0..p.len()).filter(|&i| continues(&p[i], run)).collect())
                .unwrap_or_default();
            let one_to_one = preds.len() == 1
                && runs
                    .iter()
                    .filter(|r| continues(&prev.unwrap()[preds[0]], r))
                    .count()
                    == 1;
            let chain = if one_to_one {
                open[preds[0]]
            } else {
                chains.push((run.2, Vec::new()));
                chains.len() - 1
            };
            chains[chain].1.push((*t0, *t1, run.0, run.1));
            now.push(chain);
        }
        open = now;
    }
    chains
        .into_iter()
        .map(|(dir, segs)| {
            // The edge's knots: its ends, and the middle of every step.
            let knots = |edge: fn(&Segment) -> f64| {
                let mut v = vec![(edge(&segs[0]), segs[0].0)];
                for w in segs.windows(2) {
                    let (a, b) = (edge(&w[0]), edge(&w[1]));
                    if a != b {
                        v.push((0.5 * (a + b), w[0].1));
                    }
                }
                let last = &segs[segs.len() - 1];
                v.push((edge(last), last.1));
                v
            };
            let mut outline = knots(|s| s.2);
            outline.extend(knots(|s| s.3).into_iter().rev());
            (outline, dir)
        })
        .collect()
}

impl SlipMapPlot<'_> {
    /// The directions that occur in the cycle, the paper's forward first.
    fn directions(&self) -> Vec<SlipDirection> {
        directions_forward_first()
            .into_iter()
            .filter(|d| self.map.rows.iter().any(|r| r.directions.contains(d)))
            .collect()
    }

    /// The name of the time axis: `ωt`, or `ω(t − t₀)` when the drawn
    /// cycle does not start at `t = 0`.
    fn time_desc(&self) -> &'static str {
        if self.origin.resolve(self.map) == 0.0 {
            "ωt"
        } else {
            "ω(t − t₀)"
        }
    }
}

impl Figure for SlipMapPlot<'_> {
    fn frame(&self) -> &Frame {
        &self.frame
    }

    fn key(&self) -> Key {
        let mut key = Key::default();
        for d in self.directions() {
            key.push(Sample::Swatch(direction_colour(d)), direction_label(d));
        }
        key.push(Sample::Line(Pattern::Solid, BLACK, 1.5), "(b) χP/(f p₀ a)");
        key.push(
            Sample::Line(Pattern::Solid, GREEN_LINE, 1.5),
            "(b) T/(f p₀ a²)",
        );
        key
    }

    fn plots_aspect(&self) -> f64 {
        self.frame.one_column_or(0.85, 0.55)
    }

    fn caption_tail(&self) -> String {
        let map = self.map;
        let origin = self.origin.resolve(map);
        let time = if origin == 0.0 {
            "ωt runs over one steady cycle from 0".to_string()
        } else {
            format!(
                "time is drawn from ωt₀ = {} (so that no slip event is cut in two)",
                pi_label(&(origin / PI))
            )
        };
        format!(
            ": {}, W = {} per cycle. (a) Slip zones over one steady cycle against θ; (b) the load against the same time; {time}.",
            map.outcome.state(),
            readable(map.outcome.dissipation)
        )
    }

    fn draw_plots<DB: DrawingBackend>(
        &self,
        plots: &DrawingArea<DB, Shift>,
        pen: &Pen,
    ) -> Result<(), String> {
        let map = self.map;
        let origin = self.origin.resolve(map);
        let (left, right) = plots.split_horizontally(plots.dim_in_pixel().0 * 3 / 5);
        let t_desc = self.time_desc();

        // (a) the slip map: theta across, time up, in units of pi, from 0.
        let mut chart = pen
            .chart(&left)
            .caption("(a)", pen.text())
            .build_cartesian_2d(-1.0..1.0, 0.0..2.0)
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc("θ")
            .y_desc(t_desc)
            .x_labels(5)
            .y_labels(9)
            .x_label_formatter(&pi_label)
            .y_label_formatter(&pi_label)
            .draw()
            .map_err(s)?;
        let mut rows: Vec<(f64, f64, Vec<Run>)> = Vec::new();
        for r in &map.rows {
            let rs = runs(map, &r.directions);
            for (a, b) in shifted(r.t0, r.t1, origin) {
                rows.push(((a - origin) / PI, (b - origin) / PI, rs.clone()));
            }
        }
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        let shapes = bands(&rows);
        for dir in self.directions() {
            let colour = direction_colour(dir);
            chart
                .draw_series(
                    shapes
                        .iter()
                        .filter(|c| c.1 == dir)
                        .map(|c| Polygon::new(c.0.clone(), colour.filled())),
                )
                .map_err(s)?;
        }

        // (b) the load variation against the same time.
        let mut load: Vec<(f64, f64, f64)> = vec![(0.0, map.start.x(), map.start.y())];
        load.extend(map.rows.iter().map(|r| (r.t1, r.load.x(), r.load.y())));
        let mut drawn: Vec<(f64, f64, f64)> = load
            .iter()
            .map(|&(t, x, y)| {
                let t = if t < origin - 1e-9 { t + 2.0 * PI } else { t };
                ((t - origin) / PI, x, y)
            })
            .collect();
        drawn.sort_by(|a, b| a.0.total_cmp(&b.0));
        let lo = load.iter().map(|p| p.1.min(p.2)).fold(f64::MAX, f64::min);
        let hi = load.iter().map(|p| p.1.max(p.2)).fold(f64::MIN, f64::max);
        let (lo, hi) = padded(lo, hi);
        let mut chart = pen
            .chart(&right)
            .caption("(b)", pen.text())
            .build_cartesian_2d(lo..hi, 0.0..2.0)
            .map_err(s)?;
        pen.axes(&mut chart.configure_mesh())
            .x_desc("load")
            .y_desc(t_desc)
            .x_labels(5)
            .y_labels(9)
            .y_label_formatter(&pi_label)
            .draw()
            .map_err(s)?;
        chart
            .draw_series(LineSeries::new(
                drawn.iter().map(|p| (p.1, p.0)),
                pen.line(BLACK, 1.5),
            ))
            .map_err(s)?;
        chart
            .draw_series(LineSeries::new(
                drawn.iter().map(|p| (p.2, p.0)),
                pen.line(GREEN_LINE, 1.5),
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
