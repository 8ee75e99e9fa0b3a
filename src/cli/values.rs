//! clap's value parsers of the numeric flags, built from the library's
//! ranges ([`shakedown::model::ranges`]): a value out of range is refused
//! while the command line is parsed, with the range's own words, and no
//! limit is written here a second time.
//!
//! Each parser checks the text and hands it on unchanged, so that a later
//! message (a polyline's vertex count against `--steps`, a header that
//! contradicts a flag) quotes the flag as it was typed.

use shakedown::io::parse::{parse_number, parse_point, parse_values, ParseError};
use shakedown::model::ranges::{CountRange, RealRange};

/// A refused flag value: why, and what the flag accepts. The flag and the
/// value are put in front of it when the error is shown ([`render`]).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct ValueError(String);

/// `why`, followed by what is accepted unless `why` already says it.
fn refused(why: impl std::fmt::Display, expected: &str) -> ValueError {
    let why = why.to_string();
    if why.contains("expected") {
        ValueError(why)
    } else {
        ValueError(format!("{why}: expected {expected}"))
    }
}

/// How a real value is read from its text.
type Read = fn(&str) -> Result<f64, ParseError>;

/// A real flag read by `read` (a number, or an angle that accepts `pi`)
/// and checked against `range`.
pub fn real(
    range: RealRange,
    read: Read,
) -> impl Fn(&str) -> Result<String, ValueError> + Clone + Send + Sync + 'static {
    move |text: &str| {
        let value = read(text).map_err(|e| refused(e, range.expected))?;
        range.check(value).map_err(|e| refused(e, range.expected))?;
        Ok(text.to_string())
    }
}

/// A number (`parse_number`) in `range`.
pub fn number(
    range: RealRange,
) -> impl Fn(&str) -> Result<String, ValueError> + Clone + Send + Sync + 'static {
    real(range, parse_number)
}

/// A list `a,b,c` or range `start:stop:step` of values read by `read`,
/// each in `range`.
pub fn list(
    range: RealRange,
    read: Read,
) -> impl Fn(&str) -> Result<String, ValueError> + Clone + Send + Sync + 'static {
    move |text: &str| {
        let values = parse_values(text, read).map_err(|e| refused(e, range.expected))?;
        for v in values {
            range.check(v).map_err(|e| refused(e, range.expected))?;
        }
        Ok(text.to_string())
    }
}

/// A point `x,y` (angles accept `pi`), each coordinate in `range`.
pub fn point(
    range: RealRange,
) -> impl Fn(&str) -> Result<String, ValueError> + Clone + Send + Sync + 'static {
    move |text: &str| {
        let expected = format!("x0,y0 with {} (pi allowed: pi,0.75pi)", range.expected);
        let (x, y) = parse_point(text).map_err(|e| refused(e, &expected))?;
        for v in [x, y] {
            range.check(v).map_err(|e| refused(e, &expected))?;
        }
        Ok(text.to_string())
    }
}

/// A whole number in `range`.
pub fn count(
    range: CountRange,
) -> impl Fn(&str) -> Result<String, ValueError> + Clone + Send + Sync + 'static {
    move |text: &str| {
        let value = text
            .trim()
            .parse::<usize>()
            .map_err(|_| refused(format!("'{text}' is not a whole number"), range.expected))?;
        range.check(value).map_err(|e| refused(e, range.expected))?;
        Ok(text.to_string())
    }
}

/// The one-line message of a value that a parser of this module refused,
/// in the form of [`super::bad_flag`] (`--flag value: why: expected ...`);
/// `None` for any other command-line error.
pub fn render(e: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if e.kind() != ErrorKind::ValueValidation {
        return None;
    }
    let why = std::error::Error::source(e)?.downcast_ref::<ValueError>()?;
    let text = |kind| match e.get(kind) {
        Some(ContextValue::String(s)) => Some(s.as_str()),
        _ => None,
    };
    // clap names the argument `--lambda <LAMBDA>`: the flag is its first word.
    let flag = text(ContextKind::InvalidArg)?.split_whitespace().next()?;
    let value = text(ContextKind::InvalidValue)?;
    Some(format!("{flag} {value}: {why}"))
}
