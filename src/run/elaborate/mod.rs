//! Scene-driven elaboration: derive from the scene the pipeline it needs and leave out the
//! rest (`docs/elaboration.md`).
//!
//! Pipeline position: between loading the scene and the run. [`elaborate`] reads the scene's
//! facts ([`analyse`]), decides unit by unit ([`plan`]), prices each decision
//! ([`savings`]) and yields the elaborated hardware and datapath configuration that the run
//! then uses (`RunConfig::elaborated`, in `run::frames`); [`print`](mod@print) writes the human summary. No decision may
//! change a hit record: `tests/elaborate.rs` renders pruned and full pipelines and compares
//! them byte for byte.

pub mod analyse;
pub mod instances;
pub mod plan;
pub mod print;
pub mod savings;

use crate::error::AssetError;
use crate::world::scene::Scene;
use analyse::SceneFacts;
use plan::Decision;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::resources::Resources;
use rtl_model::units::tile_list;
use serde::Serialize;
use thiserror::Error;

/// Why a scene could not be elaborated.
#[derive(Debug, Error)]
pub enum ElaborateError {
    /// The asset depths (`--depth`) are invalid.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// The configured or the elaborated hardware is invalid for its datapath.
    #[error("elaboration: hardware configuration: {0}")]
    Hardware(String),
}

/// The outcome: facts, decisions, savings, and the elaborated configuration.
#[derive(Clone, Debug, Serialize)]
pub struct Elaboration {
    /// Whether the run uses the elaborated pipeline (false under `--no-prune`).
    pub applied: bool,
    /// What the scene does.
    pub facts: SceneFacts,
    /// One decision per unit, in pipeline order.
    pub decisions: Vec<Decision>,
    /// Estimated resources of the full (configured) pipeline.
    pub full: Resources,
    /// Estimated resources of the elaborated pipeline.
    pub elaborated: Resources,
    /// Hardware of the elaborated pipeline.
    #[serde(skip)]
    pub hardware: HwConfig,
    /// Datapath of the elaborated pipeline.
    #[serde(skip)]
    pub datapath: DatapathConfig,
    /// Whether the elaborated pipeline reads its hit buffer.
    #[serde(skip)]
    pub use_hit_buffer: bool,
    /// The two-level instance scheme's list memory, when kept (`instances.rs`).
    #[serde(skip)]
    pub two_level: Option<tile_list::TileListConfig>,
}

/// Elaborates `scene` (as it will run: resolution, frames and `depth` overridden) against the
/// configured hardware `hw`, datapath `dp` and hit-buffer switch.
pub fn elaborate(
    scene: &Scene,
    depth: Option<u8>,
    hw: &HwConfig,
    dp: &DatapathConfig,
    use_hit_buffer: bool,
) -> Result<Elaboration, ElaborateError> {
    let facts = analyse::analyse(scene, depth, dp)?;
    let mut p = plan::plan(&facts, hw, dp, use_hit_buffer);
    let bad = ElaborateError::Hardware;
    p.hardware.validate_for(&p.datapath).map_err(bad)?;
    let full = hw.resources(dp).map_err(bad)?;
    let mut elaborated = p.hardware.resources(&p.datapath).map_err(bad)?;
    if let Some(tl) = &p.two_level {
        // The list memory is the scheme's price; the hardware configuration does not carry it.
        let f = &p.hardware.frame;
        elaborated.push(tile_list::resource_item(
            tl,
            p.hardware.sphere_units,
            f.width,
            f.height,
        ));
    }
    savings::fill(&mut p, facts.coordinate_range_m, hw, dp, &full, &elaborated);
    Ok(Elaboration {
        applied: true,
        facts,
        decisions: p.decisions,
        full: full.used,
        elaborated: elaborated.used,
        hardware: p.hardware,
        datapath: p.datapath,
        use_hit_buffer: p.use_hit_buffer,
        two_level: p.two_level,
    })
}

impl Elaboration {
    /// The same analysis with nothing applied (`--no-prune`): the full pipeline runs and the
    /// report still says what could have been left out.
    pub fn not_applied(mut self) -> Self {
        self.applied = false;
        for d in &mut self.decisions {
            d.applied = false;
        }
        self.elaborated = self.full;
        self.two_level = None;
        self
    }

    /// The saving of every decision that leaves out or resizes a unit, together (under
    /// `--no-prune`: what they would save). `could_narrow` is not included.
    pub fn total_saved(&self) -> savings::Saving {
        self.decisions
            .iter()
            .filter(|d| {
                matches!(
                    d.action,
                    plan::Action::LeftOut | plan::Action::Resized { .. }
                )
            })
            .fold(savings::Saving::default(), |a, d| a.plus(d.saved))
    }
}
