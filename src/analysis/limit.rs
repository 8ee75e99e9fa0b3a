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

    let n = disc.nodes();
    let ops = Arc::new(Operators::new(n));
    let contact = Contact::new(*material, Arc::clone(&ops));
    let lp = Programme::new(&contact, &ops, center, times.iter().map(|&t| unit.at(t)));
    let (slip, load_factor, iterations) = lp.solve(&lp.reduced_rows())?;
    if load_factor >= LAMBDA_CAP * (1.0 - 1e-6) {
        return Err(LimitError::Unbounded);
    }
    let max_violation = lp.max_violation(&slip, load_factor);

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
    let ops = Arc::new(Operators::new(disc.nodes()));
    let contact = Contact::new(*material, Arc::clone(&ops));
    let points = vertices
        .iter()
        .map(|o| LoadPoint::new(center.x() + o.x(), center.y() + o.y()));
    let lp = Programme::new(&contact, &ops, center, points);
    let (slip, load_factor, iterations) = lp.solve(&lp.reduced_rows())?;
    if load_factor >= LAMBDA_CAP * (1.0 - 1e-6) {
        return Err(LimitError::Unbounded);
    }
    let max_violation = lp.max_violation(&slip, load_factor);
    Ok(Limit {
        load_factor,
        lower_bound: load_factor,
        slip,
        times,
        line: false,
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

/// One row of the programme: the friction inequality
/// `s q_j - f p_j <= 0` at node `j` with sign `s` (`sign` 0 for `+1`, 1 for
/// `-1`), whose load term is `load_factor * rate`.
#[derive(Debug, Clone, Copy)]
struct Row {
    node: usize,
    sign: usize,
    rate: f64,
}

/// The `lambda_2` programme's data.
struct Programme<'a> {
    ops: &'a Operators,
    friction: f64,
    center: LoadPoint,
    p_center: Vec<f64>,
    q_center: Vec<f64>,
    /// Per load point `k`, node `j` and sign `s`: `s dq_j - f dp_j`, the
    /// change of `s q_j - f p_j` per unit lambda.
    rates: Vec<Vec<[f64; 2]>>,
}

const SIGNS: [f64; 2] = [1.0, -1.0];

impl<'a> Programme<'a> {
    /// The programme for the cycle centred on `center` whose load points
    /// at `lambda = 1` are `points`.
    fn new(
        contact: &Contact,
        ops: &'a Operators,
        center: LoadPoint,
        points: impl Iterator<Item = LoadPoint>,
    ) -> Self {
        let friction = contact.material().friction();
        let (p_center, q_center) = contact.elastic_tractions(center);
        // The tractions are affine in the load, so a difference is exact.
        let rates = points
            .map(|point| {
                let (p, q) = contact.elastic_tractions(point);
                (0..p.len())
                    .map(|j| {
                        let dp = p[j] - p_center[j];
                        let dq = q[j] - q_center[j];
                        SIGNS.map(|s| s * dq - friction * dp)
                    })
                    .collect()
            })
            .collect();
        Self {
            ops,
            friction,
            center,
            p_center,
            q_center,
            rates,
        }
    }

    /// Every row: each node and sign at each load point (`2 N M` rows).
    #[cfg(test)]
    fn all_rows(&self) -> Vec<Row> {
        self.rates
            .iter()
            .flat_map(|r| {
                r.iter().enumerate().flat_map(|(node, a)| {
                    (0..2).map(move |sign| Row {
                        node,
                        sign,
                        rate: a[sign],
                    })
                })
            })
            .collect()
    }

    /// The rows that can bind: per node and sign, the load point with the
    /// largest rate. A row differs from its node and sign's other rows
    /// only in its load term `lambda * rate`, and `lambda >= 0`, so the
    /// row with the largest rate implies the others: these `2 N` rows
    /// define the same feasible set, and the same optimum, as all `2 N M`.
    fn reduced_rows(&self) -> Vec<Row> {
        let n = self.p_center.len();
        (0..n)
            .flat_map(|node| {
                (0..2).map(move |sign| Row {
                    node,
                    sign,
                    rate: self
                        .rates
                        .iter()
                        .map(|r| r[node][sign])
                        .fold(f64::NEG_INFINITY, f64::max),
                })
            })
            .collect()
    }

    /// The optimum `(g, lambda)` with the friction law imposed on `rows`,
    /// and the interior-point iterations taken.
    fn solve(&self, rows: &[Row]) -> Result<(Vec<f64>, f64, u32), LimitError> {
        let n = self.p_center.len();
        let f = self.friction;
        // Row 0 is `mean g = 0`; then the friction rows; then
        // `-lambda <= 0` and `lambda <= cap`.
        let m_friction = rows.len();
        let m = 1 + m_friction + 2;
        // By node: the rows of node j and their signs, for the columns.
        let mut by_node: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for (r, row) in rows.iter().enumerate() {
            by_node[row.node].push((1 + r, SIGNS[row.sign]));
        }

        let mut colptr = Vec::with_capacity(n + 2);
        let mut rowval = Vec::new();
        let mut nzval = Vec::new();
        colptr.push(0);
        for col in 0..n {
            rowval.push(0);
            nzval.push(1.0 / n as f64);
            let (h, d) = (self.ops.hilbert_col(col), self.ops.abs_derivative_col(col));
            // Rows are pushed in increasing order: node by node, and a
            // node's rows are in the order of `rows`.
            let mut entries: Vec<(usize, f64)> = Vec::new();
            for (j, node_rows) in by_node.iter().enumerate() {
                for &(r, s) in node_rows {
                    // s q - f p with q = -|D| g, p = H g
                    let v = -s * d[j] - f * h[j];
                    if v != 0.0 {
                        entries.push((r, v));
                    }
                }
            }
            entries.sort_unstable_by_key(|e| e.0);
            for (r, v) in entries {
                rowval.push(r);
                nzval.push(v);
            }
            colptr.push(nzval.len());
        }
        for (r, row) in rows.iter().enumerate() {
            if row.rate != 0.0 {
                rowval.push(1 + r);
                nzval.push(row.rate);
            }
        }
        rowval.push(m - 2);
        nzval.push(-1.0);
        rowval.push(m - 1);
        nzval.push(1.0);
        colptr.push(nzval.len());
        let a = CscMatrix::new(m, n + 1, colptr, rowval, nzval);

        let mut b = vec![0.0; m];
        for (r, row) in rows.iter().enumerate() {
            let (j, s) = (row.node, SIGNS[row.sign]);
            b[1 + r] = f * self.p_center[j] - s * self.q_center[j];
        }
        b[m - 1] = LAMBDA_CAP;

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
        let mean = sol.x[..n].iter().sum::<f64>() / n as f64;
        let slip = sol.x[..n].iter().map(|g| g - mean).collect();
        Ok((slip, load_factor, sol.iterations))
    }

    /// The largest `|q| - f p` over the nodes and load points at
    /// `lambda` with the locked-in slip `g`.
    fn max_violation(&self, slip: &[f64], load_factor: f64) -> f64 {
        let hg = self.ops.residual_pressure(slip);
        let dg = self.ops.residual_shear(slip);
        let mut worst = f64::MIN;
        for r in &self.rates {
            for (j, a) in r.iter().enumerate() {
                let p = self.p_center[j] + hg[j];
                let q = self.q_center[j] + dg[j];
                for (sign, s) in SIGNS.iter().enumerate() {
                    worst = worst.max(s * q - self.friction * p + load_factor * a[sign]);
                }
            }
        }
        worst
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
    let limit = cycle_limit(material, cycle, disc, DEFAULT_SAMPLES)?;
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

    /// The `2 N` rows that can bind give the optimum of all `2 N M` rows
    /// (the programme as first stated), on several cycles and grids.
    #[test]
    fn reduced_rows_give_the_full_programme_optimum() {
        let material = Material::paper();
        let center = LoadPoint::new(PI, 0.75 * PI);
        for (nodes, phase, samples) in [
            (16, 0.0, 2),
            (16, 0.3 * PI, 12),
            (32, 0.5 * PI, 16),
            (24, 0.9 * PI, 9),
        ] {
            let unit = Cycle::new(center, 1.0, 0.625, phase).unwrap();
            let times: Vec<f64> = (0..samples)
                .map(|k| 0.5 * PI + 2.0 * PI * k as f64 / samples as f64)
                .collect();
            let ops = Arc::new(Operators::new(nodes));
            let contact = Contact::new(material, Arc::clone(&ops));
            let lp = Programme::new(&contact, &ops, center, times.iter().map(|&t| unit.at(t)));
            let (_, full, _) = lp.solve(&lp.all_rows()).unwrap();
            let (slip, reduced, _) = lp.solve(&lp.reduced_rows()).unwrap();
            assert!(
                (full - reduced).abs() <= 1e-9 * full,
                "N = {nodes}, phi = {phase}: {full} against {reduced}"
            );
            assert!(lp.max_violation(&slip, reduced) < 1e-8);
        }
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
