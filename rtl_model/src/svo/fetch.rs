//! What kind of word a walker fetches from the SVO memory image: a node word (child
//! descriptor or leaf slot), a far-pointer word, or a leaf attribute record.
//!
//! Pipeline position: named by the octree walker (`units::walker`) for each read it makes, as
//! the hardware's read port sees it; the node-memory timing model (`cycle::memory`) takes it
//! to size the read and count it. It belongs to the image's format (`docs/svo-format.md`
//! §12, the traffic), not to the timing model, so the units never import timing types.

use serde::{Deserialize, Serialize};

/// What a read fetches; decides its size and which counters it lands in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum FetchKind {
    /// A child descriptor or a leaf slot (one word of node memory).
    Node,
    /// A far-pointer word (one word of node memory).
    Far,
    /// A leaf attribute record (two words of the attribute array); the address is the
    /// attribute index held in the leaf slot.
    Attr,
}

impl FetchKind {
    /// 32-bit words the read returns.
    pub const fn words(self) -> u64 {
        match self {
            FetchKind::Node | FetchKind::Far => 1,
            FetchKind::Attr => 2,
        }
    }
}
