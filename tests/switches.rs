//! The paper's §4 optimisations switched off one at a time, and all at once, in each of the
//! three models (issue 27 part 3, docs/paper.md §2): `--no-culling`, `--no-sort`,
//! `--no-early-termination`, `--no-hit-buffer`.
//!
//! - Images do not change: every frame's records (reference: bit for bit; fixed and cycle:
//!   the packed hit-buffer word) equal the default run's, on the animated default car over
//!   three frames (the hit buffer reuses from frame 1 on, so its switch is exercised too).
//! - Each switch changes the work, so a switch accepted and ignored would fail: without
//!   culling every traced ray walks every instance; without sorting or early termination no
//!   ray terminates early and more walks are done; without the hit buffer nothing is reused;
//!   the cycle model takes more cycles with every optimisation off than with all on.
//! - The comparison itself is shown failing: one corrupted word is named by frame and pixel.
//!
//! The oracle is each model's own default run (a separate run from a fresh buffer), which
//! shares no switch logic with what it checks.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::datapath::DatapathConfig;
use std::path::Path;
use svo_sim::models::cycle::runner::CycleRun;
use svo_sim::models::cycle::CycleOptions;
use svo_sim::models::fixed::{render_frame_fixed_with, FixedBuffer};
use svo_sim::models::reference::{render_frame, FrameInput, HitBuffer, RenderOptions};
use svo_sim::world::assets::{build_assets, effective_depths, Asset, Materialise};
use svo_sim::world::scene::Scene;

const W: u32 = 96;
const H: u32 = 64;
const FRAMES: u32 = 3;

/// The default car at W×H, three frames.
fn car() -> (Scene, Vec<Asset>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/car.ron");
    let text = std::fs::read_to_string(&path).expect("scenes/car.ron");
    let text = text.replacen(
        "resolution: (640, 384)",
        &format!("resolution: ({W}, {H})"),
        1,
    );
    let mut scene = Scene::from_ron(&text, "car.ron", path.parent().expect("folder"))
        .unwrap_or_else(|e| panic!("{e}"));
    scene.file.frames = FRAMES;
    assert_eq!(scene.file.resolution, (W, H), "the resolution was replaced");
    let depths = effective_depths(&scene, None).expect("depths");
    let assets = build_assets(&scene, &depths, Materialise::Auto).expect("assets");
    (scene, assets)
}

/// The switch settings under test: each optimisation off alone, then all off.
fn cases() -> Vec<(&'static str, RenderOptions)> {
    let d = RenderOptions::default();
    vec![
        (
            "--no-culling",
            RenderOptions {
                culling: false,
                ..d
            },
        ),
        ("--no-sort", RenderOptions { sort: false, ..d }),
        (
            "--no-early-termination",
            RenderOptions {
                early_termination: false,
                ..d
            },
        ),
        (
            "--no-hit-buffer",
            RenderOptions {
                use_hit_buffer: false,
                ..d
            },
        ),
        ("all four", RenderOptions::NONE),
    ]
}

/// What one run of a model gives per frame: its records as words, walks, early
/// terminations, reused pixels, rays traced (not reused) and, for the cycle model, cycles.
#[derive(Debug, Default)]
struct Frame {
    words: Vec<u128>,
    walks: u64,
    early: u64,
    reused: u64,
    traced: u64,
    cycles: u64,
}

/// The first frame and pixel where `got` differs from `want`, named.
fn first_difference(want: &[Frame], got: &[Frame]) -> Option<String> {
    for (f, (a, b)) in want.iter().zip(got).enumerate() {
        if let Some(p) =
            (0..a.words.len().max(b.words.len())).find(|&p| a.words.get(p) != b.words.get(p))
        {
            return Some(format!(
                "frame {f}, pixel ({}, {}): {:?} by default, {:?} with the switch",
                p as u32 % W,
                p as u32 / W,
                a.words.get(p),
                b.words.get(p)
            ));
        }
    }
    (want.len() != got.len()).then(|| format!("{} frames, {} frames", want.len(), got.len()))
}

/// A reference record as a word of its bits (instance, t, voxel, normals, colour, count).
fn reference_word(r: &svo_sim::models::reference::HitRecord) -> u128 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    use std::hash::{Hash, Hasher};
    (
        r.hit,
        r.spheres.code(),
        r.instance,
        r.t.to_bits(),
        r.voxel,
        r.face_normal.map(f32::to_bits),
        r.shade_normal.map(f32::to_bits),
        r.colour,
    )
        .hash(&mut h);
    // 64 bits of hash beside the t bits: two records differ in the word if they differ at all
    // but for a hash collision of the remaining fields.
    (u128::from(h.finish()) << 64) | u128::from(r.t.to_bits())
}

fn run_reference(scene: &Scene, assets: &[Asset], opts: RenderOptions) -> Vec<Frame> {
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let mut buf = HitBuffer::new(W, H);
    (0..FRAMES)
        .map(|f| {
            let state = scene.frame_state(f, &half).expect("frame state");
            let input = FrameInput {
                scene,
                assets,
                state: &state,
            };
            let st = render_frame(&input, &mut buf, opts);
            Frame {
                words: buf.records.iter().map(reference_word).collect(),
                walks: st.walks,
                early: st.early_terminations,
                reused: st.hit_buffer_reused,
                traced: st.rays - st.hit_buffer_reused,
                cycles: 0,
            }
        })
        .collect()
}

fn run_fixed(scene: &Scene, assets: &[Asset], opts: RenderOptions) -> Vec<Frame> {
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let dp = DatapathConfig::default();
    let mut buf = FixedBuffer::new(W, H);
    (0..FRAMES)
        .map(|f| {
            let state = scene.frame_state(f, &half).expect("frame state");
            let input = FrameInput {
                scene,
                assets,
                state: &state,
            };
            let st = render_frame_fixed_with(&input, &mut buf, &dp, opts)
                .unwrap_or_else(|e| panic!("{e}"));
            Frame {
                words: buf.records.iter().map(|r| r.word).collect(),
                walks: st.walks,
                early: st.early_terminations,
                reused: st.hit_buffer_reused,
                traced: st.rays - st.hit_buffer_reused,
                cycles: 0,
            }
        })
        .collect()
}

/// The cycle model under cross-check (every stage re-executes its arithmetic, including the
/// walk lists the switches make, and compares with the functional model).
fn run_cycle(scene: &Scene, assets: &[Asset], opts: RenderOptions) -> Vec<Frame> {
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let dp = DatapathConfig::default();
    let hw = HwConfig::default();
    let mut run = CycleRun::new(
        &hw,
        &dp,
        assets,
        &scene.instance_asset,
        (W, H),
        CycleOptions {
            cross_check: true,
            ..CycleOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    run.set_switches(opts.ray_switches());
    (0..FRAMES)
        .map(|f| {
            let state = scene.frame_state(f, &half).expect("frame state");
            let input = FrameInput {
                scene,
                assets,
                state: &state,
            };
            let r = run
                .frame(&input, &dp, opts.use_hit_buffer)
                .unwrap_or_else(|e| panic!("frame {f}: {e}"));
            assert_eq!(r.cycles.reused, r.fixed.hit_buffer_reused, "frame {f}");
            assert_eq!(
                r.cycles.early_terminations, r.fixed.early_terminations,
                "frame {f}"
            );
            Frame {
                words: run.buffer().records.iter().map(|r| r.word).collect(),
                walks: r.fixed.walks,
                early: r.fixed.early_terminations,
                reused: r.fixed.hit_buffer_reused,
                traced: r.fixed.rays - r.fixed.hit_buffer_reused,
                cycles: r.cycles.cycles,
            }
        })
        .collect()
}

/// Checks one model: same records under every switch, and the work each switch must change.
fn check_model(name: &str, run: fn(&Scene, &[Asset], RenderOptions) -> Vec<Frame>) {
    let (scene, assets) = car();
    let instances = scene.file.instances.len() as u64;
    let base = run(&scene, &assets, RenderOptions::default());
    let walks = |fr: &[Frame]| fr.iter().map(|f| f.walks).sum::<u64>();
    let early = |fr: &[Frame]| fr.iter().map(|f| f.early).sum::<u64>();
    let reused = |fr: &[Frame]| fr.iter().map(|f| f.reused).sum::<u64>();
    assert!(early(&base) > 0, "{name}: the default run terminates early");
    assert!(reused(&base) > 0, "{name}: the default run reuses pixels");
    for (what, opts) in cases() {
        let got = run(&scene, &assets, opts);
        if let Some(d) = first_difference(&base, &got) {
            panic!("{name} {what}: the image changed at {d}");
        }
        println!(
            "{name} {what}: walks {} (default {}), early terminations {} ({}), reused {} ({}), cycles {} ({})",
            walks(&got),
            walks(&base),
            early(&got),
            early(&base),
            reused(&got),
            reused(&base),
            got.iter().map(|f| f.cycles).sum::<u64>(),
            base.iter().map(|f| f.cycles).sum::<u64>()
        );
        if !opts.culling && !opts.early_termination {
            for (f, fr) in got.iter().enumerate() {
                assert_eq!(
                    fr.walks,
                    fr.traced * instances,
                    "{name} {what}, frame {f}: every traced ray walks every instance"
                );
            }
        }
        if !opts.culling || !opts.sort || !opts.early_termination || !opts.use_hit_buffer {
            assert!(
                walks(&got) > walks(&base),
                "{name} {what}: more walks than by default"
            );
        }
        if !opts.sort || !opts.early_termination {
            assert_eq!(early(&got), 0, "{name} {what}: no early termination");
        }
        if !opts.use_hit_buffer {
            assert_eq!(reused(&got), 0, "{name} {what}: nothing reused");
        }
        if opts == RenderOptions::NONE && name == "cycle" {
            let c = |fr: &[Frame]| fr.iter().map(|f| f.cycles).sum::<u64>();
            assert!(
                c(&got) > c(&base),
                "cycle {what}: more cycles ({}) than with every optimisation ({})",
                c(&got),
                c(&base)
            );
        }
    }
}

#[test]
fn reference_images_do_not_change_with_any_switch() {
    check_model("reference", run_reference);
}

#[test]
fn fixed_images_do_not_change_with_any_switch() {
    check_model("fixed", run_fixed);
}

#[test]
fn cycle_images_do_not_change_with_any_switch() {
    check_model("cycle", run_cycle);
}

/// The comparison fails, naming frame and pixel, when one word of one frame differs.
#[test]
fn a_corrupted_word_is_named_by_frame_and_pixel() {
    let (scene, assets) = car();
    let base = run_fixed(&scene, &assets, RenderOptions::default());
    let mut got = run_fixed(&scene, &assets, RenderOptions::NONE);
    assert_eq!(first_difference(&base, &got), None);
    let p = (5 * W + 7) as usize;
    got[2].words[p] ^= 1 << 9;
    let d = first_difference(&base, &got).expect("a difference");
    assert!(d.starts_with("frame 2, pixel (7, 5): "), "{d}");
}
