//! Step 2 of the `.vox` loader: the scene graph (`nTRN` / `nGRP` / `nSHP`) is walked from
//! node 0 into a list of visible model instances with their transforms, and every voxel of
//! every instance is placed in our axes (see the [parent module](super), steps 2 and 3, for
//! the conventions).

use super::transform::{frame_transform, Affine};

/// One model instance to compose.
#[derive(Clone, Copy, Debug)]
pub(super) struct Placement {
    pub(super) model: usize,
    pub(super) transform: Affine,
}

impl Placement {
    /// Model `model` alone, untransformed.
    pub(super) fn alone(model: usize) -> Self {
        Self {
            model,
            transform: Affine::IDENTITY,
        }
    }
}

fn is_hidden(attributes: &dot_vox::Dict) -> bool {
    attributes.get("_hidden").is_some_and(|v| v.trim() == "1")
}

/// Every visible model instance with its model-to-world transform (vox axes), in scene order.
pub(super) fn placements(data: &dot_vox::DotVoxData) -> Result<Vec<Placement>, String> {
    if data.scenes.is_empty() {
        // Pre-scene-graph files (or files saved without one): each model untransformed.
        return Ok((0..data.models.len())
            .map(|model| Placement {
                model,
                transform: Affine::IDENTITY,
            })
            .collect());
    }
    let n = data.scenes.len();
    let mut seen = vec![false; n];
    let mut out = Vec::new();
    // Depth-first with an explicit stack, children pushed in reverse so they are visited in
    // file order (which decides who keeps a voxel where instances overlap).
    let mut stack = vec![(0usize, Affine::IDENTITY)];
    while let Some((node, parent)) = stack.pop() {
        let Some(scene_node) = data.scenes.get(node) else {
            return Err(format!(
                "reference to node {node}, but the file has {n} nodes"
            ));
        };
        // A tree visits each node once; a repeat means a cycle or a shared subtree, which
        // MagicaVoxel never writes and which could make the walk endless or exponential.
        if std::mem::replace(&mut seen[node], true) {
            return Err(format!("node {node} is referenced more than once"));
        }
        match scene_node {
            dot_vox::SceneNode::Transform {
                attributes,
                frames,
                child,
                layer_id,
            } => {
                let layer_hidden = data
                    .layers
                    .get(*layer_id as usize)
                    .is_some_and(|layer| layer.hidden());
                if is_hidden(attributes) || layer_hidden {
                    continue;
                }
                let local = match frames.first() {
                    Some(frame) => frame_transform(frame, node)?,
                    None => Affine::IDENTITY,
                };
                stack.push((*child as usize, parent.then_inner(&local)));
            }
            dot_vox::SceneNode::Group {
                attributes,
                children,
            } => {
                if is_hidden(attributes) {
                    continue;
                }
                stack.extend(children.iter().rev().map(|&c| (c as usize, parent)));
            }
            dot_vox::SceneNode::Shape { attributes, models } => {
                if is_hidden(attributes) {
                    continue;
                }
                if let Some(shape_model) = models.first() {
                    let model = shape_model.model_id as usize;
                    if model >= data.models.len() {
                        return Err(format!(
                            "shape node {node} uses model {model}, but the file has {} models",
                            data.models.len()
                        ));
                    }
                    out.push(Placement {
                        model,
                        transform: parent,
                    });
                }
            }
        }
    }
    Ok(out)
}

/// Every voxel of every placement in our axes (y up), with its palette index, in scene order.
pub(super) fn place_voxels(
    data: &dot_vox::DotVoxData,
    placements: &[Placement],
) -> Vec<([i64; 3], u8)> {
    let total: usize = placements
        .iter()
        .filter_map(|p| data.models.get(p.model))
        .map(|m| m.voxels.len())
        .sum();
    let mut out = Vec::with_capacity(total);
    for p in placements {
        let Some(model) = data.models.get(p.model) else {
            continue;
        };
        let size = [model.size.x, model.size.y, model.size.z];
        // Doubled coordinates keep the half-voxel offset exact: 2·(v + ½ − floor(s/2)).
        let pivot2 = size.map(|s| 2 * i64::from(s / 2));
        let Affine { r, t } = p.transform;
        for v in &model.voxels {
            let d = [
                2 * i64::from(v.x) + 1 - pivot2[0],
                2 * i64::from(v.y) + 1 - pivot2[1],
                2 * i64::from(v.z) + 1 - pivot2[2],
            ];
            // Each component of r·d is odd, so div_euclid(2) is the floor of a half-integer.
            let w: [i64; 3] = std::array::from_fn(|row| {
                (r[row][0] * d[0] + r[row][1] * d[1] + r[row][2] * d[2]).div_euclid(2) + t[row]
            });
            // z-up to y-up, cell for cell: the cell [y, y+1) becomes [−y−1, −y).
            out.push(([w[0], w[2], -w[1] - 1], v.i));
        }
    }
    out
}
