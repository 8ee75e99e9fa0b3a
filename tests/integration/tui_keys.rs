//! Every key of the table, through the same dispatch the terminal uses.

use std::f64::consts::PI;
use std::time::Duration;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::backend::TestBackend;
use ratatui::Terminal;
use shakedown::analysis::case::Case;
use shakedown::stepping::{Phase, Status};
use shakedown::tui::app::{App, Config, Confirm, Goal, View};
use shakedown::tui::keys::{bindings_for, event_for, Action, Mode, MODES};
use shakedown::tui::log::EventKind;
use shakedown::tui::{default_params, ui};

use crate::common;

/// The default case, with a tiny sweep for the sweep view (and a tiny
/// regime map) so that keys which start them do not start a full preset's.
fn app() -> App {
    let case = Case::from_params(&default_params()).expect("the default case is valid");
    let mut app = App::with_sweep(case, Config::default(), Ok(common::tiny_sweep_source()));
    app.set_regime_source(Ok(common::tiny_regime_source()));
    app
}

fn press(app: &mut App, code: KeyCode, modifiers: KeyModifiers) {
    app.handle_key(KeyEvent::new(code, modifiers));
}

fn key(app: &mut App, code: KeyCode) {
    press(app, code, KeyModifiers::NONE);
}

/// Frames until the goal set by `c` or `s` is reached; the cap turns a
/// goal that never ends into a failure rather than a hang.
fn run_goal(app: &mut App) {
    for _ in 0..10_000 {
        if app.goal().is_none() {
            return;
        }
        app.tick(Duration::from_millis(50));
        std::thread::sleep(Duration::from_millis(1));
    }
    panic!("goal {:?} not reached", app.goal());
}

fn screen(app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("test backend");
    terminal
        .draw(|frame| ui::draw(frame, app))
        .expect("drawing to a test backend cannot fail");
    terminal
}

fn assert_restarted(app: &App) {
    assert_eq!(app.increments(), 0);
    assert!(app.history().is_empty());
    let notice = app.notice().unwrap_or_default();
    assert!(notice.contains("restarted from O"), "notice: {notice}");
}

/// What each action must do. The match is exhaustive, so an action added
/// to the table without a test here does not compile.
fn check(action: Action, event: KeyEvent, mode: Mode) {
    let mut app = app();
    app.advance(50);
    let view = match mode {
        Mode::Sweep => View::Sweep,
        Mode::Regime => View::Regime,
        _ => View::Stepping,
    };
    app.show_view(view);
    if mode == Mode::Log {
        // Into the first cycle, where events come thick.
        app.advance(400);
        app.apply(Action::ToggleLog);
        assert_eq!(app.mode(), Mode::Log);
    }
    if mode == Mode::Tour {
        app.start_tour();
        assert_eq!(app.mode(), Mode::Tour);
    }
    let lambda = app.load_factor();
    let phase = app.phase();
    let handle = |app: &mut App| app.handle_key(event);
    match action {
        Action::LoadFactorDown => {
            handle(&mut app);
            assert!((app.load_factor() - (lambda - 0.05)).abs() < 1e-12);
            assert_restarted(&app);
        }
        Action::LoadFactorUp => {
            handle(&mut app);
            assert!((app.load_factor() - (lambda + 0.05)).abs() < 1e-12);
            assert_restarted(&app);
        }
        Action::LoadFactorDownBig => {
            handle(&mut app);
            assert!((app.load_factor() - (lambda - 0.5)).abs() < 1e-12);
            assert_restarted(&app);
        }
        Action::LoadFactorUpBig => {
            handle(&mut app);
            assert!((app.load_factor() - (lambda + 0.5)).abs() < 1e-12);
            assert_restarted(&app);
        }
        Action::PhaseDown => {
            handle(&mut app);
            assert!((app.phase() - (phase - PI / 24.0)).abs() < 1e-12);
            assert_restarted(&app);
        }
        Action::PhaseUp => {
            handle(&mut app);
            assert!((app.phase() - (phase + PI / 24.0)).abs() < 1e-12);
            assert_restarted(&app);
        }
        Action::PreviousPath | Action::NextPath => {
            let n = app.paths().len();
            let before = app.path_index();
            handle(&mut app);
            let expected = if action == Action::NextPath {
                (before + 1) % n
            } else {
                (before + n - 1) % n
            };
            assert_eq!(app.path_index(), expected);
            assert_eq!(app.initial(), &app.paths()[expected]);
            assert_restarted(&app);
        }
        Action::RunPause => {
            assert!(app.is_running());
            handle(&mut app);
            assert!(!app.is_running());
            let at = app.increments();
            app.tick(Duration::from_millis(50));
            std::thread::sleep(Duration::from_millis(30));
            app.tick(Duration::from_millis(50));
            assert_eq!(app.increments(), at, "paused, yet it stepped");
            handle(&mut app);
            assert!(app.is_running());
            wait_until(&mut app, |a| a.increments() > at);
        }
        Action::StepOne => {
            let at = app.increments();
            handle(&mut app);
            app.settle();
            assert_eq!(app.increments(), at + 1);
            assert!(!app.is_running());
            handle(&mut app);
            app.settle();
            assert_eq!(app.increments(), at + 2);
        }
        Action::ToCycleEnd => {
            // In the transient, `c` stops where the transient ends ...
            handle(&mut app);
            assert_eq!(app.goal(), Some(Goal::TransientEnd));
            run_goal(&mut app);
            assert_eq!(
                app.stepper_phase(),
                Phase::Cycle {
                    cycle: 1,
                    increment: 0
                }
            );
            // ... and in a cycle, where the cycle ends.
            app.advance(7);
            handle(&mut app);
            run_goal(&mut app);
            assert_eq!(app.cycles().len(), 1);
            assert_eq!(
                app.stepper_phase(),
                Phase::Cycle {
                    cycle: 2,
                    increment: 0
                }
            );
            assert!(!app.is_running());
        }
        Action::ToSteady => {
            handle(&mut app);
            assert_eq!(app.goal(), Some(Goal::Steady));
            run_goal(&mut app);
            let Status::Steady(summary) = app.status() else {
                panic!("not steady: {:?}", app.status());
            };
            let notice = app.notice().unwrap_or_default();
            assert!(notice.contains(summary.state().as_str()), "{notice}");
            // Asking again says so instead of running on.
            handle(&mut app);
            assert_eq!(app.goal(), None);
            assert!(app.notice().unwrap_or_default().contains("already"));
        }
        Action::Reset => {
            key(&mut app, KeyCode::Char(' '));
            handle(&mut app);
            assert_eq!(app.increments(), 0);
            assert!(app.history().is_empty());
            assert!(app.is_running(), "r reruns the transient");
            assert!(app.notice().unwrap_or_default().contains("reset"));
        }
        Action::Faster => {
            let speed = app.speed();
            handle(&mut app);
            assert_eq!(app.speed(), speed * 2);
            for _ in 0..20 {
                handle(&mut app);
            }
            assert_eq!(app.speed(), 256);
        }
        Action::Slower => {
            let speed = app.speed();
            handle(&mut app);
            assert_eq!(app.speed(), speed / 2);
            for _ in 0..20 {
                handle(&mut app);
            }
            assert_eq!(app.speed(), 1);
        }
        Action::PauseOnEvents => {
            assert!(!app.pauses_on_events());
            handle(&mut app);
            assert!(app.pauses_on_events());
            // Running now stops at the first event worth seeing.
            wait_until(&mut app, |a| !a.is_running());
            let notice = app.notice().unwrap_or_default();
            // Events inside an increment stop the run at the event.
            assert!(notice.contains("paused at the event"), "{notice}");
            handle(&mut app);
            assert!(!app.pauses_on_events());
        }
        Action::Help => {
            handle(&mut app);
            assert!(app.help_visible());
            handle(&mut app);
            assert!(!app.help_visible());
        }
        Action::Quit => {
            handle(&mut app);
            assert!(app.should_quit());
            assert_eq!(app.exit_code(), 0);
        }
        Action::Interrupt => {
            handle(&mut app);
            assert!(app.should_quit());
            assert_eq!(app.exit_code(), 130);
        }
        Action::Suspend => {
            handle(&mut app);
            assert!(app.take_suspend());
            assert!(!app.take_suspend());
        }
        Action::Back => {
            handle(&mut app);
            assert!(!app.should_quit(), "Esc never quits");
            assert_eq!(app.view(), View::Stepping);
            assert!(!app.log_visible());
        }
        Action::Back1 => {
            handle(&mut app);
            assert_eq!(app.cursor(), Some(48));
            assert!(!app.is_running(), "looking back pauses");
            handle(&mut app);
            assert_eq!(app.cursor(), Some(47));
            assert_eq!(app.shown().unwrap().increment, 47);
        }
        Action::Forward1 => {
            app.apply(Action::Back1);
            app.apply(Action::Back1);
            handle(&mut app);
            assert_eq!(app.cursor(), Some(48));
            handle(&mut app);
            assert_eq!(app.cursor(), None, "forward to the newest is live");
        }
        Action::BackCycle | Action::Oldest => {
            handle(&mut app);
            assert_eq!(app.cursor(), Some(0));
            assert_eq!(app.shown().unwrap().increment, 0);
        }
        Action::ForwardCycle | Action::Live => {
            app.apply(Action::Oldest);
            handle(&mut app);
            assert_eq!(app.cursor(), None);
        }
        Action::PrevEvent | Action::NextEvent => {
            if action == Action::NextEvent {
                app.apply(Action::Oldest);
            }
            let before = app.cursor();
            handle(&mut app);
            let notice = app.notice().unwrap_or_default().to_string();
            assert!(
                app.cursor() != before || notice.starts_with("no "),
                "{notice}"
            );
            if let Some(c) = app.cursor().filter(|_| app.cursor() != before) {
                assert!(app
                    .log()
                    .iter()
                    .any(|e| e.increment == c && app.filter().matches(e)));
            }
        }
        Action::EventKind => {
            assert_eq!(app.filter().kind, None);
            handle(&mut app);
            assert!(app.filter().kind.is_some());
        }
        Action::MinNodes => {
            handle(&mut app);
            assert_eq!(app.filter().min_nodes, 2);
        }
        Action::ToggleLog => {
            let open = app.log_visible();
            handle(&mut app);
            assert_eq!(app.log_visible(), !open);
        }
        Action::LogUp | Action::LogPageUp | Action::LogFirst => {
            let n = app.log_entries().len();
            assert!(n > 1, "events in 450 increments");
            assert_eq!(app.log_selected(), n - 1, "the log opens at the newest");
            handle(&mut app);
            assert!(app.log_selected() < n - 1);
        }
        Action::LogDown | Action::LogPageDown | Action::LogLast => {
            app.apply(Action::LogFirst);
            handle(&mut app);
            assert!(app.log_selected() > 0);
        }
        Action::LogGo => {
            app.apply(Action::LogFirst);
            let i = app.log_entries()[0].increment;
            handle(&mut app);
            assert!(!app.log_visible());
            assert_eq!(app.shown().unwrap().increment, i);
        }
        Action::ToggleProfile => {
            // Before a cycle completes the panel opens and says so.
            handle(&mut app);
            assert!(app.profile_panel().is_visible());
            let notice = app.notice().unwrap_or_default();
            assert!(notice.contains("first cycle completes"), "{notice}");
            assert!(app.profile_panel().profile().is_none());
            // Through the transient and cycle 1: the worker profiles
            // cycle 1 off the UI thread, and its dissipation column sums
            // to the W the run recorded for that cycle (model.md 4.1).
            app.apply(Action::ToCycleEnd);
            run_goal(&mut app);
            app.apply(Action::ToCycleEnd);
            run_goal(&mut app);
            wait_until(&mut app, |a| a.profile_panel().profile().is_some());
            let profile = app.profile_panel().profile().unwrap();
            assert_eq!(profile.cycle, 1);
            let w = app.profile_w().expect("W of cycle 1");
            let sum = profile.total_dissipation();
            assert!(w > 0.0 && (sum - w).abs() <= 1e-9 * w, "{sum} against {w}");
            let text = screen(&app, 80, 24).backend().to_string();
            assert!(text.contains("hot spot"), "{text}");
            handle(&mut app);
            assert!(!app.profile_panel().is_visible());
            let text = screen(&app, 80, 24).backend().to_string();
            assert!(!text.contains("hot spot"), "{text}");
        }
        Action::Pin => {
            handle(&mut app);
            assert!(app.pinned().is_some());
            handle(&mut app);
            assert!(app.pinned().is_none());
        }
        Action::Entry => {
            handle(&mut app);
            assert_eq!(app.entry(), Some(""));
            for c in "lambda = 5.13".chars() {
                key(&mut app, KeyCode::Char(c));
            }
            key(&mut app, KeyCode::Enter);
            assert_eq!(app.entry(), None);
            assert!((app.load_factor() - 5.13).abs() < 1e-12);
            assert_restarted(&app);
        }
        Action::SweepPageDown | Action::SweepLast => {
            handle(&mut app);
            assert_eq!(app.sweep().unwrap().cursor(), (2, 0));
        }
        Action::SweepPageUp | Action::SweepFirst => {
            app.apply(Action::SweepLast);
            handle(&mut app);
            assert_eq!(app.sweep().unwrap().cursor(), (0, 0));
        }
        Action::SweepLogW => {
            let log = app.sweep_log_w();
            handle(&mut app);
            assert_eq!(app.sweep_log_w(), !log);
        }
        Action::SweepSave => {
            let dir = std::env::temp_dir().join(format!("shakedown-save-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            app.set_save_dir(&dir);
            handle(&mut app);
            // It asks for the name, prefilled with the preset's.
            let name = app.save_entry().unwrap_or_default().to_string();
            assert!(
                name.starts_with("sweep-") && name.ends_with(".csv"),
                "{name}"
            );
            key(&mut app, KeyCode::Enter);
            let notice = app.notice().unwrap_or_default().to_string();
            assert!(notice.starts_with("saved"), "{notice}");
            let path = dir.join(&name);
            let text = std::fs::read_to_string(&path).unwrap();
            // sweep's writer: the metadata header, then the column line.
            assert!(text.starts_with('#'), "{text}");
            assert!(
                text.lines()
                    .any(|l| l == shakedown::analysis::sweep::CSV_HEADER),
                "{text}"
            );
            // A second save asks before it replaces the file; anything
            // but `y` keeps it.
            std::fs::write(&path, "mine").unwrap();
            handle(&mut app);
            key(&mut app, KeyCode::Enter);
            assert_eq!(app.confirm(), Some(Confirm::Overwrite));
            key(&mut app, KeyCode::Char('n'));
            assert!(app.notice().unwrap_or_default().starts_with("not saved"));
            assert_eq!(std::fs::read_to_string(&path).unwrap(), "mine");
            handle(&mut app);
            key(&mut app, KeyCode::Enter);
            key(&mut app, KeyCode::Enter);
            assert_eq!(
                std::fs::read_to_string(&path).unwrap(),
                "mine",
                "Enter is no"
            );
            // `y` replaces it, header and all.
            handle(&mut app);
            key(&mut app, KeyCode::Enter);
            key(&mut app, KeyCode::Char('y'));
            assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
            // Esc while typing saves nothing; another name is another file.
            handle(&mut app);
            key(&mut app, KeyCode::Esc);
            assert!(app.save_entry().is_none());
            handle(&mut app);
            for _ in 0..4 {
                key(&mut app, KeyCode::Backspace);
            }
            for c in "-b.csv".chars() {
                key(&mut app, KeyCode::Char(c));
            }
            key(&mut app, KeyCode::Enter);
            assert!(dir
                .join(format!("{}-b.csv", &name[..name.len() - 4]))
                .exists());
            let _ = std::fs::remove_dir_all(&dir);
        }
        Action::ToggleView => {
            handle(&mut app);
            let other = match view {
                View::Stepping => View::Sweep,
                View::Sweep | View::Regime => View::Stepping,
            };
            assert_eq!(app.view(), other);
            if other == View::Sweep {
                assert!(
                    app.sweep().unwrap().started(),
                    "the sweep starts when shown"
                );
            }
            handle(&mut app);
            // The regime map is one key (g) away from the sweep view.
            let back = if view == View::Regime {
                View::Sweep
            } else {
                view
            };
            assert_eq!(app.view(), back);
        }
        Action::ToggleRegime => {
            handle(&mut app);
            if view == View::Regime {
                // Shown directly: back to the sweep view, and in again.
                assert_eq!(app.view(), View::Sweep);
                handle(&mut app);
                assert_eq!(app.view(), View::Regime);
            } else {
                assert_eq!(app.view(), View::Regime);
                let r = app.regime().unwrap();
                assert!(r.started() && r.is_running(), "the map computes when shown");
                handle(&mut app);
                assert_eq!(app.view(), view, "g goes back where it came from");
                assert!(!app.regime().unwrap().is_running(), "and only then");
            }
        }
        Action::RegimePrevLambda | Action::RegimeNextLambda => {
            // Three lambdas: start in the middle so both ways move.
            app.apply(Action::RegimeNextLambda);
            handle(&mut app);
            let expected = if action == Action::RegimeNextLambda {
                2
            } else {
                0
            };
            assert_eq!(app.regime().unwrap().cursor(), (expected, 0));
            handle(&mut app);
            assert_eq!(app.regime().unwrap().cursor(), (expected, 0), "clamped");
        }
        Action::RegimePhaseUp => {
            handle(&mut app);
            assert_eq!(app.regime().unwrap().cursor(), (0, 1));
            handle(&mut app);
            assert_eq!(app.regime().unwrap().cursor(), (0, 1), "clamped");
        }
        Action::RegimePhaseDown => {
            app.apply(Action::RegimePhaseUp);
            handle(&mut app);
            assert_eq!(app.regime().unwrap().cursor(), (0, 0));
        }
        Action::RegimePageDown | Action::RegimeLast => {
            handle(&mut app);
            assert_eq!(app.regime().unwrap().cursor(), (2, 0));
        }
        Action::RegimePageUp | Action::RegimeFirst => {
            app.apply(Action::RegimeLast);
            handle(&mut app);
            assert_eq!(app.regime().unwrap().cursor(), (0, 0));
        }
        Action::RegimeOpen => {
            app.apply(Action::RegimeNextLambda);
            app.apply(Action::RegimePhaseUp);
            handle(&mut app);
            assert_eq!(app.view(), View::Stepping);
            assert_eq!(app.load_factor(), 5.5);
            assert_eq!(app.phase(), PI / 2.0);
            assert_eq!(app.initial().name(), "OA");
            assert_eq!(app.paths()[app.path_index()].name(), "OA");
            assert!(app.is_running());
            assert_eq!(app.increments(), 0);
            let notice = app.notice().unwrap_or_default();
            assert!(notice.contains("opened lambda 5.50, phi pi/2"), "{notice}");
        }
        Action::RegimePrevPath | Action::RegimeNextPath => {
            assert_eq!(app.regime().unwrap().initial().name(), "OA");
            handle(&mut app);
            let n = app.paths().len();
            let expected = if action == Action::RegimeNextPath {
                1
            } else {
                n - 1
            };
            let r = app.regime().unwrap();
            assert_eq!(r.initial(), &app.paths()[expected]);
            assert_eq!(r.done(), 0, "the map of another path starts empty");
            assert!(r.is_running());
        }
        Action::Tour => {
            handle(&mut app);
            assert_eq!(app.tour().map(|(k, _)| k), Some(0));
            assert_eq!(app.mode(), Mode::Tour);
            assert_eq!(app.view(), View::Stepping);
        }
        Action::TourNext => {
            handle(&mut app);
            assert_eq!(app.tour().map(|(k, _)| k), Some(1));
            assert!(app.pauses_on_events(), "stop 2 pauses at advancing stick");
            assert_eq!(app.initial().name(), "7,-7");
        }
        Action::TourPrevious => {
            app.apply(Action::TourNext);
            app.apply(Action::TourNext);
            handle(&mut app);
            assert_eq!(app.tour().map(|(k, _)| k), Some(1));
            handle(&mut app);
            handle(&mut app);
            assert_eq!(app.tour().map(|(k, _)| k), Some(0), "stops at the first");
        }
        Action::TourLeave => {
            let lambda = app.load_factor();
            handle(&mut app);
            assert!(app.tour().is_none());
            assert_eq!(app.mode(), Mode::Stepping);
            assert_eq!(app.load_factor(), lambda, "the case stays");
        }
        Action::RegimeRestart => {
            handle(&mut app);
            let r = app.regime().unwrap();
            assert!(r.is_running());
            assert_eq!(r.done(), 0);
            assert!(app.notice().unwrap_or_default().contains("again"));
        }
        Action::SweepPrevX | Action::SweepNextX => {
            // Three lambdas: start in the middle so both ways move.
            app.apply(Action::SweepNextX);
            handle(&mut app);
            let expected = if action == Action::SweepNextX { 2 } else { 0 };
            assert_eq!(app.sweep().unwrap().cursor(), (expected, 0));
            // Clamped at the ends rather than wrapping.
            handle(&mut app);
            handle(&mut app);
            assert_eq!(app.sweep().unwrap().cursor(), (expected, 0));
        }
        Action::SweepPrevRun | Action::SweepNextRun => {
            // Two initial paths per lambda: either way reaches the other,
            // and a second press wraps back.
            handle(&mut app);
            assert_eq!(app.sweep().unwrap().cursor(), (0, 1));
            handle(&mut app);
            assert_eq!(app.sweep().unwrap().cursor(), (0, 0));
        }
        Action::OpenRun => {
            app.apply(Action::SweepNextX);
            app.apply(Action::SweepNextRun);
            handle(&mut app);
            assert_eq!(app.view(), View::Stepping);
            assert_eq!(app.load_factor(), 5.5);
            assert_eq!(app.phase(), 0.0);
            assert_eq!(app.paths()[app.path_index()].name(), "7,-7");
            assert_eq!(app.initial().name(), "7,-7");
            assert!(app.is_running());
            assert_eq!(app.increments(), 0);
            let notice = app.notice().unwrap_or_default();
            assert!(notice.contains("opened lambda 5.50"), "{notice}");
        }
        Action::RestartSweep => {
            handle(&mut app);
            let sweep = app.sweep().unwrap();
            assert!(sweep.started());
            assert_eq!(sweep.done(), 0);
            assert!(app.notice().unwrap_or_default().contains("restarted"));
        }
    }
}

#[test]
fn every_key_in_the_table_does_what_it_says() {
    for mode in MODES {
        for binding in bindings_for(mode) {
            for k in binding.keys {
                check(binding.action, event_for(k), mode);
            }
        }
    }
}

/// Ticks (as frames do) until `done`, or fail after ten seconds.
fn wait_until(app: &mut App, done: impl Fn(&App) -> bool) {
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    while !done(app) {
        assert!(std::time::Instant::now() < deadline, "timed out");
        app.tick(Duration::from_millis(8));
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// The sweep runs in the background and its rows arrive while frames go
/// on; Enter then opens a finished run, and q cancels a sweep in progress.
#[test]
fn the_sweep_fills_in_and_enter_opens_a_run() {
    let mut app = app();
    key(&mut app, KeyCode::Char('v'));
    assert_eq!(app.view(), View::Sweep);
    let deadline = std::time::Instant::now() + Duration::from_secs(120);
    while app.sweep().unwrap().done() < 6 || app.sweep().unwrap().is_running() {
        assert!(
            std::time::Instant::now() < deadline,
            "the tiny sweep took too long"
        );
        app.tick(Duration::from_millis(8));
        std::thread::sleep(Duration::from_millis(10));
    }
    let sweep = app.sweep().unwrap();
    assert_eq!(sweep.total(), 6);
    let known = |s: &shakedown::tui::sweep::LimitState| {
        !matches!(s, shakedown::tui::sweep::LimitState::Computing)
    };
    while !known(app.sweep().unwrap().limit()) {
        assert!(
            std::time::Instant::now() < deadline,
            "lambda_2 took too long"
        );
        app.tick(Duration::from_millis(8));
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(matches!(
        app.sweep().unwrap().limit(),
        shakedown::tui::sweep::LimitState::Known(_)
    ));
    let mut terminal = Terminal::new(TestBackend::new(80, 24)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    assert!(text.contains("6/6 runs"), "{text}");
    assert!(text.contains("λ2="), "{text}");

    key(&mut app, KeyCode::Right);
    key(&mut app, KeyCode::Right);
    // Down the table: the next transient.
    key(&mut app, KeyCode::Down);
    let (job, row) = app.sweep().unwrap().selected().unwrap();
    assert_eq!((job.load_factor, job.initial), (7.0, 1));
    assert!(row.is_some());
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.view(), View::Stepping);
    assert_eq!(app.load_factor(), 7.0);
    assert_eq!(app.initial().name(), "7,-7");

    // Esc goes back to the stepping view; it never quits.
    key(&mut app, KeyCode::Tab);
    key(&mut app, KeyCode::Esc);
    assert_eq!(app.view(), View::Stepping);
    assert!(!app.should_quit());
    // r asks before it throws the finished map away; n keeps it.
    key(&mut app, KeyCode::Tab);
    key(&mut app, KeyCode::Char('r'));
    assert!(app.confirm().is_some());
    key(&mut app, KeyCode::Char('n'));
    assert_eq!(app.sweep().unwrap().done(), 6);
    key(&mut app, KeyCode::Char('r'));
    key(&mut app, KeyCode::Char('y'));
    assert!(app.sweep().unwrap().is_running());
    // A storm of reruns (each confirmed) leaves one sweep running.
    for _ in 0..40 {
        key(&mut app, KeyCode::Char('r'));
        key(&mut app, KeyCode::Char('y'));
    }
    assert!(app.sweep().unwrap().is_running());
    // q asks while it runs; y quits and the runs not started are dropped.
    key(&mut app, KeyCode::Char('q'));
    assert!(!app.should_quit());
    key(&mut app, KeyCode::Char('y'));
    assert!(app.should_quit());
    assert!(!app.sweep().unwrap().is_running());
}

/// The arrows move the sweep cursor in the sweep view and change the case
/// in the stepping view: one table, two meanings.
#[test]
fn arrows_follow_the_view() {
    let mut app = app();
    app.show_view(View::Sweep);
    let lambda = app.load_factor();
    key(&mut app, KeyCode::Right);
    assert_eq!(app.load_factor(), lambda);
    assert_eq!(app.sweep().unwrap().cursor(), (1, 0));
    app.show_view(View::Stepping);
    key(&mut app, KeyCode::Right);
    assert!((app.load_factor() - (lambda + 0.05)).abs() < 1e-12);
    assert_eq!(app.sweep().unwrap().cursor(), (1, 0));
}

#[test]
fn the_table_covers_the_issue_keys() {
    let mut app = app();
    let cases: [(KeyCode, KeyModifiers, Action); 23] = [
        (KeyCode::Left, KeyModifiers::NONE, Action::LoadFactorDown),
        (KeyCode::Right, KeyModifiers::NONE, Action::LoadFactorUp),
        (
            KeyCode::Left,
            KeyModifiers::SHIFT,
            Action::LoadFactorDownBig,
        ),
        (KeyCode::Right, KeyModifiers::SHIFT, Action::LoadFactorUpBig),
        (KeyCode::Down, KeyModifiers::NONE, Action::PhaseDown),
        (KeyCode::Up, KeyModifiers::NONE, Action::PhaseUp),
        (KeyCode::Char('['), KeyModifiers::NONE, Action::PreviousPath),
        (KeyCode::Char(']'), KeyModifiers::NONE, Action::NextPath),
        (KeyCode::Char(' '), KeyModifiers::NONE, Action::RunPause),
        (KeyCode::Char('n'), KeyModifiers::NONE, Action::StepOne),
        (KeyCode::Char('.'), KeyModifiers::NONE, Action::Forward1),
        (KeyCode::Char(','), KeyModifiers::NONE, Action::Back1),
        (KeyCode::Char('L'), KeyModifiers::SHIFT, Action::ToggleLog),
        (KeyCode::Char('}'), KeyModifiers::SHIFT, Action::NextEvent),
        (KeyCode::Char('p'), KeyModifiers::NONE, Action::Pin),
        (KeyCode::Char(':'), KeyModifiers::SHIFT, Action::Entry),
        (KeyCode::Char('c'), KeyModifiers::NONE, Action::ToCycleEnd),
        (KeyCode::Char('s'), KeyModifiers::NONE, Action::ToSteady),
        (KeyCode::Char('r'), KeyModifiers::NONE, Action::Reset),
        (KeyCode::Char('+'), KeyModifiers::SHIFT, Action::Faster),
        (KeyCode::Char('-'), KeyModifiers::NONE, Action::Slower),
        (
            KeyCode::Char('e'),
            KeyModifiers::NONE,
            Action::PauseOnEvents,
        ),
        (KeyCode::Char('?'), KeyModifiers::SHIFT, Action::Help),
    ];
    for (code, mods, action) in cases {
        assert_eq!(
            shakedown::tui::keys::action_for(&KeyEvent::new(code, mods), Mode::Stepping),
            Some(action),
            "{code:?} {mods:?}"
        );
    }
    for (code, mods, action) in [
        (KeyCode::Char('q'), KeyModifiers::NONE, Action::Quit),
        (KeyCode::Esc, KeyModifiers::NONE, Action::Back),
        (KeyCode::Char('c'), KeyModifiers::CONTROL, Action::Interrupt),
    ] {
        for mode in MODES {
            // While the tour has the keys, Esc leaves it.
            let action = match (mode, action) {
                (Mode::Tour, Action::Back) => Action::TourLeave,
                _ => action,
            };
            assert_eq!(
                shakedown::tui::keys::action_for(&KeyEvent::new(code, mods), mode),
                Some(action)
            );
        }
    }
    // Unbound keys do nothing.
    let before = app.increments();
    key(&mut app, KeyCode::Char('z'));
    key(&mut app, KeyCode::F(5));
    assert_eq!(app.increments(), before);
    assert!(!app.should_quit());
}

#[test]
fn esc_closes_and_never_quits() {
    let mut app = app();
    key(&mut app, KeyCode::Char('?'));
    assert!(app.help_visible());
    key(&mut app, KeyCode::Esc);
    assert!(!app.help_visible());
    key(&mut app, KeyCode::Esc);
    assert!(!app.should_quit());
    app.show_view(View::Sweep);
    key(&mut app, KeyCode::Esc);
    assert_eq!(app.view(), View::Stepping);
    assert!(!app.should_quit());
}

/// The mouse wheel scrolls history and never changes lambda or phi.
#[test]
fn the_wheel_scrolls_history_not_the_case() {
    let mut app = app();
    app.advance(30);
    let (lambda, phi) = (app.load_factor(), app.phase());
    for _ in 0..5 {
        app.scroll(-1);
    }
    assert_eq!(app.cursor(), Some(24));
    for _ in 0..10 {
        app.scroll(1);
    }
    assert_eq!(app.cursor(), None);
    assert_eq!((app.load_factor(), app.phase()), (lambda, phi));
    assert_eq!(app.increments(), 30);
}

/// Keys are answered at once while the worker steps a large model: the
/// UI thread never runs an increment.
#[test]
fn keys_answer_while_a_large_model_steps() {
    let mut params = default_params();
    params.nodes = 1024;
    let case = Case::from_params(&params).unwrap();
    let mut app = App::with_sweep(case, Config::default(), Ok(common::tiny_sweep_source()));
    app.apply(Action::ToSteady);
    for _ in 0..20 {
        let t = std::time::Instant::now();
        app.tick(Duration::from_millis(8));
        key(&mut app, KeyCode::Char('?'));
        assert!(
            t.elapsed() < Duration::from_millis(100),
            "{:?}",
            t.elapsed()
        );
    }
    let t = std::time::Instant::now();
    key(&mut app, KeyCode::Right);
    app.tick(Duration::from_millis(8));
    assert!(
        t.elapsed() < Duration::from_millis(100),
        "{:?}",
        t.elapsed()
    );
    assert!((app.load_factor() - 6.05).abs() < 1e-12);
}

/// Scrubbing shows the past instant in every panel, and the history
/// stays within a small budget at a high rate.
#[test]
fn history_scrubs_and_stays_within_budget() {
    let case = Case::from_params(&default_params()).unwrap();
    let config = Config {
        history_bytes: 1 << 20,
        ..Config::default()
    };
    let mut app = App::with_sweep(case, config, Ok(common::tiny_sweep_source()));
    app.advance(3000);
    let h = app.history();
    assert!(h.bytes() <= 1 << 20, "{}", h.bytes());
    assert!(h.thinned_before().is_some() || h.dropped_before().is_some());
    assert_eq!(app.increments(), 3000);
    app.apply(Action::Oldest);
    let first = app.shown().unwrap().increment;
    assert!(first < 2999);
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    assert!(text.contains(" history "), "{text}");
    assert!(
        text.contains("detail 1/") || text.contains("history from #"),
        "{text}"
    );
}

/// The event log lists events with their place, and the pause filter
/// skips advancing stick smaller than asked.
#[test]
fn events_are_logged_and_filtered_by_size() {
    let mut app = app();
    app.advance(800);
    assert!(app
        .log()
        .iter()
        .any(|e| e.kind == EventKind::AdvancingStick));
    let small = app
        .log()
        .iter()
        .filter(|e| e.kind == EventKind::AdvancingStick && e.nodes < 4)
        .count();
    assert!(small > 0, "one-node sticks happen in this case");
    // Choose advancing stick of at least 4 nodes and pause on it.
    while app.filter().kind != Some(EventKind::AdvancingStick) {
        app.apply(Action::EventKind);
    }
    while app.filter().min_nodes != 4 {
        app.apply(Action::MinNodes);
    }
    app.apply(Action::Reset);
    app.apply(Action::PauseOnEvents);
    wait_until(&mut app, |a| !a.is_running());
    let last = app.latest().unwrap();
    let e = last
        .events
        .iter()
        .find(|e| e.kind == EventKind::AdvancingStick)
        .expect("paused on an advancing stick")
        .clone();
    assert!(e.nodes >= 4, "{e:?}");
    // The run stopped at the event's load point, inside its increment: the
    // panels show the contact there, not at the end of the increment.
    assert_eq!(last.load, e.load, "{e:?}");
    assert_eq!(last.time, e.time, "{e:?}");
    assert!(last.partial.is_some(), "inside the increment");
    // The status line says the run is at the event's load point.
    let mut terminal = Terminal::new(TestBackend::new(80, 24)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    let point = format!("+ event at ({:.4}, {:.4})", e.load.0, e.load.1);
    assert!(text.contains(&point), "{point} not in {text}");
    // The log overlay shows the entries unclipped at 80 columns.
    app.apply(Action::ToggleLog);
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    assert!(text.contains("Event log"), "{text}");
    assert!(text.contains(&e.text), "wrapped, not cut: {text}");
    // One counter under one word: the increment's sub-segments are said
    // by the tractions panel only, never with another count in the log.
    assert!(!e.text.contains("sub-"), "{}", e.text);
    app.apply(Action::ToggleLog);
    let mut terminal = Terminal::new(TestBackend::new(160, 48)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    let substeps = app.latest().unwrap().substeps;
    let counted = if substeps == 1 {
        "1 sub-segment".to_string()
    } else {
        format!("{substeps} sub-segments")
    };
    assert!(text.contains(&counted), "{counted} not in {text}");
    assert_eq!(text.matches("sub-seg").count(), 1, "{text}");
}

/// Counts in the log's words agree with their nouns: "1 node", "2 nodes";
/// the sub-segments of the increment are not the event's to count.
#[test]
fn log_counts_are_singular_or_plural() {
    use shakedown::contact::SlipDirection;
    use shakedown::stepping::Event;
    use shakedown::tui::log::{entries, At};
    use shakedown::LoadPoint;
    let at = At {
        increment: 7,
        cycle: 1,
        time: Some(0.5),
        load: (1.0, 0.5),
    };
    let dirs = vec![SlipDirection::Stick; 16];
    let stick = |nodes: Vec<usize>, substeps| Event::AdvancingStick {
        nodes,
        substeps,
        time: Some(0.4),
        load: LoadPoint::new(1.0, 0.4),
    };
    let text = |e| entries(&[e], at, &dirs)[0].text.clone();
    assert_eq!(text(stick(vec![3], 1)), "advancing stick at 1 node");
    assert_eq!(text(stick(vec![3, 4], 0)), "advancing stick at 2 nodes");
    assert_eq!(text(stick(vec![3, 4], 2)), "advancing stick at 2 nodes");
}

#[test]
fn lambda_stops_at_zero_and_phi_wraps() {
    let mut app = app();
    for _ in 0..20 {
        press(&mut app, KeyCode::Left, KeyModifiers::SHIFT);
    }
    assert_eq!(app.load_factor(), 0.0);
    assert!(app.notice().unwrap_or_default().contains("below 0"));
    for _ in 0..24 {
        key(&mut app, KeyCode::Up);
    }
    assert!((app.phase() - PI).abs() < 1e-12);
    key(&mut app, KeyCode::Up);
    assert!((app.phase() - (-PI + PI / 24.0)).abs() < 1e-12);
}

#[test]
fn the_screen_says_when_it_restarted() {
    let mut app = app();
    app.advance(20);
    key(&mut app, KeyCode::Right);
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    assert!(text.contains("lambda = 6.05"), "{text}");
    assert!(text.contains("restarted from O"), "{text}");
}

/// Every key, in every state the keys can reach, drawn at the smallest
/// size: nothing panics.
#[test]
fn no_key_sequence_panics() {
    let mut app = app();
    let mut terminal = Terminal::new(TestBackend::new(80, 24)).unwrap();
    for round in 0..3 {
        for binding in shakedown::tui::keys::bindings() {
            if matches!(
                binding.action,
                Action::Quit | Action::Interrupt | Action::ToSteady
            ) {
                continue;
            }
            for k in binding.keys {
                app.handle_key(event_for(k));
                app.advance(round * 17 + 3);
                app.tick(Duration::from_millis(2));
                terminal.draw(|f| ui::draw(f, &app)).unwrap();
            }
        }
    }
}

#[test]
fn a_run_that_ends_refuses_to_step_and_says_why() {
    // Beyond the gross-slip limit the run ends in the first cycle.
    let mut params = default_params();
    params.load_factor = 9.0;
    params.initial = shakedown::Initial::Direct;
    let case = Case::from_params(&params).unwrap();
    let mut app = App::new(
        case,
        Config {
            color: false,
            ..Config::default()
        },
    );
    app.advance(5_000);
    assert!(matches!(app.status(), Status::Ended(_)));
    assert!(!app.is_running());
    key(&mut app, KeyCode::Char('n'));
    assert!(app.notice().unwrap_or_default().contains("ended"));
    key(&mut app, KeyCode::Char(' '));
    assert!(!app.is_running());
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    assert!(terminal.backend().to_string().contains("gross-slip"));
}

/// Paused at events inside increments (`e`), the run files one record per
/// pause under the increment in progress. The history once counted places
/// for increments, so `,` skipped increments (#125 went to #82): every
/// increment must be found under its own number, and scrubbing back steps
/// one increment at a time. The stuck nodes of an advancing stick are
/// marked with the slip of their episode however the instant is reached.
#[test]
fn pausing_at_events_leaves_no_gap_in_the_history() {
    let mut app = app();
    app.apply(Action::PauseOnEvents);
    assert!(app.pauses_on_events());
    for _ in 0..400 {
        if app.increments() >= 300 {
            break;
        }
        app.advance(300);
    }
    let h = app.history();
    assert!(h.iter().any(|r| r.partial.is_some()), "some pauses inside");
    let (first, last) = (h.oldest().unwrap().increment, h.newest().unwrap().increment);
    for i in first..=last {
        assert_eq!(h.get(i).map(|r| r.increment), Some(i), "increment {i}");
    }
    let stuck = h
        .iter()
        .rev()
        .find(|r| r.locked.is_some())
        .map(|r| r.increment)
        .expect("an advancing stick");
    let mut shown = app.shown().unwrap().increment;
    while shown > stuck {
        app.apply(Action::Back1);
        let now = app.shown().unwrap().increment;
        assert_eq!(now + 1, shown, "one increment back");
        shown = now;
    }
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    assert!(text.contains("episode slip max"), "{text}");
}

/// History has one counter, and `live` is never said over the history.
#[test]
fn history_is_never_called_live() {
    let mut app = app();
    app.advance(120);
    app.apply(Action::Back1);
    app.apply(Action::Live);
    assert_eq!(app.notice(), Some("live"));
    app.apply(Action::Oldest);
    assert!(app.cursor().is_some());
    assert_ne!(app.notice(), Some("live"));
    let mut terminal = Terminal::new(TestBackend::new(160, 48)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    let text = terminal.backend().to_string();
    assert!(!text.contains("live"), "{text}");
    assert!(!text.contains("(#"), "one counter: {text}");
}

/// The footer shows the keys of the view in use (as gitui does): at 200
/// columns the stepping view's `e`, `{ }`, `k m`, `p`, `g` and `f` are all there,
/// and with the log open, the log's own.
#[test]
fn the_footer_shows_the_keys_of_the_view() {
    let mut app = app();
    let draw = |app: &App, w: u16, h: u16| {
        let mut terminal = Terminal::new(TestBackend::new(w, h)).unwrap();
        terminal.draw(|f| ui::draw(f, app)).unwrap();
        terminal.backend().to_string()
    };
    let text = draw(&app, 80, 24);
    assert!(text.contains("? all keys"), "{text}");
    let text = draw(&app, 200, 60);
    for word in [
        "pause at events",
        "{ } events",
        "k m kind size",
        "p pin",
        "g regime",
        "f profile",
    ] {
        assert!(text.contains(word), "{word}: {text}");
    }
    app.advance(400);
    app.apply(Action::ToggleLog);
    let text = draw(&app, 200, 60);
    assert!(text.contains("Enter go there"), "{text}");
    // `{` and `}` work with the log open, and the log follows.
    let before = app.log_selected();
    app.handle_key(KeyEvent::new(KeyCode::Char('{'), KeyModifiers::NONE));
    assert!(app.cursor().is_some() || app.log_selected() != before);
}

/// `:` takes a path of the user's own, `path = X1,Y1;X2,Y2`, and refuses
/// one that leaves the allowed region with a line saying why.
#[test]
fn the_prompt_takes_a_custom_path() {
    let mut app = app();
    let type_in = |app: &mut App, text: &str| {
        app.apply(Action::Entry);
        for c in text.chars() {
            key(app, KeyCode::Char(c));
        }
        key(app, KeyCode::Enter);
    };
    type_in(&mut app, "path = 1,1;2,-1");
    assert!(matches!(app.initial(), shakedown::Initial::Custom(ref p) if p.len() == 2));
    assert_restarted_on_path(&app);
    type_in(&mut app, "path = 1,9");
    let notice = app.notice().unwrap_or_default().to_string();
    assert!(notice.starts_with("path = X1,Y1;X2,Y2"), "{notice}");
    assert!(matches!(app.initial(), shakedown::Initial::Custom(ref p) if p.len() == 2));
}

fn assert_restarted_on_path(app: &App) {
    assert_eq!(app.increments(), 0);
    let notice = app.notice().unwrap_or_default();
    assert!(notice.starts_with("path "), "notice: {notice}");
}

/// The tour from `T`: `n` and `N` walk its stops; a compare stop runs its
/// first case to the steady state, pins it and runs the second; the last
/// stop is the regime map; `Esc` gives every key its usual meaning back.
#[test]
fn the_tour_walks_its_stops_and_hands_over() {
    use shakedown::analysis::case::CaseParams;
    use shakedown::tui::app::tour::STOPS;
    let params = CaseParams {
        nodes: 32,
        steps: 100,
        ..default_params()
    };
    let case = Case::from_params(&params).unwrap();
    let mut app = App::with_sweep(case, Config::default(), Ok(common::tiny_sweep_source()));
    app.set_regime_source(Ok(common::tiny_regime_source()));
    key(&mut app, KeyCode::Char('T'));
    assert_eq!(app.mode(), Mode::Tour);
    assert_eq!(app.tour().map(|(k, _)| k), Some(0));
    // While the tour has the keys, `n` is the next stop, not a step.
    key(&mut app, KeyCode::Char('n'));
    key(&mut app, KeyCode::Char('n'));
    assert_eq!(app.tour().map(|(k, _)| k), Some(2));
    assert_eq!(app.initial().name(), "OA");
    assert_eq!(app.goal(), Some(Goal::Steady));
    wait_until(&mut app, |a| a.pinned().is_some());
    let pinned = app.pinned().unwrap().clone();
    assert_eq!(pinned.path, "OA");
    assert_ne!(pinned.state, "unclassified", "pinned at its steady state");
    assert_eq!(app.initial().name(), "7,-7");
    assert_eq!(app.goal(), Some(Goal::Steady), "the second runs to its own");
    // `N` goes back, and leaves no pin behind.
    key(&mut app, KeyCode::Char('N'));
    assert_eq!(app.tour().map(|(k, _)| k), Some(1));
    assert!(app.pinned().is_none());
    for _ in 1..STOPS.len() {
        key(&mut app, KeyCode::Char('n'));
    }
    assert_eq!(app.tour().map(|(k, _)| k), Some(STOPS.len() - 1));
    assert_eq!(app.view(), View::Regime);
    key(&mut app, KeyCode::Char('n'));
    assert_eq!(
        app.tour().map(|(k, _)| k),
        Some(STOPS.len() - 1),
        "no stop after the last"
    );
    // Esc: the map is the user's, with its own keys.
    key(&mut app, KeyCode::Esc);
    assert!(app.tour().is_none());
    assert_eq!(app.mode(), Mode::Regime);
    key(&mut app, KeyCode::Esc);
    assert_eq!(app.mode(), Mode::Stepping);
    let before = app.increments();
    key(&mut app, KeyCode::Char('n'));
    app.settle();
    assert_eq!(app.increments(), before + 1, "n steps again");
}
