//! In-order parallel execution that can be interrupted: [`run_ordered`]
//! runs jobs on worker threads that take them in list order and hands the
//! results back to the calling thread in list order, so an output written as
//! results arrive is always a prefix of the complete output, whenever it
//! stops. [`Interrupt`] is the stop request it obeys: the first request lets
//! the runs in progress finish (nothing finished is lost), the second asks
//! them to abort at their next increment.
//!
//! It knows nothing of the physics or of output formats; sweeps
//! ([`crate::analysis::sweep`]) run on it, and [`crate::io::batch`] adds
//! resume, shards and merge on top.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicUsize, Ordering};
use std::sync::mpsc;

/// How far a batch has been asked to stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum StopLevel {
    /// No request.
    Running,
    /// Start no new job; let the ones in progress finish.
    Drain,
    /// Abandon the jobs in progress as well.
    Abort,
}

/// A stop request shared between whoever asks (a Ctrl-C handler, a UI) and
/// a running batch. Requests only ever escalate.
#[derive(Debug, Default)]
pub struct Interrupt {
    /// Number of requests so far.
    requests: AtomicU8,
}

impl Interrupt {
    /// No request yet.
    pub const fn new() -> Self {
        Self {
            requests: AtomicU8::new(0),
        }
    }

    /// One more request (a Ctrl-C press): `Running -> Drain -> Abort`.
    /// Returns how many requests there have been, this one included.
    pub fn request(&self) -> u8 {
        self.requests
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |r| {
                Some(r.saturating_add(1))
            })
            .map_or(u8::MAX, |r| r.saturating_add(1))
    }

    /// Raise the request to at least `level`.
    pub fn raise(&self, level: StopLevel) {
        let want = match level {
            StopLevel::Running => 0,
            StopLevel::Drain => 1,
            StopLevel::Abort => 2,
        };
        self.requests.fetch_max(want, Ordering::SeqCst);
    }

    /// How far the batch has been asked to stop.
    pub fn level(&self) -> StopLevel {
        match self.requests.load(Ordering::SeqCst) {
            0 => StopLevel::Running,
            1 => StopLevel::Drain,
            _ => StopLevel::Abort,
        }
    }

    /// No new job may start.
    pub fn is_draining(&self) -> bool {
        self.level() >= StopLevel::Drain
    }

    /// Jobs in progress should stop at their next increment.
    pub fn is_aborting(&self) -> bool {
        self.level() >= StopLevel::Abort
    }
}

/// What a job sees while it runs: whether it should give up now.
#[derive(Clone, Copy)]
pub struct Abort<'a> {
    interrupt: &'a Interrupt,
    failed: &'a AtomicBool,
}

impl Abort<'_> {
    /// True when the job should stop at once (its result would be dropped).
    pub fn requested(&self) -> bool {
        self.failed.load(Ordering::Relaxed) || self.interrupt.is_aborting()
    }

    /// True when no further job should start (a drain or more was asked):
    /// a job made of several runs stops before its next one.
    pub fn draining(&self) -> bool {
        self.failed.load(Ordering::Relaxed) || self.interrupt.is_draining()
    }
}

/// How far [`run_ordered`] got.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    /// Results handed to `deliver`: always the first `delivered` jobs.
    pub delivered: usize,
    /// Jobs in the list.
    pub total: usize,
}

impl Progress {
    /// Every job was delivered.
    pub fn is_complete(&self) -> bool {
        self.delivered == self.total
    }
}

/// Run `work` on every job with one worker per thread of rayon's pool
/// (`RAYON_NUM_THREADS` sets it), and hand the results to `deliver` on the
/// calling thread in job order.
///
/// Workers take jobs in list order, so the results waiting for a slower
/// predecessor are few (at most one per worker). `work` returns `None` when
/// it gave up because [`Abort::requested`]; no result after such a gap is
/// delivered. When `interrupt` drains, no job starts and every job already
/// started is finished and delivered; when it aborts, jobs in progress are
/// asked to stop. An error from `deliver` stops the batch the same way and
/// is returned once the workers have stopped. The loop is bounded by the
/// job list: nothing waits for a job that no worker will run.
pub fn run_ordered<J, R, E>(
    jobs: &[J],
    interrupt: &Interrupt,
    work: impl Fn(&J, Abort<'_>) -> Option<R> + Sync,
    mut deliver: impl FnMut(usize, R) -> Result<(), E>,
) -> Result<Progress, E>
where
    J: Sync,
    R: Send,
{
    let total = jobs.len();
    let workers = rayon::current_num_threads().clamp(1, total.max(1));
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let mut delivered = 0;
    let mut error = None;
    std::thread::scope(|scope| {
        let (tx, rx) = mpsc::channel::<(usize, Option<R>)>();
        for _ in 0..workers {
            let tx = tx.clone();
            let (next, failed, work) = (&next, &failed, &work);
            scope.spawn(move || loop {
                if interrupt.is_draining() || failed.load(Ordering::Relaxed) {
                    return;
                }
                let i = next.fetch_add(1, Ordering::SeqCst);
                if i >= total {
                    return;
                }
                let abort = Abort { interrupt, failed };
                let result = work(&jobs[i], abort);
                if tx.send((i, result)).is_err() {
                    return;
                }
            });
        }
        drop(tx);
        // Results that arrived before their predecessors.
        let mut waiting: BTreeMap<usize, Option<R>> = BTreeMap::new();
        let mut gap = false;
        // Ends when every worker has returned (their senders dropped).
        for (i, result) in rx {
            waiting.insert(i, result);
            while !gap && error.is_none() {
                let Some(result) = waiting.remove(&delivered) else {
                    break;
                };
                match result {
                    None => {
                        // Nothing after a gap can be delivered: stop.
                        gap = true;
                        failed.store(true, Ordering::SeqCst);
                    }
                    Some(r) => match deliver(delivered, r) {
                        Ok(()) => delivered += 1,
                        Err(e) => {
                            error = Some(e);
                            failed.store(true, Ordering::SeqCst);
                        }
                    },
                }
            }
        }
    });
    match error {
        Some(e) => Err(e),
        None => Ok(Progress { delivered, total }),
    }
}
