//! The node memory's address map for a scene: every asset's SVO image placed one after the
//! other in one node space (and its attribute records in one attribute space), with each
//! image's top levels on chip.
//!
//! Pipeline position: built once per run from the assets; the walker pool's reads carry an
//! image's local addresses, which the dispatcher offsets by the image's base here.

use crate::world::assets::{Asset, AssetTree};
use rtl_model::cycle::memory::{MemoryLayout, OnChipConfig};
use thiserror::Error;

/// Why a scene's images cannot be placed.
#[derive(Debug, Error)]
pub enum LayoutBuildError {
    /// An asset has no memory image (walked implicitly).
    #[error("asset \"{0}\" has no memory image (it is walked implicitly from its SDF); the cycle model reads materialised octrees: use a smaller --depth, or --model reference")]
    Implicit(String),
    /// The images do not fit a 32-bit word address space.
    #[error("the scene's images need {0} node words, beyond the 32-bit address space")]
    TooLarge(u64),
    /// The memory model refused the layout.
    #[error("node memory layout: {0}")]
    Layout(String),
}

/// The placed images.
#[derive(Clone, Debug)]
pub struct SceneLayout {
    /// Node-word base of each asset's image.
    pub node_base: Vec<u32>,
    /// Attribute-record base of each asset's image.
    pub attr_base: Vec<u32>,
    /// The memory model's layout.
    pub layout: MemoryLayout,
    /// On-chip words.
    pub onchip_words: u64,
}

impl SceneLayout {
    /// Places every asset's image.
    pub fn new(assets: &[Asset], onchip: &OnChipConfig) -> Result<Self, LayoutBuildError> {
        let mut node_base = Vec::with_capacity(assets.len());
        let mut attr_base = Vec::with_capacity(assets.len());
        let mut ranges: Vec<(u32, u32)> = Vec::new();
        let (mut words, mut attrs) = (0u64, 0u64);
        for a in assets {
            let AssetTree::Image(img) = &a.tree else {
                return Err(LayoutBuildError::Implicit(a.name.clone()));
            };
            let own = MemoryLayout::from_image(img, onchip)
                .map_err(|e| LayoutBuildError::Layout(format!("asset \"{}\": {e}", a.name)))?;
            let base = u32::try_from(words).map_err(|_| LayoutBuildError::TooLarge(words))?;
            node_base.push(base);
            attr_base.push(u32::try_from(attrs).map_err(|_| LayoutBuildError::TooLarge(attrs))?);
            for &(s, e) in own.onchip_ranges() {
                let s = u64::from(s) + words;
                let e = u64::from(e) + words;
                let (s, e) = (
                    u32::try_from(s).map_err(|_| LayoutBuildError::TooLarge(s))?,
                    u32::try_from(e).map_err(|_| LayoutBuildError::TooLarge(e))?,
                );
                ranges.push((s, e));
            }
            words += img.nodes().len() as u64;
            attrs += img.attrs().len() as u64;
        }
        if words >= 1 << 32 {
            return Err(LayoutBuildError::TooLarge(words));
        }
        let layout = MemoryLayout::with_onchip_ranges(words, attrs, ranges)
            .map_err(|e| LayoutBuildError::Layout(e.to_string()))?;
        let onchip_words = layout.onchip_words();
        Ok(Self {
            node_base,
            attr_base,
            layout,
            onchip_words,
        })
    }
}
