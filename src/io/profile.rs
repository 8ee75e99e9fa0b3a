//! The fretting profile as CSV (`run --profile FILE`): the case's metadata
//! header, then one row per node (model.md section 4.1).

use std::fmt::Write;

use crate::analysis::case::Case;
use crate::analysis::profile::Profile;
use crate::stepping::Outcome;

use super::csv::case_metadata;

/// The column header of a profile file.
pub const PROFILE_HEADER: &str =
    "theta,p_min,p_max,q_min,q_max,slip_amplitude,slip_accumulated,dissipation,ruiz,wear";

/// The profile of `case` (started on `initial`), with the verdict it came
/// to, as CSV text: metadata, the column header, one row per node.
pub fn profile_csv(case: &Case, initial: &str, summary: &Outcome, profile: &Profile) -> String {
    let mut m = case_metadata("profile", case, initial);
    m.push("state", summary.state())
        .push("cycle", profile.cycle)
        .push("dissipation", profile.total_dissipation());
    let mut out = m.preamble(PROFILE_HEADER);
    out.push('\n');
    for j in 0..profile.theta.len() {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{}",
            profile.theta[j],
            profile.p_min[j],
            profile.p_max[j],
            profile.q_min[j],
            profile.q_max[j],
            profile.slip_amplitude[j],
            profile.slip_accumulated[j],
            profile.dissipation[j],
            profile.ruiz[j],
            profile.wear[j],
        );
    }
    out
}

/// A profile file that cannot be read back.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileFileError {
    /// The first line after the `#` header is not [`PROFILE_HEADER`].
    #[error(
        "it has no '{PROFILE_HEADER}' header line (write one with `shakedown run --profile FILE`)"
    )]
    Header,
    /// A row without ten finite numbers.
    #[error("line {line}: expected ten finite numbers, found '{text}'")]
    Row {
        /// The line number (from 1).
        line: usize,
        /// The row, escaped and shortened.
        text: String,
    },
    /// No rows, or more than the largest node count.
    #[error("it has {0} rows: expected one per node, 16 to 4096")]
    Nodes(usize),
}

/// Read back a profile that [`profile_csv`] wrote: its metadata header and
/// the profile (the verdict cycle from the header's `cycle`, else 0).
///
/// # Errors
///
/// [`ProfileFileError`]: no column header, a bad row, or a row count that
/// is no node count.
pub fn read_profile_csv(text: &str) -> Result<(super::csv::Metadata, Profile), ProfileFileError> {
    let meta = super::csv::Metadata::parse(text);
    let mut lines = text
        .lines()
        .enumerate()
        .skip_while(|(_, l)| l.starts_with('#'));
    match lines.next() {
        Some((_, h)) if h.trim() == PROFILE_HEADER => {}
        _ => return Err(ProfileFileError::Header),
    }
    let max = crate::model::ranges::NODES.max;
    let mut columns: [Vec<f64>; 10] = Default::default();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        if columns[0].len() == max {
            return Err(ProfileFileError::Nodes(max + 1));
        }
        let bad = || ProfileFileError::Row {
            line: i + 1,
            text: super::read::escape_text(line, 80),
        };
        let values: Vec<f64> = line
            .split(',')
            .map(|v| v.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<_>>()
            .ok_or_else(bad)?;
        if values.len() != 10 {
            return Err(bad());
        }
        for (c, v) in columns.iter_mut().zip(values) {
            c.push(v);
        }
    }
    let n = columns[0].len();
    if !crate::model::ranges::NODES.contains(n) {
        return Err(ProfileFileError::Nodes(n));
    }
    let [theta, p_min, p_max, q_min, q_max, slip_amplitude, slip_accumulated, dissipation, ruiz, wear] =
        columns;
    let cycle = meta
        .get("cycle")
        .and_then(|c| c.trim().parse().ok())
        .unwrap_or(0);
    Ok((
        meta,
        Profile {
            cycle,
            theta,
            p_min,
            p_max,
            q_min,
            q_max,
            slip_amplitude,
            slip_accumulated,
            dissipation,
            ruiz,
            wear,
        },
    ))
}
