//! The steady cycle of eq. (11) in the load plane (model.md section 5.1).

use std::f64::consts::PI;

use serde::Serialize;

use super::{finite, LoadPoint, ParamError};

/// The steady cycle of eq. (11) in the load plane (model.md section 5.1):
///
/// ```text
/// x(t) = x0 + lambda sin(t) / sqrt(1 + psi^2)
/// y(t) = y0 + lambda psi sin(t + phi) / sqrt(1 + psi^2)
/// ```
///
/// with `t = omega t` in `[0, 2 pi)`. For `phi = 0` this is a straight
/// segment of half-length `lambda` and slope `psi` through `A`; otherwise an
/// ellipse centred on `A`. The fields are public for reading; build a cycle
/// with [`Cycle::new`] or [`Cycle::paper`] so that it is validated.
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
/// assert!((c.center.distance(top) - 7.0).abs() < 1e-12);
/// assert!(((top.y() - c.center.y()) / (top.x() - c.center.x()) - 0.625).abs() < 1e-12);
/// // In phase, the cycle starts at its centre: C = A.
/// assert!(c.start().distance(c.center) < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cycle {
    /// Centre `A = (x0, y0)` (`center`): the mean loads
    /// `(chi Pt0 / f, Tt0 / f)`, where every transient ends.
    center: LoadPoint,
    /// `lambda` (`load_factor`): the load factor of eq. (12),
    /// `sqrt((chi Pt1)^2 + Tt1^2) / f`, the amplitude of the cycle.
    load_factor: f64,
    /// `psi` (`slope`): eq. (13), `Tt1 / (chi Pt1)`; the slope of the load
    /// line for `phi = 0`.
    slope: f64,
    /// `phi` (`phase`), radians: the phase of the torque relative to the
    /// force.
    phase: f64,
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

    /// A cycle with centre `A = center`, load factor `lambda =
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
        if !(0.0..=1e3).contains(&load_factor) {
            return Err(ParamError::OutOfRange {
                name: "lambda",
                value: load_factor,
                expected: "0 <= lambda <= 1000",
            });
        }
        if !(-1e6..=1e6).contains(&slope) {
            return Err(ParamError::OutOfRange {
                name: "psi",
                value: slope,
                expected: "|psi| <= 1e6",
            });
        }
        if center.x().abs() > 1e3 || center.y().abs() > 1e3 {
            return Err(ParamError::OutOfRange {
                name: "center",
                value: center.x().abs().max(center.y().abs()),
                expected: "|x0|, |y0| <= 1000",
            });
        }
        if phase.abs() > 1e3 {
            return Err(ParamError::OutOfRange {
                name: "phi",
                value: phase,
                expected: "|phi| <= 1000 rad",
            });
        }
        Ok(Self {
            center,
            load_factor,
            slope,
            phase,
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
    /// `psi`: the slope of the load line for `phi = 0` (eq. 13).
    pub fn slope(&self) -> f64 {
        self.slope
    }
    /// `phi`, radians: the phase of the torque relative to the force.
    pub fn phase(&self) -> f64 {
        self.phase
    }

    /// The load point at `omega t = t` (radians), eq. (11). Periodic in `t`
    /// with period `2 pi`.
    pub fn at(&self, t: f64) -> LoadPoint {
        let norm = (1.0 + self.slope * self.slope).sqrt();
        let amp = self.load_factor / norm;
        LoadPoint::new(
            self.center.x() + amp * t.sin(),
            self.center.y() + amp * self.slope * (t + self.phase).sin(),
        )
    }

    /// The cycle's point `C` at `t = 0`, where the transient `A -> C` ends
    /// and the first cycle begins (model.md section 5.3):
    /// `C = (x0, y0 + lambda psi sin(phi) / sqrt(1 + psi^2))`, equal to `A`
    /// for `phi = 0`.
    pub fn start(&self) -> LoadPoint {
        self.at(0.0)
    }
}
