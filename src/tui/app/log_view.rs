//! The event log over the stepping view: its filter and selection.

use super::*;

/// The event log's state, with the filter of events that the jumps `{ }`
/// and the pause `e` of the stepping view use too.
#[derive(Default)]
pub(super) struct LogView {
    pub(super) log_open: bool,
    /// Index of the selected row among the entries the filter lets through.
    pub(super) log_selected: usize,
    /// Every event kept, oldest first.
    pub(super) log: std::collections::VecDeque<LogEntry>,
    /// Entries dropped to stay within budget.
    pub(super) log_dropped: usize,
    pub(super) filter: Filter,
}

impl LogView {
    /// The entries the log lists: those matching the filter.
    pub(super) fn entries(&self) -> Vec<&LogEntry> {
        self.log
            .iter()
            .filter(|e| self.filter.kind.is_none() || self.filter.matches(e))
            .collect()
    }

    /// Move the selection by `delta` rows, within the entries listed.
    pub(super) fn move_selection(&mut self, delta: isize) {
        let n = self.entries().len();
        self.log_selected = self
            .log_selected
            .saturating_add_signed(delta)
            .min(n.saturating_sub(1));
    }

    /// Keep `entry`, dropping the oldest once `max` are kept (the
    /// selection stays on its entry).
    pub(super) fn keep(&mut self, entry: LogEntry, max: usize) {
        if self.log.len() >= max {
            self.log.pop_front();
            self.log_dropped += 1;
            self.log_selected = self.log_selected.saturating_sub(1);
        }
        self.log.push_back(entry);
    }
}

impl App {
    /// The event log's actions (and the filter's); false if `action` is not one.
    pub(super) fn log_action(&mut self, action: Action) -> bool {
        match action {
            Action::EventKind => {
                let i = KINDS
                    .iter()
                    .position(|k| *k == self.log_view.filter.kind)
                    .unwrap_or(0);
                self.log_view.filter.kind = KINDS[(i + 1) % KINDS.len()];
                self.log_view.log_selected = 0;
                self.filter_changed();
            }
            Action::MinNodes => {
                let i = MIN_NODES
                    .iter()
                    .position(|k| *k == self.log_view.filter.min_nodes)
                    .unwrap_or(0);
                self.log_view.filter.min_nodes = MIN_NODES[(i + 1) % MIN_NODES.len()];
                self.filter_changed();
            }
            Action::ToggleLog => {
                self.log_view.log_open = !self.log_view.log_open;
                let n = self.log_entries().len();
                self.log_view.log_selected = n.saturating_sub(1);
            }
            Action::LogUp => self.move_log(-1),
            Action::LogDown => self.move_log(1),
            Action::LogPageUp => self.move_log(-10),
            Action::LogPageDown => self.move_log(10),
            Action::LogFirst => self.log_view.log_selected = 0,
            Action::LogLast => {
                self.log_view.log_selected = self.log_entries().len().saturating_sub(1)
            }
            Action::LogGo => {
                if let Some(e) = self.log_entries().get(self.log_view.log_selected) {
                    let i = e.increment;
                    self.pause_for_history();
                    self.stepping.cursor = Some(i);
                    self.log_view.log_open = false;
                    if self.stepping.history.get(i).is_none() {
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
        self.notice = Some(format!("events: {}", self.log_view.filter.describe()));
    }

    pub(super) fn send_filter(&self) {
        self.worker.send(Command::PauseOn(
            self.stepping
                .pause_on_events
                .then_some(self.log_view.filter),
        ));
    }

    pub(super) fn move_log(&mut self, delta: isize) {
        self.log_view.move_selection(delta);
    }
}
