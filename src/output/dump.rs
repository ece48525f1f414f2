//! `--dump-hits`: every pixel's hit record, so other tools can compare pixel by pixel.
//!
//! Binary format (all little-endian), documented in `docs/hit-dump.md`:
//! header (32 bytes): magic `SVOHITS1`, u32 version = 1, u32 width, u32 height,
//! u32 frames, u32 record size = 40, u32 reserved = 0;
//! then per frame, per pixel row-major, a 40-byte record:
//! u32 frame, u8 hit, u8 spheres (0/1/2), u16 instance (65535 = none), f64 t (+inf on miss),
//! u32 voxel x, y, z, i8 face normal x, y, z (−1/0/1, world axes rounded), u8 reserved,
//! u8 colour r, g, b, a, u16 pixel x, u16 pixel y (records are 8-byte aligned, t too).
//! With a `.csv` file name the same fields are written as CSV with a header line instead.

use crate::models::reference::HitRecord;
use std::io::Write;

/// Bytes of one binary record.
pub const RECORD_BYTES: u32 = 40;
/// Magic of the binary format.
pub const MAGIC: &[u8; 8] = b"SVOHITS1";

/// Writes the binary header.
pub fn write_header(
    w: &mut impl Write,
    width: u32,
    height: u32,
    frames: u32,
) -> std::io::Result<()> {
    w.write_all(MAGIC)?;
    for v in [1u32, width, height, frames, RECORD_BYTES, 0] {
        w.write_all(&v.to_le_bytes())?;
    }
    Ok(())
}

fn face(rec: &HitRecord) -> [i8; 3] {
    rec.face_normal.map(|v| v.round().clamp(-1.0, 1.0) as i8)
}

/// Writes one frame's records in the binary format.
pub fn write_frame(
    w: &mut impl Write,
    frame: u32,
    width: u32,
    records: &[HitRecord],
) -> std::io::Result<()> {
    let mut buf = Vec::with_capacity(records.len() * RECORD_BYTES as usize);
    for (k, r) in records.iter().enumerate() {
        // Resolution is at most 16384 per side, so pixel coordinates fit 16 bits.
        let (x, y) = ((k as u32 % width) as u16, (k as u32 / width) as u16);
        buf.extend_from_slice(&frame.to_le_bytes());
        buf.push(u8::from(r.hit));
        buf.push(r.spheres.code());
        buf.extend_from_slice(&r.instance.to_le_bytes());
        buf.extend_from_slice(&r.t.to_le_bytes());
        for v in r.voxel {
            buf.extend_from_slice(&v.to_le_bytes());
        }
        buf.extend(face(r).map(|v| v as u8));
        buf.push(0);
        buf.extend_from_slice(&r.colour);
        buf.extend_from_slice(&x.to_le_bytes());
        buf.extend_from_slice(&y.to_le_bytes());
    }
    debug_assert_eq!(buf.len(), records.len() * RECORD_BYTES as usize);
    w.write_all(&buf)
}

/// CSV header line.
pub const CSV_HEADER: &str =
    "frame,x,y,hit,spheres,instance,t,voxel_x,voxel_y,voxel_z,face_x,face_y,face_z,r,g,b,a";

/// Writes one frame's records as CSV lines (t printed with 17 significant digits, so it
/// round-trips).
pub fn write_frame_csv(
    w: &mut impl Write,
    frame: u32,
    width: u32,
    records: &[HitRecord],
) -> std::io::Result<()> {
    for (k, r) in records.iter().enumerate() {
        let (x, y) = (k as u32 % width, k as u32 / width);
        let f = face(r);
        let inst = if r.hit { i32::from(r.instance) } else { -1 };
        writeln!(
            w,
            "{frame},{x},{y},{},{},{inst},{:.16e},{},{},{},{},{},{},{},{},{},{}",
            u8::from(r.hit),
            r.spheres.code(),
            r.t,
            r.voxel[0],
            r.voxel[1],
            r.voxel[2],
            f[0],
            f[1],
            f[2],
            r.colour[0],
            r.colour[1],
            r.colour[2],
            r.colour[3]
        )?;
    }
    Ok(())
}
