//! The `lambda_2` programme's data and its interior-point solution
//! (Clarabel): the rows that can bind, the solve, and the check of an
//! answer against every row.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, ZeroConeT,
};

use super::{LimitError, LAMBDA_CAP};
use crate::contact::{Contact, Operators};
use crate::model::LoadPoint;

/// One row of the programme: the friction inequality
/// `s q_j - f p_j <= 0` at node `j` with sign `s` (`sign` 0 for `+1`, 1 for
/// `-1`), whose load term is `load_factor * rate`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Row {
    pub(super) node: usize,
    pub(super) sign: usize,
    pub(super) rate: f64,
}

/// The `lambda_2` programme's data.
pub(super) struct Programme<'a> {
    pub(super) ops: &'a Operators,
    pub(super) friction: f64,
    pub(super) center: LoadPoint,
    pub(super) p_center: Vec<f64>,
    pub(super) q_center: Vec<f64>,
    /// Per load point `k`, node `j` and sign `s`: `s dq_j - f dp_j`, the
    /// change of `s q_j - f p_j` per unit lambda.
    pub(super) rates: Vec<Vec<[f64; 2]>>,
}

pub(super) const SIGNS: [f64; 2] = [1.0, -1.0];

impl<'a> Programme<'a> {
    /// The programme for the cycle centred on `center` whose load points
    /// at `lambda = 1` are `points`.
    pub(super) fn new(
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

    /// One row per node, the sign whose row is nearer to binding with the
    /// slip `slip` at `load_factor`: a guess of the optimum's active set.
    pub(super) fn guess(&self, rows: &[Row], slip: &[f64], load_factor: f64) -> Vec<usize> {
        let hg = self.ops.residual_pressure(slip);
        let dg = self.ops.residual_shear(slip);
        let slack = |r: usize| {
            let row = rows[r];
            let j = row.node;
            let s = SIGNS[row.sign];
            self.friction * (self.p_center[j] + hg[j])
                - s * (self.q_center[j] + dg[j])
                - load_factor * row.rate
        };
        (0..slip.len())
            .map(|j| {
                if slack(2 * j) <= slack(2 * j + 1) {
                    2 * j
                } else {
                    2 * j + 1
                }
            })
            .collect()
    }

    /// Every row: each node and sign at each load point (`2 N M` rows).
    #[cfg(test)]
    pub(super) fn all_rows(&self) -> Vec<Row> {
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
    pub(super) fn reduced_rows(&self) -> Vec<Row> {
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
    /// and the interior-point iterations taken, solved to the solver's
    /// feasibility and gap `tolerance`.
    pub(super) fn solve(
        &self,
        rows: &[Row],
        tolerance: f64,
    ) -> Result<(Vec<f64>, f64, u32), LimitError> {
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
            .tol_gap_abs(tolerance)
            .tol_gap_rel(tolerance)
            .tol_feas(tolerance)
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
    pub(super) fn max_violation(&self, slip: &[f64], load_factor: f64) -> f64 {
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
