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

use super::kernels::{axpys, border_pass, dot, dots, triangular, DenseLu, Factors, Kernel, Pass};
use super::operators::Operators;
use super::solver::SlipDirection;
use super::tolerances::PIVOT_TOL;

mod structured;
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
fn special_limit(k: usize) -> usize {
    (k / 16).clamp(4, MAX_SPECIAL)
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

    /// The slip rates of the set for the load direction `(ux, uy)`,
    /// `M_SS^-1 (ux b_x + uy b_y)`, from the kept solutions into `out` by
    /// node (other nodes untouched); false if not finite. Needs
    /// [`Self::set_loads`].
    pub(crate) fn rates(&self, ux: f64, uy: f64, out: &mut [f64]) -> bool {
        debug_assert!(self.loads.is_some(), "rates without loads");
        let k = self.nodes.len();
        let mut finite = true;
        let [sx, sy] = if self.special.is_empty() {
            &self.base_sol
        } else {
            &self.sol
        };
        if self.special.is_empty() {
            // No pinned node: no role to look at.
            for ((&node, &x), &y) in self.nodes.iter().zip(&sx[..k]).zip(&sy[..k]) {
                let r = ux * x + uy * y;
                finite &= r.is_finite();
                out[node] = r;
            }
            return finite;
        }
        let positions = self.nodes.iter().zip(&self.roles);
        for (((&node, &role), &x), &y) in positions.zip(&sx[..k]).zip(&sy[..k]) {
            if role != Role::Pinned {
                let r = ux * x + uy * y;
                finite &= r.is_finite();
                out[node] = r;
            }
        }
        finite
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

    /// Make the solutions those of the slip set `target`, whose slipping
    /// nodes and signs in node order are `set`; false if `M_SS` is singular
    /// to working precision (the caller then has no responses).
    ///
    /// The changes are found among the nodes noted since the last update
    /// ([`Self::note_changes`]): a few, where a pass over the base's nodes
    /// (as before) cost as much as the bordering itself at `N = 128`.
    pub(crate) fn update_to(
        &mut self,
        ops: &Operators,
        friction: f64,
        target: &[SlipDirection],
        set: &[(usize, f64)],
    ) -> bool {
        debug_assert!(
            set.iter().all(|&(j, s)| target[j].sign() == s)
                && set.len() == target.iter().filter(|d| d.is_slipping()).count()
                && set.windows(2).all(|w| w[0].0 < w[1].0),
            "set is not the slipping nodes of target in node order"
        );
        if !self.valid || self.friction != friction {
            return self.rebuild(ops, friction, target);
        }
        // Nodes that enter, and positions of A whose role changes: among
        // the nodes noted since the last update only (a node not in A that
        // was not noted still sticks), in node order and position order, as
        // a pass over all of them would find them.
        let mut dirty = std::mem::take(&mut self.dirty);
        dirty.sort_unstable();
        let mut changed = std::mem::take(&mut self.changed);
        changed.clear();
        let mut entries = 0;
        let mut special = self.special.len();
        for &j in &dirty {
            let p = self.pos[j];
            if p == NONE {
                entries += usize::from(target[j].is_slipping());
                continue;
            }
            let (old, role) = (self.roles[p], self.role_in(target, p));
            if role != old {
                special =
                    special + usize::from(role != Role::Active) - usize::from(old != Role::Active);
                changed.push((p, role));
            }
        }
        changed.sort_unstable_by_key(|&(p, _)| p);
        self.dirty = dirty;
        let changes = entries + changed.len();
        if changes == 0 {
            self.changed = changed;
            self.clear_dirty();
            return true;
        }
        // Past half the set, past a few pinned or reversed nodes, or after
        // many changes since the last factorisation, a rebuild costs about
        // as much and is cleaner.
        let k = set.len();
        if 2 * changes > k.max(8)
            || self.updates + changes > k.max(16)
            || special > special_limit(self.nodes.len() + entries)
        {
            self.changed = changed;
            return self.rebuild(ops, friction, target);
        }
        let roles_set = changed.iter().all(|&(p, role)| self.set_role(ops, p, role));
        self.changed = changed;
        if !roles_set {
            return self.rebuild(ops, friction, target);
        }
        let dirty = std::mem::take(&mut self.dirty);
        let bordered = dirty.iter().all(|&j| {
            let d = target[j];
            self.pos[j] != NONE || !d.is_slipping() || self.border(ops, j, d.sign())
        });
        self.dirty = dirty;
        self.clear_dirty();
        if !bordered || !self.correct() {
            return self.rebuild(ops, friction, target);
        }
        self.updates += changes;
        true
    }

    /// A fresh LU of `M_SS` for the set of `target`, and the solutions.
    fn rebuild(&mut self, ops: &Operators, friction: f64, target: &[SlipDirection]) -> bool {
        self.clear_dirty();
        for &node in &self.nodes {
            self.pos[node] = NONE;
        }
        self.nodes.clear();
        self.signs.clear();
        self.roles.clear();
        self.special.clear();
        for (j, d) in target.iter().enumerate() {
            if d.is_slipping() {
                self.pos[j] = self.nodes.len();
                self.nodes.push(j);
                self.signs.push(d.sign());
                self.roles.push(Role::Active);
            }
        }
        self.friction = friction;
        self.updates = 0;
        self.rebuilds += 1;
        self.structured = None;
        self.last_entry = 0;
        self.valid = false;
        let k = self.nodes.len();
        self.perm.clear();
        self.perm_inv.clear();
        if k == 0 {
            self.valid = true;
            return true;
        }
        if self.lu.len() < self.n * self.n {
            self.lu = Aligned::zeros(self.n * self.n);
            self.special_cols = vec![0.0; self.n * MAX_SPECIAL];
            self.deltas = vec![0.0; self.n * MAX_SPECIAL];
            self.factor = DenseLu::new(self.n);
        }
        self.ld = stride(k, self.n);
        let ld = self.ld;
        // Assemble M_SS column-major (k x k) and factorise it.
        for (b, &col) in self.nodes.iter().enumerate() {
            let hcol = ops.hilbert_col(col);
            let dcol = ops.abs_derivative_col(col);
            let out = &mut self.factor.lu[b * k..(b + 1) * k];
            for ((o, &row), &sign) in out.iter_mut().zip(&self.nodes).zip(&self.signs) {
                *o = -dcol[row] - friction * sign * hcol[row];
            }
        }
        self.factor.factorise(k);
        for j in 0..k {
            let d = self.factor.lu[j * k + j];
            if d == 0.0 || !d.is_finite() {
                return false;
            }
        }
        for j in 0..k {
            self.lu[j * ld..j * ld + k].copy_from_slice(&self.factor.lu[j * k..(j + 1) * k]);
        }
        // U inverted over itself (L below the diagonal is left as it is).
        self.factor
            .invert_upper(k, &mut self.lu[..(k - 1) * ld + k], ld);
        self.perm.extend_from_slice(self.factor.perm(k));
        self.perm_inv.resize(k, 0);
        for (i, &p) in self.perm.iter().enumerate() {
            self.perm_inv[p] = i;
        }
        if self.loads.is_some() {
            for d in 0..2 {
                let mut x = std::mem::take(&mut self.base_sol[d]);
                for (p, xp) in x[..k].iter_mut().enumerate() {
                    *xp = self.rhs(self.nodes[p], self.signs[p])[d];
                }
                self.solve_base(&mut x);
                let finite = x[..k].iter().all(|v| v.is_finite());
                self.base_sol[d] = x;
                if !finite {
                    return false;
                }
            }
        }
        self.valid = true;
        true
    }

    /// `x = A^-1 x` (by position of `A`), through the factors.
    fn solve_base(&mut self, x: &mut [f64]) {
        let (k, ld) = (self.nodes.len(), self.ld);
        let y = &mut self.v;
        for (yi, &p) in y[..k].iter_mut().zip(&self.perm) {
            *yi = x[p];
        }
        let f = Factors {
            lu: &self.lu,
            ld,
            k,
        };
        triangular(f, Pass::Lower { y, from: 0 });
        triangular(f, Pass::Inverse { y });
        x[..k].copy_from_slice(&y[..k]);
    }

    /// Give the factors the column stride `ld` (at most `N`), moving their
    /// columns: `O(k^2)`, once per `k / 8` entries at most.
    fn relayout(&mut self, ld: usize) {
        let (old, k) = (self.ld, self.perm.len());
        let ld = ld.min(self.n);
        if ld > old {
            for j in (1..k).rev() {
                self.lu.copy_within(j * old..j * old + k, j * ld);
            }
        } else {
            for j in 1..k {
                self.lu.copy_within(j * old..j * old + k, j * ld);
            }
        }
        self.ld = ld;
    }

    /// Give the position `p` of `A` the role `role` in the correction:
    /// its column `A^-1 e_p` when it leaves the active nodes, its row's
    /// change when it reverses.
    ///
    /// False if the dense factors, bordered up to the set first where a
    /// new column `A^-1 e_p` needs them, meet a small pivot.
    fn set_role(&mut self, ops: &Operators, p: usize, role: Role) -> bool {
        let (n, k) = (self.n, self.nodes.len());
        let old = self.roles[p];
        // A^-1 e_p: from the structured vectors if they give it, else from
        // the dense factors (bordered up to the set first).
        let leaves = old == Role::Active && role != Role::Active;
        let by_structure = leaves && self.structured_column(ops, p);
        if leaves && !by_structure && !self.catch_up(ops) {
            return false;
        }
        self.roles[p] = role;
        if role == Role::Active {
            // Out of the correction: the last slot moves into its slot.
            let t = self.special.iter().position(|&q| q == p).expect("slot");
            let last = self.special.len() - 1;
            if t != last {
                self.special_cols.copy_within(last * n..last * n + k, t * n);
                self.deltas.copy_within(last * n..last * n + k, t * n);
            }
            self.special.swap_remove(t);
            return true;
        }
        let t = if old == Role::Active {
            // A^-1 e_p: row perm_inv[p] of the factors' right-hand side.
            let t = self.special.len();
            self.special.push(p);
            if by_structure {
                let st = self.structured.as_ref().expect("structured");
                self.special_cols[t * n..t * n + k].copy_from_slice(&st.column()[..k]);
                return self.set_delta(ops, p, t, role);
            }
            let from = self.perm_inv[p];
            let ld = self.ld;
            let y = &mut self.special_cols[t * n..t * n + k];
            y.fill(0.0);
            y[from] = 1.0;
            let f = Factors {
                lu: &self.lu,
                ld,
                k,
            };
            triangular(f, Pass::Lower { y, from });
            triangular(f, Pass::Inverse { y });
            t
        } else {
            self.special.iter().position(|&q| q == p).expect("slot")
        };
        self.set_delta(ops, p, t, role)
    }

    /// The change of the row of position `p` (slot `t`) if it reverses.
    fn set_delta(&mut self, ops: &Operators, p: usize, t: usize, role: Role) -> bool {
        let (n, k) = (self.n, self.nodes.len());
        if role == Role::Reversed {
            // Row p gains 2 f s H[node, S] (H[node, c] = -H[c, node]).
            let f2 = -2.0 * self.friction * self.signs[p];
            let hcol = ops.hilbert_col(self.nodes[p]);
            let delta = &mut self.deltas[t * n..t * n + k];
            for (d, &node) in delta.iter_mut().zip(&self.nodes) {
                *d = f2 * hcol[node];
            }
        }
        true
    }

    /// Node `a` enters with sign `sign`: `A` is bordered by its column and
    /// row, and the kept solutions and correction columns follow; false if
    /// the Schur complement is too small (the caller refactorises).
    ///
    /// Next to an arc of a base of a few arcs, by the arcs' structure
    /// ([`structured`]); else through the dense factors (bordered up to
    /// the set first if structured borderings left them behind), after
    /// which a large base of a few arcs takes up the structured ones.
    fn border(&mut self, ops: &Operators, a: usize, sign: f64) -> bool {
        if self.structured.is_some() {
            match self.border_structured(ops, a, sign) {
                Bordered::Done => return true,
                Bordered::Singular => return false,
                Bordered::NotHere => {
                    if !self.catch_up(ops) {
                        return false;
                    }
                }
            }
        }
        // Kept if the node starts an arc of its own.
        let kept = self.structured.take();
        let k = self.nodes.len();
        let Some(sigma) = self.extend_factors(ops, k, a, sign) else {
            return false;
        };
        self.follow_border(ops, a, sign, sigma);
        self.push(a, sign);
        if let Some(st) = kept {
            self.structured = st.add_arc(self, ops, a, sign, sigma);
            return true;
        }
        if k + 1 >= structured::MIN_NODES && self.last_entry + structured::MIN_NODES / 4 <= k {
            self.last_entry = k;
            self.structured = Structured::enter(self, ops);
        }
        true
    }

    /// Append node `a` with sign `sign` to the base, active.
    fn push(&mut self, a: usize, sign: f64) {
        self.pos[a] = self.nodes.len();
        self.nodes.push(a);
        self.signs.push(sign);
        self.roles.push(Role::Active);
    }

    /// Border the dense factors of positions `0..p` with node `a` of sign
    /// `sign` as position `p` (its column and row over them): `l`, `u` and
    /// `v = A^-1 c` from one pass ([`border_pass`]), `v` and the row left
    /// in `self.v` and `self.row`; the Schur complement, or `None` if it is
    /// too small.
    fn extend_factors(&mut self, ops: &Operators, p: usize, a: usize, sign: f64) -> Option<f64> {
        debug_assert_eq!(self.perm.len(), p, "factors up to p");
        let (nodes, signs) = (&self.nodes[..p], &self.signs[..p]);
        let f = self.friction;
        let hcol = ops.hilbert_col(a);
        let dcol = ops.abs_derivative_col(a);
        let (col, row) = (&mut self.col[..p], &mut self.row[..p]);
        for ((c, r), (&node, &s)) in col.iter_mut().zip(row).zip(nodes.iter().zip(signs)) {
            *c = -dcol[node] - f * s * hcol[node];
            *r = -dcol[node] + f * sign * hcol[node];
        }
        let d0 = Self::entry(ops, f, a, sign, a);
        // u = L^-1 P c, l = U^-T r and v = U^-1 u = A^-1 c.
        let col = &self.col[..p];
        for (ui, &q) in self.u[..p].iter_mut().zip(&self.perm) {
            *ui = col[q];
        }
        let factors = Factors {
            lu: &self.lu,
            ld: self.ld,
            k: p,
        };
        border_pass(factors, &mut self.u, &self.row, &mut self.l, &mut self.v);
        let lu_dot = dot(&self.l[..p], &self.u[..p]);
        let sigma = d0 - lu_dot;
        let scale = d0.abs().max(lu_dot.abs());
        if !sigma.is_finite() || sigma.abs() <= PIVOT_TOL * scale {
            return None;
        }
        if p == self.ld {
            self.relayout(stride(p, self.n));
        }
        // The bordered factors: row l of L, and U's new column (u, sigma)
        // inverted, the column (-v / sigma, 1 / sigma) of W.
        let ld = self.ld;
        let lu = &mut self.lu[..];
        for (j, &lj) in self.l[..p].iter().enumerate() {
            lu[j * ld + p] = lj;
        }
        for (o, &vi) in lu[p * ld..p * ld + p].iter_mut().zip(&self.v[..p]) {
            *o = -vi / sigma;
        }
        lu[p * ld + p] = 1.0 / sigma;
        self.perm.push(p);
        self.perm_inv.push(p);
        Some(sigma)
    }

    /// Border the dense factors up to the set, where structured borderings
    /// left them behind; false at a small pivot. The kept solutions (and
    /// the structured vectors, which stay valid: the base is the same)
    /// have followed already.
    fn catch_up(&mut self, ops: &Operators) -> bool {
        let k = self.nodes.len();
        if self.perm.len() == k {
            return true;
        }
        if self.ld < k {
            self.relayout(stride(k, self.n));
        }
        (self.perm.len()..k).all(|p| {
            let (a, sign) = (self.nodes[p], self.signs[p]);
            self.extend_factors(ops, p, a, sign).is_some()
        })
    }

    /// The kept solutions and correction columns follow the bordering of
    /// the base (of `k` positions) by node `a` with sign `sign`, given
    /// `v = A^-1 M_Sa` in `self.v`, the row `M_aS` in `self.row` and the
    /// Schur complement `sigma`.
    fn follow_border(&mut self, ops: &Operators, a: usize, sign: f64, sigma: f64) {
        let (k, f, n, arch) = (self.nodes.len(), self.friction, self.n, self.arch);
        let hcol = ops.hilbert_col(a);
        let v = &self.v[..k];
        let row = &self.row[..k];
        // r . w for the correction's columns w and r . x for the kept
        // solutions x: four a pass over the row ([`dots`]) past
        // `MIN_NODES`; below it, one at a time in the plain loops, whose
        // numbers the runs at the defaults (`N = 128`) keep, as they keep
        // the dense borderings (the Fig. 3 map's bytes moved with the
        // lanes).
        let wide = k >= structured::MIN_NODES;
        let m = self.special.len();
        let solved = if self.loads.is_some() { 2 } else { 0 };
        let mut d = [0.0; MAX_SPECIAL + 2];
        {
            let mut vecs: [&[f64]; MAX_SPECIAL + 2] = [&[]; MAX_SPECIAL + 2];
            for (t, w) in vecs.iter_mut().enumerate().take(m) {
                *w = &self.special_cols[t * n..t * n + k];
            }
            for (x, sol) in vecs[m..m + solved].iter_mut().zip(&self.base_sol) {
                *x = &sol[..k];
            }
            if wide {
                dots(arch, &vecs[..m + solved], row, &mut d[..m + solved]);
            } else {
                for (d, x) in d.iter_mut().zip(&vecs[..m + solved]) {
                    *d = dot(row, x);
                }
            }
        }
        // The correction's columns: A_new^-1 e_q = (w + v (r.w) / sigma,
        // -(r.w) / sigma) for w = A^-1 e_q, and the reversed rows' changes
        // gain column a.
        for (t, &q) in self.special.iter().enumerate() {
            let w = &mut self.special_cols[t * n..t * n + k + 1];
            let c = d[t] / sigma;
            if wide {
                arch.dispatch(Kernel::Axpy {
                    y: &mut w[..k],
                    x: v,
                    a: -c,
                });
            } else {
                for (wi, &vi) in w[..k].iter_mut().zip(v) {
                    *wi += c * vi;
                }
            }
            w[k] = -c;
            if self.roles[q] == Role::Reversed {
                self.deltas[t * n + k] = 2.0 * f * self.signs[q] * hcol[self.nodes[q]];
            }
        }
        if self.loads.is_some() {
            // The bordered system's solution: the new entry
            // xi = (beta - r^T x) / sigma, and x - xi v on the old set.
            let betas = self.rhs(a, sign);
            for ((sol, beta), &rx) in self.base_sol.iter_mut().zip(betas).zip(&d[m..]) {
                let xi = (beta - rx) / sigma;
                if wide {
                    arch.dispatch(Kernel::Axpy {
                        y: &mut sol[..k],
                        x: v,
                        a: xi,
                    });
                } else {
                    for (x, &vi) in sol[..k].iter_mut().zip(v) {
                        *x -= xi * vi;
                    }
                }
                sol[k] = xi;
            }
        }
    }

    /// Factorise the capacitance system of the correction and apply it to
    /// the kept solutions; false if it is singular to working precision.
    fn correct(&mut self) -> bool {
        // Without loads there are no kept solutions to correct.
        if self.special.is_empty() || self.loads.is_none() {
            return true;
        }
        if !self.factor_capacitance() {
            return false;
        }
        let k = self.nodes.len();
        for d in 0..2 {
            let mut out = std::mem::take(&mut self.sol[d]);
            let base = std::mem::take(&mut self.base_sol[d]);
            // The change of the reversed rows' right-hand sides.
            for (t, &q) in self.special.iter().enumerate() {
                let (node, s) = (self.nodes[q], self.signs[q]);
                self.coef[t] = self.rhs(node, -s)[d] - self.rhs(node, s)[d];
            }
            let ok = self.apply_correction(&base[..k], &mut out[..k]);
            self.sol[d] = out;
            self.base_sol[d] = base;
            if !ok {
                return false;
            }
        }
        true
    }

    /// The capacitance system of the pinned and reversed positions `q`
    /// (slots `t`), for the unknowns `z_t` of `x = x_A + sum_t z_t A^-1 e_q`:
    /// a reversed row `t` says `z_t = beta_t - delta_t . x`, a pinned row
    /// says `x_q = 0`.
    fn factor_capacitance(&mut self) -> bool {
        let (n, k, m) = (self.n, self.nodes.len(), self.special.len());
        let mut scale = 0.0f64;
        for b in 0..m {
            let w = &self.special_cols[b * n..b * n + k];
            for (a, &q) in self.special.iter().enumerate() {
                let c = if self.roles[q] == Role::Reversed {
                    let delta = &self.deltas[a * n..a * n + k];
                    f64::from(u8::from(a == b)) + dot(delta, w)
                } else {
                    w[q]
                };
                scale = scale.max(c.abs());
                self.capacitance.lu[b * m + a] = c;
            }
        }
        self.capacitance.factorise(m);
        (0..m).all(|i| {
            let d = self.capacitance.lu[i * m + i];
            d.is_finite() && d.abs() > PIVOT_TOL * scale
        })
    }

    /// `out = x_A + sum_t z_t A^-1 e_q` for the base solution `base`
    /// (`x_A`) and the reversed rows' right-hand side changes in `coef`,
    /// with the capacitance system factorised; 0 at pinned positions.
    fn apply_correction(&mut self, base: &[f64], out: &mut [f64]) -> bool {
        let (n, k, m) = (self.n, self.nodes.len(), self.special.len());
        let mut z = std::mem::take(&mut self.coef);
        for (t, &q) in self.special.iter().enumerate() {
            z[t] = if self.roles[q] == Role::Reversed {
                z[t] - dot(&self.deltas[t * n..t * n + k], base)
            } else {
                -base[q]
            };
        }
        self.capacitance.solve(&mut z[..m]);
        out.copy_from_slice(base);
        if k >= structured::MIN_NODES {
            // Four columns a pass over `out` in the lanes of [`Kernel`]
            // (below `MIN_NODES` the plain loops' numbers, as in
            // [`Self::follow_border`]).
            let mut cols: [&[f64]; MAX_SPECIAL] = [&[]; MAX_SPECIAL];
            let mut c = [0.0; MAX_SPECIAL];
            for (t, (w, c)) in cols.iter_mut().zip(&mut c).enumerate().take(m) {
                *w = &self.special_cols[t * n..t * n + k];
                *c = -z[t];
            }
            axpys(self.arch, out, &cols[..m], &c[..m]);
        } else {
            for (t, &zt) in z[..m].iter().enumerate() {
                let w = &self.special_cols[t * n..t * n + k];
                for (x, &wi) in out.iter_mut().zip(w) {
                    *x += zt * wi;
                }
            }
        }
        self.coef = z;
        for &q in &self.special {
            if self.roles[q] == Role::Pinned {
                out[q] = 0.0;
            }
        }
        // Every entry tested (no early exit), so the test vectorises.
        out.iter().fold(true, |ok, x| ok & x.is_finite())
    }

    /// `x = M_SS^-1 b` with `b` given per node by `rhs(node, sign)`; the
    /// result goes to `out` by node (other nodes untouched).
    #[cfg(test)]
    pub(crate) fn solve(&mut self, rhs: impl Fn(usize, f64) -> f64, out: &mut [f64]) -> bool {
        let k = self.nodes.len();
        let mut x = vec![0.0; self.n];
        for (p, xp) in x[..k].iter_mut().enumerate() {
            *xp = rhs(self.nodes[p], self.signs[p]);
        }
        if k > 0 {
            self.solve_base(&mut x);
        }
        let mut sol = x.clone();
        if !self.special.is_empty() {
            for (t, &q) in self.special.iter().enumerate() {
                let (node, s) = (self.nodes[q], self.signs[q]);
                self.coef[t] = rhs(node, -s) - rhs(node, s);
            }
            assert!(self.factor_capacitance());
            if !self.apply_correction(&x[..k], &mut sol[..k]) {
                return false;
            }
        }
        let mut finite = true;
        for p in 0..k {
            if self.roles[p] != Role::Pinned {
                finite &= sol[p].is_finite();
                out[self.nodes[p]] = sol[p];
            }
        }
        finite
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
