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

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, ZeroConeT,
};
use serde::Serialize;

use crate::contact::{Contact, Operators};
use crate::model::path::Initial;
use crate::model::{Cycle, Discretisation, LoadPoint, Material, ParamError};

/// Samples of an elliptical cycle when none are given: the bound on
/// `lambda_2` is then tight to `1 - cos(pi/64)`, about 0.12 %.
pub const DEFAULT_SAMPLES: usize = 64;
/// Most samples accepted (the programme has `2 N M` rows).
pub const MAX_SAMPLES: usize = 4096;
/// `lambda` is capped here (as in [`Cycle::new`]); reaching the cap means
/// no finite limit exists for this cycle direction.
const LAMBDA_CAP: f64 = 1e3;

/// The limit analysis failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitError {
    /// An elliptical cycle was to be sampled at fewer than 3 or more than
    /// [`MAX_SAMPLES`] times `M`; holds the count given.
    #[error("samples = {0} is out of range: expected 3 to 4096 points on the ellipse")]
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
    /// Interior-point iterations.
    pub iterations: u32,
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
/// `mean g = 0`, solved by an interior-point method on a growing subset of
/// the samples until no sample is violated.
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
    if !line && !(3..=MAX_SAMPLES).contains(&samples) {
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

    let n = disc.nodes();
    let ops = Arc::new(Operators::new(n));
    let contact = Contact::new(*material, Arc::clone(&ops));
    let (p_center, q_center) = contact.elastic_tractions(center);
    // Per sample: the change of the elastic tractions per unit lambda. The
    // tractions are affine in the load, so a difference is exact.
    let rates: Vec<(Vec<f64>, Vec<f64>)> = times
        .iter()
        .map(|&t| {
            let (p, q) = contact.elastic_tractions(unit.at(t));
            let dp = p.iter().zip(&p_center).map(|(a, b)| a - b).collect();
            let dq = q.iter().zip(&q_center).map(|(a, b)| a - b).collect();
            (dp, dq)
        })
        .collect();
    let lp = Programme {
        ops: &ops,
        friction: material.friction(),
        p_center,
        q_center,
        rates,
        center,
    };

    // Most samples of a fine ellipse are slack at the optimum. Solve on a
    // coarse subset, add the samples the optimum violates, and repeat: the
    // final optimum satisfies every sample, so it is the optimum of the full
    // programme, at a fraction of its size.
    let all: Vec<usize> = (0..times.len()).collect();
    let mut active: Vec<usize> = all
        .iter()
        .copied()
        .step_by((times.len() / 8).max(1))
        .collect();
    let mut iterations = 0;
    let (slip, load_factor, max_violation) = loop {
        let (slip, load_factor, its) = lp.solve(&active)?;
        iterations += its;
        let violation: Vec<(usize, f64)> = lp
            .violations(&slip, load_factor)
            .into_iter()
            .enumerate()
            .collect();
        let max_violation = violation.iter().map(|v| v.1).fold(f64::MIN, f64::max);
        let missing: Vec<usize> = violation
            .iter()
            .filter(|(k, v)| *v > CUT_TOLERANCE && !active.contains(k))
            .map(|(k, _)| *k)
            .collect();
        if missing.is_empty() {
            break (slip, load_factor, max_violation);
        }
        active.extend(missing);
        active.sort_unstable();
    };

    let lower_bound = if line {
        load_factor
    } else {
        load_factor * (PI / samples as f64).cos()
    };
    Ok(Limit {
        load_factor,
        lower_bound,
        slip,
        times,
        line,
        max_violation,
        iterations,
    })
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

/// A sample that violates the friction law by more than this (in units of
/// `p0`) at the optimum of the subset joins the programme.
const CUT_TOLERANCE: f64 = 1e-9;

/// The `lambda_2` programme's data.
struct Programme<'a> {
    ops: &'a Operators,
    friction: f64,
    center: LoadPoint,
    p_center: Vec<f64>,
    q_center: Vec<f64>,
    /// Elastic traction change per unit lambda at each sample: `(dp, dq)`.
    rates: Vec<(Vec<f64>, Vec<f64>)>,
}

impl Programme<'_> {
    /// The optimum `(g, lambda)` with the friction law imposed at the
    /// samples `subset`, and the interior-point iterations taken.
    fn solve(&self, subset: &[usize]) -> Result<(Vec<f64>, f64, u32), LimitError> {
        let n = self.p_center.len();
        let f = self.friction;
        // Rows: 0 is `mean g = 0`; then for each sample, node j and sign s
        // the friction inequality; then `-lambda <= 0` and `lambda <= cap`.
        let m_friction = 2 * n * subset.len();
        let rows = 1 + m_friction + 2;
        let row_of = |k: usize, j: usize, s: usize| 1 + (k * n + j) * 2 + s;
        let signs = [1.0, -1.0];

        let mut colptr = Vec::with_capacity(n + 2);
        let mut rowval = Vec::new();
        let mut nzval = Vec::new();
        colptr.push(0);
        for col in 0..n {
            rowval.push(0);
            nzval.push(1.0 / n as f64);
            let (h, d) = (self.ops.hilbert_col(col), self.ops.abs_derivative_col(col));
            for k in 0..subset.len() {
                for j in 0..n {
                    for (si, s) in signs.iter().enumerate() {
                        // s q - f p with q = -|D| g, p = H g
                        let v = -s * d[j] - f * h[j];
                        if v != 0.0 {
                            rowval.push(row_of(k, j, si));
                            nzval.push(v);
                        }
                    }
                }
            }
            colptr.push(nzval.len());
        }
        for (k, &sample) in subset.iter().enumerate() {
            let (dp, dq) = &self.rates[sample];
            for j in 0..n {
                for (si, s) in signs.iter().enumerate() {
                    let v = s * dq[j] - f * dp[j];
                    if v != 0.0 {
                        rowval.push(row_of(k, j, si));
                        nzval.push(v);
                    }
                }
            }
        }
        rowval.push(rows - 2);
        nzval.push(-1.0);
        rowval.push(rows - 1);
        nzval.push(1.0);
        colptr.push(nzval.len());
        let a = CscMatrix::new(rows, n + 1, colptr, rowval, nzval);

        let mut b = vec![0.0; rows];
        for k in 0..subset.len() {
            for j in 0..n {
                for (si, s) in signs.iter().enumerate() {
                    b[row_of(k, j, si)] = f * self.p_center[j] - s * self.q_center[j];
                }
            }
        }
        b[rows - 1] = LAMBDA_CAP;

        let p = CscMatrix::<f64>::zeros((n + 1, n + 1));
        let mut c = vec![0.0; n + 1];
        c[n] = -1.0;
        let cones = [ZeroConeT(1), NonnegativeConeT(m_friction + 2)];
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(200)
            .build()
            .map_err(|e| LimitError::Setup(e.to_string()))?;
        let mut solver = DefaultSolver::new(&p, &c, &a, &b, &cones, settings)
            .map_err(|e| LimitError::Setup(e.to_string()))?;
        solver.solve();
        let sol = &solver.solution;
        match sol.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {}
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                return Err(LimitError::Infeasible {
                    center: self.center,
                })
            }
            SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => {
                return Err(LimitError::Unbounded)
            }
            SolverStatus::MaxIterations => {
                return Err(LimitError::MaxIterations {
                    iterations: sol.iterations,
                })
            }
            other => {
                return Err(LimitError::Numerical {
                    status: format!("{other:?}"),
                })
            }
        }
        let load_factor = sol.x[n];
        if !load_factor.is_finite() {
            return Err(LimitError::Numerical {
                status: "non-finite optimum".into(),
            });
        }
        if load_factor >= LAMBDA_CAP * (1.0 - 1e-6) {
            return Err(LimitError::Unbounded);
        }
        let mean = sol.x[..n].iter().sum::<f64>() / n as f64;
        let slip = sol.x[..n].iter().map(|g| g - mean).collect();
        Ok((slip, load_factor, sol.iterations))
    }

    /// At every sample, the largest `|q| - f p` over the nodes at
    /// `lambda` with the locked-in slip `g`.
    fn violations(&self, slip: &[f64], load_factor: f64) -> Vec<f64> {
        let hg = self.ops.residual_pressure(slip);
        let dg = self.ops.residual_shear(slip);
        self.rates
            .iter()
            .map(|(dp, dq)| {
                (0..slip.len())
                    .map(|j| {
                        let p = self.p_center[j] + load_factor * dp[j] + hg[j];
                        let q = self.q_center[j] + load_factor * dq[j] + dg[j];
                        q.abs() - self.friction * p
                    })
                    .fold(f64::MIN, f64::max)
            })
            .collect()
    }
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
    let limit = shakedown_limit(
        material,
        cycle.center(),
        cycle.slope(),
        cycle.phase(),
        disc,
        DEFAULT_SAMPLES,
    )?;
    Ok(Initial::Slip {
        name: "optimal".into(),
        slip: Arc::new(limit.slip),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper(phase: f64, nodes: usize, samples: usize) -> Limit {
        shakedown_limit(
            &Material::paper(),
            LoadPoint::new(PI, 0.75 * PI),
            0.625,
            phase,
            &Discretisation::new(nodes, 400).unwrap(),
            samples,
        )
        .unwrap()
    }

    #[test]
    fn optimum_is_admissible_and_tight() {
        let l = paper(0.0, 64, 0);
        assert!(l.line);
        assert!(l.max_violation < 1e-6, "{}", l.max_violation);
        assert!(l.slip.iter().sum::<f64>().abs() < 1e-9);
        // Below the gross-slip bound: |y| reaches 2 pi at lambda = 7.41.
        let gross = 1.25 * PI * (1.0f64 + 0.625 * 0.625).sqrt() / 0.625;
        assert!(l.load_factor > 0.0 && l.load_factor < gross);
        // Beyond lambda_2 the returned slip cannot hold the friction law.
        let mut c = Contact::new(Material::paper(), Arc::new(Operators::new(64)));
        c.set_slip(&l.slip);
        let cycle = Cycle::paper(1.05 * l.load_factor, 0.0).unwrap();
        let worst = [0.5 * PI, 1.5 * PI]
            .iter()
            .map(|&t| {
                let (p, q) = c.tractions_at(cycle.at(t));
                p.iter()
                    .zip(&q)
                    .map(|(p, q)| q.abs() - 0.1 * p)
                    .fold(f64::MIN, f64::max)
            })
            .fold(f64::MIN, f64::max);
        assert!(worst > 0.0);
    }

    #[test]
    fn without_slip_the_limit_is_the_elastic_one() {
        // With g = 0 the limit is where the line leaves the stick diamond
        // |x| + |y| <= 2 pi; slip can only raise it.
        let l = paper(0.0, 64, 0);
        let norm = (1.0f64 + 0.625 * 0.625).sqrt();
        let elastic = (2.0 * PI - 1.75 * PI) * norm / (1.0 + 0.625);
        assert!(l.load_factor >= elastic - 1e-6);
    }

    #[test]
    fn ellipse_bounds_bracket_a_finer_sampling() {
        let coarse = paper(0.5 * PI, 32, 8);
        let fine = paper(0.5 * PI, 32, 64);
        assert!(!coarse.line);
        assert!(fine.load_factor <= coarse.load_factor + 1e-6);
        assert!(fine.load_factor >= coarse.lower_bound - 1e-6);
    }

    #[test]
    fn bad_sample_count_is_an_error() {
        let r = shakedown_limit(
            &Material::paper(),
            LoadPoint::new(PI, 0.75 * PI),
            0.625,
            1.0,
            &Discretisation::default(),
            2,
        );
        assert_eq!(r, Err(LimitError::Samples(2)));
    }
}
