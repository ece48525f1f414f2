//! The address map the node memory serves: how many node words and attribute records there
//! are, and which node words the on-chip store holds (the image's top levels, as a whitelist
//! of word ranges and a bitmap for the per-read test). Images from `SvoImage::build` lay
//! their top `PREFIX_LEVELS` (8) levels out first, level by level, so for up to 8 levels the
//! whitelist is the single range `[0, end)`; more levels add scattered groups after it.
//!
//! Pipeline position: built once per scene image ([`MemoryLayout::from_image`]) before the
//! run; [`super::NodeMemory`] checks every request against it and routes on-chip reads to the
//! banks. Why "the top levels" and not "the first bytes" is in the module documentation of
//! [`super`].

use super::config::OnChipConfig;
use crate::svo::{ChildDescriptor, SvoImage};
use thiserror::Error;

/// Why a memory layout could not be made.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum LayoutError {
    /// More node words or attribute records than 32-bit addresses reach.
    #[error("{what} = {value} is more than a 32-bit address reaches")]
    TooLarge {
        /// Which count.
        what: &'static str,
        /// Its value.
        value: u64,
    },
    /// An on-chip range is empty, unsorted, overlapping or outside the node memory.
    #[error(
        "on-chip range {start}..{end} is empty, out of order or outside the {words} node words"
    )]
    BadRange {
        /// Start word.
        start: u32,
        /// End word (exclusive).
        end: u32,
        /// Node words.
        words: u64,
    },
    /// A pointer in the image leads outside the node memory (never for images from
    /// `SvoImage::build`).
    #[error("node word {addr} points outside the image")]
    MalformedImage {
        /// The word whose pointer is bad.
        addr: u64,
    },
}

/// The address map the model serves: node-memory size, attribute count and the on-chip
/// whitelist (sorted, disjoint, half-open word ranges).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MemoryLayout {
    node_words: u64,
    attr_records: u64,
    onchip: Vec<(u32, u32)>,
    /// The same whitelist as one bit per word up to the last on-chip word, for the per-read
    /// test (a binary search over thousands of scattered groups costs a cache miss per
    /// probe); empty when that would exceed [`MAX_ONCHIP_BITMAP_WORDS`].
    onchip_bits: Vec<u64>,
    onchip_levels: u8,
    onchip_words: u64,
}

/// Largest word range the on-chip bitmap covers (2^28 words: a 32 MiB bitmap); beyond it
/// [`MemoryLayout::is_onchip`] searches the ranges instead.
pub const MAX_ONCHIP_BITMAP_WORDS: u64 = 1 << 28;

impl MemoryLayout {
    /// A layout without an on-chip part.
    pub fn flat(node_words: u64, attr_records: u64) -> Result<Self, LayoutError> {
        Self::with_onchip_ranges(node_words, attr_records, Vec::new())
    }

    /// A layout whose on-chip part is the given word ranges (half-open, sorted, disjoint,
    /// non-empty, inside the node memory). For synthetic tests and experiments; images use
    /// [`MemoryLayout::from_image`].
    pub fn with_onchip_ranges(
        node_words: u64,
        attr_records: u64,
        ranges: Vec<(u32, u32)>,
    ) -> Result<Self, LayoutError> {
        let limit = 1u64 << 32;
        if node_words > limit {
            return Err(LayoutError::TooLarge {
                what: "node words",
                value: node_words,
            });
        }
        if attr_records > limit {
            return Err(LayoutError::TooLarge {
                what: "attribute records",
                value: attr_records,
            });
        }
        let mut prev_end = 0u32;
        for (i, &(start, end)) in ranges.iter().enumerate() {
            if start >= end || u64::from(end) > node_words || (i > 0 && start < prev_end) {
                return Err(LayoutError::BadRange {
                    start,
                    end,
                    words: node_words,
                });
            }
            prev_end = end;
        }
        let onchip_words = ranges.iter().map(|&(s, e)| u64::from(e - s)).sum();
        let span = ranges.last().map_or(0, |&(_, e)| u64::from(e));
        let mut onchip_bits = Vec::new();
        if span <= MAX_ONCHIP_BITMAP_WORDS {
            onchip_bits = vec![0u64; span.div_ceil(64) as usize];
            for &(s, e) in &ranges {
                for a in s..e {
                    onchip_bits[(a / 64) as usize] |= 1 << (a % 64);
                }
            }
        }
        Ok(Self {
            node_words,
            attr_records,
            onchip: ranges,
            onchip_bits,
            onchip_levels: 0,
            onchip_words,
        })
    }

    /// The layout of an image: its sizes and the on-chip whitelist of its top
    /// `onchip.levels` levels, cut to whole levels that fit `onchip.max_bytes`.
    ///
    /// Level 0 is the root word; level `l ≥ 1` adds the groups of the internal nodes at level
    /// `l − 1` (their children's slots and the group's far words). A far word sits in the same
    /// group as the descriptor that points to it, so the far read that descends from an
    /// on-chip node is on chip too.
    pub fn from_image(img: &SvoImage, onchip: &OnChipConfig) -> Result<Self, LayoutError> {
        let nodes = img.nodes();
        let n = nodes.len() as u64;
        let attrs = img.attrs().len() as u64;
        if n > u64::from(u32::MAX) {
            // Built images stay below 2^32 words; range ends must fit u32.
            return Err(LayoutError::TooLarge {
                what: "node words",
                value: n,
            });
        }
        let max_words = onchip.max_bytes / 4;
        if onchip.levels == 0 || max_words == 0 || nodes.is_empty() {
            return Self::flat(n, attrs);
        }
        let word = |a: u64| -> Result<u32, LayoutError> {
            usize::try_from(a)
                .ok()
                .and_then(|i| nodes.get(i).copied())
                .ok_or(LayoutError::MalformedImage { addr: a })
        };
        let mut ranges: Vec<(u64, u64)> = vec![(0, 1)];
        let mut words = 1u64;
        let mut levels = 1u8;
        // Internal nodes at level `levels − 1`, whose groups make the next level.
        let mut frontier: Vec<u64> = vec![0];
        while levels < onchip.levels && !frontier.is_empty() {
            let mut level_ranges = Vec::new();
            let mut level_words = 0u64;
            let mut next = Vec::new();
            for &a in &frontier {
                let d = ChildDescriptor::unpack(word(a)?);
                if d.valid == 0 {
                    continue;
                }
                let ptr = u64::from(d.ptr);
                let off = if d.far {
                    u64::from(word(a + ptr)?)
                } else {
                    ptr
                };
                let base = a + off;
                let k = u64::from(d.valid.count_ones());
                let mut far_words = 0;
                let mut slot = base;
                for label in 0..8u8 {
                    let bit = 1u8 << label;
                    if d.valid & bit == 0 {
                        continue;
                    }
                    if d.leaf & bit == 0 {
                        if ChildDescriptor::unpack(word(slot)?).far {
                            far_words += 1;
                        }
                        next.push(slot);
                    }
                    slot += 1;
                }
                let end = base + k + far_words;
                if end > n {
                    return Err(LayoutError::MalformedImage { addr: a });
                }
                level_ranges.push((base, end));
                level_words += k + far_words;
            }
            if words + level_words > max_words {
                break;
            }
            words += level_words;
            ranges.extend(level_ranges);
            frontier = next;
            levels += 1;
        }
        if frontier.is_empty() {
            // The whole tree is on chip; deeper levels are trivially there.
            levels = onchip.levels;
        }
        ranges.sort_unstable();
        let mut merged: Vec<(u32, u32)> = Vec::with_capacity(ranges.len());
        for (s, e) in ranges {
            // e ≤ n ≤ 2^32 − 1 (checked above), so both ends fit u32.
            let (s, e) = (s as u32, e as u32);
            match merged.last_mut() {
                Some(last) if s <= last.1 => last.1 = last.1.max(e),
                _ => merged.push((s, e)),
            }
        }
        let mut layout = Self::with_onchip_ranges(n, attrs, merged)?;
        layout.onchip_levels = levels;
        Ok(layout)
    }

    /// Whether node word `addr` is in the on-chip store.
    #[inline]
    pub fn is_onchip(&self, addr: u32) -> bool {
        if !self.onchip_bits.is_empty() || self.onchip.is_empty() {
            return self
                .onchip_bits
                .get((addr / 64) as usize)
                .is_some_and(|w| w & (1 << (addr % 64)) != 0);
        }
        // Index of the first range starting after addr; the one before may contain it.
        let i = self.onchip.partition_point(|&(s, _)| s <= addr);
        i > 0 && addr < self.onchip[i - 1].1
    }

    /// Node-memory words.
    pub fn node_words(&self) -> u64 {
        self.node_words
    }

    /// Attribute records.
    pub fn attr_records(&self) -> u64 {
        self.attr_records
    }

    /// The on-chip ranges (half-open word ranges, sorted, disjoint).
    pub fn onchip_ranges(&self) -> &[(u32, u32)] {
        &self.onchip
    }

    /// Tree levels actually on chip (0 for layouts not made from an image).
    pub fn onchip_levels(&self) -> u8 {
        self.onchip_levels
    }

    /// Words in the on-chip store.
    pub fn onchip_words(&self) -> u64 {
        self.onchip_words
    }
}
