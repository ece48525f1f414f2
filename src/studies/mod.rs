//! Studies: runs of the models over many configurations, animations or cases.
//!
//! [`sweep`] (accuracy against cost, Pareto fronts), [`drift`] (fixed-point error over a long
//! animation), [`stress`] (stiff and extreme cases with a verdict each) [`fuzz`] (mutated inputs for the parsers), [`vectors`] (HDL
//! test vectors from adversarial cases, a real frame and random stimulus) and [`synthesis`]
//! (the RTL units through Yosys, beside the resource estimate), [`instances`] (fps against
//! instance count), [`paper`] (the paper's Fig. 7: static against animated car) and [`explore`]
//! (the hardware design space: fps against resources over hardware fields, with its Pareto fronts);
//! [`scene_error`] is the error of preparing a scene, shared by the sweep and the explorer.

pub mod drift;
pub mod explore;
pub mod fuzz;
pub mod instances;
pub mod paper;
pub mod scene_error;
pub mod stress;
pub mod sweep;
pub mod synthesis;
pub mod vectors;
