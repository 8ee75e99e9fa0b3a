//! The events the explorer's loop reacts to.

use std::io;
use std::time::Duration;

use crossterm::event::{self as ct, KeyEvent, KeyEventKind, MouseEventKind};

/// What woke the loop up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// A key press or repeat (releases are dropped).
    Key(KeyEvent),
    /// The mouse wheel: `-1` a notch up (back in history), `1` down.
    Scroll(i32),
    /// The terminal was resized to this many columns and rows.
    Resize(u16, u16),
    /// Nothing arrived before the frame was due.
    Tick,
}

/// Wait at most `timeout` for terminal input.
pub fn next(timeout: Duration) -> io::Result<Event> {
    if !ct::poll(timeout)? {
        return Ok(Event::Tick);
    }
    Ok(match ct::read()? {
        // Some terminals (Windows, kitty protocol) also report releases;
        // acting on those would apply every key twice.
        ct::Event::Key(k) if k.kind != KeyEventKind::Release => Event::Key(k),
        ct::Event::Mouse(m) => match m.kind {
            MouseEventKind::ScrollUp => Event::Scroll(-1),
            MouseEventKind::ScrollDown => Event::Scroll(1),
            _ => Event::Tick,
        },
        ct::Event::Resize(w, h) => Event::Resize(w, h),
        _ => Event::Tick,
    })
}
