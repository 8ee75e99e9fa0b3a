//! Residual-traction operators `H` and `|D|` (model.md section 2).
//!
//! Every kernel of eq. (7) depends on `theta - phi` only, so on `N` equally
//! spaced nodes both operators are circulant and fully described by their
//! Fourier symbols: `H -> -i sgn(n)` (slip changes the pressure) and
//! `|D| -> |n|` (slip relieves the shear). The Nyquist mode `n = N/2` has no
//! sign, so `H` drops it and `|D|` keeps `N/2`.

use std::f64::consts::PI;

use std::sync::Arc;

use super::kernels;
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

/// The circulant operators `H` and `|D|` on `N` nodes: their entries and
/// columns, and the operators applied by FFT for whole slip vectors.
#[derive(Clone)]
pub struct Operators {
    nodes: usize,
    /// The first column of `H`, twice over (`2N` numbers): column `k` of a
    /// circulant matrix is its first column rotated down by `k`, so it is
    /// the contiguous slice from `N - k` (see [`Self::hilbert_col`]). `N`
    /// numbers stay in the first level of the cache where the dense matrix
    /// (`N^2`, 8 MB at `N = 1024`) is read from memory, column by column, at
    /// every change of the slip set.
    hilbert: Vec<f64>,
    /// The first column of `|D|`, twice over, as for `hilbert`.
    abs_derivative: Vec<f64>,
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
    /// Symbol of `|D| + i H` per FFT bin, with the `1/N` of the inverse:
    /// `(|n| + sgn n) / N`, real, each twice (for a bin's real and
    /// imaginary parts): the spectrum, seen as `2N` reals, is scaled by one
    /// elementwise product. A complex product by the symbol spent two of
    /// its four multiplies and both adds on the zero imaginary part, and
    /// cost 20 instructions a node at `N = 1024`.
    symbol: Vec<f64>,
}

impl std::fmt::Debug for Operators {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Operators")
            .field("nodes", &self.nodes)
            .finish_non_exhaustive()
    }
}

/// Scratch buffers for [`Operators::apply_both`].
#[derive(Debug, Clone, Default)]
pub struct FftScratch {
    data: Vec<Complex64>,
    work: Vec<Complex64>,
}

impl Operators {
    /// `H` and `|D|` on `nodes` equally spaced nodes (model.md section 3).
    pub fn new(nodes: usize) -> Self {
        let n = nodes;
        let half = n / 2;
        // The entries are the symbols' sums over the harmonics
        // `n = 1 .. N/2 - 1` (and `|D|`'s Nyquist term), summed in closed
        // form (model.md section 3.3): with `t = pi m / N`,
        //   `H[m, 0] = (2/N) sum_n sin(2 n t) = (2/N) cot t` for odd `m`,
        //   `|D|[m, 0] = (2 sum_n n cos(2 n t) + (N/2)(-1)^m) / N
        //              = -1 / (N sin^2 t)` for odd `m`,
        // both 0 for even `m != 0`, and `|D|[0, 0] = N/4`. Summing the
        // series took `N^2 / 2` sines and cosines, 13 ms of the 0.4 s of a
        // run at `N = 1024`; the closed form is also the more accurate (one
        // rounding per entry instead of `N/2`).
        let mut h_first = vec![0.0; n];
        let mut d_first = vec![0.0; n];
        d_first[0] = n as f64 / 4.0;
        for m in (1..n).step_by(2) {
            let t = PI * m as f64 / n as f64;
            let (sin, cos) = t.sin_cos();
            h_first[m] = 2.0 * cos / (n as f64 * sin);
            d_first[m] = -1.0 / (n as f64 * sin * sin);
        }
        let hilbert = [h_first.as_slice(), h_first.as_slice()].concat();
        let abs_derivative = [d_first.as_slice(), d_first.as_slice()].concat();
        let mut planner = FftPlanner::new();
        // Bin k holds harmonic n = k (k < N/2) or k - N (k > N/2); the
        // combined symbol |n| + i (-i sgn n) = |n| + sgn n packs |D| g in the
        // real part and H g in the imaginary part of one inverse transform.
        let symbol = (0..n)
            .flat_map(|k| {
                let (abs, sgn) = if k == 0 {
                    (0.0, 0.0)
                } else if k < half {
                    (k as f64, 1.0)
                } else if k == half {
                    (half as f64, 0.0)
                } else {
                    ((n - k) as f64, -1.0)
                };
                let s = (abs + sgn) / n as f64;
                [s, s]
            })
            .collect();
        Self {
            nodes,
            hilbert,
            abs_derivative,
            forward: planner.plan_fft_forward(n),
            inverse: planner.plan_fft_inverse(n),
            symbol,
        }
    }

    /// `H g` into `pressure` and `|D| g` into `relief`, by FFT: `O(N log N)`
    /// instead of streaming the dense matrices.
    pub fn apply_both(
        &self,
        slip: &[f64],
        pressure: &mut [f64],
        relief: &mut [f64],
        scratch: &mut FftScratch,
    ) {
        self.convolve_with(slip, scratch, |pairs| {
            kernels::from_complex(pairs, relief, pressure)
        });
    }

    /// The transform of [`Self::apply_both`], its result handed to
    /// `unpack` as the `{ re, im }` pairs of `|D| g + i H g` rather than
    /// copied out: a caller that goes on to combine the responses with
    /// other arrays does it in the pass that unpacks them.
    pub(crate) fn convolve_with<R>(
        &self,
        slip: &[f64],
        scratch: &mut FftScratch,
        unpack: impl FnOnce(&[f64]) -> R,
    ) -> R {
        let n = self.nodes;
        // Sized once: a resize that keeps the length writes nothing.
        scratch.data.resize(n, Complex64::default());
        // `Complex64` is `#[repr(C)]` `{ re, im }`: num-complex's
        // `bytemuck` feature casts it to its two `f64`s, and the passes
        // over them run in the processor's widest vectors
        // ([`kernels`]; the baseline build's loops took 13 K instructions
        // a transform at `N = 1024`).
        kernels::to_complex(pulp::bytemuck::cast_slice_mut(&mut scratch.data[..n]), slip);
        let need = self
            .forward
            .get_inplace_scratch_len()
            .max(self.inverse.get_inplace_scratch_len());
        if scratch.work.len() < need {
            scratch.work.resize(need, Complex64::default());
        }
        self.forward
            .process_with_scratch(&mut scratch.data[..n], &mut scratch.work[..need]);
        // Re and im of every bin by the real symbol.
        kernels::scale(
            pulp::bytemuck::cast_slice_mut(&mut scratch.data[..n]),
            &self.symbol,
        );
        self.inverse
            .process_with_scratch(&mut scratch.data[..n], &mut scratch.work[..need]);
        unpack(pulp::bytemuck::cast_slice(&scratch.data[..n]))
    }

    /// Number of nodes `N`.
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// `H[j, k]`: pressure at node `j` from unit slip at node `k`.
    #[inline]
    pub fn hilbert(&self, j: usize, k: usize) -> f64 {
        self.hilbert_col(k)[j]
    }

    /// `|D|[j, k]`: shear relief at node `j` from unit slip at node `k`.
    #[inline]
    pub fn abs_derivative(&self, j: usize, k: usize) -> f64 {
        self.abs_derivative_col(k)[j]
    }

    /// Column `k` of `H`, contiguous: `H[j, k] = H[(j - k) mod N, 0]`.
    #[inline]
    pub fn hilbert_col(&self, k: usize) -> &[f64] {
        Self::rotated(&self.hilbert, k)
    }

    /// Column `k` of `|D|`, contiguous.
    #[inline]
    pub fn abs_derivative_col(&self, k: usize) -> &[f64] {
        Self::rotated(&self.abs_derivative, k)
    }

    /// Column `k` of the circulant matrix whose first column, twice over,
    /// is `twice`: entry `j` is `twice[N - k + j]`.
    #[inline]
    fn rotated(twice: &[f64], k: usize) -> &[f64] {
        let n = twice.len() / 2;
        assert!(k < n, "column {k} of a circulant matrix on {n} nodes");
        &twice[n - k..2 * n - k]
    }

    /// Residual pressure `H g`.
    pub fn residual_pressure(&self, slip: &[f64]) -> Vec<f64> {
        self.apply(slip, |k| self.hilbert_col(k), 1.0)
    }

    /// Residual shear `-|D| g`.
    pub fn residual_shear(&self, slip: &[f64]) -> Vec<f64> {
        self.apply(slip, |k| self.abs_derivative_col(k), -1.0)
    }

    /// `sign` is `1` or `-1`, so `c (sign g_k)` is `(sign c) g_k` to the
    /// bit, with one multiply an entry instead of two.
    fn apply<'a>(&'a self, slip: &[f64], col: impl Fn(usize) -> &'a [f64], sign: f64) -> Vec<f64> {
        debug_assert!(sign == 1.0 || sign == -1.0);
        let mut out = vec![0.0; self.nodes];
        for (k, &gk) in slip.iter().enumerate() {
            if gk != 0.0 {
                let a = sign * gk;
                for (o, c) in out.iter_mut().zip(col(k)) {
                    *o += c * a;
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn harmonic(n: usize, k: f64, phase: f64) -> Vec<f64> {
        (0..n)
            .map(|j| (k * 2.0 * PI * j as f64 / n as f64 + phase).cos())
            .collect()
    }

    #[test]
    fn symbols_on_harmonics() {
        let n = 64;
        let ops = Operators::new(n);
        for k in [1.0, 2.0, 5.0, 31.0] {
            let g = harmonic(n, k, 0.3);
            let p = ops.residual_pressure(&g);
            let q = ops.residual_shear(&g);
            // H cos = sin; |D| cos(k.) = k cos(k.)
            let sin = harmonic(n, k, 0.3 - PI / 2.0);
            for j in 0..n {
                assert!((p[j] - sin[j]).abs() < 1e-11, "H, k={k}, j={j}");
                assert!((q[j] + k * g[j]).abs() < 1e-10, "|D|, k={k}, j={j}");
            }
        }
    }

    #[test]
    fn entries_are_the_sums_over_the_harmonics() {
        // The series of the symbols (model.md section 3.3), summed term by
        // term, against the closed form the operators are built from.
        for n in [16, 64, 1024] {
            let ops = Operators::new(n);
            let half = n / 2;
            for m in 0..n {
                let theta = 2.0 * PI * m as f64 / n as f64;
                let (mut hs, mut ds) = (0.0, 0.0);
                for k in 1..half {
                    hs += (k as f64 * theta).sin();
                    ds += k as f64 * (k as f64 * theta).cos();
                }
                let nyquist = if m % 2 == 0 { 1.0 } else { -1.0 };
                let h = 2.0 * hs / n as f64;
                let d = (2.0 * ds + half as f64 * nyquist) / n as f64;
                // The series' own rounding: N/2 terms of size 1 (H) and
                // up to N/2 (|D|), scaled by 2/N.
                let (tol_h, tol_d) = (1e-15 * n as f64, 1e-16 * (n * n) as f64);
                assert!((ops.hilbert(m, 0) - h).abs() < tol_h, "H, N={n}, m={m}");
                assert!(
                    (ops.abs_derivative(m, 0) - d).abs() < tol_d,
                    "|D|, N={n}, m={m}"
                );
            }
        }
    }

    #[test]
    fn columns_are_the_first_rotated() {
        let n = 24;
        let ops = Operators::new(n);
        for k in 0..n {
            let (h, d) = (ops.hilbert_col(k), ops.abs_derivative_col(k));
            assert_eq!((h.len(), d.len()), (n, n));
            for j in 0..n {
                let first = (j + n - k) % n;
                assert_eq!(h[j].to_bits(), ops.hilbert(first, 0).to_bits());
                assert_eq!(d[j].to_bits(), ops.abs_derivative(first, 0).to_bits());
                assert_eq!(h[j].to_bits(), ops.hilbert(j, k).to_bits());
            }
        }
        // H is odd and |D| even in theta.
        for m in 1..n {
            assert!((ops.hilbert(m, 0) + ops.hilbert(n - m, 0)).abs() < 1e-12);
            assert!((ops.abs_derivative(m, 0) - ops.abs_derivative(n - m, 0)).abs() < 1e-12);
        }
    }

    #[test]
    fn rigid_rotation_causes_no_traction() {
        let ops = Operators::new(32);
        let g = vec![0.7; 32];
        assert!(ops.residual_pressure(&g).iter().all(|v| v.abs() < 1e-12));
        assert!(ops.residual_shear(&g).iter().all(|v| v.abs() < 1e-12));
    }

    #[test]
    fn fft_matches_the_dense_matrices() {
        let n = 64;
        let ops = Operators::new(n);
        let g: Vec<f64> = (0..n)
            .map(|j| ((j * j * 7 + 3) % 13) as f64 / 13.0 - 0.4)
            .collect();
        let (mut p, mut r) = (vec![0.0; n], vec![0.0; n]);
        ops.apply_both(&g, &mut p, &mut r, &mut FftScratch::default());
        let p_dense = ops.residual_pressure(&g);
        let q_dense = ops.residual_shear(&g);
        for j in 0..n {
            assert!((p[j] - p_dense[j]).abs() < 1e-12);
            assert!((r[j] + q_dense[j]).abs() < 1e-12);
        }
        // The shear straight out of the transform, the relief negated, and
        // the totals in the same pass: to the bit, the numbers of the
        // separate passes.
        let elastic: Vec<Vec<f64>> = (0..4)
            .map(|i| {
                (0..n)
                    .map(|j| ((j * 5 + i * 3) % 11) as f64 / 7.0 - 0.6)
                    .collect()
            })
            .collect();
        let (ux, uy) = (0.6, -0.8);
        let (mut p2, mut q) = (vec![0.0; n], vec![0.0; n]);
        let (mut tp, mut tq) = (vec![0.0; n], vec![0.0; n]);
        let e = [&elastic[0][..], &elastic[1], &elastic[2], &elastic[3]];
        ops.convolve_with(&g, &mut FftScratch::default(), |pairs| {
            kernels::from_complex_totals(pairs, [&mut p2, &mut q], [&mut tp, &mut tq], (ux, uy), e)
        });
        let (mut tp2, mut tq2) = (vec![0.0; n], vec![0.0; n]);
        let minus_r: Vec<f64> = r.iter().map(|&r| -r).collect();
        kernels::combine_plus(&mut tp2, ux, e[0], uy, e[1], &p);
        kernels::combine_plus(&mut tq2, ux, e[2], uy, e[3], &minus_r);
        for j in 0..n {
            assert_eq!(p2[j].to_bits(), p[j].to_bits());
            assert_eq!(q[j].to_bits(), (-r[j]).to_bits());
            assert_eq!(tp[j].to_bits(), tp2[j].to_bits());
            assert_eq!(tq[j].to_bits(), tq2[j].to_bits());
        }
    }

    #[test]
    fn nyquist_mode() {
        let n = 16;
        let ops = Operators::new(n);
        let g: Vec<f64> = (0..n)
            .map(|j| if j % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let p = ops.residual_pressure(&g);
        let q = ops.residual_shear(&g);
        for j in 0..n {
            assert!(p[j].abs() < 1e-12);
            assert!((q[j] + (n as f64 / 2.0) * g[j]).abs() < 1e-11);
        }
    }
}
