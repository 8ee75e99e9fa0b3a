//! Friction and elastic constants (model.md section 1.1, eq. 4), and the
//! conversion between the scaled loads of eq. (3) and the load plane of
//! Fig. 2.
//!
//! After scaling, the problem depends on the material only through the
//! friction coefficient `f` and Kolosov's constant `kappa` (by way of
//! `alpha`, `beta` and `chi`); the shear modulus, the radius and the fit
//! pressure `p0` only scale the results.
//!
//! ```
//! use shakedown::model::{LoadPoint, Material};
//!
//! // The paper's material (model.md section 1.1): kappa = 1.8,
//! // alpha = 0.2857, beta = 1.7143, chi = 0.3332.
//! let m = Material::paper();
//! assert!((m.kappa() - 1.8).abs() < 1e-12);
//! assert!((m.alpha() - 0.2857).abs() < 1e-4);
//! assert!((m.beta() - 1.7143).abs() < 1e-4);
//! assert!((m.chi() - 0.3332).abs() < 1e-4);
//!
//! // A load-plane point and the scaled loads (Pt, Tt) convert both ways.
//! let p = LoadPoint::new(1.0, 2.0);
//! let loads = m.to_loads(p);
//! assert!((loads.torque - 0.2).abs() < 1e-12); // Tt = f y
//! assert!(m.to_load_plane(loads).distance(p) < 1e-12);
//! ```

use serde::{Deserialize, Serialize};

use super::{LoadPoint, Loads, ParamError};

/// Plane strain or plane stress: decides Kolosov's constant `kappa`
/// (model.md section 1.1).
///
/// Parsed from and displayed as `strain` / `stress` (case-insensitive when
/// parsing); the default is the paper's plane strain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Plane {
    /// Plane strain, `kappa = 3 - 4 nu` (the paper's choice, the default).
    #[default]
    Strain,
    /// Plane stress, `kappa = (3 - nu) / (1 + nu)`.
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
/// of eq. (4) (model.md section 1.1).
///
/// The fields are private so that the derived constants always agree with
/// `f`, `nu` and the plane: build one with [`Material::new`] (validated) or
/// [`Material::paper`], and read it through the accessors.
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

    /// A material with friction coefficient `f` (`friction`), Poisson's
    /// ratio `nu` (`poisson`) and the plane condition `plane`; computes
    /// `kappa`, `alpha`, `beta` and `chi` (model.md section 1.1).
    ///
    /// # Errors
    ///
    /// [`ParamError::NotFinite`] if `friction` or `poisson` is NaN or
    /// infinite; [`ParamError::OutOfRange`] unless `0 < f <= 10` and
    /// `0 <= nu < 0.5` (the incompressible limit `nu = 0.5` is excluded).
    ///
    /// ```
    /// use shakedown::model::{Material, ParamError, Plane};
    ///
    /// let m = Material::new(0.2, 0.25, Plane::Stress).unwrap();
    /// assert!((m.kappa() - 2.75 / 1.25).abs() < 1e-12);
    /// assert!(matches!(
    ///     Material::new(0.0, 0.3, Plane::Strain),
    ///     Err(ParamError::OutOfRange { name: "friction", .. })
    /// ));
    /// ```
    pub fn new(friction: f64, poisson: f64, plane: Plane) -> Result<Self, ParamError> {
        let friction = super::ranges::FRICTION.check(friction)?;
        let poisson = super::ranges::NU.check(poisson)?;
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

    /// The Coulomb friction coefficient `f`.
    pub fn friction(&self) -> f64 {
        self.friction
    }
    /// Poisson's ratio `nu`.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }
    /// Plane strain or plane stress.
    pub fn plane(&self) -> Plane {
        self.plane
    }
    /// Kolosov's constant `kappa`: `3 - 4 nu` in plane strain,
    /// `(3 - nu) / (1 + nu)` in plane stress.
    pub fn kappa(&self) -> f64 {
        self.kappa
    }
    /// `alpha = (kappa - 1) / (kappa + 1)`: the weight of the force in the
    /// shear traction `q` (model.md section 2.1).
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// `beta = (kappa + 3) / (kappa + 1)`: the weight of the force in the
    /// contact pressure `p` (model.md section 2.1).
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// `chi = sqrt(alpha^2 + f^2 beta^2)`, eq. (4): the scale of the force
    /// axis of the load plane, chosen so that the initial stick region is
    /// the diamond `|x| + |y| <= 2 pi` (model.md section 2.3).
    pub fn chi(&self) -> f64 {
        self.chi
    }

    /// Load-plane point `(x, y) = (chi Pt / f, Tt / f)` from the scaled loads
    /// (model.md section 1.1); the inverse of [`Material::to_loads`].
    pub fn to_load_plane(&self, loads: Loads) -> LoadPoint {
        LoadPoint::new(
            self.chi * loads.radial / self.friction,
            loads.torque / self.friction,
        )
    }

    /// Scaled loads `(Pt, Tt)` of eq. (3) from a load-plane point:
    /// `Pt = f x / chi`, `Tt = f y`; the inverse of
    /// [`Material::to_load_plane`].
    pub fn to_loads(&self, point: LoadPoint) -> Loads {
        Loads {
            radial: self.friction * point.x() / self.chi,
            torque: self.friction * point.y(),
        }
    }
}
