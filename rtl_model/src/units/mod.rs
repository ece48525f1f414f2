//! Datapath units of the fixed-point model, one module each.
//!
//! Each unit is a pure transaction function computing what the RTL computes, bit for bit,
//! from raw codes in the formats of its configuration, plus a named error-bound function of
//! those formats (derived in `docs/units/`). Saturations and wraps are counted, never silent.

pub mod cordic;
pub mod hit_record;
pub mod keyframe;
pub mod normal;
pub mod raygen;
pub mod reciprocal;
pub mod rotation;
pub mod sorter;
pub mod sorter_network;
pub mod sphere;
pub mod sqrt;
pub mod tile_list;
pub mod transform;
pub mod walker;
pub mod walker_root;
