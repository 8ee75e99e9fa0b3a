//! Taking over the terminal and giving it back, whatever happens: normal
//! quit, Ctrl-C (a key in raw mode, a signal otherwise) or a panic.

use std::io::{self, IsTerminal, Stdout};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Once};

use crossterm::{cursor, execute, terminal};
use ratatui::backend::CrosstermBackend;
use ratatui::Terminal;

use super::TuiError;

pub type Term = Terminal<CrosstermBackend<Stdout>>;

/// Both ends must be a terminal: keys come from stdin, escape codes go to
/// stdout. Checked before anything is written so a pipe gets no escapes.
pub fn check_tty() -> Result<(), TuiError> {
    if io::stdout().is_terminal() && io::stdin().is_terminal() {
        Ok(())
    } else {
        Err(TuiError::NotATerminal)
    }
}

/// Raw mode, alternate screen, hidden cursor; the panic hook is installed
/// first so that a panic anywhere after this point restores the terminal.
pub fn setup() -> Result<Term, TuiError> {
    check_tty()?;
    install_panic_hook();
    terminal::enable_raw_mode()?;
    let mut stdout = io::stdout();
    if let Err(e) = execute!(stdout, terminal::EnterAlternateScreen, cursor::Hide) {
        restore();
        return Err(e.into());
    }
    match Terminal::new(CrosstermBackend::new(stdout)) {
        Ok(t) => Ok(t),
        Err(e) => {
            restore();
            Err(e.into())
        }
    }
}

/// Undo [`setup`]. Safe to call more than once and from the panic hook;
/// errors are ignored because there is nothing left to report them to.
pub fn restore() {
    let _ = terminal::disable_raw_mode();
    let _ = execute!(io::stdout(), terminal::LeaveAlternateScreen, cursor::Show);
}

fn install_panic_hook() {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            // Restore first so the panic message lands on the normal screen.
            restore();
            previous(info);
        }));
    });
}

/// A flag raised by SIGINT. In raw mode Ctrl-C is a key, but a signal can
/// still arrive (`kill -INT`, or before raw mode is on); without a handler
/// it would kill the process with the terminal left raw.
pub fn interrupt_flag() -> Arc<AtomicBool> {
    static FLAG: std::sync::OnceLock<Arc<AtomicBool>> = std::sync::OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let setter = Arc::clone(&flag);
        // Failure only means another handler is already installed; the key
        // binding still quits.
        let _ = ctrlc::set_handler(move || setter.store(true, Ordering::SeqCst));
        flag
    })
    .clone()
}
