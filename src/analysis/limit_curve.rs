//! `lambda_2` as a function of the phase: one linear programme
//! ([`shakedown_limit`]) per `phi`, solved in parallel. This is the curve
//! the regime map draws over the `(lambda, phi)` plane, and what
//! `shakedown limit --phi 0:pi:pi/24` prints.

use rayon::prelude::*;

use crate::analysis::limit::{shakedown_limit, LimitError};
use crate::model::{Discretisation, LoadPoint, Material};

/// `lambda_2` at one phase.
#[derive(Debug, Clone, PartialEq)]
pub struct LimitPoint {
    /// `phi` in radians.
    pub phase: f64,
    /// `lambda_2` (an upper bound for an ellipse sampled at `M` points)
    /// and its guaranteed lower bound, or why the programme failed.
    pub limit: Result<(f64, f64), LimitError>,
}

/// Columns of [`curve_csv`].
pub const CURVE_HEADER: &str = "phi,lambda_2,lower_bound";

/// `lambda_2` at each of `phases` for the cycle centre `center` and slope
/// `slope`, on `disc`'s nodes, with `samples` points on an elliptical
/// cycle (see [`shakedown_limit`]). The phases are solved in parallel; the
/// result is in the order given. A failed programme is reported in its
/// point, so one bad phase does not hide the others.
pub fn limit_curve(
    material: &Material,
    center: LoadPoint,
    slope: f64,
    phases: &[f64],
    disc: &Discretisation,
    samples: usize,
) -> Vec<LimitPoint> {
    phases
        .par_iter()
        .map(|&phase| LimitPoint {
            phase,
            limit: shakedown_limit(material, center, slope, phase, disc, samples)
                .map(|l| (l.load_factor, l.lower_bound)),
        })
        .collect()
}

/// The curve as CSV under [`CURVE_HEADER`]; a failed phase has empty
/// values.
pub fn curve_csv(points: &[LimitPoint]) -> String {
    let mut out = format!("{CURVE_HEADER}\n");
    for p in points {
        match &p.limit {
            Ok((l, lo)) => out.push_str(&format!("{},{},{}\n", p.phase, l, lo)),
            Err(_) => out.push_str(&format!("{},,\n", p.phase)),
        }
    }
    out
}

/// Read a curve written by [`curve_csv`] back: `(phi, lambda_2)` pairs,
/// skipping failed phases and `#` comment lines. `None` when the text is
/// not such a CSV.
pub fn parse_curve_csv(text: &str) -> Option<Vec<(f64, f64)>> {
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'));
    if lines.next()? != CURVE_HEADER {
        return None;
    }
    let mut out = Vec::new();
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        if f.len() != 3 {
            return None;
        }
        if f[1].is_empty() {
            continue;
        }
        out.push((f[0].parse().ok()?, f[1].parse().ok()?));
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn curve_round_trips_and_matches_single_solves() {
        let m = Material::paper();
        let disc = Discretisation::new(32, 64).unwrap();
        let c = LoadPoint::new(PI, 0.75 * PI);
        let pts = limit_curve(&m, c, 0.625, &[0.0, PI / 2.0], &disc, 16);
        let one = shakedown_limit(&m, c, 0.625, PI / 2.0, &disc, 16).unwrap();
        assert_eq!(pts[1].limit.as_ref().unwrap().0, one.load_factor);
        let back = parse_curve_csv(&curve_csv(&pts)).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!(back[1], (PI / 2.0, one.load_factor));
    }
}
