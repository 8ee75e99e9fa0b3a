//! The event log's keys, over the stepping view.

use super::*;

/// The event log's keys, over the stepping view.
pub const LOG: &[Binding] = &[
    bind(
        &[key(KeyCode::Up)],
        "↑",
        Action::LogUp,
        "previous event",
        Scope::Log,
    ),
    bind(
        &[key(KeyCode::Down), ch('j')],
        "↓ j",
        Action::LogDown,
        "next event",
        Scope::Log,
    ),
    bind(
        &[key(KeyCode::PageUp)],
        "PgUp",
        Action::LogPageUp,
        "ten events up",
        Scope::Log,
    ),
    bind(
        &[key(KeyCode::PageDown)],
        "PgDn",
        Action::LogPageDown,
        "ten events down",
        Scope::Log,
    ),
    bind(
        &[key(KeyCode::Home)],
        "Home",
        Action::LogFirst,
        "first event",
        Scope::Log,
    ),
    bind(
        &[key(KeyCode::End)],
        "End",
        Action::LogLast,
        "last event",
        Scope::Log,
    ),
    bind(
        &[key(KeyCode::Enter)],
        "Enter",
        Action::LogGo,
        "show that instant",
        Scope::Log,
    ),
    bind(
        &[ch('L'), ch('E')],
        "L E",
        Action::ToggleLog,
        "close the event log",
        Scope::Log,
    ),
];
