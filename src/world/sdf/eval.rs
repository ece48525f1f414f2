//! Validated, flattened SDF: checks a [`Shape`] once and evaluates it fast.

use super::{Axis, Shape};
use glam::{DMat3, DVec3};

/// Colour of surfaces that no `Paint` names.
const DEFAULT_RGB: [u8; 3] = [180, 180, 180];

/// Distance and paint at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SdfSample {
    /// Signed distance (negative inside), or a 1-Lipschitz lower bound of it.
    pub dist: f64,
    /// sRGB colour of the nearest surface.
    pub rgb: [u8; 3],
}

#[derive(Clone, Debug)]
enum Node {
    Box {
        half: DVec3,
    },
    RoundBox {
        inner: DVec3,
        radius: f64,
    },
    Sphere {
        radius: f64,
    },
    Cylinder {
        radius: f64,
        half_length: f64,
        axis: usize,
    },
    Torus {
        major: f64,
        minor: f64,
        axis: usize,
    },
    Union(Vec<Node>),
    Difference(Box<Node>, Vec<Node>),
    Intersection(Vec<Node>),
    /// A pure translation (no rotation): the common case, without the matrix multiply.
    Shifted {
        offset: DVec3,
        child: Box<Node>,
    },
    Moved {
        local_from_parent: DMat3,
        offset: DVec3,
        child: Box<Node>,
    },
    Paint {
        rgb: [u8; 3],
        child: Box<Node>,
    },
}

/// A checked SDF ready to evaluate, with its bounding box.
#[derive(Clone, Debug)]
pub struct Sdf {
    root: Node,
    bounds_min: DVec3,
    bounds_max: DVec3,
}

fn axis_index(a: Axis) -> usize {
    match a {
        Axis::X => 0,
        Axis::Y => 1,
        Axis::Z => 2,
    }
}

/// Rotation matrix for degrees about x, then y, then z (R = Rz·Ry·Rx).
pub fn rotation_xyz_deg(deg: [f64; 3]) -> DMat3 {
    let [x, y, z] = deg.map(f64::to_radians);
    DMat3::from_rotation_z(z) * DMat3::from_rotation_y(y) * DMat3::from_rotation_x(x)
}

fn check_pos(v: f64, what: &str, path: &str) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!(
            "{path}: {what} must be a positive finite number, got {v}"
        ))
    }
}

fn check_finite3(v: [f64; 3], what: &str, path: &str) -> Result<DVec3, String> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(DVec3::from_array(v))
    } else {
        Err(format!("{path}: {what} must be finite, got {v:?}"))
    }
}

fn compile(s: &Shape, path: &str) -> Result<(Node, DVec3, DVec3), String> {
    Ok(match s {
        Shape::Box { half } => {
            let p = format!("{path}.Box");
            let h = DVec3::new(
                check_pos(half[0], "half[0]", &p)?,
                check_pos(half[1], "half[1]", &p)?,
                check_pos(half[2], "half[2]", &p)?,
            );
            (Node::Box { half: h }, -h, h)
        }
        Shape::RoundBox { half, radius } => {
            let p = format!("{path}.RoundBox");
            let h = DVec3::new(
                check_pos(half[0], "half[0]", &p)?,
                check_pos(half[1], "half[1]", &p)?,
                check_pos(half[2], "half[2]", &p)?,
            );
            let r = check_pos(*radius, "radius", &p)?;
            if r > h.min_element() {
                return Err(format!(
                    "{p}: radius {r} exceeds the smallest half size {}",
                    h.min_element()
                ));
            }
            (
                Node::RoundBox {
                    inner: h - DVec3::splat(r),
                    radius: r,
                },
                -h,
                h,
            )
        }
        Shape::Sphere { radius } => {
            let r = check_pos(*radius, "radius", &format!("{path}.Sphere"))?;
            (
                Node::Sphere { radius: r },
                DVec3::splat(-r),
                DVec3::splat(r),
            )
        }
        Shape::Cylinder {
            radius,
            half_length,
            axis,
        } => {
            let p = format!("{path}.Cylinder");
            let r = check_pos(*radius, "radius", &p)?;
            let l = check_pos(*half_length, "half_length", &p)?;
            let a = axis_index(*axis);
            let mut h = DVec3::splat(r);
            h[a] = l;
            (
                Node::Cylinder {
                    radius: r,
                    half_length: l,
                    axis: a,
                },
                -h,
                h,
            )
        }
        Shape::Torus { major, minor, axis } => {
            let p = format!("{path}.Torus");
            let big = check_pos(*major, "major", &p)?;
            let small = check_pos(*minor, "minor", &p)?;
            let a = axis_index(*axis);
            let mut h = DVec3::splat(big + small);
            h[a] = small;
            (
                Node::Torus {
                    major: big,
                    minor: small,
                    axis: a,
                },
                -h,
                h,
            )
        }
        Shape::Union(v) | Shape::Intersection(v) => {
            let is_union = matches!(s, Shape::Union(_));
            let name = if is_union { "Union" } else { "Intersection" };
            if v.is_empty() {
                return Err(format!("{path}.{name}: needs at least one shape"));
            }
            let mut nodes = Vec::with_capacity(v.len());
            let (mut lo, mut hi) = if is_union {
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY))
            } else {
                (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY))
            };
            for (i, c) in v.iter().enumerate() {
                let (n, a, b) = compile(c, &format!("{path}.{name}[{i}]"))?;
                if is_union {
                    lo = lo.min(a);
                    hi = hi.max(b);
                } else {
                    lo = lo.max(a);
                    hi = hi.min(b);
                }
                nodes.push(n);
            }
            if !is_union && lo.cmpgt(hi).any() {
                return Err(format!(
                    "{path}.Intersection: the shapes' bounds do not overlap"
                ));
            }
            (
                if is_union {
                    Node::Union(nodes)
                } else {
                    Node::Intersection(nodes)
                },
                lo,
                hi,
            )
        }
        Shape::Difference { base, minus } => {
            let (b, lo, hi) = compile(base, &format!("{path}.Difference.base"))?;
            let mut cut = Vec::with_capacity(minus.len());
            for (i, c) in minus.iter().enumerate() {
                cut.push(compile(c, &format!("{path}.Difference.minus[{i}]"))?.0);
            }
            (Node::Difference(Box::new(b), cut), lo, hi)
        }
        Shape::Moved {
            offset,
            rotation_deg,
            shape,
        } => {
            let p = format!("{path}.Moved");
            let off = check_finite3(*offset, "offset", &p)?;
            check_finite3(*rotation_deg, "rotation_deg", &p)?;
            let r = rotation_xyz_deg(*rotation_deg);
            let (c, lo, hi) = compile(shape, &p)?;
            let (mut nlo, mut nhi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            for k in 0..8 {
                let corner = DVec3::new(
                    if k & 4 != 0 { hi.x } else { lo.x },
                    if k & 2 != 0 { hi.y } else { lo.y },
                    if k & 1 != 0 { hi.z } else { lo.z },
                );
                let w = r * corner + off;
                nlo = nlo.min(w);
                nhi = nhi.max(w);
            }
            let node = if *rotation_deg == [0.0; 3] {
                Node::Shifted {
                    offset: off,
                    child: Box::new(c),
                }
            } else {
                Node::Moved {
                    local_from_parent: r.transpose(),
                    offset: off,
                    child: Box::new(c),
                }
            };
            (node, nlo, nhi)
        }
        Shape::Paint { rgb, shape } => {
            let (c, lo, hi) = compile(shape, &format!("{path}.Paint"))?;
            (
                Node::Paint {
                    rgb: *rgb,
                    child: Box::new(c),
                },
                lo,
                hi,
            )
        }
    })
}

#[inline]
fn box_dist(p: DVec3, half: DVec3) -> f64 {
    let q = p.abs() - half;
    q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
}

impl Node {
    fn dist(&self, p: DVec3) -> f64 {
        match self {
            Node::Box { half } => box_dist(p, *half),
            Node::RoundBox { inner, radius } => box_dist(p, *inner) - radius,
            Node::Sphere { radius } => p.length() - radius,
            Node::Cylinder {
                radius,
                half_length,
                axis,
            } => {
                let (a, r2) = split_axis(p, *axis);
                let d = [r2.sqrt() - radius, a.abs() - half_length];
                d[0].max(d[1]).min(0.0) + (d[0].max(0.0).powi(2) + d[1].max(0.0).powi(2)).sqrt()
            }
            Node::Torus { major, minor, axis } => {
                let (a, r2) = split_axis(p, *axis);
                let q = r2.sqrt() - major;
                (q * q + a * a).sqrt() - minor
            }
            Node::Union(v) => v.iter().map(|n| n.dist(p)).fold(f64::INFINITY, f64::min),
            Node::Intersection(v) => v
                .iter()
                .map(|n| n.dist(p))
                .fold(f64::NEG_INFINITY, f64::max),
            Node::Difference(b, cut) => cut.iter().map(|n| -n.dist(p)).fold(b.dist(p), f64::max),
            Node::Moved {
                local_from_parent,
                offset,
                child,
            } => child.dist(*local_from_parent * (p - *offset)),
            Node::Shifted { offset, child } => child.dist(p - *offset),
            Node::Paint { child, .. } => child.dist(p),
        }
    }

    fn sample(&self, p: DVec3, paint: [u8; 3]) -> SdfSample {
        match self {
            Node::Union(v) => {
                let mut best = SdfSample {
                    dist: f64::INFINITY,
                    rgb: paint,
                };
                for n in v {
                    let s = n.sample(p, paint);
                    if s.dist < best.dist {
                        best = s;
                    }
                }
                best
            }
            Node::Intersection(v) => {
                let mut best = SdfSample {
                    dist: f64::NEG_INFINITY,
                    rgb: paint,
                };
                for n in v {
                    let s = n.sample(p, paint);
                    if s.dist > best.dist {
                        best = s;
                    }
                }
                best
            }
            Node::Difference(b, cut) => {
                let mut best = b.sample(p, paint);
                for n in cut {
                    let s = n.sample(p, paint);
                    if -s.dist > best.dist {
                        best = SdfSample {
                            dist: -s.dist,
                            rgb: s.rgb,
                        };
                    }
                }
                best
            }
            Node::Moved {
                local_from_parent,
                offset,
                child,
            } => child.sample(*local_from_parent * (p - *offset), paint),
            Node::Shifted { offset, child } => child.sample(p - *offset, paint),
            Node::Paint { rgb, child } => child.sample(p, *rgb),
            _ => SdfSample {
                dist: self.dist(p),
                rgb: paint,
            },
        }
    }
}

/// Coordinate along `axis` and squared distance from it.
#[inline]
fn split_axis(p: DVec3, axis: usize) -> (f64, f64) {
    match axis {
        0 => (p.x, p.y * p.y + p.z * p.z),
        1 => (p.y, p.x * p.x + p.z * p.z),
        _ => (p.z, p.x * p.x + p.y * p.y),
    }
}

impl Node {
    /// A copy that gives bit-identical distance and paint at every point within `r` of `c`,
    /// without the terms that cannot be the minimum (union) or maximum (intersection,
    /// difference) anywhere in that ball. Every node is 1-Lipschitz, so a term's value in the
    /// ball lies within ±r of its value at c; a term dropped here is strictly beaten
    /// everywhere in the ball, and min/max of a subset that holds the extremum is the same
    /// float. `slack` absorbs rounding in the values at c.
    fn prune(&self, c: DVec3, r: f64) -> Node {
        let slack = |v: f64| 1e-9 * (v.abs() + r + 1.0);
        match self {
            Node::Union(v) => {
                let d: Vec<f64> = v.iter().map(|n| n.dist(c)).collect();
                let m = d.iter().copied().fold(f64::INFINITY, f64::min);
                let mut kept: Vec<Node> = v
                    .iter()
                    .zip(&d)
                    .filter(|&(_, &dj)| dj - r <= m + r + slack(dj))
                    .map(|(n, _)| n.prune(c, r))
                    .collect();
                if kept.len() == 1 {
                    kept.pop().expect("one element")
                } else {
                    Node::Union(kept)
                }
            }
            Node::Intersection(v) => {
                let d: Vec<f64> = v.iter().map(|n| n.dist(c)).collect();
                let m = d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let mut kept: Vec<Node> = v
                    .iter()
                    .zip(&d)
                    .filter(|&(_, &dj)| dj + r >= m - r - slack(dj))
                    .map(|(n, _)| n.prune(c, r))
                    .collect();
                if kept.len() == 1 {
                    kept.pop().expect("one element")
                } else {
                    Node::Intersection(kept)
                }
            }
            Node::Difference(b, cuts) => {
                // max(base, −cut_i): cut i matters only where −cut_i ≥ base, impossible in the
                // ball when r − cut_i(c) < base(c) − r.
                let db = b.dist(c);
                let kept: Vec<Node> = cuts
                    .iter()
                    .filter(|n| {
                        let dc = n.dist(c);
                        dc <= 2.0 * r - db + slack(dc) + slack(db)
                    })
                    .map(|n| n.prune(c, r))
                    .collect();
                if kept.is_empty() {
                    b.prune(c, r)
                } else {
                    Node::Difference(Box::new(b.prune(c, r)), kept)
                }
            }
            Node::Moved {
                local_from_parent,
                offset,
                child,
            } => Node::Moved {
                local_from_parent: *local_from_parent,
                offset: *offset,
                child: Box::new(child.prune(*local_from_parent * (c - *offset), r)),
            },
            Node::Shifted { offset, child } => Node::Shifted {
                offset: *offset,
                child: Box::new(child.prune(c - *offset, r)),
            },
            Node::Paint { rgb, child } => Node::Paint {
                rgb: *rgb,
                child: Box::new(child.prune(c, r)),
            },
            leaf => leaf.clone(),
        }
    }

    fn terms(&self) -> usize {
        match self {
            Node::Union(v) | Node::Intersection(v) => v.iter().map(Node::terms).sum(),
            Node::Difference(b, cuts) => b.terms() + cuts.iter().map(Node::terms).sum::<usize>(),
            Node::Moved { child, .. } | Node::Shifted { child, .. } | Node::Paint { child, .. } => {
                child.terms()
            }
            _ => 1,
        }
    }
}

impl Sdf {
    /// An SDF equal to this one, bit for bit in distance and paint, at every point within
    /// `radius` of `centre`, with fewer terms to evaluate (see `Node::prune`). Bounds are
    /// kept from the full shape.
    pub fn pruned(&self, centre: DVec3, radius: f64) -> Sdf {
        Sdf {
            root: self.root.prune(centre, radius),
            bounds_min: self.bounds_min,
            bounds_max: self.bounds_max,
        }
    }

    /// Number of primitives evaluated per distance query.
    pub fn terms(&self) -> usize {
        self.root.terms()
    }

    /// Checks and flattens a shape. `path` names it in error messages
    /// (e.g. `assets[1](wheel).shape`).
    pub fn new(shape: &Shape, path: &str) -> Result<Self, String> {
        let (root, bounds_min, bounds_max) = compile(shape, path)?;
        Ok(Self {
            root,
            bounds_min,
            bounds_max,
        })
    }

    /// Signed distance at `p` (asset coordinates).
    #[inline]
    pub fn dist(&self, p: DVec3) -> f64 {
        self.root.dist(p)
    }

    /// Distance and paint at `p`.
    pub fn sample(&self, p: DVec3) -> SdfSample {
        self.root.sample(p, DEFAULT_RGB)
    }

    /// Outward normal at `p` by a tetrahedral finite difference of step `h` (4 evaluations).
    pub fn normal(&self, p: DVec3, h: f64) -> DVec3 {
        let k = [
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(1.0, 1.0, 1.0),
        ];
        let g = k
            .iter()
            .fold(DVec3::ZERO, |acc, &e| acc + e * self.dist(p + e * h));
        g.normalize_or(DVec3::Y)
    }

    /// Axis-aligned bounds of the shape.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        (self.bounds_min, self.bounds_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_have_expected_distances() {
        let s = Sdf::new(&Shape::Sphere { radius: 2.0 }, "t").unwrap();
        assert!((s.dist(DVec3::new(3.0, 0.0, 0.0)) - 1.0).abs() < 1e-12);
        let b = Sdf::new(
            &Shape::Box {
                half: [1.0, 2.0, 3.0],
            },
            "t",
        )
        .unwrap();
        assert!((b.dist(DVec3::new(0.0, 0.0, 5.0)) - 2.0).abs() < 1e-12);
        assert!((b.dist(DVec3::ZERO) + 1.0).abs() < 1e-12);
        let t = Sdf::new(
            &Shape::Torus {
                major: 2.0,
                minor: 0.5,
                axis: Axis::Y,
            },
            "t",
        )
        .unwrap();
        assert!((t.dist(DVec3::new(2.0, 0.0, 0.0)) + 0.5).abs() < 1e-12);
        assert!((t.dist(DVec3::new(0.0, 1.0, 0.0)) - (5f64.sqrt() - 0.5)).abs() < 1e-12);
        let c = Sdf::new(
            &Shape::Cylinder {
                radius: 1.0,
                half_length: 2.0,
                axis: Axis::X,
            },
            "t",
        )
        .unwrap();
        assert!((c.dist(DVec3::new(3.0, 0.0, 0.0)) - 1.0).abs() < 1e-12);
        assert!((c.dist(DVec3::new(0.0, 0.0, 3.0)) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn csg_and_paint() {
        let shape = Shape::Difference {
            base: Box::new(Shape::Paint {
                rgb: [255, 0, 0],
                shape: Box::new(Shape::Box { half: [1.0; 3] }),
            }),
            minus: vec![Shape::Paint {
                rgb: [0, 0, 255],
                shape: Box::new(Shape::Moved {
                    offset: [1.0, 0.0, 0.0],
                    rotation_deg: [0.0; 3],
                    shape: Box::new(Shape::Sphere { radius: 0.5 }),
                }),
            }],
        };
        let s = Sdf::new(&shape, "t").unwrap();
        assert_eq!(s.sample(DVec3::new(0.0, 0.99, 0.0)).rgb, [255, 0, 0]);
        assert_eq!(s.sample(DVec3::new(0.45, 0.0, 0.0)).rgb, [0, 0, 255]);
        assert!(s.dist(DVec3::new(0.9, 0.0, 0.0)) > 0.0, "carved out");
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = Sdf::new(&Shape::Sphere { radius: f64::NAN }, "assets[0].shape").unwrap_err();
        assert!(
            e.contains("assets[0].shape.Sphere") && e.contains("radius"),
            "{e}"
        );
        let e = Sdf::new(
            &Shape::RoundBox {
                half: [1.0, 0.1, 1.0],
                radius: 0.2,
            },
            "a",
        )
        .unwrap_err();
        assert!(e.contains("exceeds"), "{e}");
        assert!(Sdf::new(&Shape::Union(vec![]), "a").is_err());
    }
}
