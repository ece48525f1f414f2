//! Sorter vectors: one ray's candidates per row, up to [`rows_max_keys`] = 4N keys
//! (t_enter, instance) in arrival order, out in walk order (`units::sorter::Sorter::sort`:
//! chunks of N through the network, then the merge passes; ties by lower instance id), with
//! the cycles the cycle model takes for the ray: `cycles` from accept to result and `busy`
//! before the sorter accepts the next ray. Both come from the cycle model's own code: the
//! sorter stage's cost (`units::sorter::pipe_cost`) through a `cycle::unit_pipe::UnitPipe` of
//! the default hardware's sorter latency, exactly as `src/models/cycle/stages/sorter.rs` runs it.
//!
//! Adversarial cases: every key count 0..=4N (one chunk, two, three with a run copied through
//! a pass, four), all 2^N zero-one inputs when N ≤ 8 (the 0-1 principle: a network that sorts
//! them sorts everything), equal entry distances with ids in every order (ties, also across
//! chunks), identical duplicate keys, already sorted and reversed rays of the most keys, and
//! the extreme codes 0 and the maximum.

use super::{dedup, Stage};
use crate::cycle::hw_config::UnitTimings;
use crate::cycle::unit_pipe::UnitPipe;
use crate::datapath::DatapathConfig;
use crate::units::sorter::{pipe_cost, Sorter, SorterConfig, SorterStats};
use crate::vectors::layout::{s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// One transaction: one ray's keys (t_enter code, instance id) in arrival order, at most
/// [`rows_max_keys`].
pub type SorterTxn = Vec<(i64, u16)>;

/// Bits of the `cycles` and `busy` fields.
const CYCLE_BITS: u32 = 16;

/// Most keys in one row: four network issues, so rows cover one chunk, two (one merge
/// pass), three (a run copied through a pass) and four (two full passes). Rays with more
/// candidates are left out of the captured rows.
pub fn rows_max_keys(cfg: &SorterConfig) -> usize {
    4 * usize::from(cfg.n.max(1))
}

/// The sorter stage for a datapath configuration.
pub struct SorterStage {
    cfg: SorterConfig,
    sorter: Sorter,
    id_bits: u32,
    timing: Timing,
}

impl SorterStage {
    /// The sorter of `dp`; instance ids are as wide as the hit record's.
    pub fn new(dp: &DatapathConfig) -> Self {
        let t = UnitTimings::for_datapath(dp).sorter;
        Self {
            cfg: dp.sorter.clone(),
            sorter: Sorter::new(&dp.sorter),
            id_bits: u32::from(dp.hit_record.instance_bits.clamp(1, 16)),
            timing: Timing {
                latency_cycles: t.latency_cycles,
                ii: t.ii,
            },
        }
    }

    fn lanes(&self) -> usize {
        usize::from(self.cfg.n.max(1))
    }

    fn max_keys(&self) -> usize {
        rows_max_keys(&self.cfg)
    }

    fn count_bits(&self) -> u32 {
        usize::BITS - self.max_keys().leading_zeros()
    }

    fn max_id(&self) -> u16 {
        ((1u32 << self.id_bits) - 1) as u16
    }

    /// The cycle model's timing of a ray of `count` keys entering an idle sorter: (cycles
    /// until its result leaves, cycles until the next ray may enter). The stage's cost and
    /// the `UnitPipe` are the cycle model's own; nothing here is a second formula.
    pub fn predicted_cycles(&self, count: usize) -> (u64, u64) {
        let (passes, extra) = pipe_cost(count, self.cfg.n.max(1), self.timing.latency_cycles);
        let mut pipe = UnitPipe::new(self.timing.latency_cycles, self.timing.ii);
        pipe.accept(0, (), passes, extra);
        let (mut cycles, mut busy) = (None, None);
        let limit = u64::from(self.timing.latency_cycles) + extra + passes + 2;
        for now in 1..=limit {
            if cycles.is_none() && pipe.pop(now).is_some() {
                cycles = Some(now);
            }
            if busy.is_none() && pipe.can_accept(now) {
                busy = Some(now);
            }
        }
        (cycles.unwrap_or(limit), busy.unwrap_or(limit))
    }
}

impl Stage for SorterStage {
    type Txn = SorterTxn;

    fn name(&self) -> &'static str {
        "sorter"
    }

    fn description(&self) -> &'static str {
        "one ray per row: key count and up to 4N keys in arrival order in; the keys sorted by (t_enter, id) out, lanes at or above the count 0; the cycle model's cycles from accept to result and until the next ray may enter"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.uint(
            "count",
            Input,
            self.count_bits(),
            "keys of this ray (0..=4N)",
        );
        for k in 0..self.max_keys() {
            l.fixed(
                &format!("in_t{k}"),
                Input,
                self.cfg.key,
                "entry distance of lane k, m",
            );
            l.uint(
                &format!("in_id{k}"),
                Input,
                self.id_bits,
                "instance of lane k",
            );
        }
        for k in 0..self.max_keys() {
            l.fixed(
                &format!("out_t{k}"),
                Output,
                self.cfg.key,
                "k-th nearest entry distance, m",
            );
            l.uint(&format!("out_id{k}"), Output, self.id_bits, "its instance");
        }
        l.uint(
            "cycles",
            Output,
            CYCLE_BITS,
            "the cycle model's cycles from accepting the ray to its result (idle sorter)",
        );
        l.uint(
            "busy",
            Output,
            CYCLE_BITS,
            "the cycle model's cycles from accepting the ray until the next may enter",
        );
        l
    }

    fn adversarial(&self) -> Vec<SorterTxn> {
        let n = self.lanes();
        let tmax = self.cfg.key.max_raw();
        let idmax = self.max_id();
        let m = self.max_keys();
        let mut v: Vec<SorterTxn> = Vec::new();
        for count in 0..=m {
            v.push(
                (0..count)
                    .map(|k| ((count - k) as i64 * 1000, k as u16))
                    .collect(),
            );
        }
        if n <= 8 {
            for pattern in 0u32..1 << n {
                v.push(
                    (0..n)
                        .map(|k| (i64::from((pattern >> k) & 1), k as u16))
                        .collect(),
                );
            }
        }
        // Ties: equal t, ids descending, ascending and interleaved; identical duplicates.
        v.push((0..n).map(|k| (77, (n - 1 - k) as u16)).collect());
        v.push((0..n).map(|k| (77, k as u16)).collect());
        v.push((0..n).map(|k| (5, ((k * 5 + 3) % n) as u16)).collect());
        v.push((0..n).map(|k| ((k / 2) as i64, (k % 2) as u16)).collect());
        v.push((0..n).map(|_| (9, 4)).collect());
        v.push(
            (0..n)
                .map(|k| (if k % 2 == 0 { 9 } else { 3 }, 1))
                .collect(),
        );
        // Extremes.
        v.push(
            (0..n)
                .map(|k| (if k % 2 == 0 { tmax } else { 0 }, idmax - k as u16))
                .collect(),
        );
        v.push((0..n).map(|k| (tmax - k as i64, idmax)).collect());
        v.push((0..n).map(|_| (tmax, 0)).collect());
        v.push((0..n).map(|k| (k as i64, k as u16)).collect());
        // Several chunks: ties across chunks (equal t, ids descending, so every merge decides
        // by id), identical keys, sorted and reversed inputs, the extremes, and the counts
        // just above each chunk boundary with everything equal.
        let ids = |k: usize| (k % (usize::from(idmax) + 1)) as u16;
        v.push((0..m).map(|k| (77, ids(m - 1 - k))).collect());
        v.push((0..m).map(|_| (9, 4)).collect());
        v.push((0..m).map(|k| (k as i64, ids(k))).collect());
        v.push((0..m).map(|k| ((m - k) as i64, ids(k))).collect());
        v.push(
            (0..m)
                .map(|k| (tmax - (k % 3) as i64, idmax - ids(k % 5)))
                .collect(),
        );
        v.push(
            (0..m)
                .map(|k| (if k % 2 == 0 { tmax } else { 0 }, ids(k)))
                .collect(),
        );
        for chunks in 1..m.div_ceil(n) {
            v.push(
                (0..chunks * n + 1)
                    .map(|k| (3, ids(chunks * n - k)))
                    .collect(),
            );
            // The last chunk holds the smallest keys: the merges must move them to the front.
            v.push(
                (0..chunks * n + 1)
                    .map(|k| ((chunks * n + 1 - k) as i64 * 1000, ids(k)))
                    .collect(),
            );
        }
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> SorterTxn {
        let n = self.lanes() as u64;
        // Two rays in three fit one issue (the common case); the rest need merges.
        let count = if rng.one_in(3) {
            self.lanes() + 1 + rng.below((self.max_keys() - self.lanes()) as u64) as usize
        } else {
            1 + rng.below(n) as usize
        };
        let narrow = rng.one_in(3); // few distinct values: ties
        (0..count)
            .map(|_| {
                let t = if narrow {
                    rng.below(4) as i64
                } else {
                    (rng.bits_up_to(u32::from(self.cfg.key.width)) as i64)
                        .clamp(0, self.cfg.key.max_raw())
                };
                (t, rng.below(u64::from(self.max_id()) + 1) as u16)
            })
            .collect()
    }

    fn encode(&self, keys: &SorterTxn) -> Vec<u128> {
        let n = self.max_keys();
        let keys = &keys[..keys.len().min(n)];
        let sorted = self.sorter.sort(keys, &mut SorterStats::default());
        let lane = |v: &[(i64, u16)], k: usize| v.get(k).copied().unwrap_or((0, 0));
        let mut out = vec![u(keys.len() as u64)];
        for k in 0..n {
            let (t, id) = lane(keys, k);
            out.extend([s(t), u(u64::from(id))]);
        }
        for k in 0..n {
            let (t, id) = lane(&sorted, k);
            out.extend([s(t), u(u64::from(id))]);
        }
        let (cycles, busy) = self.predicted_cycles(keys.len());
        out.extend([u(cycles), u(busy)]);
        out
    }

    fn timing(&self) -> Option<Timing> {
        Some(self.timing)
    }

    fn parameters(&self, t: &mut VectorTable) {
        // The network the RTL elaborates (`svo_sorter`'s N, D and PAIRS): the model's own,
        // so the RTL and the model share one description of it.
        let net = NetworkPairs::new(self.cfg.n.max(1));
        t.constants.push((
            "NET_LANES".into(),
            i64::from(net.lanes),
            "sorting network lanes N (the datapath's sorter.n)".into(),
        ));
        t.constants.push((
            "NET_DEPTH".into(),
            net.depth as i64,
            "network layers D, one register each".into(),
        ));
        t.constants.push((
            "NET_SLOTS".into(),
            net.slots as i64,
            "comparator slots per layer, max(N / 2, 1)".into(),
        ));
        t.bit_constants.push((
            "NET_PAIRS".into(),
            net.width(),
            net.hex(),
            "comparator (i, j), i < j, of layer l, slot p as {i[7:0], j[7:0]} at [(l*NET_SLOTS + p)*16 +: 16]; unused slots 0".into(),
        ));
        t.param("config", &self.cfg);
        t.param("id_bits", self.id_bits);
        t.param("network", crate::units::sorter::network_stages(self.cfg.n));
        t.param("max_keys", self.max_keys());
        t.param("merge_latency", crate::units::sorter::MERGE_LATENCY);
    }
}

pub use crate::units::sorter_network::NetworkPairs;

#[cfg(test)]
mod tests {
    use super::*;

    /// The datapath with an 8-lane network, the width these hand counts were made for (the
    /// default has 16 lanes since issue 28).
    fn eight_lanes() -> DatapathConfig {
        let mut dp = DatapathConfig::default();
        dp.sorter.n = 8;
        dp
    }

    #[test]
    fn rows_decode_to_a_plain_sort() {
        for dp in [eight_lanes(), DatapathConfig::default()] {
            rows_decode_to_a_plain_sort_at(&dp);
        }
    }

    fn rows_decode_to_a_plain_sort_at(dp: &DatapathConfig) {
        let st = SorterStage::new(dp);
        let l = st.layout();
        let mut rng = Rng::new(5);
        let mut cases = st.adversarial();
        // Up to 8 lanes every 0/1 pattern of the lanes is a row (2^n); wider, the counts,
        // ties and extremes only.
        let floor = if st.lanes() <= 8 { 256 } else { 32 };
        assert!(cases.len() > floor, "{} adversarial rows", cases.len());
        cases.extend((0..500).map(|_| st.random(&mut rng)));
        for keys in cases {
            let w = l.pack(&st.encode(&keys));
            let mut want = keys.clone();
            want.sort(); // the oracle: a plain tuple sort
            for (k, &(t, id)) in want.iter().enumerate() {
                assert_eq!(l.read(&w, &format!("out_t{k}")), Some(i128::from(t)));
                assert_eq!(l.read(&w, &format!("out_id{k}")), Some(i128::from(id)));
            }
            assert_eq!(l.read(&w, "count"), Some(keys.len() as i128));
        }
    }

    #[test]
    fn predicted_cycles_follow_the_documented_timing() {
        // docs/units/sorter.md §6, by hand: D = 6 on 8 lanes.
        let st = SorterStage::new(&eight_lanes());
        assert_eq!(st.predicted_cycles(0), (6, 1));
        assert_eq!(st.predicted_cycles(8), (6, 1));
        assert_eq!(st.predicted_cycles(9), (1 + 6 + 10, 1 + 10 + 1));
        assert_eq!(st.predicted_cycles(17), (2 + 6 + 2 * 18, 2 + 2 * 18 + 1));
        assert_eq!(st.predicted_cycles(32), (3 + 6 + 2 * 33, 3 + 2 * 33 + 1));
    }
}
