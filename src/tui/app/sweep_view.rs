//! The sweep view: the map over `lambda` (or `phi`), its save and the run it opens.

use super::*;

/// The sweep view's state: the sweep (or why there is none), how `W` is
/// drawn, and the save prompt.
pub(super) struct SweepView {
    pub(super) sweep: Result<Sweep, String>,
    pub(super) sweep_log_w: bool,
    pub(super) sweep_saved: bool,
    /// The file name being typed after `s`.
    pub(super) save_entry: Option<String>,
    /// Where the map is being saved, while `overwrite?` waits.
    pub(super) save_path: Option<std::path::PathBuf>,
    /// Where `s` saves (the current directory unless changed).
    pub(super) save_dir: std::path::PathBuf,
}

impl SweepView {
    /// The view of `sweep`, not started, `W` on a log axis.
    pub(super) fn new(sweep: Result<Sweep, String>) -> Self {
        Self {
            sweep,
            sweep_log_w: true,
            sweep_saved: false,
            save_entry: None,
            save_path: None,
            save_dir: std::path::PathBuf::from("."),
        }
    }

    /// Whether leaving would throw away a sweep map: one still running, or
    /// finished and not saved.
    pub(super) fn has_work(&self) -> bool {
        self.sweep
            .as_ref()
            .is_ok_and(|s| s.started() && (s.is_running() || (s.done() > 0 && !self.sweep_saved)))
    }
}

impl App {
    /// The sweep view's actions; false if `action` is not one.
    pub(super) fn sweep_action(&mut self, action: Action) -> bool {
        match action {
            Action::SweepPrevX => self.with_sweep_mut(|s| s.move_x(-1)),
            Action::SweepNextX => self.with_sweep_mut(|s| s.move_x(1)),
            Action::SweepPageDown => self.with_sweep_mut(|s| s.move_x(10)),
            Action::SweepPageUp => self.with_sweep_mut(|s| s.move_x(-10)),
            Action::SweepFirst => self.with_sweep_mut(|s| s.move_x(-(isize::MAX / 2))),
            Action::SweepLast => self.with_sweep_mut(|s| s.move_x(isize::MAX / 2)),
            Action::SweepPrevRun => self.with_sweep_mut(|s| s.move_run(-1)),
            Action::SweepNextRun => self.with_sweep_mut(|s| s.move_run(1)),
            Action::SweepLogW => self.sweep_view.sweep_log_w = !self.sweep_view.sweep_log_w,
            Action::SweepSave => self.save_sweep(),
            Action::OpenRun => self.open_selected(),
            Action::RestartSweep => {
                if self.sweep_has_work() {
                    self.confirm = Some(Confirm::RestartSweep);
                } else {
                    self.restart_sweep();
                }
            }
            _ => return false,
        }
        true
    }

    pub(super) fn restart_sweep(&mut self) {
        if let Ok(s) = &mut self.sweep_view.sweep {
            s.start();
            self.sweep_view.sweep_saved = false;
            self.notice = Some("sweep restarted".into());
        }
    }

    /// `s`: ask for the file name, prefilled `sweep-<preset>.csv`.
    pub(super) fn save_sweep(&mut self) {
        let Ok(s) = &self.sweep_view.sweep else {
            return;
        };
        self.sweep_view.save_entry = Some(format!("sweep-{}.csv", s.source().name));
    }

    /// A key while the file name is typed: Enter saves (asking first if
    /// the file exists), Esc cancels.
    pub(super) fn save_entry_key(&mut self, key: KeyEvent) {
        let Some(text) = &mut self.sweep_view.save_entry else {
            return;
        };
        match key.code {
            KeyCode::Esc => {
                self.sweep_view.save_entry = None;
                self.notice = Some("not saved".into());
            }
            KeyCode::Backspace => {
                text.pop();
            }
            KeyCode::Enter => {
                let name = self.sweep_view.save_entry.take().unwrap_or_default();
                let name = name.trim();
                if name.is_empty() {
                    self.notice = Some("not saved: no file name".into());
                    return;
                }
                let path = self.sweep_view.save_dir.join(name);
                // `symlink_metadata`: a link (even a dangling one) is there.
                if std::fs::symlink_metadata(&path).is_ok() {
                    self.sweep_view.save_path = Some(path);
                    self.confirm = Some(Confirm::Overwrite);
                } else {
                    self.sweep_view.save_path = Some(path);
                    self.write_sweep(false);
                }
            }
            KeyCode::Char(c) if text.chars().count() < 200 => text.push(c),
            _ => {}
        }
    }

    /// Write the map to the file chosen, through `sweep`'s own writer
    /// (metadata header included): as a new file, or over the old one
    /// when the user said `y`.
    pub(super) fn write_sweep(&mut self, replace: bool) {
        let (Ok(s), Some(path)) = (&self.sweep_view.sweep, self.sweep_view.save_path.take()) else {
            return;
        };
        let n = s.done();
        let spec = &s.source().spec;
        let written = if replace {
            crate::io::csv::replace_sweep_csv(&path, spec, s.rows())
        } else {
            crate::io::csv::save_sweep_csv(&path, spec, s.rows())
        };
        match written {
            Ok(()) => {
                self.sweep_view.sweep_saved = !s.is_running();
                self.notice = Some(format!("saved {n} runs to {}", path.display()));
            }
            Err(e) => self.notice = Some(format!("not saved: {e}")),
        }
    }

    pub(super) fn with_sweep_mut(&mut self, f: impl FnOnce(&mut Sweep)) {
        if let Ok(s) = &mut self.sweep_view.sweep {
            f(s);
        }
    }
    /// Whether leaving would throw away a sweep map (see [`SweepView::has_work`]).
    pub(super) fn sweep_has_work(&self) -> bool {
        self.sweep_view.has_work()
    }

    pub(super) fn toggle_view(&mut self) {
        self.view = match self.view {
            View::Stepping => View::Sweep,
            View::Sweep => View::Stepping,
            View::Regime => {
                self.pause_regime();
                View::Stepping
            }
        };
        self.help = false;
        self.log_view.log_open = false;
        match (&mut self.sweep_view.sweep, self.view) {
            (Ok(s), View::Sweep) if !s.started() => {
                s.start();
                self.notice = Some(format!(
                    "sweep {} started in the background ({} runs)",
                    s.source().name,
                    s.total()
                ));
            }
            (Err(e), View::Sweep) => self.notice = Some(format!("no sweep: {e}")),
            _ => {}
        }
    }
    /// Open the run under the sweep cursor in the stepping view.
    pub(super) fn open_selected(&mut self) {
        let Ok(sweep) = &self.sweep_view.sweep else {
            return;
        };
        let Some((job, _)) = sweep.selected() else {
            self.notice = Some("no run under the cursor".into());
            return;
        };
        let job = *job;
        // The optimal slip is taken from the map's `lambda_2` when that is
        // the limit of this phase; otherwise the worker solves for it.
        let initial = match (sweep.initial(&job), sweep.limit()) {
            (Initial::Optimal, LimitState::Known(l))
                if sweep.source().spec.phases() == [job.phase] =>
            {
                crate::analysis::curves::optimal_from(l)
            }
            (other, _) => other.clone(),
        };
        self.open_case(job.load_factor, job.phase, initial);
    }
}
