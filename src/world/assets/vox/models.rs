//! Step 1b of the `.vox` loader: the models (`SIZE` / `XYZI` chunk pairs, the children of
//! `MAIN`) read from the raw bytes and checked, after `dot_vox` has parsed the file (see the
//! [parent module](super), step 1).
//!
//! Why not `dot_vox`'s own models: it loses exactly what these checks need. It stores a
//! voxel's colour index as the file's index minus one, saturating, so the file's index 0
//! (MagicaVoxel: empty) and index 1 become the same value; it drops an `XYZI` chunk whose
//! count exceeds its bytes, or one without a `SIZE` before it, without a word (so a
//! truncated model reads as "no visible voxels", and the scene graph's model ids shift); and
//! it stops reading `MAIN`'s children at the first chunk that runs past the end, dropping the
//! rest. Here each of those is an error naming the chunk's byte offset and the model's index,
//! every voxel is checked to lie inside its model's `SIZE`, each `SIZE` axis is checked
//! against the widest octree ([`MAX_SIZE`]), and colour-index-0 voxels are skipped.

use std::path::Path;

use rtl_model::svo::MAX_DEPTH;

use super::{VoxError, MAX_SIZE};

/// Chunk header: four-byte id, content size, children size.
const HEADER: usize = 12;

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// The models of the file in file order (the index a shape node's model id refers to), with
/// `dot_vox`'s colour convention (`Voxel::i` = file index − 1) and colour-index-0 voxels left
/// out. Only called on bytes `dot_vox` has parsed, so `MAIN`'s own header fits in the file.
pub(super) fn read_models(bytes: &[u8], path: &Path) -> Result<Vec<dot_vox::Model>, VoxError> {
    let bad = |message: String| VoxError::Model {
        path: path.to_path_buf(),
        message,
    };
    // "VOX ", version, then the MAIN chunk; a first chunk that is not MAIN holds no models
    // for dot_vox either.
    let main = 8;
    if bytes.get(main..main + 4) != Some(b"MAIN".as_slice()) {
        return Ok(Vec::new());
    }
    let (Some(content), Some(children)) = (read_u32(bytes, main + 4), read_u32(bytes, main + 8))
    else {
        return Ok(Vec::new());
    };
    let start = main + HEADER + content as usize;
    let end = start.saturating_add(children as usize).min(bytes.len());
    // Nothing after MAIN's children belongs to it.
    let bytes = &bytes[..end];
    let mut models = Vec::new();
    let mut size: Option<[u32; 3]> = None;
    let mut pos = start;
    while pos < end {
        let left = end - pos;
        let (Some(content), Some(children)) = (read_u32(bytes, pos + 4), read_u32(bytes, pos + 8))
        else {
            return Err(bad(format!(
                "the chunk at byte {pos} is cut off: {left} bytes are left in MAIN, a chunk \
                 header needs {HEADER} (the file is truncated)"
            )));
        };
        let id = &bytes[pos..pos + 4];
        let name = String::from_utf8_lossy(id).into_owned();
        let declared = HEADER as u64 + u64::from(content) + u64::from(children);
        if declared > left as u64 {
            return Err(bad(format!(
                "the {name:?} chunk at byte {pos} declares {declared} bytes (with its header) \
                 but only {left} are left in MAIN (the file is truncated)"
            )));
        }
        if std::str::from_utf8(id).is_err() {
            // dot_vox stops reading MAIN here, dropping the chunks after it.
            return Err(bad(format!(
                "the chunk at byte {pos} has an id that is not text ({id:02x?})"
            )));
        }
        let body = &bytes[pos + HEADER..pos + HEADER + content as usize];
        // A chunk with children is never SIZE or XYZI for dot_vox (nor for MagicaVoxel).
        if children == 0 {
            match id {
                b"SIZE" => size = Some(read_size(body, pos, models.len()).map_err(bad)?),
                b"XYZI" => {
                    let index = models.len();
                    let Some(s) = size else {
                        return Err(bad(format!(
                            "the XYZI chunk at byte {pos} (model {index}) has no SIZE chunk \
                             before it"
                        )));
                    };
                    let voxels = read_voxels(body, pos, index, s).map_err(bad)?;
                    models.push(dot_vox::Model {
                        size: dot_vox::Size {
                            x: s[0],
                            y: s[1],
                            z: s[2],
                        },
                        voxels,
                    });
                }
                _ => {}
            }
        }
        pos += declared as usize;
    }
    Ok(models)
}

/// A `SIZE` chunk's three axes, each at most [`MAX_SIZE`] (a zero axis can hold no voxel,
/// which the voxels' check then reports).
fn read_size(body: &[u8], pos: usize, model: usize) -> Result<[u32; 3], String> {
    let (Some(x), Some(y), Some(z)) = (read_u32(body, 0), read_u32(body, 4), read_u32(body, 8))
    else {
        return Err(format!(
            "the SIZE chunk at byte {pos} (model {model}) holds {} bytes, it needs 12",
            body.len()
        ));
    };
    for (axis, v) in ["x", "y", "z"].into_iter().zip([x, y, z]) {
        if u64::from(v) > MAX_SIZE {
            return Err(format!(
                "model {model} (SIZE chunk at byte {pos}) is {x} x {y} x {z}: {axis} = {v} is \
                 above {MAX_SIZE} = 2^{MAX_DEPTH}, the side of the deepest octree the SVO builder \
                 takes (depth {MAX_DEPTH})"
            ));
        }
    }
    Ok([x, y, z])
}

/// An `XYZI` chunk's voxels: the count must fit the chunk, every voxel must lie in `size`,
/// colour index 0 (empty in MagicaVoxel) is left out.
fn read_voxels(
    body: &[u8],
    pos: usize,
    model: usize,
    size: [u32; 3],
) -> Result<Vec<dot_vox::Voxel>, String> {
    let Some(count) = read_u32(body, 0) else {
        return Err(format!(
            "the XYZI chunk at byte {pos} (model {model}) holds {} bytes, too few for its voxel \
             count",
            body.len()
        ));
    };
    let room = (body.len() - 4) / 4;
    if u64::from(count) > room as u64 {
        return Err(format!(
            "the XYZI chunk at byte {pos} (model {model}) declares {count} voxels ({} bytes) but \
             holds {} bytes of voxels, room for {room}: truncated or inconsistent",
            4 * u64::from(count),
            body.len() - 4
        ));
    }
    let mut voxels = Vec::with_capacity(count as usize);
    for (n, v) in body[4..4 + 4 * count as usize].chunks_exact(4).enumerate() {
        let [x, y, z, i] = [v[0], v[1], v[2], v[3]];
        if u32::from(x) >= size[0] || u32::from(y) >= size[1] || u32::from(z) >= size[2] {
            return Err(format!(
                "model {model}: voxel {n} of its XYZI chunk (byte {pos}) is at ({x}, {y}, {z}), \
                 outside its SIZE {} x {} x {}",
                size[0], size[1], size[2]
            ));
        }
        if i != 0 {
            voxels.push(dot_vox::Voxel { x, y, z, i: i - 1 });
        }
    }
    Ok(voxels)
}
