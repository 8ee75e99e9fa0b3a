//! Borderings in `O(k)` while the base set is a few arcs of one sign each.
//!
//! `M = -|D| - f diag(s) H` has circulant `|D|` and `H`: an entry depends
//! on the two nodes' distance round the circle and on the row's sign only.
//! So a base set made of `m` arcs (runs of neighbouring nodes), each with
//! one slip sign, has the same matrix as the set shifted round by one node
//! with its signs. That is the structure Levinson's recursion uses for one
//! Toeplitz block, here for `m` of them. When node `a` enters just past an
//! edge of an arc, with the arc's sign, the bordering ([`super`]) needs
//! `v = A^-1 c` for its column `c = M_Sa`, and nothing else: the pivot is
//! `sigma = M_aa - r . v` and every kept solution `y = A^-1 z` moves to
//! `(y - xi v, xi)`, `xi = (z_a - r . y) / sigma`, with the row `r = M_aS`
//! read off the operators. Two sets of vectors are kept, by position of `A`:
//!
//! * for each arc and side, the solution for the column of the node just
//!   outside that edge, `A^-1 M_Sg` (*neighbour solutions*): when that node
//!   enters, its `v` is there already;
//! * for each arc and side, the column of the inverse at the edge node,
//!   `A^-1 e_edge` (*edge columns*).
//!
//! Every one of them follows a bordering in `O(k)` as above, except the
//! neighbour solution of the edge that moved: the new neighbour `a + d`
//! (`d = +1` past an end, `-1` before a start) is a node nobody has solved
//! for. The set `S' = S + a` shifted back by `d`, `T = S' - d`, has the same
//! matrix as `S'`, and the column of `a + d` on `S'` is the column of `a` on
//! `T`. `T` is `S` with the node just outside the *other* edge of every arc
//! added (whose solutions are neighbour solutions) and the far edge node of
//! every other arc removed (whose inverse columns are edge columns). So
//!
//! ```text
//! y = v + sum_q mu_q A^-1 e_q - sum_j eta_j A^-1 M_Sg_j
//! ```
//!
//! with the `m` added nodes' equations (their rows `M_gS`, read off the
//! operators) and `y_q = 0` at the `m - 1` removed nodes (their equations
//! released by the multipliers `mu`) is a system of `2 m - 1` unknowns;
//! `y` and `eta`, shifted forward by `d`, are the new neighbour solution.
//! A bordering then costs about `(6 m + 4) k` multiply-adds where a pass
//! over the dense factors costs `1.5 k^2` (and streams them from memory):
//! at `N = 1024`, where a slip zone grows from about 290 to 730 nodes over
//! three arcs, 30 to 70 times fewer.
//!
//! The dense factors stop at the position where the structured borderings
//! began. Anything that needs them (a node of the base that sticks or
//! reverses, a node entering anywhere else) first borders them up to the
//! set ([`SetInverse::catch_up`]), as the borderings would have; a rebuild
//! (the slip zone collapsing at a reversal of the load) drops them.

use super::{SetInverse, NONE};
use crate::contact::kernels::DenseLu;
use crate::contact::kernels::{axpys, dot, dots, Kernel};
use crate::contact::operators::Operators;
use crate::contact::tolerances::PIVOT_TOL;

/// The most arcs for which the vectors are kept: `4 m` of them, and a
/// system of `2 m - 1`.
const MAX_ARCS: usize = 4;

/// The farthest from an arc's edge that a node entering on its own has
/// its column made by shifts (one `O(m k)` shift a node).
const MAX_WALK: usize = 32;

/// The largest shift system: `m` added and `m` removed nodes.
const MAX_DIM: usize = 2 * MAX_ARCS;

/// The smallest base for which structured borderings are taken up: below
/// it a pass over the dense factors (in the cache there) costs less than
/// the `4 m` solves that set the vectors up, and the runs at the defaults
/// (`N = 128`) keep the dense borderings' numbers.
pub(super) const MIN_NODES: usize = 192;

/// The node next to `node` (`< n`) on side `side` (0: before it, 1:
/// after it). Compared, not taken modulo `n`: a division a node was a
/// third of the shift's gather ([`SetInverse::shift_column`]).
#[inline]
fn step(node: usize, side: usize, n: usize) -> usize {
    if side == 1 {
        if node + 1 == n {
            0
        } else {
            node + 1
        }
    } else if node == 0 {
        n - 1
    } else {
        node - 1
    }
}

/// An arc of the base set: its first and last node (`edge[0]`,
/// `edge[1]`, round the circle) and the slip sign of all its nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Arc {
    edge: [usize; 2],
    sign: f64,
}

/// The vectors kept for structured borderings (see the module's
/// documentation), each of `n` entries by position of `A`, slot
/// `2 j + side` for arc `j`, with room for [`MAX_ARCS`] arcs (an arc
/// added allocates nothing).
pub(super) struct Structured {
    arcs: Vec<Arc>,
    neighbour: Vec<f64>,
    pub(super) edge: Vec<f64>,
    /// The system for the new neighbour solution.
    small: DenseLu,
    /// The added nodes' rows `M_gS` of a shift, `m` of `n` entries.
    rows: Vec<f64>,
    /// The solution on the shifted set, and the new neighbour solution.
    y: Vec<f64>,
    fresh: Vec<f64>,
    /// A known column of the inverse, shifted by [`SetInverse::shift_column`].
    w: Vec<f64>,
    /// Two solutions of a walk of shifts ([`SetInverse::border_isolated`]).
    walk: [Vec<f64>; 2],
    /// The instruction set the products run in, found once.
    arch: pulp::Arch,
}

impl Structured {
    /// The arcs of the base of `inv`, if there are at most [`MAX_ARCS`], a
    /// node outside the set, and no two arcs of opposite signs side by
    /// side (a shift by one would move one into the other).
    fn arcs(inv: &SetInverse) -> Option<Vec<Arc>> {
        let n = inv.n;
        let sign_at = |j: usize| {
            let p = inv.pos[j];
            (p != NONE).then(|| inv.signs[p])
        };
        // Start the scan just after a node outside the set.
        let out = (0..n).find(|&j| inv.pos[j] == NONE)?;
        let mut arcs: Vec<Arc> = Vec::new();
        let mut prev: Option<f64> = None;
        for t in 1..=n {
            let j = (out + t) % n;
            let s = sign_at(j);
            match (prev, s) {
                (Some(ps), Some(s)) if ps == s => arcs.last_mut().expect("open arc").edge[1] = j,
                (Some(_), Some(_)) => return None, // two signs side by side
                (None, Some(s)) => {
                    if arcs.len() == MAX_ARCS {
                        return None;
                    }
                    arcs.push(Arc {
                        edge: [j, j],
                        sign: s,
                    });
                }
                _ => {}
            }
            prev = s;
        }
        (!arcs.is_empty()).then_some(arcs)
    }

    /// The vectors for the base of `inv`, from its dense factors (which
    /// must cover the set), if the base is made of a few arcs.
    pub(super) fn enter(inv: &mut SetInverse, ops: &Operators) -> Option<Box<Self>> {
        let arcs = Self::arcs(inv)?;
        let (n, k) = (inv.n, inv.nodes.len());
        debug_assert_eq!(inv.perm.len(), k, "the factors cover the set");
        let mut neighbour = vec![0.0; 2 * MAX_ARCS * n];
        let mut edge = vec![0.0; 2 * MAX_ARCS * n];
        let mut x = vec![0.0; n];
        for (j, arc) in arcs.iter().enumerate() {
            for side in 0..2 {
                let slot = (2 * j + side) * n;
                inv.column(ops, step(arc.edge[side], side, n), &mut x[..k]);
                inv.solve_base(&mut x);
                neighbour[slot..slot + k].copy_from_slice(&x[..k]);
                x[..k].fill(0.0);
                x[inv.pos[arc.edge[side]]] = 1.0;
                inv.solve_base(&mut x);
                edge[slot..slot + k].copy_from_slice(&x[..k]);
            }
        }
        let finite = neighbour.iter().chain(&edge).all(|v| v.is_finite());
        finite.then(|| {
            Box::new(Self {
                arcs,
                neighbour,
                edge,
                small: DenseLu::new(MAX_DIM),
                rows: vec![0.0; MAX_ARCS * n],
                y: vec![0.0; n],
                fresh: vec![0.0; n],
                w: vec![0.0; n],
                walk: [vec![0.0; n], vec![0.0; n]],
                arch: pulp::Arch::new(),
            })
        })
    }
}

impl Structured {
    /// Node `a`, just bordered through the dense factors (`v` and the row
    /// left in `inv.v` and `inv.row`, the Schur complement `sigma`) and
    /// pushed, starts an arc of its own: the vectors follow, and the new
    /// arc's come from two solves. `None` (the vectors dropped) if `a` has
    /// a neighbour in the set (of the other sign: one of its sign would
    /// have had it bordered by the arcs) or the arcs are too many.
    pub(super) fn add_arc(
        mut self: Box<Self>,
        inv: &mut SetInverse,
        ops: &Operators,
        a: usize,
        sign: f64,
        sigma: f64,
    ) -> Option<Box<Self>> {
        let (n, k1, m, f) = (inv.n, inv.nodes.len(), self.arcs.len(), inv.friction);
        let k = k1 - 1;
        if m == MAX_ARCS || (0..2).any(|side| inv.pos[step(a, side, n)] != NONE) {
            return None;
        }
        let slot = |j: usize, side: usize| (2 * j + side) * n;
        let (v, row) = (&inv.v[..k], &inv.row[..k]);
        self.follow_all(ops, f, a, sign, row, v, sigma, &[]);
        self.arcs.push(Arc { edge: [a, a], sign });
        for side in 0..2 {
            let e = &mut self.edge[slot(m, side)..slot(m, side) + k1];
            e[..k].iter_mut().zip(v).for_each(|(e, &v)| *e = -v / sigma);
            e[k] = 1.0 / sigma;
        }
        // (`solve_base` works in `inv.v`.)
        let mut x = std::mem::take(&mut self.y);
        for side in 0..2 {
            inv.column(ops, step(a, side, n), &mut x[..k1]);
            inv.solve_base(&mut x);
            self.neighbour[slot(m, side)..slot(m, side) + k1].copy_from_slice(&x[..k1]);
        }
        self.y = x;
        self.neighbour[slot(m, 0)..slot(m + 1, 0)]
            .iter()
            .all(|v| v.is_finite())
            .then_some(self)
    }

    /// Where `A^-1 e_p` starts in [`Self::edge`] if node `node` is an edge
    /// of an arc.
    fn edge_column(&self, node: usize, n: usize) -> Option<usize> {
        self.arcs.iter().enumerate().find_map(|(j, arc)| {
            (0..2)
                .find(|&side| arc.edge[side] == node)
                .map(|side| (2 * j + side) * n)
        })
    }

    /// The nodes just outside the edges on side `side`, by arc.
    fn outside(&self, side: usize, n: usize) -> [usize; MAX_ARCS] {
        let mut out = [0; MAX_ARCS];
        for (o, arc) in out.iter_mut().zip(&self.arcs) {
            *o = step(arc.edge[side], side, n);
        }
        out
    }

    /// The column of the inverse left by
    /// [`SetInverse::structured_column`].
    pub(super) fn column(&self) -> &[f64] {
        &self.fresh
    }
}

/// `w` (`k + 1` entries, a kept solution `A^-1 z` in its first `k`)
/// follows the bordering by a node of row `row`, `v = A^-1 M_Sa` and Schur
/// complement `sigma`, `z_a` the new entry of its right-hand side:
/// `(w - xi v, xi)` with `xi = (z_a - r . w) / sigma`.
fn follow(w: &mut [f64], row: &[f64], v: &[f64], sigma: f64, za: f64) {
    let k = v.len();
    let xi = (za - dot(row, &w[..k])) / sigma;
    w[..k].iter_mut().zip(v).for_each(|(w, &v)| *w -= xi * v);
    w[k] = xi;
}

impl Structured {
    /// Every kept vector but those of the slots `skip` (arc, side) follows
    /// the bordering by node `a` with sign `sign` ([`follow`]).
    #[allow(clippy::too_many_arguments)]
    fn follow_all(
        &mut self,
        ops: &Operators,
        friction: f64,
        a: usize,
        sign: f64,
        row: &[f64],
        v: &[f64],
        sigma: f64,
        skip: &[(usize, usize)],
    ) {
        let (n, k) = (ops.nodes(), v.len());
        // The vectors that follow, neighbour solution and edge column of
        // each slot in turn, and the new entries of their right-hand sides.
        let mut at = [0usize; 2 * MAX_ARCS];
        let mut za = [0.0; 4 * MAX_ARCS];
        let mut c = 0;
        for j in 0..self.arcs.len() {
            for side in (0..2).filter(|&side| !skip.contains(&(j, side))) {
                at[c] = (2 * j + side) * n;
                let g = step(self.arcs[j].edge[side], side, n);
                za[2 * c] = SetInverse::entry(ops, friction, a, sign, g);
                c += 1;
            }
        }
        // xi = (z_a - r . w) / sigma for each ([`follow`]), then w - xi v.
        let mut xi = [0.0; 4 * MAX_ARCS];
        {
            let mut vecs: [&[f64]; 4 * MAX_ARCS] = [&[]; 4 * MAX_ARCS];
            for (t, &at) in at[..c].iter().enumerate() {
                vecs[2 * t] = &self.neighbour[at..at + k];
                vecs[2 * t + 1] = &self.edge[at..at + k];
            }
            dots(self.arch, &vecs[..2 * c], row, &mut xi[..2 * c]);
        }
        for (x, &z) in xi[..2 * c].iter_mut().zip(&za) {
            *x = (z - *x) / sigma;
        }
        for (t, &at) in at[..c].iter().enumerate() {
            for (kept, x) in [
                (&mut self.neighbour, xi[2 * t]),
                (&mut self.edge, xi[2 * t + 1]),
            ] {
                let w = &mut kept[at..=at + k];
                self.arch.dispatch(Kernel::Axpy {
                    y: &mut w[..k],
                    x: v,
                    a: x,
                });
                w[k] = x;
            }
        }
    }
}

/// What a structured bordering came to.
pub(super) enum Bordered {
    /// Done: the set has the node, the vectors follow.
    Done,
    /// The Schur complement is too small: refactorise.
    Singular,
    /// Not a node next to an arc with its sign, or a shift system that is
    /// near singular: border the dense factors instead.
    NotHere,
}

impl SetInverse {
    /// `out[p] = M[node_p, col]` over the base's positions (`out` has
    /// `k` entries): the column of node `col`.
    pub(super) fn column(&self, ops: &Operators, col: usize, out: &mut [f64]) {
        let (hcol, dcol, f) = (
            ops.hilbert_col(col),
            ops.abs_derivative_col(col),
            self.friction,
        );
        for ((o, &node), &s) in out.iter_mut().zip(&self.nodes).zip(&self.signs) {
            *o = -dcol[node] - f * s * hcol[node];
        }
    }

    /// `out[p] = M[row, node_p]` for a row with slip sign `sign` (`H` is
    /// odd and `|D|` even, so it is read from column `row`).
    pub(super) fn row_of(&self, ops: &Operators, row: usize, sign: f64, out: &mut [f64]) {
        let (hcol, dcol, f) = (
            ops.hilbert_col(row),
            ops.abs_derivative_col(row),
            self.friction,
        );
        for (o, &node) in out.iter_mut().zip(&self.nodes) {
            *o = -dcol[node] + f * sign * hcol[node];
        }
    }

    /// Node `a` enters with sign `sign`, by the structure of the arcs (see
    /// the module's documentation).
    pub(super) fn border_structured(&mut self, ops: &Operators, a: usize, sign: f64) -> Bordered {
        let Some(mut st) = self.structured.take() else {
            return Bordered::NotHere;
        };
        let out = self.border_arcs(ops, &mut st, a, sign);
        if !matches!(out, Bordered::Singular) {
            self.structured = Some(st);
        }
        out
    }

    fn border_arcs(
        &mut self,
        ops: &Operators,
        st: &mut Structured,
        a: usize,
        sign: f64,
    ) -> Bordered {
        let (n, k, f) = (self.n, self.nodes.len(), self.friction);
        let found = st.arcs.iter().enumerate().find_map(|(j, arc)| {
            (0..2)
                .find(|&side| arc.sign == sign && step(arc.edge[side], side, n) == a)
                .map(|side| (j, side))
        });
        let Some((i, s)) = found else {
            return self.border_isolated(ops, st, a, sign);
        };
        let beyond = step(a, s, n);
        if self.pos[beyond] != NONE {
            return self.merge_arcs(ops, st, i, s, a, sign);
        }
        // v = A^-1 M_Sa is kept; the row r = M_aS and the pivot.
        let slot = |j: usize, side: usize| (2 * j + side) * n;
        let Some(sigma) = self.schur(ops, a, sign, &st.neighbour[slot(i, s)..slot(i, s) + k])
        else {
            return Bordered::Singular;
        };
        // The new neighbour solution, from the set S + a shifted back.
        if !self.shift_column(ops, st, s, &self.v[..k], Some(a), Some(i)) {
            return Bordered::NotHere;
        }
        let (row, v) = (&self.row[..k], &self.v[..k]);
        st.follow_all(ops, f, a, sign, row, v, sigma, &[(i, s)]);
        let e = &mut st.edge[slot(i, s)..slot(i, s) + k + 1];
        e[..k].iter_mut().zip(v).for_each(|(e, &v)| *e = -v / sigma);
        e[k] = 1.0 / sigma;
        st.neighbour[slot(i, s)..slot(i, s) + k + 1].copy_from_slice(&st.fresh[..=k]);
        st.arcs[i].edge[s] = a;
        self.follow_border(ops, a, sign, sigma);
        self.push(a, sign);
        Bordered::Done
    }

    /// `A^-1 e_p` for position `p` of the base into the structured
    /// vectors' [`Structured::column`], if they are kept and give it: an
    /// edge's column is kept; a node next to one whose column is known (an
    /// edge, or a pinned or reversed node of the correction) has it from
    /// that one by a shift of the set, as a new neighbour solution is made
    /// (see the module's documentation). A slip zone whose edge sticks one
    /// node after another, inwards, so needs no dense factors.
    pub(super) fn structured_column(&mut self, ops: &Operators, p: usize) -> bool {
        let Some(mut st) = self.structured.take() else {
            return false;
        };
        let ok = self.column_by_shift(ops, &mut st, p);
        self.structured = Some(st);
        ok
    }

    fn column_by_shift(&self, ops: &Operators, st: &mut Structured, p: usize) -> bool {
        let (n, k) = (self.n, self.nodes.len());
        let node = self.nodes[p];
        if let Some(w) = st.edge_column(node, n) {
            st.fresh[..k].copy_from_slice(&st.edge[w..w + k]);
            return true;
        }
        // A neighbour q in the same arc whose column is known (kept for an
        // edge, or in the correction): the set shifted by d = node - q
        // maps q to node. s = 1: q = node - 1 and the shift is +1 (T = S - 1
        // gains the nodes before the starts and loses the ends); s = 0 the
        // other way.
        let mut w = std::mem::take(&mut st.w);
        let side = (0..2).rev().find(|&s| {
            let q = step(node, 1 - s, n);
            let pq = self.pos[q];
            if pq == NONE || self.signs[pq] != self.signs[p] {
                return false;
            }
            let col = match st.edge_column(q, n) {
                Some(at) => &st.edge[at..at + k],
                None => match self.special.iter().position(|&x| x == pq) {
                    Some(t) => &self.special_cols[t * n..t * n + k],
                    None => return false,
                },
            };
            w[..k].copy_from_slice(col);
            true
        });
        let ok = side.is_some_and(|s| self.shift_column(ops, st, s, &w[..k], None, None));
        st.w = w;
        ok
    }

    /// The set shifted by one node (`d = +1` for `s = 1`, else `-1`):
    /// from `w = A^-1 z` for `z = e_q` (`col` `None`) or for the column of
    /// a node `c` outside the set (`col` `Some(c)`, `c` not just outside an
    /// edge on side `1 - s`), the same for `e_(q + d)` or the column of
    /// `c + d`, into [`Structured::fresh`]; false if the shift system is
    /// near singular.
    ///
    /// The shifted set `T = S - d` is `S` with the node just outside each
    /// arc's edge on side `1 - s` added and each arc's edge on side `s`
    /// removed. With `grown` `Some(i)`, `c` has just grown arc `i` on side
    /// `s` (`c = edge + d`): the set `S + c` shifted back keeps arc `i`'s
    /// edge, and the result has `k + 1` entries, the last for `c`.
    fn shift_column(
        &self,
        ops: &Operators,
        st: &mut Structured,
        s: usize,
        w: &[f64],
        col: Option<usize>,
        grown: Option<usize>,
    ) -> bool {
        let (n, k, m, f) = (self.n, self.nodes.len(), st.arcs.len(), self.friction);
        let o = 1 - s;
        let slot = |j: usize, side: usize| (2 * j + side) * n;
        let entry = |row: usize, rs: f64, col: usize| SetInverse::entry(ops, f, row, rs, col);
        let added = st.outside(o, n);
        let added = &added[..m];
        let mut removed = [0usize; MAX_ARCS];
        let mut r = 0;
        for j in (0..m).filter(|&j| Some(j) != grown) {
            removed[r] = j;
            r += 1;
        }
        let removed = &removed[..r];
        // Unknowns: eta_j for the added nodes, then mu_t for the removed.
        let dim = m + r;
        let mut rows = std::mem::take(&mut st.rows);
        for (j, &g) in added.iter().enumerate() {
            self.row_of(ops, g, st.arcs[j].sign, &mut rows[j * n..j * n + k]);
        }
        let mut rhs = [0.0; MAX_DIM];
        let mut scale = 0.0f64;
        {
            let lu = &mut st.small.lu;
            let mut put = |r: usize, c: usize, x: f64| {
                scale = scale.max(x.abs());
                lu[c * dim + r] = x;
            };
            // The added rows' products with the added nodes' solutions,
            // the removed nodes' columns and w, `dim + 1` a pass over a row.
            let mut vecs: [&[f64]; MAX_DIM + 1] = [&[]; MAX_DIM + 1];
            for (l, b) in vecs.iter_mut().enumerate().take(m) {
                *b = &st.neighbour[slot(l, o)..slot(l, o) + k];
            }
            for (t, &q) in removed.iter().enumerate() {
                vecs[m + t] = &st.edge[slot(q, s)..slot(q, s) + k];
            }
            vecs[dim] = w;
            let mut d = [0.0; MAX_DIM + 1];
            for (j, &g) in added.iter().enumerate() {
                let rj = &rows[j * n..j * n + k];
                dots(st.arch, &vecs[..=dim], rj, &mut d[..=dim]);
                let sj = st.arcs[j].sign;
                for (l, &gl) in added.iter().enumerate() {
                    put(j, l, entry(g, sj, gl) - d[l]);
                }
                for t in 0..r {
                    put(j, m + t, d[m + t]);
                }
                rhs[j] = col.map_or(0.0, |c| entry(g, sj, c)) - d[dim];
            }
            for (t, &q) in removed.iter().enumerate() {
                let pt = self.pos[st.arcs[q].edge[s]];
                for l in 0..m {
                    put(m + t, l, -st.neighbour[slot(l, o) + pt]);
                }
                for (t2, &q2) in removed.iter().enumerate() {
                    put(m + t, m + t2, st.edge[slot(q2, s) + pt]);
                }
                rhs[m + t] = -w[pt];
            }
        }
        st.rows = rows;
        st.small.factorise(dim);
        let ok = (0..dim).all(|d| {
            let p = st.small.lu[d * dim + d];
            p.is_finite() && p.abs() > PIVOT_TOL * scale
        });
        if !ok {
            return false;
        }
        st.small.solve(&mut rhs[..dim]);
        // y = w - sum_l eta_l b_l + sum_t mu_t e_t, four a pass over y.
        let mut y = std::mem::take(&mut st.y);
        y[..k].copy_from_slice(w);
        let mut vecs: [&[f64]; MAX_DIM] = [&[]; MAX_DIM];
        let mut c = [0.0; MAX_DIM];
        for (l, (b, c)) in vecs.iter_mut().zip(&mut c).enumerate().take(m) {
            *b = &st.neighbour[slot(l, o)..slot(l, o) + k];
            *c = rhs[l];
        }
        for (t, &q) in removed.iter().enumerate() {
            vecs[m + t] = &st.edge[slot(q, s)..slot(q, s) + k];
            c[m + t] = -rhs[m + t];
        }
        axpys(st.arch, &mut y[..k], &vecs[..dim], &c[..dim]);
        // Shifted forward: position p holds T's value at node_p - d, which
        // is eta_j where node_p is arc j's edge on side o.
        for (x, &nd) in st.fresh[..k].iter_mut().zip(&self.nodes) {
            let pt = self.pos[step(nd, o, n)];
            *x = if pt == NONE { 0.0 } else { y[pt] };
        }
        for (j, arc) in st.arcs.iter().enumerate() {
            st.fresh[self.pos[arc.edge[o]]] = rhs[j];
        }
        let len = match grown {
            Some(i) => {
                st.fresh[k] = y[self.pos[st.arcs[i].edge[s]]];
                k + 1
            }
            None => k,
        };
        st.y = y;
        // Every entry tested (no early exit), so the test vectorises.
        st.fresh[..len]
            .iter()
            .fold(true, |ok, x| ok & x.is_finite())
    }

    /// The row `M_aS` of node `a` with sign `sign` into `self.row`, `v`
    /// into `self.v` and the Schur complement `M_aa - r . v` of the
    /// bordering, or `None` if it is too small.
    fn schur(&mut self, ops: &Operators, a: usize, sign: f64, v: &[f64]) -> Option<f64> {
        let k = self.nodes.len();
        let mut row = std::mem::take(&mut self.row);
        self.row_of(ops, a, sign, &mut row[..k]);
        self.row = row;
        self.v[..k].copy_from_slice(v);
        let rv = dot(&self.row[..k], &self.v[..k]);
        let d0 = SetInverse::entry(ops, self.friction, a, sign, a);
        let sigma = d0 - rv;
        (sigma.is_finite() && sigma.abs() > PIVOT_TOL * d0.abs().max(rv.abs())).then_some(sigma)
    }

    /// Node `a` enters with no neighbour in the set and starts an arc of
    /// its own. The solutions for its column and its two neighbours' (the
    /// new arc's neighbour solutions) come from the nearest edge's
    /// neighbour solution by shifts of the set, one node a shift
    /// ([`Self::shift_column`]), instead of from the dense factors.
    fn border_isolated(
        &mut self,
        ops: &Operators,
        st: &mut Structured,
        a: usize,
        sign: f64,
    ) -> Bordered {
        let (n, k, m, f) = (self.n, self.nodes.len(), st.arcs.len(), self.friction);
        if m == MAX_ARCS || (0..2).any(|side| self.pos[step(a, side, n)] != NONE) {
            return Bordered::NotHere;
        }
        // The nearest edge: a = edge + t d, t >= 2 (a has no neighbour in
        // the set).
        let distance = |edge: usize, side: usize| {
            if side == 1 {
                (a + n - edge) % n
            } else {
                (edge + n - a) % n
            }
        };
        let Some((t, j, s)) = (0..m)
            .flat_map(|j| (0..2).map(move |side| (j, side)))
            .map(|(j, side)| (distance(st.arcs[j].edge[side], side), j, side))
            .min()
        else {
            return Bordered::NotHere;
        };
        if t > MAX_WALK {
            return Bordered::NotHere;
        }
        let o = 1 - s;
        let slot = |j: usize, side: usize| (2 * j + side) * n;
        // c_i = edge + i d and its solution s_i: s_1 is the edge's
        // neighbour solution, and a shift of s_i gives s_(i+1). walk[0] and
        // walk[1] hold s_(i-1) and s_i; at the end s_(t+1) is in `fresh`.
        // No c_i may be just outside an edge on the other side (the
        // shifted set would hold it).
        let other = st.outside(o, n);
        let mut walk = std::mem::take(&mut st.walk);
        let mut c = step(st.arcs[j].edge[s], s, n);
        walk[1][..k].copy_from_slice(&st.neighbour[slot(j, s)..slot(j, s) + k]);
        let mut ok = true;
        for i in 1..=t {
            if other[..m].contains(&c)
                || !self.shift_column(ops, st, s, &walk[1][..k], Some(c), None)
            {
                ok = false;
                break;
            }
            if i < t {
                walk.swap(0, 1);
                walk[1][..k].copy_from_slice(&st.fresh[..k]);
                c = step(c, s, n);
            }
        }
        if !ok {
            st.walk = walk;
            return Bordered::NotHere;
        }
        // The bordering by a, with v = s_t.
        let Some(sigma) = self.schur(ops, a, sign, &walk[1][..k]) else {
            st.walk = walk;
            return Bordered::Singular;
        };
        let (row, v) = (&self.row[..k], &self.v[..k]);
        st.follow_all(ops, f, a, sign, row, v, sigma, &[]);
        let entry = |col: usize| SetInverse::entry(ops, f, a, sign, col);
        follow(&mut walk[0][..=k], row, v, sigma, entry(step(a, o, n)));
        follow(&mut st.fresh[..=k], row, v, sigma, entry(step(a, s, n)));
        st.neighbour[slot(m, o)..=slot(m, o) + k].copy_from_slice(&walk[0][..=k]);
        st.neighbour[slot(m, s)..=slot(m, s) + k].copy_from_slice(&st.fresh[..=k]);
        for side in 0..2 {
            let e = &mut st.edge[slot(m, side)..=slot(m, side) + k];
            e[..k].iter_mut().zip(v).for_each(|(e, &v)| *e = -v / sigma);
            e[k] = 1.0 / sigma;
        }
        st.arcs.push(Arc { edge: [a, a], sign });
        st.walk = walk;
        self.follow_border(ops, a, sign, sigma);
        self.push(a, sign);
        Bordered::Done
    }

    /// Node `a` fills a gap of one node between the edge `s` of arc `i` and
    /// an arc of the same sign, and the two arcs become one: the neighbour
    /// solution of `a` is kept already, and no new one is needed.
    fn merge_arcs(
        &mut self,
        ops: &Operators,
        st: &mut Structured,
        i: usize,
        s: usize,
        a: usize,
        sign: f64,
    ) -> Bordered {
        let (n, k, m, f) = (self.n, self.nodes.len(), st.arcs.len(), self.friction);
        let (o, beyond) = (1 - s, step(a, s, n));
        let Some(j) = (0..m).find(|&j| j != i && st.arcs[j].edge[o] == beyond) else {
            return Bordered::NotHere;
        };
        if st.arcs[j].sign != sign {
            return Bordered::NotHere;
        }
        let slot = |j: usize, side: usize| (2 * j + side) * n;
        let Some(sigma) = self.schur(ops, a, sign, &st.neighbour[slot(i, s)..slot(i, s) + k])
        else {
            return Bordered::Singular;
        };
        let (row, v) = (&self.row[..k], &self.v[..k]);
        st.follow_all(ops, f, a, sign, row, v, sigma, &[(i, s), (j, o)]);
        // Arc i takes arc j's far edge, and arc j goes.
        st.arcs[i].edge[s] = st.arcs[j].edge[s];
        st.neighbour
            .copy_within(slot(j, s)..slot(j, s) + k + 1, slot(i, s));
        st.edge
            .copy_within(slot(j, s)..slot(j, s) + k + 1, slot(i, s));
        st.neighbour
            .copy_within(slot(j + 1, 0)..slot(m, 0), slot(j, 0));
        st.edge.copy_within(slot(j + 1, 0)..slot(m, 0), slot(j, 0));
        st.arcs.remove(j);
        self.follow_border(ops, a, sign, sigma);
        self.push(a, sign);
        Bordered::Done
    }
}
