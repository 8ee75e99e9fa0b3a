//! Input and output: parsing of numbers and angles, presets (TOML), and
//! the batch machinery (ordered parallel runs, interrupts, shards, resume,
//! merge).

pub mod batch;
pub mod parse;
pub mod preset;
