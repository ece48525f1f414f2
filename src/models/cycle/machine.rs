//! The parts of the cycle model that outlive a frame: node memory, walker pool, hit-buffer
//! BRAM, the clock and the waveform recorder.
//!
//! Pipeline position: owned by `model::CycleModel`, borrowed by each frame's
//! `pipeline::Pipeline` and by sampled timing's functional warming (docs/cycle-model.md §2,
//! §3.5). In a file of its own so that neither needs the model's file.

use super::waves::PipelineWaves;
use rtl_model::cycle::bram::Bram;
use rtl_model::cycle::clocked::Clock;
use rtl_model::cycle::memory::NodeMemory;
use rtl_model::cycle::walker_pool::WalkerPoolModel;

/// The parts of the machine that keep their state across frames (cache lines, hit-buffer
/// words, the cycle count); a frame's `pipeline::Pipeline` borrows them.
pub struct Machine {
    /// The node memory.
    pub mem: NodeMemory,
    /// The walker pool.
    pub pool: WalkerPoolModel,
    /// The hit buffer.
    pub bram: Bram<u128>,
    /// The clock: the run's cycle counter and the one place the parts commit.
    pub clock: Clock,
    /// The waveform recorder, if any.
    pub waves: Option<PipelineWaves>,
}
