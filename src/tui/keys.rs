//! The one table of key bindings. Dispatch and the help overlay both read
//! [`BINDINGS`], so the help can never list a key that does nothing or miss
//! one that does something. Each row says which view it works in, so the
//! same key (an arrow) can mean one thing in the stepping view and another
//! in the sweep view, and the help of each view lists only its own keys.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

pub use super::app::View;

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
    ToggleView,
    SweepPrevX,
    SweepNextX,
    SweepPrevRun,
    SweepNextRun,
    OpenRun,
    RestartSweep,
}

/// The views a binding works in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    Both,
    Stepping,
    Sweep,
}

impl Scope {
    pub fn includes(self, view: View) -> bool {
        matches!(
            (self, view),
            (Scope::Both, _) | (Scope::Stepping, View::Stepping) | (Scope::Sweep, View::Sweep)
        )
    }
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
    pub scope: Scope,
}

/// Every key the explorer knows, in the order the help shows them.
pub const BINDINGS: &[Binding] = &[
    Binding {
        keys: &[key(KeyCode::Left)],
        label: "←",
        action: Action::LoadFactorDown,
        help: "lambda - 0.05 (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[key(KeyCode::Right)],
        label: "→",
        action: Action::LoadFactorUp,
        help: "lambda + 0.05 (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[shifted(KeyCode::Left)],
        label: "Shift-←",
        action: Action::LoadFactorDownBig,
        help: "lambda - 0.5 (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[shifted(KeyCode::Right)],
        label: "Shift-→",
        action: Action::LoadFactorUpBig,
        help: "lambda + 0.5 (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[key(KeyCode::Down)],
        label: "↓",
        action: Action::PhaseDown,
        help: "phi - pi/24 (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[key(KeyCode::Up)],
        label: "↑",
        action: Action::PhaseUp,
        help: "phi + pi/24 (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('[')],
        label: "[",
        action: Action::PreviousPath,
        help: "previous initial path (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch(']')],
        label: "]",
        action: Action::NextPath,
        help: "next initial path (restarts from O)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch(' ')],
        label: "Space",
        action: Action::RunPause,
        help: "run or pause",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('n'), ch('.')],
        label: "n .",
        action: Action::StepOne,
        help: "one increment",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('c')],
        label: "c",
        action: Action::ToCycleEnd,
        help: "to the end of the cycle (or transient)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('s')],
        label: "s",
        action: Action::ToSteady,
        help: "to the steady state",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('r')],
        label: "r",
        action: Action::Reset,
        help: "reset and rerun the transient",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('+'), ch('=')],
        label: "+ =",
        action: Action::Faster,
        help: "faster (x2 increments per frame)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('-')],
        label: "-",
        action: Action::Slower,
        help: "slower (/2 increments per frame)",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('e')],
        label: "e",
        action: Action::PauseOnEvents,
        help: "pause on events on/off",
        scope: Scope::Stepping,
    },
    Binding {
        keys: &[ch('v'), key(KeyCode::Tab)],
        label: "v Tab",
        action: Action::ToggleView,
        help: "switch stepping view / sweep view",
        scope: Scope::Both,
    },
    Binding {
        keys: &[key(KeyCode::Left)],
        label: "←",
        action: Action::SweepPrevX,
        help: "cursor to the previous lambda (or phi)",
        scope: Scope::Sweep,
    },
    Binding {
        keys: &[key(KeyCode::Right)],
        label: "→",
        action: Action::SweepNextX,
        help: "cursor to the next lambda (or phi)",
        scope: Scope::Sweep,
    },
    Binding {
        keys: &[key(KeyCode::Down)],
        label: "↓",
        action: Action::SweepPrevRun,
        help: "cursor to the previous transient at this x",
        scope: Scope::Sweep,
    },
    Binding {
        keys: &[key(KeyCode::Up)],
        label: "↑",
        action: Action::SweepNextRun,
        help: "cursor to the next transient at this x",
        scope: Scope::Sweep,
    },
    Binding {
        keys: &[key(KeyCode::Enter)],
        label: "Enter",
        action: Action::OpenRun,
        help: "open the selected run in the stepping view",
        scope: Scope::Sweep,
    },
    Binding {
        keys: &[ch('r')],
        label: "r",
        action: Action::RestartSweep,
        help: "rerun the whole sweep",
        scope: Scope::Sweep,
    },
    Binding {
        keys: &[ch('?')],
        label: "?",
        action: Action::Help,
        help: "this help on/off",
        scope: Scope::Both,
    },
    Binding {
        keys: &[ch('q'), key(KeyCode::Esc), ctrl('c')],
        label: "q Esc ^C",
        action: Action::Quit,
        help: "quit",
        scope: Scope::Both,
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

/// The bindings of `view`, in table order: what the help lists.
pub fn bindings_for(view: View) -> impl Iterator<Item = &'static Binding> {
    BINDINGS.iter().filter(move |b| b.scope.includes(view))
}

/// The action bound to a key press in `view`, if any.
pub fn action_for(event: &KeyEvent, view: View) -> Option<Action> {
    bindings_for(view)
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
        for view in [View::Stepping, View::Sweep] {
            for b in bindings_for(view) {
                for k in b.keys {
                    assert_eq!(
                        action_for(&event_for(k), view),
                        Some(b.action),
                        "{} in {view:?}",
                        b.label
                    );
                }
            }
        }
    }

    #[test]
    fn no_key_is_bound_twice_in_one_view() {
        for view in [View::Stepping, View::Sweep] {
            let keys: Vec<Key> = bindings_for(view)
                .flat_map(|b| b.keys.iter().copied())
                .collect();
            for (i, a) in keys.iter().enumerate() {
                assert!(!keys[i + 1..].contains(a), "{a:?} twice in {view:?}");
            }
        }
    }

    #[test]
    fn arrows_mean_different_things_per_view() {
        let right = KeyEvent::new(KeyCode::Right, KeyModifiers::NONE);
        assert_eq!(
            action_for(&right, View::Stepping),
            Some(Action::LoadFactorUp)
        );
        assert_eq!(action_for(&right, View::Sweep), Some(Action::SweepNextX));
        let tab = KeyEvent::new(KeyCode::Tab, KeyModifiers::NONE);
        assert_eq!(action_for(&tab, View::Stepping), Some(Action::ToggleView));
        assert_eq!(action_for(&tab, View::Sweep), Some(Action::ToggleView));
    }

    #[test]
    fn shift_distinguishes_arrows_but_not_characters() {
        let v = View::Stepping;
        let e = KeyEvent::new(KeyCode::Right, KeyModifiers::SHIFT);
        assert_eq!(action_for(&e, v), Some(Action::LoadFactorUpBig));
        let e = KeyEvent::new(KeyCode::Char('?'), KeyModifiers::SHIFT);
        assert_eq!(action_for(&e, v), Some(Action::Help));
        let e = KeyEvent::new(KeyCode::Char('x'), KeyModifiers::NONE);
        assert_eq!(action_for(&e, v), None);
    }
}
