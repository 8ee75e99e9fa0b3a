//! A proof of shakedown before the first cycle without slip: a safe state
//! near the present one, and an energy bound on all the slip still to come
//! (`docs/model.md` section 6.4).
//!
//! Runs that shake down only asymptotically slip less and less for hundreds
//! of cycles before a cycle passes without any slip. Melan's theorem does
//! not hold for this coupled system in general (slip changes the pressure),
//! but a local form of it does: if some locked-in slip `g_s` (a *safe
//! state*) keeps `|q| <= f p - delta` at every node and instant of the
//! cycle, and the present slip `g` is close enough to it,
//!
//! ```text
//! f C R < delta,    R^2 = (g - g_s)^T |D| (g - g_s),    C^2 = 2 (1 + 1/2 + ... + 1/(N/2 - 1)) / N,
//! ```
//!
//! then the stored energy `E = R^2 / 2` never grows, and the total slip of
//! all nodes in all later cycles is at most `R^2 / (2 (delta - f C R))`.
//! Finite total slip means the slip per cycle tends to zero: shakedown. The
//! reasoning is in `docs/model.md` section 6.4.
//!
//! Finding `g_s` is a second-order cone programme (solved with Clarabel):
//! maximise `delta - f C R` over the safe states. It is solved small and
//! early (a *quick search*: `g_s - g` among the lowest harmonics, from
//! cycle 2), which proves the runs that approach shakedown geometrically,
//! and in full late and rarely (every harmonic, from cycle 20), which the
//! slow power-law approaches need. Whatever the solver returns is checked
//! afresh, exactly, before it is believed.
//!
//! The search is here, its cone programme in [`programme`] and the
//! harmonic basis of the quick search in [`basis`].

use std::f64::consts::PI;
use std::sync::{Arc, OnceLock};

use serde::Serialize;

use super::stepper::cycle_angle;
use crate::contact::{Contact, Operators};
use crate::model::{Cycle, Material};

mod basis;
mod programme;
#[cfg(test)]
mod tests;
use basis::Basis;

/// What proves a run's shakedown before a cycle without slip: a safe state,
/// its margin and distance, and the bound on the slip still to come
/// (`docs/model.md` section 6.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Certificate {
    /// The cycle after which it was proven.
    pub cycle: usize,
    /// `delta`: the safe state keeps `|q| <= f p - delta` at every node and
    /// instant of the cycle.
    pub margin: f64,
    /// `R`: the energy distance from the slip after `cycle` to the safe
    /// state, `sqrt((g - g_s)^T |D| (g - g_s))`.
    pub distance: f64,
    /// `f C`: how much pressure a unit of energy distance can change at
    /// most (the normal-tangential coupling).
    pub coupling: f64,
    /// The total slip `sum |dg|` of all nodes over all cycles after
    /// `cycle` is at most this (so is any one node's).
    pub slip_bound: f64,
    /// `W` of cycle `cycle`, the last one run.
    pub last_dissipation: f64,
}

/// Below this value of `delta - f C R` a candidate proves nothing: the
/// solver's tractions meet the friction law to about `1e-12`.
const PROOF_TOLERANCE: f64 = 1e-9;

/// The first full search for a safe state is made after this cycle, and
/// only after a cycle whose `W` fell slowly ([`SLOW_FALL`]). A full search
/// (all `N - 1` harmonics) costs about as much as 50 to 80 cycles at
/// `N = 128`; the quick searches ([`QUICK_FIRST`]) have by then proven the
/// runs whose safe state is smooth, and a `W` that falls fast reaches a
/// cycle without slip (or its level) sooner than a full search would pay
/// for itself.
pub(crate) const FIRST_ATTEMPT: usize = 20;

/// A full search is made only after a cycle whose `W` fell by less than
/// this factor from the cycle before (see `Stepper`).
pub(crate) const SLOW_FALL: f64 = 0.8;
/// Later full searches are spaced by this factor in the cycle count. The
/// best safe state hardly depends on the slip reached (a search at cycle 35
/// finds the one found at cycle 10 to 1e-9), so the candidate found is
/// re-checked after every cycle, at `O(N)`, and searches are rare.
const ATTEMPT_GROWTH: f64 = 4.0;

/// The first quick search is made after this cycle, after any cycle whose
/// `W` fell, and later ones at twice the cycle count of the last. A quick
/// search looks for a safe state among the slip changes of the lowest
/// [`QUICK_HARMONICS`] harmonics only, and only on the margins that can
/// bind: it costs about two cycles at `N = 128`, against the tens of cycles
/// that a run with a smooth safe state still needs before its first cycle
/// without slip.
pub(crate) const QUICK_FIRST: usize = 2;

/// Harmonics of the quick search. Fewer fail where a safe state needs a
/// change of the slip over a fifth of the circle (`lambda = 4.5`, `phi =
/// 0`, path `7,-7`: 4 harmonics prove nothing by cycle 32, 8 prove it at
/// cycle 2).
const QUICK_HARMONICS: usize = 8;

/// Both searches start from the margin rows below this fraction of the
/// largest (the rest are far from binding) and add any row their answer
/// violates, at most [`QUICK_ROUNDS`] or [`FULL_ROUNDS`] times. The quick
/// search from 5 % (about 80 of the 256 rows at `N = 128`) violated most of
/// the others, and two searches in three needed a second round on about
/// 225 rows; from 20 % one in three does, and the searches of the Fig. 3
/// map take a fifth less time (0.95 s against 1.19 s, 377 searches, one
/// thread). The full search, on every row before, takes about 160 of 256
/// from 20 % and nearly always one round: the full searches of the Fig. 6
/// map took 12.3 s against 17.9 s (265 searches, two threads; 15.5 s from
/// 10 %, 23.0 s from 5 %, where more rounds are needed). The same rows came
/// out of the Fig. 3, `phi = pi/2` and Fig. 6 maps.
const START_ROWS: f64 = 0.2;
const QUICK_ROUNDS: usize = 3;
/// A full search stops adding rows after this many rounds (three at most
/// were needed in the Fig. 6 map); its answer is checked exactly anyway.
const FULL_ROUNDS: usize = 8;

/// How far a run's `W` fell in its last cycle: what decides whether a
/// search for a safe state is worth its cost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fall {
    /// `W` did not fall: no search.
    None,
    /// `W` fell by more than the factor `SLOW_FALL` (0.8): a quick search
    /// only.
    Fast,
    /// `W` fell by less than the factor `SLOW_FALL`: a quick or a full
    /// search.
    Slow,
}

/// The search for a safe state, and the best candidate so far, for one run.
#[derive(Debug, Clone)]
pub struct SafeStateSearch {
    friction: f64,
    /// `f C` (module docs).
    coupling: f64,
    /// The elastic margins and the basis: what depends on the cycle, the
    /// material and the grid only, shared by the runs of one cycle.
    setup: Arc<Setup>,
    /// The best safe state found: `g_s`, `|D| g_s` and its margin.
    candidate: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// The cycle of the next full search.
    next_attempt: usize,
    /// The cycle of the next quick search.
    next_quick: usize,
    /// Searches run (quick and full).
    pub searches: usize,
}

/// `f C` for `N` nodes: the largest `|f (H e)_j|` over `e` with
/// `e^T |D| e = 1` (Cauchy-Schwarz on the Fourier modes, attained).
pub fn coupling_constant(friction: f64, nodes: usize) -> f64 {
    let harmonic: f64 = (1..nodes / 2).map(|k| 1.0 / k as f64).sum();
    friction * (2.0 * harmonic / nodes as f64).sqrt()
}

/// What a [`SafeStateSearch`] needs that depends only on the cycle, the
/// material, the nodes and the increments per cycle, not on the run's
/// history: the least elastic margins over the cycle and the basis of the
/// cone programme. Made once per cycle and shared
/// ([`SafeStateSearch::sharing`]): setting up took about 2 % of a Fig. 3
/// sweep's instructions when every run made its own.
#[derive(Debug)]
pub(crate) struct Setup {
    material: Material,
    cycle: Cycle,
    nodes: usize,
    steps: usize,
    /// The least of `f p - s q` over the cycle's load points with no slip,
    /// per node and sign `s = +1, -1`, less the allowance for a path that
    /// leaves the chords ([`SafeStateSearch::new`]).
    elastic: Vec<[f64; 2]>,
    /// The basis of the cone programme's slip change, built at the first
    /// search (most runs never make one).
    basis: OnceLock<Basis>,
}

impl Setup {
    fn new(contact: &Contact, cycle: &Cycle, steps: usize) -> Self {
        let friction = contact.material().friction();
        let mut elastic = contact
            .least_elastic_margins((0..steps).map(|j| cycle.at(cycle_angle(j as f64, steps))));
        let dt = 2.0 * PI / steps as f64;
        let allowance =
            std::f64::consts::SQRT_2 * friction / (2.0 * PI) * cycle.load_factor() * dt * dt / 8.0;
        for e in &mut elastic {
            e[0] -= allowance;
            e[1] -= allowance;
        }
        Self {
            material: *contact.material(),
            cycle: cycle.clone(),
            nodes: contact.nodes(),
            steps,
            elastic,
            basis: OnceLock::new(),
        }
    }

    /// Whether this setup is the one a search of `cycle` on `contact`'s
    /// material and nodes, `steps` increments a cycle, would make.
    fn fits(&self, contact: &Contact, cycle: &Cycle, steps: usize) -> bool {
        self.material == *contact.material()
            && self.cycle == *cycle
            && self.nodes == contact.nodes()
            && self.steps == steps
    }
}

impl SafeStateSearch {
    /// Set up for a run of `cycle` on the contact's nodes and material.
    ///
    /// The contact follows straight chords between the cycle's
    /// `steps` load points, where every `f p - s q` is linear, so its least
    /// value over the cycle is the least over the points. Where an
    /// increment that failed to settle is bisected, the path visits points
    /// of the ellipse between them instead; these lie within
    /// `lambda (2 pi / steps)^2 / 8` of the chord, and `f p - s q` changes
    /// by at most `sqrt(2) f / (2 pi)` per unit of load, so that much is
    /// taken off every margin.
    pub fn new(contact: &Contact, cycle: &Cycle, steps: usize) -> Self {
        Self::sharing(None, contact, cycle, steps)
    }

    /// As [`Self::new`], taking the elastic margins and the basis from
    /// `shared` (the setup of an earlier run's search) if it was made for
    /// the same cycle, material, nodes and increments, and making them
    /// afresh if not. They are the same for every run of a cycle whatever
    /// its initial path: a sweep hands them from run to run within a
    /// `lambda` and `phi`, as it hands the response cache.
    pub(crate) fn sharing(
        shared: Option<Arc<Setup>>,
        contact: &Contact,
        cycle: &Cycle,
        steps: usize,
    ) -> Self {
        let setup = shared
            .filter(|s| s.fits(contact, cycle, steps))
            .unwrap_or_else(|| Arc::new(Setup::new(contact, cycle, steps)));
        let friction = contact.material().friction();
        Self {
            friction,
            coupling: coupling_constant(friction, contact.nodes()),
            setup,
            candidate: None,
            next_attempt: FIRST_ATTEMPT,
            next_quick: QUICK_FIRST,
            searches: 0,
        }
    }

    /// The setup this search works with, for the next run of its cycle
    /// ([`Self::sharing`]).
    pub(crate) fn setup(&self) -> &Arc<Setup> {
        &self.setup
    }

    fn basis(&self) -> &Basis {
        let elastic = &self.setup.elastic;
        self.setup
            .basis
            .get_or_init(|| Basis::harmonics(elastic.len()))
    }

    /// After complete cycle `cycle` (with `W` = `dissipation`, and `fall`
    /// how far it fell from the cycle before): a certificate if the
    /// contact's present slip is proven to shake down.
    pub fn check(
        &mut self,
        contact: &Contact,
        ops: &Operators,
        cycle: usize,
        dissipation: f64,
        fall: Fall,
    ) -> Option<Certificate> {
        let quick = fall != Fall::None && cycle >= self.next_quick;
        let full = fall == Fall::Slow && cycle >= self.next_attempt;
        if self.candidate.is_none() && !quick && !full {
            return None;
        }
        let g = contact.slip();
        // |D| g afresh from g (the contact's own copy is updated increment
        // by increment): O(N^2), some microseconds a cycle.
        let relief: Vec<f64> = ops.residual_shear(g).iter().map(|v| -v).collect();
        if let Some(c) = self.certify_candidate(g, &relief, cycle, dissipation) {
            return Some(c);
        }
        if !quick && !full {
            return None;
        }
        if quick {
            self.next_quick = 2 * cycle;
        }
        if full {
            self.next_attempt = ((cycle as f64 * ATTEMPT_GROWTH).ceil() as usize).max(cycle + 1);
        }
        let margins = self.margins(&ops.residual_pressure(g), &relief);
        // The margin of a safe state is at most the mean of the two signs'
        // margins at any node (the shear terms cancel, the pressure gains
        // at most f C R): a quick test that rules out cyclic slip.
        let best = margins
            .iter()
            .map(|m| 0.5 * (m[0] + m[1]))
            .fold(f64::INFINITY, f64::min);
        if best <= PROOF_TOLERANCE {
            return None;
        }
        let searches = [
            (quick, 2 * QUICK_HARMONICS.min(self.basis().size / 2)),
            (full, self.basis().size),
        ];
        for (due, columns) in searches {
            if !due {
                continue;
            }
            self.searches += 1;
            let Some(z) = self.solve(&margins, columns) else {
                continue;
            };
            self.consider(ops, g, &relief, &z);
            if let Some(c) = self.certify_candidate(g, &relief, cycle, dissipation) {
                return Some(c);
            }
        }
        None
    }

    /// Keep the safe state `g + z` if it proves more than the one kept:
    /// its margin recomputed exactly at every node, not taken from the
    /// solver.
    fn consider(&mut self, ops: &Operators, g: &[f64], relief: &[f64], z: &[f64]) {
        let safe: Vec<f64> = g.iter().zip(z).map(|(a, b)| a + b).collect();
        let safe_relief: Vec<f64> = ops.residual_shear(&safe).iter().map(|v| -v).collect();
        let safe_pressure = ops.residual_pressure(&safe);
        let margin = self
            .margins(&safe_pressure, &safe_relief)
            .iter()
            .flat_map(|m| m.iter().copied())
            .fold(f64::INFINITY, f64::min);
        let keep = match &self.candidate {
            None => true,
            Some((old, old_relief, old_margin)) => {
                self.value(g, relief, (&safe, &safe_relief, margin))
                    > self.value(g, relief, (old, old_relief, *old_margin))
            }
        };
        if keep {
            self.candidate = Some((safe, safe_relief, margin));
        }
    }

    /// `f p - s q` at the least point of the cycle, per node and sign, for
    /// locked-in slip with residual pressure `pressure` (`H g`) and relief
    /// `relief` (`|D| g`).
    fn margins(&self, pressure: &[f64], relief: &[f64]) -> Vec<[f64; 2]> {
        self.setup
            .elastic
            .iter()
            .zip(pressure.iter().zip(relief))
            .map(|(e, (p, r))| {
                let f = self.friction;
                // q = q_el - |D| g, p = p_el + H g.
                [e[0] + f * p + r, e[1] + f * p - r]
            })
            .collect()
    }

    /// `delta - f C R` of a safe state `(g_s, |D| g_s, delta)` for the
    /// present slip `g` (with `|D| g` = `relief`).
    fn value(&self, g: &[f64], relief: &[f64], safe: (&[f64], &[f64], f64)) -> f64 {
        let (gs, rs, margin) = safe;
        let distance = self.distance(g, relief, gs, rs);
        margin - self.coupling * distance
    }

    /// `sqrt((g - g_s)^T |D| (g - g_s))` from the kept `|D| g` and `|D| g_s`.
    fn distance(&self, g: &[f64], relief: &[f64], gs: &[f64], rs: &[f64]) -> f64 {
        let e: f64 = g
            .iter()
            .zip(gs)
            .zip(relief.iter().zip(rs))
            .map(|((a, b), (ra, rb))| (a - b) * (ra - rb))
            .sum();
        e.max(0.0).sqrt()
    }

    fn certify_candidate(
        &self,
        g: &[f64],
        relief: &[f64],
        cycle: usize,
        dissipation: f64,
    ) -> Option<Certificate> {
        let (gs, rs, margin) = self.candidate.as_ref()?;
        let distance = self.distance(g, relief, gs, rs);
        let value = margin - self.coupling * distance;
        (value > PROOF_TOLERANCE).then(|| Certificate {
            cycle,
            margin: *margin,
            distance,
            coupling: self.coupling,
            slip_bound: distance * distance / (2.0 * value),
            last_dissipation: dissipation,
        })
    }
}
