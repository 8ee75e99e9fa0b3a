//! The record of the run, increment by increment, within a memory budget.
//!
//! Every increment leaves a [`Record`]: the light part (load point, slip
//! directions, `W` so far, status, events) is a few hundred bytes plus one
//! byte a node; the [`Detail`] (`p`, `q`, `g` as `f32`) is twelve bytes a
//! node. When the budget is reached, older detail is decimated first (only
//! every 2nd, then 4th, ... increment keeps it), and only when the light
//! part alone fills the budget are the oldest increments dropped. The
//! newest increments always keep their detail. [`History::thinned_before`]
//! and [`History::dropped_before`] say what was lost, so the screen can.

use std::collections::VecDeque;

use super::log::LogEntry;
use crate::analysis::episodes::LockedSlip;
use crate::stepping::{Phase, Status};

/// Slip-map cell codes: the direction in the low bits, a flag on top.
/// This one: the node sticks.
pub const STICK: u8 = 0;
/// The node slips forward (`dh > 0`, `dg < 0`).
pub const FORWARD: u8 = 1;
/// The node slips backward (`dh < 0`, `dg > 0`).
pub const BACKWARD: u8 = 2;
/// Mask of the direction bits ([`STICK`], [`FORWARD`], [`BACKWARD`]).
pub const DIRECTION_MASK: u8 = 3;
/// The node went from slip to stick during this increment.
pub const NEWLY_STUCK: u8 = 4;

/// The per-node profiles of one increment, the heavy part of a record.
#[derive(Debug, Clone, PartialEq)]
pub struct Detail {
    /// Contact pressure `p` at each node, scaled by `p0`.
    pub pressure: Vec<f32>,
    /// Contact shear `q` at each node, scaled by `p0`.
    pub shear: Vec<f32>,
    /// `g` minus its mean (the rigid rotation, kept in the record).
    pub slip: Vec<f32>,
    /// `g` minus its mean before the increment, kept at advancing stick
    /// so the panel can show what the stuck nodes locked in.
    pub slip_before: Option<Vec<f32>>,
}

impl Detail {
    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + 4 * (self.pressure.len()
                + self.shear.len()
                + self.slip.len()
                + self.slip_before.as_ref().map_or(0, Vec::len))
    }
}

/// One increment as the panels draw it.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Restart generation of the run it belongs to.
    pub generation: u64,
    /// Increment number from the start of the run (0-based).
    pub increment: usize,
    /// Where the increment was taken (its cycle, its place in the cycle).
    pub phase: Phase,
    /// Where the stepper is after it.
    pub after: Phase,
    /// `omega t` at the end of the increment (or at the event it paused
    /// at), `None` in the transient.
    pub time: Option<f64>,
    /// The load point `(x, y)` at the end of the increment (or at the
    /// event it paused at).
    pub load: (f64, f64),
    /// `Some(s)`: the run paused at an event at parameter `s` of this
    /// increment, which is not finished.
    pub partial: Option<f64>,
    /// Per node: [`STICK`], [`FORWARD`] or [`BACKWARD`], maybe with
    /// [`NEWLY_STUCK`].
    pub cells: Vec<u8>,
    /// `W` of the cycle in progress so far.
    pub dissipation: f64,
    /// The rigid rotation (mean of `g`).
    pub rotation: f64,
    /// The run's status (running, steady, ended) after the increment.
    pub status: Status,
    /// What the increment did, described for the event log.
    pub events: Vec<LogEntry>,
    /// Nodes that went from slip to stick during the increment.
    pub newly_stuck: Vec<usize>,
    /// What those nodes locked in: the slip of the episode that ended, and
    /// `g` against `g` at the start of the cycle (exact values, not the
    /// `f32` of the detail, because the episode slip is often far below
    /// `g`'s round-off in `f32`).
    pub locked: Option<Box<LockedSlip>>,
    /// Sub-increments the solver took.
    pub substeps: usize,
    /// A cycle completed with this increment: its number and `W`.
    pub completed: Option<(usize, f64)>,
    /// Dropped when older detail is decimated.
    pub detail: Option<Box<Detail>>,
}

impl Record {
    /// Cycle the increment belongs to, 0 in the transient.
    pub fn cycle(&self) -> usize {
        match self.phase {
            Phase::Transient { .. } => 0,
            Phase::Cycle { cycle, .. } => cycle,
        }
    }

    /// First increment of a cycle.
    pub fn cycle_start(&self) -> bool {
        matches!(self.phase, Phase::Cycle { increment: 0, .. })
    }

    fn light_bytes(&self) -> usize {
        // Twice the inline size: the ring buffer's spare capacity.
        2 * std::mem::size_of::<Self>()
            + self.cells.len()
            + 8 * self.newly_stuck.len()
            + self.locked.as_ref().map_or(0, |l| {
                std::mem::size_of::<LockedSlip>() + 8 * 4 * l.nodes.len()
            })
            + self.events.iter().map(LogEntry::bytes).sum::<usize>()
    }

    /// Bytes this record holds, as the budget counts them.
    pub fn bytes(&self) -> usize {
        self.light_bytes() + self.detail.as_ref().map_or(0, |d| d.bytes())
    }
}

/// Increments kept, oldest first, within a byte budget.
#[derive(Debug)]
pub struct History {
    records: VecDeque<Record>,
    budget: usize,
    bytes: usize,
    /// Older detail kept only on increments that are a multiple of
    /// `2^level`.
    level: u32,
    thinned_before: Option<usize>,
    dropped: usize,
}

/// The share of the budget the newest, fully detailed increments may use.
const RECENT_SHARE: usize = 2;

impl History {
    /// An empty history that may use `budget` bytes (at least 64 KiB).
    pub fn new(budget: usize) -> Self {
        Self {
            records: VecDeque::new(),
            budget: budget.max(1 << 16),
            bytes: 0,
            level: 0,
            thinned_before: None,
            dropped: 0,
        }
    }

    /// Forget every record, keeping the budget.
    pub fn clear(&mut self) {
        *self = Self::new(self.budget);
    }

    /// Bytes the history may use.
    pub fn budget(&self) -> usize {
        self.budget
    }
    /// Bytes the records use now, as the budget counts them.
    pub fn bytes(&self) -> usize {
        self.bytes
    }
    /// Number of increments kept.
    pub fn len(&self) -> usize {
        self.records.len()
    }
    /// Whether no increment is kept.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }
    /// The increments kept, oldest first.
    pub fn iter(&self) -> impl DoubleEndedIterator<Item = &Record> + ExactSizeIterator {
        self.records.iter()
    }
    /// The newest increment kept.
    pub fn newest(&self) -> Option<&Record> {
        self.records.back()
    }
    /// The oldest increment kept (older ones were dropped).
    pub fn oldest(&self) -> Option<&Record> {
        self.records.front()
    }
    /// Increments before this one kept their detail only every
    /// `2^level`-th increment: `(increment, 2^level)`.
    pub fn thinned_before(&self) -> Option<(usize, usize)> {
        self.thinned_before.map(|i| (i, 1 << self.level))
    }
    /// Increments before this one were dropped altogether.
    pub fn dropped_before(&self) -> Option<usize> {
        (self.dropped > 0).then(|| self.records.front().map_or(0, |r| r.increment))
    }

    /// The record of increment `increment`, if kept: the one that finished
    /// it when the run paused at events inside it.
    ///
    /// Records are found by their increment number, not by their place:
    /// a run that pauses at events files one record per pause with the
    /// number of the increment in progress, so places and numbers part
    /// (counting places once showed increment #82 for #124).
    pub fn get(&self, increment: usize) -> Option<&Record> {
        let end = self.end_of(increment);
        self.records
            .get(end.checked_sub(1)?)
            .filter(|r| r.increment == increment)
    }

    /// One past the place of the last record of an increment up to
    /// `increment`.
    fn end_of(&self, increment: usize) -> usize {
        self.records.partition_point(|r| r.increment <= increment)
    }

    /// The nearest record at or before `increment` that kept its detail.
    pub fn detail_at(&self, increment: usize) -> Option<(&Record, &Detail)> {
        let end = self.end_of(increment);
        self.records
            .range(..end)
            .rev()
            .find_map(|r| r.detail.as_deref().map(|d| (r, d)))
    }

    /// File the next increment, thinning or dropping old ones if over budget.
    pub fn push(&mut self, record: Record) {
        self.bytes += record.bytes();
        self.records.push_back(record);
        if self.bytes > self.budget {
            self.compact();
        }
    }

    /// Bring the store down to 90 % of the budget (so that compaction is
    /// rare): thin older detail, then drop the oldest increments.
    fn compact(&mut self) {
        let target = self.budget / 10 * 9;
        let per_record = self.records.back().map_or(1, Record::bytes).max(1);
        let recent = (self.budget / RECENT_SHARE / per_record).max(16);
        while self.bytes > target && !self.records.is_empty() {
            let old_end = self.records.len().saturating_sub(recent);
            let stride = 1usize << self.level;
            let mut freed = 0;
            for r in self.records.range_mut(..old_end) {
                if r.increment % stride != 0 {
                    if let Some(d) = r.detail.take() {
                        freed += d.bytes();
                    }
                }
            }
            if old_end > 0 {
                let edge = self.records[old_end - 1].increment + 1;
                if freed > 0 || self.thinned_before.is_some() {
                    self.thinned_before = Some(self.thinned_before.map_or(edge, |t| t.max(edge)));
                }
            }
            self.bytes -= freed;
            if self.bytes <= target {
                break;
            }
            if self.level < 24 && old_end > 0 {
                self.level += 1;
                continue;
            }
            // Detail is gone from the old part: drop its oldest tenth.
            let n = (self.records.len() / 10).max(1);
            for _ in 0..n {
                if let Some(r) = self.records.pop_front() {
                    self.bytes -= r.bytes();
                    self.dropped += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(increment: usize, nodes: usize) -> Record {
        Record {
            generation: 0,
            increment,
            phase: Phase::Cycle {
                cycle: 1 + increment / 100,
                increment: increment % 100,
            },
            after: Phase::Cycle {
                cycle: 1,
                increment: 0,
            },
            time: Some(0.0),
            load: (0.0, 0.0),
            partial: None,
            cells: vec![0; nodes],
            dissipation: 0.0,
            rotation: 0.0,
            status: Status::Running,
            events: Vec::new(),
            newly_stuck: Vec::new(),
            locked: None,
            substeps: 1,
            completed: None,
            detail: Some(Box::new(Detail {
                pressure: vec![0.0; nodes],
                shear: vec![0.0; nodes],
                slip: vec![0.0; nodes],
                slip_before: None,
            })),
        }
    }

    #[test]
    fn pauses_inside_increments_do_not_shift_the_history() {
        // Every third increment paused at an event inside it first: two
        // records carry its number.
        let mut h = History::new(64 << 20);
        for i in 0..200 {
            if i % 3 == 0 {
                let mut partial = record(i, 8);
                partial.partial = Some(0.5);
                h.push(partial);
            }
            h.push(record(i, 8));
        }
        for i in 0..200 {
            let r = h.get(i).unwrap();
            assert_eq!(r.increment, i);
            assert!(r.partial.is_none(), "the finished record of {i}");
            assert_eq!(h.detail_at(i).unwrap().0.increment, i);
        }
        assert!(h.get(200).is_none());
    }

    #[test]
    fn stays_within_budget_and_says_what_it_lost() {
        let budget = 1 << 20;
        let mut h = History::new(budget);
        for i in 0..100_000 {
            h.push(record(i, 128));
            assert!(h.bytes() <= budget, "{} > {budget} at {i}", h.bytes());
        }
        assert!(h.thinned_before().is_some());
        assert!(h.dropped_before().is_some());
        assert_eq!(h.newest().unwrap().increment, 99_999);
        assert!(h.newest().unwrap().detail.is_some());
        let first = h.oldest().unwrap().increment;
        assert_eq!(h.get(first + 3).unwrap().increment, first + 3);
        assert!(h.detail_at(99_999).is_some());
        // Accounting matches a recount.
        let recount: usize = h.iter().map(Record::bytes).sum();
        assert_eq!(recount, h.bytes());
    }

    #[test]
    fn nothing_lost_under_budget() {
        let mut h = History::new(64 << 20);
        for i in 0..1000 {
            h.push(record(i, 64));
        }
        assert_eq!(h.len(), 1000);
        assert!(h.thinned_before().is_none() && h.dropped_before().is_none());
    }
}
