//! The two-level scheme over the instances' bounding spheres: per-tile instance lists
//! (docs/instances.md). The host projects every sphere once per frame to a conservative pixel
//! rectangle and bins it into the screen tiles it touches; each ray then tests only the
//! instances listed for its tile, in instance order, instead of every instance.
//!
//! Pipeline position: host work before ray generation; the list replaces "every instance" as
//! the input of the sphere tests (`frame.rs`, and `models::fixed::cull` for the fixed-point
//! datapath). Nothing after the sphere tests changes.
//!
//! Conservative by construction: a sphere is given as centre and a *keep radius* R, the
//! largest distance from the centre at which the sphere test of the model using the lists can
//! still keep a ray's line (the reference: r widened for f64 rounding; the fixed datapath:
//! √(T + W), `models::fixed::cull`). For a pinhole camera every primary ray has the camera
//! coordinates (u, v, 1)·s with s > 0, u = dx/dz, v = dy/dz. Projecting the line's distance
//! to the (x, z) plane can only shorten it, so a ray whose line passes within R of the centre
//! has its u within the two tangents from the eye to the disk of radius R around (c_x, c_z):
//! u ∈ [tan(θ − β), tan(θ + β)], θ = atan2(c_x, c_z), β = asin(R / |(c_x, c_z)|), valid when
//! c_z > R (the disk lies in front of the eye); the same for v in (c_y, c_z). The pixel range
//! follows from the ray generation's u(i) = (2(i + ½)/W − 1)·τ·a and v(j) = (1 − 2(j + ½)/H)·τ,
//! widened by one pixel on each side, which covers f64's rounding of every step here and of
//! the ray generation by many orders of magnitude. A sphere with c_z ≤ R + slack straddles
//! the eye's plane: its projection is unbounded and it goes into every tile. A sphere wholly
//! behind the eye or outside a side plane of the view frustum (by more than 2R + slack, which
//! covers the fixed unit's relaxed "behind" test) can meet no primary ray and goes nowhere.

use crate::world::scene::Camera;
use glam::DVec3;

/// The default tile side in pixels (docs/instances.md §3: 16 gives 3,840 tiles at 1280×768).
pub const DEFAULT_TILE: u32 = 16;

/// One instance's sphere as the binning sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BinSphere {
    /// Centre in world space.
    pub centre: DVec3,
    /// Keep radius: no ray whose line passes farther than this from the centre can be kept
    /// by the sphere test of the model the lists are for.
    pub keep_radius: f64,
    /// Metres added to the "behind the eye" test on top of 2R (the fixed unit's 2Δt).
    pub behind_slack: f64,
    /// Kept by every ray whatever its direction (the fixed unit's reach rule).
    pub everywhere: bool,
}

/// Where one sphere lands on the screen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Footprint {
    /// No primary ray can meet it.
    Nowhere,
    /// Every tile (the projection is unbounded or the test keeps every ray).
    Everywhere,
    /// Pixels `i0..=i1` × `j0..=j1` (inclusive, clamped to the screen).
    Pixels {
        /// First column.
        i0: u32,
        /// Last column.
        i1: u32,
        /// First row.
        j0: u32,
        /// Last row.
        j1: u32,
    },
}

/// The frame's per-tile instance lists.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TileLists {
    /// Tile side in pixels.
    pub tile: u32,
    /// Tiles per row.
    pub tiles_x: u32,
    /// Tile rows.
    pub tiles_y: u32,
    /// Image width in pixels.
    pub width: u32,
    /// Start of each tile's list in `ids` (tiles in raster order), plus the end.
    pub offsets: Vec<u32>,
    /// Instance ids, each tile's ascending.
    pub ids: Vec<u16>,
    /// Instances binned into every tile.
    pub everywhere: u32,
    /// Instances binned nowhere.
    pub nowhere: u32,
}

/// The conservative pixel rectangle of `s` for camera `cam` on a `w`×`h` image.
pub fn footprint(cam: &Camera, w: u32, h: u32, s: &BinSphere) -> Footprint {
    if s.everywhere || !s.keep_radius.is_finite() {
        return Footprint::Everywhere;
    }
    let l = s.centre - cam.position;
    let (cx, cy, cz) = (l.dot(cam.right), l.dot(cam.up), l.dot(cam.forward));
    let r = s.keep_radius;
    // Slack for f64 rounding of the camera coordinates (a few ulps of |l|).
    let slack = 1e-9 * (1.0 + l.length());
    // Behind the eye, or outside one of the frustum's four side planes (every primary ray has
    // |u| < τa and |v| < τ): no point of a ray at t ≥ 0 is on the far side of such a plane,
    // and the fixed unit's relaxed "behind" test keeps at most 2Δt + R behind the eye, hence
    // the same margin for all five planes.
    let tau = cam.tan_half_vfov;
    let aspect = f64::from(w) / f64::from(h);
    let margin = 2.0 * r + s.behind_slack + slack;
    let (ta, t) = (tau * aspect, tau);
    let outside = [
        (cx - ta * cz) / ta.hypot(1.0),
        (-cx - ta * cz) / ta.hypot(1.0),
        (cy - t * cz) / t.hypot(1.0),
        (-cy - t * cz) / t.hypot(1.0),
    ];
    if cz < -margin || outside.iter().any(|&d| d > margin) {
        return Footprint::Nowhere;
    }
    if cz <= r + slack {
        return Footprint::Everywhere;
    }
    let range = |c: f64| {
        let len = c.hypot(cz);
        let theta = c.atan2(cz);
        let beta = (r / len).min(1.0).asin();
        ((theta - beta).tan(), (theta + beta).tan())
    };
    let (u_lo, u_hi) = range(cx);
    let (v_lo, v_hi) = range(cy);
    // Pixel coordinates (continuous, pixel centres at integers): i = (u/(τa) + 1)·W/2 − ½,
    // j = (1 − v/τ)·H/2 − ½; v grows upward, rows downward.
    let fi = |u: f64| (u / (tau * aspect) + 1.0) * f64::from(w) / 2.0 - 0.5;
    let fj = |v: f64| (1.0 - v / tau) * f64::from(h) / 2.0 - 0.5;
    let (i_lo, i_hi) = (fi(u_lo).floor() - 1.0, fi(u_hi).ceil() + 1.0);
    let (j_lo, j_hi) = (fj(v_hi).floor() - 1.0, fj(v_lo).ceil() + 1.0);
    if !(i_lo.is_finite() && i_hi.is_finite() && j_lo.is_finite() && j_hi.is_finite()) {
        return Footprint::Everywhere;
    }
    let (wm, hm) = (f64::from(w) - 1.0, f64::from(h) - 1.0);
    if i_hi < 0.0 || j_hi < 0.0 || i_lo > wm || j_lo > hm {
        return Footprint::Nowhere;
    }
    Footprint::Pixels {
        i0: i_lo.max(0.0) as u32,
        i1: i_hi.min(wm) as u32,
        j0: j_lo.max(0.0) as u32,
        j1: j_hi.min(hm) as u32,
    }
}

impl TileLists {
    /// Bins `spheres` (instance k is `spheres[k]`) into `tile`×`tile` tiles of a `w`×`h`
    /// image: two passes (count, then fill) so each list is contiguous and ascending.
    pub fn build(cam: &Camera, w: u32, h: u32, tile: u32, spheres: &[BinSphere]) -> Self {
        let tile = tile.max(1);
        let (tx, ty) = (w.div_ceil(tile), h.div_ceil(tile));
        let n_tiles = tx as usize * ty as usize;
        let mut out = Self {
            tile,
            tiles_x: tx,
            tiles_y: ty,
            width: w,
            ..Self::default()
        };
        let rects: Vec<Option<(u32, u32, u32, u32)>> = spheres
            .iter()
            .map(|s| match footprint(cam, w, h, s) {
                Footprint::Nowhere => {
                    out.nowhere += 1;
                    None
                }
                Footprint::Everywhere => {
                    out.everywhere += 1;
                    Some((0, tx - 1, 0, ty - 1))
                }
                Footprint::Pixels { i0, i1, j0, j1 } => {
                    Some((i0 / tile, i1 / tile, j0 / tile, j1 / tile))
                }
            })
            .collect();
        let mut counts = vec![0u32; n_tiles + 1];
        for (x0, x1, y0, y1) in rects.iter().flatten().copied() {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    counts[(y * tx + x) as usize] += 1;
                }
            }
        }
        let mut offsets = Vec::with_capacity(n_tiles + 1);
        let mut acc = 0u32;
        for c in &counts[..n_tiles] {
            offsets.push(acc);
            acc += c;
        }
        offsets.push(acc);
        let mut fill = offsets.clone();
        let mut ids = vec![0u16; acc as usize];
        for (k, rect) in rects.iter().enumerate() {
            let Some((x0, x1, y0, y1)) = *rect else {
                continue;
            };
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let t = (y * tx + x) as usize;
                    ids[fill[t] as usize] = k as u16;
                    fill[t] += 1;
                }
            }
        }
        out.offsets = offsets;
        out.ids = ids;
        out
    }

    /// The tile of pixel `p` (raster order).
    #[inline]
    pub fn tile_of(&self, p: u32) -> usize {
        let (i, j) = (p % self.width.max(1), p / self.width.max(1));
        ((j / self.tile) * self.tiles_x + i / self.tile) as usize
    }

    /// The instances listed for pixel `p`, ascending.
    #[inline]
    pub fn list(&self, p: u32) -> &[u16] {
        let t = self.tile_of(p);
        match (self.offsets.get(t), self.offsets.get(t + 1)) {
            (Some(&a), Some(&b)) => &self.ids[a as usize..b as usize],
            _ => &[],
        }
    }

    /// Length of tile `t`'s list.
    pub fn len_of_tile(&self, t: usize) -> u32 {
        match (self.offsets.get(t), self.offsets.get(t + 1)) {
            (Some(&a), Some(&b)) => b - a,
            _ => 0,
        }
    }

    /// Tiles.
    pub fn tiles(&self) -> usize {
        self.tiles_x as usize * self.tiles_y as usize
    }

    /// Entries in all lists.
    pub fn entries(&self) -> u64 {
        self.ids.len() as u64
    }

    /// The longest list.
    pub fn max_len(&self) -> u32 {
        (0..self.tiles())
            .map(|t| self.len_of_tile(t))
            .max()
            .unwrap_or(0)
    }
}

/// The reference's keep radius for a sphere of radius `r`: its f64 test keeps a line at
/// computed d² ≤ r², which rounding can move by a few ulps of |l|²; 10⁻⁹ relative and absolute
/// is orders of magnitude more.
pub fn reference_keep_radius(r: f64, centre_distance: f64) -> f64 {
    r * (1.0 + 1e-9) + 1e-9 * (1.0 + centre_distance)
}
