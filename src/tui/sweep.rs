//! The sweep view's state: a preset's sweep running on background threads,
//! its rows as they arrive, `lambda_2`, and the cursor. No terminal I/O
//! here, and no physics: the runs are [`SweepSpec::run`]'s and the limit is
//! [`limit_at`]'s.
//!
//! A full preset sweep takes tens of seconds, so it runs off the UI thread
//! and hands each finished run over a channel; the UI drains the channel
//! once per frame ([`Sweep::poll`]), so it never waits on a run.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::Arc;

use crate::analysis::case::Case;
use crate::analysis::curves::limit_at;
use crate::analysis::limit::{Limit, DEFAULT_SAMPLES};
use crate::analysis::sweep::Axis;
use crate::analysis::sweep::{Job, Row, SweepSpec};
use crate::io::preset::Preset;
use crate::model::path::Initial;
use crate::model::ParamError;

/// What the sweep view runs: a sweep, its name and its horizontal axis.
#[derive(Debug, Clone)]
pub struct SweepSource {
    /// Shown in the title: the preset's name.
    pub name: String,
    /// The preset's lists of `lambda`, `phi` and initial paths, over the case's model.
    pub spec: SweepSpec,
    /// The horizontal axis of the map: `lambda` or `phi`.
    pub axis: Axis,
}

impl SweepSource {
    /// The preset's lists over the model of `case`. The model comes from
    /// the explorer's case rather than the preset so that a run opened from
    /// the map is the very run that produced the marker, flags included.
    pub fn from_preset(preset: &Preset, case: &Case) -> Result<Self, ParamError> {
        Ok(Self {
            name: preset.name.clone(),
            spec: SweepSpec::over(case, &preset.sweep)?,
            axis: preset.figure.as_ref().map_or(Axis::Lambda, |f| f.axis),
        })
    }
}

/// `lambda_2` for the map, when it has one.
#[derive(Debug, Clone, PartialEq)]
pub enum LimitState {
    /// Not a single vertical line: a `phi` axis, or several phases.
    NotShown,
    /// The linear programme is running on its own thread.
    Computing,
    /// `lambda_2` and its optimal slip.
    Known(Limit),
    /// The programme failed, with the reason.
    Failed(String),
}

/// What the background threads send.
enum Message {
    Row(Box<Row>),
    Finished,
}

/// The background threads of one sweep. Dropping it cancels the runs not
/// yet started (the ones in progress finish, and their sends are ignored
/// because the receiver is gone).
struct Worker {
    cancel: Arc<AtomicBool>,
    rx: Receiver<Message>,
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// The sweep view's state.
pub struct Sweep {
    source: SweepSource,
    jobs: Vec<Job>,
    /// By job index; `None` until the run arrives.
    rows: Vec<Option<Row>>,
    done: usize,
    /// The distinct values of the horizontal axis, increasing.
    xs: Vec<f64>,
    /// Per entry of `xs`, the jobs at that value in job order.
    columns: Vec<Vec<usize>>,
    /// (index into `xs`, index into that column).
    cursor: (usize, usize),
    limit: LimitState,
    worker: Option<Worker>,
    /// The one `lambda_2` programme in flight: it does not depend on the
    /// runs, so a rerun of the sweep keeps it rather than starting another.
    limit_rx: Option<Receiver<Result<Limit, String>>>,
    started: bool,
    /// The runs' thread is done (the limit's may not be).
    runs_finished: bool,
    /// When the runs started, and how many were done then: the rate the
    /// estimate of the time left is made from.
    clock: Option<(std::time::Instant, usize)>,
}

impl Sweep {
    /// The sweep of `source`, not started, with an empty map and the cursor
    /// at the first run of the first column.
    pub fn new(source: SweepSource) -> Self {
        let jobs = source.spec.jobs();
        let x_of = |j: &Job| match source.axis {
            Axis::Lambda => j.load_factor,
            Axis::Phi => j.phase,
        };
        let mut xs: Vec<f64> = jobs.iter().map(x_of).collect();
        xs.sort_by(f64::total_cmp);
        xs.dedup_by(|a, b| a.to_bits() == b.to_bits());
        let mut columns = vec![Vec::new(); xs.len()];
        for job in &jobs {
            let x = x_of(job);
            if let Ok(i) = xs.binary_search_by(|v| v.total_cmp(&x)) {
                columns[i].push(job.index);
            }
        }
        let limit = match Self::limit_phase(&source) {
            Some(_) => LimitState::Computing,
            None => LimitState::NotShown,
        };
        Self {
            rows: vec![None; jobs.len()],
            jobs,
            done: 0,
            xs,
            columns,
            cursor: (0, 0),
            limit,
            worker: None,
            limit_rx: None,
            started: false,
            runs_finished: false,
            clock: None,
            source,
        }
    }

    /// The phase `lambda_2` is drawn for: only a `lambda` axis over one
    /// phase has a single vertical line.
    fn limit_phase(source: &SweepSource) -> Option<f64> {
        match (source.axis, source.spec.phases()) {
            (Axis::Lambda, [phase]) => Some(*phase),
            _ => None,
        }
    }

    /// Start the sweep (again): any sweep in progress is cancelled, and the
    /// map empties. The runs and `lambda_2` go on their own threads so the
    /// limit (up to a second) shows while the runs are still coming in.
    pub fn start(&mut self) {
        self.worker = None;
        self.rows.iter_mut().for_each(|r| *r = None);
        self.done = 0;
        self.started = true;
        self.runs_finished = false;
        self.clock = Some((std::time::Instant::now(), 0));
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = mpsc::channel();
        if let Some(phase) = Self::limit_phase(&self.source) {
            if !matches!(self.limit, LimitState::Known(_)) && self.limit_rx.is_none() {
                self.limit = LimitState::Computing;
                let spec = self.source.spec.clone();
                let (tx, rx) = mpsc::channel();
                self.limit_rx = Some(rx);
                std::thread::spawn(move || {
                    let limit = limit_at(&spec, phase, DEFAULT_SAMPLES).map_err(|e| e.to_string());
                    let _ = tx.send(limit);
                });
            }
        }
        let spec = self.source.spec.clone();
        let jobs = self.jobs.clone();
        let flag = Arc::clone(&cancel);
        std::thread::spawn(move || {
            spec.run(
                &jobs,
                &|row| {
                    let _ = tx.send(Message::Row(Box::new(row.clone())));
                },
                &flag,
            );
            let _ = tx.send(Message::Finished);
        });
        self.worker = Some(Worker { cancel, rx });
    }

    /// Stop the runs not yet started (quitting, or rerunning).
    pub fn cancel(&mut self) {
        self.worker = None;
    }

    /// Take what the background threads have sent; true if anything came.
    pub fn poll(&mut self) -> bool {
        let mut changed = false;
        if let Some(rx) = &self.limit_rx {
            match rx.try_recv() {
                Ok(limit) => {
                    self.limit_rx = None;
                    self.set_limit(limit);
                    changed = true;
                }
                Err(TryRecvError::Disconnected) => {
                    self.limit_rx = None;
                    if matches!(self.limit, LimitState::Computing) {
                        self.limit = LimitState::Failed("the limit thread stopped".into());
                    }
                }
                Err(TryRecvError::Empty) => {}
            }
        }
        loop {
            let Some(worker) = &self.worker else {
                return changed;
            };
            match worker.rx.try_recv() {
                Ok(Message::Row(row)) => {
                    self.insert(*row);
                    changed = true;
                }
                Ok(Message::Finished) => {
                    self.runs_finished = true;
                    changed = true;
                }
                // Every sender is gone: the runs and the limit are done
                // (or a thread died, which the count of runs will show).
                Err(TryRecvError::Disconnected) => {
                    self.runs_finished = true;
                    self.worker = None;
                    return true;
                }
                Err(TryRecvError::Empty) => return changed,
            }
        }
    }

    /// A finished run: what the channel delivers, and what tests inject.
    pub fn insert(&mut self, row: Row) {
        if let Some(slot) = self.rows.get_mut(row.job.index) {
            if slot.is_none() {
                self.done += 1;
            }
            *slot = Some(row);
        }
    }

    /// `lambda_2`, or why it is missing: from the channel, or from tests.
    pub fn set_limit(&mut self, limit: Result<Limit, String>) {
        if matches!(self.limit, LimitState::NotShown) {
            return;
        }
        self.limit = match limit {
            Ok(l) => LimitState::Known(l),
            Err(e) => LimitState::Failed(e),
        };
    }

    // ----- what the panel reads -------------------------------------------

    /// About how long the runs left will take, at the rate of the runs
    /// done since the sweep started; `None` until one is done.
    pub fn time_left(&self) -> Option<std::time::Duration> {
        time_left(self.clock, self.done, self.total(), self.is_running())
    }

    /// What the view runs.
    pub fn source(&self) -> &SweepSource {
        &self.source
    }
    /// The map's horizontal axis.
    pub fn axis(&self) -> Axis {
        self.source.axis
    }
    /// Number of runs in the sweep.
    pub fn total(&self) -> usize {
        self.jobs.len()
    }
    /// Number of runs finished so far.
    pub fn done(&self) -> usize {
        self.done
    }
    /// Whether the sweep has been started (the view opened at least once).
    pub fn started(&self) -> bool {
        self.started
    }
    /// Runs are still being computed in the background.
    pub fn is_running(&self) -> bool {
        self.worker.is_some() && !self.runs_finished
    }
    /// `lambda_2` for the map, or why there is none yet.
    pub fn limit(&self) -> &LimitState {
        &self.limit
    }
    /// The distinct values of the horizontal axis, increasing: the columns.
    pub fn xs(&self) -> &[f64] {
        &self.xs
    }
    /// The finished runs, in job order.
    pub fn rows(&self) -> impl Iterator<Item = &Row> {
        self.rows.iter().flatten()
    }
    /// Every run of the sweep, in job order.
    pub fn jobs(&self) -> &[Job] {
        &self.jobs
    }
    /// The horizontal coordinate of a job.
    pub fn x_of(&self, job: &Job) -> f64 {
        match self.source.axis {
            Axis::Lambda => job.load_factor,
            Axis::Phi => job.phase,
        }
    }
    /// The cursor: (column index into [`Sweep::xs`], run index within it).
    pub fn cursor(&self) -> (usize, usize) {
        self.cursor
    }
    /// The selected job and its row, if it has arrived.
    pub fn selected(&self) -> Option<(&Job, Option<&Row>)> {
        let index = *self.columns.get(self.cursor.0)?.get(self.cursor.1)?;
        Some((&self.jobs[index], self.rows[index].as_ref()))
    }
    /// The initial path of a job, by its index into the spec's list.
    pub fn initial(&self, job: &Job) -> &Initial {
        &self.source.spec.initials()[job.initial]
    }

    // ----- the cursor -----------------------------------------------------

    /// Along the horizontal axis, staying on the same transient.
    pub fn move_x(&mut self, delta: isize) {
        if self.xs.is_empty() {
            return;
        }
        let last = self.xs.len() - 1;
        self.cursor.0 = self.cursor.0.saturating_add_signed(delta).min(last);
        let len = self.columns[self.cursor.0].len();
        self.cursor.1 = self.cursor.1.min(len.saturating_sub(1));
    }

    /// Between the runs at the same horizontal value, wrapping round so
    /// the 26 transients of a column are a few presses apart either way.
    pub fn move_run(&mut self, delta: isize) {
        let Some(column) = self.columns.get(self.cursor.0) else {
            return;
        };
        let len = column.len() as isize;
        if len == 0 {
            return;
        }
        self.cursor.1 = (self.cursor.1 as isize + delta).rem_euclid(len) as usize;
    }
}

/// The time the runs left will take at the rate since `clock` (when the
/// work started, and how many runs were done then): `None` while nothing
/// is running or no run has finished since.
pub fn time_left(
    clock: Option<(std::time::Instant, usize)>,
    done: usize,
    total: usize,
    running: bool,
) -> Option<std::time::Duration> {
    let (start, done_then) = clock?;
    let since = done.checked_sub(done_then).filter(|&d| d > 0 && running)?;
    let per_run = start.elapsed().as_secs_f64() / since as f64;
    Some(std::time::Duration::from_secs_f64(
        per_run * total.saturating_sub(done) as f64,
    ))
}

#[cfg(test)]
mod tests {
    use std::time::{Duration, Instant};

    use super::time_left;

    #[test]
    fn the_time_left_is_the_rate_so_far() {
        let start = Instant::now() - Duration::from_secs(10);
        // 5 runs in 10 s since the start, 10 left: about 20 s.
        let left = time_left(Some((start, 5)), 10, 20, true).unwrap();
        assert!((left.as_secs_f64() - 20.0).abs() < 0.5, "{left:?}");
        assert_eq!(
            time_left(Some((start, 5)), 5, 20, true),
            None,
            "none done yet"
        );
        assert_eq!(
            time_left(Some((start, 0)), 5, 20, false),
            None,
            "not running"
        );
        assert_eq!(time_left(None, 5, 20, true), None);
    }
}
