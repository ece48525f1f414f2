//! The scene-file description of a procedural shape (deserialised from RON).

use serde::{Deserialize, Serialize};

/// A coordinate axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Axis {
    /// x
    X,
    /// y (up)
    #[default]
    Y,
    /// z
    Z,
}

/// A procedural shape in asset coordinates (metres; the asset's octree is centred on the
/// origin). Distances are exact or 1-Lipschitz lower bounds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Shape {
    /// Axis-aligned box with half sizes.
    Box {
        /// Half size per axis.
        half: [f64; 3],
    },
    /// Box with rounded edges: `half` is the outer half size, `radius` the edge radius.
    RoundBox {
        /// Outer half size per axis.
        half: [f64; 3],
        /// Edge radius (at most the smallest half size).
        radius: f64,
    },
    /// Sphere at the origin.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// Capped cylinder along `axis`, centred at the origin.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Half of the length along the axis.
        half_length: f64,
        /// The cylinder's axis.
        #[serde(default)]
        axis: Axis,
    },
    /// Torus around `axis` (the ring lies in the plane perpendicular to it).
    Torus {
        /// Distance from the centre to the tube's centre line.
        major: f64,
        /// Tube radius.
        minor: f64,
        /// The axis the ring goes around.
        #[serde(default)]
        axis: Axis,
    },
    /// Union of shapes (nearest surface wins, including its paint).
    Union(Vec<Shape>),
    /// `base` with every shape of `minus` cut away; cut faces take the cutter's paint.
    Difference {
        /// The shape to cut from.
        base: Box<Shape>,
        /// The cutters.
        minus: Vec<Shape>,
    },
    /// Intersection of shapes.
    Intersection(Vec<Shape>),
    /// A shape rotated (degrees, about x then y then z) and then translated by `offset`.
    Moved {
        /// Translation applied after the rotation.
        #[serde(default)]
        offset: [f64; 3],
        /// Rotation in degrees about x, then y, then z (R = Rz·Ry·Rx).
        #[serde(default)]
        rotation_deg: [f64; 3],
        /// The shape.
        shape: Box<Shape>,
    },
    /// Gives a colour (sRGB bytes) to every surface of the shape that no inner `Paint` names.
    Paint {
        /// sRGB colour.
        rgb: [u8; 3],
        /// The shape.
        shape: Box<Shape>,
    },
}
