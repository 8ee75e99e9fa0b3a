//! The memory figure's CSV (`figure fig4`, [`MEMORY_HEADER`]) read back for
//! a redraw: the header must be the figure's (table `memory`, its model and
//! grid), and every row a valid point of that grid, in order, once.

use crate::analysis::memory::{MemoryPoint, MEMORY_HEADER};
use crate::io::csv::{Metadata, MetadataError};
use crate::io::read::escape_text;

/// A memory CSV that cannot be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MemoryCsvError {
    /// Not UTF-8 text.
    #[error("it is not UTF-8 text")]
    NotText,
    /// The header is not this figure's.
    #[error("{0}")]
    Header(MetadataError),
    /// The column names are not [`MEMORY_HEADER`].
    #[error("its column header is not '{MEMORY_HEADER}'")]
    Columns,
    /// A row that is not a valid point.
    #[error("line {line}: {why}")]
    Row {
        /// 1-based line number in the file.
        line: usize,
        /// What is wrong with it.
        why: String,
    },
    /// Fewer or more rows than the grid has points.
    #[error(
        "it has {found} rows, but the grid has {expected} points (a file cut short or added to)"
    )]
    Count {
        /// Rows found.
        found: usize,
        /// Points of the grid.
        expected: usize,
    },
}

/// The points of a memory CSV whose header must be `expected`, whose rows
/// are the points `grid` (`(lambda, phi)` in order) and whose run counts
/// add up to `runs` (the transients per point).
///
/// A row is valid when `R >= 0` (or empty: undefined), `0 <= r <= 1` (or
/// empty), and its four counts add up to `runs`.
///
/// # Errors
///
/// [`MemoryCsvError`]: the header, a row or the row count.
pub fn read_memory_csv(
    bytes: &[u8],
    expected: &Metadata,
    grid: &[(f64, f64)],
    runs: usize,
) -> Result<Vec<MemoryPoint>, MemoryCsvError> {
    let text = std::str::from_utf8(bytes).map_err(|_| MemoryCsvError::NotText)?;
    expected
        .check(&Metadata::parse(text))
        .map_err(MemoryCsvError::Header)?;
    let mut lines = text
        .lines()
        .enumerate()
        .skip_while(|(_, l)| l.starts_with('#'));
    match lines.next() {
        Some((_, l)) if l == MEMORY_HEADER => {}
        _ => return Err(MemoryCsvError::Columns),
    }
    let mut out = Vec::new();
    for (i, line) in lines {
        let n = i + 1;
        let row = |why: String| MemoryCsvError::Row { line: n, why };
        let Some(&(lambda, phi)) = grid.get(out.len()) else {
            return Err(MemoryCsvError::Count {
                found: out.len() + 1 + text.lines().skip(n).count(),
                expected: grid.len(),
            });
        };
        let point = parse_row(line, runs).map_err(row)?;
        if point.load_factor != lambda || point.phase != phi {
            return Err(row(format!(
                "point lambda = {}, phi = {} where the grid has lambda = {lambda}, phi = {phi} (not this grid, or a row repeated)",
                point.load_factor, point.phase
            )));
        }
        out.push(point);
    }
    if out.len() != grid.len() {
        return Err(MemoryCsvError::Count {
            found: out.len(),
            expected: grid.len(),
        });
    }
    Ok(out)
}

fn parse_row(line: &str, runs: usize) -> Result<MemoryPoint, String> {
    let f: Vec<&str> = line.split(',').collect();
    if f.len() != 8 {
        return Err(format!("{} fields, expected 8 ({MEMORY_HEADER})", f.len()));
    }
    let num = |name: &str, t: &str| {
        t.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{name} '{}' is not a finite number", escape_text(t, 40)))
    };
    let opt = |name: &str, t: &str| {
        if t.is_empty() {
            Ok(None)
        } else {
            num(name, t).map(Some)
        }
    };
    let count = |name: &str, t: &str| {
        t.parse::<usize>()
            .map_err(|_| format!("{name} '{}' is not a count", escape_text(t, 40)))
    };
    let point = MemoryPoint {
        load_factor: num("lambda", f[0])?,
        phase: num("phi", f[1])?,
        range: opt("R", f[2])?,
        stuck_fraction: opt("r", f[3])?,
        shakedown: count("shakedown", f[4])?,
        cyclic_slip: count("cyclic_slip", f[5])?,
        ratchetting: count("ratchetting", f[6])?,
        other: count("other", f[7])?,
    };
    // R is a spread over a mean and r a fraction (model.md, the memory
    // measures): R >= 0 and 0 <= r <= 1.
    if point.range.is_some_and(|r| r < 0.0) {
        return Err(format!("R = {} is negative", f[2]));
    }
    if point
        .stuck_fraction
        .is_some_and(|r| !(0.0..=1.0).contains(&r))
    {
        return Err(format!("r = {} is not a fraction in [0, 1]", f[3]));
    }
    let total = point
        .shakedown
        .checked_add(point.cyclic_slip)
        .and_then(|t| t.checked_add(point.ratchetting))
        .and_then(|t| t.checked_add(point.other));
    if total != Some(runs) {
        return Err(format!(
            "its run counts do not add up to the {runs} transients of each point"
        ));
    }
    Ok(point)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(rows: &str) -> (Metadata, String) {
        let mut m = Metadata::new("memory");
        m.push("friction", 0.1);
        (m.clone(), format!("{}{MEMORY_HEADER}\n{rows}", m.render()))
    }

    #[test]
    fn a_valid_file_reads_back_and_bad_rows_are_named() {
        let grid = [(4.0, 0.0), (5.0, 0.0)];
        let (m, text) = file("4,0,,0.5,2,0,0,0\n5,0,0.1,,0,1,1,0\n");
        let points = read_memory_csv(text.as_bytes(), &m, &grid, 2).unwrap();
        assert_eq!(points.len(), 2);
        assert_eq!(points[1].range, Some(0.1));
        for (rows, why) in [
            ("4,0,-1,0.5,2,0,0,0\n5,0,0.1,,0,1,1,0\n", "negative"),
            ("4,0,,1.5,2,0,0,0\n5,0,0.1,,0,1,1,0\n", "fraction"),
            ("4,0,,0.5,3,0,0,0\n5,0,0.1,,0,1,1,0\n", "add up"),
            ("4,0,,0.5,2,0,0,0\n4,0,,0.5,2,0,0,0\n", "repeated"),
            ("4,0,,0.5,2,0,0,0\n", "2 points"),
        ] {
            let (m, text) = file(rows);
            let e = read_memory_csv(text.as_bytes(), &m, &grid, 2).unwrap_err();
            assert!(e.to_string().contains(why), "{e}");
        }
        let (_, text) = file("4,0,,0.5,2,0,0,0\n5,0,0.1,,0,1,1,0\n");
        let mut other = Metadata::new("memory");
        other.push("friction", 0.2);
        assert!(matches!(
            read_memory_csv(text.as_bytes(), &other, &grid, 2),
            Err(MemoryCsvError::Header(_))
        ));
    }
}
