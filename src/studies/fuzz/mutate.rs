//! Seeded mutations of parser inputs: byte-level edits for the binary `.vox` format, with a
//! bias towards the fields that steer a chunk parser (chunk sizes, counts, dimensions), and
//! token-level edits for RON text (numbers swapped for extreme values, brackets and lines
//! dropped or repeated, identifiers exchanged).
//!
//! Pipeline position: none — this feeds the parser fuzzer ([`super::runner`]), which checks
//! that the loaders in front of the pipeline turn every input into a result or an error.
//! The generator is splitmix64, so the same seed gives the same inputs on every machine.

use rtl_model::vectors::rng::Rng;

/// 32-bit values that sit on the boundaries parsers get wrong: zero, one, sign and width edges,
/// powers of two near a model's limits (256 voxels a side, 2^16, 2^24).
const INTERESTING_U32: [u32; 14] = [
    0,
    1,
    2,
    0x7f,
    0x80,
    0xff,
    0x100,
    0x101,
    0xffff,
    0x1_0000,
    0x100_0000,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
];

/// Number literals that break naive numeric code: NaN and infinities, signed zero, the
/// extremes and the smallest subnormal of f64, integers just past 32 and 64 bits.
const INTERESTING_NUMBERS: [&str; 20] = [
    "0",
    "-0.0",
    "1",
    "-1",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "5e-324",
    "255",
    "256",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "0.5",
];

/// Tokens that unbalance or confuse a RON parser when dropped into the text.
const PUNCTUATION: [&str; 11] = ["(", ")", "[", "]", "{", "}", ",", ":", "\"", "/*", "Some("];

/// Longest input a mutation may produce: twice the largest seed keeps growth bounded while
/// still allowing duplicated chunks.
fn size_cap(seed_len: usize) -> usize {
    (seed_len * 2).max(4096)
}

/// One mutated input made from `seed`, with `other` (another seed of the same target) as the
/// donor for splices; `text` picks RON-aware edits in addition to byte edits.
pub fn mutate(rng: &mut Rng, seed: &[u8], other: &[u8], text: bool) -> Vec<u8> {
    let mut data = seed.to_vec();
    // One to four stacked edits: single edits keep most of the structure intact (reaching
    // deep code), stacks reach states no single edit can.
    let edits = 1 + rng.below(4);
    for _ in 0..edits {
        if text && rng.below(3) != 0 {
            text_edit(rng, &mut data);
        } else {
            byte_edit(rng, &mut data, other, text);
        }
        data.truncate(size_cap(seed.len()));
    }
    data
}

fn pos(rng: &mut Rng, len: usize) -> usize {
    rng.below(len as u64 + 1) as usize
}

/// One byte-level edit. On text, flips stay within 7-bit ASCII and the set bytes are ASCII
/// specials, so that most edits still reach the RON parser rather than the UTF-8 check (a
/// share of plain byte edits still tests that check).
fn byte_edit(rng: &mut Rng, data: &mut Vec<u8>, other: &[u8], text: bool) {
    if data.is_empty() {
        data.extend_from_slice(&other[..other.len().min(64)]);
        return;
    }
    let len = data.len();
    match rng.below(8) {
        0 => {
            let i = rng.below(len as u64) as usize;
            let bits = if text && rng.below(4) != 0 { 7 } else { 8 };
            data[i] ^= 1 << rng.below(bits);
        }
        1 => {
            let i = rng.below(len as u64) as usize;
            data[i] = if text && rng.below(4) != 0 {
                [b'\0', b'\\', b'\'', b'"', b'#', b'\n'][rng.below(6) as usize]
            } else {
                [0u8, 1, 0x7f, 0x80, 0xff][rng.below(5) as usize]
            };
        }
        2 => {
            // A 32-bit field after a chunk id: the content size, the children size or the
            // chunk's first field (SIZE's x, XYZI's count, a node id).
            let at = chunk_field(rng, data).unwrap_or_else(|| rng.below(len as u64) as usize);
            put_u32(rng, data, at);
        }
        3 => {
            let at = rng.below(len as u64) as usize;
            put_u32(rng, data, at);
        }
        4 => {
            let a = rng.below(len as u64) as usize;
            let n = 1 + rng.below((len - a).min(256) as u64) as usize;
            data.drain(a..a + n);
        }
        5 => {
            let a = rng.below(len as u64) as usize;
            let n = 1 + rng.below((len - a).min(512) as u64) as usize;
            let copy = data[a..a + n].to_vec();
            let at = pos(rng, len);
            data.splice(at..at, copy);
        }
        6 => data.truncate(rng.below(len as u64) as usize),
        _ => {
            if !other.is_empty() {
                let cut = pos(rng, len);
                let from = rng.below(other.len() as u64) as usize;
                data.truncate(cut);
                data.extend_from_slice(&other[from..]);
            }
        }
    }
}

/// Offset of a 32-bit field right after one of the `.vox` chunk ids found in `data`.
fn chunk_field(rng: &mut Rng, data: &[u8]) -> Option<usize> {
    const IDS: [&[u8; 4]; 9] = [
        b"MAIN", b"PACK", b"SIZE", b"XYZI", b"RGBA", b"nTRN", b"nGRP", b"nSHP", b"LAYR",
    ];
    let id = IDS[rng.below(IDS.len() as u64) as usize];
    let hits: Vec<usize> = data
        .windows(4)
        .enumerate()
        .filter(|(_, w)| w == id)
        .map(|(i, _)| i)
        .collect();
    if hits.is_empty() {
        return None;
    }
    let at = hits[rng.below(hits.len() as u64) as usize];
    Some(at + 4 + 4 * rng.below(4) as usize)
}

fn put_u32(rng: &mut Rng, data: &mut [u8], at: usize) {
    let v = if rng.below(4) == 0 {
        rng.next_u64() as u32
    } else {
        INTERESTING_U32[rng.below(INTERESTING_U32.len() as u64) as usize]
    };
    for (k, b) in v.to_le_bytes().iter().enumerate() {
        if let Some(slot) = data.get_mut(at + k) {
            *slot = *b;
        }
    }
}

/// Byte ranges of the maximal runs of `class` characters.
fn runs(data: &[u8], class: impl Fn(u8) -> bool) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < data.len() {
        if class(data[i]) {
            let start = i;
            while i < data.len() && class(data[i]) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

fn is_number_char(b: u8) -> bool {
    b.is_ascii_digit() || b == b'.' || b == b'-' || b == b'e' || b == b'+'
}

fn is_ident_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

fn text_edit(rng: &mut Rng, data: &mut Vec<u8>) {
    match rng.below(6) {
        0 | 1 => {
            // A number literal (a run that starts with a digit, or a sign and a digit).
            let numbers: Vec<(usize, usize)> = runs(data, is_number_char)
                .into_iter()
                .filter(|&(a, _)| {
                    data[a].is_ascii_digit()
                        || (data[a] == b'-' && data.get(a + 1).is_some_and(u8::is_ascii_digit))
                })
                .collect();
            if let Some(&(a, b)) = numbers.get(rng.below(numbers.len().max(1) as u64) as usize) {
                let with =
                    INTERESTING_NUMBERS[rng.below(INTERESTING_NUMBERS.len() as u64) as usize];
                data.splice(a..b, with.bytes());
            }
        }
        2 => {
            // Exchange one identifier for another of the same text (a field name moved, an
            // enum variant renamed, `Some` where a number was).
            let idents: Vec<(usize, usize)> = runs(data, is_ident_char)
                .into_iter()
                .filter(|&(a, _)| data[a].is_ascii_alphabetic())
                .collect();
            if idents.len() >= 2 {
                let (a, b) = idents[rng.below(idents.len() as u64) as usize];
                let (c, d) = idents[rng.below(idents.len() as u64) as usize];
                let donor = data[c..d].to_vec();
                data.splice(a..b, donor);
            }
        }
        3 => {
            let at = pos(rng, data.len());
            let with = PUNCTUATION[rng.below(PUNCTUATION.len() as u64) as usize];
            data.splice(at..at, with.bytes());
        }
        _ => line_edit(rng, data),
    }
}

/// Drops, repeats or swaps whole lines: whole fields vanish or appear twice.
fn line_edit(rng: &mut Rng, data: &mut Vec<u8>) {
    let mut lines: Vec<Vec<u8>> = data.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
    let n = lines.len() as u64;
    let i = rng.below(n) as usize;
    match rng.below(3) {
        0 => {
            lines.remove(i);
        }
        1 => {
            let copy = lines[i].clone();
            lines.insert(rng.below(n) as usize, copy);
        }
        _ => {
            let j = rng.below(n) as usize;
            lines.swap(i, j);
        }
    }
    *data = lines.join(&b'\n');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_inputs() {
        let seed = b"(a: 1, b: [2.5, -3], c: Some(4))".as_slice();
        let make = |s| {
            let mut rng = Rng::new(s);
            (0..200)
                .map(|_| mutate(&mut rng, seed, b"MAIN", true))
                .collect::<Vec<_>>()
        };
        assert_eq!(make(9), make(9));
        assert_ne!(make(9), make(10));
    }

    #[test]
    fn growth_is_bounded() {
        let seed = vec![7u8; 5000];
        let mut rng = Rng::new(3);
        for _ in 0..2000 {
            assert!(mutate(&mut rng, &seed, &seed, false).len() <= 10_000);
        }
    }

    #[test]
    fn numbers_are_replaced_by_extremes() {
        let seed = b"(x: 12)".as_slice();
        let mut rng = Rng::new(5);
        let seen_extreme = (0..500).any(|_| {
            let m = String::from_utf8_lossy(&mutate(&mut rng, seed, seed, true)).into_owned();
            m.contains("NaN") || m.contains("inf") || m.contains("1e308")
        });
        assert!(seen_extreme);
    }
}
