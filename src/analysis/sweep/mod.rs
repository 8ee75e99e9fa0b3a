//! Batch sweeps over `lambda`, `phi` and initial paths.
//!
//! Work is reused where the physics allows: the transient `O -> I -> A`
//! does not depend on `lambda` or `phi`, so the contact at the centre `A`
//! is computed once per initial path and cloned into every run. The runs of
//! one `(lambda, phi)` go one after another, each starting with the slip
//! rates the runs before it cached ([`groups`]); groups go in parallel
//! (rayon), and results come back in job order, so the output is the same
//! whatever the thread count. The `optimal` initial slip depends on `phi`,
//! so it is computed once per phase (one linear programme each).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::analysis::case::Case;
use crate::analysis::limit::{optimal_initial, LimitError};
use crate::analysis::meet::{Meeting, Meets, Trace};
use crate::analysis::ordered::{run_ordered, Abort, Interrupt, Progress};
use crate::contact::{Contact, ResponseCache};
use crate::model::path::Initial;
use crate::model::{Cycle, Discretisation, LoadPoint, Material, ParamError, Polyline};
use crate::stepping::steady::SteadyState;
use crate::stepping::{
    drive, operators, AtCenter, Control, Driven, Goal, Observer, Outcome, StepError, StepOptions,
    StepReport, Stepper,
};

/// The swept lists of a sweep: `lambda`, `phi` and the initial paths.
///
/// Like [`crate::analysis::case::CaseParams`], an input as given: nothing
/// is checked here, [`SweepSpec::new`] and [`SweepSpec::over`] validate.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepLists {
    /// The load factors `lambda`, in output order.
    pub load_factors: Vec<f64>,
    /// The phases `phi`, radians, in output order.
    pub phases: Vec<f64>,
    /// Initial paths; `optimal` is [`Initial::Optimal`], resolved per phase.
    pub initials: Vec<Initial>,
}

/// The swept variable on the horizontal axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Axis {
    /// The load factor `lambda` (Figs. 3, 4 and 8); spelt `lambda`.
    Lambda,
    /// The phase `phi` (Figs. 6 and 9); spelt `phi`.
    Phi,
}

/// The contact at the cycle centre `A` after one initial path, or the
/// outcome of a transient that already ended (gross slip, separation).
pub type Prepared = Result<AtCenter, StepError>;

/// What a sweep runs: the product `load_factors x phases x initials`, all
/// with one material, discretisation, solver options, cycle centre `A` and
/// slope `psi`.
///
/// Built with [`SweepSpec::new`] or [`SweepSpec::over`], which validate
/// every cycle up front, so a sweep never fails half-way on a bad
/// parameter.
#[derive(Debug, Clone)]
pub struct SweepSpec {
    material: Material,
    disc: Discretisation,
    options: StepOptions,
    center: LoadPoint,
    slope: f64,
    /// A polyline cycle in place of the ellipse (`--cycle`): then `slope`
    /// and the phases are unused, and the phase list is `[0]`.
    polyline: Option<Polyline>,
    load_factors: Vec<f64>,
    phases: Vec<f64>,
    initials: Vec<Initial>,
}

/// One run of a sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Job {
    /// Position in the full job list: the row order of the output.
    pub index: usize,
    /// `lambda` of this run.
    pub load_factor: f64,
    /// `phi` of this run, radians.
    pub phase: f64,
    /// Index into [`SweepSpec::initials`].
    pub initial: usize,
}

/// The state column of a row: a steady state, or a numerical failure.
///
/// Displayed as the steady state's name, or `failed`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum RowState {
    /// The run finished with this verdict (including the terminal events
    /// gross slip and separation, and not converged; model.md section 6.2).
    Steady(SteadyState),
    /// The run has no outcome ([`RunError`]).
    Failed,
}

impl std::fmt::Display for RowState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RowState::Steady(s) => s.fmt(f),
            RowState::Failed => f.write_str("failed"),
        }
    }
}

/// Why a run of a sweep has no outcome.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// An increment failed numerically (in the transient or the cycles).
    #[error(transparent)]
    Step(#[from] StepError),
    /// The optimal initial slip for this phase could not be computed.
    #[error("initial path 'optimal' at phi = {phase}: {source}")]
    Optimal {
        /// `phi` of the failed linear programme, radians.
        phase: f64,
        /// Why the `lambda_2` programme failed.
        source: LimitError,
    },
    /// The job's cycle is invalid (only for a job not from this sweep's
    /// lists; see [`SweepSpec::cycle`]).
    #[error(transparent)]
    Param(#[from] ParamError),
}

/// One finished run.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The job that was run.
    pub job: Job,
    /// The initial path's stable name ([`Initial::name`]).
    pub initial: String,
    /// The run's outcome (steady state and how it was established, `W`,
    /// cycles, rotation per cycle), or why it has none.
    pub outcome: Result<Outcome, RunError>,
}

/// Most runs in one sweep (the product of the three lists): a larger grid
/// is refused before its job list is allocated.
pub const MAX_RUNS: usize = 10_000_000;

/// Columns of a sweep's CSV, one [`crate::io::sweep_csv::row_line`] each.
pub const CSV_HEADER: &str = "lambda,phi,initial,state,dissipation,cycles,rotation_per_cycle";

impl Row {
    /// The state column: the outcome's state, or [`RowState::Failed`].
    pub fn state(&self) -> RowState {
        match &self.outcome {
            Ok(s) => RowState::Steady(s.state()),
            Err(_) => RowState::Failed,
        }
    }
}

/// The optimal slip placed at `A` for one phase.
type OptimalStart = Result<Contact, LimitError>;

impl SweepSpec {
    /// The sweep of `lists` over the model of `case` (material, contact,
    /// solver options, cycle centre and slope): what `shakedown sweep` and
    /// the terminal's sweep view both run, so they cannot drift apart. The
    /// case's own `lambda`, `phi` and initial path are not used.
    ///
    /// # Errors
    ///
    /// As [`SweepSpec::new`]: a `lambda` or `phi` of `lists` for which the
    /// cycle is invalid.
    pub fn over(case: &Case, lists: &SweepLists) -> Result<SweepSpec, ParamError> {
        Self::new(
            case.material(),
            case.disc(),
            case.options(),
            case.cycle().center(),
            // A polyline has no slope: validated on the ellipse's default
            // until `with_polyline` puts the polyline in its place.
            match case.cycle().as_polyline() {
                Some(_) => 0.625,
                None => case.cycle().slope(),
            },
            lists.clone(),
        )?
        .with_polyline(case.cycle().as_polyline().cloned())
    }

    /// A sweep of `lists` on the paper's model: its material, the default
    /// discretisation and solver options, and the centre and slope of
    /// [`Cycle::paper`] (the Fig. 3 map and the `fig6` sweep are such).
    ///
    /// # Errors
    ///
    /// As [`SweepSpec::new`]: a `lambda` or `phi` of `lists` for which the
    /// cycle is invalid.
    ///
    /// # Examples
    ///
    /// ```
    /// use shakedown::analysis::sweep::{SweepLists, SweepSpec};
    /// use shakedown::Initial;
    ///
    /// let spec = SweepSpec::paper(SweepLists {
    ///     load_factors: vec![3.0, 3.05],
    ///     phases: vec![0.0],
    ///     initials: Initial::paper_set(),
    /// })
    /// .unwrap();
    /// // lambda outermost, then phi, then the 25 initial paths.
    /// assert_eq!(spec.jobs().len(), 2 * 25);
    /// ```
    pub fn paper(lists: SweepLists) -> Result<SweepSpec, ParamError> {
        let cycle = Cycle::paper(0.0, 0.0)?;
        Self::new(
            Material::paper(),
            Discretisation::default(),
            StepOptions::default(),
            cycle.center(),
            cycle.slope(),
            lists,
        )
    }

    /// A sweep of `lists` with the cycle centre `center` and slope `slope`.
    ///
    /// # Errors
    ///
    /// A `lambda`, `phi`, centre or slope for which the cycle is invalid
    /// (see [`Cycle::new`]).
    pub fn new(
        material: Material,
        disc: Discretisation,
        options: StepOptions,
        center: LoadPoint,
        slope: f64,
        lists: SweepLists,
    ) -> Result<SweepSpec, ParamError> {
        let spec = SweepSpec {
            material,
            disc,
            options,
            center,
            slope,
            polyline: None,
            load_factors: lists.load_factors,
            phases: lists.phases,
            initials: lists.initials,
        };
        spec.validate()?;
        Ok(spec)
    }

    /// The same sweep over the closed polyline `polyline` in place of the
    /// ellipse (model.md section 5.4); `None` keeps the ellipse.
    /// A polyline has no phase: the phase list must be `[0]`.
    ///
    /// # Errors
    ///
    /// [`ParamError::OutOfRange`] (`phi`) for another phase list;
    /// [`ParamError::BadCount`] (`steps`) when the increments per cycle are
    /// not a multiple of the vertex count ([`Cycle::check_steps`]).
    pub fn with_polyline(mut self, polyline: Option<Polyline>) -> Result<Self, ParamError> {
        if polyline.is_some() && self.phases.iter().any(|&p| p != 0.0) {
            return Err(ParamError::OutOfRange {
                name: "phi",
                value: self
                    .phases
                    .iter()
                    .copied()
                    .find(|&p| p != 0.0)
                    .unwrap_or(0.0),
                expected: "no phase with a polyline cycle (--cycle)",
            });
        }
        if polyline.is_some() {
            // As `Cycle::slope` of a polyline: none, so that no ellipse is
            // silently made of it.
            self.slope = f64::NAN;
        }
        self.polyline = polyline;
        self.validate()?;
        Ok(self)
    }
    /// The polyline cycle, if the sweep is over one.
    pub fn polyline(&self) -> Option<&Polyline> {
        self.polyline.as_ref()
    }

    /// The material.
    pub fn material(&self) -> Material {
        self.material
    }
    /// The discretisation.
    pub fn disc(&self) -> Discretisation {
        self.disc
    }
    /// The stepper's options.
    pub fn options(&self) -> StepOptions {
        self.options
    }
    /// The cycle centre `A`.
    pub fn center(&self) -> LoadPoint {
        self.center
    }
    /// The slope `psi` of the cycle; NaN for a polyline, which has none
    /// (as [`Cycle::slope`]).
    pub fn slope(&self) -> f64 {
        self.slope
    }
    /// The load factors `lambda`, outermost in the job order.
    pub fn load_factors(&self) -> &[f64] {
        &self.load_factors
    }
    /// The phases `phi`.
    pub fn phases(&self) -> &[f64] {
        &self.phases
    }
    /// The initial paths, innermost in the job order.
    pub fn initials(&self) -> &[Initial] {
        &self.initials
    }

    /// The cycle of `job`.
    ///
    /// # Errors
    ///
    /// Only for a job that is not from this sweep's lists (those were all
    /// validated by [`SweepSpec::new`]).
    pub fn cycle(&self, job: &Job) -> Result<Cycle, ParamError> {
        match &self.polyline {
            None => Cycle::new(self.center, job.load_factor, self.slope, job.phase),
            Some(p) => Cycle::polyline(self.center, job.load_factor, p.clone()),
        }
    }

    /// Every run, in output order: `lambda` outermost, then `phi`, then the
    /// initial paths in their given order.
    pub fn jobs(&self) -> Vec<Job> {
        let mut jobs =
            Vec::with_capacity(self.load_factors.len() * self.phases.len() * self.initials.len());
        for &load_factor in &self.load_factors {
            for &phase in &self.phases {
                for initial in 0..self.initials.len() {
                    jobs.push(Job {
                        index: jobs.len(),
                        load_factor,
                        phase,
                        initial,
                    });
                }
            }
        }
        jobs
    }

    /// Check every cycle of the sweep before any work starts.
    fn validate(&self) -> Result<(), ParamError> {
        let runs = self
            .load_factors
            .len()
            .saturating_mul(self.phases.len())
            .saturating_mul(self.initials.len());
        if runs > MAX_RUNS {
            return Err(ParamError::BadCount {
                name: "runs",
                value: runs,
                expected: "at most 10000000 runs (lambda x phi x initial paths)",
            });
        }
        for &l in &self.load_factors {
            for &p in &self.phases {
                let job = Job {
                    index: 0,
                    load_factor: l,
                    phase: p,
                    initial: 0,
                };
                self.cycle(&job)?.check_steps(self.disc.steps_per_cycle())?;
            }
        }
        Ok(())
    }

    /// The contact at `A` for each initial path (in parallel), or the
    /// outcome of a transient that already ended in gross slip or separation.
    /// The `optimal` path has no phase-free start; it gets an error here.
    /// One entry per [`SweepSpec::initials`], in that order.
    pub fn prepare(&self) -> Vec<Prepared> {
        let ops = operators(&self.disc);
        self.initials
            .par_iter()
            .map(|initial| self.prepare_one(&ops, initial))
            .collect()
    }

    fn prepare_one(&self, ops: &Arc<crate::contact::Operators>, initial: &Initial) -> Prepared {
        Stepper::prepare_at_center(
            Arc::clone(ops),
            self.material,
            self.disc,
            initial,
            self.center,
            self.options,
        )
    }

    /// The optimal slip at `A` for `phase`: one linear programme.
    fn optimal_one(&self, ops: &Arc<crate::contact::Operators>, phase: f64) -> OptimalStart {
        let cycle = self.cycle(&Job {
            index: 0,
            load_factor: 0.0,
            phase,
            initial: 0,
        })?;
        let mut contact = Contact::new(self.material, Arc::clone(ops));
        if let Initial::Slip { slip, .. } = optimal_initial(&self.material, &cycle, &self.disc)? {
            contact.set_slip(&slip);
        }
        contact.set_load_elastic(self.center);
        Ok(contact)
    }

    /// Run the whole sweep in one call and give its rows in job order.
    /// `observer` sees each row as its run finishes (from any thread);
    /// once `cancel` is set, runs not yet started are skipped.
    pub fn run_all(
        &self,
        observer: Option<&(dyn Fn(&Row) + Sync)>,
        cancel: Option<&AtomicBool>,
    ) -> Vec<Row> {
        let never = AtomicBool::new(false);
        self.run(
            &self.jobs(),
            observer.unwrap_or(&|_| {}),
            cancel.unwrap_or(&never),
        )
    }

    /// Run `jobs` (a subset of [`SweepSpec::jobs`]) in parallel. `done` is
    /// called once per finished run, from any thread. When `cancel` is set,
    /// runs not yet started are skipped: the result then holds only the runs
    /// that finished, still in job order. The runs of one `(lambda, phi)`
    /// go one after another on one thread ([`groups`]).
    pub fn run(&self, jobs: &[Job], done: &(dyn Fn(&Row) + Sync), cancel: &AtomicBool) -> Vec<Row> {
        let starts = Starts::new(self, jobs);
        let mut rows: Vec<Row> = groups(jobs)
            .into_par_iter()
            .flat_map_iter(|group| {
                let halt = || cancel.load(Ordering::Relaxed);
                self.run_group(&jobs[group], &starts, &halt, &|| false, done)
            })
            .collect();
        rows.sort_by_key(|r| r.job.index);
        rows
    }

    /// Run `jobs` and hand each row to `deliver` in job order, as soon as
    /// it and all the rows before it are done (see
    /// [`crate::analysis::ordered::run_ordered`]). So an output written row by row is
    /// always the start of the complete output. `interrupt` stops the
    /// sweep: draining finishes the runs in progress, aborting drops them
    /// at their next increment. Only the transients (and optimal slips) the
    /// jobs need are computed, each once. The runs of one `(lambda, phi)`
    /// go one after another on one worker ([`groups`]).
    pub fn run_ordered<E>(
        &self,
        jobs: &[Job],
        interrupt: &Interrupt,
        deliver: impl FnMut(Row) -> Result<(), E>,
    ) -> Result<Progress, E> {
        self.resume_ordered(jobs, 0, interrupt, deliver)
    }

    /// [`SweepSpec::run_ordered`] for a list whose first `written` rows
    /// are already written: the rows from `written` on are delivered. The
    /// runs of the group that row `written` falls in are all made again
    /// (the rows before it are not delivered), so that each row comes out
    /// with the very bytes an uninterrupted sweep gives it.
    pub fn resume_ordered<E>(
        &self,
        jobs: &[Job],
        written: usize,
        interrupt: &Interrupt,
        mut deliver: impl FnMut(Row) -> Result<(), E>,
    ) -> Result<Progress, E> {
        let written = written.min(jobs.len());
        let groups: Vec<_> = groups(jobs)
            .into_iter()
            .filter(|g| g.end > written)
            .collect();
        let starts = Starts::new(self, &jobs[groups.first().map_or(written, |g| g.start)..]);
        let mut delivered = written;
        let mut short = false;
        run_ordered(
            &groups,
            interrupt,
            |group, abort: Abort<'_>| {
                if abort.requested() {
                    return None;
                }
                let (draining, aborted) = (|| abort.draining(), || abort.requested());
                let group = &jobs[group.clone()];
                let rows = self.run_group(group, &starts, &draining, &aborted, &|_| {});
                // A group cut short by an abort is a gap; one cut short by
                // a drain is delivered up to its last finished run.
                (!abort.requested()).then_some(rows)
            },
            |g, rows| {
                if short {
                    return Ok(());
                }
                short = rows.len() < groups[g].len();
                // Positions in `jobs` of the rows, the ones already
                // written left out.
                for (at, row) in (groups[g].start..).zip(rows) {
                    if at >= written {
                        deliver(row)?;
                        delivered += 1;
                    }
                }
                Ok(())
            },
        )?;
        Ok(Progress {
            delivered,
            total: jobs.len(),
        })
    }

    /// The runs of one group in order, each starting with the slip rates
    /// the runs before it cached (see [`groups`]); stops before a run when
    /// `halt` says so, and within one when `stop` does. `done` sees each
    /// row as its run finishes.
    fn run_group(
        &self,
        group: &[Job],
        starts: &Starts,
        halt: &dyn Fn() -> bool,
        stop: &dyn Fn() -> bool,
        done: &(dyn Fn(&Row) + Sync),
    ) -> Vec<Row> {
        let mut carry = Carry::default();
        let mut rows = Vec::with_capacity(group.len());
        for job in group {
            if halt() {
                break;
            }
            match self.run_job(job, starts, stop, &mut carry) {
                Some(row) => {
                    done(&row);
                    rows.push(row);
                }
                None => break,
            }
        }
        rows
    }

    /// One run; `None` when `stop` asked it to give up.
    fn run_job(
        &self,
        job: &Job,
        starts: &Starts,
        stop: &dyn Fn() -> bool,
        carry: &mut Carry,
    ) -> Option<Row> {
        let initial = self.initials[job.initial].name();
        let outcome = match starts.get(self, job) {
            Err(e) => Err(e),
            Ok(Err(outcome)) => Ok(*outcome),
            Ok(Ok(contact)) => match self.cycle(job) {
                Err(e) => Err(RunError::Param(e)),
                Ok(cycle) => {
                    let mut contact = contact.clone();
                    if let Some(cache) = carry.cache.take() {
                        contact.give_response_cache(cache);
                    }
                    let mut s = Stepper::from_center(contact, cycle, self.disc, self.options);
                    if let Some(setup) = carry.safe_state.take() {
                        s.give_safe_state_setup(setup);
                    }
                    // The observer below reads no events.
                    s.set_zone_events(false);
                    s.set_straight_runs(true);
                    s.set_event_reports(false);
                    let mut look = Look {
                        stop,
                        meets: &carry.meets,
                        trace: Trace::default(),
                        met: None,
                        seek: true,
                    };
                    look.trace.note(&s);
                    let mut replayed = None;
                    let outcome = loop {
                        match drive(&mut s, Goal::Steady, &mut look) {
                            Ok(Driven::Stopped) => match look.met.take() {
                                // A run met: its cycles from here on are
                                // this run's, unless they end before a
                                // verdict (then step on, meeting no more).
                                Some(meeting) => {
                                    look.seek = false;
                                    if let Some(run) = carry.meets.replay(meeting, &s) {
                                        if let Some(&outcome) = run.outcome() {
                                            replayed = Some(run);
                                            break Ok(outcome);
                                        }
                                    }
                                }
                                None => return None,
                            },
                            Ok(Driven::Finished(outcome)) => break Ok(outcome),
                            // Not a goal of this drive.
                            Ok(Driven::Reached) => {}
                            Err(e) => break Err(RunError::Step(e)),
                        }
                    };
                    let trace = std::mem::take(&mut look.trace);
                    carry.cache = s.contact_mut().take_response_cache();
                    carry.safe_state = match &mut replayed {
                        Some(run) => run.take_safe_state_setup(),
                        None => None,
                    }
                    .or_else(|| s.take_safe_state_setup());
                    // A run that took another's cycles adds nothing a later
                    // run could not meet in that one.
                    if replayed.is_none() {
                        carry.meets.keep(trace.finish(&s));
                    }
                    outcome
                }
            },
        };
        Some(Row {
            job: *job,
            initial,
            outcome,
        })
    }
}

/// What a run of a group hands the next ([`SweepSpec::run_group`]): the
/// slip rates it cached, the setup of its search for a safe state (the
/// elastic margins over the cycle and the cone programme's basis), and
/// the traces of the runs so far, for a later run that meets one of them
/// ([`crate::analysis::meet`]).
#[derive(Default)]
struct Carry {
    cache: Option<ResponseCache>,
    safe_state: Option<Arc<crate::stepping::safe_state::Setup>>,
    meets: Meets,
}

/// The observer of a sweep's run: stops it when `stop` says so, or at the
/// start of a cycle in which it meets an earlier run of its group
/// (`met`), and notes its state at the start of each cycle.
struct Look<'a> {
    stop: &'a dyn Fn() -> bool,
    meets: &'a Meets,
    trace: Trace,
    met: Option<Meeting>,
    seek: bool,
}

impl Observer for Look<'_> {
    fn observe(&mut self, stepper: &Stepper, _: &StepReport) -> Control {
        if (self.stop)() {
            return Control::Stop;
        }
        self.trace.note(stepper);
        if self.seek && stepper.outcome().is_none() {
            self.met = self.meets.find(stepper);
            if self.met.is_some() {
                return Control::Stop;
            }
        }
        Control::Continue
    }
}

/// The groups of `jobs`: the runs of one `(lambda, phi)`, consecutive in
/// job order, as ranges of positions in `jobs`.
///
/// A group's runs go one after another on one thread, and each starts
/// with the slip rates the runs before it cached: they meet the same load
/// cycle, so many of the slip sets one run solves for, the next meets
/// again (in the Fig. 3 map, more than half of the sets a run solves for
/// were met by an earlier run of its group), and a set met again costs a
/// lookup instead of a solve. A hit gives the numbers of an earlier solve
/// of the same set, which differ from those of a new solve by round-off
/// only. So a row's numbers depend on its parameters and, to round-off,
/// on the runs before it in its group: the same command gives the same
/// bytes whatever the thread count, and shards ([`crate::io::batch::Shard`])
/// and resumed sweeps keep groups whole so that they give them too.
pub fn groups(jobs: &[Job]) -> Vec<std::ops::Range<usize>> {
    let mut out: Vec<std::ops::Range<usize>> = Vec::new();
    for (i, job) in jobs.iter().enumerate() {
        match out.last_mut() {
            Some(g) if same_group(&jobs[g.start], job) => g.end = i + 1,
            _ => out.push(i..i + 1),
        }
    }
    out
}

/// Do two jobs belong to one group (the same `lambda` and `phi`)?
fn same_group(a: &Job, b: &Job) -> bool {
    a.load_factor.to_bits() == b.load_factor.to_bits() && a.phase.to_bits() == b.phase.to_bits()
}

/// Where runs start, computed on first use by whichever run needs it: the
/// contact at `A` per initial path (shared by every `lambda` and `phi`), and
/// for the `optimal` path the optimal slip per phase.
struct Starts {
    ops: OnceLock<Arc<crate::contact::Operators>>,
    shared: Vec<OnceLock<Prepared>>,
    /// One cell per distinct phase (by its bits) among the optimal jobs.
    optimal: Vec<(u64, OnceLock<OptimalStart>)>,
}

impl Starts {
    fn new(spec: &SweepSpec, jobs: &[Job]) -> Self {
        let mut phases: Vec<u64> = jobs
            .iter()
            .filter(|j| matches!(spec.initials[j.initial], Initial::Optimal))
            .map(|j| j.phase.to_bits())
            .collect();
        phases.sort_unstable();
        phases.dedup();
        Self {
            ops: OnceLock::new(),
            shared: spec.initials.iter().map(|_| OnceLock::new()).collect(),
            optimal: phases.into_iter().map(|p| (p, OnceLock::new())).collect(),
        }
    }

    fn get<'a>(
        &'a self,
        spec: &SweepSpec,
        job: &Job,
    ) -> Result<Result<&'a Contact, &'a Outcome>, RunError> {
        let ops = self.ops.get_or_init(|| operators(&spec.disc));
        match &spec.initials[job.initial] {
            Initial::Optimal => {
                let cell = &self
                    .optimal
                    .iter()
                    .find(|(bits, _)| *bits == job.phase.to_bits())
                    .expect("Starts::new saw every optimal job's phase")
                    .1;
                match cell.get_or_init(|| spec.optimal_one(ops, job.phase)) {
                    Ok(contact) => Ok(Ok(contact)),
                    Err(e) => Err(RunError::Optimal {
                        phase: job.phase,
                        source: e.clone(),
                    }),
                }
            }
            initial => {
                match self.shared[job.initial].get_or_init(|| spec.prepare_one(ops, initial)) {
                    Err(e) => Err(RunError::Step(e.clone())),
                    Ok(AtCenter::Ended(outcome)) => Ok(Err(outcome)),
                    Ok(AtCenter::Ready(contact)) => Ok(Ok(contact)),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
