//! Preset text to a [`Preset`]: the TOML tables as serde reads them, then
//! each value checked and turned into the model's types, every error naming
//! the file and the line.

use std::ops::Range;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

use crate::analysis::case::CaseParams;
use crate::analysis::sweep::{Axis, SweepLists};
use crate::io::parse::{parse_angle, parse_number, parse_values, ParseError};
use crate::model::path::Initial;
use crate::model::{Cycle, Discretisation, LoadPoint, Material, ParamError, Plane};

use super::{FigureKind, FigureSpec, Preset, PresetError, RatchettingMarkers};

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
