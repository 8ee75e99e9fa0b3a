//! The explorer's side of the worker: what it is asked to do each frame,
//! and how its records are filed in the history and the event log.

use super::*;

impl App {
    /// While `s` runs to the steady state: the cycles done, the change of
    /// `W` against the rule's tolerance, and an estimate of the time left.
    pub fn steady_progress(&self) -> Option<SteadyProgress> {
        if self.stepping.goal != Some(Goal::Steady) {
            return None;
        }
        let tolerance = self.case.options().convergence().tolerance();
        let changes: Vec<f64> = self
            .stepping
            .cycles
            .windows(2)
            .rev()
            .take(2)
            .filter(|w| w[1].0 == w[0].0 + 1 && w[0].1 > 0.0)
            .map(|w| (w[1].1 - w[0].1).abs() / w[0].1)
            .collect();
        let per_cycle = match (
            self.stepping.cycle_clock.front(),
            self.stepping.cycle_clock.back(),
        ) {
            (Some(a), Some(b)) if self.stepping.cycle_clock.len() > 1 => {
                Some((*b - *a) / (self.stepping.cycle_clock.len() - 1) as u32)
            }
            _ => None,
        };
        let cycles_left = match changes[..] {
            [now, ..] if now <= tolerance => Some(3.0),
            [now, before, ..] if now < before && now > 0.0 => {
                Some(((tolerance / now).ln() / (now / before).ln()).ceil() + 3.0)
            }
            _ => None,
        };
        let max = self.case.options().convergence().max_cycles() as f64;
        let done = self.stepping.cycles.last().map_or(0, |c| c.0);
        let cycles_left = cycles_left.map(|k| k.min((max - done as f64).max(0.0)));
        let left = match (per_cycle, cycles_left) {
            (Some(t), Some(k)) => Some(t.mul_f64(k)),
            _ => None,
        };
        Some(SteadyProgress {
            cycles: done,
            change: changes.first().copied(),
            tolerance,
            cycles_left: cycles_left.map(|k| k as usize),
            left,
        })
    }

    /// What the worker should be doing now.
    pub(super) fn wanted(&self) -> Option<worker::Goal> {
        if self.view != View::Stepping || self.quit || self.stepping.failure.is_some() {
            return None;
        }
        match self.stepping.goal {
            Some(Goal::TransientEnd) => Some(worker::Goal::TransientEnd),
            Some(Goal::CycleEnd(_)) => Some(worker::Goal::CycleEnd),
            Some(Goal::Steady) => Some(worker::Goal::Steady),
            None if self.stepping.running => Some(worker::Goal::Paced(self.speed())),
            None => None,
        }
    }

    pub(super) fn go(&mut self, goal: worker::Goal) {
        self.seq += 1;
        self.sent = Some(goal);
        self.worker.send(Command::Go {
            seq: self.seq,
            goal,
        });
    }

    /// Tell the worker what is wanted, if that changed.
    pub(super) fn sync(&mut self) {
        let wanted = self.wanted();
        if wanted == self.sent
            || (wanted.is_none() && matches!(self.sent, Some(worker::Goal::Increments(_))))
        {
            return;
        }
        match wanted {
            Some(g) => self.go(g),
            None => {
                self.seq += 1;
                self.worker.send(Command::Pause);
                self.sent = None;
            }
        }
    }

    /// One frame: take what the worker sent (at most `budget` of time),
    /// poll the sweep, and tell the worker what to do next.
    pub fn tick(&mut self, budget: Duration) {
        let deadline = Instant::now() + budget;
        if let Ok(s) = &mut self.sweep_view.sweep {
            s.poll();
        }
        if let Ok(r) = &mut self.regime_view.regime {
            r.poll();
        }
        self.started = true;
        self.sync();
        self.ask_profile();
        for i in 0..MAX_REPLIES_PER_FRAME {
            if i % 256 == 255 && Instant::now() >= deadline {
                break;
            }
            match self.worker.try_recv() {
                Some(r) => self.take(r),
                None => break,
            }
        }
        self.sync();
    }

    /// Exactly `n` increments (fewer if the run stops), waiting for them:
    /// what tests use to reach a reproducible state.
    pub fn advance(&mut self, n: usize) {
        if self.sent.is_some() {
            self.seq += 1;
            self.worker.send(Command::Pause);
            self.sent = None;
        }
        self.go(worker::Goal::Increments(n));
        let seq = self.seq;
        while let Some(reply) = self.worker.recv() {
            let done = matches!(&reply, Reply::Stopped { seq: s, generation, .. }
                if *s == seq && *generation == self.generation);
            self.take(reply);
            if done {
                break;
            }
        }
        self.sent = None;
    }

    /// Wait until the worker has finished what it was last asked (a run
    /// that goes on for ever is paused first), and take all it sent:
    /// what tests use after a key that steps.
    pub fn settle(&mut self) {
        if matches!(self.sent, Some(worker::Goal::Paced(_))) || self.sent.is_none() {
            self.advance(0);
            return;
        }
        while self.sent.is_some() {
            match self.worker.recv() {
                Some(r) => self.take(r),
                None => break,
            }
        }
    }

    /// Whether the loop has stepping to do (else it can sleep longer).
    pub fn is_busy(&self) -> bool {
        if self.sweep_view.sweep.as_ref().is_ok_and(|s| {
            s.is_running() || s.started() && matches!(s.limit(), LimitState::Computing)
        }) {
            return true;
        }
        if self.regime_view.regime.as_ref().is_ok_and(|r| {
            r.is_running() || r.started() && matches!(r.curve(), CurveState::Computing(_))
        }) {
            return true;
        }
        self.sent.is_some()
            || self.view == View::Stepping
                && (self.stepping.running || self.stepping.goal.is_some())
    }

    /// File `record` as if the worker had sent it (its generation is set
    /// to the current run's): tests drive a fixed, synthetic state with it,
    /// so screen snapshots hold no solver numbers.
    pub fn feed(&mut self, mut record: Record) {
        record.generation = self.generation;
        self.file(record);
    }

    /// Set the transient and friction coefficient as the worker's start of
    /// a run does (tests, with [`App::feed`]).
    pub fn feed_started(&mut self, transient: Vec<Segment>, friction: f64) {
        self.stepping.transient = transient;
        self.stepping.friction = friction;
    }

    pub(super) fn take(&mut self, reply: Reply) {
        match reply {
            Reply::Started {
                generation,
                transient,
                friction,
            } if generation == self.generation => {
                self.stepping.transient = transient;
                self.stepping.friction = friction;
            }
            Reply::Record(r) if r.generation == self.generation => self.file(*r),
            Reply::Profile {
                generation,
                profile,
            } if generation == self.generation => self.take_profile(profile),
            Reply::Stopped {
                generation,
                seq,
                why,
            } if generation == self.generation && seq == self.seq => {
                self.sent = None;
                self.stopped(why);
            }
            _ => {}
        }
    }

    pub(super) fn stopped(&mut self, why: Stopped) {
        let settled = matches!(why, Stopped::Reached | Stopped::Ended);
        match why {
            Stopped::Reached => {
                if let Some(goal) = self.stepping.goal.take() {
                    self.notice = Some(match (goal, self.status()) {
                        (Goal::Steady, Status::Steady(s) | Status::Ended(s)) => format!(
                            "steady state: {} after {} cycles",
                            s.state().as_str(),
                            s.cycles
                        ),
                        (Goal::TransientEnd, _) => "end of the transient".into(),
                        (Goal::CycleEnd(c), _) => format!("end of cycle {c}"),
                        (Goal::Steady, _) => "stopped".into(),
                    });
                }
            }
            Stopped::Event(text, load) => {
                self.stepping.running = false;
                self.stepping.goal = None;
                self.stepping.last_event = Some(text);
                // Inside its increment the second status line gives the
                // event's load point; the notice keeps to the point.
                self.notice = Some(if load.is_some() {
                    "paused at the event (Space runs on)".into()
                } else {
                    "paused on the event (Space runs on)".into()
                });
            }
            Stopped::Ended => {
                self.stepping.running = false;
                self.stepping.goal = None;
                if let Status::Ended(s) | Status::Steady(s) = self.status() {
                    self.notice = Some(format!("the run ended: {}", s.state().as_str()));
                }
            }
            Stopped::Failed(text) => {
                self.stepping.running = false;
                self.stepping.goal = None;
                self.stepping.last_event = Some(format!("solver failed: {text}"));
                self.stepping.failure = Some(text);
            }
            Stopped::Memory => {
                self.stepping.running = false;
                self.stepping.goal = None;
                self.notice =
                    Some("paused: the record of cycles filled its share of --history-mb".into());
            }
            Stopped::Cancelled => {}
        }
        if settled {
            self.tour_run_stopped();
        }
    }

    pub(super) fn file(&mut self, r: Record) {
        if let Some(d) = &r.detail {
            let m = d
                .slip
                .iter()
                .chain(d.slip_before.iter().flatten())
                .fold(0.0f32, |m, v| m.max(v.abs()));
            self.stepping.slip_scale = self.stepping.slip_scale.max(f64::from(m));
        }
        if let Some(c) = r.completed {
            if self.stepping.cycles.len() >= MAX_W_CYCLES {
                thin_older_half(&mut self.stepping.cycles);
            }
            self.stepping.cycles.push(c);
            if self.stepping.cycle_clock.len() >= 4 {
                self.stepping.cycle_clock.pop_front();
            }
            self.stepping.cycle_clock.push_back(Instant::now());
        }
        for e in &r.events {
            self.stepping.last_event = Some(e.text.clone());
            let max_log = (self.config.history_bytes / LOG_SHARE / LOG_ENTRY_BYTES).max(1000);
            self.log_view.keep(e.clone(), max_log);
        }
        self.stepping.history.push(r);
        if let Some(c) = self.stepping.cursor {
            // The cursor's increment was dropped: hold the oldest kept.
            if let Some(first) = self.stepping.history.oldest() {
                if c < first.increment {
                    self.stepping.cursor = Some(first.increment);
                }
            }
        }
    }
}
