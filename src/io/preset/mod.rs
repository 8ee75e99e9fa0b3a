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

use serde::Deserialize;

use crate::analysis::case::CaseParams;
use crate::analysis::sweep::{Axis, SweepLists};
use crate::model::path::Initial;

mod parse;

pub use parse::parse;

/// The built-in presets: name and TOML text, in listing order.
pub const BUILTIN: [(&str, &str); 9] = [
    ("fig3", include_str!("../../../presets/fig3.toml")),
    ("fig4", include_str!("../../../presets/fig4.toml")),
    ("fig5", include_str!("../../../presets/fig5.toml")),
    ("fig6", include_str!("../../../presets/fig6.toml")),
    ("fig7", include_str!("../../../presets/fig7.toml")),
    ("fig8", include_str!("../../../presets/fig8.toml")),
    ("fig9", include_str!("../../../presets/fig9.toml")),
    ("regime", include_str!("../../../presets/regime.toml")),
    (
        "biharmonic",
        include_str!("../../../presets/biharmonic.toml"),
    ),
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
