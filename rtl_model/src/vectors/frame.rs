//! End-to-end vectors of a small frame: what the host programs (camera position, per
//! instance its rotation, centre, sphere constants, box and memory image) and what every
//! pixel must end with (its hit-buffer word, plus the walker's t and leaf for diagnosis).
//! A whole-pipeline RTL, fed the direction table and these constants, must produce the
//! pixels' words in order.
//!
//! Pipeline position: the root package runs the frame through the units and fills these
//! plain structures; this module only lays them out.

use super::layout::{b, s, u, Direction::*, Layout};
use super::table::{Origin, VectorTable};
use crate::datapath::DatapathConfig;
use crate::fixed::Format;
use crate::units::normal::{NormalMatrix, MAT_FORMAT};
use crate::units::transform::InstanceRaw;
use crate::units::walker::{WalkerPos, WalkerT};

/// One instance as the host programs it for the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameInstance {
    /// Rotation columns and centre (transform unit).
    pub raw: InstanceRaw,
    /// Sphere threshold and inside threshold (sphere unit, `sq`).
    pub threshold: i64,
    /// "Origin may be inside" threshold.
    pub inside: i64,
    /// Δt and reach (sphere unit constants).
    pub delta_t: i64,
    /// Reach (`pos`).
    pub reach: i64,
    /// Half extents of the octree box.
    pub half: [WalkerPos; 3],
    /// Memory image index (the walker table's `images`).
    pub image: usize,
    /// Normal matrix, sQ2.16 row-major (the record stage's normal unit).
    pub nmat: NormalMatrix,
}

/// One pixel's ray and result.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FramePixel {
    /// Column and row.
    pub xy: [u16; 2],
    /// Direction-table entry.
    pub dir: [i64; 3],
    /// Spheres kept (candidates).
    pub candidates: u32,
    /// Walks run (after sorting, before early termination stopped them).
    pub walks: u32,
    /// A leaf was hit.
    pub hit: bool,
    /// The walker's t of the nearest hit, 0 on a miss.
    pub t: WalkerT,
    /// Its leaf coordinates.
    pub voxel: [u32; 3],
    /// The packed hit-buffer word.
    pub word: u128,
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The camera table (one row: the camera, the frame's size and the word of a pixel without
/// candidates), the instance table and the pixel table of a frame.
pub fn frame_tables(
    dp: &DatapathConfig,
    origin: [i64; 3],
    miss_word: u128,
    size: (u32, u32),
    instances: &[FrameInstance],
    pixels: &[FramePixel],
) -> Vec<VectorTable> {
    let mut cl = Layout::new();
    for a in AXES {
        cl.fixed(
            &format!("o_{a}"),
            Input,
            dp.raygen.pos,
            "camera position, m",
        );
    }
    cl.uint("width", Input, 16, "frame width, pixels");
    cl.uint("height", Input, 16, "frame height, pixels");
    cl.uint("instances", Input, 16, "rows of frame_instances.hex");
    cl.uint(
        "miss_word",
        Input,
        dp.hit_record.word_bits(),
        "the hit-buffer word of a pixel without candidates: the check stage writes it without a walk (a constant of the frame, from the host)",
    );
    let mut cam = VectorTable::new(
        "frame_camera",
        "the frame's camera position and size (one row)",
        cl.clone(),
    );
    let mut v: Vec<u128> = origin.map(s).to_vec();
    v.extend([
        u(u64::from(size.0)),
        u(u64::from(size.1)),
        u(instances.len() as u64),
        miss_word,
    ]);
    cam.push_block(Origin::Captured, vec![cl.pack(&v)]);

    let mut il = Layout::new();
    for k in 0..3 {
        for a in AXES {
            il.fixed(
                &format!("axis{k}_{a}"),
                Input,
                dp.raygen.mat,
                "column k of the world-from-local rotation",
            );
        }
    }
    for a in AXES {
        il.fixed(
            &format!("c_{a}"),
            Input,
            dp.raygen.pos,
            "centre (sphere and octree), m",
        );
    }
    il.fixed("threshold", Input, dp.sphere.sq, "sphere threshold T, m^2");
    il.fixed("inside", Input, dp.sphere.sq, "inside threshold, m^2");
    il.fixed("delta_t", Input, dp.sphere.tca, "sphere Δt, m");
    il.fixed(
        "reach",
        Input,
        Format {
            signed: false,
            ..dp.sphere.pos
        },
        "sphere reach, m (unsigned)",
    );
    for a in AXES {
        il.fixed(
            &format!("half_{a}"),
            Input,
            dp.walker.pos,
            "octree half extent, m",
        );
    }
    il.uint(
        "image",
        Input,
        8,
        "memory image index (walker.json parameters.images)",
    );
    for i in AXES {
        for j in AXES {
            il.fixed(
                &format!("nmat_{i}{j}"),
                Input,
                MAT_FORMAT,
                "normal matrix R·diag(1/scale), row = world axis, scaled to a largest |element| of 1 (normal unit)",
            );
        }
    }
    let mut inst = VectorTable::new(
        "frame_instances",
        "one instance per row, in instance order (the instance id is the row): what the host programs for the frame",
        il.clone(),
    );
    let rows = instances
        .iter()
        .map(|i| {
            let mut v: Vec<u128> = Vec::with_capacity(31);
            for col in i.raw.axes {
                v.extend(col.map(s));
            }
            v.extend(i.raw.centre.map(s));
            v.extend([s(i.threshold), s(i.inside), s(i.delta_t), s(i.reach)]);
            v.extend(i.half.map(|h| s(h.raw)));
            v.push(u(i.image as u64));
            v.extend(i.nmat.elements().map(|e| s(i64::from(e))));
            il.pack(&v)
        })
        .collect();
    inst.push_block(Origin::Captured, rows);

    let mut pl = Layout::new();
    pl.uint("pixel_x", Input, 16, "column");
    pl.uint("pixel_y", Input, 16, "row");
    for a in AXES {
        pl.fixed(
            &format!("dir_{a}"),
            Input,
            dp.raygen.dir,
            "direction-table entry",
        );
    }
    pl.uint("candidates", Output, 16, "spheres kept");
    pl.uint("walks", Output, 16, "walks run before early termination");
    pl.flag("hit", Output, "a leaf was hit");
    pl.fixed(
        "t",
        Output,
        dp.walker.t,
        "walker t of the nearest hit, m (0 on a miss)",
    );
    for a in AXES {
        pl.uint(
            &format!("voxel_{a}"),
            Output,
            20,
            "leaf coordinate of the nearest hit",
        );
    }
    pl.uint(
        "word",
        Output,
        dp.hit_record.word_bits(),
        "the hit-buffer word (layout in hit_record.json parameters.record_layout)",
    );
    let mut px = VectorTable::new(
        "frame_pixels",
        "one pixel per row in raster order (frame 0: every pixel traced): its direction in; candidate and walk counts, the nearest hit and the hit-buffer word out",
        pl.clone(),
    );
    let rows = pixels
        .iter()
        .map(|p| {
            let mut v = vec![u(u64::from(p.xy[0])), u(u64::from(p.xy[1]))];
            v.extend(p.dir.map(s));
            v.extend([
                u(u64::from(p.candidates)),
                u(u64::from(p.walks)),
                b(p.hit),
                s(p.t.raw),
            ]);
            v.extend(p.voxel.map(|c| u(u64::from(c))));
            v.push(p.word);
            pl.pack(&v)
        })
        .collect();
    px.push_block(Origin::Captured, rows);
    px.param("width", size.0);
    px.param("height", size.1);
    vec![cam, inst, px]
}
