//! The walker's adversarial walks: axis-parallel rays along every axis both ways with −0 on
//! the other axes, origins on the box's faces, centre planes and inner node planes, rays
//! through corners and the centre, rays grazing the edges and corners of the box and of its
//! nodes, origins inside the box, inside a deepest-level voxel, behind and beside it, zero
//! axes outside the slab, a ray with all three axes zero, and walks to the voxels of the
//! depth-20 octree (the deepest level: the stack's last frame).
//!
//! Pipeline position: part of the walker stage (`super`), first rows of `walker.hex`.

use super::{WalkTxn, WalkerStage, DEEP_VOXELS};
use crate::vectors::stage::dedup;

impl WalkerStage {
    pub(super) fn adversarial(&self) -> Vec<WalkTxn> {
        let (cube, corners, lattice) = (self.synthetic, self.synthetic + 1, self.synthetic + 2);
        let cubic = [1.0; 3];
        let aniso = [2.0, 0.5, 1.0];
        let mut v = Vec::new();
        let mut walk = |image: usize, o: [f64; 3], d: [f64; 3], half: [f64; 3]| {
            v.push(WalkTxn {
                image,
                input: self.input_for(o, d, half),
            });
        };
        for (image, half) in [
            (cube, cubic),
            (corners, cubic),
            (lattice, cubic),
            (lattice, aniso),
        ] {
            {
                // Axis-parallel rays, both ways, through the centre and off it; −0 on the
                // other axes.
                for k in 0..3 {
                    for sign in [1.0, -1.0] {
                        for off in [0.0, -0.77] {
                            let mut o = [off * half[0], -off * half[1], off * half[2]];
                            o[k] = -sign * 3.0 * half[k];
                            let mut d = [0.0, -0.0, 0.0];
                            d[(k + 1) % 3] = -0.0;
                            d[(k + 2) % 3] = 0.0;
                            d[k] = sign;
                            walk(image, o, d, half);
                        }
                    }
                }
                // Origins on faces, centre planes and level-2 node planes, axis-parallel.
                for plane in [-1.0, -0.5, 0.0, 0.25, 0.5, 1.0] {
                    walk(
                        image,
                        [plane * half[0], -3.0 * half[1], 0.1],
                        [0.0, 1.0, -0.0],
                        half,
                    );
                    walk(
                        image,
                        [-3.0 * half[0], plane * half[1], plane * half[2]],
                        [1.0, 0.0, 0.0],
                        half,
                    );
                }
                // Through the corners and the centre.
                let s = 1.0 / 3f64.sqrt();
                walk(image, half.map(|h| -2.0 * h), [s, s, s], half);
                walk(image, half.map(|h| 2.0 * h), [-s, -s, -s], half);
                walk(
                    image,
                    [-2.0 * half[0], 2.0 * half[1], -2.0 * half[2]],
                    [s, -s, s],
                    half,
                );
                // Inside the box; behind it; missing it; zero axes outside the slab.
                walk(image, [0.01, 0.02, -0.03], [0.6, 0.0, 0.8], half);
                walk(image, half.map(|h| -0.9 * h), [0.0, 0.0, 1.0], half);
                walk(image, half.map(|h| 3.0 * h), [s, s, s], half);
                walk(
                    image,
                    [-3.0 * half[0], 2.0 * half[1], 0.0],
                    [1.0, 0.0, 0.0],
                    half,
                );
                walk(
                    image,
                    [-3.0 * half[0], half[1], 0.0],
                    [1.0, 0.0, -0.0],
                    half,
                );
                walk(
                    image,
                    [-3.0 * half[0], -half[1], 0.0],
                    [1.0, -0.0, 0.0],
                    half,
                );
                walk(image, [0.0, 0.0, 0.0], [0.0, -0.0, 0.0], half);
                // Grazing the box's and the nodes' edges: axis-parallel rays whose other two
                // coordinates both lie on planes (the lower faces are inside, the upper ones
                // outside), with +0 and −0 on the zero axes.
                for (y, z) in [
                    (-1.0, -1.0),
                    (1.0, 1.0),
                    (-1.0, 1.0),
                    (0.0, 0.0),
                    (0.5, -0.5),
                    (0.25, 0.75),
                ] {
                    for (dy, dz) in [(0.0, -0.0), (-0.0, 0.0)] {
                        walk(
                            image,
                            [-3.0 * half[0], y * half[1], z * half[2]],
                            [1.0, dy, dz],
                            half,
                        );
                    }
                }
                // Grazing corners: diagonals in a face plane through a corner of the box
                // and of a level-1 node.
                let r = std::f64::consts::FRAC_1_SQRT_2;
                for c in [-1.0, 0.0, 1.0] {
                    for (dx, dy) in [(r, r), (r, -r), (-r, r)] {
                        let corner = [c * half[0], -c * half[1], c * half[2]];
                        walk(
                            image,
                            [corner[0] - 2.0 * dx, corner[1] - 2.0 * dy, corner[2]],
                            [dx, dy, 0.0],
                            half,
                        );
                    }
                }
                // Origin inside a voxel of the deepest level of the image and inside a node.
                let n = f64::from(1u32 << self.images[image].image.depth());
                let voxel = |i: f64, h: f64| -h + (2.0 * i + 0.5) * h / n;
                walk(
                    image,
                    [
                        voxel(1.0, half[0]),
                        voxel(6.0, half[1]),
                        voxel(3.0, half[2]),
                    ],
                    [-0.48, 0.6, 0.64],
                    half,
                );
            }
        }
        // The deepest level: walks to each voxel of the depth-20 octree from outside (along
        // a diagonal, an axis and a general direction) and from inside it; these fill the
        // stack to its last frame.
        let deep = self.synthetic + 3;
        let n = f64::from(1u32 << crate::svo::MAX_DEPTH);
        for (i, c) in DEEP_VOXELS.iter().enumerate() {
            let half = if i % 2 == 0 {
                [1.0; 3]
            } else {
                [2.0, 0.5, 1.0]
            };
            let centre: [f64; 3] =
                std::array::from_fn(|k| -half[k] + (2.0 * f64::from(c[k]) + 1.0) * half[k] / n);
            let s3 = 1.0 / 3f64.sqrt();
            for d in [
                [s3, s3, s3],
                [-s3, s3, -s3],
                [0.0, 0.0, -1.0],
                [0.36, -0.48, 0.8],
            ] {
                walk(
                    deep,
                    std::array::from_fn(|k| centre[k] - 3.0 * d[k]),
                    d,
                    half,
                );
            }
            walk(deep, centre, [0.6, 0.8, -0.0], half);
        }
        dedup(v)
    }
}
