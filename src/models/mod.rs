//! The three models of a frame, each a check on the next.
//!
//! - [`reference`](mod@reference): the paper's method in f64, the oracle for accuracy.
//! - [`fixed`]: the functional fixed-point model, every unit of `rtl_model::units` bit-exact
//!   with the RTL, compared with the reference every frame. It also records each pixel's work
//!   (candidates, walks, node reads) for the cycle model.
//! - [`cycle`]: the cycle-accurate pipeline, which times the functional model's work over the
//!   cycle parts of `rtl_model::cycle` (FIFOs, unit pipes, walker pool, node memory, hit-buffer
//!   BRAM) and checks its own decisions and final hit buffer against it.

pub mod cycle;
pub mod fixed;
pub mod reference;
