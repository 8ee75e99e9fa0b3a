//! The keys of every view.

use super::*;

/// The keys of every view.
pub const GLOBAL: &[Binding] = &[
    bind(
        &[ch('T')],
        "T",
        Action::Tour,
        "guided tour (from stop 1)",
        Scope::All,
    ),
    bind(
        &[ch('v'), key(KeyCode::Tab)],
        "v Tab",
        Action::ToggleView,
        "stepping view / sweep view",
        Scope::Views,
    ),
    bind(
        &[ch('?')],
        "?",
        Action::Help,
        "this help on/off",
        Scope::All,
    ),
    bind(
        &[key(KeyCode::Esc)],
        "Esc",
        Action::Back,
        "close, back, or to live",
        Scope::Views,
    ),
    bind(
        &[ctrl('z')],
        "^Z",
        Action::Suspend,
        "suspend (fg resumes)",
        Scope::All,
    ),
    bind(
        &[ch('q')],
        "q",
        Action::Quit,
        "quit (asks if a map is lost)",
        Scope::All,
    ),
    bind(
        &[ctrl('c')],
        "^C",
        Action::Interrupt,
        "quit with status 130",
        Scope::All,
    ),
];
