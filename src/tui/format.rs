//! How numbers and names are written on screen.

use std::f64::consts::PI;

/// `phi` change of the up and down keys (the grid labels are exact on).
pub const PHASE_STEP: f64 = PI / 24.0;

/// `1 zone`, `2 zones`.
pub fn plural(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// Node angle shown in `[-pi, pi)`, the range the paper's figures use.
pub fn node_theta(j: usize, n: usize) -> f64 {
    let t = 2.0 * PI * j as f64 / n as f64;
    if t >= PI {
        t - 2.0 * PI
    } else {
        t
    }
}

/// `lambda` with at least two decimals: `5.50`, `5.55`, `5.123`.
pub fn format_load_factor(v: f64) -> String {
    let two = format!("{v:.2}");
    if (two.parse::<f64>().unwrap_or(v) - v).abs() < 1e-9 {
        two
    } else {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').to_string()
    }
}

/// `phi` as a multiple of `pi` when it is one of the `pi/24` steps
/// (`0`, `pi/24`, `-3pi/8`), else in radians.
pub fn format_phase(v: f64) -> String {
    let k = (v / PHASE_STEP).round();
    if (v - k * PHASE_STEP).abs() > 1e-9 {
        return format!("{v:.4} rad");
    }
    let k = k as i64;
    if k == 0 {
        return "0".into();
    }
    let g = gcd(k.unsigned_abs(), 24) as i64;
    let (num, den) = (k / g, 24 / g);
    let sign = if num < 0 { "-" } else { "" };
    let num = num.abs();
    let head = if num == 1 {
        format!("{sign}pi")
    } else {
        format!("{sign}{num}pi")
    };
    if den == 1 {
        head
    } else {
        format!("{head}/{den}")
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// Three significant digits in scientific notation, `-` for zero.
pub fn format_sci(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phase_labels() {
        assert_eq!(format_phase(0.0), "0");
        assert_eq!(format_phase(PI / 24.0), "pi/24");
        assert_eq!(format_phase(-3.0 * PI / 8.0), "-3pi/8");
        assert_eq!(format_phase(PI / 2.0), "pi/2");
        assert_eq!(format_phase(PI), "pi");
        assert_eq!(format_phase(0.3), "0.3000 rad");
    }

    #[test]
    fn load_factor_labels() {
        assert_eq!(format_load_factor(5.5), "5.50");
        assert_eq!(format_load_factor(5.55), "5.55");
        assert_eq!(format_load_factor(5.123), "5.123");
    }
}
