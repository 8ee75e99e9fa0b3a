//! Reading user files safely: through a size cap, regular files only (a
//! FIFO would block for ever, `/dev/zero` never ends), and text from them
//! escaped before it is echoed in an error message.

use std::io::Read;
use std::path::Path;

/// Largest preset file read (1 MiB): a preset is a page of TOML.
pub const MAX_PRESET_BYTES: u64 = 1 << 20;

/// A user file that was not read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReadError {
    /// The file could not be opened or read.
    #[error("cannot read it: {0}")]
    Io(String),
    /// A FIFO, a device, a directory or a socket.
    #[error("it is not a regular file (a FIFO, device or directory): expected a file")]
    NotRegular,
    /// Longer than the cap.
    #[error("it is larger than {cap} bytes, more than such a file can be")]
    TooLarge {
        /// The cap in bytes.
        cap: u64,
    },
}

/// Read the regular file `path` whole, refusing anything else and anything
/// longer than `cap` bytes. A FIFO or device is refused before it is opened,
/// so the call never blocks.
///
/// # Errors
///
/// [`ReadError`]: the file is missing or unreadable, not a regular file, or
/// longer than `cap`.
pub fn read_capped(path: &Path, cap: u64) -> Result<Vec<u8>, ReadError> {
    let meta = std::fs::metadata(path).map_err(|e| ReadError::Io(e.to_string()))?;
    if !meta.is_file() {
        return Err(ReadError::NotRegular);
    }
    if meta.len() > cap {
        return Err(ReadError::TooLarge { cap });
    }
    let file = std::fs::File::open(path).map_err(|e| ReadError::Io(e.to_string()))?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    // The file may grow after the check: never read more than the cap.
    file.take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    if bytes.len() as u64 > cap {
        return Err(ReadError::TooLarge { cap });
    }
    Ok(bytes)
}

/// The first `max` bytes (or fewer) of the regular file `path`: enough to
/// read a CSV's `# key = value` header before deciding how much of the
/// file may be read. FIFOs and devices are refused before they are opened.
///
/// # Errors
///
/// [`ReadError`]: the file is missing or unreadable, or not a regular file.
pub fn read_head(path: &Path, max: u64) -> Result<Vec<u8>, ReadError> {
    let meta = std::fs::metadata(path).map_err(|e| ReadError::Io(e.to_string()))?;
    if !meta.is_file() {
        return Err(ReadError::NotRegular);
    }
    let file = std::fs::File::open(path).map_err(|e| ReadError::Io(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(max)
        .read_to_end(&mut bytes)
        .map_err(|e| ReadError::Io(e.to_string()))?;
    Ok(bytes)
}

/// Read a regular file as UTF-8 text through [`read_capped`].
///
/// # Errors
///
/// As [`read_capped`], and [`ReadError::Io`] when the file is not UTF-8.
pub fn read_text_capped(path: &Path, cap: u64) -> Result<String, ReadError> {
    let bytes = read_capped(path, cap)?;
    String::from_utf8(bytes).map_err(|_| ReadError::Io("it is not UTF-8 text".into()))
}

/// `text` with control characters escaped (`\u{1b}`, `\t`, ...), at most
/// `max` characters of it, so that a file's content echoed in an error
/// message can neither drive the terminal nor break the one-line rule.
pub fn escape_text(text: &str, max: usize) -> String {
    let mut out = String::new();
    for (i, c) in text.chars().enumerate() {
        if i == max {
            out.push_str("...");
            break;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_controls() {
        assert_eq!(escape_text("a\u{1b}[2Jb\n", 100), "a\\u{1b}[2Jb\\n");
        assert_eq!(escape_text("abcdef", 3), "abc...");
    }

    #[test]
    fn refuses_devices_and_large_files() {
        assert_eq!(
            read_capped(Path::new("/dev/zero"), 10),
            Err(ReadError::NotRegular)
        );
        let dir = std::env::temp_dir().join(format!("shakedown-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("big");
        std::fs::write(&f, vec![b'x'; 100]).unwrap();
        assert_eq!(read_capped(&f, 99), Err(ReadError::TooLarge { cap: 99 }));
        assert_eq!(read_capped(&f, 100).unwrap().len(), 100);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
