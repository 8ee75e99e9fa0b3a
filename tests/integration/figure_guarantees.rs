//! `shakedown figure`'s guarantees (issue 65): a redraw is drawn with the
//! model of its data, a partial table is drawn only when asked and then
//! says so, an interrupted `--force` can be finished with `--resume` and
//! gives the bytes of an uninterrupted run, and text from a preset cannot
//! break the SVG.

use crate::common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{check_svg, lambda_2, ok, scratch, shakedown, stderr, stdout};

const COARSE: [&str; 4] = ["--nodes", "32", "--steps", "100"];

#[test]
fn a_redraw_uses_the_model_of_its_csv() {
    let dir = scratch("from-model");
    let made = dir.join("made");
    let grid = ["--lambda", "4.5,5.5", "--initial", "OA,7,-7"];
    let model = ["--friction", "0.2", "--nodes", "32", "--steps", "100"];
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let made_s = s(&made);
    let first = ok(&[&["figure", "fig3", "--out", &made_s][..], &grid, &model].concat());
    // lambda_2 of the data's model, as `limit` computes it for that model.
    let limit = ok(&["limit", "--phi", "0", "--friction", "0.2", "--nodes", "32"]);
    // Both print six decimals.
    assert!(
        (lambda_2(&first) - lambda_2(&limit)).abs() < 2e-6,
        "{first}\n{limit}"
    );
    // Redrawn without the model flags: the CSV's model, not the preset's.
    let csv = s(&made.join("fig3.csv"));
    let again = dir.join("again");
    let out = ok(&[
        &["figure", "fig3", "--from", &csv, "--out", &s(&again)][..],
        &grid,
    ]
    .concat());
    assert_eq!(lambda_2(&out), lambda_2(&first), "{out}");
    let caption = std::fs::read_to_string(again.join("fig3.caption.txt")).unwrap();
    assert!(
        caption.contains("f = 0.2") && caption.contains("N = 32"),
        "{caption}"
    );
    assert_eq!(
        caption,
        std::fs::read_to_string(made.join("fig3.caption.txt")).unwrap()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_partial_table_is_drawn_only_with_partial_and_says_so() {
    let dir = scratch("from-partial");
    let made = dir.join("made");
    let grid = ["--lambda", "4.5,5,5.5", "--initial", "OA,7,-7"];
    let s = |p: &Path| p.to_str().unwrap().to_string();
    ok(&[&["figure", "fig3", "--out", &s(&made)][..], &grid, &COARSE].concat());
    // Keep the header and the first four rows (of six).
    let text = std::fs::read_to_string(made.join("fig3.csv")).unwrap();
    let header = text.lines().take_while(|l| l.starts_with('#')).count() + 1;
    let cut: String = text
        .split_inclusive('\n')
        .take(header + 4)
        .collect::<String>();
    let part = dir.join("part.csv");
    std::fs::write(&part, cut).unwrap();
    let drawn = dir.join("drawn");
    let (part_s, drawn_s) = (s(&part), s(&drawn));
    let args = [
        &["figure", "fig3", "--from", &part_s, "--out", &drawn_s][..],
        &grid,
    ]
    .concat();
    let o = shakedown(&args);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("partial: 4 of 6 runs"),
        "{}",
        stderr(&o)
    );
    assert!(!drawn.join("fig3.svg").exists());
    ok(&[&args[..], &["--partial", "--title"]].concat());
    let caption = std::fs::read_to_string(drawn.join("fig3.caption.txt")).unwrap();
    assert!(caption.contains("partial: 4 of 6 runs"), "{caption}");
    let svg = std::fs::read_to_string(drawn.join("fig3.svg")).unwrap();
    assert!(svg.contains("partial: 4 of 6 runs"), "the title says it");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Lines of the table (after the `#` header) in `path`.
fn rows_in(path: &Path) -> usize {
    std::fs::read_to_string(path)
        .map(|t| t.lines().filter(|l| !l.starts_with('#')).count())
        .unwrap_or(0)
}

#[cfg(unix)]
#[test]
fn an_interrupted_force_is_finished_by_resume_with_the_same_bytes() {
    let dir = scratch("force-resume");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let (fig, reference) = (dir.join("fig"), dir.join("reference"));
    // The figure made before, on another grid.
    ok(&[
        &["figure", "fig3", "--out", &s(&fig), "--lambda", "4,5"][..],
        &COARSE,
    ]
    .concat());
    let old = std::fs::read(fig.join("fig3.csv")).unwrap();
    let grid = ["--lambda", "3:7:0.1"];
    let fig_s = s(&fig);
    let redo = [&["figure", "fig3", "--out", &fig_s][..], &grid, &COARSE].concat();
    let child = Command::new(env!("CARGO_BIN_EXE_shakedown"))
        .args([&redo[..], &["--force"]].concat())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pending = fig.join(".fig3.csv.new");
    let start = Instant::now();
    while rows_in(&pending) < 40 {
        assert!(start.elapsed() < Duration::from_secs(120), "no rows appear");
        std::thread::sleep(Duration::from_millis(5));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    // The figure made before is whole.
    assert_eq!(std::fs::read(fig.join("fig3.csv")).unwrap(), old);
    ok(&[&redo[..], &["--resume"]].concat());
    assert!(!pending.exists());
    ok(&[
        &["figure", "fig3", "--out", &s(&reference)][..],
        &grid,
        &COARSE,
    ]
    .concat());
    for name in ["fig3.csv", "fig3_limit.csv", "fig3.svg", "fig3.caption.txt"] {
        assert!(
            std::fs::read(fig.join(name)).unwrap() == std::fs::read(reference.join(name)).unwrap(),
            "{name} differs from an uninterrupted run"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_title_with_markup_and_control_characters_keeps_the_svg_well_formed() {
    let dir = scratch("title-escape");
    let preset = dir.join("odd.toml");
    std::fs::write(
        &preset,
        "name = \"odd\"\ndescription = \"d\"\n[sweep]\nlambda = [4, 5]\ninitial = \"OA\"\n[figure]\ntitle = \"W <b>&amp; \\u0007bell\\u001b[31m\"\nkind = \"dissipation\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    ok(&[
        &[
            "figure",
            preset.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--title",
        ][..],
        &COARSE,
    ]
    .concat());
    let svg = std::fs::read_to_string(out.join("odd.svg")).unwrap();
    check_svg(&svg).unwrap();
    assert!(svg.contains("&lt;b&gt;&amp;amp;"), "markup is escaped");
    assert!(!svg
        .chars()
        .any(|c| c.is_control() && c != '\n' && c != '\t' && c != '\r'));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sweep_rows_print_numbers_in_shortest_form() {
    let o = shakedown(&[
        "sweep",
        "--lambda",
        "1e-320",
        "--phi",
        "0",
        "--initial",
        "OA",
        "--nodes",
        "16",
        "--steps",
        "16",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.lines().any(|l| l.starts_with("1e-320,0,\"OA\",")),
        "{text}"
    );
    assert!(text.contains("# lambda = 1e-320"), "{text}");
    assert!(text.lines().all(|l| l.len() < 200), "{text}");
}

/// The preset's title names its case (fig7: λ = 5.1, φ = π/2, OA); a slip
/// map of another case says which, and its redraw says the same.
#[test]
fn a_slip_map_of_another_case_says_so_in_its_caption() {
    let dir = scratch("slip-map-case");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let (made, again) = (s(&dir.join("made")), s(&dir.join("again")));
    let case = ["--lambda", "4.5", "--phi", "pi/4", "--initial", "7,-7"];
    ok(&[&["figure", "fig7", "--out", &made][..], &case, &COARSE].concat());
    let caption = std::fs::read_to_string(dir.join("made/fig7.caption.txt")).unwrap();
    for note in ["λ = 4.5", "φ = 0.25π", "initial path 7,-7"] {
        assert!(caption.contains(note), "{caption} lacks {note}");
    }
    ok(&[
        "figure",
        "fig7",
        "--from",
        &format!("{made}/fig7.csv"),
        "--out",
        &again,
    ]);
    let redrawn = std::fs::read_to_string(dir.join("again/fig7.caption.txt")).unwrap();
    assert_eq!(redrawn, caption);
    // The preset's own case adds no note.
    let own = s(&dir.join("own"));
    ok(&[&["figure", "fig7", "--out", &own][..], &COARSE].concat());
    let caption = std::fs::read_to_string(dir.join("own/fig7.caption.txt")).unwrap();
    assert!(
        caption
            .starts_with("Fig. 7: point C, λ = 5.1, φ = π/2 (N = 32, 100 increments per cycle):"),
        "{caption}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sweep figure drawn over another grid than its preset's says what its
/// title then gets wrong: fig6's λ = 5.1 and fig3's φ = 0, and the
/// transients drawn.
#[test]
fn a_sweep_figure_of_another_grid_says_so_in_its_caption() {
    let dir = scratch("sweep-grid");
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let cases: [(&str, &[&str], &[&str]); 2] = [
        (
            "fig6",
            &["--lambda", "5.5", "--phi", "0,pi/2", "--initial", "OA"],
            &["λ = 5.5", "transient OA"],
        ),
        (
            "fig3",
            &[
                "--lambda",
                "4.5,5.5",
                "--phi",
                "pi/2",
                "--initial",
                "OA,7,-7",
            ],
            &["φ = 0.5π", "transients OA and 7,-7"],
        ),
    ];
    for (name, grid, notes) in cases {
        let out = s(&dir.join(name));
        ok(&[&["figure", name, "--out", &out][..], grid, &COARSE].concat());
        let caption =
            std::fs::read_to_string(dir.join(name).join(format!("{name}.caption.txt"))).unwrap();
        for note in notes {
            assert!(caption.contains(note), "{caption} lacks {note}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
