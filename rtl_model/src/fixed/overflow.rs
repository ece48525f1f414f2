//! Sticky, named overflow counters: every saturation or wrap in the datapath is counted under
//! the signal it happened on, and the counts reach the reports.

/// Index of a named signal in an [`Overflows`] table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SignalId(pub u16);

/// Per-signal counts of saturations and wraps. Tables of the same signal list merge by
/// addition, so each worker thread keeps its own and the frame sums them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Overflows {
    names: Vec<String>,
    counts: Vec<u64>,
}

impl Overflows {
    /// A zeroed table for these signal names (index = [`SignalId`]).
    pub fn new<S: AsRef<str>>(names: &[S]) -> Self {
        Self {
            names: names.iter().map(|s| s.as_ref().to_string()).collect(),
            counts: vec![0; names.len()],
        }
    }

    /// The id of a signal name, if registered.
    pub fn id(&self, name: &str) -> Option<SignalId> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| SignalId(i as u16))
    }

    /// Counts one overflow on `sig`. An id outside the table is counted on the last entry
    /// rather than panicking (tables are built from the same signal list as the ids).
    #[inline]
    pub fn hit(&mut self, sig: SignalId) {
        let i = usize::from(sig.0).min(self.counts.len().saturating_sub(1));
        if let Some(c) = self.counts.get_mut(i) {
            *c += 1;
        }
    }

    /// Count of one signal.
    pub fn count(&self, sig: SignalId) -> u64 {
        self.counts.get(usize::from(sig.0)).copied().unwrap_or(0)
    }

    /// Sum over all signals.
    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// (name, count) of every signal with a non-zero count, in table order.
    pub fn nonzero(&self) -> impl Iterator<Item = (&str, u64)> {
        self.names
            .iter()
            .zip(&self.counts)
            .filter(|(_, &c)| c > 0)
            .map(|(n, &c)| (n.as_str(), c))
    }

    /// Adds another table's counts (same signal list).
    pub fn merge(&mut self, other: &Self) {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
    }

    /// Sets every count to zero.
    pub fn clear(&mut self) {
        self.counts.iter_mut().for_each(|c| *c = 0);
    }
}
