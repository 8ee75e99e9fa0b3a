//! The sweep CSV, both halves of its codec: the writer ([`row_line`], with
//! the metadata header of [`sweep_metadata`]; `shakedown sweep`, `figure`
//! and the explorer's save all write through it) and the readers: the row
//! check that `--resume`, `merge` and `figure --from` apply to every row
//! they keep ([`sweep_row_key`]), and [`parse_sweep_csv`], one
//! [`SweepPoint`] per run, read either from the runs themselves or back
//! from the CSV a figure wrote (so a figure can be redrawn without running
//! anything).

use crate::analysis::sweep::{Row, SweepSpec, CSV_HEADER};
use crate::io::metadata::{
    disc_entries, fmt_number, join, model_entries, polyline_entries, Metadata,
};
use crate::io::read::escape_text;
use crate::stepping::steady::SteadyState;

/// The key of a row, its first three fields `lambda,phi,"initial"`: what
/// `--resume` and `merge` match rows by. Numbers are in their shortest
/// round-trip form ([`fmt_number`]).
pub fn row_key(load_factor: f64, phase: f64, initial: &str) -> String {
    format!(
        "{},{},\"{initial}\"",
        fmt_number(load_factor),
        fmt_number(phase)
    )
}

/// One row of a sweep (no newline) under [`CSV_HEADER`]: its key
/// ([`row_key`]), the state, `W`, the cycles and the rotation per cycle.
/// Numbers are in their shortest round-trip form (`1e-320`, not 320
/// digits), so the bytes do not depend on the platform or the thread
/// count; a failed run has `NaN` for `W` and the rotation and 0 cycles.
pub fn row_line(row: &Row) -> String {
    let (w, c, r) = match &row.outcome {
        Ok(s) => (s.dissipation, s.cycles, s.rotation_per_cycle),
        Err(_) => (f64::NAN, 0, f64::NAN),
    };
    format!(
        "{},{},{},{},{}",
        row_key(row.job.load_factor, row.job.phase, &row.initial),
        row.state(),
        fmt_number(w),
        c,
        fmt_number(r)
    )
}

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

/// The model of a sweep as comment lines: tool, table `sweep`, material,
/// cycle centre and slope, discretisation, cycle cap and the three lists.
pub fn sweep_metadata(spec: &SweepSpec) -> Metadata {
    let mut m = Metadata::new("sweep");
    model_entries(&mut m, &spec.material(), spec.center(), spec.slope());
    disc_entries(&mut m, &spec.disc(), &spec.options().convergence());
    m.push("lambda", join(spec.load_factors()));
    m.push("phi", join(spec.phases()));
    let names: Vec<String> = spec.initials().iter().map(|i| i.name()).collect();
    m.push("initial", names.join(" "));
    if let Some(p) = spec.polyline() {
        polyline_entries(&mut m, p);
    }
    m
}

/// A sweep's rows as a whole CSV: [`sweep_metadata`]'s comment lines,
/// [`CSV_HEADER`] and one line per row, as `shakedown sweep` writes them.
pub fn sweep_csv<'a>(
    spec: &SweepSpec,
    rows: impl IntoIterator<Item = &'a crate::analysis::sweep::Row>,
) -> String {
    let mut text = sweep_metadata(spec).preamble(CSV_HEADER);
    text.push('\n');
    for row in rows {
        text.push_str(&row_line(row));
        text.push('\n');
    }
    text
}

/// Save a sweep's rows (the explorer's save) to the new file `path` with
/// the metadata header: nothing existing is replaced, no symlink followed
/// ([`crate::io::output::write_new`]).
///
/// # Errors
///
/// [`crate::io::output::WriteError`] naming the path.
pub fn save_sweep_csv<'a>(
    path: &std::path::Path,
    spec: &SweepSpec,
    rows: impl IntoIterator<Item = &'a crate::analysis::sweep::Row>,
) -> Result<(), crate::io::output::WriteError> {
    crate::io::output::write_new(path, sweep_csv(spec, rows).as_bytes())
}

/// [`save_sweep_csv`] over an existing file, which the user agreed to
/// replace: written beside it and renamed over it
/// ([`crate::io::output::write_atomic`]), so a failed write leaves the old
/// file whole.
///
/// # Errors
///
/// [`crate::io::output::WriteError`] naming the path.
pub fn replace_sweep_csv<'a>(
    path: &std::path::Path,
    spec: &SweepSpec,
    rows: impl IntoIterator<Item = &'a crate::analysis::sweep::Row>,
) -> Result<(), crate::io::output::WriteError> {
    crate::io::output::write_atomic(path, sweep_csv(spec, rows).as_bytes())
}

/// The columns of a sweep row, split at commas outside quotes.
fn fields(line: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => {
                out.push(&line[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&line[start..]);
    out
}

/// Validate a row of a sweep CSV ([`CSV_HEADER`]) and return its key, the
/// first three fields `lambda,phi,"initial"`. A row has seven fields:
/// finite `lambda` and `phi`, a quoted initial path, a state word (a
/// [`SteadyState`] or `failed`), `W`, a whole number of cycles and the
/// rotation per cycle; `W` and the rotation are finite except in a failed
/// row (`NaN`).
///
/// # Errors
///
/// What is wrong with the row, in a few words.
pub fn sweep_row_key(line: &str) -> Result<&str, String> {
    checked_row_key(line, None)
}

/// [`sweep_row_key`] for a file whose header caps the cycles of a run at
/// `max_cycles` (`# max-cycles`): a row with more is not a row of it.
pub fn sweep_row_key_capped(max_cycles: u64) -> impl Fn(&str) -> Result<&str, String> {
    move |line| checked_row_key(line, Some(max_cycles))
}

/// The cycle cap a sweep CSV's header records (`# max-cycles = N`), if any.
pub fn header_cycle_cap(meta: &Metadata) -> Option<u64> {
    meta.get("max-cycles").and_then(|v| v.parse().ok())
}

fn checked_row_key(line: &str, cap: Option<u64>) -> Result<&str, String> {
    let f = fields(line);
    if f.len() != 7 {
        return Err(format!("{} fields, expected 7 ({CSV_HEADER})", f.len()));
    }
    let finite = |name: &str, v: &str| -> Result<f64, String> {
        v.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{name} '{}' is not a finite number", escape_text(v, 40)))
    };
    finite("lambda", f[0])?;
    finite("phi", f[1])?;
    let initial = f[2];
    if initial.len() < 3 || !initial.starts_with('"') || !initial.ends_with('"') {
        return Err(format!(
            "initial '{}' is not a quoted path name",
            escape_text(initial, 40)
        ));
    }
    let state = f[3];
    let failed = state == "failed";
    if !failed {
        state.parse::<SteadyState>().map_err(|_| {
            format!(
                "state '{}' is not a known state (or 'failed')",
                escape_text(state, 40)
            )
        })?;
    }
    let number = |name: &str, v: &str| -> Result<(), String> {
        match v.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(()),
            Ok(x) if failed && x.is_nan() => Ok(()),
            _ => Err(format!(
                "{name} '{}' is not a finite number",
                escape_text(v, 40)
            )),
        }
    };
    number("dissipation", f[4])?;
    let cycles = f[5]
        .parse::<u64>()
        .map_err(|_| format!("cycles '{}' is not a whole number", escape_text(f[5], 40)))?;
    number("rotation_per_cycle", f[6])?;
    // Physically valid (model.md section 6): dissipation is never
    // negative, shakedown dissipates nothing, and a run that ended did at
    // least one cycle and no more than the cap.
    if !failed {
        let w: f64 = f[4].parse().unwrap_or(f64::NAN);
        if w < 0.0 {
            return Err(format!("dissipation {} is negative", f[4]));
        }
        if state == "shakedown" && w != 0.0 {
            return Err(format!("state shakedown with dissipation {} (not 0)", f[4]));
        }
        // A terminal event (gross slip, separation) may end a run in its
        // transient, before a whole cycle; every other state needs one.
        let terminal = state == "gross-slip" || state == "separation";
        if cycles == 0 && !terminal {
            return Err(format!(
                "0 cycles for state {state}, which needs a whole cycle"
            ));
        }
        if let Some(cap) = cap.filter(|&c| cycles > c) {
            return Err(format!(
                "{cycles} cycles, more than the cap of {cap} in the header"
            ));
        }
    }
    let key_len = f[0].len() + f[1].len() + f[2].len() + 2;
    Ok(&line[..key_len])
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

    #[test]
    fn rows_are_validated() {
        let good = "5.5,0,\"7,-7\",cyclic-slip,0.001,12,0";
        assert_eq!(sweep_row_key(good), Ok("5.5,0,\"7,-7\""));
        assert!(sweep_row_key("5.5,0,\"OA\",failed,NaN,0,NaN").is_ok());
        assert!(sweep_row_key("8,0,\"OA\",gross-slip,0,0,0").is_ok());
        let capped = sweep_row_key_capped(2000);
        assert!(capped(good).is_ok());
        assert!(capped("5.5,0,\"OA\",cyclic-slip,0.001,2000000,0").is_err());
        for bad in [
            "3,0,\"7,-7\",GARBAGE,xx,yy,zz",
            "3,0,\"OA\",shakedown,NaN,1,0",
            "3,0,\"OA\",shakedown,0,1",
            "3,0,\"OA\",shakedown,0,1,0,9",
            "x,0,\"OA\",shakedown,0,1,0",
            "inf,0,\"OA\",shakedown,0,1,0",
            "3,0,OA,shakedown,0,1,0",
            "3,0,\"OA\",shakedown,0,-1,0",
            "3,0,\"OA\",cyclic-slip,-1,12,0",
            "3,0,\"OA\",cyclic-slip,1,0,0",
            "3,0,\"OA\",shakedown,5.5,3,0",
        ] {
            assert!(sweep_row_key(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn rows_print_numbers_short() {
        assert_eq!(row_key(1e-320, 0.5, "OA"), "1e-320,0.5,\"OA\"");
        assert_eq!(row_key(5.5, 0.0, "7,-7"), "5.5,0,\"7,-7\"");
    }
}
