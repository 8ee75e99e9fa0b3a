//! Axis labels and numbers as journals print them: powers of ten with
//! superscripts (10⁻⁵), a linear axis with a scientific multiplier that fits
//! its data, numbers rounded for reading in text, multiples of π.

/// Superscript digits and minus, for powers of ten as journals print them.
pub(crate) fn superscript(n: i32) -> String {
    let digits = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut out = String::new();
    if n < 0 {
        out.push('⁻');
    }
    for c in n.unsigned_abs().to_string().chars() {
        out.push(digits[c.to_digit(10).unwrap_or(0) as usize]);
    }
    out
}

/// A log axis's label: `10⁻⁵` at a power of ten, nothing between (the
/// ticks there still show the log scale).
pub(crate) fn pow10_label(v: &f64) -> String {
    if *v <= 0.0 {
        return String::new();
    }
    let l = v.log10();
    let k = l.round();
    if (l - k).abs() < 1e-6 {
        format!("10{}", superscript(k as i32))
    } else {
        String::new()
    }
}

/// The whole decades round `(lo, hi)`, so that a log axis has powers of
/// ten at both ends and at least two labels.
pub(crate) fn decades(lo: f64, hi: f64) -> (f64, f64) {
    let a = lo.log10().floor();
    let mut b = hi.log10().ceil();
    if b <= a {
        b = a + 1.0;
    }
    (10f64.powf(a), 10f64.powf(b))
}

/// A linear axis from 0 fitted to `max`: its top (the first tick at or
/// above the data, so no empty band), and the power of ten its labels are
/// given in (`×10⁻⁴` beside the axis title) when the numbers are small or
/// large.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LinearAxis {
    pub(crate) top: f64,
    pub(crate) exponent: i32,
    pub(crate) ticks: usize,
}

impl LinearAxis {
    pub(crate) fn fit(max: f64) -> LinearAxis {
        if !(max.is_finite() && max > 0.0) {
            return LinearAxis {
                top: 1.0,
                exponent: 0,
                ticks: 6,
            };
        }
        let raw = max / 5.0;
        let mag = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 2.5, 5.0, 10.0]
            .iter()
            .map(|m| m * mag)
            .find(|s| max / s <= 8.0)
            .unwrap_or(10.0 * mag);
        let n = (max / step * (1.0 + 1e-9)).ceil().max(1.0);
        // A point exactly at the last tick would sit on the frame: leave
        // a little room by going one tick further only then.
        let n = if (n * step - max) < 0.02 * step * n {
            n + 1.0
        } else {
            n
        };
        let top = n * step;
        // The multiplier follows the data, not the top tick: 8.2e-4 reads
        // as 8.2 x 10^-4 even when the axis ends at 1.0e-3.
        let e = max.log10().floor() as i32;
        let exponent = if !(-2..4).contains(&e) { e } else { 0 };
        LinearAxis {
            top,
            exponent,
            ticks: n as usize + 1,
        }
    }

    /// A tick label: the value over `10^exponent`, shortest form.
    pub(crate) fn label(&self, v: f64) -> String {
        let x = v / 10f64.powi(self.exponent);
        let t = format!("{x:.3}");
        let t = t.trim_end_matches('0').trim_end_matches('.');
        if t == "-0" {
            "0".into()
        } else {
            t.to_string()
        }
    }

    /// `title` with the multiplier, when there is one.
    pub(crate) fn title(&self, title: &str) -> String {
        if self.exponent == 0 {
            title.to_string()
        } else {
            format!("{title}  (×10{})", superscript(self.exponent))
        }
    }
}

/// A number rounded for reading in text: three significant digits, as
/// `2.77 × 10⁻⁴` when it is small or large.
pub(crate) fn readable(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let e = v.abs().log10().floor() as i32;
    if (-2..4).contains(&e) {
        let d = (2 - e).max(0) as usize;
        format!("{v:.d$}")
    } else {
        let m = v / 10f64.powi(e);
        format!("{m:.2} × 10{}", superscript(e))
    }
}

/// `(lo, hi)` widened by 3 % each side (or to a unit interval when empty).
pub(crate) fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-9 {
        return (lo - 0.5, hi + 0.5);
    }
    let pad = 0.03 * (hi - lo);
    (lo - pad, hi + pad)
}

/// An axis label for a value in units of pi: `0`, `π/4`, `−3π/4`, `2π`,
/// or two decimals when it is not a multiple of `pi/4`.
pub(crate) fn pi_label(v: &f64) -> String {
    let k = (v * 4.0).round() as i64;
    if (v * 4.0 - k as f64).abs() > 1e-6 {
        return format!("{v:.2}π");
    }
    let coef = |n: i64| match n {
        1 => String::new(),
        -1 => "−".into(),
        n if n < 0 => format!("−{}", -n),
        n => n.to_string(),
    };
    match k {
        0 => "0".into(),
        _ if k % 4 == 0 => format!("{}π", coef(k / 4)),
        _ if k % 2 == 0 => format!("{}π/2", coef(k / 2)),
        _ => format!("{}π/4", coef(k)),
    }
}
