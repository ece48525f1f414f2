//! Errors of the library. Every message names the problem and where it is (file, line and
//! column, or a path into the scene such as `instances[3](door_left).keys[1].scale`).

use thiserror::Error;

/// A scene that cannot be used.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The file could not be read, or is larger than its cap.
    #[error(transparent)]
    Input(#[from] crate::input::InputError),
    /// The RON is malformed.
    #[error("{origin}:{line}:{column}: malformed scene: {message}")]
    Parse {
        /// File or description.
        origin: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The RON is well formed but a value is unusable.
    #[error("{origin}: invalid scene: {message}")]
    Invalid {
        /// File or description.
        origin: String,
        /// What is wrong and where.
        message: String,
    },
}

/// An asset whose SVO cannot be built.
#[derive(Debug, Error)]
pub enum AssetError {
    /// A `.vox` file could not be loaded.
    #[error("asset \"{asset}\": {source}")]
    Vox {
        /// Asset name.
        asset: String,
        /// Why.
        #[source]
        source: crate::world::assets::vox::VoxError,
    },
    /// `--depth` is outside 1..=20.
    #[error("--depth {0} is out of range (1 to {max})", max = rtl_model::svo::MAX_DEPTH)]
    DepthOption(u8),
    /// The depth is outside what the format supports, or too deep to build in memory.
    #[error("asset \"{asset}\": {message}")]
    Depth {
        /// Asset name.
        asset: String,
        /// Why.
        message: String,
    },
    /// The memory image could not be built.
    #[error("asset \"{asset}\": {source}")]
    Image {
        /// Asset name.
        asset: String,
        /// Why.
        #[source]
        source: rtl_model::svo::BuildError,
    },
    /// Leaves could not be collected (coordinate or depth out of range).
    #[error("asset \"{asset}\": {source}")]
    Leaves {
        /// Asset name.
        asset: String,
        /// Why.
        #[source]
        source: rtl_model::svo::LeafSetError,
    },
}
