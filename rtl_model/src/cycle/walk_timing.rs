//! One walk's cycles as the cycle model times it: the walker pool with one walker and one
//! context, in front of a node memory whose every read takes the same fixed latency. This is
//! the prediction an RTL walker is held to (`walker.hex`'s `cycles_*` fields,
//! `docs/vectors.md` §3): cycles from the cycle the walker accepts the walk (the pool's
//! dispatch) to the cycle its result leaves (the pool's retire, with the record stage always
//! ready).
//!
//! Pipeline position: beside the walker pool (`walker_pool.rs`), for the vectors. It drives
//! the pool through its public per-cycle entry points in the order the frame pipeline's
//! walker stage uses (`wake`, `retire`, `dispatch`, `issue`), so the timing is the pool's own
//! code, not a second formula.
//!
//! The fixed-latency memory is the node-memory model configured so every read takes
//! `latency` cycles: the whole node image is on chip (one bank, one port: a single context
//! never has two reads outstanding) with that latency, and attribute records, which the model
//! never keeps on chip, are cache hits of that latency: the walk's attribute lines are read
//! once into the cache before the walk starts, and the walk is timed from a later cycle.

use super::hw_config::WalkerPool as PoolConfig;
use super::memory::{
    CacheConfig, DramConfig, FetchKind, MemoryLayout, NodeMemory, NodeMemoryConfig, OnChipConfig,
};
use super::walk_op::WalkOp;
use super::walker_pool::WalkerPoolModel;
use thiserror::Error;

/// Why a walk could not be timed.
#[derive(Debug, Error)]
pub enum WalkTimingError {
    /// The memory or the pool rejected the configuration or a read.
    #[error("walk timing: {0}")]
    Model(String),
    /// The walk did not finish within the cycle budget (a broken op list).
    #[error("walk timing: the walk did not finish within {0} cycles")]
    Runaway(u64),
}

/// Cycles one walk takes on one walker context with a fixed-latency memory.
#[derive(Clone, Debug)]
pub struct WalkTiming {
    pool: PoolConfig,
    node_words: u64,
    attr_records: u64,
}

/// Most cycles a timed walk may take before it is declared broken.
const MAX_WALK_CYCLES: u64 = 1 << 40;

impl WalkTiming {
    /// Timing for walks over an image of `node_words` words and `attr_records` attribute
    /// records, with the step timing of `pool` (its walker and context counts are replaced by
    /// one each).
    pub fn new(pool: &PoolConfig, node_words: u64, attr_records: u64) -> Self {
        let pool = PoolConfig {
            walkers: 1,
            contexts_per_walker: 1,
            ..pool.clone()
        };
        Self {
            pool,
            node_words: node_words.max(1),
            attr_records: attr_records.max(1),
        }
    }

    /// Cycles from dispatch to retire of the walk whose ops are `ops` (packed
    /// [`WalkOp`]s, as [`super::walk_op::OpRecorder`] writes them), every read taking
    /// `latency` cycles.
    pub fn cycles(&self, ops: &[u64], latency: u32) -> Result<u64, WalkTimingError> {
        let model = |e: String| WalkTimingError::Model(e);
        let cfg = NodeMemoryConfig {
            onchip: OnChipConfig {
                levels: crate::svo::MAX_DEPTH + 1,
                max_bytes: u64::MAX,
                latency,
                banks: 1,
                ports_per_bank: 1,
                combine: false,
            },
            cache: CacheConfig {
                size_bytes: 64,
                ways: 1,
                line_bytes: 64,
                hit_latency: latency,
                ports: 1,
                attr_cached: true,
                banks: 1,
                miss_queue: 0,
            },
            dram: DramConfig::default(),
        };
        let nw = u32::try_from(self.node_words)
            .map_err(|_| model(format!("{} node words", self.node_words)))?;
        let layout =
            MemoryLayout::with_onchip_ranges(self.node_words, self.attr_records, vec![(0, nw)])
                .map_err(|e| model(e.to_string()))?;
        let mut mem = NodeMemory::new(cfg, layout).map_err(|e| model(e.to_string()))?;
        // Warm the cache with the walk's attribute reads (at most one per walk; the one-line
        // cache holds it), so they take `latency` like every node read.
        for &op in ops {
            if let WalkOp::Read(FetchKind::Attr, a) = WalkOp::unpack(op) {
                mem.request(0, a, FetchKind::Attr, u32::MAX)
                    .map_err(|e| model(e.to_string()))?;
            }
        }
        let _ = mem.drain();
        let start = mem.now();
        let mut pool = WalkerPoolModel::new(&self.pool).map_err(|e| model(e.to_string()))?;
        let mut now = start;
        pool.wake(now, &mut mem).map_err(|e| model(e.to_string()))?;
        if !pool.dispatch(0, ops) {
            return Err(model("the idle pool refused a walk".into()));
        }
        pool.issue();
        loop {
            now += 1;
            if now - start > MAX_WALK_CYCLES {
                return Err(WalkTimingError::Runaway(MAX_WALK_CYCLES));
            }
            pool.wake(now, &mut mem).map_err(|e| model(e.to_string()))?;
            if pool.finished_head().is_some() && pool.retire().is_some() {
                return Ok(now - start);
            }
            pool.issue();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ops(v: &[WalkOp]) -> Vec<u64> {
        v.iter().map(|o| o.pack()).collect()
    }

    #[test]
    fn hand_timed_walks() {
        // Step latency 3 (the walker of one context), whatever the default's.
        let pool = PoolConfig {
            step_latency_cycles: 3,
            ..PoolConfig::default()
        };
        let t = WalkTiming::new(&pool, 100, 10);
        // A root miss: no ops, the result one cycle after dispatch.
        assert_eq!(t.cycles(&[], 5).unwrap(), 1);
        // Root read (request at +1, data at +1+L), 2 slots 3 apart, the last one's successor
        // 3 later: 1 + L + 3 + 3.
        let miss = ops(&[WalkOp::Read(FetchKind::Node, 0), WalkOp::Issue(2)]);
        for l in [1, 3, 60] {
            assert_eq!(t.cycles(&miss, l).unwrap(), 1 + u64::from(l) + 6);
        }
        // A hit: root, one slot, the leaf slot read 3 later, the attribute read in the cycle
        // its index arrives: 1 + L + 3 + L + L.
        let hit = ops(&[
            WalkOp::Read(FetchKind::Node, 0),
            WalkOp::Issue(1),
            WalkOp::Read(FetchKind::Node, 7),
            WalkOp::Read(FetchKind::Attr, 3),
        ]);
        for l in [1, 3, 60] {
            assert_eq!(t.cycles(&hit, l).unwrap(), 1 + 3 * u64::from(l) + 3);
        }
        // The default's step latency (4, the barrel walker's) adds one cycle per step.
        let t4 = WalkTiming::new(
            &PoolConfig {
                step_latency_cycles: 4,
                ..PoolConfig::default()
            },
            100,
            10,
        );
        assert_eq!(t4.cycles(&miss, 3).unwrap(), 1 + 3 + 8);
        assert_eq!(t4.cycles(&hit, 3).unwrap(), 1 + 3 * 3 + 4);
    }
}
