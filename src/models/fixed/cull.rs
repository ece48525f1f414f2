//! The two-level scheme in the fixed-point model: the host bins the instances' spheres into
//! per-tile lists with keep radii that cover the fixed-point sphere unit's widening, so the
//! lists are conservative for *this* datapath (docs/instances.md §5), and applies the tile-list
//! memory's capacity (`rtl_model::units::tile_list`): tiles that do not fit become flat lists of
//! every instance, counted.
//!
//! Pipeline position: host work of `FramePlan` (once per frame, after the quantisation); the
//! lists then select the sphere tests of `FramePlan::pixel_at`.
//!
//! Keep radius: the sphere unit rejects a ray iff its computed p² exceeds T = r² + W (rounded
//! up into `sq`), and its computed p² is at most W below the exact one of the unquantised
//! inputs for |c − o| ≤ reach (`rtl_model::units::sphere`). So a kept ray's exact line passes
//! within R = √(T + W) of the f64 centre; R is widened by 10⁻⁹ relative and absolute for the
//! f64 evaluation. Beyond the reach the unit keeps every ray: such a sphere is binned
//! everywhere. Its "behind" test is relaxed by 2Δt, which the binning's behind rule adds.

use super::frame::{render_planned, FixedBuffer, FixedError, FixedStats};
use super::plan::FramePlan;
use crate::models::reference::cull::{BinSphere, TileLists};
use crate::models::reference::FrameInput;
use rtl_model::datapath::{overflow_table, DatapathConfig};
use rtl_model::units::tile_list::{budget, TileListConfig};
use std::time::Instant;

/// The binning spheres of a frame for datapath `cfg`.
pub fn fixed_bin_spheres(input: &FrameInput<'_>, cfg: &DatapathConfig) -> Vec<BinSphere> {
    let sc = &cfg.sphere;
    let w = sc.widening();
    let dt = sc.delta_t();
    let eye = input.state.camera.position;
    input
        .state
        .poses
        .iter()
        .map(|pose| {
            let t = sc.threshold(pose.sphere_radius()) as f64 * sc.sq.lsb();
            let dist = (pose.centre - eye).length();
            BinSphere {
                centre: pose.centre,
                keep_radius: (t + w).sqrt() * (1.0 + 1e-9) + 1e-9 * (1.0 + dist),
                behind_slack: 2.0 * dt + 1e-6,
                // The unit keeps every ray beyond the reach (its codes may round |l| either
                // way by a few lsb: a micrometre of margin).
                everywhere: dist + 1e-6 >= sc.reach,
            }
        })
        .collect()
}

/// What the capacity did to a frame's lists.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ListUse {
    /// Tiles.
    pub tiles: u32,
    /// List entries (before padding).
    pub entries: u64,
    /// Padded words used.
    pub words: u64,
    /// Tiles that did not fit and test every instance (the unit's overflow count).
    pub flat_tiles: u32,
    /// The longest list.
    pub max_len: u32,
}

/// Builds the frame's lists for `plan` (binned from `input` for `plan`'s datapath) under the
/// memory `tl` with `lanes` ids per word, and installs them in the plan.
pub fn install_lists(
    plan: &mut FramePlan<'_>,
    input: &FrameInput<'_>,
    tl: &TileListConfig,
    lanes: u32,
) -> ListUse {
    let (w, h) = input.scene.file.resolution;
    let spheres = fixed_bin_spheres(input, plan.config());
    let mut lists = TileLists::build(&input.state.camera, w, h, tl.tile, &spheres);
    let lens: Vec<u32> = (0..lists.tiles()).map(|t| lists.len_of_tile(t)).collect();
    let b = budget(&lens, lanes, tl);
    if b.flat_tiles > 0 {
        // Flat tiles list every instance: rebuild the ids with those tiles expanded.
        let n = spheres.len() as u16;
        let mut offsets = Vec::with_capacity(lens.len() + 1);
        let mut ids = Vec::new();
        for (t, &flat) in b.flat.iter().enumerate() {
            offsets.push(ids.len() as u32);
            if flat {
                ids.extend(0..n);
            } else {
                let (a, e) = (lists.offsets[t] as usize, lists.offsets[t + 1] as usize);
                ids.extend_from_slice(&lists.ids[a..e]);
            }
        }
        offsets.push(ids.len() as u32);
        lists.offsets = offsets;
        lists.ids = ids;
    }
    let used = ListUse {
        tiles: lens.len() as u32,
        entries: lens.iter().map(|&l| u64::from(l)).sum(),
        words: b.used_words,
        flat_tiles: b.flat_tiles,
        max_len: lens.iter().copied().max().unwrap_or(0),
    };
    plan.lists = Some(lists);
    used
}

/// [`super::render_frame_fixed`] with the two-level scheme: the same records, fewer sphere
/// tests.
pub fn render_frame_fixed_two_level(
    input: &FrameInput<'_>,
    buffer: &mut FixedBuffer,
    cfg: &DatapathConfig,
    use_hit_buffer: bool,
    tl: &TileListConfig,
    lanes: u32,
) -> Result<(FixedStats, ListUse), FixedError> {
    let start = Instant::now();
    let mut host_ov = overflow_table();
    let mut plan = FramePlan::new(input, buffer, cfg, use_hit_buffer, &mut host_ov)?;
    let used = install_lists(&mut plan, input, tl, lanes);
    let mut st = render_planned(&plan, buffer);
    if let Some(ov) = st.overflows.as_mut() {
        ov.merge(&host_ov);
    }
    st.wall_s = start.elapsed().as_secs_f64();
    Ok((st, used))
}
