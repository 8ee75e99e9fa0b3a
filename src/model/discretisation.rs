//! Nodes round the interface and increments per cycle.

use std::f64::consts::PI;

use serde::Serialize;

use super::ParamError;

/// Discretisation: nodes round the interface and increments per cycle.
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
    pub const MIN_NODES: usize = 16;
    pub const MAX_NODES: usize = 4096;
    pub const MIN_STEPS: usize = 16;
    pub const MAX_STEPS: usize = 100_000;

    pub fn new(nodes: usize, steps_per_cycle: usize) -> Result<Self, ParamError> {
        if !(Self::MIN_NODES..=Self::MAX_NODES).contains(&nodes) || !nodes.is_multiple_of(2) {
            return Err(ParamError::BadCount {
                name: "nodes",
                value: nodes,
                expected: "an even number from 16 to 4096",
            });
        }
        if !(Self::MIN_STEPS..=Self::MAX_STEPS).contains(&steps_per_cycle) {
            return Err(ParamError::BadCount {
                name: "steps",
                value: steps_per_cycle,
                expected: "16 to 100000 increments per cycle",
            });
        }
        Ok(Self {
            nodes,
            steps_per_cycle,
        })
    }
    pub fn nodes(&self) -> usize {
        self.nodes
    }
    pub fn steps_per_cycle(&self) -> usize {
        self.steps_per_cycle
    }
    /// Node angle `theta_j = 2 pi j / N`.
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
