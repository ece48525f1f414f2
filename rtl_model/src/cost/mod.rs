//! One home for what the hardware costs and how accurate it is: unit timing, resources and
//! the bounds that span units.
//!
//! Pipeline position: beside the run, read once per configuration. The layers:
//! - each unit owns its figures, next to its arithmetic: DSP48E2 (`units::sphere::dsp48e2_count`,
//!   `units::transform::dsp48e2_count`, `units::reciprocal::dsp48e2_count`,
//!   `units::walker::root_dsp48e2_count`, `units::sqrt::dsp48e2_count`), latency
//!   (`units::*::latency_cycles`, `units::walker::root_latency_cycles`) and error bound
//!   (`units::*::error_bound` and siblings), all built on `fixed::Products`,
//!   `fixed::dsp48e2_per_product`, `fixed::product_latency_cycles` and
//!   `fixed::Format::exact_difference`;
//! - the unit latencies are collected into the hardware's `UnitTimings` by
//!   `cycle::unit_latency`, below this layer (the hardware configuration's defaults need them);
//! - [`estimate`] multiplies the units' DSP48E2 by their instances and adds the memories into
//!   the [`ResourceReport`] of `HwConfig::resources` (`crate::resources` holds its
//!   types, below the units, which price their own memories with them);
//! - [`fabric`] estimates LUTs and flip-flops per unit, calibrated on the Yosys synthesis
//!   of the RTL, [`core_logic`] the logic svo_core builds around the units (candidate
//!   gathering, ray slots, elastic pipes, the hit buffer's check pipe), calibrated on the
//!   whole core's synthesis, and [`structures`] the contexts, FIFOs, MSHR CAM and cache
//!   control by formula; [`timing`] is the clock rule applied to the logic levels of that
//!   synthesis;
//! - [`pricing`] is what `sim sweep` prices per configuration;
//! - [`bounds`] names the error bounds that add up several units' terms (the direction error
//!   of a walk).
//!
//! The hardware configuration's schema and validation stay in `cycle::hw_config`.

pub mod bounds;
pub mod core_logic;
pub mod estimate;
pub mod fabric;
pub mod pricing;
pub mod structures;
pub mod timing;

pub use crate::resources::{ResourceItem, ResourceReport, Resources};
pub use bounds::{direction_error_bound, DirectionErrorBound};
pub use fabric::{Fabric, FabricItem, FabricTotals};
