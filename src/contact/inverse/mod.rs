//! The solutions of `M_SS x = b_S`, `M_SS = (-|D| - f diag(s) H)_SS`, for
//! the two unit load directions, kept up to date as the slip set `S`
//! changes one node at a time.
//!
//! The exact increment ([`super::solver`]) changes the slip set at its
//! events, nearly always by one node, and needs the new set's slip rates
//! per unit load at once: `M_SS^-1 b_x` and `M_SS^-1 b_y`. A new
//! factorisation per event would cost `O(k^3)` (`k` the size of the set);
//! instead one LU is kept for a *base* matrix `A` and follows the set:
//!
//! * **a node `a` enters** with sign `s_a`: `A` is bordered by its column
//!   `c = M_Sa` and row `r = M_aS`. With `P A = L U`, the bordered LU has
//!   the new row `l = U^-T r` of `L`, the new column `u = L^-1 P c` of `U`
//!   and the pivot `sigma = M_aa - l . u` (the Schur complement); and
//!   `v = A^-1 c = U^-1 u` moves the kept solutions: the entering node's
//!   rate is `xi = (b_a - r . x) / sigma` and the others move by `-xi v`.
//!   `1.5 k^2` multiply-adds, where an explicit inverse of `A` needs `3 k^2`
//!   (two products with it and a rank-one update of it).
//! * **a node of `A` sticks**: it stays in `A`, *pinned*. Its slip is held
//!   at 0 and its row is dropped, by a multiplier on its row;
//! * **a node of `A` reverses**: its row in the current matrix is that of
//!   `A` plus `delta = 2 f s_a H_a,:` (and its right-hand side changes).
//!
//! Pinned and reversed nodes (few: at `N = 1024` one change in twenty is a
//! sticking or a reversal) are a low-rank correction of `A` solved through
//! a small capacitance system (the Woodbury identity), with the columns
//! `A^-1 e_q` of those nodes, one `O(k^2)` solve each when the node changes
//! and an `O(k)` update at each later bordering. The current set's
//! solution is `x = x_A + sum_q z_q A^-1 e_q` with `x_A = A^-1 b` kept
//! through the borderings and `z` from the capacitance system.
//!
//! `A` is refactorised from the current set (faer's LU with partial
//! pivoting) when the set changes by many nodes at once, when a bordering
//! or the capacitance system meets a small pivot, when the correction
//! grows past a few nodes, and after a number of changes proportional to
//! `k`, so the round-off that the updates accumulate stays bounded and the
//! amortised cost stays `O(k^2)`.
//!
//! The factors are kept as `L` and `W = U^-1` (not `U`), packed in one
//! square array: `L` below the diagonal, `W` on and above it. Then
//! `l = W^T r` and `v = W u` are products, not substitutions, and all
//! three come from one pass over the array, column by column
//! ([`border_pass`]): column `j` of `L` finishes `u_j`, and column `j` of
//! `W` gives `l_j` and takes `u_j` into `v`. The array is read once per
//! entry instead of one and a half times, which is what an entry costs at
//! `N = 1024`, where the factors do not fit in the cache. `W` gains the
//! column `(-v / sigma, 1 / sigma)` at a bordering, and is computed from
//! `U` at a rebuild (faer's triangular inverse, `k^3 / 6` multiply-adds
//! beside the `k^3 / 3` of the LU).
//!
//! [`SetInverse`]'s data and its methods live in this folder: the state
//! here, the following of a new set in [`update`], the borderings in
//! [`border`], the corrected solutions in [`solve`], and the `O(k)`
//! borderings of arcs in [`structured`].

use super::kernels::{axpys, border_pass, dot, dots, triangular, DenseLu, Factors, Kernel, Pass};
use super::operators::Operators;
use super::solver::SlipDirection;
use super::tolerances::PIVOT_TOL;

mod border;
mod solve;
mod structured;
mod update;
use structured::{Bordered, Structured};

const NONE: usize = usize::MAX;

/// Room to grow left in each column of the factors for a set of `k`
/// nodes (see [`SetInverse::relayout`]).
fn slack(k: usize) -> usize {
    (k / 8).max(8)
}

/// The column stride of the factors for a set of `k` nodes out of `n`:
/// room to grow ([`slack`]), rounded up to whole vectors of four so that,
/// in an [`Aligned`] array, every column starts on a 32-byte boundary and
/// no vector load of a pass straddles two cache lines (a pass ran 15 %
/// faster at `k = 128`, 4 % at `k = 500` and 9 % at `k = 680`, with the
/// vectors aligned too a run at `N = 1024` 6-8 %: the same operations on
/// the same numbers).
fn stride(k: usize, n: usize) -> usize {
    ((k + slack(k) + 3) & !3).min(n)
}

/// A zeroed array of `f64` whose first entry lies on a 32-byte boundary
/// (a `Vec<f64>` promises 8): a few entries more are allocated and the
/// array starts where the boundary falls. The factors and the vectors a
/// pass reads and writes are kept in these (the vectors aligned too, a
/// pass took 3 to 9 % less time than with them 16 bytes off). Each index
/// goes through `Deref`: loops take a slice of it first.
#[derive(Default)]
struct Aligned {
    raw: Vec<f64>,
    start: usize,
    len: usize,
}

impl Aligned {
    fn zeros(len: usize) -> Self {
        let raw = vec![0.0; len + 3];
        let start = raw.as_ptr().align_offset(32).min(3);
        Self { raw, start, len }
    }
}

impl std::ops::Deref for Aligned {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.raw[self.start..self.start + self.len]
    }
}

impl std::ops::DerefMut for Aligned {
    fn deref_mut(&mut self) -> &mut [f64] {
        &mut self.raw[self.start..self.start + self.len]
    }
}

/// The most pinned or reversed nodes of the base kept as a correction.
const MAX_SPECIAL: usize = 24;

/// Pinned or reversed nodes at which the base is refactorised, for a base
/// of `k` nodes: the correction costs `O(k m)` per change for `m` of them
/// (and `O(k m^2)` with reversals), against `O(k^3)` for a new LU.
///
/// `k / 8`: `k / 16` rebuilds more often (48 rebuilds against 39 in the
/// first six cycles of `run --lambda 5.5 --phi 0.5pi`) and takes 5.0 %
/// more instructions on that run (44.56 M against 42.43 M), 2.5 % more at
/// N = 1024 (same states, `W` at round-off). A limit of 32 or 48 past
/// `k = 256` cost more.
fn special_limit(k: usize) -> usize {
    (k / 8).clamp(4, MAX_SPECIAL)
}

/// What a node of the base matrix `A` is in the current set.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Role {
    /// Slipping with the sign it has in `A`.
    Active,
    /// Stuck: its slip is held at 0 and its row is dropped.
    Pinned,
    /// Slipping the other way: its row is `A`'s plus a `delta`.
    Reversed,
}

/// The kept solutions of `M_SS x = b_S` for the current slip set, from a
/// bordered LU of a base matrix and a low-rank correction (see the
/// module's documentation).
pub(crate) struct SetInverse {
    n: usize,
    /// The column stride of the factors: the base's size and a little room
    /// to grow, so that they lie in one nearly contiguous block (columns
    /// `N` apart defeat the prefetcher).
    ld: usize,
    friction: f64,
    /// `P A = L U`, kept as `L` strictly below the diagonal (unit
    /// diagonal) and `W = U^-1` on and above it: entry `(i, j)` at
    /// `lu[j * ld + i]`; room for `N x N`.
    lu: Aligned,
    /// Row `i` of the factors is row `perm[i]` of `A`; `perm_inv` the
    /// other way.
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    /// Node and slip sign at each position of `A`.
    nodes: Vec<usize>,
    signs: Vec<f64>,
    /// What each position of `A` is in the current set.
    roles: Vec<Role>,
    /// Position in `A` of each node, or `NONE`.
    pos: Vec<usize>,
    /// The pinned and reversed positions, by slot: slot `t` has the column
    /// `A^-1 e_q` at `special_cols[t * N..]` and, if reversed, the change
    /// of its row at `deltas[t * N..]`.
    special: Vec<usize>,
    special_cols: Vec<f64>,
    deltas: Vec<f64>,
    /// The capacitance system of the correction, factorised for the
    /// current set (`special.len()` square).
    capacitance: DenseLu,
    valid: bool,
    /// The elastic pressure and shear per unit `x` and per unit `y`
    /// (`[p_x, q_x, p_y, q_y]`), once given: the right-hand sides of the
    /// two unit load directions, `b_a = -(q_a - s f p_a)` on the set.
    loads: Option<Box<[Vec<f64>; 4]>>,
    /// `A^-1 b_a` for the two unit directions (with `A`'s signs), by
    /// position, kept through the borderings while `loads` is set.
    base_sol: [Vec<f64>; 2],
    /// The current set's solutions by position (0 where pinned), when
    /// there is a correction; else `base_sol` is the solution.
    sol: [Vec<f64>; 2],
    /// Changes since the last factorisation.
    updates: usize,
    /// Factorisations (for the increment's statistics).
    pub(crate) rebuilds: usize,
    // Scratch.
    col: Aligned,
    row: Aligned,
    u: Aligned,
    v: Aligned,
    l: Aligned,
    coef: Vec<f64>,
    /// Positions whose role changes in an update.
    changed: Vec<(usize, Role)>,
    /// The nodes whose direction may have changed since the solutions were
    /// last made those of a set ([`Self::note_changes`]), each once
    /// (`is_dirty`): an update looks at these, not at every node of `A`.
    dirty: Vec<usize>,
    is_dirty: Vec<bool>,
    factor: DenseLu,
    /// The size of the base when the structured borderings were last
    /// taken up (they are set up again only after a quarter of
    /// [`structured::MIN_NODES`] more nodes).
    last_entry: usize,
    /// The vectors of the structured borderings while the base is a few
    /// arcs ([`structured`]); the dense factors then cover the positions
    /// before `perm.len()` only.
    structured: Option<Box<Structured>>,
    /// The instruction set of the [`Kernel`] products, found once.
    arch: pulp::Arch,
}

impl Clone for SetInverse {
    fn clone(&self) -> Self {
        // A cache: a clone starts empty and rebuilds on first use.
        let mut clone = SetInverse::new(self.n);
        clone.loads.clone_from(&self.loads);
        clone
    }
}

impl SetInverse {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            n,
            ld: 0,
            friction: f64::NAN,
            // The N x N buffers wait for the first rebuild: a cloned or
            // never-slipping contact does not pay for them.
            lu: Aligned::default(),
            perm: Vec::with_capacity(n),
            perm_inv: Vec::with_capacity(n),
            nodes: Vec::with_capacity(n),
            signs: Vec::with_capacity(n),
            roles: Vec::with_capacity(n),
            pos: vec![NONE; n],
            special: Vec::with_capacity(MAX_SPECIAL),
            special_cols: Vec::new(),
            deltas: Vec::new(),
            capacitance: DenseLu::new(MAX_SPECIAL),
            valid: false,
            loads: None,
            base_sol: [vec![0.0; n], vec![0.0; n]],
            sol: [vec![0.0; n], vec![0.0; n]],
            updates: 0,
            rebuilds: 0,
            col: Aligned::zeros(n),
            row: Aligned::zeros(n),
            u: Aligned::zeros(n),
            v: Aligned::zeros(n),
            l: Aligned::zeros(n),
            coef: vec![0.0; MAX_SPECIAL],
            changed: Vec::with_capacity(n),
            dirty: Vec::with_capacity(n),
            is_dirty: vec![false; n],
            factor: DenseLu::new(0),
            last_entry: 0,
            structured: None,
            arch: pulp::Arch::new(),
        }
    }

    /// Keep the solutions for the two unit load directions from now on:
    /// `p_x`, `q_x`, `p_y`, `q_y` are the elastic tractions per unit `x` and
    /// `y` (model.md section 2.1). The next update rebuilds.
    pub(crate) fn set_loads(&mut self, loads: [&[f64]; 4]) {
        self.loads = Some(Box::new(loads.map(<[f64]>::to_vec)));
        self.valid = false;
    }

    /// The right-hand sides `b_x`, `b_y` at `node` with slip sign `sign`.
    #[inline]
    fn rhs(&self, node: usize, sign: f64) -> [f64; 2] {
        match &self.loads {
            Some(l) => {
                let f = self.friction;
                [
                    -(l[1][node] - sign * f * l[0][node]),
                    -(l[3][node] - sign * f * l[2][node]),
                ]
            }
            None => [0.0; 2],
        }
    }

    /// `M[row, col]` for a row with slip sign `sign`.
    #[inline]
    fn entry(ops: &Operators, friction: f64, row: usize, sign: f64, col: usize) -> f64 {
        -ops.abs_derivative(row, col) - friction * sign * ops.hilbert(row, col)
    }

    /// The directions of `nodes` may have changed: the next
    /// [`Self::update_to`] looks at them. Every node whose direction changes
    /// between two updates must be noted (noting more does no harm).
    pub(crate) fn note_changes(&mut self, nodes: &[usize]) {
        for &j in nodes {
            if !std::mem::replace(&mut self.is_dirty[j], true) {
                self.dirty.push(j);
            }
        }
    }

    /// Forget the noted changes: the solutions are those of the target.
    fn clear_dirty(&mut self) {
        for &j in &self.dirty {
            self.is_dirty[j] = false;
        }
        self.dirty.clear();
    }

    /// What the node at position `p` of `A` is in `target`.
    #[inline]
    fn role_in(&self, target: &[SlipDirection], p: usize) -> Role {
        let d = target[self.nodes[p]];
        if !d.is_slipping() {
            Role::Pinned
        } else if d.sign() == self.signs[p] {
            Role::Active
        } else {
            Role::Reversed
        }
    }

    /// The set as slip directions by node.
    #[cfg(test)]
    fn directions(&self) -> Vec<SlipDirection> {
        let mut d = vec![SlipDirection::Stick; self.n];
        for (p, &node) in self.nodes.iter().enumerate() {
            match self.roles[p] {
                Role::Active => d[node] = SlipDirection::from_sign(self.signs[p]),
                Role::Reversed => d[node] = SlipDirection::from_sign(-self.signs[p]),
                Role::Pinned => {}
            }
        }
        d
    }

    /// The set as `(node, sign)` in position order.
    #[cfg(test)]
    fn set(&self) -> Vec<(usize, f64)> {
        let d = self.directions();
        self.nodes
            .iter()
            .filter(|&&j| d[j].is_slipping())
            .map(|&j| (j, d[j].sign()))
            .collect()
    }
}

#[cfg(test)]
mod tests;
