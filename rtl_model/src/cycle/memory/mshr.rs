//! The MSHR table: the lines in flight, each with its miss-status register, found by line.
//!
//! Pipeline position: inside [`super::dram::Dram`]; every miss of step 4 (and every miss-queue
//! head of step 1) asks whether its line is in flight, and every fill that completes frees its
//! line's entry. In hardware this is the MSHRs' parallel line compare (`crossbar.rs` prices it);
//! here an index from line to entry answers in one probe instead of a scan of the in-flight
//! lines, which with the default 256 MSHRs was the node memory's largest per-read cost
//! (issue 30).
//!
//! Nothing the model computes depends on the entries' order: the DRAM side looks entries up by
//! line and takes minima over all of them, so the index changes no cycle, only the cost.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Hashes a line number (one `u64`) by a folded 64 × 64 → 128-bit multiply: lines that
/// differ only in their high bits (the same cache set) still spread over the table, and the
/// hash is a fixed function, so nothing depends on a per-run seed.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct LineHasher(u64);

impl Hasher for LineHasher {
    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }

    #[inline]
    fn write_u64(&mut self, line: u64) {
        let p = u128::from(line ^ self.0) * 0x9E37_79B9_7F4A_7C15;
        self.0 = (p as u64) ^ ((p >> 64) as u64);
    }

    fn write(&mut self, bytes: &[u8]) {
        // Only `u64` keys are hashed here; any other key is folded in 8-byte words.
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }
}

/// Lines in flight and their entries `T`, with an index from line to entry.
#[derive(Clone, Debug)]
pub(super) struct MshrTable<T> {
    /// The entries, in no particular order (removal swaps the last one in).
    entries: Vec<(u64, T)>,
    /// Line → its position in `entries`.
    index: HashMap<u64, usize, BuildHasherDefault<LineHasher>>,
}

impl<T> MshrTable<T> {
    /// An empty table with room for `capacity` lines without growing.
    pub(super) fn with_capacity(capacity: usize) -> Self {
        // The table never holds more than `dram.mshrs` lines; reserving them up front keeps the
        // hot path free of rehashing. Capped so a huge configured count does not allocate
        // before it is used.
        let capacity = capacity.min(4096);
        Self {
            entries: Vec::with_capacity(capacity),
            index: HashMap::with_capacity_and_hasher(capacity, BuildHasherDefault::default()),
        }
    }

    /// Lines in flight.
    #[inline]
    pub(super) fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether no line is in flight.
    #[inline]
    pub(super) fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The entry of `line`, if it is in flight.
    #[inline]
    pub(super) fn get_mut(&mut self, line: u64) -> Option<&mut T> {
        let &i = self.index.get(&line)?;
        Some(&mut self.entries[i].1)
    }

    /// Adds `line` (not in flight) with its entry.
    #[inline]
    pub(super) fn insert(&mut self, line: u64, entry: T) {
        debug_assert!(
            !self.index.contains_key(&line),
            "line {line} already in flight"
        );
        self.index.insert(line, self.entries.len());
        self.entries.push((line, entry));
    }

    /// Removes `line`'s entry and returns it (`None` if it was not in flight).
    #[inline]
    pub(super) fn remove(&mut self, line: u64) -> Option<T> {
        let i = self.index.remove(&line)?;
        let (_, entry) = self.entries.swap_remove(i);
        if let Some(&(moved, _)) = self.entries.get(i) {
            self.index.insert(moved, i);
        }
        Some(entry)
    }

    /// Every line in flight with its entry, in no particular order.
    #[inline]
    pub(super) fn iter(&self) -> impl Iterator<Item = (u64, &T)> {
        self.entries.iter().map(|(l, e)| (*l, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeded random inserts and removals against a plain list of (line, value) searched
    /// linearly: the table finds exactly the lines the list holds, with their values.
    #[test]
    fn table_matches_a_linear_list() {
        let seed = 0x30_u64;
        println!("seed {seed}");
        let mut rng = crate::cycle::test_rng::TestRng::new(seed);
        let mut next = move || rng.next_bits();
        let mut table = MshrTable::with_capacity(8);
        let mut list: Vec<(u64, u64)> = Vec::new();
        for step in 0..20_000u64 {
            // Lines from a small range (many repeats), some far apart in their high bits.
            let line = (next() % 64) | ((next() % 3) << 34);
            match next() % 3 {
                0 | 1 if !list.iter().any(|&(l, _)| l == line) => {
                    table.insert(line, step);
                    list.push((line, step));
                }
                _ => {
                    let want = list
                        .iter()
                        .position(|&(l, _)| l == line)
                        .map(|p| list.swap_remove(p).1);
                    assert_eq!(table.remove(line), want, "step {step}, line {line}");
                }
            }
            let probe = (next() % 64) | ((next() % 3) << 34);
            let want = list.iter().find(|&&(l, _)| l == probe).map(|&(_, v)| v);
            assert_eq!(
                table.get_mut(probe).copied(),
                want,
                "step {step}, probe {probe}"
            );
            assert_eq!(table.len(), list.len());
        }
        let mut got: Vec<(u64, u64)> = table.iter().map(|(l, &v)| (l, v)).collect();
        got.sort_unstable();
        list.sort_unstable();
        assert_eq!(got, list);
    }
}
