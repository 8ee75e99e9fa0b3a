//! A case: everything one run needs (material, cycle, discretisation,
//! initial path, solver options), validated. The CLI, presets and the TUI
//! all build runs through this type.

use std::f64::consts::PI;

use serde::Serialize;

use crate::limit::LimitError;
use crate::params::{Cycle, Discretisation, LoadPoint, Material, ParamError, Plane};
use crate::path::{Initial, PathError};
use crate::stepper::{StepOptions, Stepper};

/// A case that cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CaseError {
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error(transparent)]
    Path(#[from] PathError),
    #[error("max-cycles = {0} is out of range: expected 1 to 100000")]
    MaxCycles(usize),
    #[error("initial path 'optimal': {0}")]
    Optimal(#[from] LimitError),
}

/// The raw parameters of a case as a user gives them (all optional fields
/// default to the paper's values).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseParams {
    pub load_factor: f64,
    pub phase: f64,
    pub slope: f64,
    pub center: (f64, f64),
    pub friction: f64,
    pub poisson: f64,
    pub plane: Plane,
    pub initial: String,
    pub nodes: usize,
    pub steps: usize,
    pub max_cycles: usize,
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
            friction: 0.1,
            poisson: 0.3,
            plane: Plane::Strain,
            initial: "OA".into(),
            nodes: 128,
            steps: 400,
            max_cycles: crate::steady::DEFAULT_MAX_CYCLES,
        }
    }
}

/// A validated case.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub material: Material,
    pub cycle: Cycle,
    pub disc: Discretisation,
    pub initial: Initial,
    pub options: StepOptions,
}

impl Case {
    /// Validate the parameters. `optimal` as the initial path is resolved by
    /// the limit analysis.
    pub fn from_params(p: &CaseParams) -> Result<Case, CaseError> {
        let material = Material::new(p.friction, p.poisson, p.plane)?;
        let cycle = Cycle::new(
            LoadPoint::new(p.center.0, p.center.1),
            p.load_factor,
            p.slope,
            p.phase,
        )?;
        let disc = Discretisation::new(p.nodes, p.steps)?;
        if !(1..=100_000).contains(&p.max_cycles) {
            return Err(CaseError::MaxCycles(p.max_cycles));
        }
        let mut options = StepOptions::default();
        options.convergence.max_cycles = p.max_cycles;
        let initial = resolve_initial(&p.initial, &material, &cycle, &disc)?;
        Ok(Case {
            material,
            cycle,
            disc,
            initial,
            options,
        })
    }

    /// A stepper at the start of this case.
    pub fn stepper(&self) -> Stepper {
        Stepper::new(
            self.material,
            self.disc,
            &self.initial,
            self.cycle,
            self.options,
        )
    }
}

/// Resolve an initial-path name: `OA`, `a,b`, or `optimal`.
pub fn resolve_initial(
    name: &str,
    material: &Material,
    cycle: &Cycle,
    disc: &Discretisation,
) -> Result<Initial, CaseError> {
    if name.trim().eq_ignore_ascii_case("optimal") {
        return crate::limit::optimal_initial(material, cycle, disc).map_err(CaseError::Optimal);
    }
    Ok(Initial::parse(name)?)
}
