//! The key tables, one per view. Dispatch and the help overlay both read
//! [`TABLES`], so the help can never list a key that does nothing or miss
//! one that does something. Each row says which view it works in, so the
//! same key (an arrow) can mean one thing in the stepping view and another
//! in the sweep view, and the help of each view lists only its own keys.

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

mod global;
mod log;
mod regime;
mod stepping;
mod sweep;
mod tour;

pub use super::app::View;

/// Everything a key can ask the explorer to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    /// `←`: lower `lambda` by [`LOAD_FACTOR_STEP`](super::app::LOAD_FACTOR_STEP)
    /// and restart.
    LoadFactorDown,
    /// `→`: raise `lambda` by [`LOAD_FACTOR_STEP`](super::app::LOAD_FACTOR_STEP)
    /// and restart.
    LoadFactorUp,
    /// Shift-`←`: lower `lambda` by [`LOAD_FACTOR_BIG_STEP`](super::app::LOAD_FACTOR_BIG_STEP)
    /// and restart.
    LoadFactorDownBig,
    /// Shift-`→`: raise `lambda` by [`LOAD_FACTOR_BIG_STEP`](super::app::LOAD_FACTOR_BIG_STEP)
    /// and restart.
    LoadFactorUpBig,
    /// `↓`: lower `phi` by [`PHASE_STEP`](super::app::PHASE_STEP)
    /// (pi/24) and restart.
    PhaseDown,
    /// `↑`: raise `phi` by [`PHASE_STEP`](super::app::PHASE_STEP)
    /// (pi/24) and restart.
    PhaseUp,
    /// `[`: the previous initial path, and restart.
    PreviousPath,
    /// `]`: the next initial path, and restart.
    NextPath,
    /// Space: run, or pause (also cancels a pending `c` or `s`).
    RunPause,
    /// `n`: pause and take exactly one increment.
    StepOne,
    /// `,` `h`: one increment back in history (pauses).
    Back1,
    /// `.` `l`: one increment forward in history; past the newest goes live.
    Forward1,
    /// `<` PgUp: one cycle back in history.
    BackCycle,
    /// `>` PgDn: one cycle forward in history.
    ForwardCycle,
    /// Home: the oldest increment kept.
    Oldest,
    /// End: follow the newest increment again.
    Live,
    /// `{`: the previous event matching the filter.
    PrevEvent,
    /// `}`: the next event matching the filter.
    NextEvent,
    /// `k`: cycle the filter's event kind ([`KINDS`](super::log::KINDS)).
    EventKind,
    /// `m`: cycle the filter's least advancing-stick size
    /// ([`MIN_NODES`](super::log::MIN_NODES)).
    MinNodes,
    /// `L` `E`: open or close the event log.
    ToggleLog,
    /// Event log: select the previous entry.
    LogUp,
    /// Event log: select the next entry.
    LogDown,
    /// Event log: ten entries up.
    LogPageUp,
    /// Event log: ten entries down.
    LogPageDown,
    /// Event log: the first entry.
    LogFirst,
    /// Event log: the last entry.
    LogLast,
    /// Event log: show the selected entry's increment and close the log.
    LogGo,
    /// `p`: pin the run on screen for comparison, or unpin.
    Pin,
    /// `f`: the fretting profile of the last completed cycle in the
    /// bottom row, or the instant's panels back.
    ToggleProfile,
    /// `:`: open the prompt for `lambda = ...`, `phi = ...` or `path = ...`.
    Entry,
    /// `c`: run to the end of the transient or of the current cycle.
    ToCycleEnd,
    /// `s`: run to the steady state.
    ToSteady,
    /// `r`: rerun the case from the start.
    Reset,
    /// `+` `=`: twice the increments per frame.
    Faster,
    /// `-`: half the increments per frame.
    Slower,
    /// `e`: pause, or not, on events matching the filter.
    PauseOnEvents,
    /// `?`: show or hide the help.
    Help,
    /// Esc: close the help or the log, leave the sweep view, or go live.
    Back,
    /// `q`: quit (asks first if a sweep map would be lost).
    Quit,
    /// Ctrl-C: quit with status 130 (asks first like `q`).
    Interrupt,
    /// Ctrl-Z: give the terminal back to the shell until `fg`.
    Suspend,
    /// `v` Tab: switch between the stepping and the sweep view.
    ToggleView,
    /// Sweep: the previous column (`lambda` or `phi`).
    SweepPrevX,
    /// Sweep: the next column (`lambda` or `phi`).
    SweepNextX,
    /// Sweep PgDn: ten columns on (right); PgDn moves on in every view.
    SweepPageDown,
    /// Sweep PgUp: ten columns back (left); PgUp moves back in every view.
    SweepPageUp,
    /// Sweep: the first column.
    SweepFirst,
    /// Sweep: the last column.
    SweepLast,
    /// Sweep: the previous run (initial transient) at this column.
    SweepPrevRun,
    /// Sweep: the next run (initial transient) at this column.
    SweepNextRun,
    /// Sweep `w`: draw `W` on a log or a linear axis.
    SweepLogW,
    /// Sweep `s`: save the map as `sweep-<preset>.csv`, as `sweep` writes it (header included; an existing file is never replaced).
    SweepSave,
    /// Sweep Enter: open the run under the cursor in the stepping view.
    OpenRun,
    /// Sweep `r`: run the sweep again (asks first if the map would be lost).
    RestartSweep,
    /// `g`: from the stepping view or the sweep's `W` plot to the regime
    /// map over `(lambda, phi)`, and back.
    ToggleRegime,
    /// Regime map: the previous `lambda`.
    RegimePrevLambda,
    /// Regime map: the next `lambda`.
    RegimeNextLambda,
    /// Regime map: the next smaller `phi` (down the map).
    RegimePhaseDown,
    /// Regime map: the next larger `phi` (up the map).
    RegimePhaseUp,
    /// Regime map PgDn: ten `lambda` on (right).
    RegimePageDown,
    /// Regime map PgUp: ten `lambda` back (left).
    RegimePageUp,
    /// Regime map: the first `lambda`.
    RegimeFirst,
    /// Regime map: the last `lambda`.
    RegimeLast,
    /// Regime map Enter: open the case under the cursor in the stepping
    /// view.
    RegimeOpen,
    /// Regime map `[`: the map of the previous initial path.
    RegimePrevPath,
    /// Regime map `]`: the map of the next initial path.
    RegimeNextPath,
    /// Regime map `r`: compute the map again.
    RegimeRestart,
    /// `T`: the guided tour, from its first stop.
    Tour,
    /// Tour `n`: the next stop.
    TourNext,
    /// Tour `N`: the previous stop.
    TourPrevious,
    /// Tour Esc: leave the tour; the case on screen is the user's.
    TourLeave,
}

/// Which key table applies: a view, or the event log over the stepping
/// view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The stepping view's keys.
    Stepping,
    /// The sweep view's keys.
    Sweep,
    /// The event log's keys, over the stepping view.
    Log,
    /// The regime map's keys, in the sweep view.
    Regime,
    /// The guided tour's keys, over whichever view its stop shows.
    Tour,
}

/// All the modes, for the help and the tests.
pub const MODES: [Mode; 5] = [
    Mode::Stepping,
    Mode::Log,
    Mode::Sweep,
    Mode::Regime,
    Mode::Tour,
];

/// The modes a binding works in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    /// Every mode, the tour's too.
    All,
    /// Every view, but not while the tour has the keys.
    Views,
    /// The stepping view only.
    Stepping,
    /// The stepping view, and the event log over it.
    SteppingAndLog,
    /// The sweep view only.
    Sweep,
    /// The event log only.
    Log,
    /// The regime map only.
    Regime,
    /// The guided tour only.
    Tour,
}

impl Scope {
    /// Whether a binding of this scope works in `mode`.
    pub fn includes(self, mode: Mode) -> bool {
        matches!(
            (self, mode),
            (Scope::All, _)
                | (
                    Scope::Views,
                    Mode::Stepping | Mode::Log | Mode::Sweep | Mode::Regime
                )
                | (Scope::Tour, Mode::Tour)
                | (Scope::Stepping, Mode::Stepping)
                | (Scope::SteppingAndLog, Mode::Stepping | Mode::Log)
                | (Scope::Sweep, Mode::Sweep)
                | (Scope::Log, Mode::Log)
                | (Scope::Regime, Mode::Regime)
        )
    }
}

/// One physical key: a code and whether Shift must be held. Character keys
/// ignore Shift because terminals disagree on whether `?` or `+` carry it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Key {
    /// The key code pressed.
    pub code: KeyCode,
    /// Shift must be held (ignored for character keys).
    pub shift: bool,
    /// Ctrl must be held.
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
    /// Keys that trigger the action (any one of them).
    pub keys: &'static [Key],
    /// How the help names the keys.
    pub label: &'static str,
    /// What the keys do.
    pub action: Action,
    /// What the help says about it (at most 30 characters).
    pub help: &'static str,
    /// The modes it works in.
    pub scope: Scope,
}

/// Every key the explorer knows, view by view, in the order the help
/// shows them.
pub const TABLES: &[&[Binding]] = &[
    stepping::STEPPING,
    log::LOG,
    sweep::SWEEP,
    regime::REGIME,
    tour::TOUR,
    global::GLOBAL,
];

/// Every binding of every view, in table order.
pub fn bindings() -> impl Iterator<Item = &'static Binding> {
    TABLES.iter().flat_map(|t| t.iter())
}

/// A row of a key table.
const fn bind(
    keys: &'static [Key],
    label: &'static str,
    action: Action,
    help: &'static str,
    scope: Scope,
) -> Binding {
    Binding {
        keys,
        label,
        action,
        help,
        scope,
    }
}

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

/// One item of the footer: the keys as shown, what they do in a word or
/// two, and the actions they stand for (each bound in the footer's mode).
pub type FooterItem = (&'static str, &'static str, &'static [Action]);

/// The footer of each mode (as gitui shows one): the keys a user reaches
/// for first; `?` lists every key.
pub fn footer(mode: Mode) -> &'static [FooterItem] {
    use Action as A;
    match mode {
        Mode::Stepping => &[
            ("Space", "run", &[A::RunPause]),
            ("n", "step", &[A::StepOne]),
            ("c", "cycle", &[A::ToCycleEnd]),
            ("s", "steady", &[A::ToSteady]),
            ("e", "pause at events", &[A::PauseOnEvents]),
            ("{ }", "events", &[A::PrevEvent, A::NextEvent]),
            ("k m", "kind size", &[A::EventKind, A::MinNodes]),
            (", .", "history", &[A::Back1, A::Forward1]),
            ("p", "pin", &[A::Pin]),
            ("L", "log", &[A::ToggleLog]),
            ("g", "regime", &[A::ToggleRegime]),
            (":", "set", &[A::Entry]),
            ("v", "sweep", &[A::ToggleView]),
            // Dropped first when the footer is short (it shows from 170
            // columns); `?` lists it always.
            ("f", "profile", &[A::ToggleProfile]),
            ("?", "all keys", &[A::Help]),
            ("q", "quit", &[A::Quit]),
        ],
        Mode::Log => &[
            ("↑↓", "select", &[A::LogUp, A::LogDown]),
            ("PgUp PgDn", "page", &[A::LogPageUp, A::LogPageDown]),
            ("Enter", "go there", &[A::LogGo]),
            ("{ }", "events", &[A::PrevEvent, A::NextEvent]),
            ("k m", "kind size", &[A::EventKind, A::MinNodes]),
            ("Esc", "close", &[A::Back]),
            ("?", "all keys", &[A::Help]),
            ("q", "quit", &[A::Quit]),
        ],
        Mode::Sweep => &[
            ("Esc", "back", &[A::Back]),
            ("←→", "x", &[A::SweepPrevX, A::SweepNextX]),
            ("↑↓", "run", &[A::SweepPrevRun, A::SweepNextRun]),
            ("PgUp PgDn", "ten x", &[A::SweepPageUp, A::SweepPageDown]),
            ("Enter", "open", &[A::OpenRun]),
            ("w", "log W", &[A::SweepLogW]),
            ("s", "save", &[A::SweepSave]),
            ("r", "rerun", &[A::RestartSweep]),
            ("g", "regime", &[A::ToggleRegime]),
            ("?", "all keys", &[A::Help]),
            ("q", "quit", &[A::Quit]),
        ],
        Mode::Regime => &[
            ("Esc g", "back", &[A::Back, A::ToggleRegime]),
            ("←→", "lambda", &[A::RegimePrevLambda, A::RegimeNextLambda]),
            ("↑↓", "phi", &[A::RegimePhaseDown, A::RegimePhaseUp]),
            ("Enter", "open", &[A::RegimeOpen]),
            ("[ ]", "path", &[A::RegimePrevPath, A::RegimeNextPath]),
            ("r", "rerun", &[A::RegimeRestart]),
            ("?", "all keys", &[A::Help]),
            ("q", "quit", &[A::Quit]),
        ],
        Mode::Tour => &[
            ("n", "next stop", &[A::TourNext]),
            ("N", "back", &[A::TourPrevious]),
            ("Space", "run", &[A::RunPause]),
            ("Esc", "take over", &[A::TourLeave]),
            ("?", "all keys", &[A::Help]),
            ("q", "quit", &[A::Quit]),
        ],
    }
}

/// The bindings of `mode`, in table order: what the help lists.
pub fn bindings_for(mode: Mode) -> impl Iterator<Item = &'static Binding> {
    bindings().filter(move |b| b.scope.includes(mode))
}

/// The action bound to a key press in `mode`, if any.
pub fn action_for(event: &KeyEvent, mode: Mode) -> Option<Action> {
    bindings_for(mode)
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
        for mode in MODES {
            for b in bindings_for(mode) {
                for k in b.keys {
                    assert_eq!(
                        action_for(&event_for(k), mode),
                        Some(b.action),
                        "{} in {mode:?}",
                        b.label
                    );
                }
            }
        }
    }

    #[test]
    fn no_key_is_bound_twice_in_one_mode() {
        for mode in MODES {
            let keys: Vec<Key> = bindings_for(mode)
                .flat_map(|b| b.keys.iter().copied())
                .collect();
            for (i, a) in keys.iter().enumerate() {
                assert!(!keys[i + 1..].contains(a), "{a:?} twice in {mode:?}");
            }
        }
    }

    #[test]
    fn arrows_mean_different_things_per_mode() {
        let right = KeyEvent::new(KeyCode::Right, KeyModifiers::NONE);
        assert_eq!(
            action_for(&right, Mode::Stepping),
            Some(Action::LoadFactorUp)
        );
        assert_eq!(action_for(&right, Mode::Sweep), Some(Action::SweepNextX));
        let up = KeyEvent::new(KeyCode::Up, KeyModifiers::NONE);
        assert_eq!(action_for(&up, Mode::Log), Some(Action::LogUp));
        let esc = KeyEvent::new(KeyCode::Esc, KeyModifiers::NONE);
        assert_eq!(action_for(&esc, Mode::Sweep), Some(Action::Back));
        let c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
        assert_eq!(action_for(&c, Mode::Stepping), Some(Action::Interrupt));
    }

    #[test]
    fn the_footer_shows_only_keys_that_work_in_its_mode() {
        for mode in MODES {
            for (keys, _, actions) in footer(mode) {
                for a in *actions {
                    assert!(
                        bindings_for(mode).any(|b| b.action == *a),
                        "{keys}: {a:?} in {mode:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn help_texts_fit_two_columns_at_80() {
        for b in bindings() {
            assert!(b.help.chars().count() <= 30, "{}", b.help);
            assert!(b.label.chars().count() <= 7, "{}", b.label);
        }
    }

    #[test]
    fn shift_distinguishes_arrows_but_not_characters() {
        let v = Mode::Stepping;
        let e = KeyEvent::new(KeyCode::Right, KeyModifiers::SHIFT);
        assert_eq!(action_for(&e, v), Some(Action::LoadFactorUpBig));
        let e = KeyEvent::new(KeyCode::Char('?'), KeyModifiers::SHIFT);
        assert_eq!(action_for(&e, v), Some(Action::Help));
        let e = KeyEvent::new(KeyCode::Char('x'), KeyModifiers::NONE);
        assert_eq!(action_for(&e, v), None);
    }
}
