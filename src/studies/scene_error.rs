//! Why a study's scene could not be prepared: loaded, set to the study's resolution and frame
//! count, its assets built, a frame's state computed.
//!
//! Pipeline position: shared by [`super::sweep`] and [`super::explore`], which prepare their
//! scenes the same way before the cycle model runs; each study's own error wraps this one
//! (`SweepError::Scene`, `ExploreError::Scene`) and prints it unchanged.

use crate::error::{AssetError, SceneError};
use thiserror::Error;

/// A scene a study cannot prepare, naming the scene (and the frame).
#[derive(Debug, Error)]
pub enum StudySceneError {
    /// The scene cannot be loaded, or does not accept the resolution or frame count.
    #[error("scene {scene}: {source}")]
    Scene {
        /// The scene.
        scene: String,
        /// What is wrong.
        #[source]
        source: SceneError,
    },
    /// An asset cannot be built.
    #[error("scene {scene}: {source}")]
    Asset {
        /// The scene.
        scene: String,
        /// What failed.
        #[source]
        source: AssetError,
    },
    /// A frame's state cannot be computed.
    #[error("scene {scene}, frame {frame}: {message}")]
    Frame {
        /// The scene.
        scene: String,
        /// The frame.
        frame: u32,
        /// What failed.
        message: String,
    },
}
