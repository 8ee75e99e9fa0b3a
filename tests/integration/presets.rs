//! The presets: every built-in one parses and runs a reduced version, the
//! CLI lists and accepts them, and bad ones are reported with file and line.

use crate::common;

use common::{read_csv, scratch, shakedown, stderr, stdout};
use shakedown::io::preset::{self, FigureKind, PresetError};

/// A few values and small discretisations keep every run quick.
const SMALL: [&str; 4] = ["--nodes", "64", "--steps", "200"];

#[test]
fn presets_command_lists_every_builtin_with_a_description() {
    let o = shakedown(&["presets"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    for (name, _) in preset::BUILTIN {
        let line = out
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("{name} missing from:\n{out}"));
        assert!(line.len() > name.len() + 10, "{line}");
    }
}

#[test]
fn every_builtin_preset_runs_reduced() {
    for p in preset::builtin() {
        let p = p.unwrap();
        let kind = p.figure.as_ref().map(|f| f.kind);
        if kind == Some(FigureKind::SlipMap) {
            let o = shakedown(&[&["run", "--preset", &p.name, "--json"][..], &SMALL].concat());
            assert!(o.status.success(), "{}: {}", p.name, stderr(&o));
            let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
            assert_eq!(
                v["parameters"]["lambda"].as_f64(),
                Some(p.params.load_factor)
            );
            continue;
        }
        // Two values of the swept variable and two initial paths.
        let lambdas: Vec<String> = p
            .sweep
            .load_factors
            .iter()
            .take(2)
            .map(f64::to_string)
            .collect();
        let phases: Vec<String> = p
            .sweep
            .phases
            .iter()
            .step_by(12)
            .take(2)
            .map(f64::to_string)
            .collect();
        let initials = if p.sweep.initials.len() > 1 {
            "OA,7,-7"
        } else {
            "OA"
        };
        let dir = scratch(&format!("preset-{}", p.name));
        let csv = dir.join("w.csv");
        let (lambdas, phases) = (lambdas.join(","), phases.join(","));
        let mut args = vec![
            "sweep",
            "--preset",
            &p.name,
            "--lambda",
            &lambdas,
            "--initial",
            initials,
            "--out",
            csv.to_str().unwrap(),
        ];
        // A polyline cycle has no phase (model.md section 5.4).
        if p.params.cycle.is_none() {
            args.extend(["--phi", &phases]);
        }
        let o = shakedown(&[&args[..], &SMALL].concat());
        assert!(o.status.success(), "{}: {}", p.name, stderr(&o));
        let (header, rows) = read_csv(&csv);
        assert_eq!(header.join(","), shakedown::analysis::sweep::CSV_HEADER);
        let paths = if initials == "OA" { 1 } else { 2 };
        let expected = lambdas.split(',').count() * phases.split(',').count() * paths;
        assert_eq!(rows.len(), expected, "{}", p.name);
        assert!(
            rows.iter().all(|r| r[3] != "failed"),
            "{}: {rows:?}",
            p.name
        );
        let _ = std::fs::remove_dir_all(dir);
    }
}

#[test]
fn builtin_presets_carry_the_papers_cases() {
    use std::f64::consts::PI;
    let get = |n: &str| preset::load(n).unwrap();
    let paper = shakedown::analysis::case::CaseParams::default();
    for (name, _) in preset::BUILTIN {
        let p = get(name);
        // The paper's parameters unless a preset says otherwise.
        assert_eq!(p.params.center, paper.center, "{name}");
        assert_eq!(p.params.slope, paper.slope, "{name}");
        assert_eq!(p.params.friction, paper.friction, "{name}");
        assert_eq!(p.params.poisson, paper.poisson, "{name}");
        assert_eq!(p.params.plane, paper.plane, "{name}");
    }
    let fig3 = get("fig3");
    assert_eq!(fig3.sweep.phases, vec![0.0]);
    assert_eq!(fig3.sweep.initials.len(), 26);
    assert!(fig3.figure.unwrap().limit);
    let fig5 = get("fig5");
    assert_eq!((fig5.params.load_factor, fig5.params.phase), (7.0, 0.0));
    let fig6 = get("fig6");
    assert_eq!(fig6.sweep.load_factors, vec![5.1]);
    assert!(fig6.sweep.phases.len() > 10);
    assert_eq!(fig6.sweep.initials.len(), 25);
    let fig7 = get("fig7");
    assert_eq!(fig7.params.load_factor, 5.1);
    assert!(fig7.params.phase > 0.0);
    let fig8 = get("fig8");
    assert_eq!(fig8.sweep.phases, vec![0.5 * PI]);
    assert_eq!(fig8.sweep.initials.len(), 25);
    let fig9 = get("fig9");
    assert_eq!(
        fig9.sweep.initials,
        vec![shakedown::model::path::Initial::Direct]
    );
    assert!(fig9.sweep.load_factors.len() > 2);
}

#[test]
fn preset_flag_is_accepted_by_run_sweep_and_tui() {
    let o = shakedown(&[&["run", "--preset", "fig5", "--lambda", "3"][..], &SMALL].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("shakedown"), "{}", stdout(&o));
    for cmd in ["run", "sweep", "tui"] {
        let o = shakedown(&[cmd, "--preset", "nosuch"]);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {}", stderr(&o));
        assert!(stderr(&o).contains("nosuch"), "{cmd}: {}", stderr(&o));
        assert!(stderr(&o).contains("fig3"), "{cmd}: {}", stderr(&o));
    }
}

#[test]
fn user_preset_file_is_loaded_and_errors_name_file_and_line() {
    let dir = scratch("user-preset");
    let good = dir.join("mine.toml");
    std::fs::write(
        &good,
        "description = \"my case\"\n[case]\nlambda = 3.0\nnodes = 64\nsteps = 200\n",
    )
    .unwrap();
    let o = shakedown(&["run", "--preset", good.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["parameters"]["lambda"].as_f64(), Some(3.0));
    assert_eq!(v["parameters"]["nodes"].as_u64(), Some(64));
    // Inside the stick diamond after OA: no slip at all.
    assert_eq!(v["state"], "shakedown");

    let bad_cases = [
        (
            "description = \"x\"\n[case]\nfriction = -0.1\n",
            3,
            "friction",
        ),
        (
            "description = \"x\"\n\n[sweep]\nlambdas = \"3:4:0.5\"\n",
            4,
            "lambdas",
        ),
        ("description = \"x\"\n[sweep]\nphi = \"0:pi:0\"\n", 3, "phi"),
        (
            "description = \"x\"\n[figure]\nkind = \"slip-map\"\nx = \"theta\"\n",
            4,
            "theta",
        ),
        ("[case]\nlambda = 3\n", 1, "description"),
    ];
    for (k, (text, line, word)) in bad_cases.iter().enumerate() {
        let path = dir.join(format!("bad{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let p = path.to_str().unwrap();
        let o = shakedown(&["run", "--preset", p]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        let err = stderr(&o);
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(&format!("{p}:{line}:")), "{text}\n{err}");
        assert!(err.contains(word), "{text}\n{err}");
        assert!(!err.contains("panicked"), "{err}");
        // The same through the library.
        assert!(matches!(
            preset::load(p),
            Err(PresetError::Invalid { line: l, .. }) if l == *line
        ));
    }
    let _ = std::fs::remove_dir_all(dir);
}
