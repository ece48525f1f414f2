//! Memory blocks for the hit buffer: how many BRAM36 (or URAM288) blocks hold one record
//! word per pixel (`docs/units/hit-record.md` §6).
//!
//! Pipeline position: beside the hit-record unit; the cycle model's resource estimate sizes
//! the hit-buffer memory with it.

/// Block RAM aspect ratios of a RAMB36E2 in simple dual-port mode: (data bits incl. parity,
/// depth). One read port (reuse check) and one write port (write-back) are all the hit
/// buffer needs, so the 72-bit SDP width is available.
pub const BRAM36_SHAPES: [(u32, u64); 7] = [
    (72, 512),
    (36, 1024),
    (18, 2048),
    (9, 4096),
    (4, 8192),
    (2, 16384),
    (1, 32768),
];

/// Fewest BRAM36 blocks holding `depth` words of `word_bits` bits: the word is split into
/// slices, each slice built from blocks of one aspect ratio side by side and stacked
/// ⌈depth / block depth⌉ deep; the cheapest mix of slices is found exactly (a small
/// covering knapsack over the bits). 1280×768 at 72 bits: 1920 blocks.
pub fn bram36_count(word_bits: u32, depth: u64) -> u64 {
    if depth == 0 || word_bits == 0 {
        return 0;
    }
    let w = word_bits as usize;
    let mut cost = vec![u64::MAX; w + 1];
    cost[0] = 0;
    for b in 1..=w {
        for &(sw, sd) in &BRAM36_SHAPES {
            let prev = cost[b.saturating_sub(sw as usize)];
            let c = prev.saturating_add(depth.div_ceil(sd));
            cost[b] = cost[b].min(c);
        }
    }
    cost[w]
}

/// UltraRAM (URAM288, 4096 × 72, one width only) blocks for the same buffer, for parts whose
/// BRAM cannot hold it: ⌈bits / 72⌉ · ⌈depth / 4096⌉. 1280×768 at 72 bits: 240.
pub fn uram288_count(word_bits: u32, depth: u64) -> u64 {
    u64::from(word_bits.div_ceil(72)) * depth.div_ceil(4096)
}
