//! Friction and elastic constants (model.md section 1, eq. 4).

use serde::{Deserialize, Serialize};

use super::{finite, LoadPoint, Loads, ParamError};

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
