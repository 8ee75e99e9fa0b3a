//! Whole-screen snapshots of the explorer in a fixed, synthetic state
//! (fed to it as the worker would, see [`synthetic`]): no number on these
//! screens comes from the solver, so a change of the physics or of a
//! tolerance does not rewrite them. Nothing depends on the clock either.

use std::f64::consts::PI;

use ratatui::backend::TestBackend;
use ratatui::style::Color;
use ratatui::Terminal;
use shakedown::analysis::case::Case;
use shakedown::analysis::episodes::LockedSlip;
use shakedown::model::path::Segment;
use shakedown::stepping::{Phase, Status};
use shakedown::tui::app::{
    App, Config, Detail, Record, View, BACKWARD, FORWARD, NEWLY_STUCK, STICK,
};
use shakedown::tui::keys::{bindings_for, Action, Mode, MODES};
use shakedown::tui::log::{At, EventKind, LogEntry};

use crate::common;
use shakedown::tui::{default_params, ui};

/// Two cycles and a bit of the synthetic state: the transient and a whole
/// cycle are in the slip map, W has points.
const INCREMENTS: usize = 900;

fn config(color: bool) -> Config {
    Config {
        color,
        ..Config::default()
    }
}

fn app(color: bool) -> App {
    let case = Case::from_params(&default_params()).expect("the default case is valid");
    App::new(case, config(color))
}

/// A synthetic record: slip bands that turn with the load, a few nodes
/// sticking every 37 increments, `W` growing through each cycle. Nothing
/// here comes from the solver, so a change of the physics or of a solver
/// tolerance leaves these screens as they are.
fn synthetic(i: usize, n: usize) -> Record {
    let transient = 20;
    let steps = 400;
    let phase_of = |i: usize| {
        if i < transient {
            Phase::Transient {
                segment: i / 10,
                increment: i % 10,
            }
        } else {
            Phase::Cycle {
                cycle: 1 + (i - transient) / steps,
                increment: (i - transient) % steps,
            }
        }
    };
    let phase = phase_of(i);
    let cycle = match phase {
        Phase::Cycle { cycle, .. } => cycle,
        _ => 0,
    };
    let t = 2.0 * PI * (i as f64) / steps as f64;
    let theta = |j: usize| 2.0 * PI * j as f64 / n as f64;
    let stuck: Vec<usize> = if i.is_multiple_of(37) {
        (10..15).collect()
    } else {
        Vec::new()
    };
    let mut cells: Vec<u8> = (0..n)
        .map(|j| {
            let s = (theta(j) + t).sin();
            if s > 0.6 {
                FORWARD
            } else if s < -0.6 {
                BACKWARD
            } else {
                STICK
            }
        })
        .collect();
    for &j in &stuck {
        cells[j] = NEWLY_STUCK;
    }
    let slip: Vec<f32> = (0..n)
        .map(|j| (0.05 * (2.0 * theta(j)).sin() * (1.0 + cycle as f64 / 10.0)) as f32)
        .collect();
    let slip_before = (!stuck.is_empty()).then(|| slip.iter().map(|g| g * 0.9).collect());
    let at = At {
        increment: i,
        cycle,
        time: (cycle > 0).then_some(t % (2.0 * PI)),
        load: (4.0 * t.cos(), 4.0 * t.sin()),
    };
    let mut events = Vec::new();
    if !stuck.is_empty() {
        events.push(LogEntry {
            kind: EventKind::AdvancingStick,
            increment: i,
            cycle,
            time: at.time,
            load: at.load,
            nodes: stuck.len(),
            theta: Some((theta(10), theta(14))),
            text: "advancing stick at 5 nodes".into(),
        });
    }
    if i.is_multiple_of(50) {
        events.push(LogEntry {
            kind: EventKind::Split,
            increment: i,
            cycle,
            time: at.time,
            load: at.load,
            nodes: 0,
            theta: Some((-1.0, 1.0)),
            text: "backward slip zone split (2 zones now), a long description to wrap".into(),
        });
    }
    let in_cycle = match phase {
        Phase::Cycle { increment, .. } => increment,
        _ => 0,
    };
    let completed = (cycle > 0 && in_cycle == steps - 1).then(|| (cycle, 0.004 / cycle as f64));
    Record {
        generation: 0,
        increment: i,
        phase,
        after: phase_of(i + 1),
        time: at.time,
        load: at.load,
        partial: None,
        cells,
        dissipation: 0.004 * in_cycle as f64 / steps as f64,
        rotation: -1e-3 * i as f64,
        status: Status::Running,
        events,
        locked: (!stuck.is_empty()).then(|| {
            // A made-up episode: each stuck node gathered a slip a million
            // times smaller than g, growing along the set, so the zoom has
            // something to fit.
            let per_node: Vec<f64> = (0..stuck.len()).map(|k| 1e-7 * (k + 1) as f64).collect();
            let g_now: Vec<f64> = stuck.iter().map(|&j| f64::from(slip[j])).collect();
            let g_cycle_start: Vec<f64> = g_now
                .iter()
                .zip(&per_node)
                .map(|(g, d)| g - 2.0 * d)
                .collect();
            let mean = per_node.iter().sum::<f64>() / per_node.len() as f64;
            Box::new(LockedSlip {
                nodes: stuck.clone(),
                max: per_node[per_node.len() - 1],
                mean,
                per_node,
                g_now,
                g_cycle_start,
            })
        }),
        newly_stuck: stuck,
        substeps: 3,
        completed,
        detail: Some(Box::new(Detail {
            pressure: (0..n)
                .map(|j| (1.0 + 0.2 * theta(j).cos()) as f32)
                .collect(),
            shear: (0..n)
                .map(|j| (0.25 * (theta(j) + t).sin()).clamp(-0.3, 0.3) as f32)
                .collect(),
            slip,
            slip_before,
        })),
    }
}

/// The explorer in a fixed, synthetic state after `n` increments.
fn fixed_app(color: bool, n: usize) -> App {
    let mut app = app(color);
    let nodes = app.case().disc().nodes();
    let a = shakedown::LoadPoint::new(0.0, 0.0);
    let b = shakedown::LoadPoint::new(4.0, 0.0);
    app.feed_started(vec![Segment::new(a, b, 0.5)], 0.3);
    for i in 0..n {
        app.feed(synthetic(i, nodes));
    }
    app
}

fn app_after(n: usize) -> App {
    fixed_app(true, n)
}

fn screen(app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("test backend");
    terminal
        .draw(|frame| ui::draw(frame, app))
        .expect("drawing to a test backend cannot fail");
    terminal
}

#[test]
fn screen_80x24() {
    let app = app_after(INCREMENTS);
    insta::assert_snapshot!(screen(&app, 80, 24).backend());
}

#[test]
fn screen_160x48() {
    let app = app_after(INCREMENTS);
    insta::assert_snapshot!(screen(&app, 160, 48).backend());
}

#[test]
fn screen_100x30_at_start() {
    let app = fixed_app(true, 0);
    insta::assert_snapshot!(screen(&app, 100, 30).backend());
}

#[test]
fn history_scrubbed_back_100x30() {
    let mut app = app_after(INCREMENTS);
    app.apply(Action::BackCycle);
    for _ in 0..3 {
        app.apply(Action::Back1);
    }
    assert_eq!(app.cursor(), Some(INCREMENTS - 1 - 403));
    let text = screen(&app, 100, 30).backend().to_string();
    assert!(text.contains(" history "), "{text}");
    insta::assert_snapshot!(text);
}

#[test]
fn advancing_stick_marks_what_was_locked_in() {
    let mut app = app_after(INCREMENTS);
    // Increment 888 = 24 * 37: five nodes stuck there.
    while app.shown().unwrap().increment != 888 {
        app.apply(Action::Back1);
    }
    let text = screen(&app, 100, 30).backend().to_string();
    // The panel zooms on what the stuck nodes gathered in their episode.
    assert!(
        text.contains("Episode slip, 5 stuck") || text.contains("episode of the 5 stuck"),
        "{text}"
    );
    assert!(text.contains("episode slip max"), "{text}");
    insta::assert_snapshot!(text);
}

#[test]
fn event_log_80x24() {
    let mut app = app_after(INCREMENTS);
    app.apply(Action::ToggleLog);
    app.apply(Action::LogPageUp);
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains("a long description"), "{text}");
    assert!(text.contains("to wrap"), "wrapped, not cut: {text}");
    insta::assert_snapshot!(text);
}

#[test]
fn pinned_run_is_drawn_against_the_current_one() {
    let mut app = app_after(INCREMENTS);
    app.apply(Action::Pin);
    let text = screen(&app, 100, 30).backend().to_string();
    assert!(text.contains("pinned lambda 6.00"), "{text}");
    // Compare reads: a legend names both runs with their states, W goes
    // on a log axis, and both g curves are named.
    assert!(text.contains("o live"), "{text}");
    assert!(text.contains("x pinned"), "{text}");
    assert!(text.contains("unclassified"), "{text}");
    assert!(text.contains("W log"), "{text}");
    assert!(text.contains("· pinned 7,-7"), "{text}");
    insta::assert_snapshot!(text);
}

/// Text that runs into the edge of the screen or of a panel's foot was
/// cut: it must say so with `…`. Checked on the status lines and the
/// panels' feet, at 80 and 100 columns, in states with the longest texts
/// (a pinned run and its notice, an advancing stick scrubbed back to).
#[test]
fn nothing_is_cut_without_an_ellipsis() {
    let mut pinned = app_after(INCREMENTS);
    pinned.apply(Action::Pin);
    let mut stuck = app_after(INCREMENTS);
    while stuck.shown().unwrap().increment != 888 {
        stuck.apply(Action::Back1);
    }
    stuck.apply(Action::Pin);
    for app in [&pinned, &stuck] {
        for (w, h) in [(80u16, 24u16), (100, 30)] {
            let text = screen(app, w, h).backend().to_string();
            let lines: Vec<Vec<char>> = text
                .lines()
                .map(|l| l.trim_matches('"').chars().collect())
                .collect();
            let rows = lines.len();
            for line in &lines[rows - 2..] {
                if line.len() == w as usize && line[w as usize - 1] != ' ' {
                    assert_eq!(line[w as usize - 1], '…', "{w}x{h}:\n{text}");
                }
            }
            // The panels' feet: a title must end before a corner.
            let foot = &lines[rows - 4];
            for (i, &c) in foot.iter().enumerate().skip(1) {
                if c == '╯' {
                    let before = foot[i - 1];
                    assert!(
                        matches!(before, '─' | '…' | ' '),
                        "{w}x{h}: cut before a corner at column {i}:\n{text}"
                    );
                }
            }
        }
    }
}

#[test]
fn ascii_draws_ascii_only() {
    let mut app = app(true);
    let nodes = app.case().disc().nodes();
    let mut ascii = Config {
        ascii: true,
        ..config(true)
    };
    ascii.color = true;
    let case = app.case().clone();
    app = App::new(case, ascii);
    for i in 0..INCREMENTS {
        app.feed(synthetic(i, nodes));
    }
    for (w, h) in [(80, 24), (100, 30)] {
        let text = screen(&app, w, h).backend().to_string();
        assert!(text.is_ascii(), "{w}x{h}:\n{text}");
    }
    app.apply(Action::ToggleLog);
    assert!(screen(&app, 80, 24).backend().to_string().is_ascii());
    app.apply(Action::ToggleLog);
    app.apply(Action::Help);
    assert!(screen(&app, 80, 24).backend().to_string().is_ascii());
    app.apply(Action::Help);
    insta::assert_snapshot!(screen(&app, 100, 30).backend());
}

#[test]
fn help_overlay_80x24() {
    let mut app = app_after(10);
    app.apply(Action::Help);
    let text = screen(&app, 80, 24).backend().to_string();
    for b in bindings_for(Mode::Stepping) {
        assert!(text.contains(b.help), "help lacks {:?}", b.help);
        assert!(text.contains(b.label), "help lacks {:?}", b.label);
    }
    insta::assert_snapshot!(text);
}

#[test]
fn every_mode_lists_every_key_at_80x24() {
    let mut app = app_after(10);
    for mode in MODES {
        match mode {
            Mode::Sweep => app.show_view(View::Sweep),
            Mode::Regime => app.show_view(View::Regime),
            Mode::Log => {
                app.show_view(View::Stepping);
                app.apply(Action::ToggleLog);
            }
            Mode::Stepping => {}
            Mode::Tour => app.start_tour(),
        }
        assert_eq!(app.mode(), mode);
        app.apply(Action::Help);
        let text = screen(&app, 80, 24).backend().to_string();
        for b in bindings_for(mode) {
            assert!(
                text.contains(b.help),
                "{mode:?} help lacks {:?}:\n{text}",
                b.help
            );
        }
        app.apply(Action::Help);
    }
}

#[test]
fn too_small_says_so() {
    let app = app_after(10);
    for (w, h) in [(79, 24), (80, 23), (40, 10)] {
        let text = screen(&app, w, h).backend().to_string();
        assert!(text.contains("need 80x24"), "{w}x{h}:\n{text}");
    }
}

#[test]
fn any_size_draws_without_panic() {
    let app = app_after(300);
    for w in (1..=220).step_by(13) {
        for h in (1..=70).step_by(7) {
            screen(&app, w, h);
        }
    }
}

#[test]
fn no_color_draws_no_colour() {
    let app = fixed_app(false, INCREMENTS);
    let terminal = screen(&app, 160, 48);
    let buffer = terminal.backend().buffer();
    for cell in buffer.content() {
        assert_eq!(cell.fg, Color::Reset, "coloured cell {cell:?}");
        assert_eq!(cell.bg, Color::Reset, "coloured cell {cell:?}");
    }
    // The slip map still tells forward, backward and stick apart by glyph.
    let text = terminal.backend().to_string();
    assert!(text.contains('>') && text.contains('·'));
}

#[test]
fn colour_is_used_when_allowed() {
    let app = app_after(INCREMENTS);
    let terminal = screen(&app, 160, 48);
    assert!(terminal
        .backend()
        .buffer()
        .content()
        .iter()
        .any(|c| c.fg != Color::Reset));
}

#[test]
fn every_panel_has_its_title() {
    let app = app_after(INCREMENTS);
    for (w, h) in [(80, 24), (100, 30), (160, 48), (200, 60)] {
        let text = screen(&app, w, h).backend().to_string();
        for title in [
            "Load plane",
            "Slip zones",
            "Tractions",
            "Locked-in slip",
            "Dissipation",
            "lambda = 6.00",
        ] {
            assert!(text.contains(title), "{w}x{h} lacks {title}:\n{text}");
        }
    }
}

/// The sweep view with every run injected (no background thread, so no
/// timing): all marker kinds, a failed run, lambda_2 and the cursor.
fn sweep_app(color: bool) -> App {
    let case = Case::from_params(&default_params()).expect("the default case is valid");
    let source = common::tiny_sweep_source();
    let rows = common::fake_rows(&source);
    let mut app = App::with_sweep(case, config(color), Ok(source));
    let sweep = app.sweep_mut().expect("a sweep");
    for row in rows {
        sweep.insert(row);
    }
    sweep.set_limit(Ok(shakedown::analysis::limit::Limit {
        load_factor: 5.2,
        lower_bound: 5.2,
        slip: vec![0.0; 32],
        times: vec![],
        line: true,
        max_violation: 0.0,
        iterations: 0,
        pivots: 0,
    }));
    sweep.move_x(1);
    sweep.move_run(1);
    app.show_view(View::Sweep);
    app
}

#[test]
fn sweep_view_80x24() {
    insta::assert_snapshot!(screen(&sweep_app(true), 80, 24).backend());
}

#[test]
fn sweep_view_160x48() {
    insta::assert_snapshot!(screen(&sweep_app(true), 160, 48).backend());
}

#[test]
fn sweep_view_help_lists_its_keys() {
    let mut app = sweep_app(true);
    app.apply(Action::Help);
    let text = screen(&app, 80, 24).backend().to_string();
    for b in bindings_for(Mode::Sweep) {
        assert!(text.contains(b.help), "help lacks {:?}", b.help);
    }
    assert!(
        !text.contains("lambda + 0.05"),
        "stepping keys in the sweep help"
    );
}

#[test]
fn sweep_view_draws_at_any_size_and_without_colour() {
    let app = sweep_app(false);
    for (w, h) in [
        (80, 24),
        (81, 25),
        (120, 40),
        (300, 24),
        (80, 100),
        (20, 5),
        (0, 0),
    ] {
        let t = screen(&app, w, h);
        for cell in t.backend().buffer().content() {
            assert_eq!(cell.fg, Color::Reset);
        }
    }
}

/// The tour at stop `stop` (0-based), in the synthetic state: the stop's
/// case is opened, then fed the synthetic records instead of the solver's.
fn tour_app(stop: usize) -> App {
    let mut app = app(true);
    app.start_tour();
    for _ in 0..stop {
        app.apply(Action::TourNext);
    }
    let nodes = app.case().disc().nodes();
    for i in 0..INCREMENTS {
        app.feed(synthetic(i, nodes));
    }
    app
}

#[test]
fn tour_caption_80x24() {
    let app = tour_app(0);
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains("Tour 1/8: the stick diamond"), "{text}");
    assert!(text.contains("n next"), "{text}");
    assert!(text.contains("Esc take over"), "{text}");
    insta::assert_snapshot!(text);
}

#[test]
fn tour_second_stop_120x36() {
    let app = tour_app(1);
    let text = screen(&app, 120, 36).backend().to_string();
    assert!(
        text.contains("Tour 2/8: advancing stick on a transient that leaves it"),
        "{text}"
    );
    assert!(
        text.contains("e:on"),
        "it pauses at advancing stick: {text}"
    );
    insta::assert_snapshot!(text);
}

/// Every stop's caption is on screen whole at 100x30 (nothing cut), and
/// its title names the stop.
#[test]
fn every_tour_stop_shows_its_caption() {
    use shakedown::tui::app::tour::STOPS;
    let mut app = app(true);
    app.start_tour();
    for (k, stop) in STOPS.iter().enumerate() {
        let text = screen(&app, 100, 30).backend().to_string();
        let title = format!("Tour {}/{}: {}", k + 1, STOPS.len(), stop.title);
        assert!(text.contains(&title), "{title} not in {text}");
        // The caption's last word is on screen: it was not cut.
        let last = stop.caption.split_whitespace().last().unwrap();
        let last = last.replace("lambda_1", "λ₁").replace("lambda_2", "λ₂");
        assert!(
            text.contains(last.trim_end_matches('.')),
            "{last} not in {text}"
        );
        app.apply(Action::TourNext);
    }
}

/// A sweep of the paper's 25 transients at two `lambda`s, every run
/// injected: the table at the cursor is longer than the panel.
fn long_sweep_app() -> App {
    use shakedown::analysis::case::CaseParams;
    use shakedown::analysis::sweep::{Axis, SweepLists, SweepSpec};
    use shakedown::model::path::Initial;
    let params = CaseParams {
        nodes: 32,
        steps: 100,
        ..CaseParams::default()
    };
    let small = Case::from_params(&params).unwrap();
    let lists = SweepLists {
        load_factors: vec![5.0, 6.0],
        phases: vec![0.0],
        initials: Initial::paper_set(),
    };
    let source = shakedown::tui::sweep::SweepSource {
        name: "long".into(),
        spec: SweepSpec::over(&small, &lists).unwrap(),
        axis: Axis::Lambda,
    };
    let rows = common::fake_rows(&source);
    let case = Case::from_params(&default_params()).unwrap();
    let mut app = App::with_sweep(case, config(true), Ok(source));
    let sweep = app.sweep_mut().unwrap();
    for row in rows {
        sweep.insert(row);
    }
    app.show_view(View::Sweep);
    app
}

/// The table of transients at the cursor scrolls with the selection: the
/// selected `7,-7` (20th of 25) is on screen at 80x24 and at 120x36, and
/// so is the first row again after Home-like moves back up.
#[test]
fn sweep_table_scrolls_with_the_selection() {
    let mut app = long_sweep_app();
    for _ in 0..19 {
        app.apply(Action::SweepNextRun);
    }
    for (w, h) in [(80, 24), (120, 36)] {
        let text = screen(&app, w, h).backend().to_string();
        assert!(text.contains(">7,-7"), "{w}x{h}: {text}");
        assert!(text.contains("of 25):"), "{w}x{h}: {text}");
    }
    insta::assert_snapshot!(screen(&app, 80, 24).backend());
    for _ in 0..19 {
        app.apply(Action::SweepPrevRun);
    }
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains(">OA"), "{text}");
    assert!(text.contains("(1-"), "{text}");
}

/// `s` in the sweep view asks for the file name, and `overwrite? y/N`
/// when it exists: both on the status line.
#[test]
fn sweep_save_asks_on_the_status_line() {
    let dir = std::env::temp_dir().join(format!("shakedown-ask-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut app = sweep_app(true);
    app.set_save_dir(&dir);
    std::fs::write(dir.join("sweep-tiny.csv"), "mine").unwrap();
    app.apply(Action::SweepSave);
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains("save as: sweep-tiny.csv_"), "{text}");
    app.handle_key(crossterm::event::KeyEvent::from(
        crossterm::event::KeyCode::Enter,
    ));
    let text = screen(&app, 120, 36).backend().to_string();
    assert!(text.contains("exists: overwrite? y/N"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `s` shows its progress on the status line: the cycle, the change of
/// `W` the stopping rule watches against its tolerance, a gauge of the
/// cycles done out of about how many, and the time left. Fed synthetic
/// cycles whose `W` falls as `1/k`, so the change of `W` falls too.
#[test]
fn the_steady_goal_shows_its_progress() {
    let mut app = app(true);
    app.apply(Action::ToSteady);
    let nodes = app.case().disc().nodes();
    for i in 0..1700 {
        app.feed(synthetic(i, nodes));
    }
    let p = app.steady_progress().expect("progress while s runs");
    assert_eq!(p.cycles, 4);
    // W_k = 0.004 / k: the change from cycle 3 to 4 is 1/4 of W_3.
    assert!((p.change.unwrap() - 0.25).abs() < 1e-12, "{p:?}");
    assert_eq!(p.tolerance, 1e-4);
    // Falling from 1/3 to 1/4: ln(1e-4 / 0.25) / ln(0.75) = 27.2, so 28
    // cycles, and three more for the rule's three pairs.
    assert_eq!(p.cycles_left, Some(31));
    assert!(p.left.is_some());
    let text = screen(&app, 120, 36).backend().to_string();
    assert!(text.contains("» steady"), "{text}");
    assert!(text.contains("cycle 4/~35"), "{text}");
    assert!(text.contains("dW/W 2.50e-1 (to 1.00e-4)"), "{text}");
    assert!(text.contains("left"), "{text}");
}

/// A synthetic fretting profile of cycle 2 on `n` nodes: envelopes, slip
/// and dissipation shaped like the real ones, with the largest Ruiz
/// parameter at a node of its own choosing; nothing from the solver.
fn synthetic_profile(n: usize, friction: f64) -> shakedown::analysis::profile::Profile {
    let theta: Vec<f64> = (0..n).map(|j| 2.0 * PI * j as f64 / n as f64).collect();
    let col = |f: &dyn Fn(f64) -> f64| theta.iter().map(|&t| f(t)).collect::<Vec<f64>>();
    let p_max = col(&|t| 1.0 + 0.3 * t.cos());
    let p_min = col(&|t| 0.7 + 0.2 * t.cos());
    let q_max = col(&|t| friction * (1.0 + 0.3 * t.cos()) * (0.9 * t.sin()).max(-0.2));
    let q_min = col(&|t| -friction * (1.0 + 0.3 * t.cos()) * (0.9 * t.cos()).max(0.1));
    let slip_amplitude = col(&|t| 0.01 * t.sin().max(0.0).powi(2));
    let slip_accumulated = slip_amplitude.iter().map(|a| 2.5 * a).collect();
    let wear: Vec<f64> = slip_amplitude.iter().map(|a| 2.0 * a).collect();
    let dissipation = wear
        .iter()
        .map(|w| 0.5 * friction * w * 2.0 * PI / n as f64)
        .collect();
    let ruiz = (0..n)
        .map(|j| q_max[j].abs().max(q_min[j].abs()) * slip_amplitude[j])
        .collect();
    shakedown::analysis::profile::Profile {
        cycle: 2,
        theta,
        p_min,
        p_max,
        q_min,
        q_max,
        slip_amplitude,
        slip_accumulated,
        dissipation,
        ruiz,
        wear,
    }
}

fn profile_app(color: bool) -> App {
    let mut app = fixed_app(color, INCREMENTS);
    let nodes = app.case().disc().nodes();
    app.feed_profile(synthetic_profile(nodes, 0.3));
    app
}

/// `f`: the fretting profile of the last completed cycle replaces the
/// bottom row, with the hot spot named in words.
#[test]
fn fretting_profile_80x24() {
    let app = profile_app(true);
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains("hot spot"), "{text}");
    insta::assert_snapshot!(text);
}

#[test]
fn fretting_profile_200x60() {
    let app = profile_app(true);
    let text = screen(&app, 200, 60).backend().to_string();
    assert!(text.contains("hot spot (max Ruiz) at θ"), "{text}");
    assert!(text.contains("Cycle 2: q and p envelopes"), "{text}");
    insta::assert_snapshot!(text);
}

/// Before its first cycle completes the panel says when it will come, and
/// it draws at any size, in ASCII and without colour.
#[test]
fn fretting_profile_degrades_gracefully() {
    let mut app = fixed_app(true, 10);
    app.apply(Action::ToggleProfile);
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains("first cycle"), "{text}");
    let mut ascii = profile_app(false);
    ascii.apply(Action::Help);
    ascii.apply(Action::Help);
    for (w, h) in [(80, 24), (81, 25), (120, 30), (200, 60), (79, 23)] {
        let _ = screen(&ascii, w, h);
    }
    let config = Config {
        ascii: true,
        ..config(false)
    };
    let case = app.case().clone();
    let mut plain = App::new(case, config);
    let nodes = plain.case().disc().nodes();
    for i in 0..INCREMENTS {
        plain.feed(synthetic(i, nodes));
    }
    plain.feed_profile(synthetic_profile(nodes, 0.3));
    let text = screen(&plain, 80, 24).backend().to_string();
    assert!(text.is_ascii(), "{text}");
    assert!(text.contains("hot spot"), "{text}");
}
