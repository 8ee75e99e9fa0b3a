//! Input and output: parsing of numbers and angles, presets (TOML), the
//! batch machinery (ordered parallel runs, interrupts, shards, resume,
//! merge), the CSV codec with its `# key = value` header, and safe file
//! handling (capped reads, atomic writes, output locks).

pub mod batch;
pub mod csv;
pub mod cycle;
pub mod design;
pub mod events;
pub mod hash;
pub mod memory_csv;
pub mod metadata;
pub mod output;
pub mod parse;
pub mod preset;
pub mod profile;
pub mod read;
pub mod slip_csv;
pub mod slip_map_csv;
pub mod sweep_csv;
