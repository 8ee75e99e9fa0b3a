//! The regime map over `(lambda, phi)`.

use super::*;

/// The regime map's state: the map (or why there is none) and the view
/// `g` goes back to.
pub(super) struct RegimeView {
    pub(super) regime: Result<Regime, String>,
    /// Where `g` in the regime map goes back to: the view it came from.
    pub(super) regime_back: View,
}

impl RegimeView {
    /// The view of `regime`, going back to the sweep view by default.
    pub(super) fn new(regime: Result<Regime, String>) -> Self {
        Self {
            regime,
            regime_back: View::Sweep,
        }
    }

    /// The map left: its runs and its `lambda_2` stop (what is done is kept).
    pub(super) fn pause(&mut self) {
        if let Ok(r) = &mut self.regime {
            r.pause();
        }
    }
}

impl App {
    /// The regime map's actions; false if `action` is not one.
    pub(super) fn regime_action(&mut self, action: Action) -> bool {
        match action {
            Action::ToggleRegime => self.toggle_regime(),
            Action::RegimePrevLambda => self.with_regime_mut(|r| r.move_lambda(-1)),
            Action::RegimeNextLambda => self.with_regime_mut(|r| r.move_lambda(1)),
            Action::RegimePhaseDown => self.with_regime_mut(|r| r.move_phase(-1)),
            Action::RegimePhaseUp => self.with_regime_mut(|r| r.move_phase(1)),
            Action::RegimePageDown => self.with_regime_mut(|r| r.move_lambda(10)),
            Action::RegimePageUp => self.with_regime_mut(|r| r.move_lambda(-10)),
            Action::RegimeFirst => self.with_regime_mut(|r| r.move_lambda(-(isize::MAX / 2))),
            Action::RegimeLast => self.with_regime_mut(|r| r.move_lambda(isize::MAX / 2)),
            Action::RegimeOpen => self.open_regime_cell(),
            Action::RegimePrevPath => self.regime_path(self.stepping.paths.len() - 1),
            Action::RegimeNextPath => self.regime_path(1),
            Action::RegimeRestart => {
                if let Ok(r) = &mut self.regime_view.regime {
                    r.restart();
                    self.notice = Some(format!(
                        "regime map of {}: computing again",
                        r.initial().name()
                    ));
                }
            }
            _ => return false,
        }
        true
    }

    /// `g`: the regime map, from the stepping view or the sweep's `W`
    /// plot, and back to where it came from. The map computes only while
    /// it is shown.
    pub(super) fn toggle_regime(&mut self) {
        match self.view {
            View::Regime => {
                self.pause_regime();
                self.view = self.regime_view.regime_back;
            }
            from => {
                self.regime_view.regime_back = from;
                self.view = View::Regime;
                self.log_view.log_open = false;
                self.help = false;
                let (lambda, phi) = (self.load_factor(), self.phase());
                match &mut self.regime_view.regime {
                    Ok(r) => {
                        if !r.started() {
                            r.move_near(lambda, phi);
                        }
                        r.start();
                        self.notice = Some(if r.is_running() {
                            format!(
                                "regime map of {}: {} of {} runs to do, in the background",
                                r.initial().name(),
                                r.total() - r.done(),
                                r.total()
                            )
                        } else {
                            format!("regime map of {}", r.initial().name())
                        });
                    }
                    Err(e) => self.notice = Some(format!("no regime map: {e}")),
                }
            }
        }
    }

    /// The map left: its runs stop (the cells done are kept).
    pub(super) fn pause_regime(&mut self) {
        self.regime_view.pause();
    }

    /// `[` `]` in the regime map: the map of another initial path, in the
    /// order `[` and `]` go through them in the stepping view.
    pub(super) fn regime_path(&mut self, offset: usize) {
        let Ok(r) = &mut self.regime_view.regime else {
            return;
        };
        let n = self.stepping.paths.len();
        let i = self
            .stepping
            .paths
            .iter()
            .position(|p| p == r.initial())
            .map_or(0, |i| (i + offset) % n);
        let initial = self.stepping.paths[i].clone();
        let name = initial.name();
        r.set_initial(initial, true);
        self.notice = Some(match r.error() {
            Some(e) => format!("no regime map of {name}: {e}"),
            None => format!("regime map of {name}: computing"),
        });
    }

    /// Enter in the regime map: the case under the cursor, with the map's
    /// transient, in the stepping view.
    pub(super) fn open_regime_cell(&mut self) {
        let Ok(r) = &self.regime_view.regime else {
            return;
        };
        let (lambda, phi) = r.selected();
        let initial = r.initial().clone();
        self.open_case(lambda, phi, initial);
    }

    pub(super) fn with_regime_mut(&mut self, f: impl FnOnce(&mut Regime)) {
        if let Ok(r) = &mut self.regime_view.regime {
            f(r);
        }
    }
}
