//! The plain result of scene-driven elaboration (`docs/elaboration.md`): the scene's facts, one
//! decision per unit with what it saves, the resources of the full and the elaborated
//! pipeline, and the elaborated hardware and datapath the cycle model then runs.
//!
//! Pipeline position: data only. `crate::run::elaborate` computes an [`Elaboration`] from a
//! scene before the run (analyse, plan, savings); the run applies it, and the JSON report
//! (`crate::output::report`) carries it. It lives in the models layer, beside the cycle model
//! whose pipeline it describes, so that the output layer can take it without importing the run
//! layer (docs/architecture.md §1).

use rtl_model::cycle::hw_config::{HwConfig, Resources};
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::tile_list;
use serde::Serialize;

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
    /// The two-level instance scheme's list memory, when kept (`run/elaborate/instances.rs`).
    #[serde(skip)]
    pub two_level: Option<tile_list::TileListConfig>,
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
    pub fn total_saved(&self) -> Saving {
        self.decisions
            .iter()
            .filter(|d| matches!(d.action, Action::LeftOut | Action::Resized { .. }))
            .fold(Saving::default(), |a, d| a.plus(d.saved))
    }
}

/// What one instance does over the frames.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InstanceFacts {
    /// Instance name.
    pub name: String,
    /// Its pose (rotation, centre, scale) differs between some two frames.
    pub moves: bool,
    /// Its quantised rotation (the `raygen.mat` codes the host writes) is not the identity
    /// in some frame, so its transform needs the products.
    pub rotates: bool,
    /// Some frame scales it by other than (1, 1, 1).
    pub scaled: bool,
}

/// Facts of a scene, as the elaboration uses them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneFacts {
    /// Frames that will run.
    pub frames: u32,
    /// Per instance, in scene order.
    pub instances: Vec<InstanceFacts>,
    /// The camera differs (bit for bit) between every two consecutive frames, so no frame
    /// after the first can reuse a pixel; with one frame this is vacuously true.
    pub camera_moves_every_frame: bool,
    /// Octree depth of the deepest asset as built (after `--depth`).
    pub deepest_asset: u8,
    /// Largest |coordinate| of any camera position or instance centre over all frames, metres.
    pub coordinate_range_m: f64,
}

impl SceneFacts {
    /// Instances that move in some frame.
    pub fn moving(&self) -> impl Iterator<Item = &InstanceFacts> {
        self.instances.iter().filter(|i| i.moves)
    }

    /// Instances whose transform needs its products in some frame.
    pub fn rotating(&self) -> impl Iterator<Item = &InstanceFacts> {
        self.instances.iter().filter(|i| i.rotates)
    }
}

/// What the elaboration does with a unit.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Action {
    /// Kept as configured.
    Kept,
    /// Left out of the pipeline.
    LeftOut,
    /// Kept with a smaller size (lanes, frames).
    Resized {
        /// Size configured.
        from: u64,
        /// Size the scene needs.
        to: u64,
    },
    /// Could be narrowed, but is not (the reason says why).
    CouldNarrow,
}

impl Action {
    /// Short text for the printed table ("resized 8 → 1").
    pub fn label(&self) -> String {
        match self {
            Action::Kept => "kept".into(),
            Action::LeftOut => "left out".into(),
            Action::Resized { from, to } => format!("resized {from} → {to}"),
            Action::CouldNarrow => "could narrow".into(),
        }
    }
}

/// One decision: a unit, what happens to it, why (a fact of the scene) and what it saves.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Decision {
    /// The unit (`sphere_lanes`, `sorter`, `transform_products`, `walk_lanes`, `scale_path`,
    /// `hit_buffer`, `walker_stacks`, `position_format`).
    pub unit: String,
    /// What the elaboration does with it.
    pub action: Action,
    /// The scene fact behind it.
    pub reason: String,
    /// Whether the elaborated configuration includes it (false for `could_narrow`, and for
    /// every decision under `--no-prune`).
    pub applied: bool,
    /// What it saves against the full pipeline.
    pub saved: Saving,
}

/// What one decision saves against the full pipeline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Saving {
    /// DSP48E2 slices.
    pub dsp48e2: u64,
    /// BRAM36 blocks.
    pub bram36: u64,
    /// URAM288 blocks.
    pub uram288: u64,
    /// Bits of on-chip memory no longer stored (words × word bits, before block rounding).
    pub ram_bits: u64,
    /// Compare-exchange elements of the sorting network (LUTs; not in the DSP/RAM estimate).
    pub comparators: u64,
    /// Cycles of latency per ray taken off the unit's configured latency.
    pub latency_cycles: u64,
}

impl Saving {
    /// Sum of two savings.
    pub fn plus(self, o: Self) -> Self {
        Self {
            dsp48e2: self.dsp48e2 + o.dsp48e2,
            bram36: self.bram36 + o.bram36,
            uram288: self.uram288 + o.uram288,
            ram_bits: self.ram_bits + o.ram_bits,
            comparators: self.comparators + o.comparators,
            latency_cycles: self.latency_cycles + o.latency_cycles,
        }
    }
}
