//! The sweep CSV's reader (the codec's other half is
//! [`crate::analysis::sweep::Row::csv_line`] with
//! [`crate::io::csv::sweep_metadata`]): one [`SweepPoint`] per run, read
//! either from the runs themselves or back from the CSV a figure wrote (so
//! a figure can be redrawn without running anything). `figure --from`
//! checks the file's header and rows before it calls [`parse_sweep_csv`].

use crate::analysis::sweep::{Row, CSV_HEADER};
use crate::stepping::steady::SteadyState;

/// One run of a sweep as the figures see it.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepPoint {
    /// `lambda`.
    pub load_factor: f64,
    /// `phi` in radians.
    pub phase: f64,
    /// The initial path's name (`OA`, `7,-7`, `optimal`, `path:...`).
    pub initial: String,
    /// The steady state, or `None` when the run failed numerically.
    pub state: Option<SteadyState>,
    /// `W` of the last complete cycle (NaN for a failed run).
    pub dissipation: f64,
}

impl SweepPoint {
    /// The point of a finished run.
    pub fn from_row(r: &Row) -> SweepPoint {
        let (state, dissipation) = match &r.outcome {
            Ok(s) => (Some(s.state()), s.dissipation),
            Err(_) => (None, f64::NAN),
        };
        SweepPoint {
            load_factor: r.job.load_factor,
            phase: r.job.phase,
            initial: r.initial.clone(),
            state,
            dissipation,
        }
    }

    /// Whether the run started from the optimal slip of the `lambda_2`
    /// programme.
    pub fn is_optimal(&self) -> bool {
        self.initial == "optimal"
    }
}

/// Why a CSV cannot be read back.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CsvError {
    /// The header is not the one expected.
    #[error("line {line}: expected the header '{expected}'")]
    Header {
        /// 1-based line.
        line: usize,
        /// The expected header.
        expected: String,
    },
    /// A row that cannot be read.
    #[error("line {line}: {message}")]
    Row {
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// The steady state named as in the CSV (`cyclic-slip`), or `None` for
/// `failed`.
pub fn parse_state(word: &str) -> Result<Option<SteadyState>, String> {
    if word == "failed" {
        return Ok(None);
    }
    SteadyState::ALL
        .into_iter()
        .find(|s| s.as_str() == word)
        .map(Some)
        .ok_or_else(|| format!("'{word}' is not a state"))
}

/// The data lines of a CSV: blank lines and `#` comment lines (metadata)
/// are skipped; the first other line must be `header`.
pub fn data_lines<'a>(
    text: &'a str,
    header: &str,
) -> Result<impl Iterator<Item = (usize, &'a str)> + 'a, CsvError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    match lines.next() {
        Some((_, h)) if h.trim() == header => Ok(lines),
        other => Err(CsvError::Header {
            line: other.map_or(1, |(n, _)| n),
            expected: header.to_string(),
        }),
    }
}

/// Read a sweep CSV (the format of `shakedown sweep` and the dissipation
/// figures) back into points. An incomplete last line (an interrupted
/// run) is skipped.
///
/// # Errors
///
/// [`CsvError`] for a wrong header or a row that cannot be read.
pub fn parse_sweep_csv(text: &str) -> Result<Vec<SweepPoint>, CsvError> {
    let lines: Vec<(usize, &str)> = data_lines(text, CSV_HEADER)?.collect();
    let last = lines.len();
    let mut out = Vec::with_capacity(last);
    let mut seen = std::collections::HashSet::with_capacity(last);
    for (k, (n, line)) in lines.into_iter().enumerate() {
        match parse_sweep_line(line) {
            Ok(p) => {
                // One row per run: a repeated key is not a sweep's table.
                let key = (
                    p.load_factor.to_bits(),
                    p.phase.to_bits(),
                    p.initial.clone(),
                );
                if !seen.insert(key) {
                    return Err(CsvError::Row {
                        line: n,
                        message: format!(
                            "a second row for lambda = {}, phi = {}, initial {}",
                            p.load_factor, p.phase, p.initial
                        ),
                    });
                }
                out.push(p)
            }
            Err(_) if k + 1 == last && !text.ends_with('\n') => {}
            Err(message) => return Err(CsvError::Row { line: n, message }),
        }
    }
    Ok(out)
}

fn parse_sweep_line(line: &str) -> Result<SweepPoint, String> {
    let open = line.find(",\"").ok_or("no quoted initial path")?;
    let close = open + 2 + line[open + 2..].find('"').ok_or("unclosed quote")?;
    let initial = line[open + 2..close].to_string();
    let head: Vec<&str> = line[..open].split(',').collect();
    let tail: Vec<&str> = line[close + 1..]
        .strip_prefix(',')
        .ok_or("missing columns")?
        .split(',')
        .collect();
    if head.len() != 2 || tail.len() != 4 {
        return Err(format!("expected 7 columns: {CSV_HEADER}"));
    }
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|_| format!("'{t}' is not a number"))
    };
    Ok(SweepPoint {
        load_factor: num(head[0])?,
        phase: num(head[1])?,
        initial,
        state: parse_state(tail[0].trim())?,
        dissipation: num(tail[1])?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_rows_comments_and_a_cut_last_line() {
        let text = format!(
            "# shakedown 0.1.0\n{CSV_HEADER}\n5.5,0,\"7,-7\",cyclic-slip,0.001,12,0\n5.5,0,\"OA\",failed,NaN,0,NaN\n5.6,0,\"O"
        );
        let p = parse_sweep_csv(&text).unwrap();
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].initial, "7,-7");
        assert_eq!(p[0].state, Some(SteadyState::CyclicSlip));
        assert_eq!(p[1].state, None);
        assert!(parse_sweep_csv("a,b\n").is_err());
        let twice =
            format!("{CSV_HEADER}\n5.5,0,\"OA\",shakedown,0,2,0\n5.5,0,\"OA\",shakedown,0,2,0\n");
        assert!(parse_sweep_csv(&twice).is_err());
        let bad = format!("{CSV_HEADER}\n5.5,0,\"OA\",pie,1,1,0\n");
        assert!(matches!(
            parse_sweep_csv(&bad),
            Err(CsvError::Row { line: 2, .. })
        ));
    }
}
