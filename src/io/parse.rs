//! Parsers for numbers as users type them: angles in radians or multiples
//! of pi (`0.5pi`, `pi/2`, `-3pi/4`, `1.57`), and value lists and ranges
//! (`3:7.5:0.05`, `1,2,5`). They never panic, whatever the input.

use std::f64::consts::PI;

/// A number, angle or range that could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParseError {
    /// Not a finite number (or not a point `x,y`); holds the text.
    #[error("'{0}' is not a number")]
    Number(String),
    /// Not an angle in radians or a multiple of pi; holds the text.
    #[error("'{0}' is not an angle: use radians (1.57) or multiples of pi (0.5pi, pi/2, -3pi/4)")]
    Angle(String),
    /// Not a list or a range `start:stop:step` with `step > 0` and
    /// `stop >= start`; holds the text.
    #[error(
        "'{0}' is not a range: use start:stop:step with step > 0 (e.g. 3:7.5:0.05) or a list a,b,c"
    )]
    Range(String),
    /// A list or range with more than [`MAX_VALUES`] values.
    #[error("range '{text}' has {} values: at most {max} are allowed", shown_count(*count))]
    TooMany {
        /// The list or range as typed.
        text: String,
        /// The number of values it would give.
        count: usize,
        /// The most allowed, [`MAX_VALUES`].
        max: usize,
    },
}

/// Values in one list or range, at most.
pub const MAX_VALUES: usize = 100_000;

fn number(text: &str) -> Option<f64> {
    let t = text.trim();
    if t.is_empty() {
        return None;
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// A count for a message: exact when it is one a person reads, "more
/// than 10^12" for an absurd range (not 18446744073709551615).
fn shown_count(count: usize) -> String {
    if count > 1_000_000_000_000 {
        "more than 10^12".into()
    } else {
        count.to_string()
    }
}

/// A plain finite number.
///
/// # Errors
///
/// [`ParseError::Number`] for empty text, text that is not a number, and
/// infinite or NaN values.
pub fn parse_number(text: &str) -> Result<f64, ParseError> {
    number(text).ok_or_else(|| ParseError::Number(text.to_string()))
}

/// An angle in radians: `1.2`, `pi`, `-pi`, `0.5pi`, `0.5*pi`, `pi/2`,
/// `3pi/4`, `-3*pi/4`.
///
/// Used for the phase φ (`phase`) and for load-plane coordinates, which
/// are multiples of pi in the paper (model.md section 5). Case and spaces
/// are ignored.
///
/// # Errors
///
/// [`ParseError::Angle`] for anything else, a zero denominator or a value
/// that is not finite.
pub fn parse_angle(text: &str) -> Result<f64, ParseError> {
    let err = || ParseError::Angle(text.to_string());
    let t: String = text.trim().to_ascii_lowercase().replace(' ', "");
    if t.is_empty() {
        return Err(err());
    }
    let Some(at) = t.find("pi") else {
        return number(&t).ok_or_else(err);
    };
    let (coef, rest) = t.split_at(at);
    let rest = &rest[2..];
    let coef = match coef.strip_suffix('*') {
        // `*pi`, `-*pi`: a product needs a coefficient.
        Some("" | "+" | "-") => return Err(err()),
        Some(c) => c,
        None => coef,
    };
    let k = match coef {
        "" | "+" => 1.0,
        "-" => -1.0,
        c => number(c).ok_or_else(err)?,
    };
    let value = if rest.is_empty() {
        k * PI
    } else if let Some(den) = rest.strip_prefix('/') {
        let d = number(den).ok_or_else(err)?;
        if d == 0.0 {
            return Err(err());
        }
        k * PI / d
    } else {
        return Err(err());
    };
    if value.is_finite() {
        Ok(value)
    } else {
        Err(err())
    }
}

/// A list `a,b,c` or a range `start:stop:step` (inclusive of `stop` up to
/// rounding) of values read by `item`. A single value is a list of one.
///
/// # Errors
///
/// [`ParseError::Range`] for empty text, a range without three parts, a
/// bound or step that `item` cannot read, `step <= 0` or `stop < start`;
/// [`ParseError::TooMany`] for more than [`MAX_VALUES`] values; in a list,
/// the error of `item` on the first value it cannot read.
pub fn parse_values(
    text: &str,
    item: impl Fn(&str) -> Result<f64, ParseError>,
) -> Result<Vec<f64>, ParseError> {
    let t = text.trim();
    if t.is_empty() {
        return Err(ParseError::Range(text.to_string()));
    }
    if t.contains(':') {
        let parts: Vec<&str> = t.split(':').collect();
        if parts.len() != 3 {
            return Err(ParseError::Range(text.to_string()));
        }
        let bad = |_| ParseError::Range(text.to_string());
        let start = item(parts[0]).map_err(bad)?;
        let stop = item(parts[1]).map_err(bad)?;
        let step = item(parts[2]).map_err(bad)?;
        if step <= 0.0 || stop < start {
            return Err(ParseError::Range(text.to_string()));
        }
        let count_f = ((stop - start) / step + 1e-9).floor() + 1.0;
        if !count_f.is_finite() || count_f > MAX_VALUES as f64 {
            return Err(ParseError::TooMany {
                text: text.to_string(),
                count: if count_f.is_finite() {
                    count_f as usize
                } else {
                    usize::MAX
                },
                max: MAX_VALUES,
            });
        }
        let count = count_f as usize;
        // Values from an integer index, rounded to 12 significant digits, so
        // that 3:7.5:0.05 gives 3.05 and not 3.0500000000000003.
        return Ok((0..count)
            .map(|i| round12(start + step * i as f64))
            .collect());
    }
    let values: Result<Vec<f64>, ParseError> = t.split(',').map(&item).collect();
    let values = values?;
    if values.len() > MAX_VALUES {
        return Err(ParseError::TooMany {
            text: text.to_string(),
            count: values.len(),
            max: MAX_VALUES,
        });
    }
    Ok(values)
}

fn round12(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let digits = 12 - v.abs().log10().ceil() as i32;
    let scale = 10f64.powi(digits.clamp(-300, 300));
    let r = (v * scale).round() / scale;
    if r.is_finite() {
        r
    } else {
        v
    }
}

/// A point `x,y`.
///
/// A point of the load plane (model.md section 1.1), each coordinate an
/// angle as [`parse_angle`] reads it.
///
/// # Errors
///
/// [`ParseError::Number`] unless there are exactly two comma-separated
/// parts; [`ParseError::Angle`] for a coordinate that is not an angle.
pub fn parse_point(text: &str) -> Result<(f64, f64), ParseError> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 2 {
        return Err(ParseError::Number(text.to_string()));
    }
    Ok((parse_angle(parts[0])?, parse_angle(parts[1])?))
}

/// Load-plane points `x1,y1;x2,y2;...`, each coordinate an angle as
/// [`parse_angle`] reads it (`1.75pi,-1.75pi`). At least one point.
///
/// # Errors
///
/// [`ParseError::Number`] when there is no point; otherwise as
/// [`parse_point`] on the first point that does not parse.
pub fn parse_points(text: &str) -> Result<Vec<(f64, f64)>, ParseError> {
    let parts: Vec<&str> = text
        .split(';')
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect();
    if parts.is_empty() {
        return Err(ParseError::Number(text.to_string()));
    }
    parts.into_iter().map(parse_point).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        assert!(close(parse_angle("0.5pi").unwrap(), PI / 2.0));
        assert!(close(parse_angle("pi/2").unwrap(), PI / 2.0));
        assert!(close(parse_angle("-3pi/4").unwrap(), -0.75 * PI));
        assert!(close(parse_angle("-3*pi/4").unwrap(), -0.75 * PI));
        assert!(close(parse_angle("PI").unwrap(), PI));
        assert!(close(parse_angle("1.25").unwrap(), 1.25));
        assert!(close(parse_angle(" -pi ").unwrap(), -PI));
        for bad in [
            "abc", "", "pi/0", "2pi3", "nan", "inf", "pipi", "1e999", "*pi", "-*pi",
        ] {
            assert!(parse_angle(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn ranges_and_lists() {
        let v = parse_values("3:7.5:0.05", parse_number).unwrap();
        assert_eq!(v.len(), 91);
        assert_eq!(v[1], 3.05);
        assert_eq!(*v.last().unwrap(), 7.5);
        assert_eq!(
            parse_values("1,2,5", parse_number).unwrap(),
            vec![1.0, 2.0, 5.0]
        );
        assert_eq!(parse_values("4", parse_number).unwrap(), vec![4.0]);
        let p = parse_values("0:pi:pi/2", parse_angle).unwrap();
        assert_eq!(p.len(), 3);
        for bad in ["1:2", "2:1:0.1", "1:2:0", "1:2:-1", "a,b", "", "0:1e9:1e-9"] {
            assert!(parse_values(bad, parse_number).is_err(), "{bad}");
        }
    }
}
