//! What a worker counts over its pixels (saturations, walker and sorter counters, walks,
//! reuse, sphere tests, early termination, hits): the per-pixel steps add to it, and the
//! frame merges the workers' counters into its statistics.
//!
//! Pipeline position: filled by [`super::FramePlan`]'s steps in both models; merged by the
//! functional model's frame (`super::super::frame`) and read by the cycle model's trace.

use rtl_model::datapath::overflow_table;
use rtl_model::fixed::Overflows;
use rtl_model::units::sorter::SorterStats;
use rtl_model::units::walker::WalkerStats;

/// Counters a worker accumulates over its pixels.
#[derive(Clone, Debug)]
pub struct PixelCounters {
    /// Saturations and wraps.
    pub ov: Overflows,
    /// Walker counters.
    pub walker: WalkerStats,
    /// Sorter counters.
    pub sorter: SorterStats,
    /// Walks.
    pub walks: u64,
    /// Pixels reused.
    pub reused: u64,
    /// Sphere tests.
    pub tests: u64,
    /// Tests that culled.
    pub culled: u64,
    /// Candidates of traced rays.
    pub candidates: u64,
    /// Rays stopped early.
    pub early: u64,
    /// Pixels that hit.
    pub hits: u64,
    /// Reciprocal zero flushes.
    pub flushes: u64,
}

impl Default for PixelCounters {
    fn default() -> Self {
        Self {
            ov: overflow_table(),
            walker: WalkerStats::default(),
            sorter: SorterStats::default(),
            walks: 0,
            reused: 0,
            tests: 0,
            culled: 0,
            candidates: 0,
            early: 0,
            hits: 0,
            flushes: 0,
        }
    }
}

impl PixelCounters {
    /// Adds `o` into `self`.
    pub fn merge(&mut self, o: &Self) {
        self.ov.merge(&o.ov);
        self.walker.steps += o.walker.steps;
        self.walker.fetches += o.walker.fetches;
        self.walker.step_limit_hits += o.walker.step_limit_hits;
        self.walker.max_stack = self.walker.max_stack.max(o.walker.max_stack);
        self.sorter.merge(&o.sorter);
        self.walks += o.walks;
        self.reused += o.reused;
        self.tests += o.tests;
        self.culled += o.culled;
        self.candidates += o.candidates;
        self.early += o.early;
        self.hits += o.hits;
        self.flushes += o.flushes;
    }
}
