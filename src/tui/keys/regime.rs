//! The regime map's keys.

use super::*;

/// The regime map's keys.
pub const REGIME: &[Binding] = &[
    bind(
        &[key(KeyCode::Left)],
        "←",
        Action::RegimePrevLambda,
        "previous lambda",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::Right)],
        "→",
        Action::RegimeNextLambda,
        "next lambda",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::Down)],
        "↓",
        Action::RegimePhaseDown,
        "smaller phi",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::Up)],
        "↑",
        Action::RegimePhaseUp,
        "larger phi",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::PageDown)],
        "PgDn",
        Action::RegimePageDown,
        "ten lambdas right (on)",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::PageUp)],
        "PgUp",
        Action::RegimePageUp,
        "ten lambdas left (back)",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::Home)],
        "Home",
        Action::RegimeFirst,
        "first lambda",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::End)],
        "End",
        Action::RegimeLast,
        "last lambda",
        Scope::Regime,
    ),
    bind(
        &[key(KeyCode::Enter)],
        "Enter",
        Action::RegimeOpen,
        "open this (lambda, phi) case",
        Scope::Regime,
    ),
    bind(
        &[ch('[')],
        "[",
        Action::RegimePrevPath,
        "map of the previous path",
        Scope::Regime,
    ),
    bind(
        &[ch(']')],
        "]",
        Action::RegimeNextPath,
        "map of the next path",
        Scope::Regime,
    ),
    bind(
        &[ch('r')],
        "r",
        Action::RegimeRestart,
        "compute the map again",
        Scope::Regime,
    ),
    bind(
        &[ch('g')],
        "g",
        Action::ToggleRegime,
        "back to the view before",
        Scope::Regime,
    ),
];
