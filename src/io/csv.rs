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
use crate::analysis::slip_map::{SlipMap, SlipMapRow};
use crate::analysis::sweep::{SweepSpec, CSV_HEADER};
use crate::contact::SlipDirection;
use crate::io::read::escape_text;
use crate::model::{Cycle, Discretisation, LoadPoint, Material, Plane};
use crate::stepping::steady::{Approach, Convergence, SteadyState};
use crate::stepping::{Certificate, Outcome, ShakedownProof, Verdict};

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
    disc_entries(&mut m, &spec.disc(), &spec.options().convergence);
    m.push("lambda", join(spec.load_factors()));
    m.push("phi", join(spec.phases()));
    let names: Vec<String> = spec.initials().iter().map(|i| i.name()).collect();
    m.push("initial", names.join(" "));
    if let Some(p) = spec.polyline() {
        polyline_entries(&mut m, p);
    }
    m
}

/// A polyline cycle has no slope or phase: its header names the cycle by
/// content instead (model.md section 5.4).
fn polyline_entries(m: &mut Metadata, polyline: &crate::model::Polyline) {
    m.set("psi", "none");
    m.set("phi", "none");
    m.push("cycle", polyline.name());
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
        text.push_str(&row.csv_line());
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
    disc_entries(&mut m, &case.disc, &case.options.convergence);
    m.push("lambda", fmt_number(case.cycle.load_factor()));
    m.push("phi", fmt_number(case.cycle.phase()));
    m.push("initial", initial);
    if let Some(p) = case.cycle.as_polyline() {
        polyline_entries(&mut m, p);
    }
    m
}

fn model_entries(m: &mut Metadata, material: &Material, center: LoadPoint, slope: f64) {
    m.push("friction", material.friction())
        .push("nu", material.poisson())
        .push("plane", material.plane())
        .push("psi", slope)
        .push("center", format!("{},{}", center.x(), center.y()));
}

fn disc_entries(m: &mut Metadata, disc: &Discretisation, convergence: &Convergence) {
    m.push("nodes", disc.nodes())
        .push("steps", disc.steps_per_cycle())
        .push("max-cycles", convergence.max_cycles);
    // How shakedown may be proven: with safe states (model.md section 6.4)
    // or only by a cycle without slip (`--run-out`); the cycle counts of
    // asymptotic shakedown differ, so files of the two do not mix.
    m.push(
        "verdicts",
        if convergence.safe_state {
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

fn join(values: &[f64]) -> String {
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

/// The table name of a slip map's CSVs ([`slip_map_metadata`]).
pub const SLIP_MAP_TABLE: &str = "slip-map";

/// The comment lines of a slip map's two CSVs ([`SlipMap::csv`] and
/// [`SlipMap::load_csv`]): the case ([`case_metadata`], table
/// [`SLIP_MAP_TABLE`]) and the outcome of the run to its steady state,
/// so that [`read_slip_map`] can give back the very map drawn.
pub fn slip_map_metadata(case: &Case, map: &SlipMap) -> Metadata {
    let mut m = case_metadata(SLIP_MAP_TABLE, case, &case.initial.name());
    let s = &map.outcome;
    m.push("state", s.state())
        .push("approach", s.approach())
        .push("dissipation", s.dissipation)
        .push("cycles", s.cycles)
        .push("rotation_per_cycle", s.rotation_per_cycle);
    // What proved a shakedown by a safe state, so that the map read back
    // says it too.
    if let Some(c) = s.certificate() {
        m.push(
            "certificate",
            format!(
                "{},{},{},{},{},{}",
                c.cycle, c.margin, c.distance, c.coupling, c.slip_bound, c.last_dissipation
            ),
        );
    }
    m
}

/// Which of a slip map's two files a [`SlipMapReadError`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlipMapFile {
    /// The map: `omega_t,theta,direction` ([`SlipMap::csv`]).
    Map,
    /// The load over the cycle ([`SlipMap::load_csv`]).
    Load,
}

/// Why a slip map's CSV cannot be read back ([`read_slip_map`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SlipMapFileError {
    /// Not an output of shakedown.
    #[error("its header does not start with '# shakedown = <version>': it is not an output of shakedown")]
    Foreign,
    /// Written by another version, whose conventions may differ.
    #[error("it was written by shakedown {found}, but this is {VERSION}: make the figure again")]
    Version {
        /// The version in the file.
        found: String,
    },
    /// Another table (a sweep, a limit).
    #[error("it is a '{found}' table, not a slip map ('# table = {SLIP_MAP_TABLE}')")]
    Kind {
        /// The file's table.
        found: String,
    },
    /// A comment line the reader needs is missing.
    #[error("its header lacks '# {key} = ...' (it was not written by `shakedown figure` for a slip map)")]
    Missing {
        /// The key.
        key: &'static str,
    },
    /// A comment line with a value that cannot be used.
    #[error("'# {key} = {value}' is not valid: {why}")]
    Value {
        /// The key.
        key: &'static str,
        /// The value, escaped.
        value: String,
        /// What is wrong.
        why: String,
    },
    /// The two files are not of the same run.
    #[error("its header differs from the map's: {0}")]
    Mismatch(MetadataError),
    /// The column header is not the expected one.
    #[error("no '{expected}' header line after the comment lines")]
    Header {
        /// The expected header.
        expected: &'static str,
    },
    /// A row that cannot be read.
    #[error("line {line}: {why}: '{text}'")]
    Row {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        why: String,
        /// The line, escaped.
        text: String,
    },
    /// Fewer (or more) rows than the header promises.
    #[error("it has {found} rows, but its header promises {expected} ({what}): it is cut short or was edited")]
    Count {
        /// Rows in the file.
        found: usize,
        /// Rows expected.
        expected: usize,
        /// How the expected count comes about.
        what: String,
    },
}

/// A [`SlipMapFileError`] and the file it is about.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{error}")]
pub struct SlipMapReadError {
    /// The file at fault.
    pub file: SlipMapFile,
    /// What is wrong with it.
    pub error: SlipMapFileError,
}

/// Read a slip map back from its two CSVs as `shakedown figure` writes
/// them (comment lines of [`slip_map_metadata`], then [`SlipMap::csv`] and
/// [`SlipMap::load_csv`]): the same map, so a redraw draws the same figure.
/// Every row is checked: the times and angles in the order written, a
/// direction of `1`, `-1` or `0`, finite loads, and as many rows as the
/// header's nodes and increments give.
///
/// # Errors
///
/// [`SlipMapReadError`], naming the file: not an output of shakedown, of
/// another version, another table, a missing or bad comment line, the two
/// files of different runs, a bad row, or a file cut short.
pub fn read_slip_map(map: &str, load: &str) -> Result<SlipMap, SlipMapReadError> {
    let in_map = |error| SlipMapReadError {
        file: SlipMapFile::Map,
        error,
    };
    let in_load = |error| SlipMapReadError {
        file: SlipMapFile::Load,
        error,
    };
    let meta = slip_map_header(map).map_err(in_map)?;
    let load_meta = slip_map_header(load).map_err(in_load)?;
    meta.check(&load_meta)
        .map_err(|e| in_load(SlipMapFileError::Mismatch(e)))?;
    let head = SlipMapHead::of(&meta).map_err(in_map)?;
    let rows = slip_map_rows(map, &head).map_err(in_map)?;
    let (start, loads) = slip_map_loads(load, &head, &rows).map_err(in_load)?;
    let rows = rows
        .into_iter()
        .zip(loads)
        .map(|((t0, t1, directions), load)| SlipMapRow {
            t0,
            t1,
            load,
            directions,
        })
        .collect();
    Ok(SlipMap {
        material: head.material,
        cycle: head.cycle,
        nodes: head.nodes,
        outcome: head.outcome,
        start,
        rows,
    })
}

/// The comment lines of one of a slip map's files, checked for the tool,
/// its version and the table.
fn slip_map_header(text: &str) -> Result<Metadata, SlipMapFileError> {
    let meta = Metadata::parse(text);
    match meta.get("shakedown") {
        None => return Err(SlipMapFileError::Foreign),
        Some(v) if v != VERSION => {
            return Err(SlipMapFileError::Version {
                found: escape_text(v, 40),
            })
        }
        Some(_) => {}
    }
    match meta.get("table") {
        Some(SLIP_MAP_TABLE) => Ok(meta),
        Some(t) => Err(SlipMapFileError::Kind {
            found: escape_text(t, 40),
        }),
        None => Err(SlipMapFileError::Missing { key: "table" }),
    }
}

/// What a slip map's comment lines say.
struct SlipMapHead {
    material: Material,
    cycle: Cycle,
    nodes: usize,
    steps: usize,
    outcome: Outcome,
}

impl SlipMapHead {
    fn of(meta: &Metadata) -> Result<Self, SlipMapFileError> {
        let get = |key: &'static str| meta.get(key).ok_or(SlipMapFileError::Missing { key });
        let bad = |key: &'static str, value: &str, why: String| SlipMapFileError::Value {
            key,
            value: escape_text(value, 40),
            why,
        };
        let number = |key: &'static str| -> Result<f64, SlipMapFileError> {
            let v = get(key)?;
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| bad(key, v, "not a finite number".into()))
        };
        let count = |key: &'static str| -> Result<usize, SlipMapFileError> {
            let v = get(key)?;
            v.parse::<usize>()
                .map_err(|_| bad(key, v, "not a whole number".into()))
        };
        let plane_text = get("plane")?;
        let plane: Plane = plane_text
            .parse()
            .map_err(|e| bad("plane", plane_text, e))?;
        let material = Material::new(number("friction")?, number("nu")?, plane).map_err(|e| {
            bad(
                "friction",
                get("friction").unwrap_or_default(),
                e.to_string(),
            )
        })?;
        let center_text = get("center")?;
        let center = center_text
            .split_once(',')
            .and_then(|(x, y)| Some(LoadPoint::new(x.parse().ok()?, y.parse().ok()?)))
            .ok_or_else(|| bad("center", center_text, "expected x,y".into()))?;
        let cycle = Cycle::new(center, number("lambda")?, number("psi")?, number("phi")?)
            .map_err(|e| bad("lambda", get("lambda").unwrap_or_default(), e.to_string()))?;
        let nodes = count("nodes")?;
        let steps = count("steps")?;
        // A bound on what a header may ask to be allocated.
        let runs = nodes.checked_mul(steps).filter(|&n| n > 0 && n <= 1 << 26);
        if runs.is_none() {
            return Err(bad(
                "nodes",
                get("nodes")?,
                format!("{nodes} nodes x {steps} increments is not a map this tool writes"),
            ));
        }
        let state_text = get("state")?;
        let state: SteadyState = state_text
            .parse()
            .map_err(|_| bad("state", state_text, "not a steady state".into()))?;
        let approach_text = get("approach")?;
        let approach = Approach::ALL
            .into_iter()
            .find(|a| a.as_str() == approach_text)
            .ok_or_else(|| bad("approach", approach_text, "not a way to a verdict".into()))?;
        let verdict = match (state, approach) {
            (SteadyState::Shakedown, Approach::NoSlipCycle) => {
                Verdict::Shakedown(ShakedownProof::NoSlipCycle)
            }
            (SteadyState::Shakedown, Approach::SafeState) => {
                let text = get("certificate")?;
                let numbers: Option<Vec<f64>> = text
                    .split(',')
                    .map(|v| v.parse::<f64>().ok().filter(|x| x.is_finite()))
                    .collect();
                let c =
                    match numbers.as_deref() {
                        Some(
                            &[cycle, margin, distance, coupling, slip_bound, last_dissipation],
                        ) if cycle >= 0.0 && cycle.fract() == 0.0 => Certificate {
                            cycle: cycle as usize,
                            margin,
                            distance,
                            coupling,
                            slip_bound,
                            last_dissipation,
                        },
                        _ => return Err(bad(
                            "certificate",
                            text,
                            "expected cycle,margin,distance,coupling,slip_bound,last_dissipation"
                                .into(),
                        )),
                    };
                Verdict::Shakedown(ShakedownProof::SafeState(c))
            }
            (SteadyState::Shakedown, Approach::Converged) => {
                Verdict::Shakedown(ShakedownProof::Converged)
            }
            (SteadyState::CyclicSlip, Approach::Converged) => Verdict::CyclicSlip,
            (SteadyState::RatchettingMonotonic, Approach::Converged) => {
                Verdict::Ratchetting { monotonic: true }
            }
            (SteadyState::RatchettingNonMonotonic, Approach::Converged) => {
                Verdict::Ratchetting { monotonic: false }
            }
            (SteadyState::NotConverged, Approach::Cap) => Verdict::NotConverged { trend: None },
            _ => {
                return Err(bad(
                    "approach",
                    approach_text,
                    format!("not how a slip map's state '{state}' is established"),
                ))
            }
        };
        let outcome = Outcome {
            verdict,
            dissipation: number("dissipation")?,
            cycles: count("cycles")?,
            rotation_per_cycle: number("rotation_per_cycle")?,
            level: None,
            steady_rotation: None,
        };
        Ok(Self {
            material,
            cycle,
            nodes,
            steps,
            outcome,
        })
    }
}

/// The data lines after the comment lines and the column header
/// `header`, numbered from 1 as in the file.
fn table_lines<'a>(
    text: &'a str,
    header: &'static str,
) -> Result<impl Iterator<Item = (usize, &'a str)>, SlipMapFileError> {
    let mut lines = text
        .split_inclusive('\n')
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .skip_while(|(_, l)| l.starts_with('#'));
    match lines.next() {
        Some((_, h)) if h.trim_end() == header => Ok(lines),
        _ => Err(SlipMapFileError::Header { expected: header }),
    }
}

/// A complete line's fields, or why not: a last line without its newline
/// is a file cut short.
fn row_fields(n: usize, line: &str, columns: usize) -> Result<Vec<&str>, SlipMapFileError> {
    let row = |why: &str| SlipMapFileError::Row {
        line: n,
        why: why.to_string(),
        text: escape_text(line.trim_end(), 60),
    };
    let Some(body) = line.strip_suffix('\n') else {
        return Err(row("the last line is incomplete (the file is cut short)"));
    };
    let f: Vec<&str> = body.trim_end_matches('\r').split(',').collect();
    if f.len() != columns {
        return Err(row(&format!("expected {columns} columns")));
    }
    Ok(f)
}

/// One increment of the map: `(t0, t1, directions)`.
type MapIncrement = (f64, f64, Vec<SlipDirection>);

fn slip_map_rows(text: &str, head: &SlipMapHead) -> Result<Vec<MapIncrement>, SlipMapFileError> {
    let (nodes, steps) = (head.nodes, head.steps);
    let expected = nodes * steps;
    let mut rows: Vec<MapIncrement> = Vec::with_capacity(steps);
    let mut found = 0;
    let mut t0 = 0.0;
    for (n, line) in table_lines(text, SlipMap::HEADER)? {
        if found == expected {
            found += 1;
            continue;
        }
        let f = row_fields(n, line, 3)?;
        let row = |why: &str| SlipMapFileError::Row {
            line: n,
            why: why.to_string(),
            text: escape_text(line.trim_end(), 60),
        };
        let num = |t: &str| t.parse::<f64>().ok().filter(|x| x.is_finite());
        let (j, k) = (found % nodes, found / nodes);
        let t1 = num(f[0]).ok_or_else(|| row("omega_t is not a finite number"))?;
        let theta = num(f[1]).ok_or_else(|| row("theta is not a finite number"))?;
        let direction = [
            SlipDirection::Forward,
            SlipDirection::Backward,
            SlipDirection::Stick,
        ]
        .into_iter()
        .find(|d| f[2].trim() == d.paper_sign().to_string())
        .ok_or_else(|| row("direction is not 1, -1 or 0"))?;
        let expected_theta = {
            let t = 2.0 * std::f64::consts::PI * j as f64 / nodes as f64;
            if t >= std::f64::consts::PI {
                t - 2.0 * std::f64::consts::PI
            } else {
                t
            }
        };
        if (theta - expected_theta).abs() > 1e-9 {
            return Err(row(&format!(
                "theta is not that of node {j} of {nodes} (the nodes are out of order)"
            )));
        }
        if j == 0 {
            if rows.last().is_some_and(|r| t1 <= r.1) {
                return Err(row("omega_t does not increase"));
            }
            rows.push((t0, t1, Vec::with_capacity(nodes)));
            t0 = t1 % (2.0 * std::f64::consts::PI);
        } else if rows.last().is_some_and(|r| r.1 != t1) {
            return Err(row(&format!(
                "omega_t differs from the other nodes of increment {}",
                k + 1
            )));
        }
        if let Some(r) = rows.last_mut() {
            r.2.push(direction);
        }
        found += 1;
    }
    if found != expected {
        return Err(SlipMapFileError::Count {
            found,
            expected,
            what: format!("{nodes} nodes x {steps} increments"),
        });
    }
    Ok(rows)
}

/// The load at `t = 0` and at the end of every increment.
fn slip_map_loads(
    text: &str,
    head: &SlipMapHead,
    rows: &[MapIncrement],
) -> Result<(LoadPoint, Vec<LoadPoint>), SlipMapFileError> {
    let expected = head.steps + 1;
    let mut points = Vec::with_capacity(expected);
    let mut found = 0;
    for (n, line) in table_lines(text, SlipMap::LOAD_HEADER)? {
        found += 1;
        if found > expected {
            continue;
        }
        let f = row_fields(n, line, 5)?;
        let row = |why: &str| SlipMapFileError::Row {
            line: n,
            why: why.to_string(),
            text: escape_text(line.trim_end(), 60),
        };
        let v: Vec<f64> = f
            .iter()
            .map(|t| t.parse::<f64>().ok().filter(|x| x.is_finite()))
            .collect::<Option<_>>()
            .ok_or_else(|| row("not a finite number"))?;
        let t = if found == 1 { 0.0 } else { rows[found - 2].1 };
        if v[0] != t {
            return Err(row("omega_t is not that of the map's increment"));
        }
        points.push(LoadPoint::new(v[1], v[2]));
    }
    if found != expected {
        return Err(SlipMapFileError::Count {
            found,
            expected,
            what: format!("t = 0 and {} increments", head.steps),
        });
    }
    let start = points.remove(0);
    Ok((start, points))
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
