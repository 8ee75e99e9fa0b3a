//! The polyline cycle's codec (`--cycle FILE`, model.md section 5.4): a
//! CSV with header `u,v` and one vertex a row, in time order, the offsets
//! from the cycle centre that `lambda` scales. Lines starting with `#` (a
//! metadata header) and blank lines are skipped. A cycle is named by its
//! content, `cycle:NAME@sha256:DIGEST`, so that every output made from it
//! records which cycle it was, whatever the file is called later.

use std::path::Path;

use crate::io::hash::content_id;
use crate::io::parse::parse_angle;
use crate::io::read::{escape_text, read_text_capped, ReadError};
use crate::model::{LoadPoint, ParamError, Polyline, MAX_VERTICES};

/// Largest cycle file read (8 MiB): 100000 vertices of two full-precision
/// numbers each fit with room to spare.
pub const MAX_CYCLE_BYTES: u64 = 8 << 20;

/// The column header of a cycle file.
pub const CYCLE_HEADER: &str = "u,v";

/// A cycle file or inline cycle that was not read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CycleFileError {
    /// The file could not be read (missing, not a regular file, too large).
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The first line that is not a comment is not the header `u,v`.
    #[error("the first line that is not a # comment must be the header u,v")]
    Header,
    /// A row that is not two finite numbers.
    #[error("line {line}: {why} in '{text}': expected u,v (numbers, or multiples of pi)")]
    Row {
        /// The line number (from 1).
        line: usize,
        /// What is wrong with it.
        why: String,
        /// The row, escaped and shortened.
        text: String,
    },
    /// Too few or too many vertices, or an offset out of range.
    #[error("{0}")]
    Param(#[from] ParamError),
}

/// The vertices of a cycle CSV, in the file's order.
///
/// # Errors
///
/// [`CycleFileError::Header`] without the `u,v` header;
/// [`CycleFileError::Row`] for a row that is not two finite numbers;
/// [`CycleFileError::Param`] for more than [`MAX_VERTICES`] rows (checked
/// while reading, so a huge file is not collected).
pub fn parse_cycle_csv(text: &str) -> Result<Vec<LoadPoint>, CycleFileError> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !(l.starts_with('#') || l.trim().is_empty()));
    match lines.next() {
        Some((_, h)) if h.trim().replace(' ', "") == CYCLE_HEADER => {}
        _ => return Err(CycleFileError::Header),
    }
    let mut vertices = Vec::new();
    for (i, line) in lines {
        if vertices.len() == MAX_VERTICES {
            return Err(ParamError::BadCount {
                name: "cycle",
                value: MAX_VERTICES + 1,
                expected: "3 to 100000 vertices",
            }
            .into());
        }
        let bad = |why: &str| CycleFileError::Row {
            line: i + 1,
            why: why.to_string(),
            text: escape_text(line, 80),
        };
        let (u, v) = line.split_once(',').ok_or_else(|| bad("one column"))?;
        if v.contains(',') {
            return Err(bad("more than two columns"));
        }
        let u = parse_angle(u).map_err(|_| bad("u is not a finite number"))?;
        let v = parse_angle(v).map_err(|_| bad("v is not a finite number"))?;
        vertices.push(LoadPoint::new(u, v));
    }
    Ok(vertices)
}

/// The cycle of the file at `path`, read through the size cap (a FIFO or
/// device is refused before it is opened) and named
/// `cycle:FILENAME@sha256:DIGEST` by its bytes.
///
/// # Errors
///
/// [`CycleFileError`]: unreadable, not a cycle CSV, or not a valid
/// polyline ([`Polyline::new`]).
pub fn read_cycle_file(path: &Path) -> Result<Polyline, CycleFileError> {
    let text = read_text_capped(path, MAX_CYCLE_BYTES)?;
    let vertices = parse_cycle_csv(&text)?;
    let stem = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(Polyline::new(cycle_name(&stem, text.as_bytes()), vertices)?)
}

/// An inline cycle (a preset's `cycle = [[u, v], ...]`), named
/// `cycle:inline@sha256:DIGEST` by the digest of its canonical CSV
/// ([`cycle_csv`]), so that the same vertices get the same name.
///
/// # Errors
///
/// [`CycleFileError::Param`] when the vertices are not a valid polyline.
pub fn inline_cycle(vertices: Vec<LoadPoint>) -> Result<Polyline, CycleFileError> {
    let text = cycle_csv(&vertices);
    Ok(Polyline::new(
        cycle_name("inline", text.as_bytes()),
        vertices,
    )?)
}

/// `cycle:STEM@sha256:DIGEST`, with the characters that would break a CSV
/// field or a header line replaced.
fn cycle_name(stem: &str, content: &[u8]) -> String {
    let stem: String = stem
        .chars()
        .map(|c| {
            if c == '"' || c == ',' || c == '=' || c.is_control() {
                '_'
            } else {
                c
            }
        })
        .collect();
    format!("cycle:{stem}@sha256:{}", content_id(content))
}

/// The key under which a file's metadata header records its polyline
/// cycle (model.md section 5.4); a file of the paper's ellipse has none.
pub const LOAD_CYCLE_KEY: &str = "load-cycle";

/// The content digest of a recorded cycle name, `DIGEST` of
/// `cycle:NAME@sha256:DIGEST`: what identifies the cycle, whatever its
/// file was called.
pub fn recorded_digest(name: &str) -> Option<&str> {
    let (_, digest) = name.strip_prefix("cycle:")?.rsplit_once("@sha256:")?;
    (!digest.is_empty() && digest.bytes().all(|b| b.is_ascii_hexdigit())).then_some(digest)
}

/// A file's recorded load cycle ([`LOAD_CYCLE_KEY`]) and the cycle it is
/// to be read with are not the same ([`check_recorded_cycle`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CycleMatchError {
    /// Made with a polyline, but none is given.
    #[error("it was made with the load cycle {recorded}: give that cycle's file with --cycle")]
    NotGiven {
        /// The file's cycle, escaped.
        recorded: String,
    },
    /// Made with the paper's ellipse, but a polyline is given.
    #[error("it was made with the paper's ellipse (psi, phi), not with the load cycle {given}: drop --cycle")]
    NotPolyline {
        /// The cycle given.
        given: String,
    },
    /// Made with another polyline (another sha256).
    #[error("it was made with the load cycle {recorded}, but the cycle given is {given}: their contents differ")]
    Differs {
        /// The file's cycle, escaped.
        recorded: String,
        /// The cycle given.
        given: String,
    },
}

/// Whether a file whose header records the cycle `recorded` (the value of
/// [`LOAD_CYCLE_KEY`], `None` for the paper's ellipse) may be read with
/// the polyline `given`: both none, or the same content (the same sha256;
/// the file may have been renamed since).
///
/// # Errors
///
/// [`CycleMatchError`]: a polyline file without its cycle, an ellipse
/// file with one, or two different cycles.
pub fn check_recorded_cycle(
    recorded: Option<&str>,
    given: Option<&Polyline>,
) -> Result<(), CycleMatchError> {
    match (recorded, given) {
        (None, None) => Ok(()),
        (Some(r), None) => Err(CycleMatchError::NotGiven {
            recorded: escape_text(r, 120),
        }),
        (None, Some(g)) => Err(CycleMatchError::NotPolyline {
            given: g.name().to_string(),
        }),
        (Some(r), Some(g)) => match (recorded_digest(r), recorded_digest(g.name())) {
            (Some(a), Some(b)) if a == b => Ok(()),
            _ => Err(CycleMatchError::Differs {
                recorded: escape_text(r, 120),
                given: g.name().to_string(),
            }),
        },
    }
}

/// The cycle CSV of `vertices`: the header `u,v` and one row a vertex,
/// each number in its shortest round-trip form (so reading it back gives
/// the same bits).
pub fn cycle_csv(vertices: &[LoadPoint]) -> String {
    let mut out = String::with_capacity(40 * vertices.len() + 8);
    out.push_str(CYCLE_HEADER);
    out.push('\n');
    for v in vertices {
        out.push_str(&format!("{:?},{:?}\n", v.x(), v.y()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_to_the_bit() {
        let vertices: Vec<LoadPoint> = (0..7)
            .map(|k| {
                let t = 2.0 * std::f64::consts::PI * k as f64 / 7.0;
                LoadPoint::new(t.sin() / 3.0, -1e-310 + t.cos())
            })
            .collect();
        let text = format!("# a header\n\n{}", cycle_csv(&vertices));
        assert_eq!(parse_cycle_csv(&text).unwrap(), vertices);
    }

    #[test]
    fn refuses_bad_rows_and_shapes() {
        assert_eq!(parse_cycle_csv("x,y\n1,2\n"), Err(CycleFileError::Header));
        assert!(matches!(
            parse_cycle_csv("u,v\n1,2\n3\n"),
            Err(CycleFileError::Row { line: 3, .. })
        ));
        assert!(matches!(
            parse_cycle_csv("u,v\n1,nan\n"),
            Err(CycleFileError::Row { line: 2, .. })
        ));
        assert!(matches!(
            parse_cycle_csv("u,v\n1,2,3\n"),
            Err(CycleFileError::Row { .. })
        ));
        // pi is allowed, as for every load-plane coordinate.
        assert_eq!(
            parse_cycle_csv("u, v\n0.5pi,-pi\n").unwrap(),
            vec![LoadPoint::new(
                0.5 * std::f64::consts::PI,
                -std::f64::consts::PI
            )]
        );
        let two = parse_cycle_csv("u,v\n0,0\n1,1\n").unwrap();
        assert!(matches!(
            inline_cycle(two),
            Err(CycleFileError::Param(ParamError::BadCount { value: 2, .. }))
        ));
    }

    #[test]
    fn a_recorded_cycle_matches_by_content_not_by_name() {
        let square = vec![
            LoadPoint::new(1.0, 0.0),
            LoadPoint::new(0.0, 1.0),
            LoadPoint::new(-1.0, 0.0),
            LoadPoint::new(0.0, -1.0),
        ];
        let text = cycle_csv(&square);
        let here = Polyline::new(cycle_name("a.csv", text.as_bytes()), square.clone()).unwrap();
        let renamed = cycle_name("b.csv", text.as_bytes());
        assert_eq!(recorded_digest(&renamed), recorded_digest(here.name()));
        assert_eq!(check_recorded_cycle(Some(&renamed), Some(&here)), Ok(()));
        // The inline form of the same vertices has the digest of the
        // canonical CSV, so it is the same cycle as that file.
        let inline = inline_cycle(square).unwrap();
        assert_eq!(check_recorded_cycle(Some(&renamed), Some(&inline)), Ok(()));
        assert_eq!(check_recorded_cycle(None, None), Ok(()));
        let other = cycle_name("a.csv", b"u,v\n1,0\n0,1\n-1,0\n");
        assert!(matches!(
            check_recorded_cycle(Some(&other), Some(&here)),
            Err(CycleMatchError::Differs { .. })
        ));
        assert!(matches!(
            check_recorded_cycle(Some(&renamed), None),
            Err(CycleMatchError::NotGiven { .. })
        ));
        assert!(matches!(
            check_recorded_cycle(None, Some(&here)),
            Err(CycleMatchError::NotPolyline { .. })
        ));
        // A value that is not a recorded cycle never matches.
        assert_eq!(recorded_digest("cycle:a.csv@sha256:"), None);
        assert!(check_recorded_cycle(Some("square"), Some(&here)).is_err());
    }

    #[test]
    fn the_name_is_the_content() {
        let a = vec![
            LoadPoint::new(0.0, 0.0),
            LoadPoint::new(1.0, 0.0),
            LoadPoint::new(0.0, 1.0),
        ];
        let mut b = a.clone();
        b[2] = LoadPoint::new(0.0, 2.0);
        let (na, nb) = (inline_cycle(a.clone()).unwrap(), inline_cycle(b).unwrap());
        assert_ne!(na.name(), nb.name());
        assert_eq!(na.name(), inline_cycle(a).unwrap().name());
        assert!(na.name().starts_with("cycle:inline@sha256:"));
    }
}
