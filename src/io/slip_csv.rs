//! The optimal slip of `limit --out FILE` (table `optimal-slip`): the
//! writer and the reader that `--initial-slip FILE` uses.

use std::fmt::Write as _;

use crate::analysis::limit::Limit;
use crate::io::metadata::{model_entries, polyline_entries, Metadata};
use crate::io::read::escape_text;
use crate::model::{LoadPoint, Material};

/// Columns of the optimal-slip CSV of `limit`.
pub const SLIP_HEADER: &str = "theta,g";

/// The optimal slip of `limit` as CSV: comment lines (table `optimal-slip`,
/// the model, `phi`, the samples and `lambda_2`), then `theta,g` at every
/// node. [`read_slip_csv`] reads it back.
pub fn slip_csv(
    limit: &Limit,
    material: &Material,
    center: LoadPoint,
    slope: f64,
    phase: f64,
    samples: usize,
) -> String {
    let nodes = limit.slip.len();
    let mut m = Metadata::new("optimal-slip");
    model_entries(&mut m, material, center, slope);
    m.push("nodes", nodes)
        .push("phi", phase)
        .push("samples", if limit.line { 2 } else { samples })
        .push("lambda_2", limit.load_factor);
    slip_rows(&m, limit)
}

/// As [`slip_csv`] for a polyline cycle: the header names the cycle by
/// content in place of `psi` and `phi`, and the samples are its vertices.
pub fn polyline_slip_csv(
    limit: &Limit,
    material: &Material,
    center: LoadPoint,
    polyline: &crate::model::Polyline,
) -> String {
    let mut m = Metadata::new("optimal-slip");
    model_entries(&mut m, material, center, f64::NAN);
    m.push("nodes", limit.slip.len())
        .push("phi", "none")
        .push("samples", polyline.vertices().len())
        .push("lambda_2", limit.load_factor);
    polyline_entries(&mut m, polyline);
    slip_rows(&m, limit)
}

fn slip_rows(m: &Metadata, limit: &Limit) -> String {
    let nodes = limit.slip.len();
    let mut out = m.preamble(SLIP_HEADER);
    out.push('\n');
    for (j, g) in limit.slip.iter().enumerate() {
        let theta = 2.0 * std::f64::consts::PI * j as f64 / nodes as f64;
        let _ = writeln!(out, "{theta},{g}");
    }
    out
}

/// A slip file that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SlipFileError {
    /// No `theta,g` header.
    #[error("it has no '{SLIP_HEADER}' header line (write one with `shakedown limit --out FILE`)")]
    Header,
    /// A bad row.
    #[error("line {line}: {why}: '{text}'")]
    Row {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        why: String,
        /// The line, escaped.
        text: String,
    },
    /// Another node count.
    #[error("it has {found} nodes, but this command has --nodes {expected}")]
    Nodes {
        /// Rows in the file.
        found: usize,
        /// `--nodes`.
        expected: usize,
    },
}

/// Read an optimal-slip CSV (as [`slip_csv`] writes it): the slip `g` at
/// each of `nodes` equally spaced nodes, every value finite.
///
/// # Errors
///
/// [`SlipFileError`]: no header, a bad row, or another node count.
pub fn read_slip_csv(text: &str, nodes: usize) -> Result<Vec<f64>, SlipFileError> {
    let mut lines = text
        .lines()
        .enumerate()
        .skip_while(|(_, l)| l.starts_with('#'));
    match lines.next() {
        Some((_, h)) if h.trim() == SLIP_HEADER => {}
        _ => return Err(SlipFileError::Header),
    }
    let mut slip = Vec::new();
    for (i, line) in lines {
        let bad = |why: &str| SlipFileError::Row {
            line: i + 1,
            why: why.to_string(),
            text: escape_text(line, 80),
        };
        if slip.len() > nodes {
            break;
        }
        let (theta, g) = line
            .split_once(',')
            .ok_or_else(|| bad("expected theta,g"))?;
        let theta: f64 = theta
            .trim()
            .parse()
            .map_err(|_| bad("theta is not a number"))?;
        let g: f64 = g.trim().parse().map_err(|_| bad("g is not a number"))?;
        if !theta.is_finite() || !g.is_finite() {
            return Err(bad("not a finite number"));
        }
        slip.push(g);
    }
    if slip.len() != nodes {
        return Err(SlipFileError::Nodes {
            found: if slip.len() > nodes {
                text.lines().filter(|l| !l.starts_with('#')).count() - 1
            } else {
                slip.len()
            },
            expected: nodes,
        });
    }
    Ok(slip)
}
