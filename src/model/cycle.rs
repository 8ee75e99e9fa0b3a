//! The steady cycle of eq. (11) in the load plane.

use std::f64::consts::PI;

use serde::Serialize;

use super::{finite, LoadPoint, ParamError};

/// The steady cycle of eq. (11) in the load plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cycle {
    /// Centre `A = (x0, y0)`.
    pub center: LoadPoint,
    /// `lambda`.
    pub load_factor: f64,
    /// `psi`: slope of the load line for `phi = 0`.
    pub slope: f64,
    /// `phi`, radians.
    pub phase: f64,
}

impl Cycle {
    /// The paper's cycle: `x0 = pi`, `y0 = 3 pi / 4`, `psi = 5/8`.
    pub fn paper(load_factor: f64, phase: f64) -> Result<Self, ParamError> {
        Self::new(LoadPoint::new(PI, 0.75 * PI), load_factor, 0.625, phase)
    }

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

    /// The load point at `omega t = t`.
    pub fn at(&self, t: f64) -> LoadPoint {
        let norm = (1.0 + self.slope * self.slope).sqrt();
        let amp = self.load_factor / norm;
        LoadPoint::new(
            self.center.x() + amp * t.sin(),
            self.center.y() + amp * self.slope * (t + self.phase).sin(),
        )
    }

    /// The cycle's point at `t = 0`, where the transient `A -> C` ends.
    pub fn start(&self) -> LoadPoint {
        self.at(0.0)
    }
}
