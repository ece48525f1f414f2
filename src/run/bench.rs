//! `sim bench`: the speed of the models on the same frames, as ratios measured in one run
//! (the machines are shared and noisy, so no figure here is compared with a fixed time).
//!
//! Pipeline position: beside [`super::frames`]. [`reference_speed`] times the f64 reference
//! with and without the hit buffer; [`fixed_speed`] times the fixed-point functional model
//! against the reference frame by frame (best of several runs each); the cycle model's own
//! bench is [`super::cycle_bench`], whose tables [`cycle_speed_table`] and
//! [`write_scaling`] present.

use super::cycle_bench::{scaling_csv, scaling_plot, ScalePoint, SpeedFrame};
use crate::models::fixed::{render_frame_fixed, FixedBuffer};
use crate::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use crate::output::interrupt;
use crate::output::png::encode_png;
use crate::output::writer::write_whole;
use crate::world::assets::Asset;
use crate::world::scene::Scene;
use anyhow::Result;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// The reference's speed in one mode over all frames.
#[derive(Clone, Debug)]
pub struct ReferenceSpeed {
    /// What was timed.
    pub label: &'static str,
    /// Rays per second over all frames.
    pub rays_per_s: f64,
    /// Rays per second of frame 0.
    pub first_rays_per_s: f64,
    /// Frames.
    pub frames: u32,
}

/// Times the reference on every frame of `scene`, without and then with the hit buffer.
pub fn reference_speed(scene: &Scene, assets: &[Asset]) -> Result<[ReferenceSpeed; 2]> {
    let (w, h) = scene.file.resolution;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let one = |label: &'static str, use_hit_buffer: bool| -> Result<ReferenceSpeed> {
        let mut buffer = HitBuffer::new(w, h);
        let opts = RenderOptions {
            use_hit_buffer,
            ..RenderOptions::default()
        };
        let (mut rays, mut secs, mut first) = (0u64, 0f64, 0f64);
        for f in 0..scene.file.frames {
            let n = scene.file.frames;
            interrupt::check(|| format!("{label}: frame {f} of {n}"), String::new)?;
            let state = scene.frame_state(f, &half).map_err(anyhow::Error::msg)?;
            let input = FrameInput {
                scene,
                assets,
                state: &state,
            };
            let st = render_frame(&input, &mut buffer, opts);
            if f == 0 {
                first = st.rays_per_s;
            }
            rays += st.rays;
            secs += st.wall_s;
        }
        Ok(ReferenceSpeed {
            label,
            rays_per_s: rays as f64 / secs,
            first_rays_per_s: first,
            frames: scene.file.frames,
        })
    };
    Ok([
        one("full trace (no hit buffer)", false)?,
        one("with hit buffer", true)?,
    ])
}

/// The reference bench's lines: each mode's speed and the hit buffer's speed-up.
pub fn reference_speed_text(s: &[ReferenceSpeed; 2]) -> String {
    let mut t = String::new();
    for r in s {
        let _ = writeln!(
            t,
            "  {:<28} {:>6.2} M rays/s over {} frames (frame 0: {:.2} M rays/s)",
            r.label,
            r.rays_per_s / 1e6,
            r.frames,
            r.first_rays_per_s / 1e6
        );
    }
    let _ = write!(
        t,
        "  hit-buffer speed-up: {:.2}x (same run)",
        s[1].rays_per_s / s[0].rays_per_s
    );
    t
}

/// One frame of the fixed-point model against the reference, best of `repeat` runs each.
#[derive(Clone, Copy, Debug)]
pub struct FixedFrameTime {
    /// Frame.
    pub frame: u32,
    /// Fastest reference run, seconds.
    pub reference_s: f64,
    /// Fastest fixed-point run, seconds.
    pub fixed_s: f64,
}

impl FixedFrameTime {
    /// The frame's line of the bench table.
    pub fn line(&self) -> String {
        format!(
            "    frame {:>3}: reference {:>7.1} ms  fixed {:>7.1} ms  ratio {:.3}",
            self.frame,
            self.reference_s * 1e3,
            self.fixed_s * 1e3,
            self.reference_s / self.fixed_s
        )
    }
}

/// Times the fixed-point model against the reference on every frame, full trace, runs of the
/// two interleaved so that a disturbance on the machine hits both; `each` sees every frame.
pub fn fixed_speed(
    scene: &Scene,
    assets: &[Asset],
    dp: &DatapathConfig,
    repeat: u32,
    mut each: impl FnMut(&FixedFrameTime),
) -> Result<Vec<FixedFrameTime>> {
    let (w, h) = scene.file.resolution;
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let full = RenderOptions {
        use_hit_buffer: false,
        ..RenderOptions::default()
    };
    let mut out = Vec::new();
    for f in 0..scene.file.frames {
        let n = scene.file.frames;
        interrupt::check(|| format!("frame {f} of {n}"), String::new)?;
        let state = scene.frame_state(f, &half).map_err(anyhow::Error::msg)?;
        let input = FrameInput {
            scene,
            assets,
            state: &state,
        };
        let (mut best_r, mut best_f) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..repeat.max(1) {
            let mut rb = HitBuffer::new(w, h);
            best_r = best_r.min(render_frame(&input, &mut rb, full).wall_s);
            let mut fb = FixedBuffer::new(w, h);
            best_f = best_f.min(render_frame_fixed(&input, &mut fb, dp, false)?.wall_s);
        }
        let t = FixedFrameTime {
            frame: f,
            reference_s: best_r,
            fixed_s: best_f,
        };
        each(&t);
        out.push(t);
    }
    Ok(out)
}

/// The fixed bench's closing line: both models' rays/s and their ratio.
pub fn fixed_speed_total(frames: &[FixedFrameTime], pixels: f64) -> String {
    let t_ref: f64 = frames.iter().map(|f| f.reference_s).sum();
    let t_fix: f64 = frames.iter().map(|f| f.fixed_s).sum();
    let rays = pixels * frames.len() as f64;
    format!(
        "  fixed {:.2} M rays/s, reference {:.2} M rays/s: ratio {:.3} (fixed rays/s ÷ reference rays/s; target ≥ 0.5)",
        rays / t_fix / 1e6,
        rays / t_ref / 1e6,
        t_ref / t_fix
    )
}

/// The cycle bench's table for one camera: per frame the wall times of the reference, the
/// cycle model and its functional model, their ratio, the modelled cycles and frame rate. A
/// sampled run (`sim bench --model cycle --sample RATE`) adds the half-width of each
/// estimate's 95 % interval and the share of the cycles simulated clock by clock.
pub fn cycle_speed_table(label: &str, frames: &[SpeedFrame], pixels: f64, hw: &HwConfig) -> String {
    let sampled = frames.iter().any(|f| f.sampled.is_some());
    let mut t = format!("{label}:\n");
    let _ = write!(
        t,
        "  {:>5} {:>10} {:>10} {:>9} {:>7} {:>10} {:>9} {:>9} {:>10} {:>8}",
        "frame",
        "ref ms",
        "cycle ms",
        "func ms",
        "ratio",
        if sampled { "est cycles" } else { "cycles" },
        "fps",
        "rays/cyc",
        "M rays/s",
        "bound"
    );
    if sampled {
        let _ = write!(t, " {:>9} {:>9}", "95% CI", "timed");
    }
    t.push('\n');
    for f in frames {
        let _ = write!(
            t,
            "  {:>5} {:>10.1} {:>10.1} {:>9.1} {:>7.2} {:>10} {:>9.1} {:>9.3} {:>10.3} {:>8}",
            f.frame,
            f.reference_s * 1e3,
            f.cycle_s * 1e3,
            f.functional_s * 1e3,
            f.cycle_s / f.reference_s.max(1e-9),
            f.cycles,
            f.fps,
            f.rays_per_cycle,
            pixels / f.cycle_s.max(1e-9) / 1e6,
            f.bound
        );
        if let Some(s) = &f.sampled {
            let c = f.cycles.max(1) as f64;
            let _ = write!(
                t,
                " {:>8.2}% {:>8.1}%",
                100.0 * (s.high - s.low) / 2.0 / c,
                100.0 * s.simulated_cycles as f64 / c
            );
        }
        t.push('\n');
    }
    let rs: f64 = frames.iter().map(|f| f.reference_s).sum();
    let cs: f64 = frames.iter().map(|f| f.cycle_s).sum();
    let cy: u64 = frames.iter().map(|f| f.cycles).sum();
    let skipped: u64 = frames.iter().map(|f| f.skipped_cycles).sum();
    // Idle-cycle skipping applies to the cycles simulated clock by clock.
    let simulated: u64 = frames
        .iter()
        .map(|f| f.sampled.map_or(f.cycles, |s| s.simulated_cycles))
        .sum();
    let n = frames.len() as f64;
    let _ = write!(
        t,
        "  total: cycle model / reference wall time {:.2}; {} {:.3} M rays/s, {:.3} M cycles/s; modelled {:.1} fps at {} MHz (slowest frame {:.1}); idle cycles skipped {:.2} % ({skipped} of {simulated} simulated)",
        cs / rs.max(1e-9),
        if sampled { "estimated from a sample:" } else { "simulated" },
        n * pixels / cs.max(1e-9) / 1e6,
        cy as f64 / cs.max(1e-9) / 1e6,
        n * f64::from(hw.clock_mhz) * 1e6 / cy.max(1) as f64,
        hw.clock_mhz,
        frames.iter().map(|f| f.fps).fold(f64::INFINITY, f64::min),
        100.0 * skipped as f64 / simulated.max(1) as f64,
    );
    t
}

/// A line of the walker and DRAM-latency scaling table.
pub fn scaling_line(p: &ScalePoint) -> String {
    format!(
        "  {:<13} {:>6} {:>10} {:>9.1}  {} — {}",
        p.sweep, p.value, p.cycles, p.fps, p.bound, p.reason
    )
}

/// Writes `scaling.csv` and `scaling.png` into `dir`; returns their paths.
pub fn write_scaling(dir: &Path, points: &[ScalePoint], scene: &Scene) -> Result<[PathBuf; 2]> {
    let csv = dir.join("scaling.csv");
    write_whole(&csv, scaling_csv(points).as_bytes())?;
    let (w, h) = scene.file.resolution;
    let img = scaling_plot(
        points,
        &format!("cycles per frame, {w}×{h}, every pixel traced"),
    )
    .map_err(anyhow::Error::msg)?;
    let png = dir.join("scaling.png");
    write_whole(&png, &encode_png(&img)?)?;
    Ok([csv, png])
}
