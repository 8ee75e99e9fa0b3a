//! The frontier table of `design --frontier` (model.md section 10): the
//! reference load factors and, per family and `K`, the highest `lambda` at
//! which a found path shakes down, with that path as `--initial-path` text
//! (quoted: it holds commas).

use crate::analysis::design::{initial_path_text, FrontierRow, References};
use crate::io::parse::parse_points;
use crate::model::LoadPoint;

/// The columns of the frontier table.
pub const FRONTIER_HEADER: &str =
    "row,family,vertices,lambda,not_found_above,evaluations,initial_path";

/// One row read back: a reference (`family` is `lambda_1`, `best_of_25` or
/// `lambda_2`) or a frontier point.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontierRecord {
    /// `reference` or `frontier`.
    pub row: String,
    /// The family (`free`, `decaying`) or the reference's name.
    pub family: String,
    /// `K` (frontier rows).
    pub vertices: Option<usize>,
    /// The load factor.
    pub lambda: f64,
    /// Where the search stopped finding shakedown paths (frontier rows).
    pub not_found_above: Option<f64>,
    /// Candidates run (frontier rows).
    pub evaluations: Option<usize>,
    /// The path's vertices (empty for `lambda_1` and `lambda_2`).
    pub path: Vec<LoadPoint>,
}

/// The table's rows (no header): the three references, then the frontier.
pub fn frontier_csv(refs: &References, rows: &[FrontierRow]) -> String {
    let t = &refs.best_turning;
    let mut s = format!(
        "{FRONTIER_HEADER}\nreference,lambda_1,,{},,,\nreference,best_of_25,,{},,,\"{},{}\"\nreference,lambda_2,,{},,,\n",
        refs.lambda_1,
        refs.best_of_25,
        t.x(),
        t.y(),
        refs.lambda_2
    );
    for r in rows {
        s.push_str(&frontier_line(r));
    }
    s
}

/// One frontier row as a CSV line (with its newline).
pub fn frontier_line(r: &FrontierRow) -> String {
    format!(
        "frontier,{},{},{},{},{},\"{}\"\n",
        r.family.as_str(),
        r.vertices,
        r.lambda,
        r.not_found_above,
        r.evaluations,
        initial_path_text(&r.path)
    )
}

/// Read a frontier table back (comment lines are skipped).
///
/// # Errors
///
/// A message naming the line that is not a row of [`FRONTIER_HEADER`].
pub fn read_frontier_csv(text: &str) -> Result<Vec<FrontierRecord>, String> {
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    match lines.next() {
        Some(h) if h.trim() == FRONTIER_HEADER => {}
        _ => return Err(format!("its columns are not '{FRONTIER_HEADER}'")),
    }
    let mut out = Vec::new();
    for (k, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let bad = |why: &str| format!("row {}: {why}: '{line}'", k + 1);
        let (head, path) = match line.split_once('"') {
            Some((h, rest)) => (h, rest.trim_end().trim_end_matches('"')),
            None => (line, ""),
        };
        let f: Vec<&str> = head.split(',').collect();
        if f.len() < 6 {
            return Err(bad("expected 7 columns"));
        }
        let opt = |t: &str| -> Result<Option<f64>, String> {
            if t.is_empty() {
                Ok(None)
            } else {
                t.parse::<f64>().map(Some).map_err(|_| bad("not a number"))
            }
        };
        let path = if path.is_empty() {
            Vec::new()
        } else {
            parse_points(path)
                .map_err(|e| bad(&e.to_string()))?
                .into_iter()
                .map(|(x, y)| LoadPoint::new(x, y))
                .collect()
        };
        out.push(FrontierRecord {
            row: f[0].to_string(),
            family: f[1].to_string(),
            vertices: opt(f[2])?.map(|v| v as usize),
            lambda: opt(f[3])?.ok_or_else(|| bad("no lambda"))?,
            not_found_above: opt(f[4])?,
            evaluations: opt(f[5])?.map(|v| v as usize),
            path,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::design::Family;

    #[test]
    fn frontier_table_reads_back() {
        let refs = References {
            lambda_1: 4.7,
            best_of_25: 4.79,
            best_name: "-7,-7".into(),
            best_turning: LoadPoint::new(-1.75 * std::f64::consts::PI, -1.75),
            lambda_2: 4.899,
        };
        let row = FrontierRow {
            family: Family::Free,
            vertices: 2,
            lambda: 4.81,
            not_found_above: 4.82,
            path: vec![LoadPoint::new(-5.99, -6.19), LoadPoint::new(1.05, 3.39)],
            evaluations: 17,
        };
        let back = read_frontier_csv(&frontier_csv(&refs, std::slice::from_ref(&row))).unwrap();
        assert_eq!(back.len(), 4);
        assert_eq!(back[1].path, vec![refs.best_turning]);
        assert_eq!(back[3].path, row.path);
        assert_eq!(back[3].vertices, Some(2));
        assert_eq!(back[3].not_found_above, Some(4.82));
        assert!(back[0].path.is_empty());
    }
}
