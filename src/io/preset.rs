//! Presets: the paper's cases as plain, commented TOML files that a user can
//! copy and edit (`presets/*.toml`). The built-in ones are compiled into
//! the binary, so it works from any directory; a name with a `/` or ending
//! in `.toml` is read from disk instead.
//!
//! A preset has a `[case]` table (the base parameters, keys as the command
//! line flags), a `[sweep]` table (the swept lists) and a `[figure]` table
//! (what `shakedown figure` draws). Every key is optional except
//! `description`; missing ones keep the paper's values. Unknown keys are
//! rejected, and every error names the file, the line and the problem.

use std::ops::Range;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

use crate::analysis::case::CaseParams;
use crate::analysis::sweep::{Axis, SweepLists};
use crate::io::parse::{parse_angle, parse_number, parse_values, ParseError};
use crate::model::path::Initial;
use crate::model::{Cycle, Discretisation, LoadPoint, Material, ParamError, Plane};

/// The built-in presets: name and TOML text, in listing order.
pub const BUILTIN: [(&str, &str); 9] = [
    ("fig3", include_str!("../../presets/fig3.toml")),
    ("fig4", include_str!("../../presets/fig4.toml")),
    ("fig5", include_str!("../../presets/fig5.toml")),
    ("fig6", include_str!("../../presets/fig6.toml")),
    ("fig7", include_str!("../../presets/fig7.toml")),
    ("fig8", include_str!("../../presets/fig8.toml")),
    ("fig9", include_str!("../../presets/fig9.toml")),
    ("regime", include_str!("../../presets/regime.toml")),
    ("biharmonic", include_str!("../../presets/biharmonic.toml")),
];

/// A preset that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PresetError {
    /// The name is neither a built-in preset nor a path to a file.
    #[error("preset '{name}' is not known: expected one of {known}, or a path to a .toml file")]
    Unknown {
        /// The name asked for.
        name: String,
        /// The built-in names, comma separated ([`builtin_names`]).
        known: String,
    },
    /// The preset file could not be read (missing, unreadable, too large
    /// or not UTF-8).
    #[error("{file}: cannot read the preset: {message}")]
    Read {
        /// The path, as given (escaped for display).
        file: String,
        /// Why it could not be read.
        message: String,
    },
    /// A value in the file is wrong: bad TOML, an unknown key, a value out
    /// of range; the error points at its line.
    #[error("{file}:{line}: {message}")]
    Invalid {
        /// The file, as named in errors (`presets/fig3.toml`).
        file: String,
        /// The 1-based line of the offending key or value.
        line: usize,
        /// What is wrong, naming the key (`case.friction: ...`).
        message: String,
    },
    /// The file is wrong as a whole, with no one line to point at (a
    /// missing key, a combination of values, a sweep over the run cap).
    #[error("{file}: {message}")]
    InvalidFile {
        /// The file, as named in errors (`presets/fig3.toml`).
        file: String,
        /// What is wrong.
        message: String,
    },
}

/// What `shakedown figure` draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FigureKind {
    /// Steady-state `W` with state markers against `lambda` or `phi`
    /// (Figs. 3, 6, 8, 9).
    Dissipation,
    /// The memory measures `R` and `r` against `lambda` (Fig. 4).
    Memory,
    /// Slip zones over one steady cycle next to the load variation
    /// (Figs. 5, 7).
    SlipMap,
    /// The steady state over the `(lambda, phi)` plane for one transient,
    /// with `lambda_2(phi)` (the regime map).
    Regime,
}

/// How ratchetting is marked: the paper uses two conventions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RatchettingMarkers {
    /// Fig. 3: a red dot with a blue edge for any ratchetting.
    Edge,
    /// Fig. 8: a blue circle for monotonic, a blue circle with a red dot
    /// for non-monotonic ratchetting.
    Monotonicity,
}

/// The `[figure]` table, resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureSpec {
    /// Which figure to draw (`kind`).
    pub kind: FigureKind,
    /// The swept variable on the horizontal axis, λ (`load_factor`) or φ
    /// (`phase`) (`x`; default `lambda`).
    pub axis: Axis,
    /// How ratchetting is marked (`ratchetting`; default `edge`, as in
    /// Fig. 3).
    pub ratchetting: RatchettingMarkers,
    /// Mark `lambda_2` (by linear programming) on the plot.
    pub limit: bool,
    /// Join the points of each series (one series per value of the
    /// variable not on the axis, and per initial path).
    pub lines: bool,
    /// Plot title; the preset's description when absent.
    pub title: Option<String>,
}

/// A loaded, validated preset.
#[derive(Debug, Clone, PartialEq)]
pub struct Preset {
    /// The preset's name (`name`, or the file's stem): also the stem of
    /// the files `shakedown figure` writes.
    pub name: String,
    /// One line saying what the preset computes (`description`).
    pub description: String,
    /// Where it came from, as named in errors (`presets/fig3.toml`).
    pub file: String,
    /// The base case.
    pub params: CaseParams,
    /// The swept lists of λ (`load_factor`), φ (`phase`) and initial
    /// transients (`[sweep]`); a key that is absent sweeps the base case's
    /// single value.
    pub sweep: SweepLists,
    /// What `shakedown figure` draws (`[figure]`), if the preset says.
    pub figure: Option<FigureSpec>,
    /// A custom transient `O -> points -> A` (`[case] initial-path`), which
    /// `run` and `tui` use instead of `initial`; a sweep without its own
    /// `initial` list runs it alone, one with a list runs it last.
    pub initial_path: Option<Initial>,
}

/// Names of the built-in presets, comma separated.
pub fn builtin_names() -> String {
    BUILTIN.map(|(n, _)| n).join(", ")
}

/// Load a built-in preset by name, or a file when `name` contains a path
/// separator or ends in `.toml`.
///
/// Built-in names are matched ignoring ASCII case and surrounding spaces.
///
/// # Errors
///
/// [`PresetError::Unknown`] for a name that is not built in;
/// [`PresetError::Read`] when the file cannot be read; otherwise as
/// [`parse`].
pub fn load(name: &str) -> Result<Preset, PresetError> {
    let looks_like_path = name.contains('/') || name.contains('\\') || name.ends_with(".toml");
    if looks_like_path {
        let shown = crate::io::read::escape_text(name, 200);
        let text = crate::io::read::read_text_capped(
            std::path::Path::new(name),
            crate::io::read::MAX_PRESET_BYTES,
        )
        .map_err(|e| PresetError::Read {
            file: shown.clone(),
            message: e.to_string(),
        })?;
        let stem = std::path::Path::new(name)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or(name);
        return parse(&text, &shown, stem);
    }
    let found = BUILTIN
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name.trim()));
    match found {
        Some((n, text)) => parse(text, &format!("presets/{n}.toml"), n),
        None => Err(PresetError::Unknown {
            name: name.to_string(),
            known: builtin_names(),
        }),
    }
}

/// Every built-in preset, parsed.
pub fn builtin() -> Vec<Result<Preset, PresetError>> {
    BUILTIN
        .iter()
        .map(|(n, text)| parse(text, &format!("presets/{n}.toml"), n))
        .collect()
}

/// A number as a preset writes it: a TOML number, or a string read as an
/// angle (`"pi/2"`, `"0.75pi"`).
#[derive(Debug, Clone, PartialEq)]
enum Num {
    Number(f64),
    Text(String),
}

struct NumVisitor;

impl<'de> Visitor<'de> for NumVisitor {
    type Value = Num;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a number, or a string such as \"pi/2\"")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Num, E> {
        Ok(Num::Number(v))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Num, E> {
        Ok(Num::Number(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Num, E> {
        Ok(Num::Number(v as f64))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Num, E> {
        Ok(Num::Text(v.to_string()))
    }
}

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NumVisitor)
    }
}

impl Num {
    fn angle(&self) -> Result<f64, ParseError> {
        match self {
            Num::Number(v) => Ok(*v),
            Num::Text(t) => parse_angle(t),
        }
    }
    fn number(&self) -> Result<f64, ParseError> {
        match self {
            Num::Number(v) => Ok(*v),
            Num::Text(t) => parse_number(t),
        }
    }
}

/// A swept list: a number, a string (a list `"1,2,3"` or a range
/// `"start:stop:step"`), or an array of numbers.
#[derive(Debug, Clone, PartialEq)]
enum Values {
    One(Num),
    Many(Vec<Num>),
}

struct ValuesVisitor;

impl<'de> Visitor<'de> for ValuesVisitor {
    type Value = Values;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a number, a list or range as a string (\"3:7.5:0.05\"), or an array")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Values, E> {
        Ok(Values::One(Num::Number(v)))
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Values, E> {
        Ok(Values::One(Num::Number(v as f64)))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Values, E> {
        Ok(Values::One(Num::Number(v as f64)))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Values, E> {
        Ok(Values::One(Num::Text(v.to_string())))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Values, A::Error> {
        let mut out = Vec::new();
        while let Some(v) = seq.next_element::<Num>()? {
            out.push(v);
        }
        Ok(Values::Many(out))
    }
}

impl<'de> Deserialize<'de> for Values {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ValuesVisitor)
    }
}

impl Values {
    fn read(&self, item: impl Fn(&str) -> Result<f64, ParseError>) -> Result<Vec<f64>, String> {
        let out = match self {
            Values::One(Num::Number(v)) => vec![*v],
            Values::One(Num::Text(t)) => parse_values(t, &item).map_err(|e| e.to_string())?,
            Values::Many(items) if items.len() > crate::io::parse::MAX_VALUES => {
                return Err(format!(
                    "the list has {} values: at most {} are allowed",
                    items.len(),
                    crate::io::parse::MAX_VALUES
                ))
            }
            Values::Many(items) => items
                .iter()
                .map(|n| match n {
                    Num::Number(v) => Ok(*v),
                    Num::Text(t) => item(t),
                })
                .collect::<Result<Vec<f64>, ParseError>>()
                .map_err(|e| e.to_string())?,
        };
        if out.is_empty() {
            return Err("the list is empty".into());
        }
        Ok(out)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileToml {
    name: Option<Spanned<String>>,
    description: Spanned<String>,
    #[serde(default)]
    case: CaseToml,
    #[serde(default)]
    sweep: SweepToml,
    figure: Option<FigureToml>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct CaseToml {
    lambda: Option<Spanned<Num>>,
    phi: Option<Spanned<Num>>,
    psi: Option<Spanned<Num>>,
    center: Option<Spanned<Vec<Num>>>,
    friction: Option<Spanned<Num>>,
    nu: Option<Spanned<Num>>,
    plane: Option<Spanned<Plane>>,
    initial: Option<Spanned<String>>,
    initial_path: Option<Spanned<Vec<Vec<Num>>>>,
    cycle: Option<Spanned<CycleToml>>,
    nodes: Option<Spanned<usize>>,
    steps: Option<Spanned<usize>>,
    max_cycles: Option<Spanned<usize>>,
}

/// `cycle = "FILE"` (a cycle CSV, relative to the preset's folder) or an
/// inline `cycle = [[u, v], ...]` (model.md section 5.4).
#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum CycleToml {
    File(String),
    Inline(Vec<Vec<Num>>),
}

/// The polyline of a preset's `cycle` key.
fn cycle_of(ctx: &Ctx, v: &Spanned<CycleToml>) -> Result<crate::model::Polyline, PresetError> {
    let at = |e: String| ctx.at(v.span(), format!("case.cycle: {e}"));
    match v.get_ref() {
        CycleToml::File(name) => {
            let path = std::path::Path::new(name);
            let path = match std::path::Path::new(ctx.file).parent() {
                Some(dir) if path.is_relative() => dir.join(path),
                _ => path.to_path_buf(),
            };
            crate::io::cycle::read_cycle_file(&path)
                .map_err(|e| at(format!("{}: {e}", crate::io::read::escape_text(name, 200))))
        }
        CycleToml::Inline(rows) => {
            let mut vertices = Vec::with_capacity(rows.len());
            for row in rows {
                if row.len() != 2 {
                    return Err(at(format!(
                        "expected vertices [u, v], found one with {} values",
                        row.len()
                    )));
                }
                let u = row[0].angle().map_err(|e| at(e.to_string()))?;
                let w = row[1].angle().map_err(|e| at(e.to_string()))?;
                vertices.push(LoadPoint::new(u, w));
            }
            crate::io::cycle::inline_cycle(vertices).map_err(|e| at(e.to_string()))
        }
    }
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepToml {
    lambda: Option<Spanned<Values>>,
    phi: Option<Spanned<Values>>,
    initial: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FigureToml {
    kind: Spanned<FigureKind>,
    x: Option<Spanned<Axis>>,
    ratchetting: Option<RatchettingMarkers>,
    limit: Option<bool>,
    lines: Option<bool>,
    title: Option<String>,
}

/// 1-based line of a byte offset.
fn line_of(text: &str, offset: usize) -> usize {
    let end = offset.min(text.len());
    text.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

struct Ctx<'a> {
    text: &'a str,
    file: &'a str,
}

impl Ctx<'_> {
    fn at(&self, span: Range<usize>, message: impl Into<String>) -> PresetError {
        PresetError::Invalid {
            file: self.file.to_string(),
            line: line_of(self.text, span.start),
            message: message.into(),
        }
    }
    fn whole(&self, message: impl Into<String>) -> PresetError {
        PresetError::InvalidFile {
            file: self.file.to_string(),
            message: message.into(),
        }
    }
}

/// Parse and validate preset text. `file` names it in errors; `default_name`
/// is used when the file has no `name`.
///
/// # Errors
///
/// [`PresetError::Invalid`] with the line of the offending key or value
/// (bad TOML, an unknown key, an empty name or description, a parameter
/// out of range, a value, list or initial path that does not parse);
/// [`PresetError::InvalidFile`] where no one line is at fault (e.g. a
/// sweep with more runs than the cap, or an unusable name taken from the
/// file name).
pub fn parse(text: &str, file: &str, default_name: &str) -> Result<Preset, PresetError> {
    let ctx = Ctx { text, file };
    let raw: FileToml = toml::from_str(text).map_err(|e| {
        let message = e.message().trim().to_string();
        match e.span() {
            Some(span) => ctx.at(span, message),
            None => ctx.whole(message),
        }
    })?;
    let name = raw
        .name
        .as_ref()
        .map(|n| n.get_ref().trim().to_string())
        .unwrap_or_else(|| default_name.to_string());
    if let Some(n) = &raw.name {
        if n.get_ref().trim().is_empty() {
            return Err(ctx.at(n.span(), "name: must not be empty"));
        }
    }
    // The name becomes a file name (`figure`): it must stay in its folder.
    if let Err(why) = crate::io::output::check_file_stem(&name) {
        let shown = crate::io::read::escape_text(&name, 60);
        return Err(match &raw.name {
            Some(n) => ctx.at(n.span(), format!("name '{shown}': {why}")),
            None => ctx.whole(format!("name '{shown}' (from the file name): {why}")),
        });
    }
    let description = raw.description.get_ref().trim().to_string();
    if description.is_empty() || description.contains('\n') {
        return Err(ctx.at(
            raw.description.span(),
            "description: must be one non-empty line",
        ));
    }

    let mut params = case_params(&ctx, &raw.case)?;
    if let Some(v) = &raw.case.cycle {
        for (key, given) in [
            ("phi", raw.case.phi.is_some()),
            ("psi", raw.case.psi.is_some()),
        ] {
            if given {
                return Err(ctx.at(
                    v.span(),
                    format!("case.cycle: a polyline cycle has no {key}: remove case.{key}"),
                ));
            }
        }
        if raw.sweep.phi.is_some() {
            return Err(ctx.at(
                v.span(),
                "case.cycle: a polyline cycle has no phase: remove sweep.phi",
            ));
        }
        let polyline = cycle_of(&ctx, v)?;
        Cycle::polyline(
            LoadPoint::new(params.center.0, params.center.1),
            params.load_factor,
            polyline.clone(),
        )
        .and_then(|c| c.check_steps(params.steps))
        .map_err(|e| ctx.at(v.span(), format!("case.cycle: {e}")))?;
        params.cycle = Some(polyline);
    }
    let mut sweep = sweep_lists(&ctx, &raw.sweep, &params)?;
    let initial_path = match &raw.case.initial_path {
        None => None,
        Some(v) => {
            let at = |e: String| ctx.at(v.span(), format!("case.initial-path: {e}"));
            let mut points = Vec::new();
            for pair in v.get_ref() {
                if pair.len() != 2 {
                    return Err(at(format!(
                        "expected points [x, y] (e.g. [[\"1.75pi\", \"-1.75pi\"]]), found one with {} values",
                        pair.len()
                    )));
                }
                let x = pair[0].angle().map_err(|e| at(e.to_string()))?;
                let y = pair[1].angle().map_err(|e| at(e.to_string()))?;
                points.push(LoadPoint::new(x, y));
            }
            let material = Material::new(params.friction, params.poisson, params.plane)
                .map_err(|e| at(e.to_string()))?;
            let custom = Initial::custom_for(points, &material).map_err(|e| at(e.to_string()))?;
            if raw.sweep.initial.is_none() {
                sweep.initials = vec![custom.clone()];
            } else if !sweep.initials.contains(&custom) {
                sweep.initials.push(custom.clone());
            }
            Some(custom)
        }
    };
    let figure = raw
        .figure
        .as_ref()
        .map(|f| figure_spec(&ctx, f, &sweep))
        .transpose()?;
    Ok(Preset {
        name,
        description,
        file: file.to_string(),
        params,
        sweep,
        figure,
        initial_path,
    })
}

fn case_params(ctx: &Ctx, c: &CaseToml) -> Result<CaseParams, PresetError> {
    let mut p = CaseParams::default();
    let number = |key: &str, v: &Spanned<Num>| {
        v.get_ref()
            .number()
            .map_err(|e| ctx.at(v.span(), format!("case.{key}: {e}")))
    };
    let angle = |key: &str, v: &Spanned<Num>| {
        v.get_ref()
            .angle()
            .map_err(|e| ctx.at(v.span(), format!("case.{key}: {e}")))
    };
    if let Some(v) = &c.lambda {
        p.load_factor = number("lambda", v)?;
    }
    if let Some(v) = &c.phi {
        p.phase = angle("phi", v)?;
    }
    if let Some(v) = &c.psi {
        p.slope = number("psi", v)?;
    }
    if let Some(v) = &c.center {
        let items = v.get_ref();
        if items.len() != 2 {
            return Err(ctx.at(
                v.span(),
                format!(
                    "case.center: expected two values [x0, y0], found {}",
                    items.len()
                ),
            ));
        }
        let read = |n: &Num| {
            n.angle()
                .map_err(|e| ctx.at(v.span(), format!("case.center: {e}")))
        };
        p.center = (read(&items[0])?, read(&items[1])?);
    }
    if let Some(v) = &c.friction {
        p.friction = number("friction", v)?;
    }
    if let Some(v) = &c.nu {
        p.poisson = number("nu", v)?;
    }
    if let Some(v) = &c.plane {
        p.plane = *v.get_ref();
    }
    if let Some(v) = &c.initial {
        let text = v.get_ref().trim();
        p.initial = if text.eq_ignore_ascii_case("optimal") {
            Initial::Optimal
        } else {
            Initial::parse(text).map_err(|e| ctx.at(v.span(), format!("case.initial: {e}")))?
        };
    }
    if let Some(v) = &c.nodes {
        p.nodes = *v.get_ref();
    }
    if let Some(v) = &c.steps {
        p.steps = *v.get_ref();
    }
    if let Some(v) = &c.max_cycles {
        p.max_cycles = *v.get_ref();
    }

    // Validate each group of values and point at the key that is wrong.
    let span_of = |name: &str| -> Option<Range<usize>> {
        match name {
            "lambda" => c.lambda.as_ref().map(Spanned::span),
            "phi" => c.phi.as_ref().map(Spanned::span),
            "psi" => c.psi.as_ref().map(Spanned::span),
            "x0" | "y0" | "center" => c.center.as_ref().map(Spanned::span),
            "friction" => c.friction.as_ref().map(Spanned::span),
            "nu" => c.nu.as_ref().map(Spanned::span),
            "nodes" => c.nodes.as_ref().map(Spanned::span),
            "steps" => c.steps.as_ref().map(Spanned::span),
            _ => None,
        }
    };
    let param_error = |e: ParamError| {
        let name = e.name();
        match span_of(name) {
            Some(span) => ctx.at(span, format!("case: {e}")),
            None => ctx.whole(format!("case: {e}")),
        }
    };
    Material::new(p.friction, p.poisson, p.plane).map_err(param_error)?;
    Cycle::new(
        LoadPoint::new(p.center.0, p.center.1),
        p.load_factor,
        p.slope,
        p.phase,
    )
    .map_err(param_error)?;
    Discretisation::new(p.nodes, p.steps).map_err(param_error)?;
    if !(1..=100_000).contains(&p.max_cycles) {
        let message = format!(
            "case.max-cycles = {} is out of range: expected 1 to 100000",
            p.max_cycles
        );
        return Err(match &c.max_cycles {
            Some(v) => ctx.at(v.span(), message),
            None => ctx.whole(message),
        });
    }
    Ok(p)
}

fn sweep_lists(ctx: &Ctx, s: &SweepToml, p: &CaseParams) -> Result<SweepLists, PresetError> {
    let load_factors = match &s.lambda {
        Some(v) => v
            .get_ref()
            .read(parse_number)
            .map_err(|e| ctx.at(v.span(), format!("sweep.lambda: {e}")))?,
        None => vec![p.load_factor],
    };
    let phases = match &s.phi {
        Some(v) => v
            .get_ref()
            .read(parse_angle)
            .map_err(|e| ctx.at(v.span(), format!("sweep.phi: {e}")))?,
        None => vec![p.phase],
    };
    let center = LoadPoint::new(p.center.0, p.center.1);
    for &l in &load_factors {
        if let Err(e) = Cycle::new(center, l, p.slope, p.phase) {
            let span = s.lambda.as_ref().map(Spanned::span).unwrap_or(0..0);
            return Err(ctx.at(span, format!("sweep.lambda: {e}")));
        }
    }
    for &phi in &phases {
        if let Err(e) = Cycle::new(center, p.load_factor, p.slope, phi) {
            let span = s.phi.as_ref().map(Spanned::span).unwrap_or(0..0);
            return Err(ctx.at(span, format!("sweep.phi: {e}")));
        }
    }
    let initials = match &s.initial {
        Some(v) => Initial::parse_list(v.get_ref())
            .map_err(|e| ctx.at(v.span(), format!("sweep.initial: {e}")))?,
        None => vec![p.initial.clone()],
    };
    let runs = load_factors
        .len()
        .saturating_mul(phases.len())
        .saturating_mul(initials.len());
    if runs > crate::analysis::sweep::MAX_RUNS {
        return Err(ctx.whole(format!(
            "sweep: lambda x phi x initial = {} x {} x {} = {runs} runs, more than the cap of {}",
            load_factors.len(),
            phases.len(),
            initials.len(),
            crate::analysis::sweep::MAX_RUNS
        )));
    }
    Ok(SweepLists {
        load_factors,
        phases,
        initials,
    })
}

fn figure_spec(ctx: &Ctx, f: &FigureToml, sweep: &SweepLists) -> Result<FigureSpec, PresetError> {
    let kind = *f.kind.get_ref();
    let axis = f.x.as_ref().map(|a| *a.get_ref()).unwrap_or(Axis::Lambda);
    if kind == FigureKind::Memory {
        if axis != Axis::Lambda {
            let span = f.x.as_ref().map(Spanned::span).unwrap_or(f.kind.span());
            return Err(ctx.at(span, "figure.x: the memory figure is drawn against lambda"));
        }
        if sweep.phases.len() != 1 {
            return Err(ctx.at(
                f.kind.span(),
                "figure.kind = \"memory\" needs a single phase in [sweep] phi",
            ));
        }
    }
    Ok(FigureSpec {
        kind,
        axis,
        ratchetting: f.ratchetting.unwrap_or(RatchettingMarkers::Edge),
        limit: f.limit.unwrap_or(false),
        lines: f.lines.unwrap_or(false),
        title: f.title.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> PresetError {
        parse(text, "my.toml", "my").unwrap_err()
    }

    #[test]
    fn every_builtin_parses() {
        for p in builtin() {
            let p = p.unwrap();
            assert!(p.figure.is_some(), "{}", p.name);
        }
    }

    #[test]
    fn errors_name_the_line() {
        let e = err("description = \"x\"\n[case]\nfriction = -1\n");
        assert!(
            matches!(&e, PresetError::Invalid { line: 3, file, .. } if file == "my.toml"),
            "{e}"
        );
        assert!(e.to_string().contains("friction"), "{e}");

        let e = err("description = \"x\"\n\n[case]\nlamda = 3\n");
        assert!(matches!(e, PresetError::Invalid { line: 4, .. }), "{e}");
        assert!(e.to_string().contains("lamda"), "{e}");

        let e = err("description = \"x\"\n[sweep]\nphi = \"0:pix:1\"\n");
        assert!(matches!(e, PresetError::Invalid { line: 3, .. }), "{e}");

        let e = err("description = \"x\"\n[case]\nnodes = 7\n");
        assert!(matches!(e, PresetError::Invalid { line: 3, .. }), "{e}");

        let e = err("description = \"x\"\n[sweep]\ninitial = \"OA,4,4\"\n");
        assert!(matches!(e, PresetError::Invalid { line: 3, .. }), "{e}");

        let e = err("description = \"x\"\n[figure]\nkind = \"pie\"\n");
        assert!(matches!(e, PresetError::Invalid { line: 3, .. }), "{e}");

        let e = err("description = \"x\n");
        assert!(matches!(e, PresetError::Invalid { line: 1, .. }), "{e}");
    }

    #[test]
    fn angles_and_defaults() {
        let p = parse(
            "description = \"d\"\n[case]\nphi = \"pi/2\"\ncenter = [\"pi\", 2]\n[sweep]\nlambda = [5, \"5.5\"]\n",
            "f",
            "f",
        )
        .unwrap();
        assert!((p.params.phase - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(p.params.center.1, 2.0);
        assert_eq!(p.sweep.load_factors, vec![5.0, 5.5]);
        assert_eq!(p.sweep.phases, vec![p.params.phase]);
        assert_eq!(p.sweep.initials, vec![Initial::Direct]);
        assert_eq!(p.params.friction, CaseParams::default().friction);
    }

    #[test]
    fn custom_initial_path() {
        let p = parse(
            "description = \"d\"\n[case]\ninitial-path = [[\"1.75pi\", \"-1.75pi\"]]\n",
            "f",
            "f",
        )
        .unwrap();
        let c = p.initial_path.unwrap();
        assert_eq!(p.sweep.initials, vec![c.clone()]);
        assert_eq!(c.name(), "path:1.75pi,-1.75pi");
        let e = err("description = \"d\"\n[case]\ninitial-path = [[0, 7]]\n");
        assert!(matches!(e, PresetError::Invalid { line: 3, .. }), "{e}");
        assert!(e.to_string().contains("gross slip"), "{e}");
    }

    #[test]
    fn unknown_name() {
        assert!(matches!(load("nope"), Err(PresetError::Unknown { .. })));
        assert!(matches!(
            load("/nonexistent/x.toml"),
            Err(PresetError::Read { .. })
        ));
        assert_eq!(load("FIG3").unwrap().name, "fig3");
    }
}
