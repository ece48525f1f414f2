//! Why the cycle model stops: [`CycleError`], in a file of its own so that every part of
//! `models::cycle` — the stages, the pipeline, sampled timing, the model — names it without
//! importing the model that imports them (the import circle of issue 30).
//!
//! Pipeline position: none; the error type of the whole cycle model (docs/cycle-model.md §2),
//! re-exported as `cycle::CycleError` and `cycle::model::CycleError`.

use rtl_model::cycle::walker_pool::PoolError;
use thiserror::Error;

/// Why the cycle model stopped.
#[derive(Debug, Error)]
pub enum CycleError {
    /// The hardware configuration is invalid.
    #[error("hardware configuration: {0}")]
    Config(String),
    /// The cycle model and the functional model disagree (a bug in one of them).
    #[error("cross-check failed at frame {frame}, pixel ({i}, {j}): {what}")]
    Mismatch {
        /// Frame.
        frame: u32,
        /// Column.
        i: u32,
        /// Row.
        j: u32,
        /// What differs.
        what: String,
    },
    /// The walker pool or node memory refused something.
    #[error(transparent)]
    Pool(#[from] PoolError),
    /// The pipeline made no progress for far longer than any latency (a model bug).
    #[error("frame {frame}: no progress for {cycles} cycles at cycle {at} ({written} of {pixels} pixels written)")]
    Stuck {
        /// Frame.
        frame: u32,
        /// Cycles without progress.
        cycles: u64,
        /// Cycle.
        at: u64,
        /// Pixels written.
        written: u64,
        /// Pixels.
        pixels: u64,
    },
    /// A FIFO or BRAM was misused (a model bug).
    #[error("pipeline: {0}")]
    Internal(String),
}
