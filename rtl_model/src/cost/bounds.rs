//! Error bounds that span several units: the one named direction-error bound of a datapath.
//!
//! Pipeline position: beside the run; `sim datapath` prints it, and the fixed model's mismatch
//! judgements (`svo_sim::models::fixed::{bound, explain}`) pass it to the walker's spatial
//! bound. Each unit's own bound stays with the unit (`units::transform::dir_error_bound`,
//! `units::reciprocal::error_bound`, …); this module only names their sum, derived in
//! `docs/number-formats.md` §3.5.

use crate::datapath::DatapathConfig;
use crate::units::{reciprocal, transform};

/// The terms of the direction error a walk sees, per component of the unit local direction:
/// how far the ray the walker follows can tilt from the exact one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionErrorBound {
    /// The transform's direction error (`units::transform::dir_error_bound`).
    pub transform: f64,
    /// The reciprocal's relative error (`units::reciprocal::error_bound(..).rel`): an error
    /// of ε·|1/d| in 1/d tilts the ray like an error of ε·|d| ≤ ε in d.
    pub reciprocal_rel: f64,
    /// The reciprocal's zero threshold (`units::reciprocal::zero_threshold`): a component at
    /// or below it is walked as parallel, a tilt of at most the threshold.
    pub zero_threshold: f64,
}

impl DirectionErrorBound {
    /// The terms of `dp` (the reciprocal's bound scans its seed ROM: build it once per use,
    /// not per ray).
    pub fn of(dp: &DatapathConfig) -> Self {
        Self {
            transform: transform::dir_error_bound(&dp.transform),
            reciprocal_rel: reciprocal::error_bound(&dp.reciprocal).rel,
            zero_threshold: reciprocal::zero_threshold(&dp.reciprocal),
        }
    }

    /// The terms every ray has: transform + reciprocal relative error (a ray with no
    /// component near the zero threshold is bounded by this).
    pub fn without_zero_threshold(&self) -> f64 {
        self.transform + self.reciprocal_rel
    }

    /// The bound for any ray: all three terms.
    pub fn total(&self) -> f64 {
        self.without_zero_threshold() + self.zero_threshold
    }
}

/// The direction-error bound of `dp` for any ray ([`DirectionErrorBound::total`]): what
/// `units::walker::spatial_error_bound` takes as `dir_err`.
pub fn direction_error_bound(dp: &DatapathConfig) -> f64 {
    DirectionErrorBound::of(dp).total()
}
