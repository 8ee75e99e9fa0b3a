//! Whole-screen snapshots of the explorer after a fixed number of
//! increments. Nothing on screen depends on the clock, so they are exact.

use ratatui::backend::TestBackend;
use ratatui::style::Color;
use ratatui::Terminal;
use shakedown::analysis::case::Case;
use shakedown::tui::app::{App, Config, View};

mod common;
use shakedown::tui::{default_params, ui};

/// Into the second cycle of the default case: the transient and a whole
/// cycle are in the slip map, W has one point, slip zones are active.
const INCREMENTS: usize = 900;

fn app(color: bool) -> App {
    let case = Case::from_params(&default_params()).expect("the default case is valid");
    App::new(case, Config { color })
}

/// `n` increments in batches of four, as frames at the default speed take
/// them, so per-frame highlights look as they do live.
fn app_after(n: usize) -> App {
    let mut app = app(true);
    advance_like_frames(&mut app, n);
    app
}

fn advance_like_frames(app: &mut App, n: usize) {
    for _ in 0..n / 4 {
        app.advance(4);
    }
    app.advance(n % 4);
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
    insta::assert_snapshot!(screen(&app(true), 100, 30).backend());
}

#[test]
fn help_overlay_80x24() {
    let mut app = app_after(10);
    app.apply(shakedown::tui::keys::Action::Help);
    let text = screen(&app, 80, 24).backend().to_string();
    for b in shakedown::tui::keys::bindings_for(View::Stepping) {
        assert!(text.contains(b.help), "help lacks {:?}", b.help);
    }
    insta::assert_snapshot!(text);
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
    let mut app = app(false);
    advance_like_frames(&mut app, INCREMENTS);
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
    let mut app = App::with_sweep(case, Config { color }, Ok(source));
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
    app.apply(shakedown::tui::keys::Action::Help);
    let text = screen(&app, 80, 24).backend().to_string();
    for b in shakedown::tui::keys::bindings_for(View::Sweep) {
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
