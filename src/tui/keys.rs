//! The one table of key bindings. Dispatch and the help overlay both read
//! [`BINDINGS`], so the help can never list a key that does nothing or miss
//! one that does something.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// Everything a key can ask the explorer to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    LoadFactorDown,
    LoadFactorUp,
    LoadFactorDownBig,
    LoadFactorUpBig,
    PhaseDown,
    PhaseUp,
    PreviousPath,
    NextPath,
    RunPause,
    StepOne,
    ToCycleEnd,
    ToSteady,
    Reset,
    Faster,
    Slower,
    PauseOnEvents,
    Help,
    Quit,
}

/// One physical key: a code and whether Shift must be held. Character keys
/// ignore Shift because terminals disagree on whether `?` or `+` carry it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Key {
    pub code: KeyCode,
    pub shift: bool,
    pub ctrl: bool,
}

const fn key(code: KeyCode) -> Key {
    Key {
        code,
        shift: false,
        ctrl: false,
    }
}

const fn shifted(code: KeyCode) -> Key {
    Key {
        code,
        shift: true,
        ctrl: false,
    }
}

const fn ch(c: char) -> Key {
    key(KeyCode::Char(c))
}

const fn ctrl(c: char) -> Key {
    Key {
        code: KeyCode::Char(c),
        shift: false,
        ctrl: true,
    }
}

/// A row of the key table: the keys, how the help names them, the action
/// and what the help says about it.
#[derive(Debug, Clone, Copy)]
pub struct Binding {
    pub keys: &'static [Key],
    pub label: &'static str,
    pub action: Action,
    pub help: &'static str,
}

/// Every key the explorer knows, in the order the help shows them.
pub const BINDINGS: &[Binding] = &[
    Binding {
        keys: &[key(KeyCode::Left)],
        label: "←",
        action: Action::LoadFactorDown,
        help: "lambda - 0.05 (restarts from O)",
    },
    Binding {
        keys: &[key(KeyCode::Right)],
        label: "→",
        action: Action::LoadFactorUp,
        help: "lambda + 0.05 (restarts from O)",
    },
    Binding {
        keys: &[shifted(KeyCode::Left)],
        label: "Shift-←",
        action: Action::LoadFactorDownBig,
        help: "lambda - 0.5 (restarts from O)",
    },
    Binding {
        keys: &[shifted(KeyCode::Right)],
        label: "Shift-→",
        action: Action::LoadFactorUpBig,
        help: "lambda + 0.5 (restarts from O)",
    },
    Binding {
        keys: &[key(KeyCode::Down)],
        label: "↓",
        action: Action::PhaseDown,
        help: "phi - pi/24 (restarts from O)",
    },
    Binding {
        keys: &[key(KeyCode::Up)],
        label: "↑",
        action: Action::PhaseUp,
        help: "phi + pi/24 (restarts from O)",
    },
    Binding {
        keys: &[ch('[')],
        label: "[",
        action: Action::PreviousPath,
        help: "previous initial path (restarts from O)",
    },
    Binding {
        keys: &[ch(']')],
        label: "]",
        action: Action::NextPath,
        help: "next initial path (restarts from O)",
    },
    Binding {
        keys: &[ch(' ')],
        label: "Space",
        action: Action::RunPause,
        help: "run or pause",
    },
    Binding {
        keys: &[ch('n'), ch('.')],
        label: "n .",
        action: Action::StepOne,
        help: "one increment",
    },
    Binding {
        keys: &[ch('c')],
        label: "c",
        action: Action::ToCycleEnd,
        help: "to the end of the cycle (or transient)",
    },
    Binding {
        keys: &[ch('s')],
        label: "s",
        action: Action::ToSteady,
        help: "to the steady state",
    },
    Binding {
        keys: &[ch('r')],
        label: "r",
        action: Action::Reset,
        help: "reset and rerun the transient",
    },
    Binding {
        keys: &[ch('+'), ch('=')],
        label: "+ =",
        action: Action::Faster,
        help: "faster (x2 increments per frame)",
    },
    Binding {
        keys: &[ch('-')],
        label: "-",
        action: Action::Slower,
        help: "slower (/2 increments per frame)",
    },
    Binding {
        keys: &[ch('e')],
        label: "e",
        action: Action::PauseOnEvents,
        help: "pause on events on/off",
    },
    Binding {
        keys: &[ch('?')],
        label: "?",
        action: Action::Help,
        help: "this help on/off",
    },
    Binding {
        keys: &[ch('q'), key(KeyCode::Esc), ctrl('c')],
        label: "q Esc ^C",
        action: Action::Quit,
        help: "quit",
    },
];

impl Key {
    fn matches(&self, event: &KeyEvent) -> bool {
        if self.code != event.code {
            return false;
        }
        let ctrl = event.modifiers.contains(KeyModifiers::CONTROL);
        if ctrl != self.ctrl {
            return false;
        }
        match self.code {
            KeyCode::Char(_) => true,
            _ => event.modifiers.contains(KeyModifiers::SHIFT) == self.shift,
        }
    }
}

/// The action bound to a key press, if any.
pub fn action_for(event: &KeyEvent) -> Option<Action> {
    BINDINGS
        .iter()
        .find(|b| b.keys.iter().any(|k| k.matches(event)))
        .map(|b| b.action)
}

/// A key event that triggers `key`, for tests and for replaying the table.
pub fn event_for(key: &Key) -> KeyEvent {
    let mut modifiers = KeyModifiers::NONE;
    if key.shift {
        modifiers |= KeyModifiers::SHIFT;
    }
    if key.ctrl {
        modifiers |= KeyModifiers::CONTROL;
    }
    KeyEvent::new(key.code, modifiers)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_dispatches_to_its_own_row() {
        for b in BINDINGS {
            for k in b.keys {
                assert_eq!(action_for(&event_for(k)), Some(b.action), "{}", b.label);
            }
        }
    }

    #[test]
    fn shift_distinguishes_arrows_but_not_characters() {
        let e = KeyEvent::new(KeyCode::Right, KeyModifiers::SHIFT);
        assert_eq!(action_for(&e), Some(Action::LoadFactorUpBig));
        let e = KeyEvent::new(KeyCode::Char('?'), KeyModifiers::SHIFT);
        assert_eq!(action_for(&e), Some(Action::Help));
        let e = KeyEvent::new(KeyCode::Char('x'), KeyModifiers::NONE);
        assert_eq!(action_for(&e), None);
    }
}
