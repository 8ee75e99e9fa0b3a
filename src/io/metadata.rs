//! The metadata header every CSV of this crate starts with: `# key = value`
//! comment lines that say what made the file (the tool's version, the
//! model, the discretisation and the grid), and numbers in their shortest
//! round-trip form.
//!
//! pandas (`comment="#"`), polars (`comment_prefix="#"`) and spreadsheets
//! read such files as they are. `--resume` and `merge` compare the comment
//! lines with those of the command that continues the file and refuse any
//! difference, naming the key.

use std::fmt::Write as _;

use crate::analysis::case::Case;
use crate::io::read::escape_text;
use crate::model::{Discretisation, LoadPoint, Material};
use crate::stepping::steady::Convergence;

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

/// One case as comment lines (table `table`): the model, the
/// discretisation, `lambda`, `phi` and the initial path.
pub fn case_metadata(table: &str, case: &Case, initial: &str) -> Metadata {
    let mut m = Metadata::new(table);
    model_entries(
        &mut m,
        &case.material(),
        case.cycle().center(),
        case.cycle().slope(),
    );
    disc_entries(&mut m, &case.disc(), &case.options().convergence());
    m.push("lambda", fmt_number(case.cycle().load_factor()));
    m.push("phi", fmt_number(case.cycle().phase()));
    m.push("initial", initial);
    if let Some(p) = case.cycle().as_polyline() {
        polyline_entries(&mut m, p);
    }
    m
}

/// A polyline cycle has no slope or phase: its header names the cycle by
/// content instead (model.md section 5.4).
pub(crate) fn polyline_entries(m: &mut Metadata, polyline: &crate::model::Polyline) {
    m.set("psi", "none");
    m.set("phi", "none");
    m.push("load-cycle", polyline.name());
}

pub(crate) fn model_entries(m: &mut Metadata, material: &Material, center: LoadPoint, slope: f64) {
    m.push("friction", fmt_number(material.friction()))
        .push("nu", fmt_number(material.poisson()))
        .push("plane", material.plane())
        .push("psi", fmt_number(slope))
        .push(
            "center",
            format!("{},{}", fmt_number(center.x()), fmt_number(center.y())),
        );
}

pub(crate) fn disc_entries(m: &mut Metadata, disc: &Discretisation, convergence: &Convergence) {
    m.push("nodes", disc.nodes())
        .push("steps", disc.steps_per_cycle())
        .push("max-cycles", convergence.max_cycles());
    // How shakedown may be proven: with safe states (model.md section 6.4)
    // or only by a cycle without slip (`--run-out`); the cycle counts of
    // asymptotic shakedown differ, so files of the two do not mix.
    m.push(
        "verdicts",
        if convergence.safe_state() {
            "safe-state"
        } else {
            "run-out"
        },
    );
}

/// `x` in its shortest round-trip form, without hundreds of digits: Rust's
/// `{}` (which never uses an exponent) for ordinary magnitudes, `{:e}`
/// (also shortest round-trip) for very small or large ones (`1e-320`).
pub fn fmt_number(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-6..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

pub(crate) fn join(values: &[f64]) -> String {
    values
        .iter()
        .map(|&v| fmt_number(v))
        .collect::<Vec<_>>()
        .join(",")
}

/// The comment lines of `limit --phi LIST`'s curve (table `limit-curve`):
/// only what `lambda_2` depends on, the model, `--nodes`, the phases and the
/// samples of an elliptical cycle (no `lambda`, increments or initial path).
pub fn limit_curve_metadata(
    material: &Material,
    center: LoadPoint,
    slope: f64,
    nodes: usize,
    phases: &[f64],
    samples: usize,
) -> Metadata {
    let mut m = Metadata::new("limit-curve");
    model_entries(&mut m, material, center, slope);
    m.push("nodes", nodes)
        .push("phi", join(phases))
        .push("samples", samples);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_round_trip() {
        for x in [1e-320, 5.5, 0.0, 1e300, -3.3e-6, 0.1 + 0.2, 12345.678] {
            let t = fmt_number(x);
            assert!(t.len() < 25, "{t}");
            assert_eq!(t.parse::<f64>().unwrap(), x, "{t}");
        }
        assert_eq!(fmt_number(5.5), "5.5");
    }

    #[test]
    fn metadata_round_trips_and_names_the_difference() {
        let mut a = Metadata::new("sweep");
        a.push("friction", 0.5).push("nodes", 64);
        let text = a.preamble("lambda,phi");
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
