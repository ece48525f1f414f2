//! The stages that get vectors, one module each: what a transaction of the unit is, its
//! field layout in the datapath's formats, its adversarial cases, its random stimulus, and
//! its encoding — inputs plus the outputs the golden model (`crate::units`) computes for
//! them. [`build`] assembles a stage's table from those and from transactions captured in a
//! real frame (the root package records those).

pub mod hit_record;
pub mod normal;
pub mod raygen;
pub mod reciprocal;
pub mod sorter;
pub mod sphere;
pub mod sqrt;
pub mod tile_list;
pub mod transform;
pub mod walker;
pub mod walker_root;

use super::layout::Layout;
use super::rng::Rng;
use super::table::{plan_rows, spread, Origin, Timing, VectorTable};

/// A unit whose transactions become vectors.
pub trait Stage {
    /// One transaction's inputs.
    type Txn: Clone;
    /// File stem.
    fn name(&self) -> &'static str;
    /// What a row is, for the manifest.
    fn description(&self) -> &'static str;
    /// The field layout: inputs, then expected outputs.
    fn layout(&self) -> Layout;
    /// The hand-built edge cases, always all included.
    fn adversarial(&self) -> Vec<Self::Txn>;
    /// One random transaction.
    fn random(&self, rng: &mut Rng) -> Self::Txn;
    /// The row's field values in layout order: the inputs and the golden model's outputs.
    fn encode(&self, t: &Self::Txn) -> Vec<u128>;
    /// Latency and II of the unit, if it has fixed timing.
    fn timing(&self) -> Option<Timing> {
        None
    }
    /// Adds the stage's constants to the manifest.
    fn parameters(&self, _table: &mut VectorTable) {}
}

/// A stage's table: every adversarial case, then `count` more rows — transactions spread
/// over `captured` (half of `count`, or fewer if fewer were captured), then random ones from
/// the stage's stream of `seed`.
pub fn build<S: Stage>(stage: &S, captured: &[S::Txn], count: usize, seed: u64) -> VectorTable {
    let adversarial = stage.adversarial();
    let (n_captured, n_random) = plan_rows(captured.len(), count);
    let layout = stage.layout();
    let mut table = VectorTable::new(stage.name(), stage.description(), layout.clone());
    table.timing = stage.timing();
    let pack = |txns: &[S::Txn]| {
        txns.iter()
            .map(|t| layout.pack(&stage.encode(t)))
            .collect::<Vec<_>>()
    };
    table.push_block(Origin::Adversarial, pack(&adversarial));
    table.push_block(Origin::Captured, pack(&spread(captured, n_captured)));
    let mut rng = Rng::for_stage(seed, stage.name());
    let random: Vec<S::Txn> = (0..n_random).map(|_| stage.random(&mut rng)).collect();
    table.push_block(Origin::Random, pack(&random));
    stage.parameters(&mut table);
    table
}

/// Keeps the first occurrence of every value, in order.
pub(crate) fn dedup<T: PartialEq + Clone>(items: Vec<T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::with_capacity(items.len());
    for it in items {
        if !out.contains(&it) {
            out.push(it);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::datapath::DatapathConfig;

    /// Every value of every adversarial and random row fits its field: a row never carries
    /// a number the RTL would read differently.
    fn all_fit<S: Stage>(s: &S) {
        let l = s.layout();
        let mut rng = Rng::new(77);
        let mut txns = s.adversarial();
        txns.extend((0..500).map(|_| s.random(&mut rng)));
        for (i, t) in txns.iter().enumerate() {
            let v = s.encode(t);
            assert_eq!(
                v.len(),
                l.fields().len(),
                "{}: one value per field",
                s.name()
            );
            let bad = l.misfits(&v);
            assert!(bad.is_empty(), "{} case {i}: {bad:?} do not fit", s.name());
        }
    }

    #[test]
    fn every_value_fits_its_field() {
        let dp = DatapathConfig::default();
        all_fit(&raygen::RaygenStage::new(&dp));
        all_fit(&sphere::SphereStage::new(&dp));
        all_fit(&sqrt::SqrtStage::new(&dp));
        all_fit(&sorter::SorterStage::new(&dp));
        all_fit(&transform::TransformStage::new(&dp));
        all_fit(&reciprocal::ReciprocalStage::new(&dp));
        all_fit(&hit_record::HitRecordStage::new(&dp));
        all_fit(&normal::NormalStage::new(&dp));
        all_fit(&tile_list::TileListStage::new());
    }
}
