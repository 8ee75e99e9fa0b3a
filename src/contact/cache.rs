//! Slip rates of recently seen slip sets, so that a slip set met again costs
//! a lookup instead of a linear solve.
//!
//! Under a periodic load the contact meets the same sequence of slip sets
//! cycle after cycle (the zones grow, stick and move across the same nodes),
//! and a run takes from a few to some hundreds of cycles to its steady
//! state. The slip rates of a set depend on the set, its directions and the
//! direction of the load only (model.md section 3), so they are kept here,
//! by set, for the one or two load directions they were solved for. Up to
//! [`RESPONSE_NODES`] nodes the residual pressure and shear rates `H g'` and
//! `-|D| g'` are kept with them, so that a hit costs copies only, no FFT;
//! above it they would crowd the rates out of the budget (a miss costs far
//! more than an FFT there), and follow from the rates by one FFT.
//! Either way a hit gives the very numbers the solve gave.
//!
//! The cache is bounded in bytes: past its budget the least recently used
//! half is dropped. It is a cache only: a cloned contact starts with an
//! empty one. A sweep hands it from run to run within a `lambda` and `phi`
//! ([`crate::analysis::sweep::groups`]).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::ops::Range;

/// The hasher of [`ResponseCache`]'s index, whose keys are hashes of the
/// sets already ([`SetKey`]), every bit of them mixed: hashing them again
/// with the standard SipHash was most of the cost of a lookup.
#[derive(Default)]
struct Prehashed(u64);

impl Hasher for Prehashed {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        // Only `u64` keys are hashed here; any other input still hashes.
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }

    fn write_u64(&mut self, key: u64) {
        self.0 = key;
    }
}

/// Default budget of one contact's cache. A sweep keeps one per worker,
/// handed from run to run within a `lambda` and `phi`: at 12 MB the
/// Fig. 3 map meets more of its sets again (every fifth `lambda` on one
/// thread, callgrind: 9.64 G instructions against 10.06 G at 8 MB, 9.44 G
/// at 16 MB) and peaks at 40-42 MB on two threads (31 MB at 8 MB, 49 MB at
/// 16 MB, against a limit of 50 MB).
pub(crate) const DEFAULT_BUDGET: usize = 12 << 20;

/// Up to this many nodes an entry also holds the residual responses.
pub(crate) const RESPONSE_NODES: usize = 256;

/// The slip rates of one set: ranges of [`ResponseCache`]'s pools.
struct Entry {
    /// The set, a code per slipping node in node order ([`code`]), in
    /// `codes_pool`.
    key: Range<usize>,
    /// The set's [`hash`], kept: a compaction indexes the entries again
    /// without hashing every code of every set (1.5 % of a run at
    /// `N = 1024`, where the budget turns over every cycle or two).
    hash: u64,
    /// The load direction `u1` of the first response.
    u1: (f64, f64),
    /// Slip rates on the set, in node order, per unit `u1` and (when
    /// computed) per unit `u2`, the perpendicular of `u1`, in `floats`.
    rates: [Range<usize>; 2],
    /// `H g'` then `-|D| g'` at every node, per unit `u1` and `u2` (empty
    /// when not kept), in `floats`.
    responses: [Range<usize>; 2],
    have2: bool,
    last_used: u64,
}

impl Entry {
    /// What the entry costs against the budget: its numbers and a fixed
    /// share for its bookkeeping.
    fn bytes(&self) -> usize {
        let floats: usize = self
            .rates
            .iter()
            .chain(&self.responses)
            .map(Range::len)
            .sum();
        4 * self.key.len() + 8 * floats + 144
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
    /// `H g'` then `-|D| g'` at every node for `first` and `second`, when
    /// kept.
    pub(crate) first_responses: Option<&'a [f64]>,
    pub(crate) second_responses: Option<&'a [f64]>,
    /// Where `first_responses` and `second_responses` start in the pool
    /// ([`ResponseCache::pool`]).
    pub(crate) responses_at: [Option<usize>; 2],
}

/// The slip rates of recently seen slip sets (module docs).
///
/// The numbers of all entries live in two pools, one of set codes and one
/// of floats, and an entry holds ranges of them: an insert appends to the
/// pools instead of allocating three vectors (about a twelfth of a sweep's
/// time went to allocating and freeing them), and a run's cache is freed
/// as a few blocks.
pub(crate) struct ResponseCache {
    budget: usize,
    /// The entries' [`Entry::bytes`], summed: what the budget bounds.
    bytes: usize,
    clock: u64,
    entries: Vec<Entry>,
    by_hash: HashMap<u64, usize, BuildHasherDefault<Prehashed>>,
    codes_pool: Vec<u32>,
    floats: Vec<f64>,
    /// Pool entries no entry refers to any more (an entry replaced),
    /// dropped at the next compaction.
    garbage: usize,
    /// Lookups and hits, for tests and statistics.
    pub(crate) lookups: u64,
    pub(crate) hits: u64,
}

impl Clone for ResponseCache {
    fn clone(&self) -> Self {
        ResponseCache::new(self.budget)
    }
}

/// A slipping node and its direction as one number.
#[inline]
fn code(&(node, sign): &(usize, f64)) -> u32 {
    ((node as u32) << 1) | u32::from(sign < 0.0)
}

/// A code's share of a set's hash: the codes mixed (the finaliser of
/// SplitMix64) so that the exclusive or of any few of them is as good as a
/// random number.
#[inline]
fn mix(code: u32) -> u64 {
    let mut z = u64::from(code).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The hash of a set from its codes: the exclusive or of their shares.
fn hash(codes: &[u32]) -> u64 {
    codes.iter().fold(0, |h, &c| h ^ mix(c))
}

/// A slip set as the cache knows it: the codes ([`code`]) of its slipping
/// nodes in node order, and their hash.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct SetKey {
    codes: Vec<u32>,
    hash: u64,
}

impl SetKey {
    /// The empty set, with room for `n` nodes.
    pub(crate) fn with_capacity(n: usize) -> Self {
        Self {
            codes: Vec::with_capacity(n),
            hash: 0,
        }
    }

    /// The key of `set` (`(node, sign)` in node order), made afresh.
    #[cfg(test)]
    pub(crate) fn of(set: &[(usize, f64)]) -> Self {
        let mut key = Self::with_capacity(set.len());
        key.set_to(set);
        key
    }

    /// The key becomes that of `set` (`(node, sign)` in node order).
    pub(crate) fn set_to(&mut self, set: &[(usize, f64)]) {
        self.codes.clear();
        self.codes.extend(set.iter().map(code));
        self.hash = hash(&self.codes);
    }
}

/// Append `values` to `pool`; their range.
fn append<T>(pool: &mut Vec<T>, values: impl IntoIterator<Item = T>) -> Range<usize> {
    let start = pool.len();
    pool.extend(values);
    start..pool.len()
}

/// Append the responses `(H g', -|D| g')` to `pool` if an entry keeps them
/// (up to [`RESPONSE_NODES`] nodes); their range, empty if not.
fn keep(pool: &mut Vec<f64>, (pressure, shear): (&[f64], &[f64])) -> Range<usize> {
    if pressure.len() > RESPONSE_NODES {
        return pool.len()..pool.len();
    }
    let start = pool.len();
    pool.extend_from_slice(pressure);
    pool.extend_from_slice(shear);
    start..pool.len()
}

/// Move the ranges `moves` (start, entry, which) of `pool`, found in the
/// entries through `range`, to its front in order of their starts, and
/// drop the rest of it. An empty range becomes `0..0`.
fn pack<T: Copy>(
    pool: &mut Vec<T>,
    entries: &mut [Entry],
    moves: &mut Vec<(usize, usize, usize)>,
    range: fn(&mut Entry, usize) -> &mut Range<usize>,
) {
    moves.sort_unstable();
    let mut at = 0;
    for (_, slot, which) in moves.drain(..) {
        let r = range(&mut entries[slot], which);
        let len = r.len();
        if len == 0 {
            *r = 0..0;
            continue;
        }
        pool.copy_within(r.clone(), at);
        *r = at..at + len;
        at += len;
    }
    pool.truncate(at);
}

impl ResponseCache {
    pub(crate) fn new(budget: usize) -> Self {
        Self {
            budget,
            bytes: 0,
            clock: 0,
            entries: Vec::new(),
            by_hash: HashMap::default(),
            codes_pool: Vec::new(),
            floats: Vec::new(),
            garbage: 0,
            lookups: 0,
            hits: 0,
        }
    }

    /// The cached rates of the slip set `set`, if any.
    #[cfg(test)]
    pub(crate) fn lookup(&mut self, set: &SetKey) -> Option<Hit<'_>> {
        let slot = self.find(set)?;
        Some(self.hit(slot))
    }

    /// The slot of the slip set `set`, if cached ([`Self::hit`] gives its
    /// rates), counted as a lookup and as a use of the entry.
    pub(crate) fn find(&mut self, set: &SetKey) -> Option<usize> {
        self.lookups += 1;
        self.clock += 1;
        let slot = *self.by_hash.get(&set.hash)?;
        let e = &mut self.entries[slot];
        if self.codes_pool[e.key.clone()] != set.codes[..] {
            return None;
        }
        self.hits += 1;
        e.last_used = self.clock;
        Some(slot)
    }

    /// The rates kept at `slot` (from [`Self::find`]).
    pub(crate) fn hit(&self, slot: usize) -> Hit<'_> {
        let e = &self.entries[slot];
        let floats = &self.floats;
        let kept = |r: &Range<usize>| (!r.is_empty()).then(|| &floats[r.clone()]);
        let at = |r: &Range<usize>| (!r.is_empty()).then_some(r.start);
        Hit {
            slot,
            u1: e.u1,
            first: &floats[e.rates[0].clone()],
            second: e.have2.then(|| &floats[e.rates[1].clone()]),
            first_responses: kept(&e.responses[0]),
            second_responses: if e.have2 { kept(&e.responses[1]) } else { None },
            responses_at: [
                at(&e.responses[0]),
                if e.have2 { at(&e.responses[1]) } else { None },
            ],
        }
    }

    /// The pool of kept numbers, which [`Hit::responses_at`] points into.
    /// Its numbers move only when entries are evicted or compacted: at an
    /// [`Self::insert`], or an [`Self::add_second`] past the budget
    /// ([`Self::second_would_evict`]).
    pub(crate) fn pool(&self) -> &[f64] {
        &self.floats
    }

    /// Keep the rates `first` (per unit `u1`, on the set in node order) of
    /// the slip set `set`, with their responses `H g'` and `-|D| g'` if there
    /// are at most [`RESPONSE_NODES`] nodes; returns the entry's slot.
    pub(crate) fn insert(
        &mut self,
        set: &SetKey,
        u1: (f64, f64),
        first: impl Iterator<Item = f64>,
        responses: (&[f64], &[f64]),
    ) -> Option<usize> {
        if self.budget == 0 {
            return None;
        }
        self.clock += 1;
        if self.floats.capacity() == 0 {
            // Room for the whole budget at once: a run's pools grow to
            // megabytes, and grown by doubling they copied their numbers at
            // every doubling, from memory the cache no longer held (with
            // the room made here a Fig. 3 sweep peaks at 25 MB instead of
            // 33 MB, and takes some 3 % less time). Pages never written
            // cost no memory.
            self.floats.reserve(self.budget / 8);
            self.codes_pool.reserve(self.budget / 32);
        }
        let h = set.hash;
        let key = append(&mut self.codes_pool, set.codes.iter().copied());
        let rates = append(&mut self.floats, first);
        let kept = keep(&mut self.floats, responses);
        let empty = self.floats.len()..self.floats.len();
        let entry = Entry {
            key,
            hash: h,
            u1,
            rates: [rates, empty.clone()],
            responses: [kept, empty],
            have2: false,
            last_used: self.clock,
        };
        if let Some(&slot) = self.by_hash.get(&h) {
            // A collision or a set solved again: replace it.
            let old = &self.entries[slot];
            self.garbage += old.bytes();
            self.bytes -= old.bytes();
            self.bytes += entry.bytes();
            self.entries[slot] = entry;
            if self.garbage > self.bytes {
                self.compact();
            }
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
    /// holds `set`.
    pub(crate) fn add_second(
        &mut self,
        slot: usize,
        set: &SetKey,
        second: impl Iterator<Item = f64>,
        responses: (&[f64], &[f64]),
    ) {
        let Some(e) = self.entries.get(slot) else {
            return;
        };
        if e.have2 || self.codes_pool[e.key.clone()] != set.codes[..] {
            return;
        }
        let before = e.bytes();
        let rates = append(&mut self.floats, second);
        let kept = keep(&mut self.floats, responses);
        let e = &mut self.entries[slot];
        e.rates[1] = rates;
        e.responses[1] = kept;
        e.have2 = true;
        self.bytes = self.bytes - before + e.bytes();
        if self.bytes > self.budget {
            self.evict();
        }
    }

    /// Whether [`Self::add_second`] of `rates` slip rates and the
    /// responses at `nodes` nodes would pass the budget, and so evict and
    /// move the pool's numbers.
    pub(crate) fn second_would_evict(&self, rates: usize, nodes: usize) -> bool {
        let kept = if nodes > RESPONSE_NODES { 0 } else { 2 * nodes };
        self.bytes + 8 * (rates + kept) > self.budget
    }

    /// Drop the least recently used half.
    fn evict(&mut self) {
        let mut stamps: Vec<u64> = self.entries.iter().map(|e| e.last_used).collect();
        // The stamp a sort would put in the middle, without the sort.
        let half = stamps.len() / 2;
        let cut = *stamps.select_nth_unstable(half).1;
        self.entries.retain(|e| e.last_used > cut);
        self.compact();
    }

    /// Move the entries' numbers to the front of the pools, in pool order,
    /// and index them again. The pools keep their capacity: giving it back
    /// and growing again costs a page fault a page (about a tenth of a run
    /// at `N = 1024`, where the budget turns over every cycle).
    fn compact(&mut self) {
        // Every range, by where it starts: moved in that order, each range
        // goes down or stays, never over one still to be moved.
        let mut moves: Vec<(usize, usize, usize)> = Vec::new();
        for (slot, e) in self.entries.iter().enumerate() {
            moves.push((e.key.start, slot, 0));
        }
        pack(
            &mut self.codes_pool,
            &mut self.entries,
            &mut moves,
            |e, _| &mut e.key,
        );
        for (slot, e) in self.entries.iter().enumerate() {
            for (which, r) in e.rates.iter().chain(&e.responses).enumerate() {
                moves.push((r.start, slot, which));
            }
        }
        pack(
            &mut self.floats,
            &mut self.entries,
            &mut moves,
            |e, which| match which {
                0 | 1 => &mut e.rates[which],
                _ => &mut e.responses[which - 2],
            },
        );
        self.by_hash.clear();
        self.bytes = 0;
        for (slot, e) in self.entries.iter().enumerate() {
            debug_assert_eq!(e.hash, hash(&self.codes_pool[e.key.clone()]));
            self.by_hash.insert(e.hash, slot);
            self.bytes += e.bytes();
        }
        self.garbage = 0;
    }

    /// Bytes held.
    #[cfg(test)]
    pub(crate) fn bytes(&self) -> usize {
        self.bytes
    }

    /// Numbers held in the pools, live or not.
    #[cfg(test)]
    fn pooled(&self) -> usize {
        4 * self.codes_pool.len() + 8 * self.floats.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nodes `from..to` slipping forward (of `n`).
    fn set(_n: usize, from: usize, to: usize) -> SetKey {
        let nodes: Vec<(usize, f64)> = (from..to).map(|j| (j, 1.0)).collect();
        SetKey::of(&nodes)
    }

    #[test]
    fn hits_what_it_holds_and_stays_within_budget() {
        let n = 128;
        let mut c = ResponseCache::new(64 << 10);
        let a = set(n, 10, 20);
        assert!(c.lookup(&a).is_none());
        let (hp, hq) = (vec![0.5; n], vec![-0.25; n]);
        let slot = c
            .insert(&a, (1.0, 0.0), (0..10).map(|i| i as f64), (&hp, &hq))
            .unwrap();
        let hit = c.lookup(&a).expect("held");
        assert_eq!(hit.first[3], 3.0);
        assert!(hit.second.is_none() && hit.second_responses.is_none());
        let first = hit.first_responses.expect("kept at N = 128");
        assert_eq!((first[0], first[n]), (0.5, -0.25));
        c.add_second(slot, &a, (0..10).map(|i| -(i as f64)), (&hq, &hp));
        let hit = c.lookup(&a).unwrap();
        assert_eq!(hit.second.unwrap()[4], -4.0);
        assert_eq!(hit.second_responses.unwrap()[n], 0.5);
        // A different set of the same size is not confused with it.
        assert!(c.lookup(&set(n, 11, 21)).is_none());
        for k in 0..2000 {
            let s = set(n, k % 100, k % 100 + 1 + k % 27);
            c.insert(
                &s,
                (0.0, 1.0),
                (0..(1 + k % 27)).map(|i| i as f64),
                (&hp, &hq),
            );
            assert!(c.bytes() <= 64 << 10);
            // The pools hold the entries' numbers (and at most as much
            // again of replaced ones), within the budget.
            assert!(c.pooled() <= 2 * c.bytes());
        }
        // What is still held reads back as it was put in.
        for k in 1990..2000 {
            let s = set(n, k % 100, k % 100 + 1 + k % 27);
            let hit = c.lookup(&s).expect("recent entries stay");
            let rates: Vec<f64> = (0..(1 + k % 27)).map(|i| i as f64).collect();
            assert_eq!(hit.first, &rates[..]);
            assert_eq!(hit.first_responses.unwrap(), [&hp[..], &hq[..]].concat());
        }
    }

    #[test]
    fn a_replaced_entry_leaves_no_garbage_behind_for_long() {
        let n = 16;
        let mut c = ResponseCache::new(1 << 20);
        let (hp, hq) = (vec![1.0; n], vec![2.0; n]);
        let a = set(n, 2, 7);
        for round in 0..10 {
            // Inserting a held set again replaces its entry.
            c.insert(
                &a,
                (1.0, 0.0),
                (0..5).map(|i| (i + round) as f64),
                (&hp, &hq),
            );
            assert!(c.pooled() <= 2 * c.bytes());
            assert_eq!(c.lookup(&a).unwrap().first[0], round as f64);
        }
    }

    #[test]
    fn an_eviction_keeps_the_pools_room_and_what_it_keeps_reads_back() {
        let n = 64;
        let mut c = ResponseCache::new(32 << 10);
        let (hp, hq) = (vec![1.0; n], vec![2.0; n]);
        let mut room = 0;
        for k in 0..400 {
            let s = set(n, k % 50, k % 50 + 1 + k % 9);
            c.insert(
                &s,
                (1.0, 0.0),
                (0..1 + k % 9).map(|i| (i + k) as f64),
                (&hp, &hq),
            );
            // Compaction moves the numbers down in place: the pools never
            // give their memory back to grow again.
            assert!(c.floats.capacity() >= room);
            room = c.floats.capacity();
            assert!(c.pooled() <= 2 * c.bytes());
        }
        for k in 390..400 {
            let s = set(n, k % 50, k % 50 + 1 + k % 9);
            let hit = c.lookup(&s).expect("recent entries stay");
            let rates: Vec<f64> = (0..1 + k % 9).map(|i| (i + k) as f64).collect();
            assert_eq!(hit.first, &rates[..]);
            assert_eq!(hit.first_responses.unwrap(), [&hp[..], &hq[..]].concat());
        }
    }

    #[test]
    fn large_grids_keep_rates_only() {
        let n = RESPONSE_NODES + 2;
        let mut c = ResponseCache::new(1 << 20);
        let a = set(n, 3, 9);
        let big = vec![1.0; n];
        c.insert(&a, (1.0, 0.0), (0..6).map(|i| i as f64), (&big, &big));
        let hit = c.lookup(&a).expect("held");
        assert!(hit.first_responses.is_none());
        assert_eq!(hit.first[5], 5.0);
    }

    /// `second_would_evict` says beforehand whether `add_second` evicts (an
    /// engine reading a hit in place copies it out first when it does).
    #[test]
    fn a_second_response_past_the_budget_is_foretold() {
        let n = 16;
        let (hp, hq) = (vec![1.0; n], vec![2.0; n]);
        let (mut evicted, mut kept) = (0, 0);
        for k in 0..200usize {
            let mut c = ResponseCache::new(4 << 10);
            let mut last = None;
            for i in 0..=k % 23 {
                let s = set(n, i, i + 1 + k % 5);
                let slot = c.insert(&s, (1.0, 0.0), (0..1 + k % 5).map(|v| v as f64), (&hp, &hq));
                last = slot.map(|slot| (slot, s));
            }
            let Some((slot, s)) = last else { continue };
            let would = c.second_would_evict(1 + k % 5, n);
            let before = c.entries.len();
            c.add_second(slot, &s, (0..1 + k % 5).map(|v| -(v as f64)), (&hq, &hp));
            assert_eq!(would, c.entries.len() < before, "case {k}");
            assert!(c.bytes() <= 4 << 10);
            if would {
                evicted += 1;
            } else {
                kept += 1;
            }
        }
        assert!(evicted > 10 && kept > 10, "{evicted} evicted, {kept} not");
    }
}
