//! The sweep view's keys.

use super::*;

/// The sweep view's keys.
pub const SWEEP: &[Binding] = &[
    bind(
        &[key(KeyCode::Left)],
        "←",
        Action::SweepPrevX,
        "previous lambda (or phi)",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::Right)],
        "→",
        Action::SweepNextX,
        "next lambda (or phi)",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::PageDown)],
        "PgDn",
        Action::SweepPageDown,
        "ten columns right (on)",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::PageUp)],
        "PgUp",
        Action::SweepPageUp,
        "ten columns left (back)",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::Home)],
        "Home",
        Action::SweepFirst,
        "first column",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::End)],
        "End",
        Action::SweepLast,
        "last column",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::Up)],
        "↑",
        Action::SweepPrevRun,
        "transient above in the table",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::Down)],
        "↓",
        Action::SweepNextRun,
        "transient below in the table",
        Scope::Sweep,
    ),
    bind(
        &[key(KeyCode::Enter)],
        "Enter",
        Action::OpenRun,
        "open the run under the cursor",
        Scope::Sweep,
    ),
    bind(
        &[ch('w')],
        "w",
        Action::SweepLogW,
        "W axis: log / linear",
        Scope::Sweep,
    ),
    bind(
        &[ch('S'), ch('s')],
        "s",
        Action::SweepSave,
        "save the map as sweep's CSV",
        Scope::Sweep,
    ),
    bind(
        &[ch('r')],
        "r",
        Action::RestartSweep,
        "rerun the sweep (asks first)",
        Scope::Sweep,
    ),
    bind(
        &[ch('g')],
        "g",
        Action::ToggleRegime,
        "regime map over (lambda, phi)",
        Scope::Sweep,
    ),
];
