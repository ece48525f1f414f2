//! The JSON report (`--report-json`): configuration, assets, per-frame counters, summary.
//! Field meanings are listed in `docs/report.md`.

use crate::models::reference::FrameStats;
use crate::world::assets::Asset;
use serde::Serialize;

/// One asset's memory image, as reported.
#[derive(Clone, Debug, Serialize)]
pub struct AssetReport {
    /// Name.
    pub name: String,
    /// "sdf", "sdf-implicit" (walked on demand, not stored) or "vox".
    pub kind: String,
    /// Octree depth.
    pub depth: u8,
    /// Half side of the octree cube in metres.
    pub half_size_m: f64,
    /// Internal nodes.
    pub nodes: u64,
    /// Solid leaves (for an implicit tree: the estimate).
    pub leaves: u64,
    /// Far-pointer words.
    pub far_words: u64,
    /// Node memory bytes.
    pub node_bytes: u64,
    /// Attribute memory bytes.
    pub attr_bytes: u64,
    /// Build time, seconds.
    pub build_s: f64,
}

impl From<&Asset> for AssetReport {
    fn from(a: &Asset) -> Self {
        let s = &a.stats;
        Self {
            name: a.name.clone(),
            kind: a.kind.to_string(),
            depth: s.depth,
            half_size_m: a.half_size,
            nodes: s.nodes,
            leaves: s.leaves,
            far_words: s.far_words,
            node_bytes: s.node_bytes,
            attr_bytes: s.attr_bytes,
            build_s: a.build_s,
        }
    }
}

/// Scene facts.
#[derive(Clone, Debug, Serialize)]
pub struct SceneReport {
    /// File or `<embedded default scene>`.
    pub origin: String,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Frames rendered.
    pub frames: u32,
    /// Instances.
    pub instances: usize,
}

/// Run options.
#[derive(Clone, Debug, Serialize)]
pub struct OptionsReport {
    /// Which model rendered ("reference").
    pub model: String,
    /// Hit buffer on.
    pub hit_buffer: bool,
    /// Early termination on.
    pub early_termination: bool,
    /// Bounding-sphere culling on.
    pub culling: bool,
    /// Front-to-back sorting of the candidates on.
    pub sort: bool,
    /// Worker threads.
    pub threads: usize,
    /// How the memory images order their words (`top-levels-first` or `depth-first`,
    /// `--image-layout`).
    pub image_layout: String,
}

/// Totals over the run.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Frames.
    pub frames: u32,
    /// Rays over all frames.
    pub rays: u64,
    /// Tracing wall time over all frames (asset build and file output excluded), seconds.
    pub wall_s: f64,
    /// rays / wall_s.
    pub rays_per_s: f64,
    /// Pixels reused from the hit buffer.
    pub hit_buffer_reused: u64,
    /// hit_buffer_reused / rays.
    pub reuse_fraction: f64,
    /// Walker steps over all frames.
    pub walker_steps: u64,
    /// Asset build time, seconds.
    pub build_s: f64,
    /// The cycle model's summary (`--model cycle`).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub cycle: Option<CycleSummary>,
}

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Producer and version.
    pub tool: String,
    /// Scene facts.
    pub scene: SceneReport,
    /// Options.
    pub options: OptionsReport,
    /// Assets.
    pub assets: Vec<AssetReport>,
    /// Per-frame counters (and, for the fixed-point model, accuracy).
    pub frames: Vec<FrameReport>,
    /// Totals.
    pub summary: Summary,
    /// The datapath configuration (fixed-point and cycle models).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub datapath: Option<rtl_model::datapath::DatapathConfig>,
    /// The hardware configuration (cycle model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hardware: Option<rtl_model::cycle::hw_config::HwConfig>,
    /// Scene-driven elaboration: facts, decisions, savings (cycle model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elaboration: Option<crate::models::cycle::elaboration::Elaboration>,
}

/// One frame of the report: the model's counters, and for the fixed-point model its accuracy
/// against the f64 reference, its overflow counts per signal and the reference's wall time.
#[derive(Clone, Debug, Serialize)]
pub struct FrameReport {
    /// Counters of the model that produced the output.
    #[serde(flatten)]
    pub stats: FrameStats,
    /// Accuracy against the f64 reference (fixed-point model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<crate::models::fixed::Accuracy>,
    /// Saturations and wraps per signal name, non-zero ones only (fixed-point model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub overflows: Option<std::collections::BTreeMap<String, u64>>,
    /// Wall time of the reference on the same frame, seconds (fixed-point model only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_wall_s: Option<f64>,
    /// The cycle model's report of the frame (`--model cycle`): `cycles`, `fps_at_clock`,
    /// `rays_per_cycle`, `stages`, `memory`, `bound`, … (docs/report.md).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub cycle: Option<crate::models::cycle::CycleFrame>,
}

impl FrameReport {
    /// A frame of the reference model.
    pub fn of(stats: FrameStats) -> Self {
        Self {
            stats,
            accuracy: None,
            overflows: None,
            reference_wall_s: None,
            cycle: None,
        }
    }
}

impl Summary {
    /// Totals of per-frame counters.
    pub fn of(frames: &[FrameStats], build_s: f64) -> Self {
        let rays: u64 = frames.iter().map(|f| f.rays).sum();
        let wall_s: f64 = frames.iter().map(|f| f.wall_s).sum();
        let reused: u64 = frames.iter().map(|f| f.hit_buffer_reused).sum();
        Self {
            frames: frames.len() as u32,
            rays,
            wall_s,
            rays_per_s: rays as f64 / wall_s.max(1e-9),
            hit_buffer_reused: reused,
            reuse_fraction: reused as f64 / (rays as f64).max(1.0),
            walker_steps: frames.iter().map(|f| f.walker_steps).sum(),
            build_s,
            cycle: None,
        }
    }
}

/// The cycle model's totals.
#[derive(Clone, Debug, Serialize)]
pub struct CycleSummary {
    /// Clock, MHz.
    pub clock_mhz: u32,
    /// Cycles over all frames.
    pub cycles: u64,
    /// Frames per second at the clock: frames / (cycles / clock).
    pub fps_at_clock: f64,
    /// The slowest frame's rate.
    pub fps_at_clock_min: f64,
    /// Pixels per cycle over the run.
    pub rays_per_cycle: f64,
    /// Simulated pixels per wall second (functional model and cycle model together).
    pub sim_rays_per_s: f64,
    /// Simulated cycles per wall second.
    pub sim_cycles_per_s: f64,
    /// Which limit held most frames.
    pub bound: String,
    /// The configuration's resources against the part.
    pub resources: rtl_model::cycle::hw_config::ResourceReport,
    /// The fabric estimate's totals (LUT, FF) against the part; `None` when the estimate
    /// failed (it is printed by `sim hardware`, with its rows).
    pub fabric: Option<rtl_model::cost::FabricTotals>,
    /// Sampled timing (`--sample`): the run's estimate and its 95 % interval; `cycles` and
    /// the frame rates above are then estimates too (docs/cycle-model.md §3.5).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampled: Option<crate::models::cycle::sample::SampledSummary>,
}

impl CycleSummary {
    /// Totals of `frames`.
    pub fn of(
        frames: &[crate::models::cycle::CycleFrame],
        hw: &rtl_model::cycle::hw_config::HwConfig,
        resources: rtl_model::cycle::hw_config::ResourceReport,
        fabric: Option<rtl_model::cost::FabricTotals>,
        wall_s: f64,
    ) -> Self {
        let cycles: u64 = frames.iter().map(|f| f.cycles).sum();
        let pixels: f64 = frames
            .iter()
            .map(|f| f.rays_per_cycle * f.cycles as f64)
            .sum();
        let mut bounds: std::collections::BTreeMap<&str, u32> = Default::default();
        for f in frames {
            *bounds.entry(f.bound.limit.as_str()).or_default() += 1;
        }
        let bound = bounds
            .iter()
            .max_by_key(|(_, n)| **n)
            .map_or("none", |(b, _)| b)
            .to_string();
        Self {
            clock_mhz: hw.clock_mhz,
            cycles,
            fps_at_clock: crate::models::cycle::stats::fps_at_clock(
                hw.clock_mhz,
                frames.len() as f64,
                cycles as f64,
            ),
            fps_at_clock_min: frames
                .iter()
                .map(|f| f.fps_at_clock)
                .fold(f64::INFINITY, f64::min)
                .min(1e300),
            rays_per_cycle: pixels / cycles.max(1) as f64,
            sim_rays_per_s: pixels / wall_s.max(1e-9),
            sim_cycles_per_s: cycles as f64 / wall_s.max(1e-9),
            bound,
            resources,
            fabric,
            sampled: crate::models::cycle::sample::SampledSummary::of(
                &frames
                    .iter()
                    .filter_map(|f| Some((f.cycles, f.sampled.as_ref()?)))
                    .collect::<Vec<_>>(),
                hw.clock_mhz,
            ),
        }
    }
}
