//! Analysis of runs: cases and sweeps, the shakedown limit `lambda_2` by linear programming, the memory
//! measures `R` and `r` of Fig. 4, slip maps and the ratchetting threshold
//! `lambda_3`.

pub mod case;
pub mod curves;
pub mod design;
pub mod episodes;
pub mod limit;
pub mod limit_curve;
mod meet;
pub mod memory;
pub mod ordered;
pub mod profile;
pub mod regime;
pub mod slip_map;
pub mod sweep;
