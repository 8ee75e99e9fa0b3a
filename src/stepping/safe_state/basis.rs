//! The harmonic basis of a safe-state search, orthonormal in the energy.

use std::f64::consts::PI;

/// A basis for the change `z` of the slip towards a safe state, orthonormal
/// in the energy `z^T |D| z`: the harmonics `cos(k theta)`, `sin(k theta)`,
/// `k = 1 .. N/2 - 1`, scaled by `1 / sqrt(N k / 2)`, and the Nyquist mode.
/// (A rigid rotation changes nothing and is left out.) Each column is kept
/// as the slip, `|D|` of it and `H` of it (`H cos = sin`, `H sin = -cos`).
/// Fewer harmonics were tried: with 32 or 16 the proofs come hundreds of
/// cycles later or not at all, since a safe state needs local corrections.
#[derive(Debug, Clone)]
pub(super) struct Basis {
    pub(super) size: usize,
    pub(super) slip: Vec<f64>,
    pub(super) relief: Vec<f64>,
    pub(super) pressure: Vec<f64>,
}

impl Basis {
    pub(super) fn harmonics(n: usize) -> Self {
        let modes = n / 2 - 1;
        let size = 2 * modes + 1;
        let mut slip = Vec::with_capacity(size * n);
        let mut relief = Vec::with_capacity(size * n);
        let mut pressure = Vec::with_capacity(size * n);
        // sin and cos of k theta_j = 2 pi (k j mod N) / N from one table:
        // N sines instead of N^2 (a run that never searches builds this
        // too, once, at its first quick test).
        let table: Vec<(f64, f64)> = (0..n)
            .map(|m| (2.0 * PI * m as f64 / n as f64).sin_cos())
            .collect();
        for k in 1..=modes {
            let kf = k as f64;
            let scale = 1.0 / (n as f64 * kf / 2.0).sqrt();
            for odd in [false, true] {
                for j in 0..n {
                    let (sin, cos) = table[k * j % n];
                    let (value, conjugate) = if odd { (sin, -cos) } else { (cos, sin) };
                    slip.push(scale * value);
                    relief.push(scale * kf * value);
                    pressure.push(scale * conjugate);
                }
            }
        }
        // The Nyquist mode (-1)^j: |D| gives N/2 times it, H nothing.
        let scale = 1.0 / (n as f64 * n as f64 / 2.0).sqrt();
        for j in 0..n {
            let value = if j % 2 == 0 { scale } else { -scale };
            slip.push(value);
            relief.push(value * (n / 2) as f64);
            pressure.push(0.0);
        }
        Self {
            size,
            slip,
            relief,
            pressure,
        }
    }
}
