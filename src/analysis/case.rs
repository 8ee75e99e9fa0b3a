//! A case: everything one run needs (material, cycle, discretisation,
//! initial path, solver options), validated. The CLI, presets and the TUI
//! all build runs through this type.
//!
//! ```
//! use shakedown::analysis::case::{Case, CaseError, CaseParams};
//! use shakedown::model::path::Initial;
//! use shakedown::model::ParamError;
//!
//! // The defaults are the paper's parameters at point B (lambda = 7, phi = 0)
//! // with the direct transient OA.
//! let case = Case::from_params(&CaseParams::default()).unwrap();
//! assert_eq!(*case.initial(), Initial::Direct);
//! assert_eq!(case.cycle().load_factor(), 7.0);
//! assert_eq!(case.disc().nodes(), 128);
//!
//! // Validation reports the first bad parameter.
//! let odd = CaseParams { nodes: 127, ..CaseParams::default() };
//! assert!(matches!(
//!     Case::from_params(&odd),
//!     Err(CaseError::Param(ParamError::BadCount { name: "nodes", .. }))
//! ));
//! // The initial path is typed: a name is parsed where it is given.
//! assert!(Initial::parse("3,3").is_err());
//! ```

use std::f64::consts::PI;

use serde::Serialize;

use crate::analysis::limit::{cycle_limit, Limit, LimitError, DEFAULT_SAMPLES};
use crate::model::path::{Initial, PathError};
use crate::model::{Cycle, Discretisation, LoadPoint, Material, ParamError, Plane, Polyline};
use crate::stepping::{Outcome, StepError, StepOptions, Stepper};

/// A case that cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CaseError {
    /// A material, cycle or discretisation parameter is invalid.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// The initial-path name does not parse.
    #[error(transparent)]
    Path(#[from] PathError),
    /// A prescribed slip ([`Initial::Slip`]) without one finite value per
    /// interface node.
    #[error(
        "initial slip '{name}' has {len} values: expected {nodes} finite values, one per node"
    )]
    Slip {
        /// The slip's name.
        name: String,
        /// The values it has (or, when it has `nodes`, the position from 1
        /// of the first that is not finite).
        len: usize,
        /// The case's interface nodes `N`.
        nodes: usize,
    },
    /// The initial path is `optimal` and the `lambda_2` linear programme
    /// that defines it failed (model.md sections 7.3 and 7.4).
    #[error("initial path 'optimal': {0}")]
    Optimal(#[from] LimitError),
}

/// The raw parameters of a case as a user gives them (all optional fields
/// default to the paper's values).
///
/// Nothing is checked here: [`Case::from_params`] validates. The loads are
/// in the load plane of Fig. 2 (model.md section 1.1) and the cycle is
/// eq. (11) (model.md section 5.1).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseParams {
    /// `lambda`, the load factor of eq. (12). Default 7 (point B).
    pub load_factor: f64,
    /// `phi`, the phase of the torque against the force, radians. Default 0.
    pub phase: f64,
    /// `psi`, the slope of the load line, eq. (13). Default `5/8`.
    pub slope: f64,
    /// The cycle centre `A = (x0, y0)` in the load plane. Default
    /// `(pi, 3 pi / 4)`.
    pub center: (f64, f64),
    /// A closed polyline of offsets `(u, v)` from the centre in place of
    /// the ellipse (`--cycle FILE`, model.md section 5.4); `phase` and
    /// `slope` are then unused. Default none: the paper's ellipse.
    pub cycle: Option<Polyline>,
    /// The friction coefficient `f`. Default 0.1.
    pub friction: f64,
    /// Poisson's ratio `nu`. Default 0.3.
    pub poisson: f64,
    /// Plane strain or plane stress. Default plane strain.
    pub plane: Plane,
    /// The initial path (model.md sections 5.2 and 7.4): [`Initial::Optimal`]
    /// is resolved by [`Case::from_params`]. Default [`Initial::Direct`]
    /// (`OA`).
    pub initial: Initial,
    /// Interface nodes `N` (even, 16 to 4096). Default 128.
    pub nodes: usize,
    /// Increments per cycle (16 to 100000). Default 400.
    pub steps: usize,
    /// Cycles run at most before the run is reported not converged
    /// ([`crate::model::ranges::MAX_CYCLES`]; model.md section 6.1).
    /// Default 2000.
    pub max_cycles: usize,
    /// Prove shakedown by a safe state before the first cycle without slip
    /// (model.md section 6.4). Default on; off, asymptotic shakedown is run
    /// out to its first cycle without slip.
    pub safe_state: bool,
}

impl Default for CaseParams {
    /// The paper's parameters with the direct path `OA`, at point B's
    /// `lambda = 7` in phase.
    fn default() -> Self {
        Self {
            load_factor: 7.0,
            phase: 0.0,
            slope: 0.625,
            center: (PI, 0.75 * PI),
            cycle: None,
            friction: 0.1,
            poisson: 0.3,
            plane: Plane::Strain,
            initial: Initial::Direct,
            nodes: 128,
            steps: 400,
            max_cycles: crate::stepping::steady::DEFAULT_MAX_CYCLES,
            safe_state: true,
        }
    }
}

/// A validated case: everything [`Case::stepper`] needs to start a run.
///
/// Its parts are read through getters and changed only through setters
/// that check what ties them together (a polyline cycle's vertex count
/// divides the increments per cycle; the initial path is resolved).
/// [`Case::initial`] never holds the unresolved [`Initial::Optimal`]: it
/// is resolved to its slip ([`Initial::Slip`]) where it is given.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    material: Material,
    cycle: Cycle,
    disc: Discretisation,
    initial: Initial,
    options: StepOptions,
}

impl Case {
    /// Validate the parameters. `optimal` as the initial path is resolved by
    /// the limit analysis (one linear programme, model.md section 7.3), so
    /// only then is this more than cheap.
    ///
    /// # Errors
    ///
    /// [`CaseError::Param`] for an invalid material ([`Material::new`]),
    /// cycle ([`Cycle::new`]), discretisation ([`Discretisation::new`]) or
    /// cycle cap (outside [`crate::model::ranges::MAX_CYCLES`]);
    /// [`CaseError::Path`] for a point `a,b` that [`Initial::parse`] refuses
    /// or a custom path that [`Initial::custom_for`] refuses;
    /// [`CaseError::Slip`] for a prescribed slip without one finite value
    /// per node; and [`CaseError::Optimal`] when the `optimal` slip cannot
    /// be computed.
    /// They are checked in that order, and the first failure is returned.
    pub fn from_params(p: &CaseParams) -> Result<Case, CaseError> {
        let material = Material::new(p.friction, p.poisson, p.plane)?;
        let center = LoadPoint::new(p.center.0, p.center.1);
        let cycle = match &p.cycle {
            None => Cycle::new(center, p.load_factor, p.slope, p.phase)?,
            Some(polyline) => Cycle::polyline(center, p.load_factor, polyline.clone())?,
        };
        let disc = Discretisation::new(p.nodes, p.steps)?;
        cycle.check_steps(p.steps)?;
        let options = StepOptions::builder()
            .max_cycles(p.max_cycles)
            .safe_state(p.safe_state)
            .build()?;
        let initial = resolve(&p.initial, &material, &cycle, &disc)?;
        Ok(Case {
            material,
            cycle,
            disc,
            initial,
            options,
        })
    }

    /// A stepper at the start of this case: at `O` before the transient, or
    /// at `A` with the locked-in slip for [`Initial::Slip`]. Each call gives
    /// a fresh, independent run.
    pub fn stepper(&self) -> Stepper {
        Stepper::new(
            self.material,
            self.disc,
            &self.initial,
            self.cycle.clone(),
            self.options,
        )
    }

    /// Friction and elastic constants.
    pub fn material(&self) -> Material {
        self.material
    }
    /// The steady cycle (`lambda`, `phi`, `psi`, centre `A`, or a polyline).
    pub fn cycle(&self) -> &Cycle {
        &self.cycle
    }
    /// Nodes and increments per cycle.
    pub fn disc(&self) -> Discretisation {
        self.disc
    }
    /// The initial path, resolved (never [`Initial::Optimal`]).
    pub fn initial(&self) -> &Initial {
        &self.initial
    }
    /// The stepper's options: the cycle cap and safe-state search of
    /// [`CaseParams`], the rest at their defaults unless
    /// [`Case::with_options`] set them.
    pub fn options(&self) -> StepOptions {
        self.options
    }

    /// Another cycle for this case (e.g. another `lambda`).
    ///
    /// # Errors
    ///
    /// [`CaseError::Param`] when a polyline cycle's vertex count does not
    /// divide the increments per cycle ([`Cycle::check_steps`]); the case
    /// is then unchanged.
    pub fn set_cycle(&mut self, cycle: Cycle) -> Result<(), CaseError> {
        cycle.check_steps(self.disc.steps_per_cycle())?;
        self.cycle = cycle;
        Ok(())
    }

    /// Another initial path for this case, checked and, for
    /// [`Initial::Optimal`], resolved as in [`Case::from_params`].
    ///
    /// # Errors
    ///
    /// [`CaseError::Path`], [`CaseError::Slip`] or [`CaseError::Optimal`]
    /// as in [`Case::from_params`]; the case is then unchanged.
    pub fn set_initial(&mut self, initial: Initial) -> Result<(), CaseError> {
        self.initial = resolve(&initial, &self.material, &self.cycle, &self.disc)?;
        Ok(())
    }

    /// This case with other stepper options (already checked by
    /// [`StepOptions::builder`]).
    pub fn with_options(self, options: StepOptions) -> Case {
        Case { options, ..self }
    }
}

/// `initial`, checked for this case (the variants of [`Initial`] can be
/// written out by hand, past [`Initial::parse`] and [`Initial::custom_for`]),
/// with [`Initial::Optimal`] computed for this material, cycle and
/// discretisation.
fn resolve(
    initial: &Initial,
    material: &Material,
    cycle: &Cycle,
    disc: &Discretisation,
) -> Result<Initial, CaseError> {
    match initial {
        Initial::Optimal => Ok(crate::analysis::limit::optimal_initial(
            material, cycle, disc,
        )?),
        Initial::Direct => Ok(Initial::Direct),
        Initial::Via { a, b } => Ok(Initial::parse(&format!("{a},{b}"))?),
        Initial::Custom(points) => Ok(Initial::custom_for(points.clone(), material)?),
        Initial::Slip { name, slip } => {
            let nodes = disc.nodes();
            let len = match slip.iter().position(|g| !g.is_finite()) {
                _ if slip.len() != nodes => slip.len(),
                Some(k) => k + 1,
                None => return Ok(initial.clone()),
            };
            Err(CaseError::Slip {
                name: name.clone(),
                len,
                nodes,
            })
        }
    }
}

impl Case {
    /// A builder with the paper's parameters ([`CaseParams::default`]):
    /// set what differs by name, then [`CaseBuilder::build`] validates.
    ///
    /// ```
    /// use std::f64::consts::PI;
    /// use shakedown::prelude::*;
    ///
    /// let case = Case::builder()
    ///     .load_factor(5.5)
    ///     .phase(PI / 2.0)
    ///     .initial(Initial::Direct)
    ///     .nodes(32)
    ///     .steps(200)
    ///     .build()?;
    /// let outcome = case.run()?;
    /// assert!(outcome.cycles > 0);
    /// assert_ne!(outcome.state(), SteadyState::NotConverged);
    /// let limit = case.limit()?;
    /// assert!(limit.load_factor.is_finite() && limit.load_factor > 0.0);
    /// assert!(Case::builder().nodes(127).build().is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn builder() -> CaseBuilder {
        CaseBuilder::default()
    }

    /// Run the case to its steady state (or the end of the run) and give
    /// its [`Outcome`].
    ///
    /// # Errors
    ///
    /// A numerical failure of an increment ([`StepError`]).
    pub fn run(&self) -> Result<Outcome, StepError> {
        self.stepper().run_to_steady()
    }

    /// The shakedown limit `lambda_2` of this case's material and cycle
    /// shape (the linear programme of model.md section 7.3; an ellipse at
    /// [`DEFAULT_SAMPLES`] instants, a polyline at its vertices, which is
    /// exact): its load factor is [`Limit::load_factor`].
    ///
    /// # Errors
    ///
    /// As [`shakedown_limit`].
    pub fn limit(&self) -> Result<Limit, LimitError> {
        cycle_limit(&self.material, &self.cycle, &self.disc, DEFAULT_SAMPLES)
    }
}

/// Named settings of a [`Case`], validated together by
/// [`CaseBuilder::build`] (in the manner of Clarabel's settings builder).
/// Unset settings are the paper's ([`CaseParams::default`]).
#[derive(Debug, Clone, Default)]
pub struct CaseBuilder {
    params: CaseParams,
}

impl CaseBuilder {
    /// `lambda`, the load factor of eq. (12).
    pub fn load_factor(mut self, load_factor: f64) -> Self {
        self.params.load_factor = load_factor;
        self
    }
    /// `phi`, the phase of the torque against the force, radians.
    pub fn phase(mut self, phase: f64) -> Self {
        self.params.phase = phase;
        self
    }
    /// `psi`, the slope of the load line, eq. (13).
    pub fn slope(mut self, slope: f64) -> Self {
        self.params.slope = slope;
        self
    }
    /// The cycle centre `A = (x0, y0)` in the load plane.
    pub fn center(mut self, x: f64, y: f64) -> Self {
        self.params.center = (x, y);
        self
    }
    /// A closed polyline cycle in place of the paper's ellipse (model.md
    /// section 5.4); `phase` and `slope` are then unused, and `steps` must
    /// be a multiple of its vertex count.
    pub fn cycle(mut self, polyline: Polyline) -> Self {
        self.params.cycle = Some(polyline);
        self
    }
    /// The friction coefficient `f`.
    pub fn friction(mut self, friction: f64) -> Self {
        self.params.friction = friction;
        self
    }
    /// Poisson's ratio `nu`.
    pub fn poisson(mut self, poisson: f64) -> Self {
        self.params.poisson = poisson;
        self
    }
    /// Plane strain or plane stress.
    pub fn plane(mut self, plane: Plane) -> Self {
        self.params.plane = plane;
        self
    }
    /// The initial path ([`Initial::Optimal`] is resolved by `build`).
    pub fn initial(mut self, initial: Initial) -> Self {
        self.params.initial = initial;
        self
    }
    /// Interface nodes `N` (even, 16 to 4096).
    pub fn nodes(mut self, nodes: usize) -> Self {
        self.params.nodes = nodes;
        self
    }
    /// Increments per cycle (16 to 100000).
    pub fn steps(mut self, steps: usize) -> Self {
        self.params.steps = steps;
        self
    }
    /// Cycles run at most before the run is reported not converged
    /// ([`crate::model::ranges::MAX_CYCLES`]).
    pub fn max_cycles(mut self, max_cycles: usize) -> Self {
        self.params.max_cycles = max_cycles;
        self
    }
    /// Prove shakedown by a safe state before the first cycle without slip
    /// (model.md section 6.4; on unless set off).
    pub fn safe_state(mut self, on: bool) -> Self {
        self.params.safe_state = on;
        self
    }

    /// The validated case.
    ///
    /// # Errors
    ///
    /// As [`Case::from_params`]: the first setting out of range, or an
    /// `optimal` initial slip that cannot be computed.
    pub fn build(self) -> Result<Case, CaseError> {
        Case::from_params(&self.params)
    }
}

/// Resolve an initial-path name: `OA`, `a,b`, or `optimal`.
///
/// `optimal` (any case) is computed for this material, cycle and
/// discretisation by [`crate::analysis::limit::optimal_initial`]: it depends
/// on the cycle's phase, not on its `lambda`. Other names go to
/// [`Initial::parse`].
///
/// # Errors
///
/// [`CaseError::Optimal`] when the `lambda_2` programme fails (e.g. no
/// slip satisfies the friction law at `A`); [`CaseError::Path`] when the
/// name does not parse.
pub fn resolve_initial(
    name: &str,
    material: &Material,
    cycle: &Cycle,
    disc: &Discretisation,
) -> Result<Initial, CaseError> {
    if name.trim().eq_ignore_ascii_case("optimal") {
        return crate::analysis::limit::optimal_initial(material, cycle, disc)
            .map_err(CaseError::Optimal);
    }
    Ok(Initial::parse(name)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> Case {
        Case::builder().nodes(16).steps(48).build().unwrap()
    }

    /// A case changes only through setters that keep what ties its parts
    /// together: a polyline's vertex count divides the increments per
    /// cycle, and the initial path is resolved.
    #[test]
    fn the_setters_keep_the_case_valid() {
        let mut case = small();
        let regular = |k: usize| {
            let v = (0..k)
                .map(|i| {
                    let t = 2.0 * PI * i as f64 / k as f64;
                    LoadPoint::new(t.cos(), t.sin())
                })
                .collect();
            Polyline::new("test", v).unwrap()
        };
        let center = case.cycle().center();
        // 48 increments: 3 vertices divide them, 5 do not.
        let good = Cycle::polyline(center, 2.0, regular(3)).unwrap();
        let bad = Cycle::polyline(center, 2.0, regular(5)).unwrap();
        let before = case.clone();
        assert!(matches!(
            case.set_cycle(bad),
            Err(CaseError::Param(ParamError::StepsPerChord { .. }))
        ));
        assert_eq!(case, before, "a refused cycle leaves the case as it was");
        case.set_cycle(good.clone()).unwrap();
        assert_eq!(*case.cycle(), good);

        let mut case = small();
        case.set_initial(Initial::Optimal).unwrap();
        assert!(
            matches!(case.initial(), Initial::Slip { name, slip } if name == "optimal" && slip.len() == 16),
            "{:?}",
            case.initial()
        );
        let via = Initial::Via { a: 7, b: -7 };
        case.set_initial(via.clone()).unwrap();
        assert_eq!(*case.initial(), via);
        // Paths written out by hand are checked as if they were parsed.
        let before = case.clone();
        let slip = |values: Vec<f64>| Initial::Slip {
            name: "hand".into(),
            slip: std::sync::Arc::new(values),
        };
        for bad in [
            Initial::Via { a: 3, b: 3 },
            Initial::Custom(vec![LoadPoint::new(0.0, 2.0 * PI)]),
            Initial::Custom(Vec::new()),
            slip(vec![0.0; 15]),
            slip(vec![f64::NAN; 16]),
        ] {
            assert!(case.set_initial(bad.clone()).is_err(), "{bad:?}");
            assert_eq!(case, before);
        }
        case.set_initial(slip(vec![0.0; 16])).unwrap();
    }

    /// The cycle cap is checked against its range, as a parameter named
    /// as the command line spells it.
    #[test]
    fn the_cycle_cap_is_checked_against_its_range() {
        let m = crate::model::ranges::MAX_CYCLES;
        for bad in [m.min - 1, m.max + 1] {
            let e = Case::builder()
                .nodes(16)
                .max_cycles(bad)
                .build()
                .unwrap_err();
            assert!(
                matches!(
                    e,
                    CaseError::Param(ParamError::BadCount {
                        name: "max-cycles",
                        ..
                    })
                ),
                "{e}"
            );
        }
        for good in [m.min, m.max] {
            let case = Case::builder().nodes(16).max_cycles(good).build().unwrap();
            assert_eq!(case.options().convergence().max_cycles(), good);
        }
    }
}
