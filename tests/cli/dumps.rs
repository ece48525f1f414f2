//! The hit dumps of the tiny run: the binary dump follows `src/output/dump.rs` (a 32-byte
//! header, the record size it states, misses with instance 65535 and t = +inf), and the CSV
//! dump has a header and one line per pixel and frame, agreeing with the binary one.
//!
//! Pipeline position: the output stage's hit dumps (`src/output/dump.rs`), read back from a
//! `sim --dump-hits` run.

use super::{tiny_run, Tmp, FRAMES, H, W};

/// Header bytes of the binary dump.
const HEADER: usize = 32;
/// Bytes of the fields documented per record (the rest of a record, if any, is padding).
const FIELDS: usize = 36;
fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// One record of the binary dump, as documented in `src/output/dump.rs`.
#[derive(Debug)]
struct Record {
    frame: u32,
    hit: u8,
    spheres: u8,
    instance: u16,
    t: f64,
}

/// The records of a binary dump; the record stride is the file's actual one, so the field
/// checks still run when the header's record size disagrees with the file (checked apart).
fn records(bytes: &[u8]) -> Vec<Record> {
    let n = (W * H * FRAMES) as usize;
    let body = bytes.len() - HEADER;
    assert_eq!(body % n, 0, "the records do not divide the file evenly");
    let stride = body / n;
    assert!(stride >= FIELDS, "records of {stride} bytes are too short");
    (0..n)
        .map(|k| {
            let r = &bytes[HEADER + k * stride..HEADER + (k + 1) * stride];
            Record {
                frame: u32_at(r, 0),
                hit: r[4],
                spheres: r[5],
                instance: u16::from_le_bytes([r[6], r[7]]),
                t: f64::from_le_bytes(r[8..16].try_into().unwrap()),
            }
        })
        .collect()
}

#[test]
fn binary_dump_header_and_size() {
    let t = Tmp::new("binary_dump_header_and_size");
    tiny_run(&t, "hits.bin", &[]);
    let b = t.read("hits.bin");
    assert!(b.len() >= HEADER, "dump of {} bytes", b.len());
    assert_eq!(&b[..8], b"SVOHITS1", "magic");
    assert_eq!(u32_at(&b, 8), 1, "version");
    assert_eq!((u32_at(&b, 12), u32_at(&b, 16)), (W, H), "dimensions");
    assert_eq!(u32_at(&b, 20), FRAMES, "frames");
    let record = u32_at(&b, 24) as usize;
    assert_eq!(record, 40, "record size in the header");
    assert_eq!(u32_at(&b, 28), 0, "reserved");
    let n = (W * H * FRAMES) as usize;
    assert_eq!(
        b.len(),
        HEADER + n * record,
        "the file should hold {n} records of {record} bytes (the header's size) after the \
         {HEADER}-byte header; its records are actually {} bytes each",
        (b.len() - HEADER) as f64 / n as f64
    );
}

#[test]
fn binary_dump_records() {
    let t = Tmp::new("binary_dump_records");
    tiny_run(&t, "hits.bin", &[]);
    let recs = records(&t.read("hits.bin"));
    let (mut hits, mut misses) = (0, 0);
    for (k, r) in recs.iter().enumerate() {
        assert_eq!(r.frame, k as u32 / (W * H), "record {k}: frame");
        assert!(r.hit <= 1 && r.spheres <= 2, "record {k}: {r:?}");
        if r.hit == 0 {
            misses += 1;
            assert_eq!(r.instance, 65535, "record {k}: a miss has no instance");
            assert!(
                r.t.is_infinite() && r.t > 0.0,
                "record {k}: a miss has t = +inf"
            );
        } else {
            hits += 1;
            assert!(r.instance < 8, "record {k}: instance {}", r.instance);
            assert!(r.t.is_finite() && r.t > 0.0, "record {k}: t {}", r.t);
        }
    }
    assert!(
        hits > 0 && misses > 0,
        "{hits} hits, {misses} misses: the car should fill part of the image"
    );
}

#[test]
fn csv_dump_has_a_line_per_pixel_and_frame() {
    let t = Tmp::new("csv_dump_has_a_line_per_pixel_and_frame");
    tiny_run(&t, "hits.csv", &[]);
    let text = String::from_utf8(t.read("hits.csv")).expect("the CSV is UTF-8");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1 + (W * H * FRAMES) as usize, "line count");
    assert!(
        lines[0].starts_with("frame,x,y,hit,"),
        "header {}",
        lines[0]
    );
    let cols = lines[0].split(',').count();
    for (k, l) in lines[1..].iter().enumerate() {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f.len(), cols, "line {}: {l}", k + 2);
        let frame = k as u32 / (W * H);
        let (x, y) = (k as u32 % W, k as u32 % (W * H) / W);
        assert_eq!(
            (f[0], f[1], f[2]),
            (
                frame.to_string().as_str(),
                x.to_string().as_str(),
                y.to_string().as_str()
            ),
            "line {}",
            k + 2
        );
        if f[3] == "0" {
            assert_eq!(f[5], "-1", "line {}: a miss has instance -1", k + 2);
        }
    }

    // Same hits and instances as the binary dump of the same run.
    let tb = Tmp::new("csv_dump_has_a_line_per_pixel_and_frame_bin");
    tiny_run(&tb, "hits.bin", &[]);
    let recs = records(&tb.read("hits.bin"));
    for (k, (l, r)) in lines[1..].iter().zip(&recs).enumerate() {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f[3], r.hit.to_string(), "pixel {k}: hit");
        if r.hit == 1 {
            assert_eq!(f[5], r.instance.to_string(), "pixel {k}: instance");
            assert_eq!(f[6].parse::<f64>().ok(), Some(r.t), "pixel {k}: t");
        }
    }
}
