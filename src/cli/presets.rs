//! `shakedown presets`: the built-in presets, one line each.

use std::process::ExitCode;

use anyhow::Result;

/// Run `shakedown presets`.
pub fn presets() -> Result<ExitCode> {
    let all = shakedown::io::preset::builtin();
    let width = shakedown::io::preset::BUILTIN
        .iter()
        .map(|(n, _)| n.len())
        .max()
        .unwrap_or(0);
    let mut code = ExitCode::SUCCESS;
    for ((name, _), preset) in shakedown::io::preset::BUILTIN.iter().zip(all) {
        match preset {
            Ok(p) => outln!("{name:width$}  {}", p.description),
            Err(e) => {
                errln!("error: {e}");
                code = ExitCode::from(1);
            }
        }
    }
    outln!();
    outln!("Use one with --preset NAME (run, sweep, tui) or `shakedown figure NAME --out DIR`;");
    outln!("a path to your own .toml works too (copy one from presets/ to start).");
    Ok(code)
}
