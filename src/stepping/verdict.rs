//! What the sequence of cycle dissipations says: the steady level it
//! approaches, with a two-sided bound ([`level`]), and when no verdict is
//! proven its trend ([`trend`]) (`docs/model.md` sections 6.1 and 6.3).

use serde::Serialize;

use super::outcome::Level;
use super::steady::SETTLE_CYCLES;

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
    /// Estimate of `lim W_k`: the [`level`] of the sequence when `W`
    /// approaches it geometrically (rising or falling); otherwise Aitken's
    /// delta-squared extrapolation of the last three cycles, kept between
    /// 0 and the last `W` when falling.
    pub limit: f64,
    /// Uncertainty of `limit`, two-sided: `[limit - uncertainty, limit +
    /// uncertainty]` holds the level. The bound of [`level`] for a
    /// geometric approach; all of `[0, limit]` for a fall that is not
    /// geometric (a power-law decay has limit 0 while Aitken's
    /// extrapolation of it stays at about `W / (p + 1)`); infinite for a
    /// rise that is not (nothing bounds it from above).
    pub uncertainty: f64,
}

/// Cycles over which the trend is measured.
pub const WINDOW: usize = 8;

/// Changes of `W` from which its geometric approach to a level is measured
/// (the last `LEVEL_WINDOW + 1` cycles).
pub const LEVEL_WINDOW: usize = 5;

/// Cycles between the two extrapolations whose difference bounds how far
/// the extrapolation itself is still moving.
const LEVEL_DRIFT: usize = 4;

/// Changes below this fraction of `W` are round-off: a sequence whose last
/// [`SETTLE_CYCLES`] changes are all below it is at its level.
const ROUND_OFF: f64 = 1e-10;

/// The level a sequence (one entry per cycle: `W`, or the rotation per
/// cycle) is approaching, with a two-sided bound (model.md section 6.1):
///
/// * at its level to round-off when its last [`SETTLE_CYCLES`] changes are
///   all below `1e-10` of it: the level is the last entry;
/// * approaching it geometrically when its last [`LEVEL_WINDOW`] changes
///   have one sign and each is smaller than the one before: the level is
///   the last entry plus the geometric tail `d rho / (1 - rho)` of the last
///   change `d`, with `rho` the mean ratio of successive changes over the
///   window. The uncertainty is twice the largest of the tail itself, its
///   spread over the ratios seen in the window, and how far the same
///   extrapolation moved over the last [`LEVEL_DRIFT`] cycles: the level is
///   then known to lie between the last entry and about three tails beyond
///   it, in the direction the sequence moves.
///
/// `None` otherwise: changes of both signs (a turning point on the way,
/// or noise), changes that do not shrink, or too few entries.
pub fn level(w: &[f64]) -> Option<Level> {
    let n = w.len();
    if n < SETTLE_CYCLES + 1 {
        return None;
    }
    let last = w[n - 1];
    if at_round_off(w) {
        return Some(Level {
            value: last,
            uncertainty: w[n - SETTLE_CYCLES - 1..]
                .windows(2)
                .map(|p| (p[1] - p[0]).abs())
                .sum(),
        });
    }
    let (value, spread) = geometric_level(w)?;
    // The extrapolation of a sequence that is still bending (a second,
    // slower mode, or one of the other sign on its way to a turning point)
    // moves from cycle to cycle: that motion is part of the uncertainty.
    let drift = if n >= 2 * LEVEL_WINDOW + 2 {
        let (earlier, _) = geometric_level(&w[..n - LEVEL_DRIFT])?;
        (value - earlier).abs()
    } else {
        0.0
    };
    Some(Level {
        value,
        uncertainty: 2.0 * spread.max(drift),
    })
}

/// Whether the last [`SETTLE_CYCLES`] changes of `w` are all round-off
/// (below `1e-10` of the largest of those entries).
fn at_round_off(w: &[f64]) -> bool {
    let n = w.len();
    if n < SETTLE_CYCLES + 1 {
        return false;
    }
    let recent = &w[n - SETTLE_CYCLES - 1..];
    let scale = recent.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    recent
        .windows(2)
        .all(|p| (p[1] - p[0]).abs() <= ROUND_OFF * scale)
}

/// The geometric extrapolation of [`level`] on the last [`LEVEL_WINDOW`]
/// changes of `w`, and the largest of its tail and the tail's spread over
/// the window's ratios; `None` unless the changes have one sign and shrink.
fn geometric_level(w: &[f64]) -> Option<(f64, f64)> {
    let n = w.len();
    if n < LEVEL_WINDOW + 1 {
        return None;
    }
    let d: Vec<f64> = w[n - LEVEL_WINDOW - 1..]
        .windows(2)
        .map(|p| p[1] - p[0])
        .collect();
    let last_change = d[LEVEL_WINDOW - 1];
    if last_change == 0.0
        || !d
            .iter()
            .all(|x| x.signum() == last_change.signum() && *x != 0.0)
    {
        return None;
    }
    let ratios = d.windows(2).map(|p| p[1] / p[0]);
    let (lo, hi) = ratios.fold((f64::INFINITY, 0.0_f64), |(lo, hi), r| {
        (lo.min(r), hi.max(r))
    });
    if hi >= 1.0 || !hi.is_finite() {
        return None;
    }
    let rho = (last_change / d[0]).powf(1.0 / (LEVEL_WINDOW - 1) as f64);
    let tail = |q: f64| last_change * q / (1.0 - q);
    let value = w[n - 1] + tail(rho);
    let spread = tail(rho)
        .abs()
        .max((tail(hi) - tail(rho)).abs())
        .max((tail(rho) - tail(lo)).abs());
    Some((value, spread))
}

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
    // Aitken's extrapolation from each triple of the window, kept to
    // `W >= 0`: its spread says how settled the extrapolation is.
    let aitken: Vec<f64> = window
        .windows(3)
        .map(|t| {
            let (d1, d2) = (t[1] - t[0], t[2] - t[1]);
            let dd = d2 - d1;
            if dd == 0.0 || !dd.is_finite() {
                t[2]
            } else {
                (t[2] - d2 * d2 / dd).max(0.0)
            }
        })
        .collect();
    let aitken_last = *aitken.last().expect("WINDOW >= 1");
    let spread = aitken
        .iter()
        .map(|a| (a - aitken_last).abs())
        .fold(0.0, f64::max);
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
    let rising = diffs[diffs.len() - 1] > 0.0;
    let (limit, uncertainty) = match level(w) {
        // At its level to round-off, or approaching it geometrically: the
        // two-sided bound of `level`, whichever way `W` moves.
        Some(l) if geometric || at_round_off(w) => (l.value.max(0.0), l.uncertainty),
        // Not geometric and rising: nothing bounds the level from above.
        _ if rising => (aitken_last.max(last), f64::INFINITY),
        // Not geometric and falling: the level may be anywhere down to 0
        // (a power-law decay has limit 0, while Aitken's extrapolation of
        // it stays at about `W / (p + 1)`).
        _ => {
            let limit = aitken_last.min(last);
            (limit, spread.max(limit))
        }
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
        assert!((t.limit - 2e-6).abs() < 1e-15, "{t:?}");
        // The bound is a few of the remaining tails, not the whole range.
        assert!(t.uncertainty < 3.0 * (t.last - 2e-6), "{t:?}");
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
    fn a_rise_to_a_level_is_bounded_on_both_sides() {
        // Rising geometrically to 7.5e-6: the interval is not clamped to
        // the largest W seen.
        let w: Vec<f64> = (1..=40).map(|k| 7.5e-6 - 1e-6 * 0.75f64.powi(k)).collect();
        let t = trend(&w).unwrap();
        assert!(t.limit > t.last, "{t:?}");
        assert!((t.limit - 7.5e-6).abs() <= t.uncertainty, "{t:?}");
        assert!(t.uncertainty < 3.0 * (7.5e-6 - t.last), "{t:?}");
    }

    #[test]
    fn too_short_has_no_trend() {
        assert!(trend(&[1.0; WINDOW + 1]).is_none());
    }
}
