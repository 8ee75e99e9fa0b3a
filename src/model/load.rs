//! The load plane of the paper's Fig. 2 and the scaled loads of eq. (3).

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

/// Scaled loads `Pt = P/(p0 a)` and `Tt = T/(p0 a^2)` (eq. 3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Loads {
    pub radial: f64,
    pub torque: f64,
}

/// A point of the load plane (the paper's Fig. 2): `x = chi Pt / f`,
/// `y = Tt / f`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LoadPoint(pub Vector2<f64>);

impl LoadPoint {
    pub const ORIGIN: LoadPoint = LoadPoint(Vector2::new(0.0, 0.0));

    pub const fn new(x: f64, y: f64) -> Self {
        LoadPoint(Vector2::new(x, y))
    }
    pub fn x(&self) -> f64 {
        self.0.x
    }
    pub fn y(&self) -> f64 {
        self.0.y
    }
    /// Linear interpolation `self + s (to - self)`.
    pub fn lerp(&self, to: LoadPoint, s: f64) -> LoadPoint {
        LoadPoint(self.0 + (to.0 - self.0) * s)
    }
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
