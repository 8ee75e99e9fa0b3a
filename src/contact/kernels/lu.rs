//! A dense LU with partial pivoting (faer's) on a reusable buffer, with a
//! substitution for one right-hand side.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::linalg::lu::partial_pivoting::solve::solve_in_place_scratch;
use faer::{MatMut, Par};

/// A dense LU with partial pivoting on a reusable column-major buffer.
pub(in crate::contact) struct DenseLu {
    pub(in crate::contact) lu: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    dim: usize,
    stack: MemBuffer,
    /// Permuted right-hand side of [`DenseLu::solve`].
    tmp: Vec<f64>,
}

impl DenseLu {
    pub(in crate::contact) fn new(capacity: usize) -> Self {
        let req =
            lu_in_place_scratch::<usize, f64>(capacity, capacity, Par::Seq, Default::default()).or(
                solve_in_place_scratch::<usize, f64>(capacity, capacity, Par::Seq),
            );
        Self {
            lu: vec![0.0; capacity * capacity],
            perm: vec![0; capacity],
            perm_inv: vec![0; capacity],
            dim: 0,
            stack: MemBuffer::new(req),
            tmp: vec![0.0; capacity],
        }
    }

    /// Room for matrices up to `capacity x capacity`, allocated at the
    /// first need: a contact that never needs this solver (most runs of
    /// a sweep, each on its own clone) does not pay for its `N x N`
    /// buffers.
    pub(in crate::contact) fn reserve(&mut self, capacity: usize) {
        if self.tmp.len() < capacity {
            *self = DenseLu::new(capacity);
        }
    }

    /// Factorise the `dim x dim` matrix already written into `self.lu`.
    pub(in crate::contact) fn factorise(&mut self, dim: usize) {
        self.dim = dim;
        let m = MatMut::from_column_major_slice_mut(&mut self.lu[..dim * dim], dim, dim);
        lu_in_place(
            m,
            &mut self.perm[..dim],
            &mut self.perm_inv[..dim],
            Par::Seq,
            MemStack::new(&mut self.stack),
            Default::default(),
        );
    }

    /// `U^-1` of the last factorisation (of a `k x k` matrix) written on
    /// and above the diagonal of `dst` (`k x k`, column stride `ld`); the
    /// entries below it are left as they are.
    pub(in crate::contact) fn invert_upper(&self, k: usize, dst: &mut [f64], ld: usize) {
        let src = faer::MatRef::from_column_major_slice(&self.lu[..k * k], k, k);
        let dst = MatMut::from_column_major_slice_with_stride_mut(dst, k, k, ld);
        faer::linalg::triangular_inverse::invert_upper_triangular(dst, src, Par::Seq);
    }

    /// The row permutation of the last factorisation of a `k x k` matrix:
    /// row `i` of the factors is row `perm[i]` of the matrix.
    pub(in crate::contact) fn perm(&self, k: usize) -> &[usize] {
        &self.perm[..k]
    }

    /// Overwrite `rhs` (length `dim`) with the solution: `P A = L U`, so
    /// `x = U^-1 L^-1 P b`, by column-oriented substitution (one vector:
    /// the blocked solve of the library costs more than the flops here).
    pub(in crate::contact) fn solve(&mut self, rhs: &mut [f64]) {
        let k = self.dim;
        let lu = &self.lu[..k * k];
        let x = &mut self.tmp[..k];
        for (xi, &pi) in x.iter_mut().zip(&self.perm[..k]) {
            *xi = rhs[pi];
        }
        // L (unit diagonal, strictly below it).
        for j in 0..k {
            let (head, tail) = x.split_at_mut(j + 1);
            let xj = head[j];
            if xj != 0.0 {
                for (t, &l) in tail.iter_mut().zip(&lu[j * k + j + 1..(j + 1) * k]) {
                    *t -= l * xj;
                }
            }
        }
        // U (the diagonal and above).
        for j in (0..k).rev() {
            let (head, tail) = x.split_at_mut(j);
            let xj = tail[0] / lu[j * k + j];
            tail[0] = xj;
            if xj != 0.0 {
                for (t, &u) in head.iter_mut().zip(&lu[j * k..j * k + j]) {
                    *t -= u * xj;
                }
            }
        }
        rhs[..k].copy_from_slice(x);
    }

    /// The library's solve, for checking [`DenseLu::solve`].
    #[cfg(test)]
    pub(in crate::contact) fn solve_reference(&mut self, rhs: &mut [f64]) {
        let k = self.dim;
        let lu = faer::MatRef::from_column_major_slice(&self.lu[..k * k], k, k);
        let perm = faer::perm::PermRef::new_checked(&self.perm[..k], &self.perm_inv[..k], k);
        let rhs = MatMut::from_column_major_slice_mut(&mut rhs[..k], k, 1);
        faer::linalg::lu::partial_pivoting::solve::solve_in_place(
            lu,
            lu,
            perm,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.stack),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn substitution_matches_the_library_solve() {
        let k = 37;
        let mut lu = DenseLu::new(k);
        for c in 0..k {
            for r in 0..k {
                lu.lu[c * k + r] =
                    (((r * 31 + c * 17) % 23) as f64 - 11.0) / 7.0 + if r == c { 0.5 } else { 0.0 };
            }
        }
        lu.factorise(k);
        let b: Vec<f64> = (0..k).map(|i| ((i * 13 % 7) as f64) - 3.0).collect();
        let (mut x, mut y) = (b.clone(), b);
        lu.solve(&mut x);
        lu.solve_reference(&mut y);
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }
}
