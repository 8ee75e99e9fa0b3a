//! The stepping view: the case (`lambda`, `phi`, the path), running and
//! pausing, history, events and the prompt.

use super::*;

/// The stepping view's state: the run being stepped (its record, the
/// cursor over it, the goal asked for), the paths `[` `]` go through, the
/// prompt, the pinned run and the fretting profile panel.
pub(super) struct SteppingView {
    /// The initial paths `[` and `]` cycle through.
    pub(super) paths: Vec<Initial>,
    pub(super) path_index: usize,
    pub(super) running: bool,
    /// Index into [`SPEEDS`].
    pub(super) speed: usize,
    pub(super) goal: Option<Goal>,
    pub(super) pause_on_events: bool,
    /// The text typed after `:`.
    pub(super) entry: Option<String>,
    pub(super) history: History,
    /// `(cycle, W)` of every completed cycle (older ones thinned).
    pub(super) cycles: Vec<(usize, f64)>,
    pub(super) transient: Vec<Segment>,
    pub(super) friction: f64,
    /// The increment on screen; `None` follows the newest.
    pub(super) cursor: Option<usize>,
    /// The largest `|g - mean g|` seen: the slip panel's steady scale.
    pub(super) slip_scale: f64,
    pub(super) pinned: Option<Pinned>,
    pub(super) last_event: Option<String>,
    pub(super) failure: Option<String>,
    /// When the last few cycles completed: the time a cycle takes.
    pub(super) cycle_clock: std::collections::VecDeque<Instant>,
    /// The fretting profile panel (`f`).
    pub(super) profile: profile_view::ProfilePanel,
}

impl SteppingView {
    /// A run not yet started, running, with `history_bytes` for its
    /// record and `paths[path_index]` as its transient.
    pub(super) fn new(history_bytes: usize, paths: Vec<Initial>, path_index: usize) -> Self {
        Self {
            paths,
            path_index,
            running: true,
            speed: DEFAULT_SPEED,
            goal: None,
            pause_on_events: false,
            entry: None,
            history: History::new(history_bytes),
            cycles: Vec::new(),
            transient: Vec::new(),
            friction: 0.0,
            cursor: None,
            slip_scale: 0.0,
            pinned: None,
            last_event: None,
            failure: None,
            cycle_clock: Default::default(),
            profile: Default::default(),
        }
    }

    /// The increment on screen: under the cursor, or the newest.
    pub(super) fn shown(&self) -> Option<&Record> {
        match self.cursor {
            Some(i) => self.history.get(i).or(self.history.newest()),
            None => self.history.newest(),
        }
    }

    /// Looking back pauses the run, so the instant stays put.
    pub(super) fn pause_for_history(&mut self) {
        self.running = false;
        self.goal = None;
    }
}

impl App {
    /// The stepping view's actions; false if `action` is not one.
    pub(super) fn stepping_action(&mut self, action: Action) -> bool {
        match action {
            Action::LoadFactorDown => self.change_load_factor(-LOAD_FACTOR_STEP),
            Action::LoadFactorUp => self.change_load_factor(LOAD_FACTOR_STEP),
            Action::LoadFactorDownBig => self.change_load_factor(-LOAD_FACTOR_BIG_STEP),
            Action::LoadFactorUpBig => self.change_load_factor(LOAD_FACTOR_BIG_STEP),
            Action::PhaseDown => self.change_phase(-1.0),
            Action::PhaseUp => self.change_phase(1.0),
            Action::PreviousPath => self.change_path(self.stepping.paths.len() - 1),
            Action::NextPath => self.change_path(1),
            Action::RunPause => self.run_pause(),
            Action::StepOne => {
                self.stepping.running = false;
                self.stepping.goal = None;
                self.stepping.cursor = None;
                if self.can_step() {
                    self.notice = None;
                    self.go(worker::Goal::Increments(1));
                }
            }
            Action::Back1 => self.scrub(-1),
            Action::Forward1 => self.scrub(1),
            Action::BackCycle => self.scrub_cycle(-1),
            Action::ForwardCycle => self.scrub_cycle(1),
            Action::Oldest => {
                if let Some(i) = self.stepping.history.oldest().map(|r| r.increment) {
                    self.pause_for_history();
                    self.stepping.cursor = Some(i);
                    self.notice = None;
                }
            }
            Action::Live => {
                self.stepping.cursor = None;
                self.notice = Some("live".into());
            }
            Action::PrevEvent => self.jump_event(false),
            Action::NextEvent => self.jump_event(true),
            Action::Pin => self.pin(),
            Action::Entry => self.stepping.entry = Some(String::new()),
            Action::ToCycleEnd => self.set_goal(match self.stepper_phase() {
                Phase::Transient { .. } => Goal::TransientEnd,
                Phase::Cycle { cycle, .. } => Goal::CycleEnd(cycle),
            }),
            Action::ToSteady => {
                if let Status::Steady(s) = self.status() {
                    self.notice = Some(format!(
                        "already classified: {} after {} cycles",
                        s.state().as_str(),
                        s.cycles
                    ));
                } else {
                    self.set_goal(Goal::Steady);
                }
            }
            Action::Reset => {
                self.restart("reset");
                self.stepping.running = true;
            }
            Action::Faster => {
                self.stepping.speed = (self.stepping.speed + 1).min(SPEEDS.len() - 1);
                self.notice = Some(format!("speed: {} incr/frame", self.speed()));
            }
            Action::Slower => {
                self.stepping.speed = self.stepping.speed.saturating_sub(1);
                self.notice = Some(format!("speed: {} incr/frame", self.speed()));
            }
            Action::PauseOnEvents => {
                self.stepping.pause_on_events = !self.stepping.pause_on_events;
                self.send_filter();
                self.notice = Some(if self.stepping.pause_on_events {
                    format!("pause on events: on ({})", self.log_view.filter.describe())
                } else {
                    "pause on events: off".into()
                });
            }
            _ => return false,
        }
        true
    }

    /// Looking back pauses the run, so the instant stays put.
    pub(super) fn pause_for_history(&mut self) {
        self.stepping.pause_for_history();
    }

    pub(super) fn scrub(&mut self, delta: isize) {
        let (Some(first), Some(last)) = (
            self.stepping.history.oldest(),
            self.stepping.history.newest(),
        ) else {
            return;
        };
        let (first, last) = (first.increment, last.increment);
        let now = self.stepping.cursor.unwrap_or(last);
        let to = now.saturating_add_signed(delta).clamp(first, last);
        if delta > 0 && to == last {
            self.stepping.cursor = None;
            self.notice = Some("live".into());
            return;
        }
        self.pause_for_history();
        self.stepping.cursor = Some(to);
        self.notice = None;
    }

    pub(super) fn scrub_cycle(&mut self, delta: isize) {
        let steps = self.case.disc().steps_per_cycle() as isize;
        self.scrub(delta * steps);
    }

    pub(super) fn jump_event(&mut self, forward: bool) {
        let now = self.shown().map_or(0, |r| r.increment);
        let found = if forward {
            self.log_view
                .log
                .iter()
                .find(|e| e.increment > now && self.log_view.filter.matches(e))
        } else {
            self.log_view
                .log
                .iter()
                .rev()
                .find(|e| e.increment < now && self.log_view.filter.matches(e))
        };
        match found {
            Some(e) => {
                let (i, text) = (e.increment, e.text.clone());
                self.pause_for_history();
                self.stepping.cursor = Some(i);
                if self
                    .stepping
                    .history
                    .newest()
                    .is_some_and(|r| r.increment == i)
                {
                    self.stepping.cursor = None;
                }
                if self.log_view.log_open {
                    // The log follows: its selection is the event shown.
                    if let Some(k) = self
                        .log_entries()
                        .iter()
                        .position(|e| e.increment == i && e.text == text)
                    {
                        self.log_view.log_selected = k;
                    }
                }
                // The status line shows the event itself, once.
                self.notice = Some(
                    if forward {
                        "next event"
                    } else {
                        "previous event"
                    }
                    .into(),
                );
            }
            None => {
                self.notice = Some(format!(
                    "no {} event {}",
                    self.log_view.filter.describe(),
                    if forward { "later" } else { "earlier" }
                ))
            }
        }
    }

    pub(super) fn pin(&mut self) {
        if self.stepping.pinned.is_some() {
            self.stepping.pinned = None;
            self.notice = Some("unpinned".into());
            return;
        }
        let Some((_, d)) = self.shown_detail() else {
            self.notice = Some("nothing to pin yet".into());
            return;
        };
        let slip = d.slip.clone();
        let state = match self.status() {
            Status::Running => "unclassified".to_string(),
            Status::Steady(s) | Status::Ended(s) => s.state().as_str().to_string(),
        };
        let label = format!(
            "lambda {} phi {} {}",
            format_load_factor(self.load_factor()),
            format_phase(self.phase()),
            self.initial().name()
        );
        self.notice = Some(format!("pinned {label}: change the run to compare"));
        self.stepping.pinned = Some(Pinned {
            label,
            path: self.initial().name(),
            state,
            cycles: self.stepping.cycles.clone(),
            slip,
        });
    }

    pub(super) fn entry_key(&mut self, key: KeyEvent) {
        let Some(text) = &mut self.stepping.entry else {
            return;
        };
        match key.code {
            KeyCode::Esc => {
                self.stepping.entry = None;
                self.notice = Some("cancelled".into());
            }
            KeyCode::Backspace => {
                text.pop();
            }
            KeyCode::Enter => {
                let text = self.stepping.entry.take().unwrap_or_default();
                self.apply_entry(&text);
            }
            KeyCode::Char(c) if text.len() < 40 => text.push(c),
            _ => {}
        }
    }

    /// `lambda = 5.13`, `phi = pi/4` (or radians), `path = OA`.
    pub(super) fn apply_entry(&mut self, text: &str) {
        let (name, value) = match text.split_once(['=', ' ']) {
            Some((n, v)) => (
                n.trim().to_lowercase(),
                v.trim().trim_start_matches('=').trim(),
            ),
            None => {
                self.notice =
                    Some("type name = value: lambda = 5.13, phi = pi/4, path = OA".into());
                return;
            }
        };
        match name.as_str() {
            "lambda" | "l" | "λ" => match value.parse::<f64>() {
                Ok(v) if v >= 0.0 && v.is_finite() => {
                    self.change_cycle(v, self.phase(), format!("lambda {}", format_load_factor(v)))
                }
                _ => self.notice = Some(format!("not a lambda: {value}")),
            },
            "phi" | "p" | "φ" => match parse_phase(value) {
                Some(v) => {
                    self.change_cycle(self.load_factor(), v, format!("phi {}", format_phase(v)))
                }
                None => self.notice = Some(format!("not a phase: {value}")),
            },
            "path" | "initial" => {
                match self
                    .stepping
                    .paths
                    .iter()
                    .position(|p| p.name().eq_ignore_ascii_case(value))
                {
                    Some(i) => {
                        self.stepping.path_index = i;
                        self.restart(&format!("path {}", self.initial().name()));
                    }
                    // Not a named path: the user's own, `X1,Y1;X2,Y2`.
                    None if value.contains(',') => self.custom_path(value),
                    None => {
                        self.notice = Some(format!(
                            "no initial path {value}: a name, or points X1,Y1;X2,Y2"
                        ))
                    }
                }
            }
            _ => self.notice = Some(format!("unknown name {name}: lambda, phi or path")),
        }
    }

    /// The user's own transient `O -> points -> A`, checked as `run --path`
    /// checks it, added to the paths `[` and `]` go through.
    pub(super) fn custom_path(&mut self, value: &str) {
        let points = match crate::io::parse::parse_points(value) {
            Ok(p) => p,
            Err(e) => {
                self.notice = Some(format!("path = X1,Y1;X2,Y2: {e}"));
                return;
            }
        };
        let points = points
            .into_iter()
            .map(|(x, y)| crate::model::LoadPoint::new(x, y))
            .collect();
        match Initial::custom_for(points, &self.case.material()) {
            Ok(initial) => {
                let i = match self.stepping.paths.iter().position(|p| *p == initial) {
                    Some(i) => i,
                    None => {
                        self.stepping.paths.push(initial.clone());
                        self.stepping.paths.len() - 1
                    }
                };
                self.stepping.path_index = i;
                self.restart(&format!("path {}", self.initial().name()));
            }
            Err(e) => self.notice = Some(format!("path = X1,Y1;X2,Y2: {e}")),
        }
    }
    pub(super) fn can_step(&mut self) -> bool {
        if let Some(f) = &self.stepping.failure {
            self.notice = Some(format!("the solver failed ({f}); r to rerun"));
            return false;
        }
        if let Status::Ended(s) = self.status() {
            self.notice = Some(format!(
                "the run has ended ({}); r to rerun, or change lambda, phi or the path",
                s.state().as_str()
            ));
            return false;
        }
        true
    }

    pub(super) fn run_pause(&mut self) {
        if self.stepping.running || self.stepping.goal.is_some() {
            self.stepping.running = false;
            self.stepping.goal = None;
            self.notice = Some("paused".into());
        } else if self.can_step() {
            self.stepping.running = true;
            self.stepping.cursor = None;
            self.notice = None;
        }
    }

    pub(super) fn set_goal(&mut self, goal: Goal) {
        if self.can_step() {
            self.stepping.running = false;
            self.stepping.cursor = None;
            self.stepping.goal = Some(goal);
            self.notice = Some(match goal {
                Goal::TransientEnd => "to the end of the transient…".into(),
                Goal::CycleEnd(c) => format!("to the end of cycle {c}…"),
                Goal::Steady => "to the steady state…".into(),
            });
        }
    }

    pub(super) fn change_load_factor(&mut self, delta: f64) {
        let old = self.load_factor();
        let new = ((old + delta) * 1e6).round() / 1e6;
        let new = new.max(0.0);
        if new == old {
            self.notice = Some("lambda cannot go below 0".into());
            return;
        }
        self.change_cycle(
            new,
            self.phase(),
            format!("lambda {}", format_load_factor(new)),
        );
    }

    pub(super) fn change_phase(&mut self, sign: f64) {
        if self.case.cycle().as_polyline().is_some() {
            self.notice = Some("a polyline cycle (--cycle) has no phase".into());
            return;
        }
        let old = self.phase();
        let k = (old / PHASE_STEP).round();
        let mut new = if (old - k * PHASE_STEP).abs() < 1e-9 {
            (k + sign) * PHASE_STEP
        } else {
            old + sign * PHASE_STEP
        };
        if new > PI + 1e-9 {
            new -= 2.0 * PI;
        } else if new <= -PI + 1e-9 {
            new += 2.0 * PI;
        }
        self.change_cycle(
            self.load_factor(),
            new,
            format!("phi {}", format_phase(new)),
        );
    }

    pub(super) fn change_cycle(&mut self, load_factor: f64, phase: f64, what: String) {
        match self.cycle_at(load_factor, phase) {
            Ok(cycle) => {
                if let Err(e) = self.case.set_cycle(cycle) {
                    self.notice = Some(e.to_string());
                    return;
                }
                self.restart(&what);
            }
            Err(e) => self.notice = Some(e.to_string()),
        }
    }

    pub(super) fn change_path(&mut self, offset: usize) {
        self.stepping.path_index = (self.stepping.path_index + offset) % self.stepping.paths.len();
        let what = format!("path {}", self.initial().name());
        self.restart(&what);
    }

    pub(super) fn send_restart(&mut self) {
        self.generation += 1;
        self.sent = None;
        self.forget_profile();
        self.worker.send(Command::Restart {
            generation: self.generation,
            case: Box::new(self.case.clone()),
            initial: self.initial().clone(),
        });
        self.send_filter();
    }

    /// Start the run again (the work it replaces is cancelled), keeping
    /// the running/paused choice and the pinned run.
    pub(super) fn restart(&mut self, why: &str) {
        self.send_restart();
        self.stepping.history.clear();
        self.log_view.log.clear();
        self.log_view.log_dropped = 0;
        self.log_view.log_selected = 0;
        self.stepping.cycles.clear();
        self.stepping.transient.clear();
        self.stepping.cursor = None;
        self.stepping.slip_scale = 0.0;
        self.stepping.last_event = None;
        self.stepping.failure = None;
        self.stepping.goal = None;
        let from = match self.initial() {
            Initial::Slip { .. } | Initial::Optimal => "restarted at A with the prescribed slip",
            _ => "restarted from O",
        };
        self.notice = Some(format!("{why}: {from}"));
    }

    /// The explorer's cycle at `load_factor` and `phase`: a polyline keeps
    /// its shape (it has no phase).
    pub(super) fn cycle_at(
        &self,
        load_factor: f64,
        phase: f64,
    ) -> Result<Cycle, crate::model::ParamError> {
        let c = &self.case.cycle();
        match c.as_polyline() {
            Some(_) => c.with_load_factor(load_factor),
            None => Cycle::new(c.center(), load_factor, c.slope(), phase),
        }
    }

    /// Step the case `(lambda, phi)` with the transient `initial` (the
    /// explorer's model otherwise) in the stepping view, from the start:
    /// what Enter in the sweep view and in the regime map does.
    pub(super) fn open_case(&mut self, load_factor: f64, phase: f64, initial: Initial) {
        let cycle = match self.cycle_at(load_factor, phase) {
            Ok(cycle) => cycle,
            Err(e) => {
                self.notice = Some(e.to_string());
                return;
            }
        };
        if let Err(e) = self.case.set_cycle(cycle) {
            self.notice = Some(e.to_string());
            return;
        }
        self.pause_regime();
        self.stepping.path_index = match self.stepping.paths.iter().position(|p| *p == initial) {
            Some(i) => i,
            None => {
                self.stepping.paths.push(initial.clone());
                self.stepping.paths.len() - 1
            }
        };
        self.view = View::Stepping;
        self.stepping.running = true;
        let what = format!(
            "opened lambda {}, phi {}, path {}",
            format_load_factor(load_factor),
            format_phase(phase),
            self.initial().name()
        );
        self.restart(&what);
    }
}

/// `pi/4`, `-3pi/8`, `0.3`.
fn parse_phase(s: &str) -> Option<f64> {
    let s = s.trim().replace('π', "pi");
    if let Ok(v) = s.parse::<f64>() {
        return v.is_finite().then_some(v);
    }
    let (num, den) = match s.split_once('/') {
        Some((a, b)) => (a.trim(), b.trim().parse::<f64>().ok()?),
        None => (s.as_str(), 1.0),
    };
    let k = match num.strip_suffix("pi")?.trim() {
        "" => 1.0,
        "-" => -1.0,
        k => k.parse::<f64>().ok()?,
    };
    Some(k * PI / den)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    pub(super) fn phases_parse() {
        assert_eq!(parse_phase("pi/4"), Some(PI / 4.0));
        assert_eq!(parse_phase("-3pi/8"), Some(-3.0 * PI / 8.0));
        assert_eq!(parse_phase("0.3"), Some(0.3));
        assert_eq!(parse_phase("x"), None);
    }
}
