//! HDL test vectors: every unit's transactions as packed rows an RTL testbench reads with
//! `$readmemh`, each table with a JSON manifest (fields: offset, width, signedness, fraction
//! bits, quantisation and overflow modes) and a SystemVerilog package of `localparam`s.
//! `docs/vectors.md` is the user's guide.
//!
//! Pipeline position: beside the units. The stage modules ([`stage`]) call the golden model
//! (`crate::units`) for every expected output, so the vectors are the model by construction;
//! the root package (`svo_sim::studies::vectors`) captures transactions from a real frame of a scene
//! and writes the files (`sim vectors`).
//!
//! Layers: [`word`] (a packed row of any width) → [`layout`] (named fields) → [`table`] (a
//! stage's rows and where they came from) → [`files`] (hex, manifest, package text);
//! [`stage`] (what each unit's rows hold); [`frame`] (end-to-end per-pixel records);
//! [`rng`] (the seeded stimulus); [`lanes`] (the units of a k-wide walk issue).
//!
//! Hook for cycle-stamped logs: a table is any [`table::VectorTable`]; a cycle model that
//! records the cycle each transaction entered and left a stage adds one table per stage (see
//! `docs/vectors.md`, "Cycle-stamped logs") and [`files::table_files`] writes it like the
//! others.

pub mod files;
pub mod frame;
pub mod lanes;
pub mod layout;
pub mod rng;
pub mod stage;
pub mod table;
pub mod word;

use crate::datapath::DatapathConfig;
use crate::svo::{BuildError, LeafSetError};
use table::VectorTable;
use thiserror::Error;

/// Why vectors could not be made.
#[derive(Debug, Error)]
pub enum VectorError {
    /// The datapath configuration is inconsistent.
    #[error("datapath configuration: {0}")]
    Config(String),
    /// A synthetic octree for the walker could not be made.
    #[error("synthetic octree: {0}")]
    LeafSet(#[from] LeafSetError),
    /// A memory image could not be built.
    #[error("synthetic octree image: {0}")]
    Image(#[from] BuildError),
    /// A walk could not be timed by the cycle model.
    #[error(transparent)]
    Timing(#[from] crate::cycle::walk_timing::WalkTimingError),
    /// A manifest could not be serialised.
    #[error("manifest: {0}")]
    Json(#[from] serde_json::Error),
}

/// Transactions captured from a real frame, per stage (inputs only: the stage modules
/// compute every expected output from the golden model).
#[derive(Clone, Debug, Default)]
pub struct Captured {
    /// Direction-table entries.
    pub raygen: Vec<stage::raygen::RaygenTxn>,
    /// Ray–sphere tests.
    pub sphere: Vec<stage::sphere::SphereTxn>,
    /// Square-root radicands of the sphere tests that took a root.
    pub sqrt: Vec<i64>,
    /// Candidate lists of rays, unsorted (at most `stage::sorter::rows_max_keys`).
    pub sorter: Vec<stage::sorter::SorterTxn>,
    /// Ray transforms.
    pub transform: Vec<stage::transform::TransformTxn>,
    /// Reciprocals (three per walk).
    pub reciprocal: Vec<stage::reciprocal::ReciprocalTxn>,
    /// Walks (image = asset index).
    pub walker: Vec<stage::walker::WalkTxn>,
    /// Hit records packed, each with the reuse check of its own word in a still next frame.
    pub hit_record: Vec<stage::hit_record::HitRecordTxn>,
    /// Record normals of hits: the attribute's normal word and the instance's matrix.
    pub normal: Vec<stage::normal::NormalTxn>,
}

/// Every unit's tables for `dp`: per stage all adversarial rows plus `count` captured and
/// random rows (random ones from `seed`), the reciprocal seed ROM, the walker-root table (the walker table's walks), the walker's visit table
/// and the memory images of `scene_images` and of the walker's synthetic octrees. In
/// pipeline order.
pub fn unit_tables(
    dp: &DatapathConfig,
    captured: &Captured,
    scene_images: Vec<stage::walker::NamedImage>,
    count: usize,
    seed: u64,
) -> Result<Vec<VectorTable>, VectorError> {
    dp.validate().map_err(VectorError::Config)?;
    let recip = stage::reciprocal::ReciprocalStage::new(dp);
    let walker = stage::walker::WalkerStage::new(dp, scene_images)?;
    let (walks, visits) = walker.build(&captured.walker, count, seed)?;
    let roots = stage::walker_root::WalkerRootStage::new(dp).build(&walker.walk_blocks(
        &captured.walker,
        count,
        seed,
    ));
    let mut v = vec![
        stage::build(
            &stage::raygen::RaygenStage::new(dp),
            &captured.raygen,
            count,
            seed,
        ),
        stage::build(&stage::tile_list::TileListStage::new(), &[], count, seed),
        stage::build(
            &stage::sphere::SphereStage::new(dp),
            &captured.sphere,
            count,
            seed,
        ),
        stage::build(
            &stage::sqrt::SqrtStage::new(dp),
            &captured.sqrt,
            count,
            seed,
        ),
        stage::build(
            &stage::sorter::SorterStage::new(dp),
            &captured.sorter,
            count,
            seed,
        ),
        stage::build(
            &stage::transform::TransformStage::new(dp),
            &captured.transform,
            count,
            seed,
        ),
        stage::build(&recip, &captured.reciprocal, count, seed),
        recip.seed_rom(),
        roots,
        walks,
        visits,
        stage::build(
            &stage::hit_record::HitRecordStage::new(dp),
            &captured.hit_record,
            count,
            seed,
        ),
        stage::build(
            &stage::normal::NormalStage::new(dp),
            &captured.normal,
            count,
            seed,
        ),
    ];
    v.extend(walker.image_tables());
    Ok(v)
}

/// The names of the stages with an RTL unit and a testbench in `testbench/` (one a line).
pub const RTL_UNITS: &[&str] = &[
    "raygen",
    "sqrt",
    "sphere",
    "sorter",
    "transform",
    "reciprocal",
    "hit_record",
    "normal",
    "walker",
    "walker_root",
];
