//! What goes in and out of the node memory: a request's id, a completed read and where it was
//! served, why a request is refused, and the queued form of a request.
//!
//! Pipeline position: the interface between the walker pool (which requests reads and wakes
//! contexts on completions) and [`super::NodeMemory`].

use crate::svo::FetchKind;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Largest request cycle accepted. Keeping cycles below 2^62 leaves room for every latency
/// and byte-slot sum without overflow checks on the hot path.
pub const MAX_CYCLE: u64 = 1 << 62;

/// Identifies one request; assigned in call order from 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct RequestId(pub u64);

/// Where a read was served.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Source {
    /// The on-chip store, in this bank.
    OnChip {
        /// Bank index (word address mod banks).
        bank: u32,
    },
    /// A cache hit.
    CacheHit,
    /// A miss that issued a line fill (also an uncached attribute read that did).
    Miss,
    /// A miss that joined a fill already in flight for its line.
    Merged,
}

/// A completed read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Completion {
    /// The request.
    pub id: RequestId,
    /// Who asked (walker context or any id the caller chose).
    pub requester: u32,
    /// What was read.
    pub kind: FetchKind,
    /// Node word address, or attribute index for [`FetchKind::Attr`].
    pub addr: u32,
    /// Cycle the request was made.
    pub cycle_requested: u64,
    /// Cycle it got its port (on-chip bank or cache lookup).
    pub cycle_served: u64,
    /// First cycle its data is valid.
    pub cycle_done: u64,
    /// Where it was served.
    pub source: Source,
}

/// Why a request was refused. Refused requests are not queued and get no completion.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum RequestError {
    /// The address is outside the node memory or the attribute array.
    #[error("{kind:?} read at {addr} is outside the {limit} entries of its memory")]
    OutOfRange {
        /// What was read.
        kind: FetchKind,
        /// The address.
        addr: u32,
        /// Words (node memory) or records (attributes) there are.
        limit: u64,
    },
    /// The cycle was already simulated (before the last `tick`).
    #[error("request for cycle {cycle}, but cycles before {now} are already simulated")]
    InPast {
        /// The request's cycle.
        cycle: u64,
        /// The first cycle still open.
        now: u64,
    },
    /// The cycle is above [`MAX_CYCLE`].
    #[error("request cycle {0} is above the model's limit of 2^62")]
    CycleTooLarge(u64),
}

/// A queued request; ordered by (cycle, requester, id), the service order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Req {
    pub(super) cycle: u64,
    pub(super) requester: u32,
    pub(super) id: u64,
    pub(super) addr: u32,
    pub(super) kind: FetchKind,
}
