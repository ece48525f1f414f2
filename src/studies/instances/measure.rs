//! The study's measurements: modelled frame rate against instance count for the flat and the
//! two-level scheme (cycle model), the functional models' speed, and the hit buffer's reuse.
//!
//! Pipeline position: `sim instances` (`super::command`) calls these; each builds its scene
//! (`super::scene`), elaborates it as `sim` would, and runs the models.

use super::scene::CrowdCase;
use crate::models::cycle::runner::CycleRun;
use crate::models::cycle::CycleOptions;
use crate::models::fixed::cull::render_frame_fixed_two_level;
use crate::models::fixed::{render_frame_fixed, FixedBuffer};
use crate::models::reference::{
    render_frame, render_frame_two_level, FrameInput, HitBuffer, RenderOptions,
};
use crate::run::elaborate::elaborate;
use crate::world::assets::{build_assets, effective_depths, Asset, Materialise};
use crate::world::scene::{FrameState, Scene};
use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use rtl_model::units::tile_list::{bram36_count, TileListConfig};
use serde::Serialize;
use std::sync::atomic::AtomicU64;

/// One point of the frame-rate table.
#[derive(Clone, Debug, Serialize)]
pub struct FpsPoint {
    /// Instances.
    pub n: u32,
    /// "still" or "moving" camera.
    pub camera: &'static str,
    /// "flat" or "two-level".
    pub scheme: &'static str,
    /// Cycles of the measured frame (frame 1: after the first, so a still camera reuses).
    pub cycles: u64,
    /// Frames per second at the clock.
    pub fps: f64,
    /// The limit that holds, as the cycle model reports it (or the sphere-lane bound).
    pub bound: String,
    /// Whether the cycle model ran this point (false: the flat sphere-lane bound of §6).
    pub simulated: bool,
    /// Sphere tests per ray (functional model).
    pub tests_per_ray: f64,
    /// Cycles the sphere lanes are occupied for in the frame (Σ over rays of the passes).
    pub lane_cycles: u64,
    /// Hit-buffer reuse of the frame.
    pub reuse: f64,
    /// Whether the elaborated pipeline (with the list memory) fits the XCVU9P.
    pub fits: bool,
    /// DSP48E2, BRAM36, URAM288 of the elaborated pipeline (list memory included).
    pub resources: (u64, u64, u64),
}

/// A built study scene.
pub struct Built {
    /// The scene.
    pub scene: Scene,
    /// Its assets.
    pub assets: Vec<Asset>,
    /// Frame states 0 and 1.
    pub states: Vec<FrameState>,
}

/// Builds `case`'s scene, assets and frame states.
pub fn build(case: &CrowdCase) -> Result<Built, String> {
    let scene = case.scene()?;
    let depths = effective_depths(&scene, None).map_err(|e| e.to_string())?;
    let assets = build_assets(&scene, &depths, Materialise::Auto).map_err(|e| e.to_string())?;
    let halves: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let states = (0..scene.file.frames)
        .map(|f| scene.frame_state(f, &halves))
        .collect::<Result<_, _>>()?;
    Ok(Built {
        scene,
        assets,
        states,
    })
}

/// Runs the cycle model over both frames with `tl` (or flat) and returns frame 1's point.
fn cycle_point(
    b: &Built,
    hw: &HwConfig,
    dp: &DatapathConfig,
    use_hb: bool,
    tl: Option<TileListConfig>,
) -> Result<(u64, f64, String, f64, f64), String> {
    let mut run = CycleRun::new(
        hw,
        dp,
        &b.assets,
        &b.scene.instance_asset,
        b.scene.file.resolution,
        CycleOptions::default(),
    )
    .map_err(|e| e.to_string())?;
    run.set_two_level(tl);
    let mut last = None;
    for st in &b.states {
        let input = FrameInput {
            scene: &b.scene,
            assets: &b.assets,
            state: st,
        };
        last = Some(run.frame(&input, dp, use_hb).map_err(|e| e.to_string())?);
    }
    let r = last.ok_or("no frame")?;
    let rays = r.fixed.rays.max(1) as f64;
    Ok((
        r.cycles.cycles,
        r.cycles.fps_at_clock,
        r.cycles.bound.limit.clone(),
        r.fixed.sphere_tests as f64 / rays,
        r.fixed.hit_buffer_reused as f64 / rays,
    ))
}

/// Σ over the rays of frame 1 of ⌈list / lanes⌉ (at least 1): the sphere lanes' busy cycles
/// with the lists of `tl` (the same lists the run installs).
fn two_level_lane_cycles(b: &Built, dp: &DatapathConfig, tl: &TileListConfig, lanes: u32) -> u64 {
    use crate::models::fixed::cull::fixed_bin_spheres;
    use crate::models::reference::cull::TileLists;
    let st = &b.states[b.states.len() - 1];
    let (w, h) = b.scene.file.resolution;
    let input = FrameInput {
        scene: &b.scene,
        assets: &b.assets,
        state: st,
    };
    let lists = TileLists::build(&st.camera, w, h, tl.tile, &fixed_bin_spheres(&input, dp));
    (0..w * h)
        .map(|p| {
            u64::from(rtl_model::units::tile_list::passes(
                lists.list(p).len() as u32,
                lanes,
            ))
        })
        .sum()
}

/// The limit to name: the sphere lanes when they take more than one cycle a ray on average
/// and are busy for at least 90 % of the frame's cycles (the cycle model's own classification
/// does not consider them), else the model's (at one cycle a ray the lanes keep up with the
/// clock, which is the model's `clock` limit).
fn bound_name(lane_cycles: u64, cycles: u64, rays: u64, model: &str) -> String {
    if lane_cycles > rays && lane_cycles * 10 >= cycles * 9 {
        format!(
            "sphere lanes ({:.2} cycles a ray)",
            lane_cycles as f64 / rays.max(1) as f64
        )
    } else {
        model.to_string()
    }
}

/// The flat and two-level points of one scene; the flat cycle model runs only up to
/// `flat_limit` instances, beyond which its sphere lanes bound the frame (docs/instances.md
/// §8): at least rays × ⌈n / lanes⌉ cycles, and no fewer than the two-level frame, whose walks
/// are the same.
pub fn fps_points(case: &CrowdCase, flat_limit: u32) -> Result<Vec<FpsPoint>, String> {
    let b = build(case)?;
    let dp = DatapathConfig::default();
    let hw = HwConfig::for_datapath(&dp);
    let e = elaborate(&b.scene, None, &hw, &dp, true).map_err(|e| e.to_string())?;
    let (ehw, edp, use_hb) = (&e.hardware, &e.datapath, e.use_hit_buffer);
    let res = ehw.resources(edp)?;
    let (w, h) = case.size;
    let rays = u64::from(w) * u64::from(h);
    let list_bram = e
        .two_level
        .map_or(0, |tl| bram36_count(&tl, ehw.sphere_units, w, h));
    let used = (
        res.used.dsp48e2,
        res.used.bram36 + list_bram,
        res.used.uram288,
    );
    let fits = used.0 <= res.available.dsp48e2
        && used.1 <= res.available.bram36
        && used.2 <= res.available.uram288;
    let camera = if case.moving_camera {
        "moving"
    } else {
        "still"
    };
    let lanes = u64::from(ehw.sphere_units.max(1));
    let flat_lanes = rays * u64::from(case.n).div_ceil(lanes);
    let clock = f64::from(ehw.clock_mhz) * 1e6;
    let point = |scheme,
                 (cycles, fps, bound, tests, reuse): (u64, f64, String, f64, f64),
                 lane_cycles,
                 simulated| FpsPoint {
        n: case.n,
        camera,
        scheme,
        cycles,
        fps,
        bound: bound_name(lane_cycles, cycles, rays, &bound),
        simulated,
        tests_per_ray: tests,
        lane_cycles,
        reuse,
        fits,
        resources: used,
    };
    let mut out = Vec::new();
    let two = match e.two_level {
        Some(tl) => Some((
            cycle_point(&b, ehw, edp, use_hb, Some(tl))?,
            two_level_lane_cycles(&b, edp, &tl, ehw.sphere_units),
        )),
        None => None,
    };
    if case.n <= flat_limit || two.is_none() {
        out.push(point(
            "flat",
            cycle_point(&b, ehw, edp, use_hb, None)?,
            flat_lanes,
            true,
        ));
    } else if let Some(((c2, _, _, _, r), _)) = &two {
        // Not simulated: the lanes' occupancy bounds the frame from below, and so does the
        // two-level frame (the same walks, fewer lane cycles).
        let c = flat_lanes.max(*c2);
        out.push(point(
            "flat",
            (
                c,
                clock / c as f64,
                "sphere lanes".into(),
                f64::from(case.n),
                *r,
            ),
            flat_lanes,
            false,
        ));
    }
    match two {
        Some((t, lc)) => out.push(point("two-level", t, lc, true)),
        None => {
            // Left out by elaboration (n ≤ lanes): the pipeline is the flat one.
            let mut p = out[0].clone();
            p.scheme = "two-level";
            p.bound = format!("{} (lists left out: n ≤ lanes)", p.bound);
            out.push(p);
        }
    }
    Ok(out)
}

/// Rays per second of the reference and the functional model, flat and two-level, on frame 0
/// of `case` traced in full (no reuse).
#[derive(Clone, Debug, Serialize)]
pub struct SpeedRow {
    /// Instances.
    pub n: u32,
    /// Reference, flat.
    pub reference_flat: f64,
    /// Reference, two-level.
    pub reference_two_level: f64,
    /// Functional model, flat.
    pub fixed_flat: f64,
    /// Functional model, two-level.
    pub fixed_two_level: f64,
}

/// The default datapath with 16-bit instance ids in the hit record, so that the fixed models
/// can name every instance of the largest crowd (10,000) without an id overflow.
fn wide_ids_datapath() -> DatapathConfig {
    DatapathConfig {
        hit_record: rtl_model::units::hit_record::HitRecordConfig {
            instance_bits: 16,
            ..Default::default()
        },
        ..DatapathConfig::default()
    }
}

/// Measures [`SpeedRow`] (best of `reps`).
pub fn speed(case: &CrowdCase, reps: u32) -> Result<SpeedRow, String> {
    let b = build(case)?;
    let (w, h) = case.size;
    let rays = f64::from(w) * f64::from(h);
    let dp = wide_ids_datapath();
    let tl = TileListConfig::default();
    let input = FrameInput {
        scene: &b.scene,
        assets: &b.assets,
        state: &b.states[0],
    };
    let no_hb = RenderOptions {
        use_hit_buffer: false,
        ..RenderOptions::default()
    };
    let mut best = [f64::INFINITY; 4];
    for _ in 0..reps.max(1) {
        let mut rb = HitBuffer::new(w, h);
        best[0] = best[0].min(render_frame(&input, &mut rb, no_hb).wall_s);
        let mut rb = HitBuffer::new(w, h);
        let st = render_frame_two_level(&input, &mut rb, no_hb, tl.tile, &AtomicU64::new(0));
        best[1] = best[1].min(st.wall_s);
        let mut fb = FixedBuffer::new(w, h);
        let st = render_frame_fixed(&input, &mut fb, &dp, false).map_err(|e| e.to_string())?;
        best[2] = best[2].min(st.wall_s);
        let mut fb = FixedBuffer::new(w, h);
        let (st, _) = render_frame_fixed_two_level(&input, &mut fb, &dp, false, &tl, 8)
            .map_err(|e| e.to_string())?;
        best[3] = best[3].min(st.wall_s);
    }
    let r = |s: f64| rays / s.max(1e-9);
    Ok(SpeedRow {
        n: case.n,
        reference_flat: r(best[0]),
        reference_two_level: r(best[1]),
        fixed_flat: r(best[2]),
        fixed_two_level: r(best[3]),
    })
}

/// Hit-buffer reuse of frame 1 with a still camera (reference, two-level: the same decisions
/// as every model, `tests/two_level.rs`).
pub fn reuse(case: &CrowdCase) -> Result<f64, String> {
    let b = build(case)?;
    let (w, h) = case.size;
    let mut buf = HitBuffer::new(w, h);
    let mut last = 0.0;
    for st in &b.states {
        let input = FrameInput {
            scene: &b.scene,
            assets: &b.assets,
            state: st,
        };
        let s = render_frame_two_level(
            &input,
            &mut buf,
            RenderOptions::default(),
            16,
            &AtomicU64::new(0),
        );
        last = s.hit_buffer_reused as f64 / s.rays.max(1) as f64;
    }
    Ok(last)
}

/// The host's binning of one frame: list entries, the longest list, padded words (8 ids a
/// word), the time the f64 binning takes on this machine (best of 5), and the memory's
/// BRAM36.
#[derive(Clone, Debug, Serialize)]
pub struct BinRow {
    /// Instances.
    pub n: u32,
    /// List entries (all tiles).
    pub entries: u64,
    /// Mean list length over the tiles.
    pub mean_len: f64,
    /// The longest list.
    pub max_len: u32,
    /// Padded 8-id words.
    pub words: u64,
    /// Tiles that overflowed the default memory (flat tiles).
    pub flat_tiles: u32,
    /// Host time to bin, microseconds (best of 5).
    pub host_us: f64,
    /// Bytes the host writes per frame.
    pub host_bytes: u64,
}

/// Measures [`BinRow`] on frame 0 of `case` with the default list memory.
pub fn binning(case: &CrowdCase) -> Result<BinRow, String> {
    use crate::models::fixed::cull::{fixed_bin_spheres, install_lists};
    use crate::models::fixed::plan::FramePlan;
    use crate::models::reference::cull::TileLists;
    let b = build(case)?;
    let (w, h) = case.size;
    let dp = wide_ids_datapath();
    let tl = TileListConfig::default();
    let input = FrameInput {
        scene: &b.scene,
        assets: &b.assets,
        state: &b.states[0],
    };
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = std::time::Instant::now();
        let spheres = fixed_bin_spheres(&input, &dp);
        let lists = TileLists::build(&b.states[0].camera, w, h, tl.tile, &spheres);
        best = best.min(t.elapsed().as_secs_f64());
        std::hint::black_box(lists);
    }
    let mut fb = FixedBuffer::new(w, h);
    let mut ov = rtl_model::datapath::overflow_table();
    let mut plan =
        FramePlan::new(&input, &mut fb, &dp, false, &mut ov).map_err(|e| e.to_string())?;
    let u = install_lists(&mut plan, &input, &tl, 8);
    Ok(BinRow {
        n: case.n,
        entries: u.entries,
        mean_len: u.entries as f64 / f64::from(u.tiles.max(1)),
        max_len: u.max_len,
        words: u.words,
        flat_tiles: u.flat_tiles,
        host_us: best * 1e6,
        host_bytes: rtl_model::units::tile_list::host_bytes(&tl, 8, u.words, w, h),
    })
}
