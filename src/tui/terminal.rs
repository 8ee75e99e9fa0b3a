//! Taking over the terminal and giving it back, whatever happens: normal
//! quit, Ctrl-C, SIGTERM, SIGHUP, SIGQUIT, a panic; and lending it back to
//! the shell on SIGTSTP (or Ctrl-Z) until `fg`.

use std::io::{self, IsTerminal, Stdout};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Once, OnceLock};

use crossterm::event::{DisableMouseCapture, EnableMouseCapture};
use crossterm::{cursor, execute, terminal};
use ratatui::backend::CrosstermBackend;
use ratatui::Terminal;
use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGTSTP};

use super::TuiError;

/// The ratatui terminal the explorer draws on: crossterm over stdout.
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

/// Raw mode, alternate screen, mouse capture, hidden cursor; the panic
/// hook is installed first so that a panic anywhere after this point
/// restores the terminal.
pub fn setup() -> Result<Term, TuiError> {
    check_tty()?;
    install_panic_hook();
    enter()?;
    match Terminal::new(CrosstermBackend::new(io::stdout())) {
        Ok(t) => Ok(t),
        Err(e) => {
            restore();
            Err(e.into())
        }
    }
}

fn enter() -> Result<(), TuiError> {
    terminal::enable_raw_mode()?;
    if let Err(e) = execute!(
        io::stdout(),
        terminal::EnterAlternateScreen,
        EnableMouseCapture,
        cursor::Hide
    ) {
        restore();
        return Err(e.into());
    }
    Ok(())
}

/// Undo [`setup`]. Safe to call more than once and from the panic hook;
/// errors are ignored because there is nothing left to report them to.
pub fn restore() {
    let _ = execute!(
        io::stdout(),
        DisableMouseCapture,
        terminal::LeaveAlternateScreen,
        cursor::Show
    );
    let _ = terminal::disable_raw_mode();
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

/// What a signal asks of the loop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Signal {
    /// No signal is pending.
    None,
    /// SIGINT: quit with status 130.
    Interrupt,
    /// SIGTERM, SIGHUP, SIGQUIT: restore and exit with this status.
    Exit(u8),
    /// SIGTSTP: give the terminal back and stop until `fg`.
    Suspend,
}

/// The last signal received (0 for none). The handlers only store the
/// number; the loop acts on it within a frame, on its own thread, so the
/// terminal is restored by the code that owns it.
pub fn signals() -> Arc<AtomicUsize> {
    static FLAG: OnceLock<Arc<AtomicUsize>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicUsize::new(0));
        for sig in [SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGTSTP] {
            // Failure leaves that signal's default action; the keys work.
            let _ = signal_hook::flag::register_usize(sig, Arc::clone(&flag), sig as usize);
        }
        watchdog();
        flag
    })
    .clone()
}

/// How long the loop has to act on SIGTERM, SIGHUP or SIGQUIT before the
/// watchdog restores the terminal and exits on its own.
const EXIT_GRACE: std::time::Duration = std::time::Duration::from_millis(1500);

/// The loop acts on an exit signal within a frame. But when the terminal
/// itself is gone (an SSH connection dropped, the tmux server killed),
/// crossterm's input poll can spin on end-of-file and never return, and the
/// explorer would run on for ever without a terminal. So a thread waits for
/// the same signals and, if the process is still alive after
/// [`EXIT_GRACE`], restores what it can and exits with `128 + signal`.
fn watchdog() {
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGTERM, SIGHUP, SIGQUIT]) else {
        return;
    };
    let _ = std::thread::Builder::new()
        .name("shakedown-signals".into())
        .spawn(move || {
            if let Some(sig) = signals.forever().next() {
                std::thread::sleep(EXIT_GRACE);
                restore();
                std::process::exit(128 + sig);
            }
        });
}

/// Take the pending signal, if any.
pub fn take_signal(flag: &AtomicUsize) -> Signal {
    match flag.swap(0, Ordering::SeqCst) as i32 {
        0 => Signal::None,
        SIGINT => Signal::Interrupt,
        SIGTSTP => Signal::Suspend,
        sig => Signal::Exit((128 + sig).clamp(0, 255) as u8),
    }
}

/// Restore the terminal, stop as the terminal's own Ctrl-Z would, and on
/// `fg` take the terminal again and redraw everything.
pub fn suspend(term: &mut Term) -> Result<(), TuiError> {
    restore();
    // The terminal's Ctrl-Z stops the whole foreground process group, and
    // so must this: stopping only this process would leave a wrapper that
    // waits for it (`cargo run`, a script) running, and the shell would
    // never get the terminal back. SIGSTOP, because SIGTSTP is caught here.
    // Stops here until SIGCONT.
    // SAFETY: kill(2) with pid 0 signals our own process group; it takes
    // no pointers.
    if unsafe { libc::kill(0, libc::SIGSTOP) } != 0 {
        let _ = signal_hook::low_level::emulate_default_handler(SIGTSTP);
    }
    enter()?;
    term.clear()?;
    Ok(())
}
