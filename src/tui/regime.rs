//! The regime map's state in the sweep view: the steady state over the
//! `(lambda, phi)` plane for one initial transient (the `regime` preset's
//! ranges on a coarser grid, so it fills in within a minute), its runs on
//! background threads, `lambda_2(phi)` from the linear programme, and the
//! cursor over the cells. No terminal I/O here and no physics: the runs
//! are [`SweepSpec::run_ordered`]'s, the map is a [`RegimeMap`] and the
//! limit curve is [`lambda2_points`]'s.
//!
//! The map computes only while it is on screen. Leaving it, or starting
//! it again (another transient, a rerun), cancels the runs it replaces:
//! the ones not started are dropped and the ones in progress stop at
//! their next increment, so a storm of keys leaves one computation and
//! flat memory. The cells already done are kept when it is only left, and
//! coming back runs the rest.
//!
//! `lambda_2(phi)` starts with the map, on a thread of its own (not on
//! rayon's pool, where it would queue behind the map's runs), and each
//! point is drawn as soon as its programme is solved. It is cancelled and
//! resumed with the map.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::Arc;

use crate::analysis::case::Case;
use crate::analysis::curves::lambda2_points;
use crate::analysis::ordered::{Interrupt, StopLevel};
use crate::analysis::regime::{RegimeCell, RegimeMap};
use crate::analysis::sweep::{Job, Row, SweepLists, SweepSpec};
use crate::io::parse::{parse_angle, parse_number, parse_values};
use crate::io::preset::Preset;
use crate::model::path::Initial;

/// The preset whose `lambda` and `phi` ranges the map covers.
pub const REGIME_PRESET: &str = "regime";
/// The map's `lambda` step: coarser than the preset's, so it stays
/// interactive (19 values over 3 to 7.5).
pub const LAMBDA_STEP: f64 = 0.25;
/// The map's `phi` step, `pi/12` (13 values over 0 to `pi`).
pub const PHASE_STEP_TEXT: &str = "pi/12";
/// Samples of an elliptical cycle for each `lambda_2(phi)` of the map, as
/// `figure regime` uses (within 0.5 % of the limit).
const CURVE_SAMPLES: usize = 32;

/// What the regime map covers: the explorer's model (so that a cell opened
/// in the stepping view is the very run that coloured it) over a grid of
/// `lambda` and `phi`.
#[derive(Debug, Clone)]
pub struct RegimeSource {
    /// Shown in the title: the preset's name.
    pub name: String,
    /// The transient the map starts with (the preset's first, `OA` by
    /// default); `[` and `]` choose another.
    pub initial: Initial,
    case: Case,
    load_factors: Vec<f64>,
    phases: Vec<f64>,
}

impl RegimeSource {
    /// The grid `load_factors x phases` over the model of `case`.
    ///
    /// # Errors
    ///
    /// An empty list, or a `lambda` or `phi` for which the cycle is
    /// invalid (as [`SweepSpec::over`]).
    pub fn new(
        name: &str,
        case: &Case,
        load_factors: Vec<f64>,
        phases: Vec<f64>,
    ) -> Result<Self, String> {
        if load_factors.is_empty() || phases.is_empty() {
            return Err("the regime map needs at least one lambda and one phi".into());
        }
        let mut source = Self {
            name: name.to_string(),
            initial: Initial::Direct,
            case: case.clone(),
            load_factors,
            phases,
        };
        source.load_factors.sort_by(f64::total_cmp);
        source.load_factors.dedup();
        source.phases.sort_by(f64::total_cmp);
        source.phases.dedup();
        source.spec(&Initial::Direct)?;
        Ok(source)
    }

    /// The preset's `lambda` and `phi` ranges (from their smallest to their
    /// largest value) in steps of [`LAMBDA_STEP`] and `pi/12`, over the
    /// model of `case`.
    ///
    /// # Errors
    ///
    /// As [`RegimeSource::new`].
    pub fn from_preset(preset: &Preset, case: &Case) -> Result<Self, String> {
        let range = |v: &[f64]| {
            let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        };
        let (l0, l1) = range(&preset.sweep.load_factors);
        let (p0, p1) = range(&preset.sweep.phases);
        let lambdas = if l1 > l0 {
            parse_values(&format!("{l0}:{l1}:{LAMBDA_STEP}"), parse_number)
                .map_err(|e| e.to_string())?
        } else {
            vec![l0]
        };
        let phases = if p1 > p0 {
            parse_values(&format!("{p0}:{p1}:{PHASE_STEP_TEXT}"), parse_angle)
                .map_err(|e| e.to_string())?
        } else {
            vec![p0]
        };
        let mut source = Self::new(&preset.name, case, lambdas, phases)?;
        if let Some(initial) = preset.sweep.initials.first() {
            source.initial = initial.clone();
        }
        Ok(source)
    }

    /// The built-in [`REGIME_PRESET`] over the model of `case`.
    ///
    /// # Errors
    ///
    /// As [`RegimeSource::new`], or the preset cannot be loaded.
    pub fn builtin(case: &Case) -> Result<Self, String> {
        let preset = crate::io::preset::load(REGIME_PRESET).map_err(|e| e.to_string())?;
        Self::from_preset(&preset, case)
    }

    /// The sweep of the grid for one transient.
    fn spec(&self, initial: &Initial) -> Result<SweepSpec, String> {
        let lists = SweepLists {
            load_factors: self.load_factors.clone(),
            phases: self.phases.clone(),
            initials: vec![initial.clone()],
        };
        SweepSpec::over(&self.case, &lists).map_err(|e| e.to_string())
    }

    /// The `lambda` values, ascending.
    pub fn load_factors(&self) -> &[f64] {
        &self.load_factors
    }

    /// The `phi` values, ascending.
    pub fn phases(&self) -> &[f64] {
        &self.phases
    }
}

/// `lambda_2` over the map's phases.
#[derive(Debug, Clone, PartialEq)]
pub enum CurveState {
    /// The linear programmes are running (or paused with the map): one
    /// entry per phase of the map, `Some` once that phase's point is in.
    Computing(Vec<Option<Option<f64>>>),
    /// `lambda_2` at each phase of the map (`None` where it failed).
    Known(Vec<Option<f64>>),
}

impl CurveState {
    /// `lambda_2` at each phase of the map, `None` where it is not (yet)
    /// known: what the map draws, point by point as they arrive.
    pub fn points(&self) -> Vec<Option<f64>> {
        match self {
            Self::Computing(points) => points.iter().map(|p| p.flatten()).collect(),
            Self::Known(curve) => curve.clone(),
        }
    }

    /// Phases solved, of how many.
    pub fn solved(&self) -> (usize, usize) {
        match self {
            Self::Computing(points) => (points.iter().flatten().count(), points.len()),
            Self::Known(curve) => (curve.len(), curve.len()),
        }
    }
}

/// Counts the background threads alive: one is taken for each thread and
/// given back when it ends, however it ends.
struct Alive(Arc<AtomicUsize>);

impl Alive {
    fn new(count: &Arc<AtomicUsize>) -> Self {
        count.fetch_add(1, Ordering::SeqCst);
        Self(Arc::clone(count))
    }
}

impl Drop for Alive {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// The thread of one computation. Dropping it cancels the computation:
/// no run starts, the runs in progress stop at their next increment, and
/// whatever they still send goes nowhere.
struct Worker {
    interrupt: Arc<Interrupt>,
    rx: Receiver<Box<Row>>,
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.interrupt.raise(StopLevel::Abort);
    }
}

/// The `lambda_2(phi)` thread. Dropping it cancels the programmes not yet
/// started; the one in progress finishes and its point goes nowhere.
struct CurveWorker {
    cancel: Arc<AtomicBool>,
    rx: Receiver<(usize, Option<f64>)>,
}

impl Drop for CurveWorker {
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// The regime map's state.
pub struct Regime {
    source: RegimeSource,
    initial: Initial,
    /// The sweep of the grid for [`Regime::initial`], when it is valid.
    spec: Result<SweepSpec, String>,
    map: RegimeMap,
    /// The cell under the cursor: (index of `lambda`, index of `phi`).
    cursor: (usize, usize),
    worker: Option<Worker>,
    curve: CurveState,
    curve_worker: Option<CurveWorker>,
    alive: Arc<AtomicUsize>,
    started: bool,
    /// When the runs (re)started and how many cells were done then.
    clock: Option<(std::time::Instant, usize)>,
}

impl Regime {
    /// The map of `source` for its transient, not started, with the
    /// cursor on the first cell.
    pub fn new(source: RegimeSource) -> Self {
        let initial = source.initial.clone();
        let map = RegimeMap::empty(&source.load_factors, &source.phases);
        let map_phases = source.phases.len();
        Self {
            spec: source.spec(&initial),
            source,
            initial,
            map,
            cursor: (0, 0),
            worker: None,
            curve: CurveState::Computing(vec![None; map_phases]),
            curve_worker: None,
            alive: Arc::new(AtomicUsize::new(0)),
            started: false,
            clock: None,
        }
    }

    /// Compute the cells not yet done (all of them the first time), and,
    /// beside them, the points of `lambda_2(phi)` not yet solved. A
    /// computation in progress is cancelled first.
    pub fn start(&mut self) {
        self.worker = None;
        self.started = true;
        self.start_curve();
        let Ok(spec) = &self.spec else {
            return;
        };
        let todo: Vec<Job> = spec
            .jobs()
            .into_iter()
            .filter(|j| self.cell_at(j.load_factor, j.phase).is_none())
            .collect();
        if todo.is_empty() {
            return;
        }
        self.clock = Some((std::time::Instant::now(), self.done()));
        let interrupt = Arc::new(Interrupt::new());
        let (tx, rx) = mpsc::channel();
        let spec = spec.clone();
        let stop = Arc::clone(&interrupt);
        let alive = Alive::new(&self.alive);
        std::thread::spawn(move || {
            let _alive = alive;
            // A send fails once the receiver is gone: that stops the runs.
            let _ = spec.run_ordered(&todo, &stop, |row| tx.send(Box::new(row)));
        });
        self.worker = Some(Worker { interrupt, rx });
    }

    /// The points of `lambda_2(phi)` not yet solved, on a thread of their
    /// own, started with the map's runs. The curve does not depend on the
    /// transient, so each point is solved once.
    fn start_curve(&mut self) {
        let CurveState::Computing(points) = &self.curve else {
            return;
        };
        if self.curve_worker.is_some() {
            return;
        }
        let Ok(spec) = &self.spec else {
            return;
        };
        let todo: Vec<usize> = (0..points.len()).filter(|&j| points[j].is_none()).collect();
        let phases: Vec<f64> = todo.iter().map(|&j| self.source.phases[j]).collect();
        let spec = spec.clone();
        let (tx, rx) = mpsc::channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let stop = Arc::clone(&cancel);
        let alive = Alive::new(&self.alive);
        // One programme after another on this thread, not on rayon's pool,
        // where the map's runs are queued ahead of them.
        std::thread::spawn(move || {
            let _alive = alive;
            lambda2_points(&spec, &phases, CURVE_SAMPLES, &stop, |i, l2| {
                tx.send((todo[i], l2)).is_ok()
            });
        });
        self.curve_worker = Some(CurveWorker { cancel, rx });
    }

    /// Empty the map and compute it again.
    pub fn restart(&mut self) {
        self.worker = None;
        self.map.clear();
        self.start();
    }

    /// Another transient: the map empties and, when `run`, is computed
    /// for it (the computation it replaces is cancelled).
    pub fn set_initial(&mut self, initial: Initial, run: bool) {
        if initial == self.initial {
            return;
        }
        self.worker = None;
        self.spec = self.source.spec(&initial);
        self.initial = initial;
        self.map.clear();
        if run {
            self.start();
        }
    }

    /// Stop computing (the map is left): the cells and the points of
    /// `lambda_2` done are kept.
    pub fn pause(&mut self) {
        self.worker = None;
        self.curve_worker = None;
    }

    /// Take what the background threads have sent; true if anything came.
    pub fn poll(&mut self) -> bool {
        let mut changed = self.poll_curve();
        loop {
            let Some(worker) = &self.worker else {
                return changed;
            };
            match worker.rx.try_recv() {
                Ok(row) => {
                    self.insert(&row);
                    changed = true;
                }
                Err(TryRecvError::Disconnected) => {
                    self.worker = None;
                    return true;
                }
                Err(TryRecvError::Empty) => return changed,
            }
        }
    }

    /// Take the points of `lambda_2` that have arrived; true if any did.
    /// The curve is known once its thread has ended uncancelled (a phase
    /// whose programme failed then reads as failed).
    fn poll_curve(&mut self) -> bool {
        let Some(worker) = &self.curve_worker else {
            return false;
        };
        let CurveState::Computing(points) = &mut self.curve else {
            self.curve_worker = None;
            return false;
        };
        let mut changed = false;
        let ended = loop {
            match worker.rx.try_recv() {
                Ok((j, l2)) => {
                    if let Some(p) = points.get_mut(j) {
                        *p = Some(l2);
                        changed = true;
                    }
                }
                Err(TryRecvError::Empty) => break false,
                Err(TryRecvError::Disconnected) => break true,
            }
        };
        if ended {
            let cancelled = worker.cancel.load(Ordering::Relaxed);
            self.curve_worker = None;
            if !cancelled {
                self.curve = CurveState::Known(points.iter().map(|p| p.flatten()).collect());
                changed = true;
            }
        }
        changed
    }

    /// A finished run: what the channel delivers, and what tests inject.
    /// A run of another transient or off the grid is ignored.
    pub fn insert(&mut self, row: &Row) {
        if row.initial != self.initial.name() {
            return;
        }
        self.map
            .insert(row.job.load_factor, row.job.phase, RegimeCell::of_row(row));
    }

    /// `lambda_2(phi)`, one value per phase of the map (tests inject it).
    pub fn set_curve(&mut self, curve: Vec<Option<f64>>) {
        self.curve_worker = None;
        self.curve = CurveState::Known(curve);
    }

    // ----- what the panel reads -------------------------------------------

    /// What the map covers.
    pub fn source(&self) -> &RegimeSource {
        &self.source
    }

    /// About how long the cells left will take, at the rate since the
    /// runs last started; `None` until one is done.
    pub fn time_left(&self) -> Option<std::time::Duration> {
        super::sweep::time_left(self.clock, self.done(), self.total(), self.is_running())
    }

    /// The transient the map is for.
    pub fn initial(&self) -> &Initial {
        &self.initial
    }
    /// Why the map cannot be computed for this transient, if it cannot.
    pub fn error(&self) -> Option<&str> {
        self.spec.as_ref().err().map(String::as_str)
    }
    /// The states so far.
    pub fn map(&self) -> &RegimeMap {
        &self.map
    }
    /// The cells in the map.
    pub fn total(&self) -> usize {
        self.source.load_factors.len() * self.source.phases.len()
    }
    /// The cells done.
    pub fn done(&self) -> usize {
        self.map.filled()
    }
    /// Whether the map has been started (shown at least once).
    pub fn started(&self) -> bool {
        self.started
    }
    /// Runs are being computed in the background.
    pub fn is_running(&self) -> bool {
        self.worker.is_some()
    }
    /// `lambda_2(phi)`, or that it is still being computed.
    pub fn curve(&self) -> &CurveState {
        &self.curve
    }
    /// The background threads alive now, including the ones cancelled
    /// that have not yet reached their next increment.
    pub fn threads_alive(&self) -> usize {
        self.alive.load(Ordering::SeqCst)
    }
    /// The cursor: (index of `lambda`, index of `phi`) into the map's grid.
    pub fn cursor(&self) -> (usize, usize) {
        self.cursor
    }
    /// `lambda` and `phi` under the cursor.
    pub fn selected(&self) -> (f64, f64) {
        (
            self.source.load_factors[self.cursor.0],
            self.source.phases[self.cursor.1],
        )
    }
    /// The cell under the cursor, once its run is done.
    pub fn selected_cell(&self) -> Option<RegimeCell> {
        self.map.cell(self.cursor.0, self.cursor.1)
    }

    fn cell_at(&self, load_factor: f64, phase: f64) -> Option<RegimeCell> {
        let i = self
            .source
            .load_factors
            .iter()
            .position(|&v| v == load_factor)?;
        let j = self.source.phases.iter().position(|&v| v == phase)?;
        self.map.cell(i, j)
    }

    // ----- the cursor -----------------------------------------------------

    /// Along `lambda`, clamped at the ends.
    pub fn move_lambda(&mut self, delta: isize) {
        let last = self.source.load_factors.len() - 1;
        self.cursor.0 = self.cursor.0.saturating_add_signed(delta).min(last);
    }

    /// Along `phi`, clamped at the ends.
    pub fn move_phase(&mut self, delta: isize) {
        let last = self.source.phases.len() - 1;
        self.cursor.1 = self.cursor.1.saturating_add_signed(delta).min(last);
    }

    /// The cell nearest to `(lambda, phi)`: the stepping view's case,
    /// when the map opens.
    pub fn move_near(&mut self, load_factor: f64, phase: f64) {
        if let Some(c) = self.map.nearest(load_factor, phase) {
            self.cursor = c;
        }
    }
}
