//! Placement maths of the `.vox` scene graph: integer affine maps with signed-permutation
//! rotations, and the decoding of a transform node's `_r` (packed rotation byte) and `_t`
//! (translation) into one. Used by the scene-graph walk in [`super::graph`] (see the
//! [parent module](super), step 2, for the conventions).

/// Integer affine map `x ↦ r·x + t` with `r` a signed permutation matrix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Affine {
    pub(super) r: [[i64; 3]; 3],
    pub(super) t: [i64; 3],
}

impl Affine {
    pub(super) const IDENTITY: Self = Self {
        r: [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
        t: [0, 0, 0],
    };

    /// `self ∘ inner`: apply `inner` first.
    pub(super) fn then_inner(&self, inner: &Self) -> Self {
        let mut r = [[0i64; 3]; 3];
        let mut t = self.t;
        for (row, out) in r.iter_mut().enumerate() {
            for (col, v) in out.iter_mut().enumerate() {
                *v = (0..3).map(|k| self.r[row][k] * inner.r[k][col]).sum();
            }
            t[row] += (0..3).map(|k| self.r[row][k] * inner.t[k]).sum::<i64>();
        }
        Self { r, t }
    }
}

/// Decodes MagicaVoxel's packed rotation byte (row-major signed permutation).
fn decode_rotation(byte: u8) -> Option<[[i64; 3]; 3]> {
    let c0 = usize::from(byte & 3);
    let c1 = usize::from((byte >> 2) & 3);
    if c0 > 2 || c1 > 2 || c0 == c1 {
        return None;
    }
    let c2 = 3 - c0 - c1;
    let sign = |bit: u8| if byte & (1 << bit) != 0 { -1 } else { 1 };
    let mut r = [[0i64; 3]; 3];
    r[0][c0] = sign(4);
    r[1][c1] = sign(5);
    r[2][c2] = sign(6);
    Some(r)
}

/// The local transform of a transform node's first frame.
pub(super) fn frame_transform(frame: &dot_vox::Frame, node: usize) -> Result<Affine, String> {
    let mut a = Affine::IDENTITY;
    if let Some(text) = frame.attributes.get("_r") {
        let r = text
            .trim()
            .parse::<u8>()
            .ok()
            .and_then(decode_rotation)
            .ok_or_else(|| format!("node {node}: invalid rotation _r = {text:?}"))?;
        a.r = r;
    }
    if let Some(text) = frame.attributes.get("_t") {
        let parts: Vec<Option<i64>> = text
            .split_whitespace()
            .map(|p| p.parse::<i32>().ok().map(i64::from))
            .collect();
        match parts.as_slice() {
            [Some(x), Some(y), Some(z)] => a.t = [*x, *y, *z],
            _ => return Err(format!("node {node}: invalid translation _t = {text:?}")),
        }
    }
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_byte_decodes_spec_example() {
        // The format description's example: R = [[0,1,0],[0,0,-1],[-1,0,0]],
        // _r = (1 << 0) | (2 << 2) | (0 << 4) | (1 << 5) | (1 << 6).
        let byte = 1 | (2 << 2) | (1 << 5) | (1 << 6);
        assert_eq!(
            decode_rotation(byte),
            Some([[0, 1, 0], [0, 0, -1], [-1, 0, 0]])
        );
        assert_eq!(decode_rotation(4), Some(Affine::IDENTITY.r));
        assert_eq!(decode_rotation(0), None); // both rows point at column 0
        assert_eq!(decode_rotation(3), None); // column 3 does not exist
    }

    #[test]
    fn affine_composition_applies_inner_first() {
        let rot_z90 = Affine {
            r: [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
            t: [10, 0, 0],
        };
        let shift = Affine {
            r: Affine::IDENTITY.r,
            t: [1, 2, 3],
        };
        let m = rot_z90.then_inner(&shift);
        // rot_z90(shift(0)) = rot_z90((1,2,3)) = (-2 + 10, 1, 3)
        assert_eq!(m.t, [8, 1, 3]);
        assert_eq!(m.r, rot_z90.r);
    }
}
