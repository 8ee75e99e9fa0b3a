//! The data a sweep figure draws, one [`SweepPoint`] per run. Reading it
//! from a CSV is the io layer's job ([`crate::io::sweep_csv`]); it is
//! re-exported here for the figures.

pub use crate::io::sweep_csv::{data_lines, parse_state, parse_sweep_csv, CsvError, SweepPoint};
