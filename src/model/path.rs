//! Load paths (model.md section 5): the initial transients that prepare the
//! locked-in slip, and the steady cycle of eq. (11) that follows.
//!
//! Because slip changes the contact pressure, the steady state can depend on
//! the history before the cycle; an [`Initial`] names that history. The
//! paper's 25 transients are `OA` and the 24 paths `O -> I -> A` through the
//! crosses of Fig. 2 (model.md section 5.2), in a stable order used by every
//! table, CSV and plot.
//!
//! ```
//! use shakedown::model::path::{Initial, PathError};
//!
//! assert_eq!(Initial::parse("7,-7"), Ok(Initial::Via { a: 7, b: -7 }));
//! assert_eq!(Initial::parse("OA"), Ok(Initial::Direct));
//! // (3 pi/4, 3 pi/4) lies inside the stick diamond: it would leave no slip.
//! assert_eq!(Initial::parse("3,3"), Err(PathError::InsideStick(3, 3)));
//!
//! let all = Initial::paper_set();
//! assert_eq!(all.len(), 25);
//! assert_eq!(all[1].name(), "-7,-7");
//! ```

use std::f64::consts::{FRAC_PI_4, PI};
use std::sync::Arc;

use crate::model::{Cycle, LoadPoint, Material};

/// A bad initial-path name or custom path.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// The text is neither `OA` nor a pair of integers `a,b` (the text as
    /// given).
    #[error(
        "initial path '{0}' is not known: expected OA, optimal, or one of the 24 points a,b in units of pi/4 with |a|,|b| in {{3,5,7}} and |a|+|b| > 8 (e.g. 7,-7)"
    )]
    Unknown(String),
    /// The point `I = (a pi/4, b pi/4)` lies in the initial stick diamond
    /// `|x| + |y| <= 2 pi` (model.md section 2.3), so the path would leave
    /// no locked-in slip: `(a, b)`.
    #[error(
        "initial point {0},{1} (units of pi/4) lies inside the initial stick region |x|+|y| <= 2pi, so it prepares no slip: pick |a|+|b| > 8"
    )]
    InsideStick(i32, i32),
    /// The point `(a, b)` is outside the diamond but not one of the paper's
    /// 24 (`|a|, |b|` in `{3, 5, 7}`, `|a| + |b| > 8`).
    #[error(
        "initial point {0},{1} (units of pi/4) is not one of the paper's 24: |a| and |b| must be 3, 5 or 7 with |a|+|b| > 8"
    )]
    NotPaperPoint(i32, i32),
    /// A list ends with a lone number where a point `a,b` needs two (the
    /// number as given).
    #[error("initial point '{0}' needs two numbers a,b (units of pi/4)")]
    HalfPoint(String),
    /// The list of initial paths is empty.
    #[error("the list of initial paths is empty")]
    EmptyList,
    /// A point of a custom transient has a NaN or infinite coordinate.
    #[error("custom path point {index} is not finite")]
    NotFinite {
        /// Position of the offending point in the list (from 1).
        index: usize,
    },
    /// A custom path point beyond the gross-slip line `|y| = 2 pi`.
    #[error("custom path point {index} ({x}, {y}) is beyond gross slip: |y| must be below 2 pi = 6.2832")]
    GrossSlip {
        /// Position of the point in the list (from 1).
        index: usize,
        /// Its `x`.
        x: f64,
        /// Its `y`.
        y: f64,
    },
    /// A custom path point at which the contact separates.
    #[error("custom path point {index} ({x}, {y}) separates the contact: |x| must be below 2 pi chi / (f beta) = {limit:.4}")]
    Separation {
        /// Position of the point in the list (from 1).
        index: usize,
        /// Its `x`.
        x: f64,
        /// Its `y`.
        y: f64,
        /// The separation bound on `|x|` for this material.
        limit: f64,
    },
    /// A custom path with no point.
    #[error("a custom path needs at least one point")]
    EmptyPath,
}

/// How the locked-in slip is prepared before the steady cycle starts
/// (model.md sections 5.2 and 7.4).
///
/// Every path but [`Initial::Slip`] and [`Initial::Optimal`] starts at the
/// unloaded, unslipped state `O` and ends at the cycle centre `A`; the
/// straight entry `A -> C` onto the cycle follows in every case (model.md
/// section 5.3, [`entry_waypoints`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Initial {
    /// The direct path `O -> A` ("OA").
    Direct,
    /// `O -> I -> A` with `I = (a pi/4, b pi/4)`: one of the paper's 24.
    Via {
        /// `x` of the turning point `I`, in units of `pi/4`.
        a: i32,
        /// `y` of the turning point `I`, in units of `pi/4`.
        b: i32,
    },
    /// `O -> p1 -> ... -> pk -> A`, a user's own transient.
    Custom(Vec<LoadPoint>),
    /// Start at `A` with this locked-in slip and no transient (model.md
    /// section 7.4: the optimal slip of the `lambda_2` problem).
    Slip {
        /// The name reported for this path (e.g. `optimal`).
        name: String,
        /// The nodal slip `g_j`, one value per interface node.
        slip: Arc<Vec<f64>>,
    },
    /// The optimal slip of the `lambda_2` problem, not yet computed: it
    /// depends on the cycle's phase, so a sweep over `phi` resolves it once
    /// per phase ([`crate::analysis::sweep::SweepSpec::run`]), and a single case
    /// resolves it with [`crate::analysis::limit::optimal_initial`]. A stepper given
    /// this unresolved marker would start at `A` with no slip, so resolve it
    /// first.
    Optimal,
}

impl Initial {
    /// The paper's 25 transients in their stable order: `OA` first, then
    /// the 24 points sorted by `a` then `b` (both from -7 to 7).
    pub fn paper_set() -> Vec<Initial> {
        let mut out = vec![Initial::Direct];
        let values: [i32; 6] = [-7, -5, -3, 3, 5, 7];
        for a in values {
            for b in values {
                if a.abs() + b.abs() > 8 {
                    out.push(Initial::Via { a, b });
                }
            }
        }
        out
    }

    /// Stable name: `OA`, `a,b`, `path:x1,y1;...` (units of pi) or the
    /// slip's name.
    pub fn name(&self) -> String {
        match self {
            Initial::Direct => "OA".into(),
            Initial::Via { a, b } => format!("{a},{b}"),
            Initial::Custom(points) => custom_name(points),
            Initial::Slip { name, .. } => name.clone(),
            Initial::Optimal => "optimal".into(),
        }
    }

    /// Parse `OA` or `a,b`. (`optimal` needs the limit analysis and is
    /// resolved by the caller, e.g. [`crate::analysis::case::resolve_initial`].)
    /// Case and surrounding spaces are ignored; the result's
    /// [`Initial::name`] parses back to it.
    ///
    /// # Errors
    ///
    /// [`PathError::Unknown`] for anything but `OA` or two integers `a,b`
    /// (including `optimal`); [`PathError::InsideStick`] if `I` lies in the
    /// stick diamond; [`PathError::NotPaperPoint`] if it is outside the
    /// diamond but not one of the paper's 24.
    pub fn parse(text: &str) -> Result<Initial, PathError> {
        let t = text.trim();
        if t.eq_ignore_ascii_case("oa") {
            return Ok(Initial::Direct);
        }
        let parts: Vec<&str> = t.split(',').map(str::trim).collect();
        if parts.len() != 2 {
            return Err(PathError::Unknown(text.to_string()));
        }
        let (Ok(a), Ok(b)) = (parts[0].parse::<i32>(), parts[1].parse::<i32>()) else {
            return Err(PathError::Unknown(text.to_string()));
        };
        // unsigned_abs: `i32::MIN.abs()` overflows.
        let (ua, ub) = (u64::from(a.unsigned_abs()), u64::from(b.unsigned_abs()));
        if ua + ub <= 8 {
            return Err(PathError::InsideStick(a, b));
        }
        let ok = |v: i32| matches!(v.unsigned_abs(), 3 | 5 | 7);
        if !ok(a) || !ok(b) {
            return Err(PathError::NotPaperPoint(a, b));
        }
        Ok(Initial::Via { a, b })
    }

    /// Parse a list such as `all`, `OA,7,-7,3,7` or `all,optimal`: `all` is
    /// the paper's 25, `optimal` the (unresolved) [`Initial::Optimal`], and a
    /// point takes two numbers. Repeats are dropped, keeping the first.
    ///
    /// # Errors
    ///
    /// [`PathError::EmptyList`] for an empty text; [`PathError::HalfPoint`]
    /// for a trailing lone number; otherwise the first error of
    /// [`Initial::parse`] on an item (an empty item between commas is
    /// [`PathError::Unknown`]).
    ///
    /// ```
    /// use shakedown::model::path::Initial;
    ///
    /// let list = Initial::parse_list("all,optimal").unwrap();
    /// assert_eq!(list.len(), 26);
    /// assert_eq!(list[25], Initial::Optimal);
    /// assert_eq!(
    ///     Initial::parse_list("OA, 7,-7, oa").unwrap(),
    ///     vec![Initial::Direct, Initial::Via { a: 7, b: -7 }],
    /// );
    /// ```
    pub fn parse_list(text: &str) -> Result<Vec<Initial>, PathError> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        let mut out: Vec<Initial> = Vec::new();
        let push = |i: Initial, out: &mut Vec<Initial>| {
            if !out.contains(&i) {
                out.push(i);
            }
        };
        let mut k = 0;
        while k < parts.len() {
            let p = parts[k];
            if p.parse::<i32>().is_ok() {
                let q = parts
                    .get(k + 1)
                    .ok_or_else(|| PathError::HalfPoint(p.to_string()))?;
                push(Initial::parse(&format!("{p},{q}"))?, &mut out);
                k += 2;
                continue;
            }
            if p.eq_ignore_ascii_case("all") {
                for i in Initial::paper_set() {
                    push(i, &mut out);
                }
            } else if p.eq_ignore_ascii_case("optimal") {
                push(Initial::Optimal, &mut out);
            } else if p.is_empty() && parts.len() == 1 {
                return Err(PathError::EmptyList);
            } else {
                push(Initial::parse(p)?, &mut out);
            }
            k += 1;
        }
        Ok(out)
    }

    /// A custom transient through the given load-plane points.
    ///
    /// # Errors
    ///
    /// [`PathError::NotFinite`] for a point that is not finite (numbered
    /// from 1).
    pub fn custom(points: Vec<LoadPoint>) -> Result<Initial, PathError> {
        if let Some(index) = points
            .iter()
            .position(|p| !(p.x().is_finite() && p.y().is_finite()))
        {
            return Err(PathError::NotFinite { index: index + 1 });
        }
        Ok(Initial::Custom(points))
    }

    /// A custom transient `O -> points -> A` for `material`, with every
    /// point checked: finite, inside gross slip (`|y| < 2 pi`) and free of
    /// separation without locked-in slip (`|x| < 2 pi chi / (f beta)`,
    /// model.md section 1). The run itself still reports gross slip or
    /// separation that locked-in slip brings on earlier.
    ///
    /// # Errors
    ///
    /// [`PathError::EmptyPath`], [`PathError::NotFinite`],
    /// [`PathError::GrossSlip`] or [`PathError::Separation`], naming the
    /// first bad point (numbered from 1).
    pub fn custom_for(points: Vec<LoadPoint>, material: &Material) -> Result<Initial, PathError> {
        if points.is_empty() {
            return Err(PathError::EmptyPath);
        }
        let limit = 2.0 * PI * material.chi() / (material.friction() * material.beta());
        for (k, p) in points.iter().enumerate() {
            let (index, x, y) = (k + 1, p.x(), p.y());
            if !(x.is_finite() && y.is_finite()) {
                return Err(PathError::NotFinite { index });
            }
            if y.abs() >= 2.0 * PI {
                return Err(PathError::GrossSlip { index, x, y });
            }
            if x.abs() >= limit {
                return Err(PathError::Separation { index, x, y, limit });
            }
        }
        Ok(Initial::Custom(points))
    }

    /// Waypoints of the transient from the unloaded state to the cycle
    /// centre `A` (inclusive), for the paths that start at `O`: `[O, A]`,
    /// `[O, I, A]` or `[O, p1, ..., pk, A]`. For [`Initial::Slip`] and
    /// [`Initial::Optimal`], which start at `A`, it is `[A]` alone.
    pub fn waypoints_to(&self, center: LoadPoint) -> Vec<LoadPoint> {
        let mut w = vec![LoadPoint::ORIGIN];
        match self {
            Initial::Direct => {}
            Initial::Via { a, b } => {
                w.push(LoadPoint::new(*a as f64 * FRAC_PI_4, *b as f64 * FRAC_PI_4));
            }
            Initial::Custom(points) => w.extend(points.iter().copied()),
            Initial::Slip { .. } | Initial::Optimal => return vec![center],
        }
        w.push(center);
        w
    }
}

/// `path:x1,y1;x2,y2` with the coordinates in units of pi (`1.75pi`), the
/// form `--initial-path` takes: a stable name for a custom path in a
/// sweep's CSV.
fn custom_name(points: &[LoadPoint]) -> String {
    let pi = |v: f64| format!("{}pi", v / PI);
    let parts: Vec<String> = points
        .iter()
        .map(|p| format!("{},{}", pi(p.x()), pi(p.y())))
        .collect();
    format!("path:{}", parts.join(";"))
}

/// Serialised as its stable [`Initial::name`] (a slip's values are in
/// their own file, named by content).
impl serde::Serialize for Initial {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}

impl std::fmt::Display for Initial {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}

/// One straight segment of a transient, cut into equal increments (at
/// least one: [`Segment::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    from: LoadPoint,
    to: LoadPoint,
    increments: usize,
}

impl Segment {
    /// The segment `from -> to`, cut into the fewest equal increments no
    /// longer than `max_step` (at least one, even for a zero-length
    /// segment); `max_step` is normally
    /// [`crate::model::Discretisation::transient_step`].
    pub fn new(from: LoadPoint, to: LoadPoint, max_step: f64) -> Self {
        let increments = ((from.distance(to) / max_step).ceil() as usize).max(1);
        Self {
            from,
            to,
            increments,
        }
    }
    /// The load point at fraction `s` of the way, `from + s (to - from)`
    /// (`s` in `[0, 1]` on the segment).
    pub fn at(&self, s: f64) -> LoadPoint {
        self.from.lerp(self.to, s)
    }
    /// Start of the segment in the load plane.
    pub fn from(&self) -> LoadPoint {
        self.from
    }
    /// End of the segment in the load plane.
    pub fn to(&self) -> LoadPoint {
        self.to
    }
    /// Number of equal increments, at least 1.
    pub fn increments(&self) -> usize {
        self.increments
    }
}

/// Straight segments through the waypoints, skipping zero-length ones
/// (so that, e.g., the `A -> C` entry of an in-phase cycle, where `C = A`,
/// gives no segment), each cut into increments no longer than `max_step`.
pub fn segments(waypoints: &[LoadPoint], max_step: f64) -> Vec<Segment> {
    waypoints
        .windows(2)
        .filter(|w| w[0].distance(w[1]) > 1e-14)
        .map(|w| Segment::new(w[0], w[1], max_step))
        .collect()
}

/// The waypoints `[A, C]` of the segment `A -> C` from the cycle centre to
/// the cycle's `t = 0` point ([`Cycle::start`]). For `phi = 0` it is empty
/// (`C = A`, and [`segments`] drops it). The paper does not say how the
/// ellipse is entered; this straight segment is this project's convention
/// (model.md section 5.3). It belongs to the transient: slip on it counts as
/// slip after `A` for the stuck fraction `r` (model.md section 7.2).
pub fn entry_waypoints(cycle: &Cycle) -> Vec<LoadPoint> {
    vec![cycle.center(), cycle.start()]
}

/// Whether `p` lies in the initial stick region `|x| + |y| <= 2 pi` (model.md
/// section 2.3): a path from `O` that stays inside it causes no slip.
pub fn inside_stick_diamond(p: LoadPoint) -> bool {
    p.diamond_norm() <= 2.0 * PI
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_set_has_25_outside_the_diamond() {
        let set = Initial::paper_set();
        assert_eq!(set.len(), 25);
        assert_eq!(set[0], Initial::Direct);
        for i in &set[1..] {
            let w = i.waypoints_to(LoadPoint::new(PI, 0.75 * PI));
            assert!(!inside_stick_diamond(w[1]), "{i}");
        }
        let names: std::collections::BTreeSet<String> = set.iter().map(|i| i.name()).collect();
        assert_eq!(names.len(), 25);
    }

    #[test]
    fn parse_names() {
        assert_eq!(Initial::parse("oa").unwrap(), Initial::Direct);
        assert_eq!(
            Initial::parse("7,-7").unwrap(),
            Initial::Via { a: 7, b: -7 }
        );
        assert_eq!(
            Initial::parse(" -3 , 7 ").unwrap(),
            Initial::Via { a: -3, b: 7 }
        );
        assert!(matches!(
            Initial::parse("3,3"),
            Err(PathError::InsideStick(3, 3))
        ));
        assert!(matches!(
            Initial::parse("9,9"),
            Err(PathError::NotPaperPoint(9, 9))
        ));
        assert!(matches!(
            Initial::parse("4,7"),
            Err(PathError::NotPaperPoint(4, 7))
        ));
        assert!(Initial::parse("x").is_err());
        for i in Initial::paper_set() {
            assert_eq!(Initial::parse(&i.name()).unwrap(), i);
        }
    }

    #[test]
    fn parse_lists() {
        let l = Initial::parse_list("all,optimal").unwrap();
        assert_eq!(l.len(), 26);
        assert_eq!(l[25], Initial::Optimal);
        assert_eq!(
            Initial::parse_list("OA, 7,-7 ,oa").unwrap(),
            vec![Initial::Direct, Initial::Via { a: 7, b: -7 }]
        );
        assert!(matches!(
            Initial::parse_list("OA,7"),
            Err(PathError::HalfPoint(_))
        ));
        assert!(matches!(Initial::parse_list(""), Err(PathError::EmptyList)));
        assert!(Initial::parse_list("OA,,7,7").is_err());
    }
}
