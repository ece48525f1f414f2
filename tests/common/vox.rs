//! Helpers shared by the `.vox` loader tests (`tests/vox_models.rs`, `tests/vox_conventions.rs`).

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
