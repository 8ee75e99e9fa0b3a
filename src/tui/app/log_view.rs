//! The event log over the stepping view: its filter and selection.

use super::*;

impl App {
    /// The event log's actions (and the filter's); false if `action` is not one.
    pub(super) fn log_action(&mut self, action: Action) -> bool {
        match action {
            Action::EventKind => {
                let i = KINDS
                    .iter()
                    .position(|k| *k == self.filter.kind)
                    .unwrap_or(0);
                self.filter.kind = KINDS[(i + 1) % KINDS.len()];
                self.log_selected = 0;
                self.filter_changed();
            }
            Action::MinNodes => {
                let i = MIN_NODES
                    .iter()
                    .position(|k| *k == self.filter.min_nodes)
                    .unwrap_or(0);
                self.filter.min_nodes = MIN_NODES[(i + 1) % MIN_NODES.len()];
                self.filter_changed();
            }
            Action::ToggleLog => {
                self.log_open = !self.log_open;
                let n = self.log_entries().len();
                self.log_selected = n.saturating_sub(1);
            }
            Action::LogUp => self.move_log(-1),
            Action::LogDown => self.move_log(1),
            Action::LogPageUp => self.move_log(-10),
            Action::LogPageDown => self.move_log(10),
            Action::LogFirst => self.log_selected = 0,
            Action::LogLast => self.log_selected = self.log_entries().len().saturating_sub(1),
            Action::LogGo => {
                if let Some(e) = self.log_entries().get(self.log_selected) {
                    let i = e.increment;
                    self.pause_for_history();
                    self.cursor = Some(i);
                    self.log_open = false;
                    if self.history.get(i).is_none() {
                        self.notice = Some("that increment was dropped from history".into());
                    }
                }
            }
            _ => return false,
        }
        true
    }

    pub(super) fn filter_changed(&mut self) {
        self.send_filter();
        self.notice = Some(format!("events: {}", self.filter.describe()));
    }

    pub(super) fn send_filter(&self) {
        self.worker.send(Command::PauseOn(
            self.pause_on_events.then_some(self.filter),
        ));
    }

    pub(super) fn move_log(&mut self, delta: isize) {
        let n = self.log_entries().len();
        self.log_selected = self
            .log_selected
            .saturating_add_signed(delta)
            .min(n.saturating_sub(1));
    }
}
