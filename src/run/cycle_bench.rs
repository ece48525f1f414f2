//! `sim bench --model cycle`: the simulator's speed against the reference on the same frames,
//! the modelled hardware's frame rate with a still and a moving camera, and the scaling of
//! cycles per frame with the number of walkers and with DRAM latency (table, CSV and a PNG
//! plot).
//!
//! Pipeline position: a benchmark, not a test (DESIGN.md: speed targets live in benchmarks),
//! beside [`super::bench`]: it runs the cycle model over a scene's frames and draws a figure,
//! so it sits in the run layer, above the models it times and the output it draws with.
//! Everything runs in one process, so the ratios compare like with like on a shared machine.

use super::parallel::map_in_order;
use crate::models::cycle::runner::CycleRun;
use crate::models::cycle::sample::SampleConfig;
use crate::models::cycle::CycleOptions;
use crate::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use crate::world::assets::Asset;
use crate::world::scene::Scene;
use plotters::prelude::*;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use std::time::Instant;

/// One frame of the speed comparison.
#[derive(Clone, Debug)]
pub struct SpeedFrame {
    /// Frame.
    pub frame: u32,
    /// Reference wall time, s.
    pub reference_s: f64,
    /// Cycle model wall time (functional model and cycle simulation, which run at the same
    /// time on two threads), s.
    pub cycle_s: f64,
    /// Of which the functional model's wall time on its own thread, s: when it is well below
    /// `cycle_s`, the cycle simulation sets the pace.
    pub functional_s: f64,
    /// Cycles of the frame.
    pub cycles: u64,
    /// Frames per second at the clock.
    pub fps: f64,
    /// Pixels per cycle.
    pub rays_per_cycle: f64,
    /// The limit.
    pub bound: String,
    /// Cycles of the frame taken at once by idle-cycle skipping (docs/cycle-model.md §3.3).
    pub skipped_cycles: u64,
    /// With sampled timing: the 95 % interval of the estimate (`cycles` is the estimate,
    /// rounded), and the cycles simulated clock by clock.
    pub sampled: Option<SampledSpeed>,
}

/// What a sampled frame of the speed comparison adds (docs/cycle-model.md §3.5).
#[derive(Clone, Copy, Debug)]
pub struct SampledSpeed {
    /// Lower end of the 95 % interval of the frame's cycles.
    pub low: f64,
    /// Upper end.
    pub high: f64,
    /// Cycles simulated clock by clock (the timed segments with their warming and drains).
    pub simulated_cycles: u64,
}

/// Runs every frame of `scene` through the reference and the cycle model (both with or both
/// without the hit buffer) and times each; with `sample`, the cycle model times only a
/// sample of each frame (`--sample`) and reports its estimate.
pub fn speed(
    scene: &Scene,
    assets: &[Asset],
    dp: &DatapathConfig,
    hw: &HwConfig,
    use_hit_buffer: bool,
    sample: Option<SampleConfig>,
) -> anyhow::Result<Vec<SpeedFrame>> {
    let (w, h) = scene.file.resolution;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let mut run = CycleRun::new(
        hw,
        dp,
        assets,
        &scene.instance_asset,
        (w, h),
        CycleOptions {
            sample,
            ..CycleOptions::default()
        },
    )?;
    let mut reference = HitBuffer::new(w, h);
    let opts = RenderOptions {
        use_hit_buffer,
        ..RenderOptions::default()
    };
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
        let t = Instant::now();
        render_frame(&input, &mut reference, opts);
        let reference_s = t.elapsed().as_secs_f64();
        let skipped_before = run.model().skipped_cycles().0;
        let r = run.frame(&input, dp, use_hit_buffer)?;
        let skipped_cycles = run.model().skipped_cycles().0 - skipped_before;
        let sampled = r.cycles.sampled.as_ref().map(|s| SampledSpeed {
            low: s.cycles_low,
            high: s.cycles_high,
            simulated_cycles: s.cycles_simulated,
        });
        out.push(SpeedFrame {
            frame: f,
            reference_s,
            cycle_s: r.wall_s,
            functional_s: r.fixed.wall_s,
            cycles: r.cycles.cycles,
            fps: r.cycles.fps_at_clock,
            rays_per_cycle: r.cycles.rays_per_cycle,
            bound: r.cycles.bound.limit.clone(),
            skipped_cycles,
            sampled,
        });
    }
    Ok(out)
}

/// One point of the scaling sweep.
#[derive(Clone, Debug)]
pub struct ScalePoint {
    /// `walkers` or `dram_latency`.
    pub sweep: &'static str,
    /// The swept value.
    pub value: u32,
    /// Cycles of the frame.
    pub cycles: u64,
    /// Frames per second at the clock.
    pub fps: f64,
    /// The limit.
    pub bound: String,
    /// Its figures.
    pub reason: String,
}

/// Cycles of one full-trace frame (frame 0, no reuse) per configuration: walkers 1..=64
/// (the default DRAM), then DRAM latency 15..=480 cycles (the default pool).
pub fn scaling(
    scene: &Scene,
    assets: &[Asset],
    dp: &DatapathConfig,
    hw: &HwConfig,
    mut progress: impl FnMut(&ScalePoint),
) -> anyhow::Result<Vec<ScalePoint>> {
    let (w, h) = scene.file.resolution;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let state = scene
        .frame_state(0, &half)
        .map_err(|m| anyhow::anyhow!("frame 0: {m}"))?;
    let input = FrameInput {
        scene,
        assets,
        state: &state,
    };
    let mut configs: Vec<(&'static str, u32, HwConfig)> = Vec::new();
    for walkers in [1u32, 2, 4, 8, 16, 32, 64] {
        let mut c = hw.clone();
        c.walker_pool.walkers = walkers;
        configs.push(("walkers", walkers, c));
    }
    for lat in [15u32, 30, 60, 120, 240, 480] {
        let mut c = hw.clone();
        c.node_memory.dram.latency = lat;
        configs.push(("dram_latency", lat, c));
    }
    // Independent runs: on all cores, points and progress in the sequential order.
    map_in_order(
        "scaling point",
        &configs,
        |(sweep, value, c)| -> anyhow::Result<ScalePoint> {
            let mut run = CycleRun::new(
                c,
                dp,
                assets,
                &scene.instance_asset,
                (w, h),
                CycleOptions::default(),
            )?;
            let r = run.frame(&input, dp, false)?;
            Ok(ScalePoint {
                sweep,
                value: *value,
                cycles: r.cycles.cycles,
                fps: r.cycles.fps_at_clock,
                bound: r.cycles.bound.limit.clone(),
                reason: r.cycles.bound.reason.clone(),
            })
        },
        |p| progress(p),
    )
}

/// The sweep as CSV.
pub fn scaling_csv(points: &[ScalePoint]) -> String {
    let mut s = String::from("sweep,value,cycles,fps_at_clock,bound,reason\n");
    for p in points {
        s.push_str(&format!(
            "{},{},{},{:.2},{},\"{}\"\n",
            p.sweep, p.value, p.cycles, p.fps, p.bound, p.reason
        ));
    }
    s
}

/// Two panels, cycles per frame against walkers and against DRAM latency (both log2 axes),
/// each point labelled with its bound.
pub fn scaling_plot(points: &[ScalePoint], title: &str) -> Result<image::RgbImage, String> {
    crate::output::figure::register_font()?;
    let (w, h) = (1000u32, 480u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let err = |e: DrawingAreaErrorKind<_>| format!("plot: {e:?}");
        root.fill(&WHITE).map_err(err)?;
        let root = root
            .titled(title, ("sans-serif", 18))
            .map_err(|e| format!("plot: {e:?}"))?;
        let areas = root.split_evenly((1, 2));
        for (area, sweep, xdesc) in [
            (&areas[0], "walkers", "walkers (8 contexts each)"),
            (&areas[1], "dram_latency", "DRAM latency (cycles)"),
        ] {
            let pts: Vec<(f64, f64, String)> = points
                .iter()
                .filter(|p| p.sweep == sweep)
                .map(|p| (f64::from(p.value), p.cycles as f64 / 1e6, p.bound.clone()))
                .collect();
            if pts.is_empty() {
                continue;
            }
            let xmin = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
            let xmax = pts.iter().map(|p| p.0).fold(0.0, f64::max);
            let ymax = pts.iter().map(|p| p.1).fold(0.0, f64::max) * 1.15;
            let mut chart = ChartBuilder::on(area)
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(60)
                .build_cartesian_2d((xmin / 1.3..xmax * 1.3).log_scale(), 0.0..ymax)
                .map_err(|e| format!("plot: {e:?}"))?;
            chart
                .configure_mesh()
                .x_desc(xdesc)
                .y_desc("M cycles per frame")
                .x_label_formatter(&|v| format!("{v:.0}"))
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(|e| format!("plot: {e:?}"))?;
            let c = RGBColor(31, 90, 200);
            chart
                .draw_series(LineSeries::new(
                    pts.iter().map(|p| (p.0, p.1)),
                    c.stroke_width(2),
                ))
                .map_err(|e| format!("plot: {e:?}"))?;
            chart
                .draw_series(pts.iter().map(|p| {
                    let colour = match p.2.as_str() {
                        "memory" => RGBColor(210, 40, 40),
                        "clock" => RGBColor(20, 150, 60),
                        _ => c,
                    };
                    EmptyElement::at((p.0, p.1))
                        + Circle::new((0, 0), 5, colour.filled())
                        + Text::new(p.2.clone(), (6, -16), ("sans-serif", 12))
                }))
                .map_err(|e| format!("plot: {e:?}"))?;
        }
        root.present().map_err(|e| format!("plot: {e:?}"))?;
    }
    image::RgbImage::from_raw(w, h, buf).ok_or_else(|| "plot: buffer size".to_string())
}
