//! Steps 3 to 6 of the `.vox` loader: placed voxels become the asset's leaf set. The bounding
//! box is shifted to 0 and centred in the `2^depth` cube, each voxel gets its palette colour,
//! only voxels with an empty face neighbour are kept, their normal points to the open faces,
//! and a depth above the needed one cuts each voxel into a block of which only the open faces
//! are kept (see the [parent module](super) for the conventions).

use std::path::Path;

use rtl_model::svo::{LeafAttr, LeafSet, MAX_DEPTH};

use super::occupancy::Occupancy;
use super::{VoxAsset, VoxError, MAX_UPSCALED_LEAVES};

/// Directions to the six face neighbours, in our axes; bit `i` of a face mask is set when the
/// neighbour in direction `i` is empty.
const DIRS: [[i64; 3]; 6] = [
    [-1, 0, 0],
    [1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
    [0, 0, -1],
    [0, 0, 1],
];

/// Fallback order for normals whose open directions cancel: +y, −y, +x, −x, +z, −z.
const FALLBACK_DIRS: [usize; 6] = [3, 2, 1, 0, 5, 4];

fn normal_for_mask(mask: u8) -> [f64; 3] {
    let mut sum = [0i64; 3];
    for (i, d) in DIRS.iter().enumerate() {
        if mask & (1 << i) != 0 {
            for k in 0..3 {
                sum[k] += d[k];
            }
        }
    }
    if sum == [0, 0, 0] {
        // LeafAttr would store a zero normal as +z, a side direction in a y-up world; an open
        // face direction is a better guess.
        if let Some(&i) = FALLBACK_DIRS.iter().find(|&&i| mask & (1 << i) != 0) {
            sum = DIRS[i];
        }
    }
    let len = ((sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) as f64).sqrt();
    if len == 0.0 {
        return [0.0, 1.0, 0.0];
    }
    sum.map(|c| c as f64 / len)
}

/// Smallest `d ≥ 1` with `2^d ≥ extent`.
fn needed_depth(extent: u64) -> u32 {
    extent.max(2).next_power_of_two().trailing_zeros()
}

/// Fine leaves of a `k³` block on the faces towards empty neighbours:
/// `k³ − Π(k − open faces on that axis)`.
fn block_surface_cells(k: u64, mask: u8) -> u64 {
    let inner: u64 = (0..3)
        .map(|axis| {
            let open =
                u64::from((mask >> (2 * axis)) & 1) + u64::from((mask >> (2 * axis + 1)) & 1);
            k.saturating_sub(open)
        })
        .product();
    k * k * k - inner
}

pub(super) fn build(
    path: &Path,
    data: &dot_vox::DotVoxData,
    models: usize,
    placed: Vec<([i64; 3], u8)>,
    depth: Option<u8>,
) -> Result<VoxAsset, VoxError> {
    let empty = || VoxError::Empty {
        path: path.to_path_buf(),
    };
    let first = placed.first().ok_or_else(empty)?.0;
    let (mut lo, mut hi) = (first, first);
    for (c, _) in &placed {
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    let dims: [u64; 3] = std::array::from_fn(|k| (hi[k] - lo[k]) as u64 + 1);
    let extent = dims[0].max(dims[1]).max(dims[2]);
    let needed = needed_depth(extent);
    if needed > u32::from(MAX_DEPTH) {
        return Err(VoxError::DepthTooLarge {
            path: path.to_path_buf(),
            needed,
            extent,
        });
    }
    let needed = needed as u8; // at most MAX_DEPTH
    let depth = match depth {
        None => needed,
        Some(d) if d < needed => {
            return Err(VoxError::DepthTooSmall {
                path: path.to_path_buf(),
                needed,
                given: d,
                extent,
            })
        }
        Some(d) => d, // range checked on entry
    };

    // Occupancy in grid coordinates (bounding box at 0); a repeated cell keeps the first voxel.
    let mut occupancy = Occupancy::new(dims);
    let mut solid: Vec<([i64; 3], u8)> = Vec::with_capacity(placed.len());
    for (c, colour) in placed {
        let g = [c[0] - lo[0], c[1] - lo[1], c[2] - lo[2]];
        if occupancy.insert(g) {
            solid.push((g, colour));
        }
    }
    let voxels = solid.len();
    if voxels == 0 {
        return Err(empty());
    }

    let surface: Vec<([i64; 3], u8, u8)> = solid
        .iter()
        .filter_map(|&(c, colour)| {
            let mask = DIRS.iter().enumerate().fold(0u8, |m, (i, d)| {
                let n = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                if occupancy.contains(n) {
                    m
                } else {
                    m | (1 << i)
                }
            });
            (mask != 0).then_some((c, colour, mask))
        })
        .collect();
    drop(solid);
    drop(occupancy);

    let colours: [[u8; 4]; 256] = std::array::from_fn(|i| {
        let c = data
            .palette
            .get(i)
            .or_else(|| dot_vox::DEFAULT_PALETTE.get(i))
            .copied()
            .unwrap_or(dot_vox::Color {
                r: 255,
                g: 0,
                b: 255,
                a: 255,
            });
        [c.r, c.g, c.b, 255]
    });
    let normals: [[f64; 3]; 64] = std::array::from_fn(|m| normal_for_mask(m as u8));
    let attr = |colour: u8, mask: u8| {
        LeafAttr::new(colours[usize::from(colour)], normals[usize::from(mask)])
    };

    let k = 1u64 << (depth - needed);
    let side = 1u64 << depth;
    let offset: [u64; 3] = std::array::from_fn(|a| (side - dims[a] * k) / 2);
    let leaves_error = |source| VoxError::Leaves {
        path: path.to_path_buf(),
        source,
    };

    let leaves = if k == 1 {
        let leaves = surface.iter().map(|&(c, colour, mask)| {
            let p: [u32; 3] = std::array::from_fn(|a| (offset[a] + c[a] as u64) as u32);
            (p, attr(colour, mask))
        });
        LeafSet::from_coords(depth, leaves).map_err(leaves_error)?
    } else {
        let count: u64 = surface
            .iter()
            .map(|&(_, _, mask)| block_surface_cells(k, mask))
            .fold(0u64, u64::saturating_add);
        if count > MAX_UPSCALED_LEAVES {
            return Err(VoxError::TooManyLeaves {
                path: path.to_path_buf(),
                depth,
                leaves: count,
            });
        }
        let leaves = surface.iter().flat_map(|&(c, colour, mask)| {
            let base: [u64; 3] = std::array::from_fn(|a| offset[a] + c[a] as u64 * k);
            let a = attr(colour, mask);
            block_surface(k, mask)
                .into_iter()
                .map(move |f| (std::array::from_fn(|i| (base[i] + f[i]) as u32), a))
        });
        LeafSet::from_coords(depth, leaves).map_err(leaves_error)?
    };

    Ok(VoxAsset {
        leaves,
        depth,
        grid_dims: dims.map(|d| d as u32),
        models,
        file_models: models,
        notice: None,
        voxels,
        solid_min: lo,
        offset,
        upscale: k,
    })
}

/// Offsets inside a `k³` block of the cells on its open faces (mask bit `2a` = low face of
/// axis `a`, `2a + 1` = high face), each cell once.
fn block_surface(k: u64, mask: u8) -> Vec<[u64; 3]> {
    let plane = |face: usize| if face % 2 == 1 { k - 1 } else { 0 };
    let mut out = Vec::new();
    for face in (0..6).filter(|&f| mask & (1 << f) != 0) {
        let axis = face / 2;
        let (u_axis, v_axis) = ((axis + 1) % 3, (axis + 2) % 3);
        for u in 0..k {
            for v in 0..k {
                let mut cell = [0u64; 3];
                cell[axis] = plane(face);
                cell[u_axis] = u;
                cell[v_axis] = v;
                // Edges and corners lie on several open faces; the first one emits them.
                let on_earlier = (0..face).any(|g| mask & (1 << g) != 0 && cell[g / 2] == plane(g));
                if !on_earlier {
                    out.push(cell);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn needed_depth_is_smallest_power_of_two_cover() {
        assert_eq!(needed_depth(1), 1);
        assert_eq!(needed_depth(2), 1);
        assert_eq!(needed_depth(3), 2);
        assert_eq!(needed_depth(124), 7);
        assert_eq!(needed_depth(128), 7);
        assert_eq!(needed_depth(129), 8);
    }

    #[test]
    fn block_surface_matches_count_and_is_unique() {
        for k in [1u64, 2, 3, 4] {
            for mask in 0u8..64 {
                let cells = block_surface(k, mask);
                let unique: HashSet<[u64; 3]> = cells.iter().copied().collect();
                assert_eq!(unique.len(), cells.len(), "k {k} mask {mask:#08b}");
                assert_eq!(
                    cells.len() as u64,
                    block_surface_cells(k, mask),
                    "k {k} mask {mask:#08b}"
                );
            }
        }
    }

    #[test]
    fn normals_point_to_open_faces() {
        assert_eq!(normal_for_mask(0b00_1000), [0.0, 1.0, 0.0]);
        assert_eq!(normal_for_mask(0b00_0001), [-1.0, 0.0, 0.0]);
        // +x and +y open: diagonal
        let n = normal_for_mask(0b00_1010);
        assert!((n[0] - n[1]).abs() < 1e-12 && (n[0] - 0.5f64.sqrt()).abs() < 1e-12);
        // ±x open cancels: fall back to +x (the first open in the fallback order)
        assert_eq!(normal_for_mask(0b00_0011), [1.0, 0.0, 0.0]);
        // everything open: +y
        assert_eq!(normal_for_mask(0b11_1111), [0.0, 1.0, 0.0]);
    }
}
