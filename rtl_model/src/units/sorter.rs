//! Candidate sorter: orders a ray's candidate instances front to back by entry distance.
//!
//! Pipeline position: after the sphere tests (one per instance, world space), before the
//! hit-buffer check and the walks. Its input is every candidate of one ray — an instance
//! whose bounding sphere the ray pierces — as a key (t_enter raw code, instance id); its output
//! is the same keys in walk order, so early termination can stop once the best hit is no
//! farther than the next candidate's t_enter.
//!
//! Hardware, as modelled here (`docs/units/sorter.md`):
//! - An N-lane sorting network of compare-exchange (CE) elements, one pipeline register per
//!   layer: latency = depth cycles, one batch of up to N keys accepted per cycle (II = 1).
//!   N = 2, 4, 8 and 16 use networks of the fewest comparators known (1/1, 5/3, 19/6, 60/10
//!   comparators/depth, Green's network for 16); every other N uses Batcher's odd–even merge
//!   sort pruned to N lanes.
//! - Lanes a ray leaves empty hold an invalid key that compares above every valid key; since
//!   every CE puts its smaller key on its lower lane, a CE touching an empty upper lane never
//!   moves anything, so the model simply skips it (`apply_network`).
//! - Order is total: a CE compares the tuple (t, id), so equal entry distances go lower
//!   instance id first. The order is then deterministic and equal to a sort by (t, id), the
//!   order of the f64 reference's stable sort of candidates listed by instance index.
//! - More than N candidates are never dropped: they are sorted in arrival-order chunks of N
//!   (one network issue each, II = 1), then the sorted runs are merged pairwise by a
//!   streaming two-way merger (one key per cycle) in ⌈log2 chunks⌉ passes through a
//!   ping-pong run buffer. Every extra chunk, pass, merge step and cycle is counted.

use crate::fixed::Format;
use serde::{Deserialize, Serialize};

/// One sort key: (t_enter raw code in [`SorterConfig::key`], instance id). Keys compare as
/// tuples, t first, then id (the tie rule).
pub type SortKey = (i64, u16);

/// Cycles of the streaming two-way merger per pass beyond its one key per cycle: the head
/// compare is registered once before the first key leaves.
pub const MERGE_LATENCY: u64 = 1;

/// Configuration of the sorter.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SorterConfig {
    /// Lanes of the sorting network (keys sorted per issue). Default 16 (issue 28): a
    /// 60-comparator, depth-10 network. With 8 lanes (19 comparators, depth 6) every ray of
    /// the car fits one issue, but a crowd of instances has rays with more candidates than
    /// lanes, and such a ray holds the sorter's input for its merges: `scenes/crowd_1000.ron`
    /// (9.5 candidates per ray) was sorter bound at 29.5 fps with 8 lanes and reaches 68.9
    /// with 16 (docs/cycle-model.md §7). The three-fold comparators are about 39k LUTs, 4 % of
    /// the part; elaboration narrows the network to a scene's instance count. 0 is invalid and is
    /// treated as 1 (no network, every key merged), counted in [`SorterStats::config_errors`].
    pub n: u8,
    /// Format of t_enter (the sphere unit's output). Default uQ10.22, truncating: t_enter is
    /// never negative (the sphere unit clamps it to 0), 1024 m covers any scene, and 2^−22 m
    /// keeps the order of candidates that differ by far less than a voxel. Truncation toward
    /// −∞ keeps early termination conservative: a key is never above the true t_enter, so a
    /// walk is never skipped that the exact key would have kept.
    pub key: Format,
}

impl Default for SorterConfig {
    fn default() -> Self {
        Self {
            n: 16,
            key: Format::uq(10, 22),
        }
    }
}

impl SorterConfig {
    /// Checks that the configuration describes hardware: N ≥ 1 and a valid key format.
    pub fn validate(&self) -> Result<(), String> {
        if self.n == 0 {
            return Err("sorter.n must be at least 1".into());
        }
        if !self.key.is_valid() {
            return Err(format!(
                "sorter.key: format {} is not valid",
                self.key.name()
            ));
        }
        Ok(())
    }
}

/// Counters of the sorter (`sorter/...` in reports). Tables merge by addition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SorterStats {
    /// Rays sorted with at least one candidate (`sorter/sorts`).
    pub sorts: u64,
    /// Keys sorted (`sorter/keys`).
    pub keys: u64,
    /// Network issues: one per chunk of up to N keys (`sorter/networks_run`).
    pub networks_run: u64,
    /// Chunks beyond the first, i.e. network issues caused by more than N candidates
    /// (`sorter/overflow_batches`).
    pub overflow_batches: u64,
    /// Passes of the two-way merger (`sorter/merge_passes`).
    pub merge_passes: u64,
    /// Keys moved through the merger, one per cycle (`sorter/merge_steps`).
    pub merge_steps: u64,
    /// Latency of all sorts, cycles (`sorter/cycles`).
    pub cycles: u64,
    /// Latency beyond one network pass, caused by more than N candidates
    /// (`sorter/extra_cycles`).
    pub extra_cycles: u64,
    /// Keys whose t code lay outside the key format and were clamped into it
    /// (`sorter/keys_clamped`): an upstream bug, since the sphere unit quantises into it.
    pub keys_clamped: u64,
    /// Sorts run with an invalid configuration (`sorter/config_errors`).
    pub config_errors: u64,
}

impl SorterStats {
    /// Adds another table's counts (each worker keeps its own; the frame sums them).
    pub fn merge(&mut self, o: &Self) {
        self.sorts += o.sorts;
        self.keys += o.keys;
        self.networks_run += o.networks_run;
        self.overflow_batches += o.overflow_batches;
        self.merge_passes += o.merge_passes;
        self.merge_steps += o.merge_steps;
        self.cycles += o.cycles;
        self.extra_cycles += o.extra_cycles;
        self.keys_clamped += o.keys_clamped;
        self.config_errors += o.config_errors;
    }
}

// Networks of the fewest comparators known, by layer. Each pair (i, j), i < j, puts the
// smaller key on lane i. They are checked exhaustively by the 0-1 principle in
// `rtl_model/tests/unit_sorter.rs`; sources are in `docs/units/sorter.md`.

/// 2 lanes: 1 comparator, depth 1.
const BEST_2: &[&[(u8, u8)]] = &[&[(0, 1)]];

/// 4 lanes: 5 comparators, depth 3 (optimal in both; Knuth TAOCP 3, §5.3.4).
const BEST_4: &[&[(u8, u8)]] = &[&[(0, 1), (2, 3)], &[(0, 2), (1, 3)], &[(1, 2)]];

/// 8 lanes: 19 comparators, depth 6 (optimal in both; Knuth TAOCP 3, §5.3.4).
const BEST_8: &[&[(u8, u8)]] = &[
    &[(0, 2), (1, 3), (4, 6), (5, 7)],
    &[(0, 4), (1, 5), (2, 6), (3, 7)],
    &[(0, 1), (2, 3), (4, 5), (6, 7)],
    &[(2, 4), (3, 5)],
    &[(1, 4), (3, 6)],
    &[(1, 2), (3, 4), (5, 6)],
];

/// 16 lanes: 60 comparators, depth 10 (Green 1969, the fewest comparators known; Knuth
/// TAOCP 3, §5.3.4), in the layered form of Dobbelaere's list of sorting networks.
const BEST_16: &[&[(u8, u8)]] = &[
    &[
        (0, 13),
        (1, 12),
        (2, 15),
        (3, 14),
        (4, 8),
        (5, 6),
        (7, 11),
        (9, 10),
    ],
    &[
        (0, 5),
        (1, 7),
        (2, 9),
        (3, 4),
        (6, 13),
        (8, 14),
        (10, 15),
        (11, 12),
    ],
    &[
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 8),
        (7, 9),
        (10, 11),
        (12, 13),
        (14, 15),
    ],
    &[
        (0, 2),
        (1, 3),
        (4, 10),
        (5, 11),
        (6, 7),
        (8, 9),
        (12, 14),
        (13, 15),
    ],
    &[(1, 2), (3, 12), (4, 6), (5, 7), (8, 10), (9, 11), (13, 14)],
    &[(1, 4), (2, 6), (5, 8), (7, 10), (9, 13), (11, 14)],
    &[(2, 4), (3, 6), (9, 12), (11, 13)],
    &[(3, 5), (6, 8), (7, 9), (10, 12)],
    &[(3, 4), (5, 6), (7, 8), (9, 10), (11, 12)],
    &[(6, 7), (8, 9)],
];

/// Batcher's odd–even merge sort for `n` lanes, as a comparator sequence: the network for
/// the next power of two P ≥ n with every comparator that touches a lane ≥ n removed. That
/// is exact, not an approximation: lanes ≥ n act as +∞ padding that no comparator moves.
/// For P = 2^k it has (k² − k + 4)·2^(k−2) − 1 comparators and depth k(k+1)/2.
fn batcher(n: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    if n < 2 {
        return out;
    }
    let p2 = n.next_power_of_two(); // n ≤ 255 here, so no overflow
    let mut p = 1;
    while p < p2 {
        let mut k = p;
        while k >= 1 {
            let mut j = k % p;
            while j + k < p2 {
                for i in 0..k {
                    let (a, b) = (i + j, i + j + k);
                    // Compare only within one block of 2p lanes: the merge of two sorted
                    // runs of p lanes each.
                    if b < p2 && a / (2 * p) == b / (2 * p) && b < n {
                        out.push((a, b));
                    }
                }
                j += 2 * k;
            }
            k /= 2;
        }
        p *= 2;
    }
    out
}

/// Layers a comparator sequence as soon as possible: each comparator goes one layer after the
/// latest comparator before it on either of its lanes. This keeps the network's function
/// (comparators on disjoint lanes commute) and gives its true depth.
fn layer(seq: &[(usize, usize)], n: usize) -> Vec<Vec<(usize, usize)>> {
    let mut last = vec![0usize; n];
    let mut stages: Vec<Vec<(usize, usize)>> = Vec::new();
    for &(i, j) in seq {
        let (Some(&li), Some(&lj)) = (last.get(i), last.get(j)) else {
            continue;
        };
        let s = li.max(lj); // 0-based stage index of this comparator
        if stages.len() <= s {
            stages.resize_with(s + 1, Vec::new);
        }
        stages[s].push((i, j));
        last[i] = s + 1;
        last[j] = s + 1;
    }
    stages
}

/// The network for `n` lanes by layer (stage): the fewest comparators known for n = 2, 4,
/// 8, 16, Batcher's odd–even merge sort otherwise. Every pair (i, j) has i < j < n and puts
/// the smaller key on lane i; pairs within one layer touch disjoint lanes. n ≤ 1 gives no
/// layers.
pub fn network_stages(n: u8) -> Vec<Vec<(usize, usize)>> {
    let table = match n {
        2 => Some(BEST_2),
        4 => Some(BEST_4),
        8 => Some(BEST_8),
        16 => Some(BEST_16),
        _ => None,
    };
    let seq: Vec<(usize, usize)> = match table {
        Some(t) => t
            .iter()
            .flat_map(|s| s.iter().map(|&(i, j)| (usize::from(i), usize::from(j))))
            .collect(),
        None => batcher(usize::from(n)),
    };
    layer(&seq, usize::from(n))
}

/// The network for `n` lanes as comparator pairs in stage order (see [`network_stages`]).
///
/// ```
/// use rtl_model::units::sorter::network;
/// assert_eq!(network(4), vec![(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)]);
/// ```
pub fn network(n: u8) -> Vec<(usize, usize)> {
    network_stages(n).concat()
}

/// Compare-exchange elements of the `n`-lane network: 5 for 4, 19 for 8, 60 for 16.
pub fn comparator_count(n: u8) -> usize {
    network_stages(n).iter().map(Vec::len).sum()
}

/// Layers of the `n`-lane network, which is its pipeline depth: 3 for 4, 6 for 8, 10 for 16.
pub fn depth(n: u8) -> usize {
    network_stages(n).len()
}

/// Latency of one network issue, cycles: one register per layer.
pub fn network_latency(n: u8) -> u64 {
    depth(n) as u64
}

/// Initiation interval of the network, cycles: fully pipelined, a new batch of up to N keys
/// every cycle.
pub fn network_ii(_n: u8) -> u64 {
    1
}

/// One compare-exchange: the smaller (t, id) to the lower of the two lanes. Lanes outside
/// `keys` are empty (+∞) lanes and leave the keys unchanged.
#[inline]
pub fn compare_exchange(keys: &mut [SortKey], i: usize, j: usize) {
    let (lo, hi) = (i.min(j), i.max(j));
    if hi < keys.len() && keys[lo] > keys[hi] {
        keys.swap(lo, hi);
    }
}

/// Runs a comparator sequence over `keys`. Comparators touching a lane at or beyond
/// `keys.len()` are skipped, which is what a network does whose upper lanes are empty.
pub fn apply_network(net: &[(usize, usize)], keys: &mut [SortKey]) {
    for &(i, j) in net {
        compare_exchange(keys, i, j);
    }
}

/// Work and timing of sorting `count` keys on an `n`-lane sorter (n = 0 is taken as 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SortTiming {
    /// Network issues: ⌈count / n⌉.
    pub chunks: u64,
    /// Merge passes: ⌈log2 chunks⌉.
    pub merge_passes: u64,
    /// Keys through the merger: passes · count (a run without a partner in a pass is copied
    /// through the merger all the same, since the next pass reads the other buffer).
    pub merge_steps: u64,
    /// Cycles from the first key in to the last key out: depth for one chunk; otherwise
    /// (chunks − 1) + depth + passes · (count + [`MERGE_LATENCY`]). 0 for no keys (nothing
    /// to sort: the statistics count no sort; the cycle model still passes the ray through
    /// the network as an empty issue, see [`pipe_cost`]).
    pub latency: u64,
    /// Cycles the network is occupied (one per chunk).
    pub network_busy: u64,
    /// Cycles the merger is occupied.
    pub merger_busy: u64,
    /// Cycles the ray holds the sorter's input before the next ray may enter: 1 for one chunk
    /// (the network's II); for several, `latency − depth + 1` (the chunks' issues and every
    /// merge pass), so that the next ray's network pass ends after this ray's last key left.
    /// The unit has one merger and no reorder buffer: two rays never merge at once and results
    /// leave in order (`testbench/rtl/svo_sorter.v` takes exactly these cycles).
    pub occupancy: u64,
}

/// The cycle model's parameters for one ray of `count` candidates (documented in
/// [`SortTiming`]); [`Sorter::sort`] counts exactly this.
pub fn sort_timing(count: usize, n: u8) -> SortTiming {
    sort_timing_with_latency(count, n, network_latency(n.max(1)))
}

/// [`sort_timing`] with the network latency given (a [`Sorter`] knows it, so its hot path
/// does not rebuild the network to measure it).
fn sort_timing_with_latency(count: usize, n: u8, d: u64) -> SortTiming {
    if count == 0 {
        return SortTiming::default();
    }
    let n = usize::from(n.max(1));
    let count64 = count as u64;
    let chunks = count.div_ceil(n) as u64;
    let passes = u64::from(64 - (chunks - 1).leading_zeros()); // ⌈log2 chunks⌉, 0 for 1
    let merge_cycles = passes * (count64 + MERGE_LATENCY);
    let latency = (chunks - 1) + d + merge_cycles;
    SortTiming {
        chunks,
        merge_passes: passes,
        merge_steps: passes * count64,
        latency,
        network_busy: chunks,
        merger_busy: merge_cycles,
        occupancy: if chunks > 1 { latency - d + 1 } else { 1 },
    }
}

/// What the cycle model's sorter stage (`src/models/cycle/stages/sorter.rs`) gives a
/// `UnitPipe` of latency `network_latency` for a ray of `count` candidates on `lanes` lanes:
/// (initiation intervals the ray occupies the input, latency beyond the network's). A ray
/// without candidates still passes the network as an empty issue: (1, 0). The vector stage
/// times its rows with this and the same `UnitPipe`, so the RTL is checked against the cycle
/// model's own code.
pub fn pipe_cost(count: usize, lanes: u8, network_latency: u32) -> (u64, u64) {
    let t = sort_timing(count, lanes);
    (
        t.occupancy.max(1),
        t.latency.saturating_sub(u64::from(network_latency)),
    )
}

/// Hardware cost of a sorter configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SorterResources {
    /// Compare-exchange elements.
    pub comparators: usize,
    /// Pipeline layers.
    pub depth: usize,
    /// Width of one comparison: key width + id bits.
    pub compare_bits: u32,
    /// Comparators × compare bits (the magnitude-comparator bits, ~one LUT-carry bit each).
    pub comparator_bits: u64,
    /// Pipeline registers: depth × lanes × (compare bits + 1 valid bit).
    pub register_bits: u64,
}

/// Comparators, depth and register bits of the network for `cfg`, with instance ids of
/// `id_bits` bits (the hit record's `instance_bits`, 8 by default).
pub fn resources(cfg: &SorterConfig, id_bits: u8) -> SorterResources {
    let comparators = comparator_count(cfg.n);
    let depth = depth(cfg.n);
    let compare_bits = u32::from(cfg.key.width) + u32::from(id_bits);
    SorterResources {
        comparators,
        depth,
        compare_bits,
        comparator_bits: comparators as u64 * u64::from(compare_bits),
        register_bits: depth as u64 * u64::from(cfg.n) * (u64::from(compare_bits) + 1),
    }
}

/// Merges two sorted runs, one key per step, the left run first on equal keys (equal keys are
/// identical tuples, so this only fixes which copy goes first).
fn merge_two(a: &[SortKey], b: &[SortKey]) -> Vec<SortKey> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] <= b[j] {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

/// A sorter with its network built once, for sorting many rays with one configuration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sorter {
    cfg: SorterConfig,
    net: Vec<(usize, usize)>,
    /// Network latency, cycles (its depth).
    latency: u64,
    /// Model speed-up: per key count k ≤ n, the comparators of `net` with both lanes below k,
    /// in order — the only ones that act when the lanes from k up are empty.
    net_by_count: Vec<Vec<(usize, usize)>>,
    /// Whether `cfg` validates (checked once, not per sort).
    valid: bool,
}

impl Sorter {
    /// Builds the network for `cfg.n` lanes (n = 0 is taken as 1).
    pub fn new(cfg: &SorterConfig) -> Self {
        let net = network(cfg.n.max(1));
        let net_by_count = (0..=usize::from(cfg.n.max(1)))
            .map(|k| net.iter().copied().filter(|&(i, j)| i.max(j) < k).collect())
            .collect();
        Self {
            cfg: cfg.clone(),
            net,
            latency: network_latency(cfg.n.max(1)),
            net_by_count,
            valid: cfg.validate().is_ok(),
        }
    }

    /// The configuration.
    pub fn config(&self) -> &SorterConfig {
        &self.cfg
    }

    /// Sorts one ray's candidates front to back, by (t, id), as the hardware does: chunks of N
    /// through the network, then two-way merge passes over the sorted runs. Any number of keys
    /// is handled and returned (none dropped, none duplicated). t codes outside `cfg.key` are
    /// clamped into it first and counted; the returned keys are the clamped ones.
    ///
    /// ```
    /// use rtl_model::units::sorter::{Sorter, SorterConfig, SorterStats};
    /// let cfg = SorterConfig::default();
    /// let mut st = SorterStats::default();
    /// let out = Sorter::new(&cfg).sort(&[(30, 2), (10, 7), (30, 1)], &mut st);
    /// assert_eq!(out, vec![(10, 7), (30, 1), (30, 2)]); // equal t: lower id first
    /// assert_eq!((st.networks_run, st.merge_steps), (1, 0));
    /// ```
    pub fn sort(&self, keys: &[(i64, u16)], stats: &mut SorterStats) -> Vec<(i64, u16)> {
        let cfg = &self.cfg;
        if cfg.validate().is_err() {
            stats.config_errors += 1;
        }
        if keys.is_empty() {
            return Vec::new();
        }
        let n = cfg.n.max(1);
        // Min/max raw codes are only defined for valid formats; an invalid one sorts unclamped.
        let range = cfg
            .key
            .is_valid()
            .then(|| (cfg.key.min_raw(), cfg.key.max_raw()));
        let mut lanes: Vec<SortKey> = keys
            .iter()
            .map(|&(t, id)| match range {
                Some((lo, hi)) if t < lo || t > hi => {
                    stats.keys_clamped += 1;
                    (t.clamp(lo, hi), id)
                }
                _ => (t, id),
            })
            .collect();

        // Network pass: each chunk of up to n keys is one issue.
        let mut runs: Vec<Vec<SortKey>> = Vec::with_capacity(lanes.len().div_ceil(usize::from(n)));
        for chunk in lanes.chunks_mut(usize::from(n)) {
            apply_network(&self.net, chunk);
            runs.push(chunk.to_vec());
        }

        // Merge passes: pairs of neighbouring runs, the odd last run copied through.
        while runs.len() > 1 {
            let mut next = Vec::with_capacity(runs.len().div_ceil(2));
            for pair in runs.chunks(2) {
                match pair {
                    [a, b] => next.push(merge_two(a, b)),
                    [a] => next.push(a.clone()),
                    _ => {}
                }
            }
            runs = next;
        }

        self.count(keys.len(), stats);
        runs.pop().unwrap_or_default()
    }

    /// Sorts in place when the keys fit one network issue (the common case, without the
    /// model's allocations); otherwise as [`Sorter::sort`]. Same order and statistics.
    pub fn sort_in_place(&self, keys: &mut Vec<(i64, u16)>, stats: &mut SorterStats) {
        let n = self.cfg.n.max(1);
        if keys.is_empty() {
            // What `sort` does with no keys: count an invalid configuration, return none.
            stats.config_errors += u64::from(!self.valid);
            return;
        }
        if keys.len() > usize::from(n) || !self.cfg.key.is_valid() || self.cfg.n == 0 {
            let sorted = self.sort(keys, stats);
            keys.clear();
            keys.extend_from_slice(&sorted);
            return;
        }
        let (lo, hi) = (self.cfg.key.min_raw(), self.cfg.key.max_raw());
        for k in keys.iter_mut() {
            if k.0 < lo || k.0 > hi {
                stats.keys_clamped += 1;
                k.0 = k.0.clamp(lo, hi);
            }
        }
        // One key is already in order: every comparator touches an empty lane (model
        // speed-up; the statistics still count the issue).
        if keys.len() > 1 {
            // The comparators that touch an empty lane are skipped (`apply_network`), so the
            // ones left for this count do the same (keys.len() ≤ n here: `net_by_count` has
            // an entry for it).
            apply_network(&self.net_by_count[keys.len()], keys);
        }
        self.count(keys.len(), stats);
    }

    /// Statistics of one sort of `count` keys.
    fn count(&self, count: usize, stats: &mut SorterStats) {
        let n = self.cfg.n.max(1);
        let t = sort_timing_with_latency(count, n, self.latency);
        stats.sorts += 1;
        stats.keys += count as u64;
        stats.networks_run += t.chunks;
        stats.overflow_batches += t.chunks - 1;
        stats.merge_passes += t.merge_passes;
        stats.merge_steps += t.merge_steps;
        stats.cycles += t.latency;
        stats.extra_cycles += t.latency - self.latency;
    }
}
