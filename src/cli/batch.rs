//! The command-line side of batch runs, shared by `sweep` and `figure`:
//! Ctrl-C, an output file that can be resumed, line-by-line writing that
//! survives a closed pipe, and [`stream_sweep`], which does all of it for
//! a sweep's rows.
//!
//! How a batch command uses it (see [`stream_sweep`]):
//!
//! 1. Build the job list and each job's line key; slice it with
//!    `--shard K/N` ([`shakedown::io::batch::Shard`]).
//! 2. [`Output::open`] the `--out` file (or stdout). With `--resume` it keeps
//!    the complete lines that match the job list's first keys, cuts off the
//!    rest, and says how many jobs are done already.
//! 3. [`ctrl_c`] gives the process-wide [`Interrupt`] that Ctrl-C raises.
//! 4. Run the remaining jobs with
//!    [`shakedown::io::batch::run_ordered`] (or `SweepSpec::run_ordered`),
//!    writing each line with [`Output::line`] as it is delivered.
//! 5. [`Output::finish`]; if the interrupt was raised, tell the user how to
//!    resume and exit with [`INTERRUPTED`].

use std::fs::{File, OpenOptions};
use std::io::{self, IsTerminal, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::OnceLock;

use anyhow::{anyhow, Result};
use indicatif::{ProgressBar, ProgressStyle};
use shakedown::analysis::sweep::{Job, Row, SweepSpec, CSV_HEADER};
use shakedown::io::batch::{resume_point, Interrupt};
use shakedown::io::csv::{check_preamble, sweep_metadata, sweep_row_key_capped, Metadata};
use shakedown::io::output::{is_nonempty_file, same_file, LockError, OutputLock, WriteError};
use shakedown::io::read::{read_capped, ReadError};

use super::InputError;

/// Take the lock on the output `path` given with `flag`; a second writer,
/// or a folder where the lock cannot be made, is refused (bad input).
pub fn lock_output(flag: &str, path: &Path) -> Result<OutputLock> {
    OutputLock::acquire(path).map_err(|e| match e {
        LockError::Busy { .. } | LockError::BusyFile | LockError::NotRegular { .. } => {
            anyhow!(InputError(format!("{flag} {}: {e}", path.display())))
        }
        LockError::Io { source, .. } => anyhow!(InputError(format!(
            "{flag} {}: cannot create it: {source}: expected a writable file path",
            path.display()
        ))),
    })
}

/// [`lock_output`] for an output that may be a device or FIFO
/// (`/dev/stdout`): those are written in place and not locked.
pub fn lock_file_output(flag: &str, path: &Path) -> Result<Option<OutputLock>> {
    let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file());
    if special {
        return Ok(None);
    }
    lock_output(flag, path).map(Some)
}

/// `--out -` means stdout, as in most tools, rather than a file named `-`.
pub fn dash_is_stdout(out: Option<PathBuf>) -> Option<PathBuf> {
    out.filter(|p| p.as_os_str() != "-")
}

/// Refuse an output that is one of the inputs (`(flag, path)` pairs): it
/// would be destroyed before it is read.
pub fn refuse_input_as_output(flag: &str, out: &Path, inputs: &[(&str, &Path)]) -> Result<()> {
    for (what, input) in inputs {
        if same_file(out, input) {
            return Err(anyhow!(InputError(format!(
                "{flag} {}: it is the {what} {}: write the output to another file",
                out.display(),
                input.display()
            ))));
        }
    }
    Ok(())
}

/// A failed whole-file write as an error: bad input when the path is wrong
/// (exit 2), an environment failure otherwise (a full disk: exit 1).
pub fn write_error(flag: &str, e: WriteError) -> anyhow::Error {
    if e.is_input() {
        anyhow!(InputError(format!(
            "{flag} {e}: expected a writable file path"
        )))
    } else {
        anyhow!("{flag} {e}")
    }
}

/// Write a whole file atomically ([`shakedown::io::output::write_atomic`]).
pub fn write_file(flag: &str, path: &Path, bytes: &[u8]) -> Result<()> {
    shakedown::io::output::write_atomic(path, bytes).map_err(|e| write_error(flag, e))
}

/// Exit status after an interrupt: 128 + SIGINT, what shells report for a
/// process that Ctrl-C ended.
pub const INTERRUPTED: u8 = 130;

static INTERRUPT: Interrupt = Interrupt::new();
static HANDLER: OnceLock<Result<(), String>> = OnceLock::new();

/// The interrupt that Ctrl-C (SIGINT) raises, with the handler installed on
/// first use. First press: start no new run, finish the runs in progress.
/// Second: abandon those too. Third: exit at once (status 130). Even then,
/// or after a hard kill (a batch system's time limit), the output holds
/// complete lines but for at most the last one, which `--resume` discards.
pub fn ctrl_c() -> Result<&'static Interrupt> {
    let installed = HANDLER.get_or_init(|| {
        ctrlc::set_handler(|| match INTERRUPT.request() {
            1 => errln!(
                "\ninterrupted: finishing the runs in progress (Ctrl-C again to abandon them)"
            ),
            2 => errln!("\ninterrupted: abandoning the runs in progress"),
            _ => std::process::exit(i32::from(INTERRUPTED)),
        })
        .map_err(|e| e.to_string())
    });
    match installed {
        Ok(()) => Ok(&INTERRUPT),
        Err(e) => Err(anyhow!("cannot install the Ctrl-C handler: {e}")),
    }
}

/// Is this (anywhere in its chain) a write to a closed pipe, as in
/// `shakedown sweep | head`? Then the reader has all it wants: stop quietly.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<io::Error>()
            .is_some_and(|io| io.kind() == io::ErrorKind::BrokenPipe)
    })
}

/// Print to stdout. A closed pipe (`shakedown presets | head -1`) is
/// returned as an error that [`is_broken_pipe`] recognises, and `main`
/// ends quietly with status 0; any other failure (a full disk) is an
/// environment error (status 1).
pub fn print_stdout(text: &str) -> Result<()> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Err(anyhow::Error::new(e)),
        Err(e) => Err(anyhow!("cannot write to stdout: {e}")),
    }
}

/// Write `text` to stderr. If that fails (`2>/dev/full`), nothing more
/// can be reported: end the process quietly with status 1.
pub fn print_stderr(text: &str) {
    let mut err = io::stderr().lock();
    if err
        .write_all(text.as_bytes())
        .and_then(|()| err.flush())
        .is_err()
    {
        std::process::exit(1);
    }
}

/// Where the lines go: a file (that may be resumed) or stdout.
pub struct Output {
    sink: Box<dyn Write>,
    path: Option<PathBuf>,
    /// Lines already in the file before this run (resumed).
    pub kept: usize,
    /// Lines written by this run.
    pub written: usize,
    /// Held while the output is open.
    _lock: Option<OutputLock>,
}

impl Output {
    /// Open `--out` (or stdout when `None`), writing `meta`'s comment lines
    /// and then `columns` as the header.
    ///
    /// A file is locked first ([`OutputLock`]): a second writer is refused.
    /// Without `resume` an existing non-empty file is refused unless
    /// `force`; otherwise it is created or truncated and the header
    /// written. With `resume` an existing file (read through a size cap,
    /// regular files only) must carry the same comment lines (the first
    /// differing key is named) and hold valid rows (by `key_of`) whose keys
    /// are the first of `keys`; those are kept, an incomplete last line is
    /// cut off, and [`Output::kept`] says how many jobs to skip. A missing
    /// file starts afresh. Whatever is refused is left untouched.
    #[allow(clippy::too_many_arguments)]
    pub fn open<K: AsRef<str>>(
        path: Option<&Path>,
        resume: bool,
        force: bool,
        meta: &Metadata,
        columns: &str,
        keys: &[K],
        key_of: impl Fn(&str) -> Result<&str, String>,
    ) -> Result<Output> {
        let header = meta.preamble(columns);
        let Some(path) = path else {
            if resume {
                return Err(anyhow!(InputError(
                    "--resume needs --out FILE: it continues an interrupted output file".into()
                )));
            }
            let mut out = Output {
                sink: Box::new(io::BufWriter::new(io::stdout())),
                path: None,
                kept: 0,
                written: 0,
                _lock: None,
            };
            out.raw(&format!("{header}\n"))?;
            return Ok(out);
        };
        let shown = path.display();
        let cannot = |what: &str, e: io::Error| {
            anyhow!(InputError(format!(
                "--out {shown}: cannot {what}: {e}: expected a writable file path"
            )))
        };
        // Devices and FIFOs (/dev/stdout, /dev/null) are written in place
        // and never locked or resumed.
        let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir());
        if resume && special {
            return Err(anyhow!(InputError(format!(
                "--resume --out {shown}: cannot resume it: it is not a regular file (a FIFO or device): expected a file"
            ))));
        }
        let mut lock = if special || path.is_dir() {
            None
        } else {
            Some(lock_output("--out", path)?)
        };
        let existing = if resume && !special {
            let cap = header.len() as u64 + 4096 + 512 * (keys.len() as u64 + 1);
            match read_capped(path, cap) {
                Ok(bytes) => Some(bytes),
                Err(ReadError::Io(_)) if !path.exists() => None,
                Err(e) => {
                    return Err(anyhow!(InputError(format!(
                        "--resume --out {shown}: cannot resume this file: {e}"
                    ))))
                }
            }
        } else {
            None
        };
        if !resume && !force && is_nonempty_file(path) {
            return Err(anyhow!(InputError(format!(
                "--out {shown}: it exists and is not empty: add --resume to continue it, or --force to replace it"
            ))));
        }
        let (file, kept, has_header) = match existing {
            None => {
                // Open without truncating, lock the file itself (a hard link
                // to a file another process writes is refused), then empty it.
                let file = OpenOptions::new()
                    .write(true)
                    .create(true)
                    .truncate(false)
                    .open(path)
                    .map_err(|e| cannot("create it", e))?;
                pin(&mut lock, &file, path)?;
                if !special {
                    file.set_len(0).map_err(|e| cannot("empty it", e))?;
                }
                (file, 0, false)
            }
            Some(bytes) => {
                let refuse = |e: &dyn std::fmt::Display| {
                    anyhow!(InputError(format!(
                        "--resume --out {shown}: cannot resume this file: {e}"
                    )))
                };
                check_preamble(&bytes, meta).map_err(|e| refuse(&e))?;
                let point = resume_point(&bytes, &header, keys, key_of).map_err(|e| refuse(&e))?;
                let mut file = OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| cannot("open it to resume", e))?;
                pin(&mut lock, &file, path)?;
                file.set_len(point.bytes as u64)
                    .and_then(|()| file.seek(SeekFrom::End(0)).map(|_| ()))
                    .map_err(|e| cannot("cut off its incomplete last line", e))?;
                (file, point.kept, point.has_header)
            }
        };
        let mut out = Output {
            sink: Box::new(io::BufWriter::new(file)),
            path: Some(path.to_path_buf()),
            kept,
            written: 0,
            _lock: lock,
        };
        if !has_header {
            out.raw(&format!("{header}\n"))?;
        }
        Ok(out)
    }

    fn raw(&mut self, text: &str) -> Result<()> {
        self.sink
            .write_all(text.as_bytes())
            .and_then(|()| self.sink.flush())
            .map_err(|e| self.write_error(e))
    }

    fn write_error(&self, e: io::Error) -> anyhow::Error {
        match &self.path {
            // Keep the io::Error in the chain so a closed pipe is recognised.
            None => anyhow::Error::new(e).context("cannot write to stdout"),
            Some(p) => {
                anyhow::Error::new(e).context(format!("--out {}: cannot write", p.display()))
            }
        }
    }

    /// Write one complete line (a newline is added) and flush it, so that
    /// the file never holds more than the last line incomplete.
    pub fn line(&mut self, line: &str) -> Result<()> {
        let mut text = String::with_capacity(line.len() + 1);
        text.push_str(line);
        text.push('\n');
        self.raw(&text)?;
        self.written += 1;
        Ok(())
    }

    /// Where the lines go, for messages.
    pub fn describe(&self) -> String {
        match &self.path {
            Some(p) => p.display().to_string(),
            None => "stdout".into(),
        }
    }

    /// Whether this output can be resumed (a file).
    pub fn is_file(&self) -> bool {
        self.path.is_some()
    }
}

/// Lock the output file `file` itself (see [`OutputLock::pin`]).
fn pin(lock: &mut Option<OutputLock>, file: &File, path: &Path) -> Result<()> {
    let Some(lock) = lock else { return Ok(()) };
    let handle = file.try_clone().map_err(|e| {
        anyhow!(InputError(format!(
            "--out {}: cannot lock it: {e}",
            path.display()
        )))
    })?;
    lock.pin(handle)
        .map_err(|e| anyhow!(InputError(format!("--out {}: {e}", path.display()))))
}

/// The end of an interrupted batch: say what is done and how to finish.
pub fn report_interrupt(out: &Output, total: usize) -> ExitCode {
    let done = out.kept + out.written;
    if out.is_file() {
        errln!(
            "interrupted: {done} of {total} runs are in {}; run the same command with --resume to finish",
            out.describe()
        );
    } else {
        errln!("interrupted: {done} of {total} runs were written");
    }
    ExitCode::from(INTERRUPTED)
}

/// A progress bar on stderr when it is a terminal.
pub fn progress(len: usize) -> ProgressBar {
    if std::io::stderr().is_terminal() {
        let b = ProgressBar::new(len as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} runs  {elapsed} (eta {eta})")
                .expect("valid template"),
        );
        b
    } else {
        ProgressBar::hidden()
    }
}

/// How [`stream_sweep`] ended.
pub struct Streamed {
    /// The output, still open and locked: [`Output::kept`] rows were there
    /// before, [`Output::written`] were added.
    pub out: Output,
    /// Every job is in the output; false when Ctrl-C stopped the runs.
    pub complete: bool,
}

/// Run the jobs of `spec` that are not yet in the output and stream their
/// rows into it: what `sweep` and a sweep figure both do.
///
/// The output (`target`, or stdout) is opened with the sweep's metadata
/// and [`CSV_HEADER`] ([`Output::open`]; `resume` keeps the complete rows
/// whose keys are the first of `keys`, one key per job), a "resuming"
/// note says how many runs are already done, and the rest run in parallel
/// under [`ctrl_c`] with a [`progress`] bar. Rows are written in job
/// order, one flushed line each, so that an interrupt leaves a file of
/// complete rows (a prefix of the full table) that `--resume` continues.
/// `each` sees every row written, with the bar (to print above it).
///
/// # Errors
///
/// The output cannot be opened or resumed (bad input), a line cannot be
/// written (a closed pipe: see [`is_broken_pipe`]), or the Ctrl-C handler
/// cannot be installed.
pub fn stream_sweep(
    spec: &SweepSpec,
    jobs: &[Job],
    keys: &[String],
    target: Option<&Path>,
    resume: bool,
    force: bool,
    mut each: impl FnMut(&Row, &ProgressBar),
) -> Result<Streamed> {
    let meta = sweep_metadata(spec);
    let mut out = Output::open(
        target,
        resume,
        force,
        &meta,
        CSV_HEADER,
        keys,
        sweep_row_key_capped(spec.options().convergence().max_cycles() as u64),
    )?;
    let todo = &jobs[out.kept.min(jobs.len())..];
    if out.kept > 0 {
        errln!(
            "resuming: {} of {} runs are already in {}",
            out.kept,
            jobs.len(),
            out.describe()
        );
    }
    if todo.is_empty() {
        return Ok(Streamed {
            out,
            complete: true,
        });
    }
    let interrupt = ctrl_c()?;
    let bar = progress(jobs.len());
    bar.set_position(out.kept as u64);
    bar.reset_eta();
    let result = spec.resume_ordered(jobs, out.kept, interrupt, |row| {
        out.line(&shakedown::io::sweep_csv::row_line(&row))?;
        bar.inc(1);
        each(&row, &bar);
        anyhow::Ok(())
    });
    bar.finish_and_clear();
    let complete = result?.is_complete();
    Ok(Streamed { out, complete })
}
