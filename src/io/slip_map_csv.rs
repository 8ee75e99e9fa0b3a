//! A slip map's two CSVs (`figure fig5`, `fig7`): the map
//! ([`SlipMap::csv`]) and the load over its cycle ([`SlipMap::load_csv`]),
//! with the metadata header that lets [`read_slip_map`] give back the very
//! map drawn.

use crate::analysis::case::Case;
use crate::analysis::slip_map::{SlipMap, SlipMapRow};
use crate::contact::SlipDirection;
use crate::io::cycle::{check_recorded_cycle, CycleMatchError, LOAD_CYCLE_KEY};
use crate::io::metadata::{case_metadata, Metadata, MetadataError, VERSION};
use crate::io::read::escape_text;
use crate::model::{Cycle, LoadPoint, Material, Plane, Polyline};
use crate::stepping::steady::{Approach, SteadyState};
use crate::stepping::{Certificate, Outcome, ShakedownProof, Verdict};

/// The table name of a slip map's CSVs ([`slip_map_metadata`]).
pub const SLIP_MAP_TABLE: &str = "slip-map";

/// The comment lines of a slip map's two CSVs ([`SlipMap::csv`] and
/// [`SlipMap::load_csv`]): the case ([`case_metadata`], table
/// [`SLIP_MAP_TABLE`]) and the outcome of the run to its steady state,
/// so that [`read_slip_map`] can give back the very map drawn.
pub fn slip_map_metadata(case: &Case, map: &SlipMap) -> Metadata {
    let mut m = case_metadata(SLIP_MAP_TABLE, case, &case.initial().name());
    let s = &map.outcome;
    m.push("state", s.state())
        .push("approach", s.approach())
        .push("dissipation", s.dissipation)
        .push("cycles", s.cycles)
        .push("rotation_per_cycle", s.rotation_per_cycle)
        // Rows are the cycle's straight sub-segments (increments split at
        // events), so their number is not the increments'.
        .push("rows", map.rows.len());
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
    /// A map of a polyline cycle without that cycle, or with another one
    /// (or an ellipse's map with a polyline).
    #[error(transparent)]
    Cycle(#[from] CycleMatchError),
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
/// A map of a polyline cycle is read with that cycle, `polyline`, whose
/// content the header records ([`check_recorded_cycle`]); a map of the
/// paper's ellipse, with `None`. Every row is checked: the times and angles in the order written, a
/// direction of `1`, `-1` or `0`, finite loads, and as many rows as the
/// header's nodes and increments give.
///
/// # Errors
///
/// [`SlipMapReadError`], naming the file: not an output of shakedown, of
/// another version, another table, a missing or bad comment line, not the
/// cycle given, the two files of different runs, a bad row, or a file cut
/// short.
pub fn read_slip_map(
    map: &str,
    load: &str,
    polyline: Option<&Polyline>,
) -> Result<SlipMap, SlipMapReadError> {
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
    let head = SlipMapHead::of(&meta, polyline).map_err(in_map)?;
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
    /// Rows of the map: sub-segments of the cycle.
    rows: usize,
    outcome: Outcome,
}

impl SlipMapHead {
    fn of(meta: &Metadata, polyline: Option<&Polyline>) -> Result<Self, SlipMapFileError> {
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
        // A polyline's header has no psi or phi (`none`) but names the
        // cycle by content: it is drawn with that cycle or not at all,
        // never with an ellipse.
        check_recorded_cycle(meta.get(LOAD_CYCLE_KEY), polyline)?;
        let lambda = number("lambda")?;
        let cycle = match polyline {
            Some(p) => Cycle::polyline(center, lambda, p.clone()),
            None => Cycle::new(center, lambda, number("psi")?, number("phi")?),
        }
        .map_err(|e| bad("lambda", get("lambda").unwrap_or_default(), e.to_string()))?;
        let nodes = count("nodes")?;
        let rows = count("rows")?;
        // A bound on what a header may ask to be allocated.
        let cells = nodes.checked_mul(rows).filter(|&n| n > 0 && n <= 1 << 26);
        if cells.is_none() {
            return Err(bad(
                "rows",
                get("rows")?,
                format!("{nodes} nodes x {rows} rows is not a map this tool writes"),
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
            rows,
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

/// Line `n` of a file, `line`, cannot be read: `why`.
fn row_error(n: usize, line: &str, why: &str) -> SlipMapFileError {
    SlipMapFileError::Row {
        line: n,
        why: why.to_string(),
        text: escape_text(line.trim_end(), 60),
    }
}

/// A complete line's fields, or why not: a last line without its newline
/// is a file cut short.
fn row_fields(n: usize, line: &str, columns: usize) -> Result<Vec<&str>, SlipMapFileError> {
    let row = |why: &str| row_error(n, line, why);
    let Some(body) = line.strip_suffix('\n') else {
        return Err(row("the last line is incomplete (the file is cut short)"));
    };
    let f: Vec<&str> = body.trim_end_matches('\r').split(',').collect();
    if f.len() != columns {
        return Err(row(&format!("expected {columns} columns")));
    }
    Ok(f)
}

/// One row of the map (a sub-segment of the cycle): `(t0, t1, directions)`.
type MapIncrement = (f64, f64, Vec<SlipDirection>);

fn slip_map_rows(text: &str, head: &SlipMapHead) -> Result<Vec<MapIncrement>, SlipMapFileError> {
    let (nodes, count) = (head.nodes, head.rows);
    let expected = nodes * count;
    let mut rows: Vec<MapIncrement> = Vec::with_capacity(count);
    let mut found = 0;
    let mut t0 = 0.0;
    for (n, line) in table_lines(text, SlipMap::HEADER)? {
        if found == expected {
            found += 1;
            continue;
        }
        let f = row_fields(n, line, 3)?;
        let row = |why: &str| row_error(n, line, why);
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
            what: format!("{nodes} nodes x {count} rows"),
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
    let expected = head.rows + 1;
    let mut points = Vec::with_capacity(expected);
    let mut found = 0;
    for (n, line) in table_lines(text, SlipMap::LOAD_HEADER)? {
        found += 1;
        if found > expected {
            continue;
        }
        let f = row_fields(n, line, 5)?;
        let row = |why: &str| row_error(n, line, why);
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
            what: format!("t = 0 and {} rows", head.rows),
        });
    }
    let start = points.remove(0);
    Ok((start, points))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::case::CaseParams;
    use crate::analysis::slip_map::slip_map;
    use crate::io::cycle::inline_cycle;

    /// A map's two CSVs as `figure` writes them.
    fn files(params: &CaseParams) -> (SlipMap, String, String) {
        let case = Case::from_params(params).unwrap();
        let map = slip_map(&case).unwrap();
        let meta = slip_map_metadata(&case, &map).render();
        let (text, load) = (meta.clone() + &map.csv(), meta + &map.load_csv());
        (map, text, load)
    }

    fn cycle_error(r: Result<SlipMap, SlipMapReadError>) -> CycleMatchError {
        match r {
            Err(SlipMapReadError {
                file: SlipMapFile::Map,
                error: SlipMapFileError::Cycle(e),
            }) => e,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_polyline_map_is_read_back_with_its_cycle_and_no_other() {
        let offsets = |a: f64| {
            [(a, a), (-a, a), (-a, -a), (a, -a)]
                .map(|(u, v)| LoadPoint::new(u, v))
                .to_vec()
        };
        let square = inline_cycle(offsets(0.5)).unwrap();
        let params = CaseParams {
            load_factor: 7.0,
            nodes: 32,
            steps: 100,
            cycle: Some(square.clone()),
            ..CaseParams::default()
        };
        let (map, text, load) = files(&params);
        let back = read_slip_map(&text, &load, Some(&square)).unwrap();
        assert_eq!(back.cycle, map.cycle);
        assert_eq!(back.start, map.start);
        assert_eq!(back.rows.len(), map.rows.len());
        for (a, b) in back.rows.iter().zip(&map.rows) {
            assert_eq!((a.t1, a.load, &a.directions), (b.t1, b.load, &b.directions));
        }
        assert!(matches!(
            cycle_error(read_slip_map(&text, &load, None)),
            CycleMatchError::NotGiven { .. }
        ));
        let other = inline_cycle(offsets(0.4)).unwrap();
        assert!(matches!(
            cycle_error(read_slip_map(&text, &load, Some(&other))),
            CycleMatchError::Differs { .. }
        ));
        // A map of the ellipse is not read with a polyline.
        let (_, text, load) = files(&CaseParams {
            cycle: None,
            ..params
        });
        assert!(read_slip_map(&text, &load, None).is_ok());
        assert!(matches!(
            cycle_error(read_slip_map(&text, &load, Some(&square))),
            CycleMatchError::NotPolyline { .. }
        ));
    }
}
