//! Slip rates of recently seen slip sets, so that a slip set met again costs
//! a lookup instead of a linear solve.
//!
//! Under a periodic load the contact meets the same sequence of slip sets
//! cycle after cycle (the zones grow, stick and move across the same nodes),
//! and a run takes from a few to some hundreds of cycles to its steady
//! state. The slip rates of a set depend on the set, its directions and the
//! direction of the load only (model.md section 3), so they are kept here,
//! by set, for the one or two load directions they were solved for. The
//! pressure and shear rates follow from them by one FFT.
//!
//! The cache is bounded in bytes: past its budget the least recently used
//! half is dropped. It is a cache only: a cloned contact starts with an
//! empty one.

use std::collections::HashMap;

use super::solver::SlipDirection;

/// Default budget of one contact's cache.
pub(crate) const DEFAULT_BUDGET: usize = 8 << 20;

/// The slip rates of one set.
struct Entry {
    /// Slip sign of every node (0 stick).
    signs: Vec<i8>,
    /// The load direction `u1` of the first response.
    u1: (f64, f64),
    /// Slip rates on the set, in node order, per unit `u1` and (when
    /// computed) per unit `u2`, the perpendicular of `u1`.
    rates: [Vec<f64>; 2],
    have2: bool,
    last_used: u64,
}

impl Entry {
    fn bytes(&self) -> usize {
        self.signs.len() + 8 * (self.rates[0].capacity() + self.rates[1].capacity()) + 96
    }
}

/// What a hit gives back.
pub(crate) struct Hit<'a> {
    /// Index of the entry, for [`ResponseCache::add_second`].
    pub(crate) slot: usize,
    pub(crate) u1: (f64, f64),
    /// Rates per unit `u1`, and per unit `u2` if known, on the set in node
    /// order.
    pub(crate) first: &'a [f64],
    pub(crate) second: Option<&'a [f64]>,
}

pub(crate) struct ResponseCache {
    budget: usize,
    bytes: usize,
    clock: u64,
    entries: Vec<Entry>,
    by_hash: HashMap<u64, usize>,
    /// Lookups and hits, for tests and statistics.
    pub(crate) lookups: u64,
    pub(crate) hits: u64,
}

impl Clone for ResponseCache {
    fn clone(&self) -> Self {
        ResponseCache::new(self.budget)
    }
}

fn hash(dirs: &[SlipDirection]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for chunk in dirs.chunks(32) {
        // Two bits a node, 32 nodes a word.
        let mut word: u64 = 0;
        for (i, d) in chunk.iter().enumerate() {
            let bits: u64 = match d {
                SlipDirection::Stick => 0,
                SlipDirection::Forward => 1,
                SlipDirection::Backward => 2,
            };
            word |= bits << (2 * i);
        }
        h = (h ^ word).wrapping_mul(0x0100_0000_01b3).rotate_left(29);
    }
    h
}

fn same(signs: &[i8], dirs: &[SlipDirection]) -> bool {
    signs.len() == dirs.len() && signs.iter().zip(dirs).all(|(&s, d)| s == d.sign() as i8)
}

impl ResponseCache {
    pub(crate) fn new(budget: usize) -> Self {
        Self {
            budget,
            bytes: 0,
            clock: 0,
            entries: Vec::new(),
            by_hash: HashMap::new(),
            lookups: 0,
            hits: 0,
        }
    }

    /// The cached rates of the set `dirs`, if any.
    pub(crate) fn lookup(&mut self, dirs: &[SlipDirection]) -> Option<Hit<'_>> {
        self.lookups += 1;
        self.clock += 1;
        let slot = *self.by_hash.get(&hash(dirs))?;
        let e = &mut self.entries[slot];
        if !same(&e.signs, dirs) {
            return None;
        }
        self.hits += 1;
        e.last_used = self.clock;
        Some(Hit {
            slot,
            u1: e.u1,
            first: &e.rates[0],
            second: e.have2.then_some(e.rates[1].as_slice()),
        })
    }

    /// Keep the rates `first` (per unit `u1`, on the set in node order) of
    /// the set `dirs`; returns the entry's slot.
    pub(crate) fn insert(
        &mut self,
        dirs: &[SlipDirection],
        u1: (f64, f64),
        first: impl Iterator<Item = f64>,
    ) -> Option<usize> {
        if self.budget == 0 {
            return None;
        }
        self.clock += 1;
        let entry = Entry {
            signs: dirs.iter().map(|d| d.sign() as i8).collect(),
            u1,
            rates: [first.collect(), Vec::new()],
            have2: false,
            last_used: self.clock,
        };
        let h = hash(dirs);
        if let Some(&slot) = self.by_hash.get(&h) {
            // A collision or a set solved again: replace it.
            self.bytes -= self.entries[slot].bytes();
            self.bytes += entry.bytes();
            self.entries[slot] = entry;
            return Some(slot);
        }
        self.bytes += entry.bytes();
        self.entries.push(entry);
        self.by_hash.insert(h, self.entries.len() - 1);
        if self.bytes > self.budget {
            self.evict();
            return self.by_hash.get(&h).copied();
        }
        Some(self.entries.len() - 1)
    }

    /// Add the rates per unit `u2` to the entry at `slot`, if it still
    /// holds `dirs`.
    pub(crate) fn add_second(
        &mut self,
        slot: usize,
        dirs: &[SlipDirection],
        second: impl Iterator<Item = f64>,
    ) {
        let Some(e) = self.entries.get_mut(slot) else {
            return;
        };
        if e.have2 || !same(&e.signs, dirs) {
            return;
        }
        let before = e.bytes();
        e.rates[1].clear();
        e.rates[1].extend(second);
        e.have2 = true;
        self.bytes = self.bytes - before + e.bytes();
        if self.bytes > self.budget {
            self.evict();
        }
    }

    /// Drop the least recently used half.
    fn evict(&mut self) {
        let mut stamps: Vec<u64> = self.entries.iter().map(|e| e.last_used).collect();
        stamps.sort_unstable();
        let cut = stamps[stamps.len() / 2];
        self.entries.retain(|e| e.last_used > cut);
        self.by_hash.clear();
        self.bytes = 0;
        for (slot, e) in self.entries.iter().enumerate() {
            let dirs: Vec<SlipDirection> = e
                .signs
                .iter()
                .map(|&s| match s {
                    0 => SlipDirection::Stick,
                    s => SlipDirection::from_sign(s as f64),
                })
                .collect();
            self.by_hash.insert(hash(&dirs), slot);
            self.bytes += e.bytes();
        }
    }

    /// Bytes held.
    #[cfg(test)]
    pub(crate) fn bytes(&self) -> usize {
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(n: usize, from: usize, to: usize) -> Vec<SlipDirection> {
        (0..n)
            .map(|j| {
                if (from..to).contains(&j) {
                    SlipDirection::Forward
                } else {
                    SlipDirection::Stick
                }
            })
            .collect()
    }

    #[test]
    fn hits_what_it_holds_and_stays_within_budget() {
        let n = 128;
        let mut c = ResponseCache::new(64 << 10);
        let a = set(n, 10, 20);
        assert!(c.lookup(&a).is_none());
        let slot = c.insert(&a, (1.0, 0.0), (0..10).map(|i| i as f64)).unwrap();
        let hit = c.lookup(&a).expect("held");
        assert_eq!(hit.first[3], 3.0);
        assert!(hit.second.is_none());
        c.add_second(slot, &a, (0..10).map(|i| -(i as f64)));
        assert_eq!(c.lookup(&a).unwrap().second.unwrap()[4], -4.0);
        // A different set of the same size is not confused with it.
        assert!(c.lookup(&set(n, 11, 21)).is_none());
        for k in 0..2000 {
            let s = set(n, k % 100, k % 100 + 1 + k % 27);
            c.insert(&s, (0.0, 1.0), (0..(1 + k % 27)).map(|i| i as f64));
            assert!(c.bytes() <= 64 << 10);
        }
    }
}
