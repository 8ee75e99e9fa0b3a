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

/// Write `bytes` to a new file `path`, refusing to replace anything: an
/// existing file, folder or symlink (even a dangling one) is left as it is
/// (`create_new` never follows a symlink). The output is locked while it is
/// written ([`OutputLock`]), and a failed write removes the partial file.
///
/// # Errors
///
/// [`WriteError`] naming the path: stage "create it" with
/// `AlreadyExists` when something is there, or the system's error.
pub fn write_new(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let _lock = OutputLock::acquire(path)
        .map_err(|e| WriteError::new(path, "lock it", io::Error::other(e.to_string())))?;
    let mut f = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
        .map_err(|e| WriteError::new(path, "create it", e))?;
    let written = f
        .write_all(bytes)
        .and_then(|()| f.sync_all())
        .map_err(|e| WriteError::new(path, "write it", e));
    if written.is_err() {
        let _ = std::fs::remove_file(path);
    }
    written
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
    /// Another process writes the same file under another name (a symlink
    /// or a hard link).
    #[error("another process is writing this file under another name (a link to it): wait for it to finish or stop it")]
    BusyFile,
    /// The lock path is a symlink, a folder, a FIFO or a device: it is
    /// never opened for writing.
    #[error("its lock file {} is not a regular file (a symlink, folder or device): remove it, or choose another output", lock.display())]
    NotRegular {
        /// The lock file.
        lock: PathBuf,
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

/// An advisory lock on an output. It belongs to the file, not to the name
/// it is given by:
///
/// * the lock file `OUT.lock` sits beside the output's resolved path
///   (symlinks followed), so two names of one path meet at one lock;
/// * an output that exists is itself locked (`flock` on its inode), so a
///   hard link to a file in use is refused too; [`OutputLock::pin`] does
///   the same for an output created after the lock was taken.
///
/// The lock file is locked with the operating system's file lock and holds
/// the owner's pid. The operating system releases it when the process ends,
/// even by a hard kill, so a stale lock file never blocks anyone; the file
/// is removed when the lock is dropped. A lock path that is a symlink or
/// not a regular file is never opened for writing.
#[derive(Debug)]
pub struct OutputLock {
    file: File,
    path: PathBuf,
    /// The output itself, locked, while it exists.
    pinned: Option<File>,
}

/// Longest file name most file systems take (bytes).
const NAME_MAX: usize = 255;

impl OutputLock {
    /// The lock file of `output`: `OUT.lock` beside it. A name too long
    /// for `.lock` to be added is replaced by a digest of it.
    pub fn path_for(output: &Path) -> PathBuf {
        let mut name = output
            .file_name()
            .map(|n| n.to_os_string())
            .unwrap_or_else(|| "output".into());
        if name.len() + ".lock".len() > NAME_MAX {
            let digest = crate::io::hash::digest_hex(name.as_encoded_bytes());
            name = format!(".{}", &digest[..32]).into();
        }
        name.push(".lock");
        output.with_file_name(name)
    }

    /// The path an output resolves to: symlinks followed (the output's own,
    /// if it exists, and its folder's).
    ///
    /// # Errors
    ///
    /// The system's error when the folder does not exist, or the output is
    /// a symlink to nothing.
    pub fn resolve(output: &Path) -> io::Result<PathBuf> {
        if std::fs::symlink_metadata(output).is_ok() {
            return output.canonicalize();
        }
        let name = output
            .file_name()
            .ok_or_else(|| io::Error::from(io::ErrorKind::InvalidInput))?;
        Ok(folder_of(output).canonicalize()?.join(name))
    }

    /// Take the lock on `output`, or say who holds it.
    ///
    /// # Errors
    ///
    /// [`LockError::Busy`] or [`LockError::BusyFile`] when another process
    /// holds it, [`LockError::NotRegular`] for an odd lock path,
    /// [`LockError::Io`] when the lock file cannot be made (a missing
    /// folder, no permission).
    pub fn acquire(output: &Path) -> Result<OutputLock, LockError> {
        let resolved = Self::resolve(output).map_err(|source| LockError::Io {
            lock: Self::path_for(output),
            source,
        })?;
        let path = Self::path_for(&resolved);
        // A holder that finishes removes the file; if we locked a file that
        // was removed meanwhile, try again on the new one.
        for _ in 0..100 {
            let file = match open_lock_file(&path) {
                Ok(f) => f,
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) if e.kind() == io::ErrorKind::InvalidData => {
                    return Err(LockError::NotRegular { lock: path })
                }
                Err(source) => return Err(LockError::Io { lock: path, source }),
            };
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
            let mut lock = OutputLock {
                file,
                path,
                pinned: None,
            };
            // The output itself, under whatever name: a hard link to a file
            // another process writes is refused here.
            if std::fs::metadata(&resolved).is_ok_and(|m| m.is_file()) {
                if let Ok(out) = File::open(&resolved) {
                    lock.pin(out)?;
                }
            }
            let _ = lock.file.set_len(0);
            let _ = writeln!(lock.file, "{}", std::process::id());
            // Whoever left temporary files of this output is gone (we hold
            // its lock): clean them up.
            remove_stale_temps(&resolved);
            return Ok(lock);
        }
        Err(LockError::Busy {
            lock: path,
            pid: None,
        })
    }

    /// Lock the output file itself (`file` is an open handle of it), so
    /// that no other process writes it under another name. A second call
    /// keeps the first pin.
    ///
    /// # Errors
    ///
    /// [`LockError::BusyFile`] when another process writes that file.
    pub fn pin(&mut self, file: File) -> Result<(), LockError> {
        if self.pinned.is_some() {
            return Ok(());
        }
        match file.try_lock() {
            Ok(()) => {
                self.pinned = Some(file);
                Ok(())
            }
            Err(std::fs::TryLockError::WouldBlock) => Err(LockError::BusyFile),
            // A file system without locks: the name lock still holds.
            Err(std::fs::TryLockError::Error(_)) => Ok(()),
        }
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Remove the temporary files that a killed writer of `output` left
/// beside it: `.NAME….PID.tmp` (and their `.lock`) and `.tmp-PID-NAME…`,
/// where `…` is empty or starts with `.` or `_` (a figure's `NAME.csv`,
/// `NAME_limit.csv`), for any process but this one. Only the holder of the
/// output's lock calls this, so no live writer owns them.
pub fn remove_stale_temps(output: &Path) {
    let Some(name) = output.file_name().and_then(|n| n.to_str()) else {
        return;
    };
    let me = std::process::id().to_string();
    let ours = |rest: &str| rest.is_empty() || rest.starts_with(['.', '_']);
    let Ok(entries) = std::fs::read_dir(folder_of(output)) else {
        return;
    };
    for entry in entries.flatten().take(100_000) {
        let file = entry.file_name();
        let Some(f) = file.to_str() else { continue };
        let stale = if let Some(body) = f.strip_prefix('.').and_then(|b| b.strip_prefix(name)) {
            let body = body.strip_suffix(".lock").unwrap_or(body);
            body.strip_suffix(".tmp")
                .and_then(|b| b.rsplit_once('.'))
                .is_some_and(|(rest, pid)| {
                    ours(rest)
                        && !pid.is_empty()
                        && pid.bytes().all(|c| c.is_ascii_digit())
                        && pid != me
                })
        } else if let Some(body) = f.strip_prefix(".tmp-") {
            body.split_once('-').is_some_and(|(pid, rest)| {
                !pid.is_empty()
                    && pid.bytes().all(|c| c.is_ascii_digit())
                    && pid != me
                    && rest.strip_prefix(name).is_some_and(ours)
            })
        } else {
            false
        };
        if stale && entry.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Open the lock file `path` for writing without following a symlink and
/// without touching anything but a regular file: a new one is made with
/// `create_new` (which refuses a symlink, even a dangling one); an existing
/// one must be a regular file before it is opened and the same file after.
/// `InvalidData` means "not a regular file"; `AlreadyExists` a race (retry).
fn open_lock_file(path: &Path) -> io::Result<File> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_file() => {
            let f = OpenOptions::new().read(true).write(true).open(path)?;
            if !same_inode_nofollow(&f, path) {
                return Err(io::Error::from(io::ErrorKind::InvalidData));
            }
            Ok(f)
        }
        Ok(_) => Err(io::Error::from(io::ErrorKind::InvalidData)),
        Err(e) if e.kind() == io::ErrorKind::NotFound => OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(path),
        Err(e) => Err(e),
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

/// `same_inode` of the path itself (a symlink is not its target).
#[cfg(unix)]
fn same_inode_nofollow(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => b.file_type().is_file() && a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_inode_nofollow(file: &File, path: &Path) -> bool {
    same_inode(file, path)
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
    } else if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.')))
    {
        return Err(format!(
            "it contains {}: a name becomes a file name, so use only ASCII letters, digits, '-', '_' and '.'",
            if c == ' ' { "a space".to_string() } else { format!("'{}'", c.escape_default()) }
        ));
    } else {
        return Ok(());
    };
    Err(format!(
        "{why}: a name becomes a file name, so use only ASCII letters, digits, '-', '_' and '.'"
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

    #[cfg(unix)]
    #[test]
    fn the_lock_belongs_to_the_file_not_the_name() {
        let d = dir("links");
        let out = d.join("x.csv");
        std::fs::write(&out, "data").unwrap();
        let _lock = OutputLock::acquire(&out).unwrap();
        std::os::unix::fs::symlink(&out, d.join("y.csv")).unwrap();
        std::fs::hard_link(&out, d.join("z.csv")).unwrap();
        let e = OutputLock::acquire(&d.join("y.csv")).unwrap_err();
        assert!(matches!(e, LockError::Busy { .. }), "{e}");
        let e = OutputLock::acquire(&d.join("z.csv")).unwrap_err();
        assert!(matches!(e, LockError::BusyFile), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_lock_path_that_is_a_link_or_folder_is_never_written() {
        let d = dir("oddlock");
        let victim = d.join("v.txt");
        std::fs::write(&victim, "keep").unwrap();
        std::os::unix::fs::symlink(&victim, d.join("o.csv.lock")).unwrap();
        let e = OutputLock::acquire(&d.join("o.csv")).unwrap_err();
        assert!(matches!(e, LockError::NotRegular { .. }), "{e}");
        assert_eq!(std::fs::read(&victim).unwrap(), b"keep");
        std::os::unix::fs::symlink(d.join("none"), d.join("p.csv.lock")).unwrap();
        assert!(OutputLock::acquire(&d.join("p.csv")).is_err());
        assert!(!d.join("none").exists(), "a dangling link is not followed");
        std::fs::create_dir(d.join("q.csv.lock")).unwrap();
        let e = OutputLock::acquire(&d.join("q.csv")).unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
        let long = "n".repeat(255);
        let lock = OutputLock::acquire(&d.join(&long)).unwrap();
        assert!(lock.path().file_name().unwrap().len() <= 255);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_killed_writers_temporary_files_are_cleaned() {
        let d = dir("stale");
        for f in [
            ".fig3.csv.1.tmp",
            ".fig3.csv.2.tmp.lock",
            ".tmp-3-fig3.svg",
            ".fig30.csv.4.tmp",
            "fig3.csv",
        ] {
            std::fs::write(d.join(f), "x").unwrap();
        }
        let _lock = OutputLock::acquire(&d.join("fig3")).unwrap();
        let mut left: Vec<String> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        left.sort();
        assert_eq!(left, [".fig30.csv.4.tmp", "fig3.csv", "fig3.lock"]);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn file_stems_stay_in_their_folder() {
        for bad in [
            "",
            "../x",
            "/etc/x",
            "a/b",
            "a\\b",
            "..",
            ".hidden",
            "a\u{1b}b",
            "c:x",
            "a b",
            "~x",
            "a\u{202e}b",
        ] {
            assert!(check_file_stem(bad).is_err(), "{bad:?}");
        }
        for good in ["fig3", "my-map_2", "Fig3.draft"] {
            assert!(check_file_stem(good).is_ok(), "{good}");
        }
    }
}
