//! Fixed-point arithmetic at hardware widths: run-time formats, raw two's-complement values,
//! and sticky overflow counters.
//!
//! Pipeline position: every datapath unit of the fixed-point model computes through this
//! layer. A value is a raw `i64` whose meaning (signedness, width W ≤ 64, fraction bits F)
//! is given by a [`Format`]; operations compute exactly in `i128` and then requantise into an
//! explicit result format with the quantisation and overflow modes RTL engineers know from
//! `ap_fixed` / `sc_fixed`. Every saturation or wrap is counted in [`Overflows`] under the
//! signal's name; data never panics the model.
//!
//! Why a layer of our own rather than the `fixed` crate: `fixed` stores values in 8/16/32/64/
//! 128-bit integers with compile-time fraction bits, while the datapath sweeps widths such as
//! 18, 24, 27 or 41 bits at run time (`docs/number-formats.md`).

mod dsp;
mod format;
mod ops;
mod overflow;

pub use dsp::{dsp48e2_per_product, product_latency_cycles, Products, DSP_PIPELINE_CYCLES};
pub use format::{Format, OverflowMode, Quant};
pub use ops::{add, from_f64, mul, quantize, shift_right, sub, to_f64};
pub use overflow::{Overflows, SignalId};
