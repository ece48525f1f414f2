//! Step 1 of the `.vox` loader: the bytes become `dot_vox`'s data, behind a guard against
//! chunk trees nested deep enough to overflow `dot_vox`'s recursive parser and a
//! `catch_unwind` around the parse (see the [parent module](super), step 1).

use std::path::Path;

use super::{VoxError, MAX_CHUNK_NESTING};

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<dot_vox::DotVoxData, VoxError> {
    if let Some(depth) = chunk_nesting_exceeds(bytes, MAX_CHUNK_NESTING) {
        return Err(VoxError::Parse {
            path: path.to_path_buf(),
            message: format!("chunks nested at least {depth} deep (at most {MAX_CHUNK_NESTING})"),
        });
    }
    match std::panic::catch_unwind(|| dot_vox::load_bytes(bytes)) {
        Ok(Ok(data)) => Ok(data),
        Ok(Err(message)) => Err(VoxError::Parse {
            path: path.to_path_buf(),
            message: message.to_string(),
        }),
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "non-text panic payload".to_string());
            Err(VoxError::Panicked {
                path: path.to_path_buf(),
                message,
            })
        }
    }
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Walks the RIFF-style chunk tree the way `dot_vox` does (header: id, content size, children
/// size; children parsed as a chunk list when their size is non-zero) and returns the nesting
/// depth reached if it exceeds `limit`. It follows every chunk `dot_vox` could descend into
/// (and possibly more), so `dot_vox`'s recursion is never deeper than what passed here.
/// Iterative, so the check itself cannot overflow the stack.
fn chunk_nesting_exceeds(bytes: &[u8], limit: usize) -> Option<usize> {
    const HEADER: usize = 12;
    // (start, end, depth) of chunk lists still to scan; the file's chunks start after
    // "VOX " and the version.
    let mut lists = vec![(8usize.min(bytes.len()), bytes.len(), 1usize)];
    while let Some((mut pos, end, depth)) = lists.pop() {
        while end.saturating_sub(pos) >= HEADER {
            let (Some(content), Some(children)) =
                (read_u32(bytes, pos + 4), read_u32(bytes, pos + 8))
            else {
                break;
            };
            let children_start = (pos + HEADER).checked_add(content as usize);
            let next = children_start.and_then(|s| s.checked_add(children as usize));
            let (Some(children_start), Some(next)) = (children_start, next) else {
                break;
            };
            if next > end {
                break; // dot_vox fails on the short read and stops this list here too
            }
            if children > 0 {
                if depth + 1 > limit {
                    return Some(depth + 1);
                }
                lists.push((children_start, next, depth + 1));
            }
            pos = next;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::assets::vox::load_vox_bytes;

    #[test]
    fn deep_chunk_nesting_is_rejected_before_parsing() {
        let levels = 100_000usize;
        let mut b = b"VOX ".to_vec();
        b.extend(150u32.to_le_bytes());
        for l in 0..levels {
            b.extend(b"MAIN");
            b.extend(0u32.to_le_bytes());
            b.extend((((levels - l - 1) * 12) as u32).to_le_bytes());
        }
        assert_eq!(
            chunk_nesting_exceeds(&b, MAX_CHUNK_NESTING),
            Some(MAX_CHUNK_NESTING + 1)
        );
        let err = load_vox_bytes(&b, Path::new("nested.vox"), None).unwrap_err();
        assert!(matches!(err, VoxError::Parse { .. }), "{err}");
        assert!(err.to_string().contains("nested.vox"), "{err}");
    }
}
