//! The status lines: the case, where the run is, what it has become, and
//! what just happened.

use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use super::Theme;
use crate::stepping::{Phase, Status};
use crate::tui::app::{format_load_factor, format_phase, format_sci, App, Goal};

pub fn render(frame: &mut Frame, area: Rect, app: &App, theme: &Theme) {
    let stepper = app.stepper();
    let case = app.case();
    let label = |s: &str| Span::styled(s.to_string(), theme.label());
    let value = |s: String| Span::styled(s, theme.value());
    let sep = || Span::styled("  │ ", theme.dim());

    let wide = area.width >= 100;
    let path = &app.paths()[app.path_index()];
    let line1 = Line::from(vec![
        label(" lambda = "),
        value(format_load_factor(app.load_factor())),
        label("  phi = "),
        value(format_phase(app.phase())),
        label("  psi = "),
        value(format!("{}", case.cycle.slope)),
        label("  path "),
        value(path.name()),
        label(format!(" ({}/{})", app.path_index() + 1, app.paths().len()).as_str()),
    ]);
    // The discretisation is secondary: shown when there is room for it
    // next to the help hint.
    let mut line1 = line1;
    if wide {
        line1.spans.extend([
            sep(),
            label("N "),
            value(case.disc.nodes().to_string()),
            label(", "),
            value(case.disc.steps_per_cycle().to_string()),
            label(" incr/cycle"),
        ]);
    }

    let (where_label, where_value) = match stepper.phase() {
        Phase::Transient { segment, increment } => (
            " transient ",
            format!(
                "seg {}/{} incr {}",
                segment + 1,
                stepper.transient().len(),
                increment
            ),
        ),
        Phase::Cycle { cycle, increment } => (
            " cycle ",
            format!("{cycle}  incr {increment}/{}", case.disc.steps_per_cycle()),
        ),
    };
    let (state, state_style) = match stepper.status() {
        Status::Running => ("unclassified".to_string(), theme.label()),
        Status::Steady(s) if wide => (
            format!("{} (cycle {})", s.state.as_str(), s.cycles),
            theme.alert(),
        ),
        Status::Steady(s) => (s.state.as_str().to_string(), theme.alert()),
        Status::Ended(s) if wide => (format!("{} (run ended)", s.state.as_str()), theme.error()),
        Status::Ended(s) => (s.state.as_str().to_string(), theme.error()),
    };
    let rotation = match stepper.summary() {
        Some(s) => Some(s.rotation_per_cycle),
        None => stepper.history().last().map(|r| r.rotation),
    };
    let mut line2 = Line::from(vec![label(where_label), value(where_value)]);
    if wide {
        line2
            .spans
            .extend([label("  total "), value(stepper.increments().to_string())]);
    }
    line2.spans.extend([
        sep(),
        label("state "),
        Span::styled(state, state_style),
        label("  rot/cycle "),
        value(rotation.map_or("–".into(), format_sci)),
    ]);

    let mode = match (app.goal(), app.is_running()) {
        (Some(Goal::Steady), _) => "» steady".to_string(),
        (Some(Goal::CycleEnd(_)), _) => "» cycle end".to_string(),
        (Some(Goal::TransientEnd), _) => "» transient end".to_string(),
        (None, true) => format!("▶ {}/frame", app.speed()),
        (None, false) => format!("‖ paused {}/frame", app.speed()),
    };
    let mut spans = vec![
        Span::raw(" "),
        Span::styled(
            mode,
            if app.is_running() || app.goal().is_some() {
                theme.fg(Color::LightGreen)
            } else {
                theme.alert()
            },
        ),
        label(if app.pauses_on_events() {
            " e:on"
        } else {
            " e:off"
        }),
        sep(),
    ];
    if let Some(f) = app.failure() {
        spans.push(Span::styled(format!("solver failed: {f}"), theme.error()));
    } else {
        if let Some(n) = app.notice() {
            spans.push(Span::styled(n.to_string(), theme.alert()));
            spans.push(sep());
        }
        spans.push(label("event: "));
        spans.push(Span::raw(app.last_event().unwrap_or("–").to_string()));
    }
    let line3 = Line::from(spans);

    // The help hint is pinned to the right of the first line.
    let first_width = line1.width();
    frame.render_widget(Paragraph::new(vec![line1, line2, line3]), area);
    // The view key is named when it fits beside the case, so a user finds
    // the sweep view without opening the help; the help lists it anyway.
    let long = " v sweep  ? help  q quit ";
    let room = area.width as usize >= first_width + long.chars().count();
    let hint = if room { long } else { " ? help  q quit " };
    let w = hint.chars().count() as u16;
    if area.width > w {
        let rect = Rect::new(area.x + area.width - w, area.y, w, 1);
        frame.render_widget(
            Paragraph::new(Span::styled(
                hint,
                theme.label().add_modifier(Modifier::REVERSED),
            )),
            rect,
        );
    }
}
