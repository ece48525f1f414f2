//! `sim render --dump-hits`: every pixel's ray and hit in the model's own voxel coordinates,
//! so other tools (the OpenVDB peer of `tests/openvdb_peer/`) can compare pixel by pixel.
//!
//! Pipeline position: output of `sim render` (`crate::run::render`; the records are
//! `crate::models::reference::model_render`'s). Binary format (all
//! little-endian), documented in `docs/render.md` §5: header (32 bytes): magic `SVOMHIT1`,
//! u32 version = 1, u32 width, u32 height, u32 record size = 80, u32 projection (0 pinhole,
//! 1 orthographic), u32 reserved = 0; then per pixel, row-major, an 80-byte record:
//! f64 origin x, y, z; f64 direction x, y, z; f64 t (−1 on a miss); i32 voxel x, y, z (model
//! indices, 0 on a miss); u8 hit; i8 face x, y, z; u8 r, g, b, a; u16 pixel x; u16 pixel y.
//! With a `.csv` file name the same fields are written as CSV with a header line instead.
//! The file is written by the one output writer (`super::writer`).

use std::io::Write;
use std::path::Path;

use crate::models::reference::model_render::{ModelHit, ModelRender, Projection};

/// Magic of the binary format.
pub const MAGIC: &[u8; 8] = b"SVOMHIT1";
/// Bytes of one binary record.
pub const RECORD_BYTES: u32 = 80;
/// Bytes of the header.
pub const HEADER_BYTES: u32 = 32;
/// The CSV header line.
pub const CSV_HEADER: &str = "x,y,hit,t,voxel_x,voxel_y,voxel_z,face_x,face_y,face_z,r,g,b,a,origin_x,origin_y,origin_z,dir_x,dir_y,dir_z";

/// Code of a projection in the header.
pub fn projection_code(p: Projection) -> u32 {
    match p {
        Projection::Pinhole { .. } => 0,
        Projection::Ortho { .. } => 1,
    }
}

/// One record in the binary format.
pub fn encode_record(out: &mut Vec<u8>, r: &ModelHit, x: u16, y: u16) {
    for v in r.origin.iter().chain(&r.dir).chain([&r.t]) {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for v in r.voxel {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.push(u8::from(r.hit));
    out.extend(r.face.map(|v| v as u8));
    out.extend_from_slice(&r.rgba);
    out.extend_from_slice(&x.to_le_bytes());
    out.extend_from_slice(&y.to_le_bytes());
}

/// The whole binary file.
pub fn encode_binary(render: &ModelRender, projection: Projection) -> Vec<u8> {
    let n = render.hits.len();
    let mut out = Vec::with_capacity(HEADER_BYTES as usize + n * RECORD_BYTES as usize);
    out.extend_from_slice(MAGIC);
    let header = [
        1u32,
        render.width,
        render.height,
        RECORD_BYTES,
        projection_code(projection),
        0,
    ];
    for v in header {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for (k, r) in render.hits.iter().enumerate() {
        // Sides are at most 16384, so pixel coordinates fit 16 bits.
        let (x, y) = (k as u32 % render.width, k as u32 / render.width);
        encode_record(&mut out, r, x as u16, y as u16);
    }
    out
}

/// The whole CSV file (floats as `{:.16e}`, which round-trips; t of a miss is −1).
pub fn encode_csv(render: &ModelRender) -> Vec<u8> {
    let mut out = Vec::with_capacity(render.hits.len() * 200);
    out.extend_from_slice(CSV_HEADER.as_bytes());
    out.push(b'\n');
    for (k, r) in render.hits.iter().enumerate() {
        let (x, y) = (k as u32 % render.width, k as u32 / render.width);
        let [vx, vy, vz] = r.voxel;
        let [fx, fy, fz] = r.face;
        let [cr, cg, cb, ca] = r.rgba;
        let [ox, oy, oz] = r.origin;
        let [dx, dy, dz] = r.dir;
        // Writing into a Vec cannot fail.
        let _ = writeln!(
            out,
            "{x},{y},{},{:.16e},{vx},{vy},{vz},{fx},{fy},{fz},{cr},{cg},{cb},{ca},{ox:.16e},{oy:.16e},{oz:.16e},{dx:.16e},{dy:.16e},{dz:.16e}",
            u8::from(r.hit),
            r.t
        );
    }
    out
}

/// The dump's bytes for `path` (CSV if its extension is `csv`, any case, else binary); the
/// caller writes them through the one output writer (`super::writer`).
pub fn encode_dump(path: &Path, render: &ModelRender, projection: Projection) -> Vec<u8> {
    let csv = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    if csv {
        encode_csv(render)
    } else {
        encode_binary(render, projection)
    }
}
