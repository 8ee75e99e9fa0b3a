//! The guided tour's keys: while it has them, `n` and `N` move between
//! its stops and the other views' keys wait until `Esc`.

use super::*;

/// The guided tour's keys.
pub const TOUR: &[Binding] = &[
    bind(&[ch('n')], "n", Action::TourNext, "next stop", Scope::Tour),
    bind(
        &[ch('N')],
        "N",
        Action::TourPrevious,
        "previous stop",
        Scope::Tour,
    ),
    bind(
        &[ch(' ')],
        "Space",
        Action::RunPause,
        "run or pause the case",
        Scope::Tour,
    ),
    bind(
        &[key(KeyCode::Esc)],
        "Esc",
        Action::TourLeave,
        "leave the tour, keep the case",
        Scope::Tour,
    ),
];
