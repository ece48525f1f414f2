//! The stiff and extreme cases of `sim stress`, one function each, and the list that names
//! them with what they stress, the bound they are judged by and the verdict expected.
//!
//! Pipeline position: input of `sim stress` and `tests/stress.rs`. Every case is one frame
//! at a small resolution, built from exact numbers (no keyframe interpolation), so that the
//! extreme is hit exactly: zero components carry the sign wanted, rays pass through grid
//! corners exactly, a ray is tangent to a sphere at a box corner, and so on.

use super::build::{case, look_at, pose, shape_asset, upright, voxel_asset, CaseInput};
use super::measure::Verdict;
use crate::world::scene::Camera;
use crate::world::sdf::{Axis, Shape};
use glam::DVec3;

/// One case: its name, what it stresses, the bound, the verdict expected, and its builder.
pub struct CaseSpec {
    /// Short name (`sim stress --case NAME`).
    pub name: &'static str,
    /// What it stresses.
    pub what: &'static str,
    /// The documented bound it is judged by (`docs/stability.md`).
    pub bound: &'static str,
    /// The verdict the documentation expects.
    pub expected: Verdict,
    /// Builds the frame.
    pub build: fn() -> Result<CaseInput, String>,
}

const SPATIAL: &str = "every mismatch within ε (spatial bound, number-formats §3.5) of a leaf surface; t within the entry bound";

/// Every case, in report order.
pub fn all() -> Vec<CaseSpec> {
    vec![
        CaseSpec { name: "axis_zero", what: "axis-parallel rays with exact +0 and −0 components, in the octree's root centre planes, over a 3-D checkerboard", bound: SPATIAL, expected: Verdict::Pass, build: axis_zero },
        CaseSpec { name: "zero_dir_at_centre", what: "the same ±0 rays from the exact centre of an octree (origin on all three root centre planes), inside a hollow shell", bound: SPATIAL, expected: Verdict::Pass, build: zero_dir_at_centre },
        CaseSpec { name: "near_axis", what: "rays within 2·10^-6 of the z axis: components from 1.2·10^-7 to 1.9·10^-6 (below 2^-21 flushed to zero, up to 2^-20), crossing voxel boundaries", bound: SPATIAL, expected: Verdict::Pass, build: near_axis },
        CaseSpec { name: "corners", what: "rays along the main diagonal through the corners of every level's nodes, leaves touching the diagonal only at corners", bound: SPATIAL, expected: Verdict::Pass, build: corners },
        CaseSpec { name: "edges", what: "rays lying in a grid plane (d_z = ±0) and through vertical node edges, over a checkerboard", bound: SPATIAL, expected: Verdict::Pass, build: edges },
        CaseSpec { name: "grazing_sphere", what: "rays tangent to a bounding sphere within 10^-6 where it touches the box corner, the corner leaf solid", bound: "sphere test never rejects an exact hit (widened threshold W); mismatches within ε", expected: Verdict::Pass, build: grazing_sphere },
        CaseSpec { name: "camera_in_sphere", what: "camera inside two bounding spheres but outside their boxes (sort keys 0), a third instance behind", bound: SPATIAL, expected: Verdict::Pass, build: camera_in_sphere },
        CaseSpec { name: "camera_in_svo", what: "camera inside a rotated octree, in a hollow shell: every walk starts inside the box", bound: SPATIAL, expected: Verdict::Pass, build: camera_in_svo },
        CaseSpec { name: "camera_in_leaf", what: "camera inside a solid leaf of a full octree: every ray hits at t = 0", bound: SPATIAL, expected: Verdict::Pass, build: camera_in_leaf },
        CaseSpec { name: "scale_1e4", what: "a 5 mm and a 50 m instance in one frame (scale ratio 10^4), the camera 5 cm from the small one and inside the big one's sphere", bound: SPATIAL, expected: Verdict::Pass, build: scale_1e4 },
        CaseSpec { name: "anisotropic_1000", what: "one instance scaled 20 m × 2 cm × 2 m (1000:1), rotated", bound: SPATIAL, expected: Verdict::Pass, build: anisotropic },
        CaseSpec { name: "depth16", what: "a depth-16 octree (30 µm leaves): a checkerboard patch and a diagonal line of leaves, seen from 1 cm", bound: SPATIAL, expected: Verdict::Pass, build: depth16 },
        CaseSpec { name: "range_edge", what: "camera and instance near the position format's limit (|x| up to 126.5 m of ±128 m)", bound: SPATIAL, expected: Verdict::Pass, build: range_edge },
        CaseSpec { name: "range_beyond", what: "camera and instance beyond the position format's range (140-150 m)", bound: "not representable by sQ8.32 positions: must be flagged (raygen/pos saturates)", expected: Verdict::Flagged, build: range_beyond },
        CaseSpec { name: "far_camera", what: "camera 100 m from a 1 m instance, 1.2° field of view", bound: SPATIAL, expected: Verdict::Pass, build: far_camera },
        CaseSpec { name: "far_beyond_reach", what: "camera 200 m from the instance (beyond the sphere unit's 128 m reach and the local position range)", bound: "not representable: must be flagged (sphere/reach, transform/origin)", expected: Verdict::Flagged, build: far_beyond_reach },
        CaseSpec { name: "far_diagonal", what: "camera 205 m from the instance along the diagonal: every component of c − o (118 m) within the 128 m reach, the length not", bound: "beyond the sphere unit's analysed range |c − o| ≤ 128 m: must be flagged (sphere/reach); was unflagged before the fix of the unit's reach guard", expected: Verdict::Flagged, build: far_diagonal },
        CaseSpec { name: "coincident", what: "two instances at the same pose (equal sort keys and equal hit t: the lower id must win in both models) and a third 10^-9 m beside them", bound: "ties go to the lower instance id; mismatches within ε", expected: Verdict::Pass, build: coincident },
        CaseSpec { name: "overlap_72", what: "72 overlapping instances (rings along the view axis): up to 72 candidates per ray, 9× the sorter's N = 8", bound: "no candidate dropped (chunked sort + merge); mismatches within ε", expected: Verdict::Pass, build: overlap_72 },
    ]
}

/// A 3-D checkerboard of leaves at `depth`: solid where x + y + z is even.
fn checkerboard(depth: u8) -> impl Iterator<Item = [u32; 3]> {
    let n = 1u32 << depth;
    (0..n).flat_map(move |z| {
        (0..n).flat_map(move |y| {
            (0..n)
                .filter(move |x| (x + y + z) % 2 == 0)
                .map(move |x| [x, y, z])
        })
    })
}

fn axis_zero() -> Result<CaseInput, String> {
    // A mirrored basis chosen so that the pinhole formula forward + u·right + v·up yields
    // exact −0 components: in the middle column (u = +0) d_x = −0 + (−1)(+0) + (−0)·v is −0
    // for v > 0; in the middle row (v = +0) d_y is −0 for u > 0; the centre ray is
    // (−0, −0, −1). The camera sits on x = y = 0, the octree's root centre planes.
    let camera = Camera {
        position: DVec3::new(0.0, 0.0, 3.0),
        forward: DVec3::new(-0.0, -0.0, -1.0),
        right: DVec3::new(-1.0, -0.0, -0.0),
        up: DVec3::new(-0.0, -1.0, -0.0),
        tan_half_vfov: 20f64.to_radians().tan(),
    };
    let a = voxel_asset("checker5", 5, 1.0, checkerboard(5))?;
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(DVec3::ZERO, DVec3::ONE)],
    )
}

/// The mirrored basis of [`axis_zero`]: exact −0 components in the middle row and column.
fn signed_zero_camera(position: DVec3) -> Camera {
    Camera {
        position,
        forward: DVec3::new(-0.0, -0.0, -1.0),
        right: DVec3::new(-1.0, -0.0, -0.0),
        up: DVec3::new(-0.0, -1.0, -0.0),
        tan_half_vfov: 20f64.to_radians().tan(),
    }
}

fn zero_dir_at_centre() -> Result<CaseInput, String> {
    // Zero components with the origin exactly on their centre plane: the §3.3 midpoint rule
    // (−∞ at or above the plane) decides, never (−∞ + ∞)/2.
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let camera = signed_zero_camera(DVec3::ZERO);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(DVec3::ZERO, DVec3::ONE)],
    )
}

fn near_axis() -> Result<CaseInput, String> {
    // Leaves only in the back layer (z index 0), a checkerboard in x, y: rays run 2 m through
    // the octree nearly parallel to z and land left or right of a boundary x = b by their
    // tiny slopes. The camera is 3·10^-7 m beside b = 1/64 (a depth-7 voxel boundary).
    let n = 1u32 << 7;
    let back = (0..n).flat_map(move |y| {
        (0..n)
            .filter(move |x| (x + y) % 2 == 0)
            .map(move |x| [x, y, 0])
    });
    let a = voxel_asset("back7", 7, 1.0, back)?;
    let camera = Camera {
        position: DVec3::new(1.0 / 64.0 + 3e-7, -2e-7, 3.0),
        forward: DVec3::new(0.0, 0.0, -1.0),
        right: DVec3::new(1.0, 0.0, 0.0),
        up: DVec3::new(0.0, 1.0, 0.0),
        tan_half_vfov: 2e-6,
    };
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(DVec3::ZERO, DVec3::ONE)],
    )
}

fn corners() -> Result<CaseInput, String> {
    // Leaves beside the main diagonal, touching it only at their corners (k+1, k+1, k+1).
    let n = 1u32 << 5;
    let beside = (0..n).flat_map(move |k| {
        [[k + 1, k, k], [k, k + 1, k], [k, k, k + 1]]
            .into_iter()
            .filter(move |c| c.iter().all(|&v| v < n))
    });
    let a = voxel_asset("diagonal5", 5, 1.0, beside)?;
    let p = DVec3::splat(2.2);
    let camera = look_at(p, DVec3::ZERO, DVec3::Y, 3.0);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(DVec3::ZERO, DVec3::ONE)],
    )
}

fn edges() -> Result<CaseInput, String> {
    // The camera on x = y in the plane z = 3/16 (a depth-5 grid plane, exact in binary),
    // looking along x = y: the middle row lies in the plane (d_z = ±0), the middle column
    // passes along the vertical edges x = y = const.
    let z0 = 0.1875;
    let a = voxel_asset("checker5", 5, 1.0, checkerboard(5))?;
    let camera = look_at(
        DVec3::new(-2.5, -2.5, z0),
        DVec3::new(0.0, 0.0, z0),
        DVec3::Z,
        30.0,
    );
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(DVec3::ZERO, DVec3::ONE)],
    )
}

fn grazing_sphere() -> Result<CaseInput, String> {
    // Every leaf solid; the bounding sphere (radius √3) touches the box at its corners. The
    // centre ray is tangent to the sphere at the corner (1, 1, 1); neighbouring rays are
    // within 10^-6 m of it, some just inside the corner leaf, some just outside the sphere.
    let n = 1u32 << 4;
    let all = (0..n).flat_map(move |z| (0..n).flat_map(move |y| (0..n).map(move |x| [x, y, z])));
    let a = voxel_asset("full4", 4, 1.0, all)?;
    let corner = DVec3::ONE;
    let tangent = DVec3::new(1.0, -1.0, 0.0).normalize();
    let camera = Camera {
        tan_half_vfov: 2.5e-7,
        ..look_at(corner - 4.0 * tangent, corner, DVec3::Z, 1.0)
    };
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(DVec3::ZERO, DVec3::ONE)],
    )
}

fn shell(radius: f64) -> Shape {
    Shape::Sphere { radius }
}

fn camera_in_sphere() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    // |(1.2, 1.2, 0.3)| = 1.72 < √3: inside the first sphere, outside its box; the second
    // instance's sphere (radius 1.04, 0.86 m away) holds the camera too, its box does not.
    let camera = look_at(DVec3::new(1.2, 1.2, 0.3), DVec3::ZERO, DVec3::Y, 60.0);
    let poses = vec![
        upright(DVec3::ZERO, DVec3::ONE),
        pose(
            [0.0, 30.0, 0.0],
            DVec3::new(1.6, 1.95, 0.4),
            DVec3::splat(0.6),
        ),
        upright(DVec3::new(-3.0, -3.0, 0.0), DVec3::ONE),
    ];
    case((33, 33), vec![a], &[0, 0, 0], camera, poses)
}

fn camera_in_svo() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let camera = look_at(
        DVec3::new(0.1, 0.05, -0.2),
        DVec3::new(0.3, -0.2, -1.0),
        DVec3::Y,
        90.0,
    );
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![pose([10.0, 20.0, 30.0], DVec3::ZERO, DVec3::ONE)],
    )
}

fn camera_in_leaf() -> Result<CaseInput, String> {
    let n = 1u32 << 4;
    let all = (0..n).flat_map(move |z| (0..n).flat_map(move |y| (0..n).map(move |x| [x, y, z])));
    let a = voxel_asset("full4", 4, 1.0, all)?;
    let camera = look_at(
        DVec3::new(0.3, 0.2, 0.1),
        DVec3::new(1.0, -0.5, 2.0),
        DVec3::Y,
        90.0,
    );
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![pose([0.0, 0.0, 45.0], DVec3::ZERO, DVec3::ONE)],
    )
}

fn scale_1e4() -> Result<CaseInput, String> {
    let tiny = shape_asset(
        "nut",
        &Shape::Torus {
            major: 0.6,
            minor: 0.3,
            axis: Axis::Z,
        },
        1.0,
        6,
    )?;
    let huge = shape_asset("dome", &shell(0.9), 1.0, 7)?;
    let camera = look_at(DVec3::new(0.0, 0.0, 0.05), DVec3::ZERO, DVec3::Y, 20.0);
    let poses = vec![
        pose([20.0, 10.0, 0.0], DVec3::ZERO, DVec3::splat(0.005)),
        upright(DVec3::new(0.0, 0.0, -60.0), DVec3::splat(50.0)),
    ];
    case((33, 33), vec![tiny, huge], &[0, 1], camera, poses)
}

fn anisotropic() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.95), 1.0, 6)?;
    let camera = look_at(DVec3::new(1.5, 2.5, 3.0), DVec3::ZERO, DVec3::Y, 70.0);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![pose(
            [15.0, 25.0, 35.0],
            DVec3::ZERO,
            DVec3::new(10.0, 0.01, 1.0),
        )],
    )
}

fn depth16() -> Result<CaseInput, String> {
    // Leaves of 2/65536 m ≈ 30.5 µm: a 128 × 128 checkerboard patch in the layer z = 40000
    // and a diagonal line of 600 leaves, so walks descend all 16 levels.
    let (x0, z) = (32_700u32, 40_000u32);
    let patch = (x0..x0 + 128).flat_map(move |y| {
        (x0..x0 + 128)
            .filter(move |x| (x + y) % 2 == 0)
            .map(move |x| [x, y, z])
    });
    let line = (32_768u32..33_368).map(|k| [k, k, k]);
    let a = voxel_asset("deep16", 16, 1.0, patch.chain(line))?;
    let leaf = 2.0 / 65_536.0;
    let centre = |c: f64| -1.0 + c * leaf;
    let target = DVec3::new(
        centre(f64::from(x0) + 64.0),
        centre(f64::from(x0) + 64.0),
        centre(f64::from(z)),
    );
    let camera = look_at(
        target + DVec3::new(2e-4, 1e-4, 0.01),
        target,
        DVec3::Y,
        20.0,
    );
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(DVec3::ZERO, DVec3::ONE)],
    )
}

fn range_edge() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let c = DVec3::new(120.0, -120.0, 100.0);
    let camera = look_at(DVec3::new(126.5, -126.5, 112.0), c, DVec3::Y, 50.0);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![pose([0.0, 40.0, 0.0], c, DVec3::splat(5.0))],
    )
}

fn range_beyond() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let c = DVec3::new(140.0, 0.0, 0.0);
    let camera = look_at(DVec3::new(150.0, 2.0, 12.0), c, DVec3::Y, 50.0);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(c, DVec3::splat(5.0))],
    )
}

fn far_camera() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let camera = look_at(DVec3::new(60.0, 20.0, 77.5), DVec3::ZERO, DVec3::Y, 1.2);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![pose([5.0, 10.0, 0.0], DVec3::ZERO, DVec3::ONE)],
    )
}

fn far_beyond_reach() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let c = DVec3::new(100.0, 0.0, 0.0);
    let camera = look_at(DVec3::new(-100.0, 0.0, 0.0), c, DVec3::Y, 1.2);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(c, DVec3::ONE)],
    )
}

fn far_diagonal() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let c = DVec3::splat(60.0);
    let camera = look_at(DVec3::splat(-58.36), c, DVec3::Y, 1.0);
    case(
        (33, 33),
        vec![a],
        &[0],
        camera,
        vec![upright(c, DVec3::ONE)],
    )
}

fn coincident() -> Result<CaseInput, String> {
    let a = shape_asset("ball6", &shell(0.9), 1.0, 6)?;
    let camera = look_at(DVec3::new(0.5, 0.8, 3.0), DVec3::ZERO, DVec3::Y, 50.0);
    let p = pose([10.0, 20.0, 30.0], DVec3::ZERO, DVec3::ONE);
    let mut beside = p;
    beside.centre = DVec3::new(1e-9, 0.0, 0.0);
    case((33, 33), vec![a], &[0, 0, 0], camera, vec![p, p, beside])
}

fn overlap_72() -> Result<CaseInput, String> {
    let ring = shape_asset(
        "ring",
        &Shape::Torus {
            major: 0.8,
            minor: 0.1,
            axis: Axis::Z,
        },
        1.0,
        6,
    )?;
    let poses = (0..72u32)
        .map(|k| {
            let f = f64::from(k);
            pose(
                [
                    f64::from(k * 7 % 20) - 10.0,
                    f64::from(k * 13 % 20) - 10.0,
                    f * 5.0,
                ],
                DVec3::new(0.02 * f, 0.01 * f, -0.25 * f),
                DVec3::ONE,
            )
        })
        .collect();
    let camera = look_at(
        DVec3::new(0.1, 0.05, 2.0),
        DVec3::new(0.7, 0.35, -17.75),
        DVec3::Y,
        30.0,
    );
    case((33, 33), vec![ring], &[0; 72], camera, poses)
}
