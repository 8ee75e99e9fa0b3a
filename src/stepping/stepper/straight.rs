//! The stepper's straight-run bookkeeping: whether a step may take a whole
//! straight run of increments, how many the step under way takes, the
//! runs of the cycle found so far, and the increments that go one at a
//! time after a run did not settle. Kept apart from the physics state and
//! the reporting switches of [`super::Stepper`].

use crate::model::LoadPoint;

/// Straight runs of the increments of a transient segment or of a cycle
/// (see [`super::Stepper::set_straight_runs`]).
#[derive(Debug, Clone)]
pub(super) struct StraightRuns {
    /// Whether a step takes a whole straight run of increments.
    pub(super) on: bool,
    /// Increments the step under way takes: 1, or a straight run's.
    pub(super) span: usize,
    /// The end of the straight run of the cycle from each increment, once
    /// a step has started there (0 until then).
    ends: Vec<usize>,
    /// Increments of the current transient segment or cycle below this one
    /// are taken one at a time: a straight run's step did not settle.
    single_until: usize,
}

impl StraightRuns {
    /// Off, for a cycle of `steps` increments.
    pub(super) fn new(steps: usize) -> Self {
        Self {
            on: false,
            span: 1,
            ends: vec![0; steps],
            single_until: 0,
        }
    }

    /// Increments below `increment` of the current segment or cycle go one
    /// at a time (a straight run's step up to it did not settle).
    pub(super) fn refuse_below(&mut self, increment: usize) {
        self.single_until = increment;
    }

    /// A new segment or cycle: every increment may start a run again.
    pub(super) fn refuse_none(&mut self) {
        self.single_until = 0;
    }

    /// Increments a step from `increment` of a transient segment of `len`
    /// increments takes: the rest of the segment, or 1.
    pub(super) fn span_in_segment(&self, increment: usize, len: usize) -> usize {
        if self.on && increment >= self.single_until {
            len - increment
        } else {
            1
        }
    }

    /// Increments a step from `increment` of the cycle whose load points
    /// are `pts` takes: the straight run from there ([`Self::end_from`]),
    /// or 1.
    pub(super) fn span_in_cycle(&mut self, pts: &[LoadPoint], increment: usize) -> usize {
        if self.on && increment >= self.single_until {
            self.end_from(pts, increment) - increment
        } else {
            1
        }
    }

    /// The increment `m` of the cycle, and the parameter `r` in `[0, 1]` of
    /// its chord, at parameter `s` of the step from `increment` (a straight
    /// run of [`Self::span`] increments of the cycle whose load points are
    /// `pts`): where the run's chord passes the same load point. One
    /// increment: `(increment, s)` itself.
    pub(super) fn within(&self, pts: &[LoadPoint], increment: usize, s: f64) -> (usize, f64) {
        if self.span == 1 || s <= 0.0 {
            return (increment, s);
        }
        let pts = &pts[increment..=increment + self.span];
        let (a, b) = (pts[0], pts[self.span]);
        let (dx, dy) = (b.x() - a.x(), b.y() - a.y());
        // Where vertex `m` of the run lies along its chord: 0 at the first,
        // 1 at the last, increasing between (the run goes one way).
        let along = |m: usize| {
            if m == self.span {
                1.0
            } else {
                let p = pts[m];
                ((p.x() - a.x()) * dx + (p.y() - a.y()) * dy) / (dx * dx + dy * dy)
            }
        };
        // The last vertex at or before `s`, by bisection.
        let (mut lo, mut hi) = (0, self.span);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if along(mid) <= s {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (start, end) = (if lo == 0 { 0.0 } else { along(lo) }, along(lo + 1));
        (
            increment + lo,
            ((s - start) / (end - start)).clamp(0.0, 1.0),
        )
    }

    /// The end of the straight run of the cycle's increments from
    /// `increment` (`pts` the cycle's `steps + 1` load points): the last
    /// vertex `j` such that the vertices between lie on the chord
    /// `increment -> j` to within the rounding of the load points
    /// themselves (a few ulps), each chord going the same way. Along such a
    /// run the polygon of the increments is that one chord, so a step along
    /// it follows the same path, with fewer stops.
    fn end_from(&mut self, pts: &[LoadPoint], increment: usize) -> usize {
        let steps = pts.len() - 1;
        if self.ends[increment] != 0 {
            return self.ends[increment];
        }
        let a = pts[increment];
        let size = |p: LoadPoint| p.x().abs().max(p.y().abs());
        // Off the chord `a -> b` by more than the rounding of the points.
        let off = |p: LoadPoint, b: LoadPoint, scale: f64| {
            let (dx, dy) = (b.x() - a.x(), b.y() - a.y());
            ((p.x() - a.x()) * dy - (p.y() - a.y()) * dx).abs()
                > 64.0 * f64::EPSILON * scale * dx.hypot(dy)
        };
        // Grow the run while each next vertex goes on the same way, in line
        // with the run so far ...
        let mut end = increment + 1;
        let mut scale = size(a).max(size(pts[end]));
        while end < steps {
            let (last, b) = (pts[end], pts[end + 1]);
            let forward =
                (b.x() - last.x()) * (b.x() - a.x()) + (b.y() - last.y()) * (b.y() - a.y());
            let wider = scale.max(size(b));
            if forward <= 0.0 || off(b, last, wider) {
                break;
            }
            scale = wider;
            end += 1;
        }
        // ... then hold every vertex between to the whole chord, cutting
        // the run at the first one off it (rarely, if ever: a slow drift).
        while let Some(m) = (increment + 1..end).find(|&m| off(pts[m], pts[end], scale)) {
            end = m;
        }
        self.ends[increment] = end;
        end
    }
}
