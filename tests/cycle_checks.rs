//! The cycle model's checks against the functional model's trace, each shown failing: a
//! frame runs with one field of the trace corrupted (through the test hook
//! `CycleRun::frame_with_corrupt_trace`) and must stop with exactly the disagreement named, at
//! the corrupted pixel. The checks are those of docs/cycle-model.md §2.4 — the decisions the
//! cycle model makes itself (reuse, early termination), the cross-check's re-executed
//! arithmetic (sort, walk), and the hit buffer compared word for word after the frame.
//!
//! Without `cross_check` the cycle model times a walk's recorded ops without re-executing
//! them, so a walk's step count or node address changed in the trace changes only its timing;
//! those two are shown failing under cross-check, which re-executes every walk.

use rtl_model::cycle::hw_config::HwConfig;
use rtl_model::cycle::walk_op::WalkOp;
use rtl_model::datapath::DatapathConfig;
use rtl_model::svo::FetchKind;
use svo_sim::models::cycle::runner::{CycleRun, CycleRunError};
use svo_sim::models::cycle::{CycleError, CycleOptions};
use svo_sim::models::fixed::trace::RowTrace;
use svo_sim::models::reference::FrameInput;
use svo_sim::world::assets::{build_assets, effective_depths, Asset, Materialise};
use svo_sim::world::scene::Scene;

const W: u32 = 64;
const H: u32 = 40;

fn car() -> (Scene, Vec<Asset>) {
    let mut scene = Scene::default_car().unwrap();
    scene.set_resolution(W, H).unwrap();
    scene.set_frames(2).unwrap();
    let depths = effective_depths(&scene, Some(7)).unwrap();
    let assets = build_assets(&scene, &depths, Materialise::Auto).unwrap();
    (scene, assets)
}

/// Frames 0 to `frame` of the car, the trace of `frame` passed through `corrupt`; the cycle
/// model's result for that frame.
fn run_frame(
    cross_check: bool,
    frame: u32,
    corrupt: &mut dyn FnMut(usize, &mut RowTrace),
) -> Result<(), CycleRunError> {
    let (scene, assets) = car();
    let half: Vec<f64> = assets.iter().map(|a| a.half_size).collect();
    let dp = DatapathConfig::default();
    let opts = CycleOptions {
        cross_check,
        ..CycleOptions::default()
    };
    let hw = HwConfig::default();
    let mut run = CycleRun::new(&hw, &dp, &assets, &scene.instance_asset, (W, H), opts).unwrap();
    for f in 0..=frame {
        let state = scene.frame_state(f, &half).unwrap();
        let input = FrameInput {
            scene: &scene,
            assets: &assets,
            state: &state,
        };
        if f < frame {
            run.frame(&input, &dp, true).unwrap();
        } else {
            run.frame_with_corrupt_trace(&input, &dp, true, corrupt)?;
        }
    }
    Ok(())
}

/// Frame 0 with its trace passed through `corrupt`.
fn run(
    cross_check: bool,
    corrupt: &mut dyn FnMut(usize, &mut RowTrace),
) -> Result<(), CycleRunError> {
    run_frame(cross_check, 0, corrupt)
}

/// Whether the first walk of pixel `i` has an op that `is` accepts.
fn first_walk_has(r: &RowTrace, i: usize, is: fn(WalkOp) -> bool) -> Option<usize> {
    let p = r.pixels[i];
    if p.walk_len == 0 {
        return None;
    }
    let w = r.walks[p.walk_start as usize];
    (w.op_start as usize..(w.op_start + w.op_len) as usize).find(|&k| is(WalkOp::unpack(r.ops[k])))
}

fn is_issue(op: WalkOp) -> bool {
    matches!(op, WalkOp::Issue(_))
}

fn is_node_read(op: WalkOp) -> bool {
    matches!(op, WalkOp::Read(FetchKind::Node, _))
}

/// Where the corruption landed: (column, row), once the trace has been read.
type Corrupted = std::rc::Rc<std::cell::Cell<Option<(u32, u32)>>>;

/// Corrupts, with `f`, the first pixel (in raster order) that `pick` accepts; returns its
/// (column, row) once the run is over. `f` gets the row and the pixel's column.
fn first_where(
    pick: impl Fn(&RowTrace, usize) -> bool,
    f: impl Fn(&mut RowTrace, usize),
) -> (impl FnMut(usize, &mut RowTrace), Corrupted) {
    let at = std::rc::Rc::new(std::cell::Cell::new(None));
    let seen = at.clone();
    let corrupt = move |j: usize, row: &mut RowTrace| {
        if seen.get().is_some() {
            return;
        }
        if let Some(i) = (0..row.pixels.len()).find(|&i| pick(row, i)) {
            f(row, i);
            seen.set(Some((i as u32, j as u32)));
        }
    };
    (corrupt, at)
}

/// The run must fail with a disagreement at `at` whose message contains `what`.
fn expect_mismatch(
    r: Result<(), CycleRunError>,
    at_frame: u32,
    at: Option<(u32, u32)>,
    what: &str,
) {
    let (ci, cj) = at.expect("the trace had no pixel to corrupt");
    match r {
        Err(CycleRunError::Cycle(CycleError::Mismatch {
            frame,
            i,
            j,
            what: msg,
        })) => {
            println!("failed as expected: frame {frame}, pixel ({i}, {j}): {msg}");
            assert_eq!(
                (frame, i, j),
                (at_frame, ci, cj),
                "disagreement at another pixel: {msg}"
            );
            assert!(msg.contains(what), "expected \"{what}\", got \"{msg}\"");
        }
        Err(e) => panic!("expected the disagreement \"{what}\" at ({ci}, {cj}), got: {e}"),
        Ok(()) => panic!("the corrupted trace at ({ci}, {cj}) was accepted"),
    }
}

/// The hook itself changes nothing: an untouched trace passes, with and without cross-check.
#[test]
fn an_untouched_trace_passes() {
    for cross in [false, true] {
        run(cross, &mut |_, _| {}).unwrap_or_else(|e| panic!("cross-check {cross}: {e}"));
    }
}

/// A ray's walk count (early termination): one walk fewer in the trace than the functional
/// model did. The cycle model decides early termination itself and wants the walk.
#[test]
fn a_walk_count_corrupted_is_caught() {
    let (mut c, at) = first_where(
        |r, i| r.pixels[i].walk_len >= 2,
        |r, i| r.pixels[i].walk_len -= 1,
    );
    let res = run(false, &mut c);
    expect_mismatch(res, 0, at.get(), "wanted here, the functional model did");
}

/// A walk's step count: the first issue run of a walk one slot longer. Under cross-check the
/// walker stage re-executes the walk and compares its ops.
#[test]
fn a_walk_step_count_corrupted_is_caught_by_cross_check() {
    let expected = std::rc::Rc::new(std::cell::RefCell::new(String::new()));
    let exp = expected.clone();
    let (mut c, at) = first_where(
        |r, i| first_walk_has(r, i, is_issue).is_some(),
        move |r, i| {
            if let Some(k) = first_walk_has(r, i, is_issue) {
                if let WalkOp::Issue(n) = WalkOp::unpack(r.ops[k]) {
                    r.ops[k] = WalkOp::Issue(n + 1).pack();
                    let op = k - r.walks[r.pixels[i].walk_start as usize].op_start as usize;
                    *exp.borrow_mut() = format!(
                        "op {op}: Some(Issue({n})) here, Some(Issue({})) in the functional model",
                        n + 1
                    );
                }
            }
        },
    );
    let res = run(true, &mut c);
    expect_mismatch(res, 0, at.get(), &expected.borrow());
}

/// A node address: the first node read of a walk one word further on.
#[test]
fn a_node_address_corrupted_is_caught_by_cross_check() {
    let (mut c, at) = first_where(
        |r, i| first_walk_has(r, i, is_node_read).is_some(),
        |r, i| {
            if let Some(k) = first_walk_has(r, i, is_node_read) {
                if let WalkOp::Read(kind, a) = WalkOp::unpack(r.ops[k]) {
                    r.ops[k] = WalkOp::Read(kind, a + 1).pack();
                }
            }
        },
    );
    let res = run(true, &mut c);
    expect_mismatch(res, 0, at.get(), "here, Some(Read(Node, ");
}

/// A candidate order: the first two candidates of a ray swapped. Under cross-check the sorter
/// stage sorts the ray's own sphere hits and compares.
#[test]
fn a_candidate_order_corrupted_is_caught_by_cross_check() {
    let (mut c, at) = first_where(
        |r, i| {
            let p = r.pixels[i];
            let s = p.cand_start as usize;
            p.cand_len >= 2 && r.candidates[s] != r.candidates[s + 1]
        },
        |r, i| {
            let s = r.pixels[i].cand_start as usize;
            r.candidates.swap(s, s + 1);
        },
    );
    let res = run(true, &mut c);
    expect_mismatch(res, 0, at.get(), "sorted candidates");
}

/// A hit-buffer word: in frame 1 (the camera still), the word of a reused pixel with its low
/// bit flipped — the check stage takes the word from its own hit buffer. The hit buffer is
/// compared word for word after the frame.
#[test]
fn a_hit_buffer_word_corrupted_is_caught() {
    let (mut c, at) = first_where(|r, i| r.pixels[i].reused, |r, i| r.words[i] ^= 1);
    let res = run_frame(false, 1, &mut c);
    expect_mismatch(res, 1, at.get(), "hit-buffer word");
}

/// A walked ray's hit-buffer word: under cross-check the record stage packs its own record,
/// so the corrupted trace word differs from the BRAM's after the frame.
#[test]
fn a_walked_rays_word_corrupted_is_caught_by_cross_check() {
    let (mut c, at) = first_where(|r, i| r.pixels[i].walk_len >= 1, |r, i| r.words[i] ^= 1);
    let res = run(true, &mut c);
    expect_mismatch(res, 0, at.get(), "hit-buffer word");
}

/// The reuse decision: a pixel of frame 0 marked reused in the trace. The check stage
/// decides reuse from its own BRAM and the host's dirty flags.
#[test]
fn a_reuse_flag_corrupted_is_caught() {
    let (mut c, at) = first_where(
        |r, i| r.pixels[i].cand_len >= 1,
        |r, i| r.pixels[i].reused = true,
    );
    let res = run(false, &mut c);
    expect_mismatch(res, 0, at.get(), "hit-buffer reuse false here, true");
}
