//! The finite step (model.md section 3.2): the active-set iteration of one
//! increment from the last increment's slip set, its reduced system by a
//! fresh LU, and the commit of a solved increment. The fallback of the
//! exact increment ([`super::increment`]) and the public one-step solve.

use std::f64::consts::PI;

use super::{Contact, ContactEnd, ContactError, SlipDirection, Solved, Trial, Workspace};
use crate::contact::kernels::DenseLu;
use crate::contact::operators::Operators;
use crate::contact::tolerances::{DG_TOL, GROSS_TOL, TRACTION_TOL};
use crate::model::LoadPoint;

pub(in crate::contact) fn most_negative(p: &[f64]) -> Option<(usize, f64)> {
    p.iter()
        .copied()
        .enumerate()
        .filter(|(_, v)| *v < 0.0)
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// `x` with `(-|D| - f diag(s) H)_SS x = rhs` for the slip set `set`
/// (nodes and signs `s`), by a fresh LU with partial pivoting of the
/// `k x k` reduced matrix. The finite step is the fallback of the exact
/// increment and the public one-step solve, not a hot path: a fresh
/// factorisation each pass is the simple way, and the path-following
/// increment keeps its own low-rank updated inverse ([`SetInverse`]).
fn solve_reduced(
    lu: &mut DenseLu,
    ops: &Operators,
    friction: f64,
    set: &[(usize, f64)],
    rhs: &[f64],
    x: &mut [f64],
) {
    let k = set.len();
    lu.reserve(ops.nodes());
    for (b, &(col, _)) in set.iter().enumerate() {
        let hcol = ops.hilbert_col(col);
        let dcol = ops.abs_derivative_col(col);
        let out = &mut lu.lu[b * k..(b + 1) * k];
        for (o, &(row, sign)) in out.iter_mut().zip(set) {
            *o = -dcol[row] - friction * sign * hcol[row];
        }
    }
    lu.factorise(k);
    x.copy_from_slice(rhs);
    lu.solve(x);
}

/// A hash of a slip set with directions, to notice a cycling active set.
pub(in crate::contact) fn fingerprint(dirs: &[SlipDirection]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    dirs.hash(&mut h);
    h.finish()
}

/// Where a trial slip set would hold every node off the torque limit, one
/// node is held stuck instead, and if that fails the next: at most this
/// many in one search (model.md section 3.2, "Every node at the limit").
pub(in crate::contact) const MAX_HELD: usize = 8;

/// Whether `y` is on the torque limit `|y| = 2 pi` (to [`GROSS_TOL`]).
pub(in crate::contact) fn on_the_torque_limit(y: f64) -> bool {
    y.abs() >= 2.0 * PI * (1.0 - GROSS_TOL)
}

/// The node to hold stuck where a trial set would hold every node off the
/// torque limit: of `slipping` (node, how fast it slips or how far it is
/// past the limit), the least, among nodes not `held` already.
///
/// With every node slipping, the slip rates are fixed only up to a rigid
/// rotation, which changes no traction, so the `N` equations of the set
/// have `N - 1` effective unknowns and in general no solution: some node
/// must stick. Where the last stick node reaches the limit beside a zone
/// slipping the other way, the stick zone moves over by a node: the
/// neighbour on the other side, the slowest node of that zone, sticks.
pub(in crate::contact) fn node_to_hold(
    slipping: impl Iterator<Item = (usize, f64)>,
    held: &[usize],
) -> Option<usize> {
    slipping
        .filter(|(j, _)| !held.contains(j))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(j, _)| j)
}

impl Contact {
    /// Solve the increment to `load` in one finite step, without
    /// committing it (model.md section 3.2): the active-set iteration from
    /// the last increment's slip set. Events inside the step are not
    /// located ([`Contact::advance`] finds them exactly).
    ///
    /// It ends in [`ContactEnd::GrossSlip`] only where every node slips and
    /// `load` is on or past the torque limit `|y| = 2 pi` (reported at
    /// `load`, not at the crossing); off it, a node is held stuck where a
    /// trial set would hold every node. [`ContactEnd::Separation`] is
    /// reported where the solution makes `p < 0`, and
    /// [`ContactError::NotSettled`] where the iteration finds no consistent
    /// set (a shorter step then helps).
    ///
    /// # Examples
    ///
    /// ```
    /// use shakedown::contact::Solved;
    /// use shakedown::stepping::operators;
    /// use shakedown::{Contact, ContactEnd, Discretisation, LoadPoint, Material};
    ///
    /// let mut contact = Contact::new(Material::paper(), operators(&Discretisation::default()));
    /// // Past the stick diamond |x| + |y| <= 2 pi some nodes slip.
    /// let Ok(Solved::Trial(trial)) = contact.solve(LoadPoint::new(1.0, 5.8)) else {
    ///     panic!("a partial slip step settles");
    /// };
    /// assert!(trial.directions.iter().any(|d| d.is_slipping()));
    /// contact.commit(trial);
    /// // Past |y| = 2 pi the whole interface slides.
    /// let end = contact.solve(LoadPoint::new(1.0, 7.0)).unwrap();
    /// assert!(matches!(end, Solved::Ended(ContactEnd::GrossSlip { .. })));
    /// ```
    pub fn solve(&mut self, load: LoadPoint) -> Result<Solved, ContactError> {
        let n = self.nodes();
        let f = self.material.friction();
        let mut w = self
            .work
            .take()
            .unwrap_or_else(|| Box::new(Workspace::new(n)));
        let result = self.solve_with(load, f, n, &mut w);
        self.work = Some(w);
        result
    }

    pub(in crate::contact) fn solve_with(
        &self,
        load: LoadPoint,
        f: f64,
        n: usize,
        w: &mut Workspace,
    ) -> Result<Solved, ContactError> {
        self.tractions_into(load, &mut w.p0, &mut w.q0);
        if let Some((node, pressure)) = most_negative(&w.p0) {
            return Ok(Solved::Ended(self.separation(load, node, pressure)));
        }

        // Warm start: last increment's slip set plus every predictor violation.
        let mut dirs = self.directions.clone();
        for ((d, &q0), &p0) in dirs.iter_mut().zip(&w.q0).zip(&w.p0) {
            if q0.abs() > f * p0 + TRACTION_TOL {
                *d = SlipDirection::from_sign(q0);
            }
        }

        let max_iterations = 4 * n + 20;
        let mut seen: Vec<u64> = Vec::new();
        let mut held: Vec<usize> = Vec::new();
        let mut factorisations = 0;
        let mut dg = vec![0.0f64; n];
        let mut p = w.p0.clone();
        let mut q = w.q0.clone();
        for iteration in 1..=max_iterations {
            w.set.clear();
            w.set.extend(
                (0..n)
                    .filter(|&j| dirs[j].is_slipping())
                    .map(|j| (j, dirs[j].sign())),
            );
            if w.set.len() == n {
                if on_the_torque_limit(load.y()) {
                    return Ok(Solved::Ended(ContactEnd::GrossSlip { load }));
                }
                // Off the torque limit not every node can slip: hold the
                // slowest node of the last pass (before any pass, the node
                // least past the limit) and try again; `node_to_hold`.
                let passed = dg.iter().any(|&d| d != 0.0);
                let slipping =
                    w.set
                        .iter()
                        .filter(|&&(j, _)| !passed || dg[j] != 0.0)
                        .map(|&(j, _)| {
                            let key = if passed {
                                dg[j].abs()
                            } else {
                                w.q0[j].abs() - f * w.p0[j]
                            };
                            (j, key)
                        });
                match node_to_hold(slipping, &held) {
                    Some(j) if held.len() < MAX_HELD => {
                        dirs[j] = SlipDirection::Stick;
                        held.push(j);
                        continue;
                    }
                    _ => break,
                }
            }
            dg.fill(0.0);
            p.copy_from_slice(&w.p0);
            q.copy_from_slice(&w.q0);
            if !w.set.is_empty() {
                let k = w.set.len();
                for (r, &(j, s)) in w.rhs.iter_mut().zip(&w.set) {
                    *r = -(w.q0[j] - s * f * w.p0[j]);
                }
                solve_reduced(
                    &mut w.reduced,
                    &self.ops,
                    f,
                    &w.set,
                    &w.rhs[..k],
                    &mut w.x[..k],
                );
                factorisations += 1;
                for (&d, &(col, _)) in w.x[..k].iter().zip(&w.set) {
                    if !d.is_finite() {
                        return Err(ContactError::NotSettled {
                            load,
                            iterations: iteration,
                        });
                    }
                    dg[col] = d;
                }
                self.ops
                    .apply_both(&dg, &mut w.pressure_change, &mut w.relief, &mut w.fft);
                for j in 0..n {
                    p[j] = w.p0[j] + w.pressure_change[j];
                    q[j] = w.q0[j] - w.relief[j];
                }
            }

            let scale = w.set.iter().map(|&(j, _)| dg[j].abs()).fold(0.0, f64::max);
            let mut changed = false;
            for &(j, _) in &w.set {
                if dirs[j].sign() * dg[j] < -DG_TOL * scale {
                    dirs[j] = SlipDirection::Stick;
                    changed = true;
                }
            }
            // A node released in this pass still carries its dg here; it comes
            // back next pass if its traction then asks for it.
            for j in 0..n {
                if dg[j] == 0.0 && !dirs[j].is_slipping() && q[j].abs() > f * p[j] + TRACTION_TOL {
                    dirs[j] = SlipDirection::from_sign(q[j]);
                    changed = true;
                }
            }
            if !changed {
                if let Some((node, pressure)) = most_negative(&p) {
                    return Ok(Solved::Ended(self.separation(load, node, pressure)));
                }
                let directions: Vec<SlipDirection> = (0..n)
                    .map(|j| {
                        if dirs[j].is_slipping() && dg[j] != 0.0 {
                            SlipDirection::from_sign(dg[j])
                        } else {
                            SlipDirection::Stick
                        }
                    })
                    .collect();
                let dtheta = 2.0 * PI / n as f64;
                // q dg = f p |dg| on slip nodes; averaging the pressure at the
                // start (old load) and end of the increment makes the sum
                // second order in the increment.
                let dissipation: f64 = (0..n)
                    .filter(|&j| dg[j] != 0.0)
                    .map(|j| 0.5 * f * 0.5 * (p[j] + self.pressure[j]) * dg[j].abs())
                    .sum::<f64>()
                    * dtheta;
                return Ok(Solved::Trial(Trial {
                    load,
                    slip_increment: dg,
                    pressure: p,
                    shear: q,
                    directions,
                    dissipation,
                    iterations: iteration,
                    factorisations,
                }));
            }
            // Most increments settle in one to three passes; only a longer
            // search is watched for revisiting a slip set (a cycle).
            if iteration > 4 {
                let h = fingerprint(&dirs);
                if seen.contains(&h) {
                    break;
                }
                seen.push(h);
            }
        }
        Err(ContactError::NotSettled {
            load,
            iterations: max_iterations.min(seen.len() + 5),
        })
    }

    /// Tractions at `load` with the current slip, into the given buffers.
    pub(in crate::contact) fn tractions_into(&self, load: LoadPoint, p: &mut [f64], q: &mut [f64]) {
        let loads = self.material.to_loads(load);
        let two_pi = 2.0 * PI;
        let pr = self.material.beta() * loads.radial / two_pi;
        let qr = self.material.alpha() * loads.radial / two_pi;
        let qt = loads.torque / two_pi;
        for j in 0..p.len() {
            p[j] = 1.0 - pr * self.sin[j] + self.residual_pressure[j];
            q[j] = -qt - qr * self.cos[j] + self.residual_shear[j];
        }
    }

    pub(in crate::contact) fn separation(
        &self,
        load: LoadPoint,
        node: usize,
        pressure: f64,
    ) -> ContactEnd {
        ContactEnd::Separation {
            load,
            node,
            theta: 2.0 * PI * node as f64 / self.nodes() as f64,
            pressure,
        }
    }

    /// Commit a solved increment.
    pub fn commit(&mut self, trial: Trial) {
        self.forget_clearance();
        if trial.slip_increment.iter().any(|&d| d != 0.0) {
            for (g, d) in self.slip.iter_mut().zip(&trial.slip_increment) {
                *g += d;
            }
            let (p_el, q_el) = self.elastic_tractions(trial.load);
            for j in 0..self.nodes() {
                self.residual_pressure[j] = trial.pressure[j] - p_el[j];
                self.residual_shear[j] = trial.shear[j] - q_el[j];
            }
        }
        self.load = trial.load;
        self.pressure = trial.pressure;
        self.shear = trial.shear;
        if self.directions != trial.directions {
            self.invalidate_responses();
        }
        self.directions = trial.directions;
    }
}
