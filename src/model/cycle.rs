//! The steady cycle in the load plane: the paper's ellipse of eq. (11)
//! (model.md section 5.1) or any closed polyline (model.md section 5.4).

use std::f64::consts::PI;
use std::sync::Arc;

use serde::Serialize;

use super::{finite, LoadPoint, ParamError};

/// Most vertices a polyline cycle may have: a cycle's load points are
/// tabulated per increment, and the increments per cycle are at most
/// 100000 (a multiple of the vertex count, model.md section 5.4).
pub const MAX_VERTICES: usize = 100_000;

/// The oscillating part of the load (model.md section 5): the offsets from
/// the centre `A` that `lambda` scales.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Shape {
    /// The paper's ellipse of eq. (11), with slope `psi` and phase `phi`.
    Ellipse {
        /// `psi`: eq. (13), `Tt1 / (chi Pt1)`; the slope of the load line
        /// for `phi = 0`.
        slope: f64,
        /// `phi`, radians: the phase of the torque relative to the force.
        phase: f64,
    },
    /// A closed polyline through the offsets of a [`Polyline`] in time
    /// order, equal time per chord (model.md section 5.4).
    Polyline(Polyline),
}

/// A closed polyline of load-plane offsets `(u, v)` from the centre, one
/// vertex per equal share of the period, in time order; the last vertex
/// joins the first. Validated: at least 3 vertices, at most
/// [`MAX_VERTICES`], all finite and of modest size.
///
/// ```
/// use shakedown::model::{LoadPoint, Polyline};
///
/// let square = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)];
/// let p = Polyline::new("square", square.iter().map(|&(u, v)| LoadPoint::new(u, v)).collect())?;
/// assert_eq!(p.vertices().len(), 4);
/// assert!(Polyline::new("two", vec![LoadPoint::new(0.0, 0.0); 2]).is_err());
/// # Ok::<(), shakedown::model::ParamError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Polyline {
    /// How the cycle is identified in headers and names (for a file,
    /// `cycle:NAME@sha256:DIGEST`, so that its content is recorded).
    name: String,
    /// The offsets `(u, v)`, shared by every run of a sweep.
    #[serde(serialize_with = "serialize_slice")]
    vertices: Arc<[LoadPoint]>,
}

fn serialize_slice<S: serde::Serializer>(v: &Arc<[LoadPoint]>, s: S) -> Result<S::Ok, S::Error> {
    v[..].serialize(s)
}

impl Polyline {
    /// The polyline through `vertices` (offsets from the centre), named
    /// `name` in headers.
    ///
    /// # Errors
    ///
    /// [`ParamError::BadCount`] (`cycle`) for fewer than 3 or more than
    /// [`MAX_VERTICES`] vertices; [`ParamError::NotFinite`] (`cycle`) for a
    /// coordinate that is not finite; [`ParamError::OutOfRange`] (`cycle`)
    /// for an offset beyond 1000 (a sanity bound: gross slip sets in at
    /// `|y| = 2 pi`).
    pub fn new(name: impl Into<String>, vertices: Vec<LoadPoint>) -> Result<Self, ParamError> {
        if !(3..=MAX_VERTICES).contains(&vertices.len()) {
            return Err(ParamError::BadCount {
                name: "cycle",
                value: vertices.len(),
                expected: "3 to 100000 vertices",
            });
        }
        for v in &vertices {
            finite("cycle", v.x())?;
            finite("cycle", v.y())?;
            let size = v.x().abs().max(v.y().abs());
            if size > 1e3 {
                return Err(ParamError::OutOfRange {
                    name: "cycle",
                    value: size,
                    expected: "offsets |u|, |v| <= 1000",
                });
            }
        }
        Ok(Self {
            name: name.into(),
            vertices: vertices.into(),
        })
    }
    /// The name recorded in headers.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The offsets `(u, v)` in time order.
    pub fn vertices(&self) -> &[LoadPoint] {
        &self.vertices
    }
    /// The offset at `omega t = t`: on the chord from vertex `k` to `k + 1`
    /// for `t` in `[2 pi k / M, 2 pi (k + 1) / M)`, linear in time.
    fn at(&self, t: f64) -> LoadPoint {
        let m = self.vertices.len();
        let mut position = (t / (2.0 * PI)).rem_euclid(1.0) * m as f64;
        // A time computed for a vertex (`2 pi i / steps` with `steps` a
        // multiple of `M`) lands on the vertex exactly, not an ulp before it.
        let nearest = position.round();
        if (position - nearest).abs() <= 1e-9 {
            position = nearest;
        }
        // The end of the period is its start: the first vertex itself.
        if position >= m as f64 {
            position -= m as f64;
        }
        let k = (position.floor() as usize).min(m - 1);
        let r = position - k as f64;
        let next = if k + 1 == m { 0 } else { k + 1 };
        if r <= 0.0 {
            self.vertices[k]
        } else {
            self.vertices[k].lerp(self.vertices[next], r)
        }
    }
}

/// The steady cycle in the load plane (model.md section 5.1): centre `A`,
/// load factor `lambda` and a [`Shape`]. For the paper's ellipse,
///
/// ```text
/// x(t) = x0 + lambda sin(t) / sqrt(1 + psi^2)
/// y(t) = y0 + lambda psi sin(t + phi) / sqrt(1 + psi^2)
/// ```
///
/// with `t = omega t` in `[0, 2 pi)`. For `phi = 0` this is a straight
/// segment of half-length `lambda` and slope `psi` through `A`; otherwise an
/// ellipse centred on `A`. For a polyline, `x = x0 + lambda u(t)`,
/// `y = y0 + lambda v(t)` (model.md section 5.4). Build a cycle with
/// [`Cycle::new`], [`Cycle::paper`] or [`Cycle::polyline`] so that it is
/// validated.
///
/// ```
/// use std::f64::consts::PI;
/// use shakedown::model::Cycle;
///
/// // Point B of the paper: lambda = 7 in phase.
/// let c = Cycle::paper(7.0, 0.0).unwrap();
/// // A quarter cycle on, the load is at the end of the load line, at
/// // distance lambda from A along slope psi = 5/8.
/// let top = c.at(PI / 2.0);
/// assert!((c.center().distance(top) - 7.0).abs() < 1e-12);
/// assert!(((top.y() - c.center().y()) / (top.x() - c.center().x()) - 0.625).abs() < 1e-12);
/// // In phase, the cycle starts at its centre: C = A.
/// assert!(c.start().distance(c.center()) < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cycle {
    /// Centre `A = (x0, y0)` (`center`): the mean loads
    /// `(chi Pt0 / f, Tt0 / f)`, where every transient ends.
    center: LoadPoint,
    /// `lambda` (`load_factor`): the load factor of eq. (12),
    /// `sqrt((chi Pt1)^2 + Tt1^2) / f`, the amplitude of the cycle.
    load_factor: f64,
    /// The oscillating part the load factor scales.
    shape: Shape,
}

fn check_center_and_load_factor(center: LoadPoint, load_factor: f64) -> Result<(), ParamError> {
    finite("x0", center.x())?;
    finite("y0", center.y())?;
    super::ranges::LAMBDA.check(load_factor)?;
    if !(super::ranges::CENTER.contains(center.x()) && super::ranges::CENTER.contains(center.y())) {
        return Err(ParamError::OutOfRange {
            name: "center",
            value: center.x().abs().max(center.y().abs()),
            expected: super::ranges::CENTER.expected,
        });
    }
    Ok(())
}

impl Cycle {
    /// The paper's cycle: `x0 = pi`, `y0 = 3 pi / 4`, `psi = 5/8`
    /// (model.md section 5.1), with the given `lambda` and `phi`.
    ///
    /// # Errors
    ///
    /// As [`Cycle::new`]: a `lambda` or `phi` that is not finite, or out of
    /// range.
    ///
    /// ```
    /// use shakedown::model::{Cycle, ParamError};
    ///
    /// assert!(matches!(
    ///     Cycle::paper(-1.0, 0.0),
    ///     Err(ParamError::OutOfRange { name: "lambda", .. })
    /// ));
    /// assert!(matches!(
    ///     Cycle::paper(5.0, f64::NAN),
    ///     Err(ParamError::NotFinite { name: "phi", .. })
    /// ));
    /// ```
    pub fn paper(load_factor: f64, phase: f64) -> Result<Self, ParamError> {
        Self::new(LoadPoint::new(PI, 0.75 * PI), load_factor, 0.625, phase)
    }

    /// The ellipse with centre `A = center`, load factor `lambda =
    /// load_factor`, slope `psi = slope` and phase `phi = phase` (radians).
    ///
    /// # Errors
    ///
    /// [`ParamError::NotFinite`] if any coordinate or parameter is NaN or
    /// infinite; [`ParamError::OutOfRange`] unless `0 <= lambda <= 1000`,
    /// `|psi| <= 1e6`, `|x0|, |y0| <= 1000` and `|phi| <= 1000`. The bounds
    /// are sanity limits far outside the physical range (gross slip sets in
    /// at `|y| = 2 pi`, model.md section 2.3).
    pub fn new(
        center: LoadPoint,
        load_factor: f64,
        slope: f64,
        phase: f64,
    ) -> Result<Self, ParamError> {
        finite("x0", center.x())?;
        finite("y0", center.y())?;
        finite("lambda", load_factor)?;
        finite("psi", slope)?;
        finite("phi", phase)?;
        check_center_and_load_factor(center, load_factor)?;
        super::ranges::PSI.check(slope)?;
        super::ranges::PHI.check(phase)?;
        Ok(Self {
            center,
            load_factor,
            shape: Shape::Ellipse { slope, phase },
        })
    }

    /// The polyline cycle `x = x0 + lambda u`, `y = y0 + lambda v` through
    /// the offsets of `polyline` (model.md section 5.4).
    ///
    /// # Errors
    ///
    /// As [`Cycle::new`] for the centre and `lambda`.
    pub fn polyline(
        center: LoadPoint,
        load_factor: f64,
        polyline: Polyline,
    ) -> Result<Self, ParamError> {
        check_center_and_load_factor(center, load_factor)?;
        Ok(Self {
            center,
            load_factor,
            shape: Shape::Polyline(polyline),
        })
    }

    /// The same shape and centre at another load factor.
    ///
    /// # Errors
    ///
    /// As [`Cycle::new`] for `lambda`.
    pub fn with_load_factor(&self, load_factor: f64) -> Result<Self, ParamError> {
        check_center_and_load_factor(self.center, load_factor)?;
        Ok(Self {
            load_factor,
            ..self.clone()
        })
    }

    /// Centre `A = (x0, y0)`: the mean loads, where every transient ends.
    pub fn center(&self) -> LoadPoint {
        self.center
    }
    /// `lambda`: the load factor of eq. (12), the amplitude of the cycle.
    pub fn load_factor(&self) -> f64 {
        self.load_factor
    }
    /// The oscillating part: the paper's ellipse or a polyline.
    pub fn shape(&self) -> &Shape {
        &self.shape
    }
    /// The polyline, for a polyline cycle.
    pub fn as_polyline(&self) -> Option<&Polyline> {
        match &self.shape {
            Shape::Polyline(p) => Some(p),
            Shape::Ellipse { .. } => None,
        }
    }
    /// `psi`: the slope of the load line for `phi = 0` (eq. 13). A polyline
    /// has none: NaN, which every constructor refuses, so that it cannot
    /// silently stand for an ellipse (match on [`Cycle::shape`] instead).
    pub fn slope(&self) -> f64 {
        match self.shape {
            Shape::Ellipse { slope, .. } => slope,
            Shape::Polyline(_) => f64::NAN,
        }
    }
    /// `phi`, radians: the phase of the torque relative to the force. A
    /// polyline has none: NaN, as for [`Cycle::slope`].
    pub fn phase(&self) -> f64 {
        match self.shape {
            Shape::Ellipse { phase, .. } => phase,
            Shape::Polyline(_) => f64::NAN,
        }
    }

    /// Whether `steps` increments per cycle follow this cycle: any count
    /// for the ellipse; for a polyline a multiple of its vertex count, so
    /// that every vertex is the end of an increment and every increment is
    /// a piece of one chord (model.md section 5.4).
    ///
    /// # Errors
    ///
    /// [`ParamError::StepsPerChord`] otherwise.
    pub fn check_steps(&self, steps: usize) -> Result<(), ParamError> {
        match &self.shape {
            Shape::Polyline(p) if !steps.is_multiple_of(p.vertices.len()) => {
                Err(ParamError::StepsPerChord {
                    steps,
                    vertices: p.vertices.len(),
                })
            }
            _ => Ok(()),
        }
    }

    /// The load point at `omega t = t` (radians). Periodic in `t` with
    /// period `2 pi`.
    pub fn at(&self, t: f64) -> LoadPoint {
        match &self.shape {
            Shape::Ellipse { slope, phase } => {
                let norm = (1.0 + slope * slope).sqrt();
                let amp = self.load_factor / norm;
                LoadPoint::new(
                    self.center.x() + amp * t.sin(),
                    self.center.y() + amp * slope * (t + phase).sin(),
                )
            }
            Shape::Polyline(p) => {
                let o = p.at(t);
                LoadPoint::new(
                    self.center.x() + self.load_factor * o.x(),
                    self.center.y() + self.load_factor * o.y(),
                )
            }
        }
    }

    /// The cycle's point `C` at `t = 0`, where the transient `A -> C` ends
    /// and the first cycle begins (model.md section 5.3). For the ellipse
    /// `C = (x0, y0 + lambda psi sin(phi) / sqrt(1 + psi^2))`, equal to `A`
    /// for `phi = 0`; for a polyline its first vertex.
    pub fn start(&self) -> LoadPoint {
        self.at(0.0)
    }
}
