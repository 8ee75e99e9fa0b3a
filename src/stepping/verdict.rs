//! What the sequence of cycle dissipations says when no verdict is proven:
//! its trend and an estimate of its limit (`docs/model.md` section 6.3).

use serde::Serialize;

/// The trend of `W` over the last cycles of a run, and where it is heading.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Trend {
    /// `W` of the last cycle.
    pub last: f64,
    /// Ratio of successive changes `(W_k - W_(k-1)) / (W_(k-1) - W_(k-2))`,
    /// the geometric mean over the last [`WINDOW`] cycles: below 1 the
    /// changes shrink geometrically and the limit below is well determined;
    /// near 1 (or above) it is not.
    pub ratio: f64,
    /// Local power-law exponent `p` of `W_k ~ k^(-p)` over the last
    /// [`WINDOW`] cycles (0 for a level `W`, negative for a rising one).
    pub exponent: f64,
    /// Estimate of `lim W_k`: Aitken's delta-squared extrapolation of the
    /// last three cycles, clamped to `[0, max W]` of the window.
    pub limit: f64,
    /// Uncertainty of `limit`: the spread of the extrapolations over the
    /// window, and all of `[0, limit]` when the changes do not shrink
    /// geometrically (a power-law decay has limit 0 while Aitken's
    /// extrapolation of it stays at about `W / (p + 1)`).
    pub uncertainty: f64,
}

/// Cycles over which the trend is measured.
pub const WINDOW: usize = 8;

/// The ratio of successive changes at or below which the changes count as
/// shrinking geometrically.
const GEOMETRIC: f64 = 0.95;

/// How far below the ratio of a power-law decay the ratio of successive
/// changes must be to count as geometric.
const POWER_LAW_MARGIN: f64 = 0.02;

/// The trend of `w` (one entry per cycle); `None` with fewer than
/// `WINDOW + 2` cycles.
pub fn trend(w: &[f64]) -> Option<Trend> {
    let n = w.len();
    if n < WINDOW + 2 {
        return None;
    }
    let last = w[n - 1];
    let window = &w[n - WINDOW - 2..];
    let hi = window.iter().cloned().fold(0.0, f64::max);
    // Aitken's extrapolation from each triple of the window.
    let aitken: Vec<f64> = window
        .windows(3)
        .map(|t| {
            let (d1, d2) = (t[1] - t[0], t[2] - t[1]);
            let dd = d2 - d1;
            if dd == 0.0 || !dd.is_finite() {
                t[2]
            } else {
                (t[2] - d2 * d2 / dd).clamp(0.0, hi)
            }
        })
        .collect();
    let limit = *aitken.last().expect("WINDOW >= 1");
    let spread = aitken.iter().map(|a| (a - limit).abs()).fold(0.0, f64::max);
    // Geometric mean of the ratios of successive changes.
    let diffs: Vec<f64> = window.windows(2).map(|p| p[1] - p[0]).collect();
    let ratio = if diffs[0] == 0.0 || diffs[diffs.len() - 1] == 0.0 {
        0.0
    } else {
        (diffs[diffs.len() - 1] / diffs[0])
            .abs()
            .powf(1.0 / (diffs.len() - 1) as f64)
    };
    let first = w[n - 1 - WINDOW];
    let exponent = if first > 0.0 && last > 0.0 {
        (first / last).ln() / (n as f64 / (n - WINDOW) as f64).ln()
    } else {
        f64::NAN
    };
    // A power-law decay `W_k ~ k^(-p)` (limit 0) has changes whose ratio is
    // about `((k - 1) / k)^(p + 1)`: a ratio that close to it is no evidence
    // of a geometric approach to a positive level, however small it is.
    let k = n as f64;
    let power_law_ratio = if exponent.is_finite() {
        ((k - 1.0) / k).powf(exponent.max(0.0) + 1.0)
    } else {
        1.0
    };
    let same_sign = diffs.iter().all(|d| d.signum() == diffs[0].signum());
    let geometric = same_sign && ratio <= GEOMETRIC && ratio < power_law_ratio - POWER_LAW_MARGIN;
    let uncertainty = if geometric || spread == 0.0 && diffs.iter().all(|&d| d == 0.0) {
        spread
    } else {
        spread.max(limit)
    };
    Some(Trend {
        last,
        ratio,
        exponent,
        limit,
        uncertainty,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometric_approach_to_a_level_is_extrapolated() {
        let w: Vec<f64> = (1..=30).map(|k| 2e-6 + 1e-3 * 0.8f64.powi(k)).collect();
        let t = trend(&w).unwrap();
        assert!((t.limit - 2e-6).abs() < 1e-9, "{t:?}");
        assert!(t.uncertainty < 1e-9, "{t:?}");
        assert!((t.ratio - 0.8).abs() < 1e-6, "{t:?}");
    }

    #[test]
    fn power_law_decay_leaves_the_limit_open_down_to_zero() {
        let w: Vec<f64> = (1..=200).map(|k| (k as f64).powf(-3.0)).collect();
        let t = trend(&w).unwrap();
        assert!(t.limit > 0.0 && t.limit - t.uncertainty <= 0.0, "{t:?}");
        assert!((t.exponent - 3.0).abs() < 0.01, "{t:?}");
        assert!(t.ratio > 0.95, "{t:?}");
    }

    #[test]
    fn a_level_sequence_has_itself_as_limit() {
        let w = vec![3e-5; 20];
        let t = trend(&w).unwrap();
        assert_eq!((t.limit, t.uncertainty, t.exponent), (3e-5, 0.0, 0.0));
    }

    #[test]
    fn too_short_has_no_trend() {
        assert!(trend(&[1.0; WINDOW + 1]).is_none());
    }
}
