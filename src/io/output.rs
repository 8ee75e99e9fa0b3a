//! Writing outputs without destroying anything: whole files replaced
//! atomically (temporary file in the same folder, then rename), a lock that
//! refuses a second writer on the same output, file names from presets
//! kept inside their folder, and a check that an output is not an input.

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Why an output was not written. [`WriteError::is_input`] tells a bad path
/// (the user's input) from a failure of the environment (a full disk).
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot {stage}: {source}", path.display())]
pub struct WriteError {
    /// The output.
    pub path: PathBuf,
    /// What was being done: "create it", "write it", ...
    pub stage: &'static str,
    /// The system's error.
    #[source]
    pub source: io::Error,
}

impl WriteError {
    fn new(path: &Path, stage: &'static str, source: io::Error) -> Self {
        Self {
            path: path.to_path_buf(),
            stage,
            source,
        }
    }

    /// True when the path itself is wrong (a missing folder, a directory,
    /// no permission): bad input. False for failures while writing (a full
    /// disk, an I/O error): the environment.
    pub fn is_input(&self) -> bool {
        self.stage == "create it" && is_path_problem(&self.source)
    }
}

/// Whether an error opening a path means the path is wrong rather than the
/// machine in trouble.
pub fn is_path_problem(e: &io::Error) -> bool {
    use io::ErrorKind::*;
    matches!(
        e.kind(),
        NotFound | PermissionDenied | IsADirectory | NotADirectory | ReadOnlyFilesystem
    ) || e.raw_os_error() == Some(21)
}

/// Replace `path` with `bytes` atomically: write a temporary file in the
/// same folder, flush it to disk, and rename it over `path`. If anything
/// fails, the temporary file is removed and `path` is as it was. A target
/// that exists and is not a regular file (`/dev/stdout`, a FIFO, a device)
/// is written in place instead: it cannot be replaced by a rename.
///
/// # Errors
///
/// [`WriteError`] naming the path; [`WriteError::is_input`] says whether
/// the path was at fault.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(WriteError::new(
                path,
                "create it",
                io::Error::from(io::ErrorKind::IsADirectory),
            ));
        }
        if !meta.is_file() {
            let mut f = OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(|e| WriteError::new(path, "create it", e))?;
            return f
                .write_all(bytes)
                .and_then(|()| f.flush())
                .map_err(|e| WriteError::new(path, "write it", e));
        }
    }
    let temp = temp_path(path);
    let result = (|| {
        let mut f = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)
            .map_err(|e| WriteError::new(path, "create it", e))?;
        f.write_all(bytes)
            .and_then(|()| f.sync_all())
            .map_err(|e| WriteError::new(path, "write it", e))?;
        drop(f);
        std::fs::rename(&temp, path).map_err(|e| WriteError::new(path, "replace it", e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    result
}

/// A temporary name beside `path` for this process: `.NAME.PID.tmp`.
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    path.with_file_name(format!(".{name}.{}.tmp", std::process::id()))
}

/// The folder a relative or absolute output path lives in.
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// An output refused because another process is writing it.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another process holds the lock.
    #[error("another process{} is writing it (lock file {}): wait for it to finish or stop it", pid.map(|p| format!(" (pid {p})")).unwrap_or_default(), lock.display())]
    Busy {
        /// The lock file.
        lock: PathBuf,
        /// The holder's process id, if it wrote one.
        pid: Option<u32>,
    },
    /// The lock file could not be created.
    #[error("cannot create the lock file {}: {source}", lock.display())]
    Io {
        /// The lock file.
        lock: PathBuf,
        /// The system's error.
        #[source]
        source: io::Error,
    },
}

/// An advisory lock on an output: the file `OUT.lock` beside it, locked
/// with the operating system's file lock (`flock`) and holding the owner's
/// pid. The operating system releases the lock when the process ends, even
/// by a hard kill, so a stale lock file never blocks anyone; the file is
/// removed when the lock is dropped.
#[derive(Debug)]
pub struct OutputLock {
    file: File,
    path: PathBuf,
}

impl OutputLock {
    /// The lock file of `output`: `OUT.lock` in the same folder.
    pub fn path_for(output: &Path) -> PathBuf {
        let mut name = output
            .file_name()
            .map(|n| n.to_os_string())
            .unwrap_or_else(|| "output".into());
        name.push(".lock");
        output.with_file_name(name)
    }

    /// Take the lock on `output`, or say who holds it.
    ///
    /// # Errors
    ///
    /// [`LockError::Busy`] when another process holds it,
    /// [`LockError::Io`] when the lock file cannot be made (a missing
    /// folder, no permission).
    pub fn acquire(output: &Path) -> Result<OutputLock, LockError> {
        let path = Self::path_for(output);
        // A holder that finishes removes the file; if we locked a file that
        // was removed meanwhile, try again on the new one.
        for _ in 0..100 {
            let file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(|source| LockError::Io {
                    lock: path.clone(),
                    source,
                })?;
            match file.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => {
                    let pid = std::fs::read_to_string(&path)
                        .ok()
                        .and_then(|t| t.trim().parse().ok());
                    return Err(LockError::Busy { lock: path, pid });
                }
                Err(std::fs::TryLockError::Error(source)) => {
                    return Err(LockError::Io { lock: path, source })
                }
            }
            if !same_inode(&file, &path) {
                continue;
            }
            let mut lock = OutputLock { file, path };
            let _ = lock.file.set_len(0);
            let _ = writeln!(lock.file, "{}", std::process::id());
            return Ok(lock);
        }
        Err(LockError::Busy {
            lock: path,
            pid: None,
        })
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Remove first, then unlock (on close): a newcomer that opened the
        // old file sees that it is gone and retries.
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

#[cfg(unix)]
fn same_inode(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode(_: &File, path: &Path) -> bool {
    path.exists()
}

/// Whether `a` and `b` name the same existing file (through links and
/// different spellings of the path).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Whether writing `path` would destroy something: it is a regular file
/// that is not empty.
pub fn is_nonempty_file(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.len() > 0)
}

/// A name used as a file name stem (a preset's `name`) that stays inside
/// its folder: not empty, at most 100 characters, no path separator, no
/// `..`, no leading `.`, no `:` and no control character.
///
/// # Errors
///
/// A sentence saying what is wrong with the name.
pub fn check_file_stem(name: &str) -> Result<(), String> {
    let why = if name.is_empty() {
        "it is empty"
    } else if name.chars().count() > 100 {
        "it is longer than 100 characters"
    } else if name.contains('/') || name.contains('\\') {
        "it contains a path separator"
    } else if name.contains("..") {
        "it contains '..'"
    } else if name.starts_with('.') {
        "it starts with '.'"
    } else if name.contains(':') {
        "it contains ':'"
    } else if name.chars().any(char::is_control) {
        "it contains a control character"
    } else {
        return Ok(());
    };
    Err(format!(
        "{why}: a name becomes a file name, so use letters, digits, '-' and '_'"
    ))
}

/// Check that `output` can be created in its folder (the folder exists).
///
/// # Errors
///
/// The system's error for the folder.
pub fn check_folder(output: &Path) -> io::Result<()> {
    let dir = folder_of(output);
    let meta = std::fs::metadata(dir)?;
    if meta.is_dir() {
        Ok(())
    } else {
        Err(io::Error::from(io::ErrorKind::NotADirectory))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("shakedown-out-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn atomic_write_replaces_whole_files() {
        let d = dir("atomic");
        let f = d.join("a.csv");
        write_atomic(&f, b"one").unwrap();
        write_atomic(&f, b"two").unwrap();
        assert_eq!(std::fs::read(&f).unwrap(), b"two");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "no temp left");
        let e = write_atomic(&d.join("no/such.csv"), b"x").unwrap_err();
        assert!(e.is_input());
        let e = write_atomic(Path::new("/dev/full"), b"x").unwrap_err();
        assert!(!e.is_input(), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_second_writer_is_refused() {
        let d = dir("lock");
        let out = d.join("map.csv");
        let lock = OutputLock::acquire(&out).unwrap();
        assert!(lock.path().exists());
        let e = OutputLock::acquire(&out).unwrap_err();
        assert!(e.to_string().contains("map.csv.lock"), "{e}");
        drop(lock);
        assert!(!OutputLock::path_for(&out).exists());
        let _again = OutputLock::acquire(&out).unwrap();
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn file_stems_stay_in_their_folder() {
        for bad in [
            "", "../x", "/etc/x", "a/b", "a\\b", "..", ".hidden", "a\u{1b}b", "c:x",
        ] {
            assert!(check_file_stem(bad).is_err(), "{bad:?}");
        }
        for good in ["fig3", "my-map_2", "Fig 3 (draft)"] {
            assert!(check_file_stem(good).is_ok(), "{good}");
        }
    }
}
