//! The walk along a segment with the slip set fixed: the scan for the
//! first event (entry into slip, separation, the torque limit), located in
//! closed form from the linear rates, and the move up to it.

use super::*;
use std::f64::consts::PI;

use crate::contact::kernels::{self, end_margins, event_times};
use crate::contact::solver::on_the_torque_limit;
use crate::contact::solver::{Contact, Workspace};
use crate::contact::tolerances::{CLEARANCE_SLACK, EVENT_TIES, RATE_TOL, SCREEN, TRACTION_TOL};
use crate::model::LoadPoint;

impl Contact {
    /// The first event in `(0, remaining]` of the segment with the cached
    /// set, or a request to solve the rate problem here first. The segment
    /// runs along `dx u1 + dy u2`; `load_dy` is its change of `y`. With
    /// the stop, a lower bound on every node's end margin where the segment
    /// ends, if the scan took the end margins (the clearance of the next
    /// segment, should this one reach its end).
    pub(super) fn scan(
        &self,
        w: &mut Workspace,
        dx: f64,
        dy: f64,
        load_dy: f64,
        remaining: f64,
    ) -> (Stop, f64, bool, Option<f64>) {
        let f = self.material.friction();
        let t_min = remaining;
        // Taken here whatever happens: it holds only for the state it was
        // taken at, which this segment leaves.
        let clearance = w.engine.clearance.take();
        // A slip rate against its direction: the set must be decided anew
        // here, and the segment is scanned again after that.
        let bounded = self.bounded();
        if !w.engine.set.is_empty() && w.engine.rates_against(dx, dy, bounded) {
            return (Stop::End, t_min, true, None);
        }
        let (ex, ey) = (remaining * dx, remaining * dy);
        if self.segment_increments == 1 && bounded {
            if let Some((_, c)) = clearance.filter(|&(at, _)| at == self.load) {
                // Every node's end margin is at least the clearance less
                // the most the segment can lower it: if that stays above
                // the screen, the pass over the nodes would find nothing
                // below it and test none, so it need not be made.
                let fall = ex.abs() * w.engine.reach(0, f)
                    + if ey == 0.0 {
                        0.0
                    } else {
                        ey.abs() * w.engine.reach(1, f)
                    };
                let ahead = c - fall * (1.0 + CLEARANCE_SLACK) - CLEARANCE_SLACK;
                if ahead >= SCREEN {
                    #[cfg(feature = "counters")]
                    {
                        w.engine.spared[1] += 1;
                    }
                    let (stop, t, need_rates) = self.gross_or(Stop::End, t_min, false, load_dy);
                    return (stop, t, need_rates, Some(ahead));
                }
            }
        }
        let mut margins = std::mem::take(&mut w.engine.margins);
        let e = &w.engine;
        let mut t_min = t_min;
        let mut stop = Stop::End;
        let mut need_rates = false;
        let n = e.tpx.len();
        let (p, q) = (&self.pressure[..n], &self.shear[..n]);
        let (tpx, tpy, tqx, tqy) = (&e.tpx[..n], &e.tpy[..n], &e.tqx[..n], &e.tqy[..n]);
        let v = [p, q, tpx, tpy, tqx, tqy, &e.off[..n]];
        // A branch-free pass over the nodes gives each a number, and the
        // nodes whose number is below `bound` take the exact test, in node
        // order. Most often that is the end margin, and nothing is below
        // the screen (no node can reach an event on the segment). On a
        // straight run of increments, though, most stick nodes would reach
        // the limit by the end of so long a segment: there the number is
        // the node's first event, and only the nodes within round-off of the
        // earliest take the exact test, which finds the same event at the
        // same parameter as testing every node would. A node at the limit
        // with its slack falling (-1 there) goes by its end margin.
        let mut lowest = -1.0;
        let mut bound = 0.0;
        if self.segment_increments > 1 {
            lowest = event_times(v, [dx, dy, remaining], f, RATE_TOL, &mut margins[..n]);
            bound = if lowest < remaining + remaining * EVENT_TIES {
                lowest + lowest * EVENT_TIES + f64::MIN_POSITIVE
            } else {
                lowest
            };
        }
        let mut ahead = None;
        if lowest < 0.0 {
            lowest = end_margins(v, f, ex, ey, &mut margins[..n]);
            bound = SCREEN;
            ahead = Some(lowest - CLEARANCE_SLACK);
        }
        if lowest < bound {
            // Chunks with no node below the bound (nearly all: an event
            // involves a node or two) are passed over branch-free; in the
            // others a bit per node below it gives the nodes to test, in
            // node order (a loop over every node of such a chunk, with a
            // branch each, cost 1.3 % more of a sweep's instructions).
            // Whole chunks and the tail apart: with `chunks`, whose length
            // the compiler does not know, the test of a chunk is a loop
            // again (`advance` took 871 M instructions on every fifth
            // `lambda` of the Fig. 3 map against 742 M).
            const CHUNK: usize = 16;
            let chunks = margins[..n].chunks_exact(CHUNK);
            let tail = chunks.remainder();
            let masks = chunks
                .map(|chunk| {
                    if !chunk.iter().fold(false, |acc, &m| acc | (m < bound)) {
                        return 0;
                    }
                    let mut below = 0u32;
                    for (i, &m) in chunk.iter().enumerate() {
                        below |= u32::from(m < bound) << i;
                    }
                    below
                })
                .chain(std::iter::once(
                    tail.iter()
                        .enumerate()
                        .fold(0u32, |acc, (i, &m)| acc | (u32::from(m < bound) << i)),
                ));
            for (c, mut below) in masks.enumerate() {
                while below != 0 {
                    let j = c * CHUNK + below.trailing_zeros() as usize;
                    below &= below - 1;
                    self.locate(
                        w,
                        j,
                        dx,
                        dy,
                        remaining,
                        &mut t_min,
                        &mut stop,
                        &mut need_rates,
                    );
                }
            }
        }
        w.engine.margins = margins;
        let (stop, t, need_rates) = self.gross_or(stop, t_min, need_rates, load_dy);
        (stop, t, need_rates, ahead)
    }

    /// The segment's first stop: `stop` at `t_min` (with `need_rates`), or
    /// gross slip where `|y|` reaches `2 pi` first (`load_dy` the change of
    /// `y` along the segment).
    pub(super) fn gross_or(
        &self,
        mut stop: Stop,
        mut t_min: f64,
        need_rates: bool,
        load_dy: f64,
    ) -> (Stop, f64, bool) {
        if load_dy != 0.0 {
            let y = self.load.y();
            let limit = 2.0 * PI * load_dy.signum();
            let t = if on_the_torque_limit(y) && y * load_dy > 0.0 {
                0.0
            } else {
                (limit - y) / load_dy
            };
            if t >= 0.0 && t <= t_min {
                t_min = t;
                stop = Stop::Gross;
            }
        }
        (stop, t_min, need_rates)
    }

    /// The exact test of node `j` for an event before `t_min` (the slow
    /// part of [`Self::scan`], only for nodes whose end margin is low).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub(super) fn locate(
        &self,
        w: &Workspace,
        j: usize,
        dx: f64,
        dy: f64,
        remaining: f64,
        t_min: &mut f64,
        stop: &mut Stop,
        need_rates: &mut bool,
    ) {
        let f = self.material.friction();
        let e = &w.engine;
        let (p, q) = (self.pressure[j], self.shear[j]);
        let a = dx * e.tpx[j] + dy * e.tpy[j];
        // Separation: p + t a = 0 (divide only when it comes first).
        if a < 0.0 && p < -a * *t_min {
            *t_min = p.max(0.0) / -a;
            *stop = Stop::Separation(j);
        }
        if e.stick[j] {
            let b = dx * e.tqx[j] + dy * e.tqy[j];
            // Slack f p - sigma q on the forward (sigma = 1) and backward
            // side, and its rate.
            for (h0, h1) in [(f * p - q, f * a - b), (f * p + q, f * a + b)] {
                if h1 < -RATE_TOL && h0 + remaining * h1 < -TRACTION_TOL {
                    if h0 <= TRACTION_TOL {
                        *need_rates = true;
                    } else if h0 < -h1 * *t_min {
                        *t_min = h0 / -h1;
                        *stop = Stop::Entry;
                    }
                }
            }
        }
    }

    /// Move by `t` of the segment parameter with the cached set, to `load`.
    ///
    /// The residual tractions move with the slip rates; `p` and `q` are
    /// then the elastic part at `load` plus the residual part, so they never
    /// drift from the load. One pass over the nodes does both and the
    /// dissipation `f/2 sum p |dg| dtheta`, with `p` averaged over the
    /// sub-segment (exact: `p` is linear and `dg` uniform on it).
    pub(super) fn move_along(
        &mut self,
        w: &mut Workspace,
        t: f64,
        dx: f64,
        dy: f64,
        load: LoadPoint,
    ) {
        let f = self.material.friction();
        let n = self.nodes();
        let e = &mut w.engine;
        self.increment.segments += 1;
        self.load = load;
        if t == 0.0 {
            return;
        }
        let (tx, ty) = (t * dx, t * dy);
        let elastic = self.elastic_part(load);
        if e.set.is_empty() {
            // Stick only: the residual part does not change.
            let parts = [
                &self.sin[..],
                &self.cos,
                &self.residual_pressure,
                &self.residual_shear,
            ];
            kernels::tractions(elastic, parts, &mut self.pressure, &mut self.shear);
            return;
        }
        // Slip, and its forward and backward parts, change on the set only:
        // a loop over the set's indices when it is small, else in the
        // vectorised pass over every node below (the rates are 0 off the
        // set, so the two give the same numbers).
        let inc = &mut self.increment;
        inc.slipped = true;
        let by_node = e.set.len() * SET_LOOP_SHARE < n;
        if by_node {
            inc.clear_stale();
            for &(j, _) in &e.set {
                // The bits of `t rg` (`Engine::combine`).
                let dg = t * (dx * e.gx[j] + dy * e.gy[j]);
                self.slip[j] += dg;
                inc.forward[j] += dg.max(0.0);
                inc.backward[j] += (-dg).max(0.0);
            }
        }
        let slip = (!by_node).then(|| kernels::SlipOut {
            slip: &mut self.slip,
            forward: &mut inc.forward,
            backward: &mut inc.backward,
            fresh: std::mem::take(&mut inc.stale),
        });
        // The rates along the segment, if a scan or a rate problem made
        // them; else the pass makes them from those per unit `u1`, `u2`.
        let combined = e.rg_for == Some((dx, dy));
        // One pass over the nodes: the residual tractions move with the
        // slip rates, `p` and `q` follow, and the dissipation
        // f/2 sum |dg| (p before + p after) dtheta accumulates.
        let slide = kernels::Slide {
            t,
            tx,
            ty,
            elastic,
            responses: e.responses(),
            trig: [&self.sin, &self.cos],
            rates: if combined {
                [&e.rg, &[]]
            } else {
                [&e.gx, &e.gy]
            },
            along: (!combined).then_some([dx, dy]),
        };
        let state = [
            &mut self.residual_pressure[..],
            &mut self.residual_shear,
            &mut self.pressure,
            &mut self.shear,
        ];
        let acc = kernels::slide(&slide, state, slip);
        let sum = (acc[0] + acc[1]) + (acc[2] + acc[3]);
        let dtheta = 2.0 * PI / n as f64;
        self.increment.dissipation += 0.5 * f * 0.5 * sum * dtheta;
    }
}
