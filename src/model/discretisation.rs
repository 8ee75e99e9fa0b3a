//! Nodes round the interface and increments per cycle (model.md section
//! 3.3).

use std::f64::consts::PI;

use serde::Serialize;

use super::ParamError;

/// Discretisation: nodes round the interface and increments per cycle
/// (model.md section 3.3).
///
/// `N` (`nodes`) equally spaced nodes `theta_j = 2 pi j / N` carry the
/// nodal slip `g_j`; the steady cycle is cut into `steps` equal increments
/// of `omega t`, and a transient into increments no longer than
/// [`Discretisation::transient_step`]. The default is the paper's
/// resolution, 128 nodes and 400 increments a cycle.
///
/// ```
/// use shakedown::model::{Discretisation, ParamError};
///
/// let d = Discretisation::new(64, 200).unwrap();
/// assert_eq!((d.nodes(), d.steps_per_cycle()), (64, 200));
/// assert_eq!(Discretisation::default().nodes(), 128);
/// // N must be even (the Nyquist mode, model.md section 3.3) and in range.
/// assert!(matches!(
///     Discretisation::new(63, 200),
///     Err(ParamError::BadCount { name: "nodes", .. })
/// ));
/// assert!(matches!(
///     Discretisation::new(64, 3),
///     Err(ParamError::BadCount { name: "steps", .. })
/// ));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Discretisation {
    nodes: usize,
    steps_per_cycle: usize,
}

impl Default for Discretisation {
    fn default() -> Self {
        Self {
            nodes: 128,
            steps_per_cycle: 400,
        }
    }
}

impl Discretisation {
    /// Fewest interface nodes `N` accepted.
    pub const MIN_NODES: usize = super::ranges::NODES.min;
    /// Most interface nodes `N` accepted (the operators are dense
    /// `N x N` matrices).
    pub const MAX_NODES: usize = super::ranges::NODES.max;
    /// Fewest increments per cycle accepted.
    pub const MIN_STEPS: usize = super::ranges::STEPS.min;
    /// Most increments per cycle accepted.
    pub const MAX_STEPS: usize = super::ranges::STEPS.max;

    /// `nodes` interface nodes and `steps_per_cycle` increments per cycle.
    ///
    /// # Errors
    ///
    /// [`ParamError::BadCount`] (named `nodes`) unless `nodes` is even and in
    /// [`MIN_NODES`](Self::MIN_NODES)`..=`[`MAX_NODES`](Self::MAX_NODES);
    /// [`ParamError::BadCount`] (named `steps`) unless `steps_per_cycle` is in
    /// [`MIN_STEPS`](Self::MIN_STEPS)`..=`[`MAX_STEPS`](Self::MAX_STEPS).
    pub fn new(nodes: usize, steps_per_cycle: usize) -> Result<Self, ParamError> {
        let nodes = super::ranges::NODES.check(nodes)?;
        let steps_per_cycle = super::ranges::STEPS.check(steps_per_cycle)?;
        Ok(Self {
            nodes,
            steps_per_cycle,
        })
    }
    /// The number `N` of interface nodes (`nodes`).
    pub fn nodes(&self) -> usize {
        self.nodes
    }
    /// Increments per steady cycle (`steps`).
    pub fn steps_per_cycle(&self) -> usize {
        self.steps_per_cycle
    }
    /// Node angle `theta_j = 2 pi j / N`, in `[0, 2 pi)` for `j < N`.
    pub fn theta(&self, j: usize) -> f64 {
        2.0 * PI * j as f64 / self.nodes as f64
    }
    /// Longest load-plane distance of one transient increment. It is the
    /// path length per increment of an in-phase cycle with `lambda = 2 pi`
    /// (`4 lambda` per cycle), so refining `steps` refines transients too.
    pub fn transient_step(&self) -> f64 {
        8.0 * PI / self.steps_per_cycle as f64
    }
}
