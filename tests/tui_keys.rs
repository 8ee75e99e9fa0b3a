//! Every key of the table, through the same dispatch the terminal uses.

use std::f64::consts::PI;
use std::time::Duration;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::backend::TestBackend;
use ratatui::Terminal;
use shakedown::analysis::case::Case;
use shakedown::stepping::{Phase, Status};
use shakedown::tui::app::{App, Config, Goal, View};
use shakedown::tui::keys::{bindings_for, event_for, Action, BINDINGS};
use shakedown::tui::{default_params, ui};

mod common;

/// The default case, with a tiny sweep for the sweep view so that keys
/// which start it do not start a full preset's.
fn app() -> App {
    let case = Case::from_params(&default_params()).expect("the default case is valid");
    App::with_sweep(
        case,
        Config { color: true },
        Ok(common::tiny_sweep_source()),
    )
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
    }
    panic!("goal {:?} not reached", app.goal());
}

fn assert_restarted(app: &App) {
    assert_eq!(app.stepper().increments(), 0);
    assert!(app.slip_rows().is_empty());
    let notice = app.notice().unwrap_or_default();
    assert!(notice.contains("restarted from O"), "notice: {notice}");
}

/// What each action must do. The match is exhaustive, so an action added
/// to the table without a test here does not compile.
fn check(action: Action, event: KeyEvent, view: View) {
    let mut app = app();
    app.advance(50);
    app.show_view(view);
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
            assert_eq!(app.case().initial, app.paths()[expected]);
            assert_restarted(&app);
        }
        Action::RunPause => {
            assert!(app.is_running());
            handle(&mut app);
            assert!(!app.is_running());
            let at = app.stepper().increments();
            app.tick(Duration::from_millis(50));
            assert_eq!(app.stepper().increments(), at, "paused, yet it stepped");
            handle(&mut app);
            assert!(app.is_running());
            app.tick(Duration::from_millis(50));
            assert!(app.stepper().increments() > at);
        }
        Action::StepOne => {
            let at = app.stepper().increments();
            handle(&mut app);
            assert_eq!(app.stepper().increments(), at + 1);
            assert!(!app.is_running());
            handle(&mut app);
            assert_eq!(app.stepper().increments(), at + 2);
        }
        Action::ToCycleEnd => {
            // In the transient, `c` stops where the transient ends ...
            handle(&mut app);
            assert_eq!(app.goal(), Some(Goal::TransientEnd));
            run_goal(&mut app);
            assert_eq!(
                app.stepper().phase(),
                Phase::Cycle {
                    cycle: 1,
                    increment: 0
                }
            );
            // ... and in a cycle, where the cycle ends.
            app.advance(7);
            handle(&mut app);
            run_goal(&mut app);
            assert_eq!(app.stepper().history().len(), 1);
            assert_eq!(
                app.stepper().phase(),
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
            let Status::Steady(summary) = app.stepper().status() else {
                panic!("not steady: {:?}", app.stepper().status());
            };
            let notice = app.notice().unwrap_or_default();
            assert!(notice.contains(summary.state.as_str()), "{notice}");
            // Asking again says so instead of running on.
            handle(&mut app);
            assert_eq!(app.goal(), None);
            assert!(app.notice().unwrap_or_default().contains("already"));
        }
        Action::Reset => {
            key(&mut app, KeyCode::Char(' '));
            handle(&mut app);
            assert_eq!(app.stepper().increments(), 0);
            assert!(app.slip_rows().is_empty());
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
            for _ in 0..10_000 {
                if !app.is_running() {
                    break;
                }
                app.tick(Duration::from_millis(50));
            }
            assert!(!app.is_running());
            let notice = app.notice().unwrap_or_default();
            assert!(notice.contains("paused on the event"), "{notice}");
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
        }
        Action::ToggleView => {
            handle(&mut app);
            let other = match view {
                View::Stepping => View::Sweep,
                View::Sweep => View::Stepping,
            };
            assert_eq!(app.view(), other);
            if other == View::Sweep {
                assert!(
                    app.sweep().unwrap().started(),
                    "the sweep starts when shown"
                );
            }
            handle(&mut app);
            assert_eq!(app.view(), view);
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
            assert_eq!(app.case().initial.name(), "7,-7");
            assert!(app.is_running());
            assert_eq!(app.stepper().increments(), 0);
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
    for view in [View::Stepping, View::Sweep] {
        for binding in bindings_for(view) {
            for k in binding.keys {
                check(binding.action, event_for(k), view);
            }
        }
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
    key(&mut app, KeyCode::Up);
    let (job, row) = app.sweep().unwrap().selected().unwrap();
    assert_eq!((job.load_factor, job.initial), (7.0, 1));
    assert!(row.is_some());
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.view(), View::Stepping);
    assert_eq!(app.load_factor(), 7.0);
    assert_eq!(app.case().initial.name(), "7,-7");

    // Rerun, then quit while it runs: the runs not started are dropped.
    key(&mut app, KeyCode::Tab);
    key(&mut app, KeyCode::Char('r'));
    assert!(app.sweep().unwrap().is_running());
    key(&mut app, KeyCode::Char('q'));
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
    let cases: [(KeyCode, KeyModifiers, Action); 18] = [
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
        (KeyCode::Char('.'), KeyModifiers::NONE, Action::StepOne),
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
            shakedown::tui::keys::action_for(&KeyEvent::new(code, mods), View::Stepping),
            Some(action),
            "{code:?} {mods:?}"
        );
    }
    for (code, mods) in [
        (KeyCode::Char('q'), KeyModifiers::NONE),
        (KeyCode::Esc, KeyModifiers::NONE),
        (KeyCode::Char('c'), KeyModifiers::CONTROL),
    ] {
        assert_eq!(
            shakedown::tui::keys::action_for(&KeyEvent::new(code, mods), View::Stepping),
            Some(Action::Quit)
        );
    }
    // Unbound keys do nothing.
    let before = app.stepper().increments();
    key(&mut app, KeyCode::Char('z'));
    key(&mut app, KeyCode::F(5));
    assert_eq!(app.stepper().increments(), before);
    assert!(!app.should_quit());
}

#[test]
fn esc_closes_the_help_before_it_quits() {
    let mut app = app();
    key(&mut app, KeyCode::Char('?'));
    assert!(app.help_visible());
    key(&mut app, KeyCode::Esc);
    assert!(!app.help_visible());
    assert!(!app.should_quit());
    key(&mut app, KeyCode::Esc);
    assert!(app.should_quit());
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
        for binding in BINDINGS {
            if binding.action == Action::Quit || binding.action == Action::ToSteady {
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
    params.initial = "OA".into();
    let case = Case::from_params(&params).unwrap();
    let mut app = App::new(case, Config { color: false });
    app.advance(5_000);
    assert!(app.stepper().is_finished());
    assert!(!app.is_running());
    key(&mut app, KeyCode::Char('n'));
    assert!(app.notice().unwrap_or_default().contains("ended"));
    key(&mut app, KeyCode::Char(' '));
    assert!(!app.is_running());
    let mut terminal = Terminal::new(TestBackend::new(100, 30)).unwrap();
    terminal.draw(|f| ui::draw(f, &app)).unwrap();
    assert!(terminal.backend().to_string().contains("gross-slip"));
}
