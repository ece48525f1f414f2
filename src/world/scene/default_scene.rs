//! The embedded default scene: the animated car of `scenes/car.ron`, compiled into the
//! binary so `cargo run --release --bin sim` needs no file.

/// RON text of the default scene (the same file as `scenes/car.ron`).
pub const DEFAULT_SCENE_RON: &str = include_str!("../../../scenes/car.ron");
