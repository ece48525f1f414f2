//! Helpers shared by the `.vox` loader tests (`tests/vox_models.rs`, `tests/vox_conventions.rs`,
//! `tests/bad_input_vox.rs`): a writer of tiny `.vox` files by hand, chunk by chunk, and checks
//! of loaded assets.

use std::collections::HashMap;
use std::path::Path;

use rtl_model::svo::LeafAttr;
use svo_sim::world::assets::vox::{VoxAsset, VoxError};

/// Each leaf's attribute by coordinate.
pub fn leaf_map(asset: &VoxAsset) -> HashMap<[u32; 3], LeafAttr> {
    asset.leaves.coords().collect()
}

/// Fails unless the error's message names `path`.
pub fn assert_names_path(err: &VoxError, path: &Path) {
    let text = err.to_string();
    assert!(
        text.contains(&path.display().to_string()),
        "error message does not name {}: {text}",
        path.display()
    );
}

// ---------------------------------------------------------------------------------------------
// Writing `.vox` files

/// One RIFF-style chunk.
pub fn chunk(id: &[u8; 4], content: &[u8], children: &[u8]) -> Vec<u8> {
    let mut out = id.to_vec();
    out.extend((content.len() as u32).to_le_bytes());
    out.extend((children.len() as u32).to_le_bytes());
    out.extend(content);
    out.extend(children);
    out
}

/// A whole `.vox` file: "VOX ", version 150, and a MAIN chunk holding `children`.
pub fn vox_file(children: &[Vec<u8>]) -> Vec<u8> {
    let mut out = b"VOX ".to_vec();
    out.extend(150u32.to_le_bytes());
    out.extend(chunk(b"MAIN", &[], &children.concat()));
    out
}

/// SIZE and XYZI chunks of one model; voxels are (x, y, z, file colour index: 1..=255, or 0,
/// which MagicaVoxel treats as empty).
pub fn model(size: [u32; 3], voxels: &[[u8; 4]]) -> Vec<u8> {
    let size_content: Vec<u8> = size.iter().flat_map(|s| s.to_le_bytes()).collect();
    let mut xyzi = (voxels.len() as u32).to_le_bytes().to_vec();
    xyzi.extend(voxels.iter().flatten());
    [
        chunk(b"SIZE", &size_content, &[]),
        chunk(b"XYZI", &xyzi, &[]),
    ]
    .concat()
}

/// RGBA chunk; entry `j` is the colour of file index `j + 1`.
pub fn rgba(palette: &[[u8; 4]; 256]) -> Vec<u8> {
    chunk(b"RGBA", &palette.concat(), &[])
}

/// A palette whose every entry is distinct, with alpha ≠ 255 to see it forced opaque.
pub fn test_palette() -> [[u8; 4]; 256] {
    std::array::from_fn(|j| [j as u8, 255 - j as u8, (j as u8).wrapping_mul(7), 0x80])
}

pub fn dict(pairs: &[(&str, &str)]) -> Vec<u8> {
    let mut out = (pairs.len() as u32).to_le_bytes().to_vec();
    for s in pairs.iter().flat_map(|(k, v)| [k, v]) {
        out.extend((s.len() as u32).to_le_bytes());
        out.extend(s.as_bytes());
    }
    out
}

pub fn transform_node(
    id: u32,
    attrs: &[(&str, &str)],
    child: u32,
    frame: &[(&str, &str)],
) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend(dict(attrs));
    c.extend(child.to_le_bytes());
    c.extend((-1i32).to_le_bytes()); // reserved
    c.extend((-1i32).to_le_bytes()); // layer: none
    c.extend(1u32.to_le_bytes()); // one frame
    c.extend(dict(frame));
    chunk(b"nTRN", &c, &[])
}

pub fn group_node(id: u32, children: &[u32]) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend(dict(&[]));
    c.extend((children.len() as u32).to_le_bytes());
    c.extend(children.iter().flat_map(|k| k.to_le_bytes()));
    chunk(b"nGRP", &c, &[])
}

pub fn shape_node(id: u32, model_id: u32) -> Vec<u8> {
    let mut c = id.to_le_bytes().to_vec();
    c.extend(dict(&[]));
    c.extend(1u32.to_le_bytes());
    c.extend(model_id.to_le_bytes());
    c.extend(dict(&[]));
    chunk(b"nSHP", &c, &[])
}
