//! Batch machinery shared by every command that runs many cases and writes
//! one line per case (`sweep` and `figure`): in-order execution that
//! can be interrupted, resuming an interrupted output file, slicing a job
//! list into shards and merging the shards back.
//!
//! Everything here is independent of the physics and of the output format:
//! a job is any `Sync` value, a line's identity is a string `key` that the
//! caller derives from its job (for `sweep`: `lambda,phi,"initial"`).
//!
//! * In-order interruptible execution lives in
//!   [`crate::analysis::ordered`] (re-exported here): it is below the
//!   sweeps that use it.
//! * [`resume_point`] reads an interrupted output and says how many of its
//!   lines to keep; [`merge`] orders the lines of shard outputs by the
//!   unsharded job list; [`Shard`] is the `K/N` slice.

use std::collections::{HashMap, VecDeque};
use std::ops::Range;

pub use crate::analysis::ordered::{run_ordered, Abort, Interrupt, Progress, StopLevel};

/// A bad `K/N` shard.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    /// Not `K/N`.
    #[error("'{0}' is not a shard: expected K/N with whole numbers 1 <= K <= N (e.g. 3/16)")]
    Syntax(String),
    #[error(
        "shard {index}/{count} is out of range: expected K/N with 1 <= K <= N <= {max}",
        max = Shard::MAX_COUNT
    )]
    /// `K` or `N` out of range.
    OutOfRange {
        /// `K`.
        index: usize,
        /// `N`.
        count: usize,
    },
}

/// The `K`-th of `N` disjoint slices of a job list (`1 <= K <= N`).
///
/// Slices are strided: job `i` (0-based) belongs to shard
/// `K = (i mod N) + 1`. Neighbouring jobs of a sweep cost about the same
/// (the cost grows with `lambda`), so striding gives every shard a similar
/// share of cheap and expensive runs. The union of the `N` slices is the
/// whole list, and no job is in two slices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    index: usize,
    count: usize,
}

impl Shard {
    /// Largest number of shards (any batch system's array limit is lower).
    pub const MAX_COUNT: usize = 1_000_000;

    /// The `index`-th of `count` slices.
    ///
    /// # Errors
    ///
    /// [`ShardError::OutOfRange`] unless `1 <= index <= count <= MAX_COUNT`.
    pub fn new(index: usize, count: usize) -> Result<Self, ShardError> {
        if index == 0 || index > count || count > Self::MAX_COUNT {
            return Err(ShardError::OutOfRange { index, count });
        }
        Ok(Self { index, count })
    }

    /// Read `K/N`, e.g. `3/16`.
    pub fn parse(text: &str) -> Result<Self, ShardError> {
        let syntax = || ShardError::Syntax(text.to_string());
        let (k, n) = text.trim().split_once('/').ok_or_else(syntax)?;
        let k = k.trim().parse::<usize>().map_err(|_| syntax())?;
        let n = n.trim().parse::<usize>().map_err(|_| syntax())?;
        Self::new(k, n)
    }

    /// `K`, 1-based.
    pub fn index(&self) -> usize {
        self.index
    }
    /// `N`.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Does job `i` (0-based position in the full list) belong here?
    pub fn contains(&self, i: usize) -> bool {
        i % self.count == self.index - 1
    }

    /// This shard's jobs, in list order.
    pub fn select<T: Clone>(&self, jobs: &[T]) -> Vec<T> {
        jobs.iter()
            .skip(self.index - 1)
            .step_by(self.count)
            .cloned()
            .collect()
    }

    /// This shard's groups, whole and in list order: groups `K`, `K+N`,
    /// `K+2N`, ... of `groups` (ranges of `items`, such as a sweep's runs
    /// of one `lambda` and `phi`, which share cached slip rates: see
    /// [`crate::analysis::sweep::groups`]).
    pub fn select_groups<T: Clone>(&self, items: &[T], groups: &[Range<usize>]) -> Vec<T> {
        groups
            .iter()
            .skip(self.index - 1)
            .step_by(self.count)
            .flat_map(|g| items[g.clone()].iter().cloned())
            .collect()
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// An output file that cannot be resumed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ResumeError {
    /// The header differs.
    #[error("it does not start with this command's header (comment lines and then '{expected}')")]
    Header {
        /// The expected column header.
        expected: String,
    },
    /// Not text.
    #[error("it is not UTF-8 text")]
    NotText,
    /// A row of another job.
    #[error(
        "line {line} is for {found}, but this command's run number {run} is {expected}: the file comes from different flags"
    )]
    Mismatch {
        /// 1-based line number.
        line: usize,
        /// 1-based run number.
        run: usize,
        /// The row's key.
        found: String,
        /// The job's key.
        expected: String,
    },
    /// A row that does not validate.
    #[error("line {line} is not a valid row ({why}): '{text}'")]
    Malformed {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        why: String,
        /// The line, escaped.
        text: String,
    },
    /// More rows than jobs.
    #[error("it has {found} rows, more than the {jobs} runs of this command")]
    TooMany {
        /// Rows found.
        found: usize,
        /// Jobs of the command.
        jobs: usize,
    },
}

/// Where an interrupted output file resumes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResumePoint {
    /// Rows to keep: the first `kept` jobs are done.
    pub kept: usize,
    /// Bytes to keep: the header and the kept rows, each with its newline.
    /// Anything after (an incomplete last line) is cut off.
    pub bytes: usize,
    /// False when not even the header is complete: write it again.
    pub has_header: bool,
}

/// Read an interrupted output: the header (which may span several lines,
/// such as `# key = value` comment lines and the column names), then
/// complete lines (ending in a newline) whose keys are `keys[0], keys[1],
/// ...` in order. `key_of` validates a line and extracts its key, or says
/// what is wrong with it. A last line
/// without its newline was cut by the interruption and is dropped; any
/// other mismatch is an error, so that a file from other flags is never
/// overwritten.
pub fn resume_point<K: AsRef<str>>(
    content: &[u8],
    header: &str,
    keys: &[K],
    key_of: impl Fn(&str) -> Result<&str, String>,
) -> Result<ResumePoint, ResumeError> {
    let header_lines = header.matches('\n').count() + 1;
    let text = std::str::from_utf8(content).or_else(|e| {
        // A multi-byte character cut at the very end is an interrupted
        // write; anything else is not our file.
        if e.error_len().is_none() {
            Ok(std::str::from_utf8(&content[..e.valid_up_to()]).expect("valid prefix"))
        } else {
            Err(ResumeError::NotText)
        }
    })?;
    let header_line = format!("{header}\n");
    if !text.starts_with(&header_line) {
        if header_line.starts_with(text) {
            return Ok(ResumePoint {
                kept: 0,
                bytes: 0,
                has_header: false,
            });
        }
        return Err(ResumeError::Header {
            expected: header.lines().last().unwrap_or_default().to_string(),
        });
    }
    let mut bytes = header_line.len();
    let mut kept = 0;
    let mut rest = &text[bytes..];
    while let Some(end) = rest.find('\n') {
        let line = &rest[..end];
        let number = kept + header_lines + 1;
        let key = key_of(line).map_err(|why| ResumeError::Malformed {
            line: number,
            why,
            text: crate::io::read::escape_text(line, 120),
        })?;
        let Some(expected) = keys.get(kept) else {
            return Err(ResumeError::TooMany {
                found: kept + 1 + rest[end + 1..].matches('\n').count(),
                jobs: keys.len(),
            });
        };
        if key != expected.as_ref() {
            return Err(ResumeError::Mismatch {
                line: number,
                run: kept + 1,
                found: key.to_string(),
                expected: expected.as_ref().to_string(),
            });
        }
        kept += 1;
        bytes += end + 1;
        rest = &rest[end + 1..];
    }
    Ok(ResumePoint {
        kept,
        bytes,
        has_header: true,
    })
}

/// Shard outputs that do not merge into the full output.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MergeError {
    /// An input's header differs.
    #[error("{file}: it does not start with this command's header (comment lines and then '{expected}')")]
    Header {
        /// The input.
        file: String,
        /// The expected column header.
        expected: String,
    },
    /// An input is not text.
    #[error("{file}: it is not UTF-8 text")]
    NotText {
        /// The input.
        file: String,
    },
    /// A row that does not validate.
    #[error("{file} line {line}: not a valid row ({why}): '{text}'")]
    Malformed {
        /// The input.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        why: String,
        /// The line, escaped.
        text: String,
    },
    /// A row of no job, or of a job already found.
    #[error("{file} line {line}: {key} is not a run of these flags, or it appears twice")]
    Unexpected {
        /// The input.
        file: String,
        /// 1-based line number.
        line: usize,
        /// The row's key.
        key: String,
    },
    /// Jobs in no input.
    #[error(
        "{missing} of {total} runs are in none of the files (the first is {first}): finish every shard (sweep --shard K/N --resume) and merge again"
    )]
    Missing {
        /// Jobs missing.
        missing: usize,
        /// Jobs in all.
        total: usize,
        /// The first missing job's key.
        first: String,
    },
}

/// Put the rows of several shard outputs into job order. `keys` is the
/// full (unsharded) job list's keys; each input is `(name, content)`.
/// Every input must start with `header`; a last line without its newline
/// (an interrupted shard) is ignored. Every job must be found exactly once
/// (jobs with equal keys are interchangeable: their rows are identical).
/// Returns the merged text, header included, byte for byte what one
/// unsharded run writes.
pub fn merge<K: AsRef<str>>(
    header: &str,
    keys: &[K],
    inputs: &[(String, Vec<u8>)],
    key_of: impl Fn(&str) -> Result<&str, String>,
) -> Result<String, MergeError> {
    let header_lines = header.matches('\n').count() + 1;
    let mut slots: HashMap<&str, VecDeque<usize>> = HashMap::new();
    for (i, k) in keys.iter().enumerate() {
        slots.entry(k.as_ref()).or_default().push_back(i);
    }
    let mut rows: Vec<Option<&str>> = vec![None; keys.len()];
    let header_line = format!("{header}\n");
    for (file, content) in inputs {
        let text =
            std::str::from_utf8(content).map_err(|_| MergeError::NotText { file: file.clone() })?;
        let body = text
            .strip_prefix(&header_line)
            .ok_or_else(|| MergeError::Header {
                file: file.clone(),
                expected: header.lines().last().unwrap_or_default().to_string(),
            })?;
        // Only complete lines: split_inclusive keeps the newline.
        for (n, line) in body.split_inclusive('\n').enumerate() {
            let Some(line) = line.strip_suffix('\n') else {
                break;
            };
            let number = n + header_lines + 1;
            let key = key_of(line).map_err(|why| MergeError::Malformed {
                file: file.clone(),
                line: number,
                why,
                text: crate::io::read::escape_text(line, 120),
            })?;
            let slot = slots
                .get_mut(key)
                .and_then(VecDeque::pop_front)
                .ok_or_else(|| MergeError::Unexpected {
                    file: file.clone(),
                    line: number,
                    key: key.to_string(),
                })?;
            rows[slot] = Some(line);
        }
    }
    let missing = rows.iter().filter(|r| r.is_none()).count();
    if let Some(first) = rows.iter().position(Option::is_none) {
        return Err(MergeError::Missing {
            missing,
            total: keys.len(),
            first: keys[first].as_ref().to_string(),
        });
    }
    let mut out = String::with_capacity(inputs.iter().map(|(_, c)| c.len()).sum());
    out.push_str(&header_line);
    for row in rows.into_iter().flatten() {
        out.push_str(row);
        out.push('\n');
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Lines `key,value`; the key is the first field.
    fn key_of(line: &str) -> Result<&str, String> {
        line.split_once(',')
            .map(|(k, _)| k)
            .ok_or_else(|| "no comma".to_string())
    }

    fn full(keys: &[&str]) -> String {
        let mut s = String::from("k,v\n");
        for k in keys {
            s.push_str(&format!("{k},x{k}\n"));
        }
        s
    }

    #[test]
    fn shards_partition_the_list() {
        let jobs: Vec<usize> = (0..23).collect();
        for n in [1, 2, 5, 23, 40] {
            let mut all: Vec<usize> = (1..=n)
                .flat_map(|k| Shard::new(k, n).unwrap().select(&jobs))
                .collect();
            all.sort_unstable();
            assert_eq!(all, jobs, "{n} shards");
            for k in 1..=n {
                let s = Shard::new(k, n).unwrap();
                assert!(s.select(&jobs).iter().all(|&i| s.contains(i)));
            }
        }
    }

    #[test]
    fn shards_of_groups_partition_the_list_and_keep_groups_whole() {
        // Items (group, member): groups of 3, 1 and 4 members, and so on.
        let sizes = [3, 1, 4, 1, 5, 2, 6];
        let items: Vec<(usize, usize)> = sizes
            .iter()
            .enumerate()
            .flat_map(|(g, &m)| (0..m).map(move |i| (g, i)))
            .collect();
        let mut groups = Vec::new();
        for &m in &sizes {
            let start = groups.last().map_or(0, |g: &Range<usize>| g.end);
            groups.push(start..start + m);
        }
        for n in [1, 2, 3, 7, 9] {
            let mut all = Vec::new();
            for k in 1..=n {
                let mine = Shard::new(k, n).unwrap().select_groups(&items, &groups);
                // Groups K, K+N, ... whole, in list order.
                let want: Vec<(usize, usize)> = items
                    .iter()
                    .copied()
                    .filter(|&(g, _)| g % n == k - 1)
                    .collect();
                assert_eq!(mine, want, "shard {k}/{n}");
                all.extend(mine);
            }
            all.sort_unstable();
            assert_eq!(all, items, "{n} shards");
        }
    }

    #[test]
    fn shard_syntax_and_range() {
        assert_eq!(Shard::parse(" 3/16 ").unwrap(), Shard::new(3, 16).unwrap());
        for bad in ["0/4", "5/4", "1/0", "1/2000000"] {
            assert!(
                matches!(Shard::parse(bad), Err(ShardError::OutOfRange { .. })),
                "{bad}"
            );
        }
        for bad in ["", "3", "a/b", "-1/4", "1/4/5", "1.5/4"] {
            assert!(
                matches!(Shard::parse(bad), Err(ShardError::Syntax(_))),
                "{bad}"
            );
        }
    }

    #[test]
    fn results_come_in_order_and_a_drain_keeps_a_prefix() {
        let jobs: Vec<u64> = (0..200).collect();
        let interrupt = Interrupt::new();
        let mut got = Vec::new();
        let progress = run_ordered(
            &jobs,
            &interrupt,
            |&j, _| {
                if j == 50 {
                    interrupt.raise(StopLevel::Drain);
                }
                // Uneven work so that results finish out of order.
                std::thread::sleep(std::time::Duration::from_micros((j * 37) % 300));
                Some(j * 2)
            },
            |i, r| {
                assert_eq!(r, 2 * i as u64);
                got.push(r);
                Ok::<_, ()>(())
            },
        )
        .unwrap();
        // Job 50 and everything before it had started: all are delivered;
        // after the drain each worker finishes at most the job it holds.
        let workers = rayon::current_num_threads();
        assert!(progress.delivered >= 51, "{progress:?}");
        assert!(progress.delivered <= 51 + workers, "{progress:?}");
        let expected: Vec<u64> = (0..progress.delivered as u64).map(|j| 2 * j).collect();
        assert_eq!(got, expected);
    }

    #[test]
    fn an_abort_leaves_a_gap_and_nothing_after_it() {
        let jobs: Vec<usize> = (0..100).collect();
        let interrupt = Interrupt::new();
        let progress = run_ordered(
            &jobs,
            &interrupt,
            |&j, abort| {
                if j == 10 {
                    interrupt.raise(StopLevel::Abort);
                }
                if abort.requested() {
                    None
                } else {
                    Some(j)
                }
            },
            |i, r| {
                assert_eq!(i, r);
                Ok::<_, ()>(())
            },
        )
        .unwrap();
        assert!(progress.delivered <= 10);
        assert!(!progress.is_complete());
    }

    #[test]
    fn a_delivery_error_stops_the_batch() {
        let jobs: Vec<usize> = (0..1000).collect();
        let interrupt = Interrupt::new();
        let started = AtomicUsize::new(0);
        let result = run_ordered(
            &jobs,
            &interrupt,
            |&j, _| {
                started.fetch_add(1, Ordering::SeqCst);
                std::thread::sleep(std::time::Duration::from_micros(200));
                Some(j)
            },
            |i, _| if i == 5 { Err("disk full") } else { Ok(()) },
        );
        assert_eq!(result, Err("disk full"));
        assert!(started.load(Ordering::SeqCst) < 1000);
    }

    #[test]
    fn interrupt_escalates() {
        let i = Interrupt::new();
        assert_eq!(i.level(), StopLevel::Running);
        assert_eq!(i.request(), 1);
        assert!(i.is_draining() && !i.is_aborting());
        i.request();
        assert!(i.is_aborting());
        i.raise(StopLevel::Drain);
        assert_eq!(i.level(), StopLevel::Abort);
    }

    #[test]
    fn resume_keeps_complete_matching_lines() {
        let keys = ["a", "b", "c", "d"];
        let text = full(&keys);
        for cut in 0..=text.len() {
            let p = resume_point(&text.as_bytes()[..cut], "k,v", &keys, key_of).unwrap();
            let kept_text = &text[..p.bytes];
            assert!(kept_text.ends_with('\n') || p.bytes == 0);
            assert_eq!(
                kept_text.matches('\n').count(),
                p.kept + usize::from(p.has_header)
            );
            // The kept part plus the rows not kept is the whole file.
            let mut rebuilt = if p.has_header {
                kept_text.to_string()
            } else {
                "k,v\n".to_string()
            };
            for k in &keys[p.kept..] {
                rebuilt.push_str(&format!("{k},x{k}\n"));
            }
            assert_eq!(rebuilt, text, "cut at {cut}");
        }
    }

    #[test]
    fn resume_refuses_other_files() {
        let keys = ["a", "b"];
        assert!(matches!(
            resume_point(b"other,header\na,1\n", "k,v", &keys, key_of),
            Err(ResumeError::Header { .. })
        ));
        assert!(matches!(
            resume_point(b"k,v\nb,1\n", "k,v", &keys, key_of),
            Err(ResumeError::Mismatch { line: 2, .. })
        ));
        assert!(matches!(
            resume_point(b"k,v\na,1\nb,2\nc,3\n", "k,v", &keys, key_of),
            Err(ResumeError::TooMany { found: 3, jobs: 2 })
        ));
        assert!(matches!(
            resume_point(b"k,v\nnocomma\n", "k,v", &keys, key_of),
            Err(ResumeError::Malformed { line: 2, .. })
        ));
        assert!(matches!(
            resume_point(b"k,v\n\xff\xfe,1\n", "k,v", &keys, key_of),
            Err(ResumeError::NotText)
        ));
    }

    #[test]
    fn merge_restores_the_unsharded_order() {
        let keys = ["a", "b", "c", "b", "e", "f", "g"];
        let whole = full(&keys);
        for n in 1..=4 {
            let inputs: Vec<(String, Vec<u8>)> = (1..=n)
                .rev()
                .map(|k| {
                    let mine = Shard::new(k, n).unwrap().select(&keys);
                    (format!("shard{k}"), full(&mine).into_bytes())
                })
                .collect();
            assert_eq!(merge("k,v", &keys, &inputs, key_of).unwrap(), whole);
        }
    }

    #[test]
    fn merge_finds_gaps_strangers_and_duplicates() {
        let keys = ["a", "b", "c"];
        let one = |t: &str| vec![("s".to_string(), t.as_bytes().to_vec())];
        assert!(matches!(
            merge("k,v", &keys, &one("k,v\na,1\nb,1\n"), key_of),
            Err(MergeError::Missing { missing: 1, .. })
        ));
        // An interrupted last line does not count.
        assert!(matches!(
            merge("k,v", &keys, &one("k,v\na,1\nb,1\nc,1"), key_of),
            Err(MergeError::Missing { missing: 1, .. })
        ));
        assert!(matches!(
            merge("k,v", &keys, &one("k,v\na,1\nz,1\n"), key_of),
            Err(MergeError::Unexpected { line: 3, .. })
        ));
        assert!(matches!(
            merge("k,v", &keys, &one("k,v\na,1\na,1\n"), key_of),
            Err(MergeError::Unexpected { line: 3, .. })
        ));
        assert!(matches!(
            merge("k,v", &keys, &one("x,y\na,1\n"), key_of),
            Err(MergeError::Header { .. })
        ));
    }
}
