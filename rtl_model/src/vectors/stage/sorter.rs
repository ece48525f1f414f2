//! Sorter vectors: one issue of the sorting network, up to N (t_enter, instance) keys of one
//! ray in arrival order, out in walk order (`units::sorter::Sorter::sort`, ties by lower
//! instance id). Rays with more than N candidates are several issues (one per chunk of N in
//! arrival order) plus merge passes; the rows here are single issues.
//!
//! Adversarial cases: every key count 0..=N, all 2^N zero-one inputs when N ≤ 8 (the 0-1
//! principle: a network that sorts them sorts everything), equal entry distances with ids in
//! every order (ties), identical duplicate keys, and the extreme codes 0 and the maximum.

use super::{dedup, Stage};
use crate::cycle::hw_config::UnitTimings;
use crate::datapath::DatapathConfig;
use crate::units::sorter::{Sorter, SorterConfig, SorterStats};
use crate::vectors::layout::{s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{Timing, VectorTable};

/// One transaction: the keys (t_enter code, instance id) in arrival order, at most N.
pub type SorterTxn = Vec<(i64, u16)>;

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

    fn count_bits(&self) -> u32 {
        usize::BITS - self.lanes().leading_zeros()
    }

    fn max_id(&self) -> u16 {
        ((1u32 << self.id_bits) - 1) as u16
    }
}

impl Stage for SorterStage {
    type Txn = SorterTxn;

    fn name(&self) -> &'static str {
        "sorter"
    }

    fn description(&self) -> &'static str {
        "one sorting-network issue per row: key count and up to N keys in arrival order in; the keys sorted by (t_enter, id) out; lanes at or above the count are 0"
    }

    fn layout(&self) -> Layout {
        let mut l = Layout::new();
        l.uint(
            "count",
            Input,
            self.count_bits(),
            "keys in this issue (0..=N)",
        );
        for k in 0..self.lanes() {
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
        for k in 0..self.lanes() {
            l.fixed(
                &format!("out_t{k}"),
                Output,
                self.cfg.key,
                "k-th nearest entry distance, m",
            );
            l.uint(&format!("out_id{k}"), Output, self.id_bits, "its instance");
        }
        l
    }

    fn adversarial(&self) -> Vec<SorterTxn> {
        let n = self.lanes();
        let tmax = self.cfg.key.max_raw();
        let idmax = self.max_id();
        let mut v: Vec<SorterTxn> = Vec::new();
        for count in 0..=n {
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
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> SorterTxn {
        let n = self.lanes() as u64;
        let count = 1 + rng.below(n) as usize;
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
        let n = self.lanes();
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
        out
    }

    fn timing(&self) -> Option<Timing> {
        Some(self.timing)
    }

    fn parameters(&self, t: &mut VectorTable) {
        t.param("config", &self.cfg);
        t.param("id_bits", self.id_bits);
        t.param("network", crate::units::sorter::network_stages(self.cfg.n));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_decode_to_a_plain_sort() {
        let st = SorterStage::new(&DatapathConfig::default());
        let l = st.layout();
        let mut rng = Rng::new(5);
        let mut cases = st.adversarial();
        assert!(cases.len() > 256);
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
}
