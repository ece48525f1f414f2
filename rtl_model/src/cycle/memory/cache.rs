//! The cache in front of DRAM: which line a read falls in (node words and attribute records
//! share one address space), and the tags of a set-associative cache with true LRU.
//!
//! Pipeline position: inside [`super::NodeMemory`]; step 4 of a simulated cycle looks reads
//! up here, and a completed fill installs its line (step 1).

use crate::svo::FetchKind;

/// Byte address at which the attribute array starts in the model's unified address space.
/// Node words occupy bytes `0 .. 4·2^32 = 2^34`; attribute record `i` is at
/// `ATTR_REGION_BASE + 8·i`. The base is a multiple of every valid `sets · line_bytes`, so an
/// attribute record's cache set is `(8·i / line_bytes) mod sets`, as for a node word.
pub const ATTR_REGION_BASE: u64 = 1 << 40;

/// The cache line holding a read: node words from byte 0, attribute records from
/// [`ATTR_REGION_BASE`].
#[inline]
pub(super) fn line_of(kind: FetchKind, addr: u32, line_bytes: u64) -> u64 {
    let byte = match kind {
        FetchKind::Node | FetchKind::Far => 4 * u64::from(addr),
        FetchKind::Attr => ATTR_REGION_BASE + 8 * u64::from(addr),
    };
    byte / line_bytes
}

/// Tags of a set-associative cache with true LRU, each set kept in recency order (most
/// recent first), as an LRU stack in hardware would shift.
#[derive(Clone, Debug)]
pub(super) struct Tags {
    sets: u64,
    ways: usize,
    tags: Vec<u64>,
}

const INVALID: u64 = u64::MAX;

impl Tags {
    pub(super) fn new(sets: u64, ways: u32) -> Self {
        let ways = ways as usize;
        Self {
            sets,
            ways,
            tags: vec![INVALID; sets as usize * ways],
        }
    }

    fn set(&mut self, line: u64) -> &mut [u64] {
        // sets is a power of two; 0 (no cache) is handled by the callers.
        let s = (line & (self.sets - 1)) as usize;
        &mut self.tags[s * self.ways..(s + 1) * self.ways]
    }

    /// Whether `line` is cached (no change to the recency order).
    pub(super) fn contains(&self, line: u64) -> bool {
        if self.sets == 0 {
            return false;
        }
        let s = (line & (self.sets - 1)) as usize;
        self.tags[s * self.ways..(s + 1) * self.ways].contains(&line)
    }

    /// Looks up `line`; on a hit it becomes most recently used.
    pub(super) fn touch(&mut self, line: u64) -> bool {
        if self.sets == 0 {
            return false;
        }
        let set = self.set(line);
        match set.iter().position(|&t| t == line) {
            Some(p) => {
                set[..=p].rotate_right(1);
                true
            }
            None => false,
        }
    }

    /// Installs `line` as most recently used, evicting the least recently used way.
    pub(super) fn install(&mut self, line: u64) {
        if self.sets == 0 {
            return;
        }
        let set = self.set(line);
        let p = set.iter().position(|&t| t == line).unwrap_or(set.len() - 1);
        set[..=p].rotate_right(1);
        set[0] = line;
    }
}
