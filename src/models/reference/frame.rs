//! One frame of the reference: every pixel's ray through sphere tests, sort, hit-buffer
//! check, transform and walk, with early termination. Rows run in parallel; the result and
//! the counters do not depend on the thread count.

use super::cull::{reference_keep_radius, BinSphere, TileLists};
use super::hit_buffer::{Dirty, HitBuffer};
use super::octree::Octree;
use super::ray::{primary_ray, Ray};
use super::record::{HitRecord, SphereCount};
use super::sphere::sphere_entry;
use super::stats::FrameStats;
use super::walk::{walk, WalkCounters, WalkHit};
use crate::world::assets::{Asset, AssetTree};
use crate::world::scene::{FrameState, Pose, Scene};
use glam::{DMat3, DVec3};
use rayon::prelude::*;
use rtl_model::svo::LeafAttr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// Switches of the renderer: the paper's §4 optimisations, each of which can be switched off
/// to measure what it saves (`sim paper`, docs/paper.md). None of them changes an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Reuse unchanged pixels through the hit buffer.
    pub use_hit_buffer: bool,
    /// Walk candidates front to back and stop once the nearest hit is certain. Needs `sort`:
    /// without a front-to-back order no candidate is certain to be behind the best hit, so
    /// with `sort` off every candidate is walked whatever this says.
    pub early_termination: bool,
    /// Drop the instances whose bounding sphere the ray misses. Off: every instance is a
    /// candidate and is walked. The sphere tests still run: their count is the record's
    /// "nature of the hit" and the hit buffer's reuse condition, and their entry distance the
    /// sort key; an instance whose sphere is missed has no entry (+∞): it sorts after every
    /// pierced one, and early termination skips it once a hit is found.
    pub culling: bool,
    /// Order the candidates front to back by entry distance. Off: candidates are walked in
    /// instance order (and early termination cannot apply).
    pub sort: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            use_hit_buffer: true,
            early_termination: true,
            culling: true,
            sort: true,
        }
    }
}

impl RenderOptions {
    /// Every §4 optimisation off: the paper's case (b).
    pub const NONE: Self = Self {
        use_hit_buffer: false,
        early_termination: false,
        culling: false,
        sort: false,
    };

    /// The per-ray switches (everything but the hit buffer, which works across frames).
    pub fn ray_switches(&self) -> RaySwitches {
        RaySwitches {
            culling: self.culling,
            sort: self.sort,
            early_termination: self.early_termination,
        }
    }
}

/// The per-ray switches of [`RenderOptions`] as the fixed-point and cycle models take them
/// (their hit-buffer switch is a separate argument, as it has always been).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RaySwitches {
    /// [`RenderOptions::culling`].
    pub culling: bool,
    /// [`RenderOptions::sort`].
    pub sort: bool,
    /// [`RenderOptions::early_termination`].
    pub early_termination: bool,
}

impl Default for RaySwitches {
    fn default() -> Self {
        RenderOptions::default().ray_switches()
    }
}

impl RaySwitches {
    /// Whether early termination can stop a ray: asked for, and the candidates in order.
    pub fn terminates(&self) -> bool {
        self.early_termination && self.sort
    }
}

/// What a frame needs: the scene (resolution, instance → asset), assets and the frame state.
pub struct FrameInput<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// Built assets, in scene order.
    pub assets: &'a [Asset],
    /// Camera and poses of this frame.
    pub state: &'a FrameState,
}

/// Per-instance constants of a frame.
struct Inst<'a> {
    pose: Pose,
    radius: f64,
    tree: &'a AssetTree,
    /// World-from-local rotation divided by the scale, for shading normals (inverse transpose
    /// of R·S applied to an asset-space normal).
    normal_to_world: DMat3,
}

/// Constants of one frame shared by all rows.
struct FrameCtx<'a> {
    insts: Vec<Inst<'a>>,
    dirty: Dirty,
    opts: RenderOptions,
    /// The two-level scheme's per-tile lists, when used (`cull.rs`).
    lists: Option<TileLists>,
}

/// Per-row scratch and counters (one per worker task, merged at the end).
#[derive(Default)]
struct RowState {
    cands: Vec<(f64, u16)>,
    st: FrameStats,
    wc: WalkCounters,
}

/// Walks either kind of asset tree; returns the hit with its leaf attributes.
#[inline]
fn walk_any(
    tree: &AssetTree,
    half: DVec3,
    o: DVec3,
    d: DVec3,
    wc: &mut WalkCounters,
) -> Option<(WalkHit<()>, LeafAttr)> {
    fn resolve<T: Octree>(t: &T, h: WalkHit<T::Leaf>) -> (WalkHit<()>, LeafAttr) {
        let attr = t.attr(h.attr);
        (
            WalkHit {
                t: h.t,
                voxel: h.voxel,
                level: h.level,
                attr: (),
                face_normal: h.face_normal,
            },
            attr,
        )
    }
    match tree {
        AssetTree::Image(img) => walk(img, half, o, d, wc).map(|h| resolve(img, h)),
        AssetTree::Implicit(sdf) => walk(sdf, half, o, d, wc).map(|h| resolve(sdf, h)),
    }
}

/// Traces one ray. `prev` is the pixel's last record; reuse only if allowed.
fn trace(ray: &Ray, p: u32, ctx: &FrameCtx<'_>, prev: &HitRecord, row: &mut RowState) -> HitRecord {
    let FrameCtx {
        insts,
        dirty,
        opts,
        lists,
    } = ctx;
    let opts = *opts;
    let RowState { cands, st, wc } = row;
    cands.clear();
    let mut test = |i: usize, inst: &Inst<'_>| {
        if let Some(t) = sphere_entry(ray.origin, ray.dir, inst.pose.centre, inst.radius) {
            cands.push((t, i as u16));
        }
    };
    let tested = match lists {
        // Two-level: only this tile's instances, ascending, so the candidates come out in
        // the same order as from the flat loop.
        Some(l) => {
            let list = l.list(p);
            for &i in list {
                test(usize::from(i), &insts[usize::from(i)]);
            }
            list.len()
        }
        None => {
            for (i, inst) in insts.iter().enumerate() {
                test(i, inst);
            }
            insts.len()
        }
    };
    st.sphere_tests += tested as u64;
    st.spheres_culled += (tested - cands.len()) as u64;
    let pierced = cands.len();
    let spheres = SphereCount::from_count(pierced);
    if !opts.culling && pierced < insts.len() {
        // No culling: every instance is a candidate; one whose sphere the ray misses has no
        // entry distance (+∞) and comes after the pierced ones, in instance order.
        let mut k = 0;
        for i in 0..insts.len() as u16 {
            if cands.get(k).is_some_and(|c| c.1 == i) {
                k += 1;
            } else {
                cands.push((f64::INFINITY, i));
            }
        }
    }
    if cands.is_empty() {
        return HitRecord::MISS;
    }
    if opts.use_hit_buffer && !dirty.camera && pierced == 1 {
        // The one pierced sphere: the only one with a finite entry.
        let i = cands[0].1;
        if !dirty.instances[usize::from(i)] && (!prev.hit || prev.instance == i) {
            st.hit_buffer_reused += 1;
            st.hits += u64::from(prev.hit);
            return HitRecord { spheres, ..*prev };
        }
    }
    st.candidates += cands.len() as u64;
    st.candidates_max = st.candidates_max.max(cands.len() as u32);
    if opts.sort {
        // Front to back by entry distance; ties by instance index (insertion sort: stable,
        // and the candidate lists are short).
        for k in 1..cands.len() {
            let mut j = k;
            while j > 0 && cands[j - 1].0 > cands[j].0 {
                cands.swap(j - 1, j);
                j -= 1;
            }
        }
    } else if !opts.culling {
        // Instance order (the pierced ones were listed first above).
        cands.sort_unstable_by_key(|c| c.1);
    }
    let terminates = opts.ray_switches().terminates();
    let mut best = HitRecord {
        spheres,
        ..HitRecord::MISS
    };
    for (k, &(t_enter, i)) in cands.iter().enumerate() {
        if terminates && best.hit && best.t <= t_enter {
            st.early_terminations += 1;
            st.walks_skipped += (cands.len() - k) as u64;
            break;
        }
        let inst = &insts[usize::from(i)];
        let r = inst.pose.world_from_local;
        // Eq. 3: d' = Rᵀ d, o' = Rᵀ (o − c); scale stays in the box extents (§3.2).
        let rel = ray.origin - inst.pose.centre;
        let o_local = DVec3::new(r.x_axis.dot(rel), r.y_axis.dot(rel), r.z_axis.dot(rel));
        let d_local = DVec3::new(
            r.x_axis.dot(ray.dir),
            r.y_axis.dot(ray.dir),
            r.z_axis.dot(ray.dir),
        );
        st.walks += 1;
        if let Some((h, attr)) = walk_any(inst.tree, inst.pose.half_extent, o_local, d_local, wc) {
            if !best.hit || h.t < best.t {
                let n =
                    (inst.normal_to_world * DVec3::from_array(attr.normal())).normalize_or_zero();
                best = HitRecord {
                    hit: true,
                    spheres,
                    instance: i,
                    t: h.t,
                    voxel: h.voxel,
                    face_normal: (r * h.face_normal).as_vec3().to_array(),
                    shade_normal: n.as_vec3().to_array(),
                    colour: attr.rgba(),
                };
            }
        }
    }
    st.hits += u64::from(best.hit);
    best
}

/// Renders one frame into `buffer` (which holds the previous frame's records on entry).
pub fn render_frame(
    input: &FrameInput<'_>,
    buffer: &mut HitBuffer,
    opts: RenderOptions,
) -> FrameStats {
    render_frame_with_progress(input, buffer, opts, &AtomicU64::new(0))
}

/// [`render_frame`] with the two-level scheme: per-tile instance lists of `tile`-pixel tiles
/// select each ray's sphere tests (`cull.rs`); the records are the flat scheme's.
pub fn render_frame_two_level(
    input: &FrameInput<'_>,
    buffer: &mut HitBuffer,
    opts: RenderOptions,
    tile: u32,
    rows_done: &AtomicU64,
) -> FrameStats {
    render_frame_inner(input, buffer, opts, Some(tile), rows_done)
}

/// [`render_frame`], adding one to `rows_done` as each image row completes (for progress
/// display from another thread).
pub fn render_frame_with_progress(
    input: &FrameInput<'_>,
    buffer: &mut HitBuffer,
    opts: RenderOptions,
    rows_done: &AtomicU64,
) -> FrameStats {
    render_frame_inner(input, buffer, opts, None, rows_done)
}

fn render_frame_inner(
    input: &FrameInput<'_>,
    buffer: &mut HitBuffer,
    opts: RenderOptions,
    tile: Option<u32>,
    rows_done: &AtomicU64,
) -> FrameStats {
    let start = Instant::now();
    let (w, h) = input.scene.file.resolution;
    debug_assert_eq!((buffer.width, buffer.height), (w, h));
    let insts: Vec<Inst<'_>> = input
        .state
        .poses
        .iter()
        .zip(&input.scene.instance_asset)
        .map(|(pose, &ai)| {
            let asset = &input.assets[ai];
            let scale = pose.half_extent / asset.half_size;
            Inst {
                pose: *pose,
                radius: pose.sphere_radius(),
                tree: &asset.tree,
                normal_to_world: pose.world_from_local * DMat3::from_diagonal(scale.recip()),
            }
        })
        .collect();
    let dirty = if opts.use_hit_buffer {
        buffer.begin_frame(input.state)
    } else {
        buffer.invalidate();
        Dirty {
            camera: true,
            instances: vec![true; insts.len()],
        }
    };
    let cam = input.state.camera;
    let lists = tile.map(|t| {
        let spheres: Vec<BinSphere> = insts
            .iter()
            .map(|inst| BinSphere {
                centre: inst.pose.centre,
                keep_radius: reference_keep_radius(
                    inst.radius,
                    (inst.pose.centre - cam.position).length(),
                ),
                behind_slack: 0.0,
                everywhere: false,
            })
            .collect();
        TileLists::build(&cam, w, h, t, &spheres)
    });
    let ctx = FrameCtx {
        insts,
        dirty,
        opts,
        lists,
    };
    let rows: Vec<RowState> = buffer
        .records
        .par_chunks_mut(w as usize)
        .enumerate()
        .map(|(j, records)| {
            let mut row = RowState {
                cands: Vec::with_capacity(ctx.insts.len()),
                ..RowState::default()
            };
            for (i, rec) in records.iter_mut().enumerate() {
                let ray = primary_ray(&cam, w, h, i as u32, j as u32);
                let p = j as u32 * w + i as u32;
                *rec = trace(&ray, p, &ctx, rec, &mut row);
            }
            row.st.rays = records.len() as u64;
            rows_done.fetch_add(1, Ordering::Relaxed);
            row
        })
        .collect();
    let dirty = ctx.dirty;
    let mut total = FrameStats {
        frame: input.state.frame,
        ..FrameStats::default()
    };
    for RowState { st, wc, .. } in &rows {
        total.merge(st);
        total.walker_steps += wc.steps;
        total.node_fetches += wc.fetches;
        total.max_stack = total.max_stack.max(wc.max_stack);
    }
    total.camera_dirty = dirty.camera;
    total.instances_dirty = dirty.instances.iter().filter(|&&d| d).count() as u32;
    total.wall_s = start.elapsed().as_secs_f64();
    total.rays_per_s = total.rays as f64 / total.wall_s.max(1e-9);
    total
}
