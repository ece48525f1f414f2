//! Validation of sampled timing against the full model (`sim bench --sample-validate`, and
//! `tests/sampled_timing.rs`): the same frames through a full and a sampled cycle-model run,
//! per frame the full cycles, the estimate, its 95 % interval and both wall times.
//!
//! Pipeline position: a study over `runner::CycleRun` (docs/cycle-model.md §3.5).

use super::runner::CycleRun;
use super::sample::SampleConfig;
use super::CycleOptions;
use crate::models::reference::FrameInput;
use crate::world::assets::Asset;
use crate::world::scene::Scene;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;

/// One frame of the comparison.
#[derive(Clone, Debug)]
pub struct SampleCheck {
    /// Frame.
    pub frame: u32,
    /// The full model's cycles.
    pub full_cycles: u64,
    /// The sampled estimate.
    pub estimate: f64,
    /// Its 95 % interval.
    pub low: f64,
    /// Its 95 % interval.
    pub high: f64,
    /// Full run's wall time for the frame (functional and cycle model), s.
    pub full_s: f64,
    /// Sampled run's wall time for the frame, s.
    pub sampled_s: f64,
}

impl SampleCheck {
    /// Relative error of the estimate.
    pub fn error(&self) -> f64 {
        (self.estimate - self.full_cycles as f64) / (self.full_cycles.max(1) as f64)
    }

    /// Whether the full figure lies in the interval.
    pub fn covered(&self) -> bool {
        (self.low..=self.high).contains(&(self.full_cycles as f64))
    }
}

/// Runs every frame of `scene` through a full and a sampled cycle model (hit buffer on when
/// `use_hit_buffer`) and compares them frame by frame.
pub fn compare(
    scene: &Scene,
    assets: &[Asset],
    dp: &DatapathConfig,
    hw: &HwConfig,
    use_hit_buffer: bool,
    sample: SampleConfig,
) -> anyhow::Result<Vec<SampleCheck>> {
    let (w, h) = scene.file.resolution;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let new_run = |s: Option<SampleConfig>| {
        CycleRun::new(
            hw,
            dp,
            assets,
            &scene.instance_asset,
            (w, h),
            CycleOptions {
                sample: s,
                ..CycleOptions::default()
            },
        )
    };
    let (mut full, mut sampled) = (new_run(None)?, new_run(Some(sample))?);
    let reuse = use_hit_buffer && hw.hit_buffer.present;
    let mut out = Vec::new();
    for f in 0..scene.file.frames {
        let state = scene
            .frame_state(f, &half)
            .map_err(|m| anyhow::anyhow!("frame {f}: {m}"))?;
        let input = FrameInput {
            scene,
            assets,
            state: &state,
        };
        let a = full.frame(&input, dp, reuse)?;
        let b = sampled.frame(&input, dp, reuse)?;
        let s = b
            .cycles
            .sampled
            .as_ref()
            .ok_or_else(|| anyhow::anyhow!("frame {f}: the sampled run reported no sample"))?;
        out.push(SampleCheck {
            frame: f,
            full_cycles: a.cycles.cycles,
            estimate: s.cycles_estimate,
            low: s.cycles_low,
            high: s.cycles_high,
            full_s: a.wall_s,
            sampled_s: b.wall_s,
        });
    }
    Ok(out)
}
