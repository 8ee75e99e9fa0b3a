//! Every integration test in one binary: one link, one run (as bottom
//! keeps `tests/integration/main.rs`). Each file is a module.

mod allocations;
mod bad_input;
mod batch_cli;
mod common;
mod design;
mod docs_commands;
mod engine;
mod events;
mod figure_guarantees;
mod figure_polyline;
mod figures;
mod history_trim;
mod kernels;
mod level;
mod limit;
mod numerical_failure;
mod parser_props;
mod physics;
mod polyline;
mod presets;
mod solver_props;
mod sweep_determinism;
mod tui_keys;
mod tui_maps;
mod tui_snapshots;
mod verdicts;
