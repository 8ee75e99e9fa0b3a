//! The regime map in the sweep view, and the custom transient on the load
//! plane: screens of a fixed, synthetic state (no number on them comes
//! from the solver), and the keys that compute, cancel and open the map.

use std::f64::consts::PI;
use std::time::{Duration, Instant};

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use ratatui::backend::TestBackend;
use ratatui::style::Color;
use ratatui::Terminal;
use shakedown::analysis::case::Case;
use shakedown::analysis::sweep::{Job, Row, RunError};
use shakedown::io::parse::{parse_angle, parse_number, parse_values};
use shakedown::model::path::{segments, Initial};
use shakedown::stepping::steady::SteadyState;
use shakedown::stepping::StepError;
use shakedown::tui::app::{App, Config, View};
use shakedown::tui::keys::{bindings_for, Action, Mode};
use shakedown::tui::regime::{CurveState, RegimeSource};
use shakedown::tui::{default_params, ui};
use shakedown::LoadPoint;

use crate::common;

fn screen(app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("test backend");
    terminal
        .draw(|frame| ui::draw(frame, app))
        .expect("drawing to a test backend cannot fail");
    terminal
}

fn key(app: &mut App, code: KeyCode) {
    app.handle_key(KeyEvent::new(code, KeyModifiers::NONE));
}

/// A synthetic `lambda_2(phi)`: nothing to do with the solver's.
fn fake_limit(phase: f64) -> f64 {
    4.8 + 0.6 * phase.sin()
}

/// A synthetic steady state over the plane: shakedown left of
/// [`fake_limit`], then cyclic slip near `phi = 0` and `pi` and monotonic
/// ratchetting between, non-monotonic ratchetting further right and gross
/// slip at the end; one run failed, one did not converge, one separated,
/// and the top of the last column is not run yet.
fn fake_row(load_factor: f64, phase: f64, last: f64) -> Option<Row> {
    if load_factor == last && phase > 2.0 * PI / 3.0 + 1e-9 {
        return None;
    }
    let over = load_factor - fake_limit(phase);
    let state = if load_factor == 6.0 && (phase - PI / 2.0).abs() < 1e-9 {
        None
    } else if (load_factor - 6.5).abs() < 1e-9 && phase == 0.0 {
        Some(SteadyState::NotConverged)
    } else if (load_factor - 7.0).abs() < 1e-9 && phase == 0.0 {
        Some(SteadyState::Separation)
    } else if over < 0.0 {
        Some(SteadyState::Shakedown)
    } else if over < 1.0 {
        if (PI / 3.0..2.0 * PI / 3.0).contains(&phase) {
            Some(SteadyState::RatchettingMonotonic)
        } else {
            Some(SteadyState::CyclicSlip)
        }
    } else if load_factor < 7.4 {
        Some(SteadyState::RatchettingNonMonotonic)
    } else {
        Some(SteadyState::GrossSlip)
    };
    let job = Job {
        index: 0,
        load_factor,
        phase,
        initial: 0,
    };
    let outcome = match state {
        None => Err(RunError::Step(StepError::NotSettled {
            load: LoadPoint::new(1.0, 2.0),
            phase: "cycle 2".into(),
            bisections: 8,
        })),
        Some(state) => {
            let dissipation = if state == SteadyState::Shakedown {
                0.0
            } else {
                1e-4 * (1.0 + over.max(0.0)).powi(4)
            };
            Ok(crate::common::fake_outcome(state, dissipation, 5))
        }
    };
    Some(Row {
        job,
        initial: "OA".into(),
        outcome,
    })
}

/// The explorer showing a regime map over the default grid (lambda 3 to
/// 7.5 by 0.25, phi 0 to pi by pi/12) filled with [`fake_row`], the
/// synthetic `lambda_2(phi)`, and the cursor at `lambda = 5`, `phi = pi/2`.
fn regime_app(config: Config) -> App {
    let case = Case::from_params(&default_params()).expect("the default case is valid");
    let lambdas = parse_values("3:7.5:0.25", parse_number).unwrap();
    let phases = parse_values("0:pi:pi/12", parse_angle).unwrap();
    let source = RegimeSource::new("regime", &case, lambdas.clone(), phases.clone()).unwrap();
    let mut app = App::with_sweep(case, config, Ok(common::tiny_sweep_source()));
    app.set_regime_source(Ok(source));
    let regime = app.regime_mut().unwrap();
    let last = lambdas[lambdas.len() - 1];
    for &l in &lambdas {
        for &p in &phases {
            if let Some(row) = fake_row(l, p, last) {
                regime.insert(&row);
            }
        }
    }
    regime.set_curve(phases.iter().map(|&p| Some(fake_limit(p))).collect());
    regime.move_near(5.0, PI / 2.0);
    app.show_view(View::Regime);
    app
}

fn colour() -> Config {
    Config::default()
}

#[test]
fn regime_map_80x24() {
    let app = regime_app(colour());
    assert_eq!(app.regime().unwrap().cursor(), (8, 6));
    let t = screen(&app, 80, 24);
    let text = t.backend().to_string();
    for s in [
        "Regime map",
        "OA",
        "lambda",
        "pi/2",
        "shakedown",
        "Enter opens",
    ] {
        assert!(text.contains(s), "lacks {s}:\n{text}");
    }
    insta::assert_snapshot!(t.backend());
}

#[test]
fn regime_map_160x48() {
    let t = screen(&regime_app(colour()), 160, 48);
    insta::assert_snapshot!(t.backend());
}

/// Every state has its colour (the figure's) and its letter; with
/// `NO_COLOR` the letters alone tell them apart, and `--ascii` draws
/// ASCII only.
#[test]
fn regime_map_reads_without_colour_and_in_ascii() {
    let app = regime_app(colour());
    let t = screen(&app, 100, 30);
    let cells = t.backend().buffer().content();
    for state in [
        SteadyState::Shakedown,
        SteadyState::CyclicSlip,
        SteadyState::RatchettingMonotonic,
        SteadyState::RatchettingNonMonotonic,
    ] {
        let c = shakedown::palette::map_colour(Some(state));
        assert!(
            cells
                .iter()
                .any(|cell| cell.bg == Color::Rgb(c.0, c.1, c.2)),
            "no cell in the colour of {state}"
        );
    }

    let plain = Config {
        color: false,
        ascii: true,
        ..Config::default()
    };
    let app = regime_app(plain);
    for (w, h) in [(80, 24), (100, 30), (160, 48)] {
        let t = screen(&app, w, h);
        let text = t.backend().to_string();
        assert!(text.is_ascii(), "{w}x{h}:\n{text}");
        for cell in t.backend().buffer().content() {
            assert_eq!(cell.fg, Color::Reset, "coloured cell {cell:?}");
            assert_eq!(cell.bg, Color::Reset, "coloured cell {cell:?}");
        }
        // Letters on the map (beside the legend's), the pending dots
        // and the lambda_2 bars.
        let map: String = text
            .lines()
            .map(|l| l.chars().take(usize::from(w) - 32).collect::<String>())
            .collect();
        for c in ['S', 'C', 'M', 'N', 'G', 'X', '?', '!', '.', '|'] {
            assert!(map.contains(c), "{w}x{h}: no {c} on the map:\n{text}");
        }
    }
    insta::assert_snapshot!(screen(&app, 80, 24).backend());
}

#[test]
fn regime_map_draws_at_any_size() {
    let app = regime_app(colour());
    for w in (1..=230).step_by(11) {
        for h in (1..=70).step_by(5) {
            screen(&app, w, h);
        }
    }
    // Too narrow for the grid inside the 80-column minimum: it says so.
    let mut wide = regime_app(colour());
    let case = wide.case().clone();
    let many = parse_values("1:7.5:0.05", parse_number).unwrap();
    wide.set_regime_source(Ok(
        RegimeSource::new("many", &case, many, vec![0.0]).unwrap()
    ));
    wide.show_view(View::Regime);
    let text = screen(&wide, 80, 24).backend().to_string();
    assert!(text.contains("enlarge the terminal"), "{text}");
}

#[test]
fn regime_help_lists_its_keys() {
    let mut app = regime_app(colour());
    assert_eq!(app.mode(), Mode::Regime);
    app.apply(Action::Help);
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains("regime map"), "{text}");
    for b in bindings_for(Mode::Regime) {
        assert!(text.contains(b.help), "help lacks {:?}:\n{text}", b.help);
    }
}

/// Ticks (as frames do) until `done`, or fail after `secs` seconds.
fn wait_until(app: &mut App, secs: u64, done: impl Fn(&App) -> bool) {
    let deadline = Instant::now() + Duration::from_secs(secs);
    while !done(app) {
        assert!(Instant::now() < deadline, "timed out");
        app.tick(Duration::from_millis(8));
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn tiny_app() -> App {
    let case = Case::from_params(&default_params()).expect("the default case is valid");
    let mut app = App::with_sweep(case, Config::default(), Ok(common::tiny_sweep_source()));
    app.set_regime_source(Ok(common::tiny_regime_source()));
    app
}

/// `lambda_2(phi)` starts with the map on a thread of its own, is
/// cancelled when the map is left and resumed when it comes back: the
/// curve it ends with is the one an uninterrupted map draws.
#[test]
fn the_limit_curve_starts_with_the_map_and_resumes_after_a_cancel() {
    let mut whole = tiny_app();
    key(&mut whole, KeyCode::Char('g'));
    wait_until(&mut whole, 120, |a| {
        matches!(a.regime().unwrap().curve(), CurveState::Known(_))
    });
    let CurveState::Known(expected) = whole.regime().unwrap().curve().clone() else {
        unreachable!()
    };
    assert_eq!(expected.len(), 2);
    assert!(expected.iter().all(Option::is_some), "{expected:?}");

    let mut app = tiny_app();
    key(&mut app, KeyCode::Char('g'));
    assert!(app.regime().unwrap().is_running());
    // Left at once: both threads stop (the curve's after the programme in
    // progress), and the points already in are kept.
    key(&mut app, KeyCode::Esc);
    assert_eq!(app.view(), View::Stepping);
    wait_until(&mut app, 60, |a| a.regime().unwrap().threads_alive() == 0);
    app.tick(Duration::from_millis(8));
    let (solved, total) = app.regime().unwrap().curve().solved();
    assert!(solved <= total && total == 2);
    key(&mut app, KeyCode::Char('g'));
    wait_until(&mut app, 120, |a| {
        matches!(a.regime().unwrap().curve(), CurveState::Known(_))
    });
    assert_eq!(app.regime().unwrap().curve(), &CurveState::Known(expected));
}

/// `g` in the sweep view computes the map in the background while frames
/// go on; the arrows move over the cells and Enter opens one.
#[test]
fn the_regime_map_fills_in_and_enter_opens_a_case() {
    let mut app = tiny_app();
    key(&mut app, KeyCode::Char('v'));
    assert_eq!(app.view(), View::Sweep);
    key(&mut app, KeyCode::Char('g'));
    assert_eq!(app.view(), View::Regime);
    assert_eq!(app.mode(), Mode::Regime);
    assert!(app.regime().unwrap().is_running());
    // The cursor starts at the stepping view's case (lambda 6, phi 0),
    // and keys are answered at once while the map computes.
    assert_eq!(app.regime().unwrap().cursor(), (1, 0));
    key(&mut app, KeyCode::Right);
    assert_eq!(app.regime().unwrap().cursor(), (2, 0));
    wait_until(&mut app, 120, |a| {
        let r = a.regime().unwrap();
        !r.is_running() && matches!(r.curve(), CurveState::Known(_))
    });
    let r = app.regime().unwrap();
    assert_eq!((r.done(), r.total()), (6, 6));
    assert_eq!(r.threads_alive(), 0, "nothing left running");
    let text = screen(&app, 80, 24).backend().to_string();
    assert!(text.contains("6/6 runs"), "{text}");
    assert!(text.contains("done"), "{text}");

    key(&mut app, KeyCode::End);
    key(&mut app, KeyCode::Up);
    assert_eq!(app.regime().unwrap().cursor(), (2, 1));
    key(&mut app, KeyCode::Home);
    // PgDn moves on (right), PgUp back, as in every view.
    key(&mut app, KeyCode::PageDown);
    assert_eq!(app.regime().unwrap().cursor(), (2, 1));
    key(&mut app, KeyCode::PageUp);
    key(&mut app, KeyCode::Down);
    assert_eq!(app.regime().unwrap().cursor(), (0, 0));
    key(&mut app, KeyCode::Right);
    key(&mut app, KeyCode::Up);
    let cell = app.regime().unwrap().selected_cell();
    assert!(cell.is_some());
    key(&mut app, KeyCode::Enter);
    assert_eq!(app.view(), View::Stepping);
    assert_eq!(app.load_factor(), 5.5);
    assert_eq!(app.phase(), std::f64::consts::FRAC_PI_2);
    assert_eq!(app.initial(), &Initial::Direct);
    assert!(app.is_running());

    // Back to the map: it is kept, nothing is recomputed.
    key(&mut app, KeyCode::Tab);
    key(&mut app, KeyCode::Char('g'));
    assert!(!app.regime().unwrap().is_running());
    assert_eq!(app.regime().unwrap().done(), 6);
    // g goes back to the W plot, Esc from the map to the stepping view.
    key(&mut app, KeyCode::Char('g'));
    assert_eq!(app.view(), View::Sweep);
    key(&mut app, KeyCode::Char('g'));
    key(&mut app, KeyCode::Esc);
    assert_eq!(app.view(), View::Stepping);
    assert!(!app.should_quit());
}

/// Reruns and changes of the transient, pressed as fast as keys come,
/// cancel the work they replace: one computation is left, the threads of
/// the others end at their next increment, and leaving the map (Esc)
/// stops it too.
#[test]
fn a_storm_of_restarts_leaves_one_computation() {
    let mut app = tiny_app();
    app.show_view(View::Sweep);
    key(&mut app, KeyCode::Char('g'));
    for k in 0..60 {
        let code = match k % 3 {
            0 => KeyCode::Char('r'),
            1 => KeyCode::Char(']'),
            _ => KeyCode::Char('['),
        };
        key(&mut app, code);
        app.tick(Duration::from_millis(1));
    }
    let r = app.regime().unwrap();
    assert!(r.is_running());
    assert_eq!(r.initial(), &Initial::Direct, "] [ r: back at OA");
    // The cancelled computations end quickly; the live one (and perhaps
    // lambda_2's thread) remain.
    wait_until(&mut app, 30, |a| a.regime().unwrap().threads_alive() <= 2);
    key(&mut app, KeyCode::Esc);
    assert_eq!(app.view(), View::Stepping);
    assert!(!app.regime().unwrap().is_running(), "Esc cancels the map");
    wait_until(&mut app, 60, |a| a.regime().unwrap().threads_alive() == 0);
    // Coming back computes only what is missing.
    let done = app.regime().unwrap().done();
    app.show_view(View::Sweep);
    key(&mut app, KeyCode::Char('g'));
    wait_until(&mut app, 120, |a| !a.regime().unwrap().is_running());
    assert_eq!(app.regime().unwrap().done(), 6);
    assert!(done <= 6);
}

/// `--initial-path`: the points of the custom transient are marked on the
/// load plane, numbered in path order, ASCII-safe with `--ascii`.
#[test]
fn custom_path_points_on_the_load_plane() {
    let points = vec![
        LoadPoint::new(0.0, 1.5 * PI),
        LoadPoint::new(2.0 * PI, -1.5 * PI),
    ];
    let app_with = |config: Config| {
        let mut params = default_params();
        params.initial = shakedown::Initial::Direct;
        let mut case = Case::from_params(&params).unwrap();
        case.set_initial(Initial::custom(points.clone()).unwrap())
            .unwrap();
        let center = case.cycle().center();
        let mut app = App::new(case.clone(), config);
        let waypoints = case.initial().waypoints_to(center);
        app.feed_started(segments(&waypoints, 0.5), 0.1);
        app
    };
    let t = screen(&app_with(Config::default()), 100, 30);
    let text = t.backend().to_string();
    assert!(text.contains("◆1") && text.contains("◆2"), "{text}");
    insta::assert_snapshot!(t.backend());

    let ascii = Config {
        ascii: true,
        ..Config::default()
    };
    let text = screen(&app_with(ascii), 100, 30).backend().to_string();
    assert!(text.is_ascii());
    assert!(text.contains("*1") && text.contains("*2"), "{text}");
    let text = screen(&app_with(Config::default()), 80, 24)
        .backend()
        .to_string();
    assert!(text.contains("◆1") && text.contains("◆2"), "{text}");
}
