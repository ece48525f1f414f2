//! The measurements of `sim paper`: every case over the animation, timed by the reference
//! (wall time of the whole animation, best of N runs, the cases' order alternating between
//! runs so that a slow spell of the machine does not fall on one case) and by the cycle model
//! (cycles of every frame, full or sampled timing, frames per second at the hardware clock).
//!
//! Pipeline position: called by [`super::command`]; renders with the models directly (no
//! files, no comparison against the reference: tests/switches.rs and tests/car_static.rs
//! check the images).

use super::cases::{cases, flags, Car, Case, CAR_STATIC_RON};
use crate::models::cycle::runner::CycleRun;
use crate::models::cycle::sample::SampleConfig;
use crate::models::cycle::CycleOptions;
use crate::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use crate::world::assets::{build_assets, effective_depths, Asset, Materialise};
use crate::world::scene::Scene;
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use serde::Serialize;
use std::path::Path;

/// What to measure.
#[derive(Clone, Debug)]
pub struct PaperConfig {
    /// Frames of the animation (the scenes have 48).
    pub frames: u32,
    /// Resolutions, each a full set of cases.
    pub resolutions: Vec<(u32, u32)>,
    /// Reference runs per case (best of N); 0 skips the reference.
    pub repeats: u32,
    /// Run the cycle model.
    pub cycle: bool,
    /// Sampled timing for the cycle model (`None`: every cycle simulated).
    pub sample: Option<SampleConfig>,
    /// The hardware the cycle model runs (`sim paper --hw`; the default without it), checked
    /// against the default datapath by the caller.
    pub hw: HwConfig,
    /// What the table calls that hardware: "default hardware" or the file it came from.
    pub hw_name: String,
}

/// One case at one resolution.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Case id ("a", "a'", "b", "c").
    pub case: String,
    /// What the case is.
    pub label: String,
    /// Its switches as `sim` flags.
    pub flags: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frames rendered.
    pub frames: u32,
    /// Reference: best wall time of the whole animation over the runs, seconds.
    pub reference_best_s: Option<f64>,
    /// Reference: median of the runs, seconds.
    pub reference_median_s: Option<f64>,
    /// Reference: frames per second of the best run.
    pub reference_fps: Option<f64>,
    /// Reference: this case's frame rate over (a)'s (above 1: faster than the static car).
    pub reference_vs_a: Option<f64>,
    /// Walks over the animation (the reference's counter; the same work in every run).
    /// `None` when the reference did not run (`--repeats 0`): the cycle model does not fill it.
    pub walks: Option<u64>,
    /// Pixels reused from the hit buffer over the animation (reference); `None` as `walks`.
    pub reused: Option<u64>,
    /// Cycle model: cycles of the whole animation.
    pub cycles: Option<u64>,
    /// Cycle model: frames per second at the hardware clock (frames / (cycles / clock)).
    pub cycle_fps: Option<f64>,
    /// Cycle model: this case's frame rate over (a)'s.
    pub cycle_vs_a: Option<f64>,
    /// Cycle model: the frames' cycles are sampled estimates (`--sample`).
    pub cycle_sampled: bool,
}

/// A case's scene at `(w, h)` with `frames` frames, its assets built.
struct Built {
    scene: Scene,
    assets: Vec<Asset>,
    half: Vec<f64>,
}

fn build(car: Car, (w, h): (u32, u32), frames: u32) -> Result<Built, String> {
    let mut scene = match car {
        Car::Static => Scene::from_ron(CAR_STATIC_RON, "scenes/car_static.ron", Path::new(".")),
        Car::Animated => Scene::default_car(),
    }
    .map_err(|e| e.to_string())?;
    if (w, h) != scene.file.resolution {
        scene.set_resolution(w, h).map_err(|e| e.to_string())?;
    }
    scene.set_frames(frames).map_err(|e| e.to_string())?;
    let depths = effective_depths(&scene, None).map_err(|e| e.to_string())?;
    let assets = build_assets(&scene, &depths, Materialise::Auto).map_err(|e| e.to_string())?;
    let half = assets.iter().map(|a| a.half_size).collect();
    Ok(Built {
        scene,
        assets,
        half,
    })
}

/// One reference run of the animation: wall time (sum of the frames'), walks, reused pixels.
fn reference_run(b: &Built, opts: RenderOptions) -> Result<(f64, u64, u64), String> {
    let (w, h) = b.scene.file.resolution;
    let mut buf = HitBuffer::new(w, h);
    let (mut secs, mut walks, mut reused) = (0.0, 0, 0);
    for f in 0..b.scene.file.frames {
        let state = b.scene.frame_state(f, &b.half)?;
        let input = FrameInput {
            scene: &b.scene,
            assets: &b.assets,
            state: &state,
        };
        let st = render_frame(&input, &mut buf, opts);
        secs += st.wall_s;
        walks += st.walks;
        reused += st.hit_buffer_reused;
    }
    Ok((secs, walks, reused))
}

/// The cycle model over the animation on `hw`: total cycles.
fn cycle_run(
    b: &Built,
    hw: &HwConfig,
    opts: RenderOptions,
    sample: Option<SampleConfig>,
    progress: &mut dyn FnMut(&str),
    what: &str,
) -> Result<u64, String> {
    let dp = DatapathConfig::default();
    let mut run = CycleRun::new(
        hw,
        &dp,
        &b.assets,
        &b.scene.instance_asset,
        b.scene.file.resolution,
        CycleOptions {
            sample,
            ..CycleOptions::default()
        },
    )
    .map_err(|e| e.to_string())?;
    run.set_switches(opts.ray_switches());
    let mut cycles = 0;
    let frames = b.scene.file.frames;
    for f in 0..frames {
        crate::output::interrupt::check(|| what.to_string(), String::new)
            .map_err(|e| e.to_string())?;
        let state = b.scene.frame_state(f, &b.half)?;
        let input = FrameInput {
            scene: &b.scene,
            assets: &b.assets,
            state: &state,
        };
        let r = run
            .frame(&input, &dp, opts.use_hit_buffer)
            .map_err(|e| format!("{what}, frame {f}: {e}"))?;
        cycles += r.cycles.cycles;
        if f % 8 == 7 || f + 1 == frames {
            progress(&format!("  {what}: cycle model, frame {}/{frames}", f + 1));
        }
    }
    Ok(cycles)
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Runs every case at every resolution; `progress` gets a line per finished step.
pub fn measure(c: &PaperConfig, progress: &mut dyn FnMut(&str)) -> Result<Vec<Row>, String> {
    let clock_hz = f64::from(c.hw.clock_mhz) * 1e6;
    let all = cases();
    let mut rows = Vec::new();
    for &(w, h) in &c.resolutions {
        progress(&format!(
            "{w}x{h}: building the static and the animated car"
        ));
        let stat = build(Car::Static, (w, h), c.frames)?;
        let anim = build(Car::Animated, (w, h), c.frames)?;
        let built = |case: &Case| match case.car {
            Car::Static => &stat,
            Car::Animated => &anim,
        };
        let frames = stat.scene.file.frames;
        // Reference: N rounds over the cases, forwards then backwards.
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); all.len()];
        let mut work: Vec<Option<(u64, u64)>> = vec![None; all.len()];
        for round in 0..c.repeats {
            let order: Vec<usize> = if round % 2 == 0 {
                (0..all.len()).collect()
            } else {
                (0..all.len()).rev().collect()
            };
            for k in order {
                let case = &all[k];
                crate::output::interrupt::check(|| format!("case ({})", case.id), String::new)
                    .map_err(|e| e.to_string())?;
                let (s, walks, reused) = reference_run(built(case), case.options)?;
                times[k].push(s);
                work[k] = Some((walks, reused));
                progress(&format!(
                    "{w}x{h} ({}) {}: reference run {}/{}: {:.3} s for {frames} frames",
                    case.id,
                    case.label,
                    round + 1,
                    c.repeats,
                    s
                ));
            }
        }
        let mut cycles: Vec<Option<u64>> = vec![None; all.len()];
        if c.cycle {
            for (k, case) in all.iter().enumerate() {
                let what = format!("{w}x{h} ({}) {}", case.id, case.label);
                let n = cycle_run(built(case), &c.hw, case.options, c.sample, progress, &what)?;
                progress(&format!(
                    "{what}: {n} cycles, {:.1} fps",
                    f64::from(frames) * clock_hz / n.max(1) as f64
                ));
                cycles[k] = Some(n);
            }
        }
        let best = |k: usize| {
            times[k]
                .iter()
                .copied()
                .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.min(t))))
        };
        let fps_ref = |k: usize| best(k).map(|s| f64::from(frames) / s.max(1e-12));
        let fps_cyc = |k: usize| cycles[k].map(|n| f64::from(frames) * clock_hz / n.max(1) as f64);
        for (k, case) in all.iter().enumerate() {
            rows.push(Row {
                case: case.id.into(),
                label: case.label.into(),
                flags: flags(&case.options),
                width: w,
                height: h,
                frames,
                reference_best_s: best(k),
                reference_median_s: (!times[k].is_empty()).then(|| median(&mut times[k].clone())),
                reference_fps: fps_ref(k),
                reference_vs_a: fps_ref(k).zip(fps_ref(0)).map(|(x, a)| x / a),
                walks: work[k].map(|w| w.0),
                reused: work[k].map(|w| w.1),
                cycles: cycles[k],
                cycle_fps: fps_cyc(k),
                cycle_vs_a: fps_cyc(k).zip(fps_cyc(0)).map(|(x, a)| x / a),
                cycle_sampled: c.cycle && c.sample.is_some(),
            });
        }
    }
    Ok(rows)
}
