//! The CSV codecs, one module per format, each with its reader and writer
//! and the metadata header every file of this crate starts with:
//!
//! - [`crate::io::metadata`]: the `# key = value` header and numbers;
//! - [`crate::io::sweep_csv`]: sweeps (`sweep`, sweep figures, the
//!   explorer's save);
//! - [`crate::io::slip_csv`]: the optimal slip of `limit --out`;
//! - [`crate::io::slip_map_csv`]: slip maps (`figure fig5`, `fig7`);
//! - [`crate::io::memory_csv`]: the memory figure (`figure fig4`).
//!
//! This module gathers their names, as they were before the split.

pub use crate::io::metadata::{
    case_metadata, check_preamble, fmt_number, limit_curve_metadata, Metadata, MetadataError,
    VERSION,
};
pub use crate::io::slip_csv::{
    polyline_slip_csv, read_slip_csv, slip_csv, SlipFileError, SLIP_HEADER,
};
pub use crate::io::slip_map_csv::{
    read_slip_map, slip_map_metadata, SlipMapFile, SlipMapFileError, SlipMapReadError,
    SLIP_MAP_TABLE,
};
pub use crate::io::sweep_csv::{
    header_cycle_cap, replace_sweep_csv, save_sweep_csv, sweep_csv, sweep_metadata, sweep_row_key,
    sweep_row_key_capped,
};
