//! Inputs of the model (model.md section 1) and their validation.
//!
//! Everything the physics needs reduces to the friction coefficient `f`,
//! Kolosov's constant `kappa`, the load path and the discretisation. Every
//! constructor validates, so a value of these types is always usable.

use std::f64::consts::PI;

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

/// A parameter that is out of range or not a number.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    #[error("{name} = {value} is not a finite number")]
    NotFinite { name: &'static str, value: f64 },
    #[error("{name} = {value} is out of range: expected {expected}")]
    OutOfRange {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
    #[error("{name} = {value} is out of range: expected {expected}")]
    BadCount {
        name: &'static str,
        value: usize,
        expected: &'static str,
    },
}

pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::NotFinite { name, value })
    }
}

/// Plane strain or plane stress: decides Kolosov's constant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Plane {
    #[default]
    Strain,
    Stress,
}

impl std::fmt::Display for Plane {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Plane::Strain => "strain",
            Plane::Stress => "stress",
        })
    }
}

impl std::str::FromStr for Plane {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "strain" => Ok(Plane::Strain),
            "stress" => Ok(Plane::Stress),
            other => Err(format!(
                "'{other}' is not a plane: expected strain or stress"
            )),
        }
    }
}

/// Friction and elastic constants with the derived `kappa, alpha, beta, chi`
/// of eq. (4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Material {
    friction: f64,
    poisson: f64,
    plane: Plane,
    kappa: f64,
    alpha: f64,
    beta: f64,
    chi: f64,
}

impl Material {
    /// The paper's material: `f = 0.1`, plane strain, `nu = 0.3`.
    pub fn paper() -> Self {
        Self::new(0.1, 0.3, Plane::Strain).expect("paper's parameters are valid")
    }

    pub fn new(friction: f64, poisson: f64, plane: Plane) -> Result<Self, ParamError> {
        let friction = finite("friction", friction)?;
        let poisson = finite("nu", poisson)?;
        if friction <= 0.0 || friction > 10.0 {
            return Err(ParamError::OutOfRange {
                name: "friction",
                value: friction,
                expected: "0 < f <= 10",
            });
        }
        if !(0.0..0.5).contains(&poisson) {
            return Err(ParamError::OutOfRange {
                name: "nu",
                value: poisson,
                expected: "0 <= nu < 0.5",
            });
        }
        let kappa = match plane {
            Plane::Strain => 3.0 - 4.0 * poisson,
            Plane::Stress => (3.0 - poisson) / (1.0 + poisson),
        };
        let alpha = (kappa - 1.0) / (kappa + 1.0);
        let beta = (kappa + 3.0) / (kappa + 1.0);
        let chi = (alpha * alpha + friction * friction * beta * beta).sqrt();
        Ok(Self {
            friction,
            poisson,
            plane,
            kappa,
            alpha,
            beta,
            chi,
        })
    }

    pub fn friction(&self) -> f64 {
        self.friction
    }
    pub fn poisson(&self) -> f64 {
        self.poisson
    }
    pub fn plane(&self) -> Plane {
        self.plane
    }
    pub fn kappa(&self) -> f64 {
        self.kappa
    }
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    pub fn beta(&self) -> f64 {
        self.beta
    }
    pub fn chi(&self) -> f64 {
        self.chi
    }

    /// Load-plane point `(x, y) = (chi Pt / f, Tt / f)` from the scaled loads.
    pub fn to_load_plane(&self, loads: Loads) -> LoadPoint {
        LoadPoint::new(
            self.chi * loads.radial / self.friction,
            loads.torque / self.friction,
        )
    }

    /// Scaled loads `(Pt, Tt)` of eq. (3) from a load-plane point.
    pub fn to_loads(&self, point: LoadPoint) -> Loads {
        Loads {
            radial: self.friction * point.x() / self.chi,
            torque: self.friction * point.y(),
        }
    }
}

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

/// Discretisation: nodes round the interface and increments per cycle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Discretisation {
    nodes: usize,
    steps_per_cycle: usize,
}

impl Default for Discretisation {
    fn default() -> Self {
        Self {
            nodes: 128,
            steps_per_cycle: 400,
        }
    }
}

impl Discretisation {
    pub const MIN_NODES: usize = 16;
    pub const MAX_NODES: usize = 4096;
    pub const MIN_STEPS: usize = 16;
    pub const MAX_STEPS: usize = 100_000;

    pub fn new(nodes: usize, steps_per_cycle: usize) -> Result<Self, ParamError> {
        if !(Self::MIN_NODES..=Self::MAX_NODES).contains(&nodes) || !nodes.is_multiple_of(2) {
            return Err(ParamError::BadCount {
                name: "nodes",
                value: nodes,
                expected: "an even number from 16 to 4096",
            });
        }
        if !(Self::MIN_STEPS..=Self::MAX_STEPS).contains(&steps_per_cycle) {
            return Err(ParamError::BadCount {
                name: "steps",
                value: steps_per_cycle,
                expected: "16 to 100000 increments per cycle",
            });
        }
        Ok(Self {
            nodes,
            steps_per_cycle,
        })
    }
    pub fn nodes(&self) -> usize {
        self.nodes
    }
    pub fn steps_per_cycle(&self) -> usize {
        self.steps_per_cycle
    }
    /// Node angle `theta_j = 2 pi j / N`.
    pub fn theta(&self, j: usize) -> f64 {
        2.0 * PI * j as f64 / self.nodes as f64
    }
    /// Longest load-plane distance of one transient increment. It is the
    /// path length per increment of an in-phase cycle with `lambda = 2 pi`
    /// (`4 lambda` per cycle), so refining `steps` refines transients too.
    pub fn transient_step(&self) -> f64 {
        8.0 * PI / self.steps_per_cycle as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derived_constants_plane_strain() {
        let m = Material::paper();
        assert!((m.kappa() - 1.8).abs() < 1e-12);
        assert!((m.alpha() - 0.8 / 2.8).abs() < 1e-12);
        assert!((m.beta() - 4.8 / 2.8).abs() < 1e-12);
        let chi = ((0.8f64 / 2.8).powi(2) + 0.01 * (4.8f64 / 2.8).powi(2)).sqrt();
        assert!((m.chi() - chi).abs() < 1e-12);
    }

    #[test]
    fn plane_stress_kappa() {
        let m = Material::new(0.2, 0.25, Plane::Stress).unwrap();
        assert!((m.kappa() - 2.75 / 1.25).abs() < 1e-12);
    }

    #[test]
    fn load_conversion_round_trips() {
        let m = Material::paper();
        let p = LoadPoint::new(1.3, -2.1);
        let back = m.to_load_plane(m.to_loads(p));
        assert!(p.distance(back) < 1e-12);
    }

    #[test]
    fn rejects_bad_inputs() {
        assert!(Material::new(0.0, 0.3, Plane::Strain).is_err());
        assert!(Material::new(f64::NAN, 0.3, Plane::Strain).is_err());
        assert!(Material::new(0.1, 0.5, Plane::Strain).is_err());
        assert!(Material::new(0.1, -0.1, Plane::Strain).is_err());
        assert!(Discretisation::new(7, 400).is_err());
        assert!(Discretisation::new(8, 400).is_err());
        assert!(Discretisation::new(100_000, 400).is_err());
        assert!(Discretisation::new(64, 3).is_err());
        assert!(Cycle::paper(-1.0, 0.0).is_err());
        assert!(Cycle::paper(f64::INFINITY, 0.0).is_err());
        assert!(Cycle::paper(1.0, f64::NAN).is_err());
    }

    #[test]
    fn cycle_is_a_line_of_half_length_lambda_for_zero_phase() {
        let c = Cycle::paper(2.0, 0.0).unwrap();
        let top = c.at(PI / 2.0);
        assert!((c.center.distance(top) - 2.0).abs() < 1e-12);
        assert!(((top.y() - c.center.y()) / (top.x() - c.center.x()) - 0.625).abs() < 1e-12);
    }
}
