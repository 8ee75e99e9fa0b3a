//! `shakedown`: the terminal explorer (default) and the headless batch tool.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
