//! Per-stage cycle accounting for the cycle report: every cycle of a frame, each stage is in
//! exactly one of four states.
//!
//! Pipeline position: kept by every stage of the cycle model (`unit_pipe`, the walker pool,
//! the hit-buffer check and write-back) and printed per frame (`frames[].stages[]`).

use serde::{Deserialize, Serialize};

/// What a stage did in one cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StageState {
    /// Accepted a transaction, or had transactions in flight that moved.
    Busy,
    /// Could take work but its input was empty while the frame still had work upstream.
    Starved,
    /// Had a result its output FIFO could not take (downstream full).
    Backpressured,
    /// Nothing to do: the frame's work for this stage is done, or it waits on its own
    /// initiation interval.
    Idle,
}

/// Cycles of a frame in each state.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageCycles {
    /// Stage name.
    pub name: String,
    /// Busy cycles.
    pub busy: u64,
    /// Starved cycles.
    pub starved: u64,
    /// Back-pressured cycles.
    pub backpressured: u64,
    /// Idle cycles.
    pub idle: u64,
    /// Transactions that passed the stage.
    pub transactions: u64,
}

impl StageCycles {
    /// A stage with no cycles yet.
    pub fn named(name: &str) -> Self {
        Self {
            name: name.to_string(),
            ..Self::default()
        }
    }

    /// Counts one cycle.
    #[inline]
    pub fn count(&mut self, s: StageState) {
        match s {
            StageState::Busy => self.busy += 1,
            StageState::Starved => self.starved += 1,
            StageState::Backpressured => self.backpressured += 1,
            StageState::Idle => self.idle += 1,
        }
    }

    /// Counts `k` cycles in state `s` (idle-cycle skipping).
    #[inline]
    pub fn count_many(&mut self, s: StageState, k: u64) {
        match s {
            StageState::Busy => self.busy += k,
            StageState::Starved => self.starved += k,
            StageState::Backpressured => self.backpressured += k,
            StageState::Idle => self.idle += k,
        }
    }

    /// Cycles counted.
    pub fn cycles(&self) -> u64 {
        self.busy + self.starved + self.backpressured + self.idle
    }

    /// Busy share of the counted cycles.
    pub fn utilisation(&self) -> f64 {
        let c = self.cycles();
        if c == 0 {
            0.0
        } else {
            self.busy as f64 / c as f64
        }
    }

    /// Adds `o`'s counts (same stage, another frame).
    pub fn add(&mut self, o: &Self) {
        self.busy += o.busy;
        self.starved += o.starved;
        self.backpressured += o.backpressured;
        self.idle += o.idle;
        self.transactions += o.transactions;
    }
}
