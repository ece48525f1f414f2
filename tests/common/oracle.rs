//! Independent oracles for the reference renderer.
//!
//! - Oracle A ([`amanatides_woo`]): a 3D-DDA (Amanatides & Woo 1987) over a DENSE voxel
//!   grid, in an instance's local frame. It never sees the SVO image or any code of
//!   `svo_sim::models::reference`; it reads a [`DenseGrid`] (or any `solid` predicate) and derives
//!   every time from the grid planes by division. Where the walker is a recursive
//!   subdivision with midpoint times (t0 + t1)/2 and a mirrored frame, this is a flat walk
//!   that compares plane-crossing times directly, so the two share neither structure nor
//!   arithmetic.
//! - Oracle B ([`pixel_ray`], [`brute_force`]): the camera ray re-derived from the camera
//!   basis, then a slab test of every solid voxel of every instance as an oriented box in
//!   WORLD space (no transform of the ray into local frames, no octree, no bounding spheres).
//!
//! Conventions (the walker's documented ones, re-derived here):
//! - Grid planes of an axis with half extent h and n cells are p(i) = −h + i·(2h/n),
//!   i = 0..=n. The tests only use half extents for which every p(i) is exact, so "a point on a
//!   plane" means the same thing to both sides.
//! - A direction component that is ±0.0 keeps the ray in one slab of that axis: for +0.0 the
//!   half-open [p(i), p(i+1)) containing the origin, for −0.0 the (p(i), p(i+1)] one; a ray
//!   with no such slab misses. This is "the cell the ray is in just after t" for a ray
//!   nudged in the zero's direction.
//! - Any other component moves the ray: the cell at time t is the one whose planes were
//!   crossed at or before t, so an origin on a plane belongs to the cell the ray enters.
//! - Only cells with a positive-length t-interval that ends after 0 are reported; when two or
//!   three crossing times tie exactly the walk steps all tied axes at once (a diagonal step),
//!   so a cell touched only at an edge or corner is never reported.
//! - A hit's t is max(entry, 0).

/// A dense solid/empty grid of 2^depth cells per axis, x fastest.
#[derive(Clone, Debug)]
pub struct DenseGrid {
    depth: u8,
    n: u32,
    solid: Vec<bool>,
}

impl DenseGrid {
    /// An empty grid.
    pub fn new(depth: u8) -> Self {
        assert!(
            (1..=10).contains(&depth),
            "dense grids are for small depths"
        );
        let n = 1u32 << depth;
        Self {
            depth,
            n,
            solid: vec![false; (n as usize).pow(3)],
        }
    }

    /// A grid with exactly the given cells solid.
    pub fn from_coords(depth: u8, coords: impl IntoIterator<Item = [u32; 3]>) -> Self {
        let mut g = Self::new(depth);
        for c in coords {
            g.set(c, true);
        }
        g
    }

    /// Levels (cells per axis = 2^depth).
    pub fn depth(&self) -> u8 {
        self.depth
    }

    /// Cells per axis.
    pub fn n(&self) -> u32 {
        self.n
    }

    fn index(&self, c: [u32; 3]) -> usize {
        assert!(c.iter().all(|&v| v < self.n), "cell {c:?} outside the grid");
        let n = self.n as usize;
        c[0] as usize + n * (c[1] as usize + n * c[2] as usize)
    }

    /// Is the cell solid? Cells outside the grid are empty.
    pub fn get(&self, c: [u32; 3]) -> bool {
        c.iter().all(|&v| v < self.n) && self.solid[self.index(c)]
    }

    /// Sets one cell.
    pub fn set(&mut self, c: [u32; 3], v: bool) {
        let i = self.index(c);
        self.solid[i] = v;
    }

    /// Number of solid cells.
    pub fn count(&self) -> usize {
        self.solid.iter().filter(|&&s| s).count()
    }
}

/// Comparison tolerance for ray parameters: 1e-9 relative, 1e-9 absolute below 1.
pub fn tol(t: f64) -> f64 {
    1e-9 * t.abs().max(1.0)
}

/// Position of grid plane `i` (0..=n) of an axis with half extent `half` and `n` cells.
pub fn plane(half: f64, n: u32, i: u32) -> f64 {
    -half + f64::from(i) * (2.0 * half / f64::from(n))
}

/// Is `x` in the slab [a, b) (`neg` false, a +0.0 direction) or (a, b] (`neg` true, −0.0)?
fn in_slab(x: f64, a: f64, b: f64, neg: bool) -> bool {
    if neg {
        a < x && x <= b
    } else {
        a <= x && x < b
    }
}

/// First solid cell along o + t·d (t ≥ 0) in the grid of `n` cells per axis covering
/// [−half, half]: oracle A.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridHit {
    /// max(entry, 0).
    pub t: f64,
    /// The cell.
    pub voxel: [u32; 3],
}

/// Oracle A: Amanatides–Woo over a grid of `n` cells per axis covering [−half, half], with
/// `solid` telling which cells are solid. See the module doc for the conventions.
pub fn amanatides_woo(
    n: u32,
    half: [f64; 3],
    o: [f64; 3],
    d: [f64; 3],
    solid: impl Fn([u32; 3]) -> bool,
) -> Option<GridHit> {
    assert!(d.iter().any(|&v| v != 0.0), "zero direction");
    // Crossing time of plane i of axis k, always computed the same way (division, no
    // reciprocal and no incremental sums), so a tie between axes is a tie of these numbers.
    let cross = |k: usize, i: u32| (plane(half[k], n, i) - o[k]) / d[k];

    let mut cell = [0u32; 3];
    let mut moving = [false; 3];
    let (mut t_enter, mut t_exit) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        if d[k] == 0.0 {
            let neg = d[k].is_sign_negative();
            let slab = (0..n)
                .find(|&i| in_slab(o[k], plane(half[k], n, i), plane(half[k], n, i + 1), neg));
            cell[k] = slab?;
        } else {
            moving[k] = true;
            let (a, b) = (cross(k, 0), cross(k, n));
            let (lo, hi) = if d[k] > 0.0 { (a, b) } else { (b, a) };
            t_enter = t_enter.max(lo);
            t_exit = t_exit.min(hi);
        }
    }
    // Clip to the box: a positive-length piece that ends after t = 0.
    if !(t_enter < t_exit && t_exit > 0.0) {
        return None;
    }
    let t_start = t_enter.max(0.0);
    // The start cell: planes crossed at or before t_start are behind the ray. t_start is
    // below every axis' exit time, so the searches always succeed inside the grid.
    for k in (0..3).filter(|&k| moving[k]) {
        cell[k] = if d[k] > 0.0 {
            (0..n)
                .rev()
                .find(|&i| cross(k, i) <= t_start)
                .expect("entry plane is crossed")
        } else {
            (1..=n)
                .find(|&i| cross(k, i) <= t_start)
                .expect("entry plane is crossed")
                - 1
        };
    }
    let next_cross = |k: usize, c: u32| {
        if d[k] > 0.0 {
            cross(k, c + 1)
        } else {
            cross(k, c)
        }
    };
    let mut t = t_start;
    loop {
        let t_next = (0..3)
            .filter(|&k| moving[k])
            .map(|k| next_cross(k, cell[k]))
            .fold(f64::INFINITY, f64::min);
        // The current cell's interval is [t, t_next): report it only if it has positive
        // length (it always ends after 0 because t ≥ 0).
        if t_next > t && solid(cell) {
            return Some(GridHit { t, voxel: cell });
        }
        // Step every axis whose crossing is exactly t_next (diagonal step on ties).
        for k in (0..3).filter(|&k| moving[k]) {
            if next_cross(k, cell[k]) == t_next {
                if d[k] > 0.0 {
                    if cell[k] + 1 == n {
                        return None;
                    }
                    cell[k] += 1;
                } else {
                    if cell[k] == 0 {
                        return None;
                    }
                    cell[k] -= 1;
                }
            }
        }
        t = t_next;
    }
}

/// Slab test of one cell of the grid (same plane positions and zero rules as
/// [`amanatides_woo`]): its raw (entry, exit) along the ray, or `None` when a zero
/// component keeps the ray out of it. The interval may be empty (entry ≥ exit).
pub fn cell_interval(
    n: u32,
    half: [f64; 3],
    c: [u32; 3],
    o: [f64; 3],
    d: [f64; 3],
) -> Option<(f64, f64)> {
    let (mut enter, mut exit) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        let (a, b) = (plane(half[k], n, c[k]), plane(half[k], n, c[k] + 1));
        if d[k] == 0.0 {
            if !in_slab(o[k], a, b, d[k].is_sign_negative()) {
                return None;
            }
        } else {
            let (ta, tb) = ((a - o[k]) / d[k], (b - o[k]) / d[k]);
            enter = enter.max(ta.min(tb));
            exit = exit.min(ta.max(tb));
        }
    }
    Some((enter, exit))
}

// ---------------------------------------------------------------------------------------------
// Oracle B: world space

/// A pinhole camera as the frame state gives it (an orthonormal basis).
#[derive(Clone, Copy, Debug)]
pub struct CameraBasis {
    /// Eye.
    pub position: [f64; 3],
    /// Unit view direction.
    pub forward: [f64; 3],
    /// Unit right vector.
    pub right: [f64; 3],
    /// Unit up vector of the image plane.
    pub up: [f64; 3],
    /// tan(vfov / 2).
    pub tan_half_vfov: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Ray through the centre of pixel (i, j) of a W×H image, i to the right and j downward.
/// The image plane at distance 1 spans ±tan(vfov/2) vertically and ±tan(vfov/2)·W/H
/// horizontally, so pixel centre (i + ½, j + ½) maps to
///   x = (2i + 1 − W)/H · tan,  y = (H − 2j − 1)/H · tan
/// (the horizontal term already includes the aspect ratio W/H). Written from the geometry,
/// not from the reference's expression, so the two round differently.
pub fn pixel_ray(cam: &CameraBasis, w: u32, h: u32, i: u32, j: u32) -> ([f64; 3], [f64; 3]) {
    let (wf, hf) = (f64::from(w), f64::from(h));
    let x = (2.0 * f64::from(i) + 1.0 - wf) / hf * cam.tan_half_vfov;
    let y = (hf - 2.0 * f64::from(j) - 1.0) / hf * cam.tan_half_vfov;
    let raw: [f64; 3] = std::array::from_fn(|k| cam.forward[k] + x * cam.right[k] + y * cam.up[k]);
    let len = dot(raw, raw).sqrt();
    (cam.position, raw.map(|v| v / len))
}

/// Raw slab interval of the oriented box {centre + Σ a_k·s_k : |s_k| ≤ half_k} (axes a_k
/// unit and orthogonal) along o + t·d, or `None` when the ray is parallel to a slab and
/// outside it. Computed in the box's own frame by projecting onto its axes.
pub fn obb_interval(
    o: [f64; 3],
    d: [f64; 3],
    centre: [f64; 3],
    axes: &[[f64; 3]; 3],
    half: [f64; 3],
) -> Option<(f64, f64)> {
    let rel = [centre[0] - o[0], centre[1] - o[1], centre[2] - o[2]];
    let (mut enter, mut exit) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        // The ray's coordinate along axis k relative to the centre is t·f − e.
        let e = dot(axes[k], rel);
        let f = dot(axes[k], d);
        if f == 0.0 {
            if e.abs() > half[k] {
                return None;
            }
        } else {
            let (ta, tb) = ((e - half[k]) / f, (e + half[k]) / f);
            enter = enter.max(ta.min(tb));
            exit = exit.min(ta.max(tb));
        }
    }
    Some((enter, exit))
}

/// One instance as the world-space oracle sees it: an oriented box split into 2^depth
/// cells per axis, and the list of solid cells.
#[derive(Clone, Debug)]
pub struct WorldInstance {
    /// Local x, y, z axes in world coordinates (the rotation's columns).
    pub axes: [[f64; 3]; 3],
    /// World position of the box centre.
    pub centre: [f64; 3],
    /// Half extents of the box along its axes (scale included).
    pub half_extent: [f64; 3],
    /// Cells per axis = 2^depth.
    pub depth: u8,
    /// Solid cells.
    pub voxels: Vec<[u32; 3]>,
}

impl WorldInstance {
    /// World centre of cell `c`: centre + Σ axis_k · half_k·((2c_k + 1)/n − 1).
    pub fn cell_centre(&self, c: [u32; 3]) -> [f64; 3] {
        let n = f64::from(1u32 << self.depth);
        let local: [f64; 3] = std::array::from_fn(|k| {
            self.half_extent[k] * ((2.0 * f64::from(c[k]) + 1.0) / n - 1.0)
        });
        std::array::from_fn(|r| {
            self.centre[r]
                + self.axes[0][r] * local[0]
                + self.axes[1][r] * local[1]
                + self.axes[2][r] * local[2]
        })
    }

    /// Half sizes of one cell.
    pub fn cell_half(&self) -> [f64; 3] {
        let n = f64::from(1u32 << self.depth);
        self.half_extent.map(|h| h / n)
    }

    /// Raw slab interval of cell `c` along the ray.
    pub fn cell_interval(&self, o: [f64; 3], d: [f64; 3], c: [u32; 3]) -> Option<(f64, f64)> {
        obb_interval(o, d, self.cell_centre(c), &self.axes, self.cell_half())
    }
}

/// A voxel the ray reaches (or grazes within tolerance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Touch {
    /// Instance index.
    pub instance: usize,
    /// Cell.
    pub voxel: [u32; 3],
    /// max(entry, 0).
    pub t: f64,
    /// Exit time.
    pub exit: f64,
}

impl Touch {
    /// Length of the part of the voxel's interval at t ≥ 0.
    pub fn length(&self) -> f64 {
        self.exit - self.t
    }

    /// A proper hit: an interval after t = 0 longer than the tolerance. Anything shorter is a
    /// graze that rounding may turn either way.
    pub fn is_proper(&self) -> bool {
        self.length() > tol(self.t)
    }
}

/// Oracle B: every solid voxel of every instance the ray o + t·d (t ≥ 0) touches, each with
/// its interval, including grazes down to −tolerance. Unsorted.
pub fn brute_force(instances: &[WorldInstance], o: [f64; 3], d: [f64; 3]) -> Vec<Touch> {
    let mut out = Vec::new();
    for (i, inst) in instances.iter().enumerate() {
        // Whole-box test first, only to save time; loose, so it never drops a graze.
        match obb_interval(o, d, inst.centre, &inst.axes, inst.half_extent) {
            Some((enter, exit)) if exit >= -1e-6 && enter <= exit + 1e-6 => {}
            _ => continue,
        }
        for &c in &inst.voxels {
            if let Some((enter, exit)) = inst.cell_interval(o, d, c) {
                let t = enter.max(0.0);
                if exit - t >= -tol(t) {
                    out.push(Touch {
                        instance: i,
                        voxel: c,
                        t,
                        exit,
                    });
                }
            }
        }
    }
    out
}
