//! The shakedown limit `lambda_2` by linear programming (model.md section 7).
//!
//! A cycle can shake down only if some locked-in slip `g` keeps
//! `|q| <= f p` at every load point of the cycle. With
//! `p = p_el(load) + H g` and `q = q_el(load) - |D| g` both tractions are
//! linear in `(g, load)`, and at a fixed `omega t` the cycle's load is
//! linear in `lambda`. So the largest such `lambda` is a linear programme
//! in `(g, lambda)`:
//!
//! ```text
//! maximise lambda  subject to   s q_j(t_k) - f p_j(t_k) <= 0   (s = +1, -1)
//!                               mean g = 0
//! ```
//!
//! for every node `j` and sampled time `t_k`. The rigid rotation (mean of
//! `g`) carries no traction, so fixing it only removes a free direction.
//!
//! The constraints are linear in the load, so a `g` admissible at some load
//! points is admissible on their convex hull. For a straight load line
//! (`phi = 0`) the two ends therefore suffice and the result is exact. An
//! ellipse is sampled at `M` equally spaced times: the sampled optimum
//! `lambda_M` is an upper bound, and since the inscribed `M`-gon contains
//! the ellipse shrunk by `cos(pi / M)`, `lambda_M cos(pi / M)` is a lower
//! bound that the returned slip provably achieves.

use std::f64::consts::PI;
use std::sync::Arc;

use serde::Serialize;

mod programme;
#[cfg(test)]
mod tests;
mod vertex;

use programme::{Programme, Row, SIGNS};

use crate::contact::{Contact, Operators};
use crate::model::path::Initial;
use crate::model::{Cycle, Discretisation, LoadPoint, Material, ParamError};

/// Samples of an elliptical cycle when none are given: the bound on
/// `lambda_2` is then tight to `1 - cos(pi/64)`, about 0.12 %.
pub const DEFAULT_SAMPLES: usize = 64;
/// Most samples accepted (the programme has `2 N M` rows).
pub const MAX_SAMPLES: usize = crate::model::ranges::SAMPLES.max;
/// `lambda` is capped here (as in [`Cycle::new`]); reaching the cap means
/// no finite limit exists for this cycle direction.
const LAMBDA_CAP: f64 = 1e3;

/// The limit analysis failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitError {
    /// An elliptical cycle was to be sampled at fewer than 3 or more than
    /// [`MAX_SAMPLES`] times `M`; holds the count given.
    #[error("samples = {0} is out of range: expected {expected}", expected = crate::model::ranges::SAMPLES.expected)]
    Samples(usize),
    /// The cycle's centre `A`, slope ψ (`slope`) or phase φ (`phase`) is
    /// not valid (as for [`Cycle::new`]).
    #[error(transparent)]
    Param(#[from] ParamError),
    /// No locked-in slip `g` keeps `|q| <= f p` even at the centre `A`
    /// (λ = 0): the programme has no feasible point and `lambda_2` does not
    /// exist.
    #[error(
        "no locked-in slip satisfies the friction law at the cycle centre {center}: lambda_2 does not exist"
    )]
    Infeasible {
        /// The cycle centre `A` in the load plane.
        center: LoadPoint,
    },
    /// Some slip `g` keeps the friction law for every λ up to the cap of
    /// 1000: no finite limit in this cycle direction.
    #[error("lambda_2 is unbounded: some slip keeps the friction law for every lambda up to 1000")]
    Unbounded,
    /// The interior-point solver hit its iteration limit.
    #[error("the LP solver stopped after {iterations} iterations without converging")]
    MaxIterations {
        /// Interior-point iterations taken.
        iterations: u32,
    },
    /// The interior-point solver failed numerically, or its optimum λ is
    /// not finite.
    #[error("the LP solver failed numerically ({status})")]
    Numerical {
        /// The solver's status, in words.
        status: String,
    },
    /// Simplex pivots from the coarser grid's optimum reached no certified
    /// vertex on a grid too fine for the interior-point fallback
    /// ([`INTERIOR_POINT_MAX_NODES`]).
    #[error("no certified optimum on {nodes} nodes: the simplex pivots from the coarser grid's optimum did not end in a certificate; try fewer nodes")]
    NotCertified {
        /// The grid's node count.
        nodes: usize,
    },
    /// The solver rejected its settings or the problem's data; holds its
    /// message.
    #[error("the LP solver rejected the problem: {0}")]
    Setup(String),
}

/// The optimum of the `lambda_2` programme.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Limit {
    /// `lambda_2` of the sampled programme: exact for a straight load line,
    /// an upper bound for an ellipse.
    pub load_factor: f64,
    /// A `lambda` up to which [`Limit::slip`] keeps the friction law on the
    /// whole cycle: `load_factor` for a line, `load_factor cos(pi/M)` for an
    /// ellipse sampled at `M` points.
    pub lower_bound: f64,
    /// The optimal locked-in slip `g(theta_j)`, with mean zero.
    pub slip: Vec<f64>,
    /// `omega t` of the load points the friction law was imposed at.
    pub times: Vec<f64>,
    /// Whether the cycle is a straight line (`psi sin(phi) = 0`).
    pub line: bool,
    /// Largest `|q| - f p` of the returned slip at `lambda_2` over the
    /// sampled points: the solver's accuracy (slightly positive is round-off).
    pub max_violation: f64,
    /// Interior-point iterations of the programme solved by Clarabel: the
    /// coarsest grid's when the optimum was reached by pivots.
    pub iterations: u32,
    /// Simplex pivots from the guessed active set to the certified vertex,
    /// over every grid (0 when the interior-point answer was kept).
    pub pivots: usize,
}

/// The smallest grid solved by the interior-point method; finer grids
/// start their pivots from the optimum on half their nodes.
const COARSEST: usize = 64;

/// The finest grid the interior-point method is used on when pivots end
/// without a certificate: on the dense `2 N x N` rows it takes about 5 s
/// of CPU at 512 nodes, and grows as `N^3`.
pub const INTERIOR_POINT_MAX_NODES: usize = 512;

/// Clarabel's default feasibility and gap tolerance: its optimum is then
/// good to about `1e-9` relative at `N = 128` (and `1e-6` at `N = 1024`),
/// which is why its answer is refined to the exact vertex.
const DEFAULT_TOLERANCE: f64 = 1e-8;

/// The solved programme.
struct Optimum {
    slip: Vec<f64>,
    load_factor: f64,
    iterations: u32,
    pivots: usize,
    max_violation: f64,
}

impl Optimum {
    /// The [`Limit`] of this optimum, imposed at `times`, whose slip holds
    /// up to `shrink` times `lambda_2` on the whole cycle.
    fn into_limit(self, shrink: f64, times: Vec<f64>, line: bool) -> Limit {
        Limit {
            load_factor: self.load_factor,
            lower_bound: self.load_factor * shrink,
            slip: self.slip,
            times,
            line,
            max_violation: self.max_violation,
            iterations: self.iterations,
            pivots: self.pivots,
        }
    }
}

/// The `lambda_2` programme on `nodes` nodes with the friction law imposed
/// at `points` (the cycle's load points at `lambda = 1`).
///
/// Grids finer than [`COARSEST`] whose half is even start from the optimum
/// on half the nodes: its slip, interpolated by trigonometric
/// interpolation, picks per node the sign whose row is nearer to binding,
/// and simplex pivots move that guess to the optimal vertex, certified by
/// LP duality ([`vertex`]). The coarsest grid, and any grid whose pivots
/// do not end in a certificate, is solved by the interior-point method
/// (Clarabel) and its answer then refined to the exact vertex the same way.
fn optimum(
    material: &Material,
    center: LoadPoint,
    points: &[LoadPoint],
    nodes: usize,
) -> Result<Optimum, LimitError> {
    let ops = Arc::new(Operators::new(nodes));
    let contact = Contact::new(*material, Arc::clone(&ops));
    let lp = Programme::new(&contact, &ops, center, points.iter().copied());
    let rows = lp.reduced_rows();
    let half = nodes / 2;
    let mut iterations = 0;
    let mut pivots = 0;
    let mut found = None;
    if nodes > COARSEST && half.is_multiple_of(2) {
        let coarse = optimum(material, center, points, half)?;
        iterations = coarse.iterations;
        pivots = coarse.pivots;
        let slip = interpolate(&coarse.slip, nodes);
        let guess = lp.guess(&rows, &slip, coarse.load_factor);
        found = lp.vertex(&rows, guess);
    }
    let (slip, load_factor) = match found {
        Some(v) => {
            pivots += v.pivots;
            (v.slip, v.load_factor)
        }
        None if nodes > INTERIOR_POINT_MAX_NODES => {
            return Err(LimitError::NotCertified { nodes });
        }
        None => {
            let (slip, load_factor, its) = lp.solve(&rows, DEFAULT_TOLERANCE)?;
            iterations = its;
            let guess = lp.guess(&rows, &slip, load_factor);
            match lp.vertex(&rows, guess) {
                Some(v) => {
                    pivots += v.pivots;
                    (v.slip, v.load_factor)
                }
                None => (slip, load_factor),
            }
        }
    };
    if load_factor >= LAMBDA_CAP * (1.0 - 1e-6) {
        return Err(LimitError::Unbounded);
    }
    if load_factor < 0.0 {
        return Err(LimitError::Infeasible { center });
    }
    let max_violation = lp.max_violation(&slip, load_factor);
    Ok(Optimum {
        slip,
        load_factor,
        iterations,
        pivots,
        max_violation,
    })
}

/// The trigonometric interpolant of `slip` (on `slip.len()` equally spaced
/// nodes) at `nodes` equally spaced nodes: the harmonics below the coarse
/// grid's Nyquist, and half its Nyquist term each way.
fn interpolate(slip: &[f64], nodes: usize) -> Vec<f64> {
    let m = slip.len();
    let theta = |j: usize, n: usize| 2.0 * PI * j as f64 / n as f64;
    let mut cos = vec![0.0; m / 2 + 1];
    let mut sin = vec![0.0; m / 2 + 1];
    for (k, (c, s)) in cos.iter_mut().zip(&mut sin).enumerate() {
        let w = if k == 0 || 2 * k == m { 1.0 } else { 2.0 } / m as f64;
        for (i, g) in slip.iter().enumerate() {
            let (sk, ck) = (k as f64 * theta(i, m)).sin_cos();
            *c += w * g * ck;
            *s += w * g * sk;
        }
    }
    (0..nodes)
        .map(|j| {
            let t = theta(j, nodes);
            cos.iter()
                .zip(&sin)
                .enumerate()
                .map(|(k, (c, s))| {
                    let (sk, ck) = (k as f64 * t).sin_cos();
                    // The Nyquist harmonic is sampled as a cosine only.
                    if 2 * k == m {
                        c * ck
                    } else {
                        c * ck + s * sk
                    }
                })
                .sum()
        })
        .collect()
}

/// Whether the cycle `(slope, phase)` is a straight line, so that its two
/// ends bound every constraint.
pub fn is_line(slope: f64, phase: f64) -> bool {
    (slope * phase.sin()).abs() < 1e-12
}

/// `lambda_2` for the cycle with centre `center`, slope `psi` and phase
/// `phi` on the discretisation's nodes. `samples` is used for an ellipse
/// only; a line uses its two ends.
///
/// The linear programme of model.md section 7.3 in `(g, lambda)`, with
/// `mean g = 0`, solved by an interior-point method on the `2 N` rows that
/// can bind (per node and sign, the sample where the load raises
/// `s q - f p` fastest), whatever the number of samples.
///
/// # Errors
///
/// [`LimitError::Samples`] for an ellipse with `samples` outside
/// `3..=`[`MAX_SAMPLES`]; [`LimitError::Param`] for an invalid centre,
/// slope or phase; [`LimitError::Infeasible`] when no slip satisfies the
/// friction law at `A`; [`LimitError::Unbounded`] when λ reaches the cap of
/// 1000; [`LimitError::MaxIterations`], [`LimitError::Numerical`] or
/// [`LimitError::Setup`] when the LP solver fails.
pub fn shakedown_limit(
    material: &Material,
    center: LoadPoint,
    slope: f64,
    phase: f64,
    disc: &Discretisation,
    samples: usize,
) -> Result<Limit, LimitError> {
    let line = is_line(slope, phase);
    if !line && !crate::model::ranges::SAMPLES.contains(samples) {
        return Err(LimitError::Samples(samples));
    }
    // A unit cycle: its load at time t is the direction the load moves per
    // unit of lambda.
    let unit = Cycle::new(center, 1.0, slope, phase)?;
    let times: Vec<f64> = if line {
        vec![0.5 * PI, 1.5 * PI]
    } else {
        (0..samples)
            .map(|k| 2.0 * PI * k as f64 / samples as f64)
            .collect()
    };

    let points: Vec<LoadPoint> = times.iter().map(|&t| unit.at(t)).collect();
    let optimum = optimum(material, center, &points, disc.nodes())?;
    // The inscribed M-gon holds the ellipse shrunk by cos(pi / M).
    let shrink = if line {
        1.0
    } else {
        (PI / samples as f64).cos()
    };
    Ok(optimum.into_limit(shrink, times, line))
}

/// `lambda_2` for any cycle: the ellipse as [`shakedown_limit`] with
/// `samples`; a polyline at its vertices (`samples` unused; at most
/// [`MAX_SAMPLES`] of them). The friction
/// rows are linear in the load, so a slip admissible at the vertices is
/// admissible on every chord between them (their convex hull): the
/// polyline's `lambda_2` is exact, and [`Limit::lower_bound`] equals it
/// (model.md section 5.4).
///
/// # Errors
///
/// As [`shakedown_limit`].
pub fn cycle_limit(
    material: &Material,
    cycle: &Cycle,
    disc: &Discretisation,
    samples: usize,
) -> Result<Limit, LimitError> {
    let Some(polyline) = cycle.as_polyline() else {
        return shakedown_limit(
            material,
            cycle.center(),
            cycle.slope(),
            cycle.phase(),
            disc,
            samples,
        );
    };
    let center = cycle.center();
    let vertices = polyline.vertices();
    let m = vertices.len();
    // The programme holds a rate per vertex, node and sign.
    if m > MAX_SAMPLES {
        return Err(LimitError::Samples(m));
    }
    let times: Vec<f64> = (0..m).map(|k| 2.0 * PI * k as f64 / m as f64).collect();
    let points: Vec<LoadPoint> = vertices
        .iter()
        .map(|o| LoadPoint::new(center.x() + o.x(), center.y() + o.y()))
        .collect();
    Ok(optimum(material, center, &points, disc.nodes())?.into_limit(1.0, times, false))
}

/// One row of [`sample_convergence`]: the sample count `M`, `lambda_M`
/// (an upper bound) and `lambda_M cos(pi/M)` (a lower bound).
pub type ConvergenceRow = (usize, f64, f64);

/// The convergence of `lambda_2` in the number of samples of an elliptical
/// cycle: `limit` (solved with `samples`) and the same programme on the
/// coarser samplings `samples/8, samples/4, samples/2` (those with at least
/// 3 samples), coarsest first, ending with `samples` itself. A straight
/// line has nothing to converge: the list is empty. The loop doubles a
/// count of at least 1, so it ends for every `samples`.
///
/// # Errors
///
/// As [`shakedown_limit`] on a coarser sampling.
pub fn sample_convergence(
    material: &Material,
    center: LoadPoint,
    slope: f64,
    phase: f64,
    disc: &Discretisation,
    samples: usize,
    limit: &Limit,
) -> Result<Vec<ConvergenceRow>, LimitError> {
    let mut rows = Vec::new();
    if limit.line {
        return Ok(rows);
    }
    let mut m = (samples / 8).max(1);
    while m < samples {
        if m >= 3 {
            let l = shakedown_limit(material, center, slope, phase, disc, m)?;
            rows.push((m, l.load_factor, l.lower_bound));
        }
        m *= 2;
    }
    rows.push((samples, limit.load_factor, limit.lower_bound));
    Ok(rows)
}

/// The optimal slip of the `lambda_2` problem for `cycle` (its `lambda` is
/// irrelevant) as an initial condition named `optimal`: the run starts at
/// the centre `A` with this slip and no transient.
///
/// Model.md section 7.4; the slip is [`Limit::slip`] of
/// [`shakedown_limit`] with [`DEFAULT_SAMPLES`] samples for an ellipse.
///
/// # Errors
///
/// As [`shakedown_limit`].
pub fn optimal_initial(
    material: &Material,
    cycle: &Cycle,
    disc: &Discretisation,
) -> Result<Initial, LimitError> {
    let limit = cycle_limit(material, cycle, disc, DEFAULT_SAMPLES)?;
    Ok(Initial::Slip {
        name: "optimal".into(),
        slip: Arc::new(limit.slip),
    })
}
