//! The CSV codec: every CSV this crate writes starts with `# key = value`
//! comment lines that say what made it (the tool's version, the model, the
//! discretisation and the grid), then the column header, then the rows.
//!
//! pandas (`comment="#"`), polars (`comment_prefix="#"`) and spreadsheets
//! read such files as they are. `--resume` and `merge` compare the comment
//! lines with those of the command that continues the file and refuse any
//! difference, naming the key; every row they keep is validated
//! ([`sweep_row_key`]).

use std::fmt::Write as _;

use crate::analysis::case::Case;
use crate::analysis::limit::Limit;
use crate::analysis::sweep::{SweepSpec, CSV_HEADER};
use crate::io::read::escape_text;
use crate::model::{Discretisation, LoadPoint, Material};
use crate::stepping::steady::SteadyState;

/// The version of the tool that wrote a file, as its first comment line says.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The comment lines of a CSV: ordered `key = value` pairs.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Metadata {
    entries: Vec<(String, String)>,
}

/// Comment lines that differ from those expected, or cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MetadataError {
    /// A key whose value differs.
    #[error("it was made with {key} = {found}, but this command has {key} = {expected}")]
    Differs {
        /// The key.
        key: String,
        /// The file's value.
        found: String,
        /// This command's value.
        expected: String,
    },
    /// A key this command has and the file lacks (or the reverse).
    #[error("its header lacks '# {key} = {expected}' (it was not written by this version of shakedown with these flags)")]
    Missing {
        /// The key.
        key: String,
        /// This command's value.
        expected: String,
    },
    /// A key the file has and this command does not.
    #[error("its header has '{key}', which this command does not write")]
    Extra {
        /// The key.
        key: String,
    },
    /// Not a file of this tool.
    #[error("its header does not start with '# shakedown = <version>': it is not an output of shakedown")]
    Foreign,
}

impl Metadata {
    /// Metadata naming the tool, its version and the table (`sweep`,
    /// `limit`, `memory`, ...).
    pub fn new(table: &str) -> Self {
        let mut m = Self::default();
        m.push("shakedown", VERSION);
        m.push("table", table);
        m
    }

    /// Add `key = value` (values are kept on one line).
    pub fn push(&mut self, key: &str, value: impl ToString) -> &mut Self {
        let value = value.to_string().replace(['\n', '\r'], " ");
        self.entries.push((key.to_string(), value));
        self
    }

    /// Set `key` to `value`: in place if present, else at the end.
    pub fn set(&mut self, key: &str, value: impl ToString) -> &mut Self {
        let value = value.to_string().replace(['\n', '\r'], " ");
        match self.entries.iter_mut().find(|(k, _)| k == key) {
            Some(e) => e.1 = value,
            None => self.entries.push((key.to_string(), value)),
        }
        self
    }

    /// The value of `key`, if present.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The pairs, in order.
    pub fn entries(&self) -> &[(String, String)] {
        &self.entries
    }

    /// The comment lines, each ending in a newline.
    pub fn render(&self) -> String {
        let mut s = String::new();
        for (k, v) in &self.entries {
            let _ = writeln!(s, "# {k} = {v}");
        }
        s
    }

    /// The comment lines and then the column header, without the final
    /// newline: what [`crate::io::batch::resume_point`] and
    /// [`crate::io::batch::merge`] take as the header.
    pub fn preamble(&self, columns: &str) -> String {
        format!("{}{columns}", self.render())
    }

    /// Read the complete leading `# key = value` lines of `text` (a last
    /// line without its newline is ignored).
    pub fn parse(text: &str) -> Self {
        let mut m = Self::default();
        for line in text.split_inclusive('\n') {
            let Some(line) = line.strip_suffix('\n') else {
                break;
            };
            let Some(rest) = line.strip_prefix("# ") else {
                break;
            };
            let (k, v) = rest.split_once(" = ").unwrap_or((rest, ""));
            m.entries.push((k.to_string(), v.to_string()));
        }
        m
    }

    /// Compare a file's comment lines `found` with these (expected) ones:
    /// the first key that differs, is missing or is extra.
    ///
    /// # Errors
    ///
    /// [`MetadataError`] naming the key.
    pub fn check(&self, found: &Metadata) -> Result<(), MetadataError> {
        if found.get("shakedown").is_none() {
            return Err(MetadataError::Foreign);
        }
        for (k, v) in &self.entries {
            match found.get(k) {
                None => {
                    return Err(MetadataError::Missing {
                        key: k.clone(),
                        expected: v.clone(),
                    })
                }
                Some(f) if f != v => {
                    return Err(MetadataError::Differs {
                        key: k.clone(),
                        found: escape_text(f, 80),
                        expected: abbreviate(v),
                    })
                }
                Some(_) => {}
            }
        }
        if let Some((k, _)) = found.entries.iter().find(|(k, _)| self.get(k).is_none()) {
            return Err(MetadataError::Extra {
                key: escape_text(k, 40),
            });
        }
        Ok(())
    }
}

fn abbreviate(v: &str) -> String {
    escape_text(v, 80)
}

/// Check the comment lines at the start of `content` against `expected`.
/// An empty file, or one cut inside its first comment lines in a way that
/// is still a prefix of the expected ones, passes (it is rewritten).
///
/// # Errors
///
/// [`MetadataError`] naming the first differing key.
pub fn check_preamble(content: &[u8], expected: &Metadata) -> Result<(), MetadataError> {
    let text = String::from_utf8_lossy(&content[..content.len().min(1 << 22)]);
    let rendered = expected.render();
    if rendered.starts_with(text.as_ref()) || text.starts_with(&rendered) {
        return Ok(());
    }
    expected.check(&Metadata::parse(&text))
}

/// The model of a sweep as comment lines: tool, table `sweep`, material,
/// cycle centre and slope, discretisation, cycle cap and the three lists.
pub fn sweep_metadata(spec: &SweepSpec) -> Metadata {
    let mut m = Metadata::new("sweep");
    model_entries(&mut m, &spec.material(), spec.center(), spec.slope());
    disc_entries(&mut m, &spec.disc(), spec.options().convergence.max_cycles);
    m.push("lambda", join(spec.load_factors()));
    m.push("phi", join(spec.phases()));
    let names: Vec<String> = spec.initials().iter().map(|i| i.name()).collect();
    m.push("initial", names.join(" "));
    m
}

/// One case as comment lines (table `table`): the model, the
/// discretisation, `lambda`, `phi` and the initial path.
pub fn case_metadata(table: &str, case: &Case, initial: &str) -> Metadata {
    let mut m = Metadata::new(table);
    model_entries(
        &mut m,
        &case.material,
        case.cycle.center(),
        case.cycle.slope(),
    );
    disc_entries(&mut m, &case.disc, case.options.convergence.max_cycles);
    m.push("lambda", case.cycle.load_factor());
    m.push("phi", case.cycle.phase());
    m.push("initial", initial);
    m
}

fn model_entries(m: &mut Metadata, material: &Material, center: LoadPoint, slope: f64) {
    m.push("friction", material.friction())
        .push("nu", material.poisson())
        .push("plane", material.plane())
        .push("psi", slope)
        .push("center", format!("{},{}", center.x(), center.y()));
}

fn disc_entries(m: &mut Metadata, disc: &Discretisation, max_cycles: usize) {
    m.push("nodes", disc.nodes())
        .push("steps", disc.steps_per_cycle())
        .push("max-cycles", max_cycles);
}

fn join(values: &[f64]) -> String {
    values
        .iter()
        .map(f64::to_string)
        .collect::<Vec<_>>()
        .join(",")
}

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
    f[5].parse::<u64>()
        .map_err(|_| format!("cycles '{}' is not a whole number", escape_text(f[5], 40)))?;
    number("rotation_per_cycle", f[6])?;
    let key_len = f[0].len() + f[1].len() + f[2].len() + 2;
    Ok(&line[..key_len])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_validated() {
        let good = "5.5,0,\"7,-7\",cyclic-slip,0.001,12,0";
        assert_eq!(sweep_row_key(good), Ok("5.5,0,\"7,-7\""));
        assert!(sweep_row_key("5.5,0,\"OA\",failed,NaN,0,NaN").is_ok());
        for bad in [
            "3,0,\"7,-7\",GARBAGE,xx,yy,zz",
            "3,0,\"OA\",shakedown,NaN,1,0",
            "3,0,\"OA\",shakedown,0,1",
            "3,0,\"OA\",shakedown,0,1,0,9",
            "x,0,\"OA\",shakedown,0,1,0",
            "inf,0,\"OA\",shakedown,0,1,0",
            "3,0,OA,shakedown,0,1,0",
            "3,0,\"OA\",shakedown,0,-1,0",
        ] {
            assert!(sweep_row_key(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn metadata_round_trips_and_names_the_difference() {
        let mut a = Metadata::new("sweep");
        a.push("friction", 0.5).push("nodes", 64);
        let text = a.preamble(CSV_HEADER);
        assert_eq!(Metadata::parse(&format!("{text}\n")), a);
        let mut b = Metadata::new("sweep");
        b.push("friction", 0.2).push("nodes", 64);
        let e = a.check(&b).unwrap_err();
        assert!(e.to_string().contains("friction = 0.2"), "{e}");
        assert!(check_preamble(b"", &a).is_ok());
        assert!(check_preamble(&text.as_bytes()[..20], &a).is_ok());
        assert_eq!(
            check_preamble(b"lambda,phi\n", &a),
            Err(MetadataError::Foreign)
        );
    }
}
