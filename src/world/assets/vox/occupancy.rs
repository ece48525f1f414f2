//! The solid cells of a composed `.vox` grid, for the surface test of step 5 (see the
//! [parent module](super)): a dense bitset when the grid is small enough, a hash set of packed
//! coordinates otherwise.

use std::collections::HashSet;

/// Composed grids with at most this many cells use a dense occupancy bitset (32 MiB at most);
/// larger, sparse ones use a hash set.
const DENSE_OCCUPANCY_CELLS: u64 = 1 << 28;

/// Solid cells of the composed grid, dense or hashed.
pub(super) enum Occupancy {
    Dense { dims: [u64; 3], bits: Vec<u64> },
    Sparse(HashSet<u64>),
}

impl Occupancy {
    pub(super) fn new(dims: [u64; 3]) -> Self {
        let cells = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
        if cells <= DENSE_OCCUPANCY_CELLS {
            Self::Dense {
                dims,
                bits: vec![0; cells.div_ceil(64) as usize],
            }
        } else {
            Self::Sparse(HashSet::new())
        }
    }

    /// Key of an in-grid cell: linear index (dense) or packed 20-bit fields (sparse: every
    /// extent is at most 2^MAX_DEPTH).
    fn key(&self, c: [i64; 3]) -> Option<u64> {
        match self {
            Self::Dense { dims, .. } => {
                let [x, y, z] = c.map(|v| u64::try_from(v).ok());
                let (x, y, z) = (x?, y?, z?);
                (x < dims[0] && y < dims[1] && z < dims[2]).then(|| x + dims[0] * (y + dims[1] * z))
            }
            Self::Sparse(_) => {
                let [x, y, z] = c.map(|v| u64::try_from(v).ok().filter(|&v| v < 1 << 20));
                Some(x? | (y? << 20) | (z? << 40))
            }
        }
    }

    /// Marks a cell solid; false if it already was (or lies outside the grid).
    pub(super) fn insert(&mut self, c: [i64; 3]) -> bool {
        let Some(key) = self.key(c) else {
            return false;
        };
        match self {
            Self::Dense { bits, .. } => {
                let (word, bit) = ((key / 64) as usize, key % 64);
                let was = bits[word] & (1 << bit) != 0;
                bits[word] |= 1 << bit;
                !was
            }
            Self::Sparse(set) => set.insert(key),
        }
    }

    pub(super) fn contains(&self, c: [i64; 3]) -> bool {
        let Some(key) = self.key(c) else {
            return false;
        };
        match self {
            Self::Dense { bits, .. } => bits[(key / 64) as usize] & (1 << (key % 64)) != 0,
            Self::Sparse(set) => set.contains(&key),
        }
    }
}
