//! The load plane of the paper's Fig. 2 and the scaled loads of eq. (3)
//! (model.md section 1.1). [`crate::model::Material`] converts between the
//! two, since the conversion needs `f` and `chi`.

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

/// Scaled loads `Pt = P/(p0 a)` and `Tt = T/(p0 a^2)` (eq. 3).
///
/// Sense (model.md section 1.1): a positive `Pt` pushes the disc towards
/// `theta = -pi/2`; a positive `Tt` turns it clockwise, the sense of forward
/// slip (model.md section 1.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Loads {
    /// The scaled radial force `Pt = P / (p0 a)`.
    pub radial: f64,
    /// The scaled torque `Tt = T / (p0 a^2)`.
    pub torque: f64,
}

/// A point of the load plane (the paper's Fig. 2): `x = chi Pt / f`,
/// `y = Tt / f`.
///
/// In these coordinates the initial stick region is the diamond
/// `|x| + |y| <= 2 pi` and gross slip sets in at `|y| = 2 pi`, whatever the
/// material (model.md section 2.3). Serialised as `[x, y]`; displayed as
/// `(x, y)` to four decimals.
///
/// A point is only coordinates: where one is an input, the type it goes
/// into checks it (the centre by [`crate::model::Cycle::new`], a vertex by
/// [`crate::model::Polyline::new`], a transient's point by
/// [`crate::model::Initial::custom`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoadPoint(Vector2<f64>);

impl LoadPoint {
    /// The unloaded state `O = (0, 0)`, where every transient starts.
    pub const ORIGIN: LoadPoint = LoadPoint(Vector2::new(0.0, 0.0));

    /// The point `(x, y) = (chi Pt / f, Tt / f)`.
    pub const fn new(x: f64, y: f64) -> Self {
        LoadPoint(Vector2::new(x, y))
    }
    /// `x = chi Pt / f`, the scaled force.
    pub fn x(&self) -> f64 {
        self.0.x
    }
    /// `y = Tt / f`, the scaled torque.
    pub fn y(&self) -> f64 {
        self.0.y
    }
    /// The coordinates `(x, y)` as a vector.
    pub fn vector(&self) -> Vector2<f64> {
        self.0
    }
    /// Linear interpolation `self + s (to - self)`.
    pub fn lerp(&self, to: LoadPoint, s: f64) -> LoadPoint {
        LoadPoint(self.0 + (to.0 - self.0) * s)
    }
    /// Euclidean distance to `to` in the load plane (the measure of the
    /// transient increments, [`crate::model::Discretisation::transient_step`]).
    pub fn distance(&self, to: LoadPoint) -> f64 {
        (to.0 - self.0).norm()
    }
    /// `|x| + |y|`: the point is in the initial stick diamond when this is
    /// at most `2 pi`.
    pub fn diamond_norm(&self) -> f64 {
        self.0.x.abs() + self.0.y.abs()
    }
}

impl Serialize for LoadPoint {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        [self.x(), self.y()].serialize(s)
    }
}

impl std::fmt::Display for LoadPoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "({:.4}, {:.4})", self.x(), self.y())
    }
}
