//! The functional fixed-point model: a whole frame through the bit-exact datapath units of
//! `rtl_model::units` (ray-direction table, sphere test, sorter, transform, reciprocal,
//! octree walker, hit-buffer record), with the same hit-buffer rule as the f64 reference, and
//! its accuracy against that reference.
//!
//! Pipeline position: `sim --model fixed`. The host-side work (camera basis, per-instance
//! matrices, centres and sphere thresholds, the direction table) is done in f64 and quantised
//! once per frame, as a CPU driving the FPGA would.

pub mod accuracy;
pub mod bound;
pub mod cull;
pub mod explain;
pub mod frame;
pub mod plan;
pub mod row_feed;
pub mod trace;

pub use accuracy::{compare, diff_image, Accuracy};
pub use frame::{
    render_frame_fixed, render_frame_fixed_with, render_streamed, to_hit_records, FixedBuffer,
    FixedError, FixedRecord, FixedStats,
};
