//! Path design: a transient `O -> P1 -> ... -> PK -> A` that makes the steady
//! cycle at a given `lambda` shake down (model.md section 10, the paper's open
//! question of its section 3).
//!
//! Every candidate is run by the real engine ([`Stepper`]) to its verdict;
//! nothing is modelled. The search is argmin's particle swarm over the
//! parameters of a path family ([`Family`]), inside the region where a
//! transient can neither slide grossly nor separate ([`Region`]). Candidates
//! of one swarm generation are evaluated in parallel (argmin's `rayon`
//! feature keeps their order), and every random draw comes from one
//! generator seeded by the user, so a search is deterministic for a given
//! seed whatever the thread count.
//!
//! The objective of a candidate at `lambda` ([`cost`]): `-1` when it shakes
//! down (the search then stops), else the `W` of its steady cycle (the last
//! cycle's when the run did not converge), and `GROSS_COST` when the run
//! ended in gross slip or separation. Only comparisons of costs steer a
//! particle swarm, so no scaling of `W` is needed.
//!
//! The frontier ([`frontier`]) is a bisection in `lambda` between a load
//! factor at which a known path shakes down and `lambda_2`, above which no
//! locked-in slip can shake down (model.md section 7.3): a search that finds
//! a shakedown path at the midpoint raises the lower end to the largest
//! `lambda` at which that very path still shakes down ([`path_limit`]); a
//! search that finds none lowers the upper end. The lower end is therefore
//! always a `lambda` at which a named path has been run to shakedown; the
//! upper end is only where this search stopped finding one.

use std::f64::consts::PI;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::particleswarm::{Particle, ParticleSwarm};
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::Serialize;

use crate::analysis::case::Case;
use crate::analysis::limit::{shakedown_limit, LimitError};
use crate::analysis::ordered::Interrupt;
use crate::contact::Operators;
use crate::model::path::{Initial, PathError};
use crate::model::{Cycle, LoadPoint, Material, ParamError};
use crate::stepping::steady::SteadyState;
use crate::stepping::{operators, Outcome, StepError, Stepper};

/// The cost of a candidate whose run ended in gross slip or separation.
pub const GROSS_COST: f64 = 1e3;

/// The cost of a candidate that shakes down (any `W` is above it).
pub const SHAKEDOWN_COST: f64 = -1.0;

/// How far inside the gross-slip line `|y| = 2 pi` a vertex may go: a
/// vertex on the line slides the whole interface at once.
pub const GROSS_SLIP_GAP: f64 = crate::model::ranges::GROSS_GAP.low;

/// Why a design could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// A cycle parameter is invalid (e.g. `lambda` out of range).
    #[error(transparent)]
    Param(#[from] ParamError),
    /// A path left the admissible region (a bug: paths are clamped to it).
    #[error(transparent)]
    Path(#[from] PathError),
    /// A run failed.
    #[error(transparent)]
    Step(#[from] StepError),
    /// `lambda_2` could not be computed.
    #[error(transparent)]
    Limit(#[from] LimitError),
    /// The number of vertices is outside [`crate::model::ranges::VERTICES`].
    #[error("vertices = {0} is out of range: expected {expected}", expected = crate::model::ranges::VERTICES.expected)]
    Vertices(usize),
    /// The optimiser failed (its message).
    #[error("the particle swarm failed: {0}")]
    Optimiser(String),
}

/// The admissible box of the load plane: `|x| <= x_max`, `|y| <= y_max`.
/// Below `|y| = 2 pi` the interface cannot slide as a whole, and below the
/// separation bound on `|x|` it cannot separate without locked-in slip
/// (model.md section 2.3, [`Initial::custom_for`]). The box is convex, so
/// the straight segments between its points stay in it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Region {
    x_max: f64,
    y_max: f64,
}

impl Region {
    /// The box for `material`: `|y| <= 2 pi - GROSS_SLIP_GAP`, and `|x|` at
    /// most 99.9 % of the separation bound `2 pi chi / (f beta)` (12.21 for
    /// the paper's material).
    pub fn for_material(material: &Material) -> Self {
        Self::box_for(material, GROSS_SLIP_GAP)
    }

    /// The box with `|y| <= 2 pi - gap`: a wider `gap` keeps the vertices
    /// further inside the gross-slip line. The frontier's dependence on
    /// `gap` shows how much the gross-slip line limits what a transient can
    /// lock in (model.md section 10).
    ///
    /// # Errors
    ///
    /// [`ParamError`] unless `gap` is in [`crate::model::ranges::GROSS_GAP`].
    pub fn with_gross_gap(material: &Material, gap: f64) -> Result<Self, ParamError> {
        Ok(Self::box_for(
            material,
            crate::model::ranges::GROSS_GAP.check(gap)?,
        ))
    }

    fn box_for(material: &Material, gap: f64) -> Self {
        let separation = 2.0 * PI * material.chi() / (material.friction() * material.beta());
        Self {
            x_max: 0.999 * separation,
            y_max: 2.0 * PI - gap,
        }
    }

    /// Largest `|x|` of a vertex.
    pub fn x_max(&self) -> f64 {
        self.x_max
    }
    /// Largest `|y|` of a vertex.
    pub fn y_max(&self) -> f64 {
        self.y_max
    }

    /// Whether `p` lies in the box.
    pub fn contains(&self, p: LoadPoint) -> bool {
        p.x().abs() <= self.x_max && p.y().abs() <= self.y_max
    }

    fn clamp(&self, x: f64, y: f64) -> LoadPoint {
        LoadPoint::new(
            x.clamp(-self.x_max, self.x_max),
            y.clamp(-self.y_max, self.y_max),
        )
    }
}

/// A family of transients `O -> P1 -> ... -> PK -> A`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// `K` free vertices: `2K` parameters, the coordinates.
    Free,
    /// Alternating loads of decreasing amplitude about `A` (Barber 2018): `P1`
    /// free, then `Pk = A + rho^(k-1) R((k-1) alpha) (P1 - A)` with the
    /// decay `rho` in `[0, 1]` and the turn `alpha` in `[-pi, pi]` (`pi`: a
    /// zig-zag through `A`, otherwise a spiral). Four parameters whatever
    /// `K`.
    Decaying,
}

impl Family {
    /// The name used in tables: `free` or `decaying`.
    pub fn as_str(self) -> &'static str {
        match self {
            Family::Free => "free",
            Family::Decaying => "decaying",
        }
    }
}

/// A family with its number of vertices, on a region round a centre: the map
/// from parameters to paths.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Shape {
    family: Family,
    vertices: usize,
    region: Region,
    center: LoadPoint,
}

impl Shape {
    /// The family `family` with `vertices` vertices, on `region` round the
    /// centre `center`.
    ///
    /// # Errors
    ///
    /// [`DesignError::Vertices`] unless `vertices` is in
    /// [`crate::model::ranges::VERTICES`].
    pub fn new(
        family: Family,
        vertices: usize,
        region: Region,
        center: LoadPoint,
    ) -> Result<Self, DesignError> {
        if !crate::model::ranges::VERTICES.contains(vertices) {
            return Err(DesignError::Vertices(vertices));
        }
        Ok(Self {
            family,
            vertices,
            region,
            center,
        })
    }

    /// The family.
    pub fn family(&self) -> Family {
        self.family
    }
    /// `K`, the vertices between `O` and `A`.
    pub fn vertices(&self) -> usize {
        self.vertices
    }
    /// The admissible box.
    pub fn region(&self) -> Region {
        self.region
    }
    /// The cycle centre `A`.
    pub fn center(&self) -> LoadPoint {
        self.center
    }

    /// The number of parameters.
    pub fn dimension(&self) -> usize {
        match self.family {
            Family::Free => 2 * self.vertices,
            Family::Decaying => 4,
        }
    }

    /// The parameter box `(lower, upper)`.
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let (x, y) = (self.region.x_max, self.region.y_max);
        match self.family {
            Family::Free => ([-x, -y].repeat(self.vertices), [x, y].repeat(self.vertices)),
            Family::Decaying => (vec![-x, -y, 0.0, -PI], vec![x, y, 1.0, PI]),
        }
    }

    /// The vertices `P1 ... PK` of the parameters, each clamped to the
    /// region (so that every path this returns is admissible).
    pub fn path(&self, params: &[f64]) -> Vec<LoadPoint> {
        match self.family {
            Family::Free => params
                .chunks_exact(2)
                .map(|c| self.region.clamp(c[0], c[1]))
                .collect(),
            Family::Decaying => {
                let first = self.region.clamp(params[0], params[1]);
                let (rho, alpha) = (params[2].clamp(0.0, 1.0), params[3]);
                let (a, d) = (
                    self.center,
                    (first.x() - self.center.x(), first.y() - self.center.y()),
                );
                (0..self.vertices)
                    .map(|k| {
                        // P1 itself, not A + (P1 - A) with its rounding.
                        if k == 0 {
                            return first;
                        }
                        let (s, c) = (k as f64 * alpha).sin_cos();
                        let scale = rho.powi(k as i32);
                        self.region.clamp(
                            a.x() + scale * (c * d.0 - s * d.1),
                            a.y() + scale * (s * d.0 + c * d.1),
                        )
                    })
                    .collect()
            }
        }
    }

    /// Parameters of this shape whose path starts `O -> I -> ...` with the
    /// single turning point `I` and then stays at `A` (free: the other
    /// vertices at `A`; decaying: no amplitude after `I`). A path of
    /// [`Initial::Via`] thus becomes a member of every family.
    pub fn through(&self, turning: LoadPoint) -> Vec<f64> {
        match self.family {
            Family::Free => {
                let mut p = vec![turning.x(), turning.y()];
                for _ in 1..self.vertices {
                    p.extend([self.center.x(), self.center.y()]);
                }
                p
            }
            Family::Decaying => vec![turning.x(), turning.y(), 0.0, PI],
        }
    }

    /// The free-family parameters of `path` padded to this shape's `K` by
    /// vertices at `A` (`None` for the decaying family or a longer path).
    pub fn padded(&self, path: &[LoadPoint]) -> Option<Vec<f64>> {
        if self.family != Family::Free || path.len() > self.vertices {
            return None;
        }
        let mut p: Vec<f64> = path.iter().flat_map(|v| [v.x(), v.y()]).collect();
        for _ in path.len()..self.vertices {
            p.extend([self.center.x(), self.center.y()]);
        }
        Some(p)
    }
}

/// The `--initial-path` text of a path: `x,y` per vertex joined by `;`, each
/// number in Rust's shortest form that reads back to the same `f64`.
pub fn initial_path_text(path: &[LoadPoint]) -> String {
    path.iter()
        .map(|p| format!("{},{}", p.x(), p.y()))
        .collect::<Vec<_>>()
        .join(";")
}

/// The cost of a run's verdict (module documentation).
pub fn cost(summary: &Outcome) -> f64 {
    match summary.state() {
        SteadyState::Shakedown => SHAKEDOWN_COST,
        SteadyState::GrossSlip | SteadyState::Separation => GROSS_COST,
        _ if summary.dissipation.is_finite() => summary.dissipation.max(0.0),
        _ => GROSS_COST,
    }
}

/// One case at varying `lambda` and transient: everything a run needs but
/// those two, with the operators built once.
#[derive(Clone)]
pub struct Runner {
    case: Case,
    ops: Arc<Operators>,
}

impl Runner {
    /// Runs of `case` (its `lambda` and initial path are replaced per run).
    pub fn new(case: &Case) -> Self {
        Self {
            case: case.clone(),
            ops: operators(&case.disc()),
        }
    }

    /// The case this runner was made from.
    pub fn case(&self) -> &Case {
        &self.case
    }

    /// The cycle at `lambda` (the case's centre, slope and phase).
    ///
    /// # Errors
    ///
    /// [`DesignError::Param`] for a `lambda` outside `0..=1000`.
    pub fn cycle(&self, lambda: f64) -> Result<Cycle, DesignError> {
        let c = &self.case.cycle();
        Ok(Cycle::new(c.center(), lambda, c.slope(), c.phase())?)
    }

    /// Run `initial` at `lambda` to its verdict.
    ///
    /// # Errors
    ///
    /// [`DesignError::Param`] for a bad `lambda`, [`DesignError::Step`] when
    /// the run fails.
    pub fn run(&self, initial: &Initial, lambda: f64) -> Result<Outcome, DesignError> {
        let cycle = self.cycle(lambda)?;
        let c = &self.case;
        let mut s = Stepper::with_operators(
            Arc::clone(&self.ops),
            c.material(),
            c.disc(),
            initial,
            cycle,
            c.options(),
        );
        Ok(s.run_to_steady()?)
    }

    /// Run the transient through `path` at `lambda`.
    ///
    /// # Errors
    ///
    /// As [`Runner::run`], and [`DesignError::Path`] for a path outside the
    /// admissible region.
    pub fn run_path(&self, path: &[LoadPoint], lambda: f64) -> Result<Outcome, DesignError> {
        let initial = Initial::custom_for(path.to_vec(), &self.case.material())?;
        self.run(&initial, lambda)
    }
}

/// The largest `lambda` in `[lo, hi]`, to within `tol`, at which `initial`
/// shakes down, by bisection, given that it shakes down at `lo` (checked:
/// `None` when it does not). Shakedown is taken to hold below a `lambda` at
/// which it holds; the value returned is one at which a run shook down.
///
/// # Errors
///
/// As [`Runner::run`].
pub fn path_limit(
    runner: &Runner,
    initial: &Initial,
    lo: f64,
    hi: f64,
    tol: f64,
) -> Result<Option<f64>, DesignError> {
    if runner.run(initial, lo)?.state() != SteadyState::Shakedown {
        return Ok(None);
    }
    let (mut lo, mut hi) = (lo, hi);
    while hi - lo > tol {
        let mid = 0.5 * (lo + hi);
        if runner.run(initial, mid)?.state() == SteadyState::Shakedown {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(Some(lo))
}

/// The budget and seed of one search, checked by [`Budget::new`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Budget {
    particles: usize,
    iterations: u64,
    seed: u64,
}

impl Budget {
    /// `particles` in the swarm, `iterations` generations after the first,
    /// and the `seed` of every random draw.
    ///
    /// # Errors
    ///
    /// [`ParamError::BadCount`] unless `particles` is in
    /// [`crate::model::ranges::PARTICLES`] and `iterations` in
    /// [`crate::model::ranges::ITERATIONS`].
    pub fn new(particles: usize, iterations: u64, seed: u64) -> Result<Self, ParamError> {
        use crate::model::ranges::{ITERATIONS, PARTICLES};
        let iterations = usize::try_from(iterations).unwrap_or(usize::MAX);
        Ok(Self {
            particles: PARTICLES.check(particles)?,
            iterations: ITERATIONS.check(iterations)? as u64,
            seed,
        })
    }
    /// Particles in the swarm.
    pub fn particles(&self) -> usize {
        self.particles
    }
    /// Swarm generations after the first.
    pub fn iterations(&self) -> u64 {
        self.iterations
    }
    /// The seed of every random draw.
    pub fn seed(&self) -> u64 {
        self.seed
    }
    /// The same budget with another seed.
    pub fn with_seed(self, seed: u64) -> Self {
        Self { seed, ..self }
    }
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            particles: 24,
            iterations: 20,
            seed: 1,
        }
    }
}

/// The best candidate of a search: its path, its verdict at the search's
/// `lambda`, and its cost.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The parameters in the search's family.
    pub params: Vec<f64>,
    /// The vertices `P1 ... PK`.
    pub path: Vec<LoadPoint>,
    /// The run's verdict at the search's `lambda`.
    pub summary: Outcome,
    /// [`cost`] of the summary.
    pub cost: f64,
}

impl Candidate {
    /// Whether the candidate shakes down.
    pub fn shakes_down(&self) -> bool {
        self.summary.state() == SteadyState::Shakedown
    }
}

/// What a search ended with.
#[derive(Debug, Clone)]
pub struct Found {
    /// The best candidate (`None` only when stopped before any run).
    pub best: Option<Candidate>,
    /// Candidates run.
    pub evaluations: usize,
    /// Whether Ctrl-C (or the caller) stopped the search.
    pub interrupted: bool,
}

/// What a search reports after each run: runs so far and the best cost.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// The `lambda` searched at.
    pub lambda: f64,
    /// Candidates run so far in this search.
    pub evaluations: usize,
    /// The largest number of candidates this search may run.
    pub budget: usize,
    /// The best cost so far.
    pub best_cost: f64,
    /// For a frontier: the highest `lambda` at which a found path shook
    /// down so far.
    pub best_lambda: Option<f64>,
}

struct Objective<'a> {
    runner: &'a Runner,
    shape: Shape,
    lambda: f64,
    stop: &'a Interrupt,
    best: Mutex<Option<Candidate>>,
    evaluations: AtomicUsize,
    budget: usize,
    report: &'a (dyn Fn(Progress) + Sync),
}

/// `a` before `b`: lower cost, then (ties, e.g. two shakedowns) the
/// parameters in lexicographic order, so the best does not depend on the
/// order in which parallel runs finish.
fn better(a: &Candidate, b: &Candidate) -> bool {
    let params = || {
        a.params
            .iter()
            .zip(&b.params)
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    };
    a.cost.total_cmp(&b.cost).then_with(params).is_lt()
}

impl Objective<'_> {
    fn evaluate(&self, params: &[f64]) -> Result<f64, DesignError> {
        // Once stopped, no new run starts; the swarm finishes its generation
        // at once on costs that never beat the best.
        if self.stop.is_draining() {
            return Ok(f64::INFINITY);
        }
        let path = self.shape.path(params);
        let summary = self.runner.run_path(&path, self.lambda)?;
        let c = Candidate {
            params: params.to_vec(),
            path,
            cost: cost(&summary),
            summary,
        };
        let value = c.cost;
        let best_cost = {
            let mut best = self.best.lock().unwrap_or_else(|e| e.into_inner());
            if best.as_ref().is_none_or(|b| better(&c, b)) {
                *best = Some(c);
            }
            best.as_ref().map_or(f64::INFINITY, |b| b.cost)
        };
        let evaluations = self.evaluations.fetch_add(1, Ordering::SeqCst) + 1;
        (self.report)(Progress {
            lambda: self.lambda,
            evaluations,
            budget: self.budget,
            best_cost,
            best_lambda: None,
        });
        Ok(value)
    }
}

/// The objective as argmin sees it (the search keeps the objective itself,
/// with the best run it recorded).
struct Borrowed<'a, 'b>(&'a Objective<'b>);

impl CostFunction for Borrowed<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, params: &Vec<f64>) -> Result<f64, ArgminError> {
        self.0.evaluate(params).map_err(ArgminError::new)
    }
}

/// Search `shape` at `lambda` for a transient that shakes down, else the
/// least `W`. The first generation holds `warm` (parameters of this shape,
/// e.g. the best path found at a lower `lambda`), then each of the paper's
/// 24 turning points ([`Shape::through`]) while there is room, then random
/// points of the box; it stops at the first shakedown, after
/// `budget.iterations` further generations, or when `stop` drains.
///
/// # Errors
///
/// [`DesignError::Step`] when a run fails, [`DesignError::Optimiser`] when
/// the swarm does.
pub fn search(
    runner: &Runner,
    shape: Shape,
    lambda: f64,
    budget: Budget,
    warm: &[Vec<f64>],
    stop: &Interrupt,
    report: &(dyn Fn(Progress) + Sync),
) -> Result<Found, DesignError> {
    runner.cycle(lambda)?;
    let particles = budget.particles.max(2);
    let (lower, upper) = shape.bounds();
    let mut rng = rand::rngs::StdRng::seed_from_u64(budget.seed);
    let mut positions: Vec<Vec<f64>> = warm
        .iter()
        .filter(|p| p.len() == shape.dimension())
        .take(particles)
        .cloned()
        .collect();
    for i in Initial::paper_set().iter().skip(1) {
        if positions.len() >= particles {
            break;
        }
        positions.push(shape.through(i.waypoints_to(shape.center)[1]));
    }
    while positions.len() < particles {
        positions.push(
            lower
                .iter()
                .zip(&upper)
                .map(|(l, u)| rng.random_range(*l..=*u))
                .collect(),
        );
    }
    // Velocities of a quarter of the box at most: argmin's own start (the
    // whole box) throws most particles onto its edges at the first move.
    let velocities: Vec<Vec<f64>> = (0..particles)
        .map(|_| {
            lower
                .iter()
                .zip(&upper)
                .map(|(l, u)| 0.25 * (u - l) * rng.random_range(-1.0..=1.0))
                .collect()
        })
        .collect();
    let objective = Objective {
        runner,
        shape,
        lambda,
        stop,
        best: Mutex::new(None),
        evaluations: AtomicUsize::new(0),
        budget: particles * (budget.iterations as usize + 1),
        report,
    };
    // The first generation, run here so that the warm starts are in it.
    let costs: Vec<f64> = positions
        .par_iter()
        .map(|p| objective.evaluate(p))
        .collect::<Result<_, _>>()?;
    let done = |o: &Objective| {
        o.best
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .is_some_and(Candidate::shakes_down)
    };
    if !done(&objective) && !stop.is_draining() && budget.iterations > 0 {
        let population: Vec<Particle<Vec<f64>, f64>> = positions
            .into_iter()
            .zip(velocities)
            .zip(costs)
            .map(|((p, v), c)| Particle::new(p, c, v))
            .collect();
        let solver = ParticleSwarm::new((lower, upper), particles).with_rng_generator(
            rand::rngs::StdRng::seed_from_u64(budget.seed.wrapping_add(0x9e37_79b9_7f4a_7c15)),
        );
        let result = Executor::new(Borrowed(&objective), solver)
            .configure(|s| {
                s.population(population)
                    .max_iters(budget.iterations)
                    .target_cost(0.5 * SHAKEDOWN_COST)
            })
            .run();
        if let Err(e) = result {
            return Err(match e.downcast::<DesignError>() {
                Ok(d) => d,
                Err(e) => DesignError::Optimiser(e.to_string()),
            });
        }
    }
    let best = objective
        .best
        .into_inner()
        .unwrap_or_else(|e| e.into_inner());
    Ok(Found {
        best,
        evaluations: objective.evaluations.into_inner(),
        interrupted: stop.is_draining(),
    })
}

/// One row of the frontier: the highest `lambda` at which a path this
/// search found shakes down, for one family and `K`.
#[derive(Debug, Clone, Serialize)]
pub struct FrontierRow {
    /// The family.
    pub family: Family,
    /// `K`.
    pub vertices: usize,
    /// The highest `lambda` at which the path below shook down.
    pub lambda: f64,
    /// The lowest `lambda` at which the search found no shakedown path
    /// (`lambda_2` if it always found one).
    pub not_found_above: f64,
    /// The path (vertices `P1 ... PK`).
    pub path: Vec<LoadPoint>,
    /// Candidates run for this row.
    pub evaluations: usize,
}

/// The reference load factors beside the frontier.
#[derive(Debug, Clone, Serialize)]
pub struct References {
    /// The least over the paper's 25 transients of the largest `lambda` at
    /// which each shakes down (to the bisection's tolerance).
    pub lambda_1: f64,
    /// The greatest of the same (the best of the 25).
    pub best_of_25: f64,
    /// The name of that transient.
    pub best_name: String,
    /// Its turning point (the cycle centre for `OA`).
    pub best_turning: LoadPoint,
    /// `lambda_2` of the linear programme (exact for `phi = 0`, an upper
    /// bound otherwise).
    pub lambda_2: f64,
}

/// The bisection tolerance of the references and the frontier's paths.
pub const LAMBDA_TOL: f64 = 5e-4;

/// `lambda_1`, the best of the 25 and `lambda_2` for the runner's case.
///
/// # Errors
///
/// [`DesignError::Limit`] when the linear programme fails, else as
/// [`Runner::run`].
pub fn references(runner: &Runner) -> Result<References, DesignError> {
    let c = runner.case();
    let limit = shakedown_limit(
        &c.material(),
        c.cycle().center(),
        c.cycle().slope(),
        c.cycle().phase(),
        &c.disc(),
        crate::analysis::limit::DEFAULT_SAMPLES,
    )?;
    let lambda_2 = limit.load_factor;
    let set = Initial::paper_set();
    let limits: Vec<f64> = set
        .par_iter()
        .map(|i| {
            path_limit(runner, i, 0.5 * lambda_2, lambda_2, LAMBDA_TOL)
                .map(|l| l.unwrap_or(0.5 * lambda_2))
        })
        .collect::<Result<_, _>>()?;
    let (mut lambda_1, mut best, mut best_index) = (f64::INFINITY, f64::NEG_INFINITY, 0);
    for (k, &l) in limits.iter().enumerate() {
        lambda_1 = lambda_1.min(l);
        if l > best {
            (best, best_index) = (l, k);
        }
    }
    Ok(References {
        lambda_1,
        best_of_25: best,
        best_name: set[best_index].name(),
        best_turning: set[best_index].waypoints_to(c.cycle().center())[1],
        lambda_2,
    })
}

/// The frontier of `shape`'s family for `K = 1 ..= shape.vertices`
/// (module documentation). `start` is a path that shakes down at
/// `start_lambda` (e.g. the best of the 25); each `K` starts from the best
/// path of `K - 1`, padded, so the frontier never falls with `K`. Each
/// search at a midpoint uses `budget` with its seed advanced per search.
///
/// # Errors
///
/// As [`search`].
#[allow(clippy::too_many_arguments)]
pub fn frontier(
    runner: &Runner,
    family: Family,
    max_vertices: usize,
    refs: &References,
    region: Region,
    budget: Budget,
    stop: &Interrupt,
    report: &(dyn Fn(Progress) + Sync),
    row_done: &mut dyn FnMut(&FrontierRow),
) -> Result<Vec<FrontierRow>, DesignError> {
    let c = runner.case();
    let center = c.cycle().center();
    let mut rows = Vec::new();
    let mut lo = refs.best_of_25;
    let mut best_params: Option<Vec<f64>> = None;
    let mut best_path = vec![refs.best_turning];
    let first = if family == Family::Free { 1 } else { 2 };
    let mut seed = budget.seed;
    for k in first..=max_vertices {
        if stop.is_draining() {
            break;
        }
        let shape = Shape::new(family, k, region, center)?;
        let mut params = match (&best_params, family) {
            (Some(p), Family::Decaying) => p.clone(),
            _ => shape
                .padded(&best_path)
                .unwrap_or_else(|| shape.through(refs.best_turning)),
        };
        let mut path = shape.path(&params);
        let mut hi = refs.lambda_2;
        let mut evaluations = 0;
        while hi - lo > 4.0 * LAMBDA_TOL && !stop.is_draining() {
            let mid = 0.5 * (lo + hi);
            let best_lambda = Some(lo);
            let report = |p: Progress| report(Progress { best_lambda, ..p });
            seed = seed.wrapping_add(1);
            let found = search(
                runner,
                shape,
                mid,
                budget.with_seed(seed),
                std::slice::from_ref(&params),
                stop,
                &report,
            )?;
            evaluations += found.evaluations;
            match found.best {
                Some(b) if b.shakes_down() => {
                    let initial = Initial::custom_for(b.path.clone(), &c.material())?;
                    lo = path_limit(runner, &initial, mid, hi, LAMBDA_TOL)?.unwrap_or(mid);
                    params = b.params;
                    path = b.path;
                }
                _ if found.interrupted => break,
                _ => hi = mid,
            }
        }
        let row = FrontierRow {
            family,
            vertices: k,
            lambda: lo,
            not_found_above: hi,
            path: path.clone(),
            evaluations,
        };
        row_done(&row);
        rows.push(row);
        best_path = path;
        best_params = Some(params);
    }
    Ok(rows)
}

#[cfg(test)]
mod tests;
