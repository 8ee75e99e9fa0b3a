//! The model's inputs (model.md section 1) and their validation: the
//! material, the load plane, the steady cycle, the discretisation and the
//! initial load paths.
//!
//! Everything the physics needs reduces to the friction coefficient `f`,
//! Kolosov's constant `kappa`, the load path and the discretisation. Every
//! constructor validates, so a value of these types is always usable.

mod cycle;
mod discretisation;
mod load;
mod material;
pub mod path;
pub mod ranges;

pub use cycle::{Cycle, Polyline, Shape, MAX_VERTICES};
pub use discretisation::Discretisation;
pub use load::{LoadPoint, Loads};
pub use material::{Material, Plane};
pub use path::{Initial, PathError, Segment};

/// A parameter that is out of range or not a number.
///
/// Returned by every validating constructor of this module
/// ([`Material::new`], [`Cycle::new`], [`Discretisation::new`]), so that a
/// value of those types is always usable by the solver. `name` is the
/// parameter as the command line spells it (`friction`, `nu`, `lambda`,
/// `psi`, `phi`, `nodes`, `steps`, ...).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// A real parameter is NaN or infinite.
    #[error("{name} = {value} is not a finite number")]
    NotFinite {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A real parameter is finite but outside its admissible range.
    #[error("{name} = {value} is out of range: expected {expected}")]
    OutOfRange {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The admissible range, in words (e.g. `0 < f <= 10`).
        expected: &'static str,
    },
    /// A count (nodes, increments per cycle) is outside its admissible
    /// range or, for the nodes, odd.
    #[error("{name} = {value} is out of range: expected {expected}")]
    BadCount {
        /// The parameter's name.
        name: &'static str,
        /// The count given.
        value: usize,
        /// The admissible counts, in words.
        expected: &'static str,
    },
    /// The increments per cycle do not split a polyline cycle into equal
    /// increments per chord (model.md section 5.4).
    #[error("steps = {steps} is out of range: expected a multiple of the cycle's {vertices} vertices, so that each chord gets the same increments (e.g. {})", steps.div_ceil(*vertices).max(1) * vertices)]
    StepsPerChord {
        /// The increments per cycle given.
        steps: usize,
        /// The cycle's vertex count.
        vertices: usize,
    },
}

impl ParamError {
    /// The parameter as the command line spells it.
    pub fn name(&self) -> &'static str {
        match self {
            ParamError::NotFinite { name, .. }
            | ParamError::OutOfRange { name, .. }
            | ParamError::BadCount { name, .. } => name,
            ParamError::StepsPerChord { .. } => "steps",
        }
    }
}

pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::NotFinite { name, value })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

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

    /// Equal time per chord: at `steps` a multiple of the vertex count,
    /// every vertex is a load point to the bit (not an ulp before it), and
    /// between vertices the load is on the chord, linear in time.
    #[test]
    fn a_polyline_cycle_passes_its_vertices_at_equal_times() {
        let square: Vec<LoadPoint> = [(1.0, -1.0), (1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0)]
            .iter()
            .map(|&(u, v)| LoadPoint::new(u, v))
            .collect();
        let polyline = Polyline::new("square", square.clone()).unwrap();
        let center = LoadPoint::new(PI, 0.75 * PI);
        let c = Cycle::polyline(center, 2.0, polyline).unwrap();
        let at = |k: usize, steps: usize| c.at(2.0 * PI * k as f64 / steps as f64);
        for steps in [4, 12, 400] {
            for (k, v) in square.iter().enumerate() {
                let want = LoadPoint::new(center.x() + 2.0 * v.x(), center.y() + 2.0 * v.y());
                assert_eq!(at(k * steps / 4, steps), want, "{steps} {k}");
            }
        }
        // A third of the way along the second chord, and round again.
        let p = at(4, 12);
        assert!((p.x() - (PI + 2.0 * (1.0 - 2.0 / 3.0))).abs() < 1e-12);
        assert!((p.y() - (0.75 * PI + 2.0)).abs() < 1e-12);
        assert_eq!(at(12, 12), c.start());
        assert_eq!(c.check_steps(400), Ok(()));
        assert_eq!(
            c.check_steps(402),
            Err(ParamError::StepsPerChord {
                steps: 402,
                vertices: 4
            })
        );
        assert!(c.slope().is_nan() && c.phase().is_nan());
        assert_eq!(
            c.with_load_factor(3.0).unwrap().as_polyline(),
            c.as_polyline()
        );
        assert!(Polyline::new("nan", vec![LoadPoint::new(f64::NAN, 0.0); 3]).is_err());
        assert!(Polyline::new("far", vec![LoadPoint::new(2e3, 0.0); 3]).is_err());
    }

    #[test]
    fn cycle_is_a_line_of_half_length_lambda_for_zero_phase() {
        let c = Cycle::paper(2.0, 0.0).unwrap();
        let top = c.at(PI / 2.0);
        assert!((c.center().distance(top) - 2.0).abs() < 1e-12);
        assert!(((top.y() - c.center().y()) / (top.x() - c.center().x()) - 0.625).abs() < 1e-12);
    }
}
