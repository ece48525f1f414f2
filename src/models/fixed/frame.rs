//! One frame of the functional fixed-point model: a prepared [`FramePlan`] run over every
//! pixel, in parallel over rows (or row after row, streaming each row's trace to a cycle model
//! running beside it), and the buffer of packed records it leaves.
//!
//! Pipeline position: `sim --model fixed`, and the functional half of `sim --model cycle`.

use super::plan::{FramePlan, PixelCounters};
use super::row_feed::{FeedGuard, RowFeed};
use super::trace::{NoPixelObserver, PixelObserver, RowRecorder, RowTrace};
use crate::models::reference::{FrameInput, HitRecord, RenderOptions};
use crate::world::scene::FrameState;
use rayon::prelude::*;
use rtl_model::datapath::{overflow_table, DatapathConfig};
use rtl_model::fixed::Overflows;
use rtl_model::units::hit_record::unpack;
use rtl_model::units::sorter::SorterStats;
use rtl_model::units::walker::{WalkerStats, WalkerT};
use std::time::Instant;
use thiserror::Error;

/// Why a frame cannot run on the fixed-point model.
#[derive(Debug, Error)]
pub enum FixedError {
    /// The datapath configuration is inconsistent.
    #[error("datapath configuration: {0}")]
    Config(String),
    /// An asset has no memory image (walked implicitly), which the hardware cannot read.
    #[error("asset \"{0}\" has no memory image (it is walked implicitly from its SDF); the fixed-point model needs a materialised octree: use a smaller --depth")]
    Implicit(String),
}

/// A hit-buffer entry: the packed BRAM word the hardware keeps, plus instrumentation the
/// model keeps beside it for accuracy checks (not hardware state).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FixedRecord {
    /// The packed record (`rtl_model::units::hit_record` layout).
    pub word: u128,
    /// Hit.
    pub hit: bool,
    /// Walker t of the hit.
    pub t: WalkerT,
    /// Leaf coordinates of the hit.
    pub voxel: [u32; 3],
    /// Entry face in world space, rounded to axes ×127 (for dumps).
    pub face: [i8; 3],
}

/// The fixed-point model's hit buffer across frames.
#[derive(Clone)]
pub struct FixedBuffer {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// One entry per pixel.
    pub records: Vec<FixedRecord>,
    pub(crate) prev: Option<FrameState>,
    /// The per-pixel direction table (raw codes) and the camera it was written for: the host
    /// rewrites it only when the camera changes.
    pub(crate) dir_table: Vec<[i64; 3]>,
    pub(crate) table_camera: Option<crate::world::scene::Camera>,
}

impl FixedBuffer {
    /// Empty: the first frame traces every pixel.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            records: vec![FixedRecord::default(); width as usize * height as usize],
            prev: None,
            dir_table: Vec::new(),
            table_camera: None,
        }
    }
}

/// Counters of a fixed-point frame.
#[derive(Clone, Debug, Default)]
pub struct FixedStats {
    /// Rays.
    pub rays: u64,
    /// Ray–sphere tests.
    pub sphere_tests: u64,
    /// Tests that culled.
    pub spheres_culled: u64,
    /// Candidates of traced (not reused) rays.
    pub candidates: u64,
    /// Rays that stopped with candidates left.
    pub early_terminations: u64,
    /// Pixels that hit.
    pub hits: u64,
    /// Walks.
    pub walks: u64,
    /// Direction components flushed to zero by the reciprocal unit (§3.3 approximation).
    pub zero_flushes: u64,
    /// Pixels reused from the hit buffer.
    pub hit_buffer_reused: u64,
    /// Walker counters.
    pub walker: WalkerStats,
    /// Sorter counters.
    pub sorter: SorterStats,
    /// Saturations and wraps per signal.
    pub overflows: Option<Overflows>,
    /// Wall time, seconds.
    pub wall_s: f64,
}

/// Renders one frame through the fixed-point units into `buffer`, in parallel over rows.
pub fn render_frame_fixed(
    input: &FrameInput<'_>,
    buffer: &mut FixedBuffer,
    cfg: &DatapathConfig,
    use_hit_buffer: bool,
) -> Result<FixedStats, FixedError> {
    let opts = RenderOptions {
        use_hit_buffer,
        ..RenderOptions::default()
    };
    render_frame_fixed_with(input, buffer, cfg, opts)
}

/// [`render_frame_fixed`] with every switch of `opts` (culling, sorting, early termination,
/// hit buffer).
pub fn render_frame_fixed_with(
    input: &FrameInput<'_>,
    buffer: &mut FixedBuffer,
    cfg: &DatapathConfig,
    opts: RenderOptions,
) -> Result<FixedStats, FixedError> {
    let start = Instant::now();
    let mut host_ov = overflow_table();
    let plan = FramePlan::new(input, buffer, cfg, opts.use_hit_buffer, &mut host_ov)?
        .with_switches(opts.ray_switches());
    let mut st = render_planned(&plan, buffer);
    if let Some(ov) = st.overflows.as_mut() {
        ov.merge(&host_ov);
    }
    st.wall_s = start.elapsed().as_secs_f64();
    Ok(st)
}

/// One row of a prepared frame: every pixel of row `j` through the datapath into `records`
/// (that row's entries), each reported to `obs`.
fn render_row<P: PixelObserver>(
    plan: &FramePlan<'_>,
    table: &[[i64; 3]],
    j: usize,
    records: &mut [FixedRecord],
    obs: &mut P,
) -> PixelCounters {
    let width = records.len();
    let mut c = PixelCounters::default();
    let mut cands: Vec<(i64, u16)> = Vec::with_capacity(plan.instances());
    for (i, rec) in records.iter_mut().enumerate() {
        // Ray generation: the pixel's direction table entry.
        let d = table[j * width + i];
        let p = (j * width + i) as u32;
        plan.pixel_at(Some(p), d, rec, &mut c, &mut cands, obs);
    }
    c
}

/// The frame's counters from its rows'.
fn frame_stats(rows: &[PixelCounters], w: u32, h: u32, start: Instant) -> FixedStats {
    let mut all = PixelCounters::default();
    for r in rows {
        all.merge(r);
    }
    FixedStats {
        rays: u64::from(w) * u64::from(h),
        sphere_tests: all.tests,
        spheres_culled: all.culled,
        candidates: all.candidates,
        early_terminations: all.early,
        hits: all.hits,
        walks: all.walks,
        zero_flushes: all.flushes,
        hit_buffer_reused: all.reused,
        walker: all.walker,
        sorter: all.sorter,
        overflows: Some(all.ov),
        wall_s: start.elapsed().as_secs_f64(),
    }
}

/// Runs a prepared frame (`FramePlan::new` already updated `buffer`'s direction table and
/// previous state) over every pixel, in parallel over rows.
pub(crate) fn render_planned(plan: &FramePlan<'_>, buffer: &mut FixedBuffer) -> FixedStats {
    let start = Instant::now();
    let (w, h) = (buffer.width, buffer.height);
    let table = &buffer.dir_table;
    let rows: Vec<PixelCounters> = buffer
        .records
        .par_chunks_mut(w as usize)
        .enumerate()
        .map(|(j, records)| render_row(plan, table, j, records, &mut NoPixelObserver))
        .collect();
    frame_stats(&rows, w, h, start)
}

/// Runs a prepared frame on the calling thread, row after row, publishing each row's trace
/// into `feed` as soon as it is complete (for a cycle model running at the same time on
/// another thread). `records` and `table` are the buffer's records and direction table.
/// Stops early, leaving the later rows unrendered, if the consumer cancels the feed; the feed
/// is closed on return, also by a panic.
pub fn render_streamed(
    plan: &FramePlan<'_>,
    table: &[[i64; 3]],
    records: &mut [FixedRecord],
    (w, h): (u32, u32),
    feed: &RowFeed,
) -> FixedStats {
    let _close = FeedGuard(feed);
    let start = Instant::now();
    let mut rows = Vec::with_capacity(h as usize);
    for (j, row) in records.chunks_mut(w as usize).enumerate() {
        if feed.is_cancelled() {
            break;
        }
        let mut t = RowTrace::default();
        rows.push(render_row(
            plan,
            table,
            j,
            row,
            &mut RowRecorder::new(&mut t),
        ));
        if feed.publish(j, t).is_err() {
            break;
        }
    }
    frame_stats(&rows, w, h, start)
}

/// The fixed-point records as the reference's record type, for PNGs, dumps and comparisons:
/// t from the walker, colour and shading normal from the packed word.
pub fn to_hit_records(buffer: &FixedBuffer, cfg: &DatapathConfig) -> Vec<HitRecord> {
    buffer
        .records
        .iter()
        .map(|r| {
            let f = unpack(r.word, &cfg.hit_record);
            if !r.hit {
                return HitRecord {
                    spheres: f.kind,
                    ..HitRecord::MISS
                };
            }
            let n =
                rtl_model::units::hit_record::decode_normal(f.normal, cfg.hit_record.normal_bits);
            let c = f.colour;
            HitRecord {
                hit: true,
                spheres: f.kind,
                instance: f
                    .instance
                    .unwrap_or(crate::models::reference::record::NO_INSTANCE),
                t: r.t.to_f64(&cfg.walker),
                voxel: r.voxel,
                face_normal: r.face.map(|v| f32::from(v) / 127.0),
                shade_normal: n.map(|v| v as f32),
                colour: [c[0], c[1], c[2], 255],
            }
        })
        .collect()
}
