//! The regime map: the steady state and `W` over the `(lambda, phi)` plane
//! for one initial transient. The paper's Figs. 3, 6 and 8 are lines of
//! this plane (`phi = 0`, `lambda = 5.1`, `phi = pi/2`), and its Fig. 9
//! samples it at six values of `lambda`; the map shows the whole plane,
//! with the shakedown limit `lambda_2(phi)` of
//! [`crate::analysis::limit_curve`] as its boundary.
//!
//! A map is built from the rows of a sweep over `lambda x phi` (one
//! initial path): [`RegimeMap::from_rows`], or from plain cells with
//! [`RegimeMap::from_cells`] (a figure's CSV, or the terminal's sweep view).

use crate::analysis::sweep::Row;
use crate::stepping::steady::SteadyState;

/// One cell of the map: the state of the run (`None` when it failed) and
/// its `W`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegimeCell {
    /// The steady state, `None` for a numerical failure.
    pub state: Option<SteadyState>,
    /// `W` of the last complete cycle.
    pub dissipation: f64,
}

impl RegimeCell {
    /// The cell of a sweep's run: its state and `W`, or a failure.
    pub fn of_row(row: &Row) -> RegimeCell {
        match &row.outcome {
            Ok(s) => RegimeCell {
                state: Some(s.state()),
                dissipation: s.dissipation,
            },
            Err(_) => RegimeCell {
                state: None,
                dissipation: f64::NAN,
            },
        }
    }
}

/// The states over a `lambda x phi` grid.
#[derive(Debug, Clone, PartialEq)]
pub struct RegimeMap {
    load_factors: Vec<f64>,
    phases: Vec<f64>,
    /// Row-major by phase: `cells[j * load_factors.len() + i]` is
    /// `(load_factors[i], phases[j])`; `None` where no run was given.
    cells: Vec<Option<RegimeCell>>,
}

impl RegimeMap {
    /// A map over the grid `load_factors x phases` (sorted, repeats
    /// dropped) with no cell yet: one to fill in with [`RegimeMap::insert`]
    /// as runs finish (the terminal's regime map).
    pub fn empty(load_factors: &[f64], phases: &[f64]) -> RegimeMap {
        let sorted = |v: &[f64]| {
            let mut v = v.to_vec();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        };
        let load_factors = sorted(load_factors);
        let phases = sorted(phases);
        RegimeMap {
            cells: vec![None; load_factors.len() * phases.len()],
            load_factors,
            phases,
        }
    }

    /// Put `cell` at the grid point `(lambda, phi)`, replacing what was
    /// there. Returns false, and changes nothing, when the point is not on
    /// the grid.
    pub fn insert(&mut self, load_factor: f64, phase: f64, cell: RegimeCell) -> bool {
        let i = self.load_factors.partition_point(|&v| v < load_factor);
        let j = self.phases.partition_point(|&v| v < phase);
        if self.load_factors.get(i) != Some(&load_factor) || self.phases.get(j) != Some(&phase) {
            return false;
        }
        self.cells[j * self.load_factors.len() + i] = Some(cell);
        true
    }

    /// Empty every cell, keeping the grid.
    pub fn clear(&mut self) {
        self.cells.iter_mut().for_each(|c| *c = None);
    }

    /// The number of cells that hold a run.
    pub fn filled(&self) -> usize {
        self.cells.iter().filter(|c| c.is_some()).count()
    }

    /// The map of `(lambda, phi, cell)` triples. The grid is the sorted
    /// distinct `lambda` and `phi`; a repeated point keeps the last cell.
    pub fn from_cells(cells: impl IntoIterator<Item = (f64, f64, RegimeCell)>) -> RegimeMap {
        let cells: Vec<(f64, f64, RegimeCell)> = cells.into_iter().collect();
        let lambdas: Vec<f64> = cells.iter().map(|c| c.0).collect();
        let phases: Vec<f64> = cells.iter().map(|c| c.1).collect();
        let mut map = Self::empty(&lambdas, &phases);
        for (l, p, cell) in cells {
            map.insert(l, p, cell);
        }
        map
    }

    /// The map of a sweep's rows (use one initial path: with several, the
    /// last one at each point wins).
    pub fn from_rows(rows: &[Row]) -> RegimeMap {
        Self::from_cells(
            rows.iter()
                .map(|r| (r.job.load_factor, r.job.phase, RegimeCell::of_row(r))),
        )
    }

    /// The `lambda` values, ascending.
    pub fn load_factors(&self) -> &[f64] {
        &self.load_factors
    }

    /// The `phi` values, ascending.
    pub fn phases(&self) -> &[f64] {
        &self.phases
    }

    /// The cell at `(load_factors[i], phases[j])`.
    pub fn cell(&self, i: usize, j: usize) -> Option<RegimeCell> {
        if i >= self.load_factors.len() || j >= self.phases.len() {
            return None;
        }
        self.cells[j * self.load_factors.len() + i]
    }

    /// The grid indices `(i, j)` nearest to `(lambda, phi)` (for a cursor).
    pub fn nearest(&self, load_factor: f64, phase: f64) -> Option<(usize, usize)> {
        let near = |v: &[f64], x: f64| {
            (0..v.len()).min_by(|&a, &b| (v[a] - x).abs().total_cmp(&(v[b] - x).abs()))
        };
        Some((
            near(&self.load_factors, load_factor)?,
            near(&self.phases, phase)?,
        ))
    }

    /// The half-widths of cell `(i, j)` in `lambda` and `phi`: half the gap
    /// to each neighbour (the gap to the one neighbour at an edge), so the
    /// cells tile the plane even on an uneven grid. Returns
    /// `((lambda_lo, lambda_hi), (phi_lo, phi_hi))`.
    pub fn cell_bounds(&self, i: usize, j: usize) -> ((f64, f64), (f64, f64)) {
        (bounds(&self.load_factors, i), bounds(&self.phases, j))
    }

    /// The smallest and largest positive finite `W` on the map.
    pub fn dissipation_range(&self) -> Option<(f64, f64)> {
        let w = self
            .cells
            .iter()
            .flatten()
            .map(|c| c.dissipation)
            .filter(|w| w.is_finite() && *w > 0.0);
        let lo = w.clone().fold(f64::MAX, f64::min);
        let hi = w.fold(0.0, f64::max);
        (hi > 0.0).then_some((lo, hi))
    }
}

fn bounds(v: &[f64], i: usize) -> (f64, f64) {
    let gap = |a: usize, b: usize| 0.5 * (v[b] - v[a]);
    match v.len() {
        0 => (0.0, 0.0),
        1 => (v[0] - 0.5, v[0] + 0.5),
        n => {
            let lo = if i == 0 { gap(0, 1) } else { gap(i - 1, i) };
            let hi = if i + 1 == n {
                gap(n - 2, n - 1)
            } else {
                gap(i, i + 1)
            };
            (v[i] - lo, v[i] + hi)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_from_cells() {
        let c = |w| RegimeCell {
            state: Some(SteadyState::CyclicSlip),
            dissipation: w,
        };
        let m = RegimeMap::from_cells([(5.0, 0.0, c(1.0)), (4.0, 0.0, c(0.5)), (5.0, 1.0, c(2.0))]);
        assert_eq!(m.load_factors(), &[4.0, 5.0]);
        assert_eq!(m.phases(), &[0.0, 1.0]);
        assert_eq!(m.cell(1, 1).unwrap().dissipation, 2.0);
        assert_eq!(m.cell(0, 1), None);
        assert_eq!(m.nearest(4.4, 0.9), Some((0, 1)));
        assert_eq!(m.cell_bounds(0, 0), ((3.5, 4.5), (-0.5, 0.5)));
        assert_eq!(m.dissipation_range(), Some((0.5, 2.0)));
        assert_eq!(m.filled(), 3);
    }

    #[test]
    fn an_empty_grid_fills_in() {
        let mut m = RegimeMap::empty(&[5.0, 4.0, 5.0], &[0.0, 1.0]);
        assert_eq!(m.load_factors(), &[4.0, 5.0]);
        assert_eq!(m.filled(), 0);
        let c = RegimeCell {
            state: None,
            dissipation: f64::NAN,
        };
        assert!(m.insert(5.0, 1.0, c));
        assert!(!m.insert(4.5, 1.0, c), "not a grid point");
        assert!(!m.insert(9.0, 1.0, c), "beyond the grid");
        assert_eq!(m.filled(), 1);
        assert!(m.cell(1, 1).is_some());
        m.clear();
        assert_eq!(m.filled(), 0);
    }
}
