//! The walker's memory images as vector tables: the synthetic octrees of the adversarial and
//! random walks, each image's own node and attribute tables, and the concatenated memory a
//! walker testbench loads (`walker_nodes.hex`, `walker_attrs.hex`: every image one after the
//! other, at the bases the walk rows carry).
//!
//! Pipeline position: beside the walker stage (`super`), whose walks read these images.

use super::{NamedImage, WalkerStage};
use crate::svo::{LeafAttr, LeafSet, SvoImage};
use crate::vectors::layout::{u, Direction::*, Layout};
use crate::vectors::table::{Origin, VectorTable};
use crate::vectors::VectorError;

fn attr(c: [u32; 3]) -> LeafAttr {
    LeafAttr::new(
        [c[0] as u8 * 16, c[1] as u8 * 16, c[2] as u8 * 16, 255],
        [0.0, 0.0, 1.0],
    )
}

/// Voxels of the deepest synthetic octree (depth [`MAX_DEPTH`](crate::svo::MAX_DEPTH)): two
/// opposite corners and three near the centre, so walks there fill the stack.
pub(super) const DEEP_VOXELS: [[u32; 3]; 5] = [
    [0, 0, 0],
    [(1 << 20) - 1, (1 << 20) - 1, (1 << 20) - 1],
    [1 << 19, 1 << 19, 1 << 19],
    [(1 << 19) - 1, 1 << 19, (1 << 19) - 1],
    [(1 << 19) + 12345, (1 << 19) - 777, 1 << 18],
];

/// The synthetic octrees: a full depth-3 cube, two opposite corner voxels at depth 4, a
/// sparse lattice at depth 4, and five voxels at the deepest level (depth 20).
pub(super) fn synthetic_images() -> Result<Vec<NamedImage>, VectorError> {
    let full: Vec<[u32; 3]> = (0..512).map(|i| [i & 7, (i >> 3) & 7, i >> 6]).collect();
    let corners = vec![[0, 0, 0], [15, 15, 15]];
    let lattice: Vec<[u32; 3]> = (0..4096u32)
        .map(|i| [i & 15, (i >> 4) & 15, i >> 8])
        .filter(|c| (c[0] + 2 * c[1] + c[2]) % 7 == 0 && c[1] > 3)
        .collect();
    [
        ("adv_cube3", 3, full),
        ("adv_corners4", 4, corners),
        ("adv_lattice4", 4, lattice),
        ("adv_deep20", crate::svo::MAX_DEPTH, DEEP_VOXELS.to_vec()),
    ]
    .into_iter()
    .map(|(name, depth, coords)| {
        let set = LeafSet::from_coords(
            depth,
            coords.into_iter().map(|c| (c, attr(c.map(|v| v & 15)))),
        )?;
        Ok(NamedImage {
            name: name.to_string(),
            image: SvoImage::build(&set)?,
        })
    })
    .collect()
}

impl WalkerStage {
    /// The concatenated memory a walker testbench loads: every image's node words
    /// (`walker_nodes`, 32 bits) and leaf attributes (`walker_attrs`, 64 bits: normal word
    /// high, colour word low), synthetic images included, in image order.
    fn memory_tables(&self) -> Vec<VectorTable> {
        let mut nl = Layout::new();
        nl.uint("word", Output, 32, "node memory word");
        let mut nodes = VectorTable::new(
            "walker_nodes",
            "every walker image's node words one after the other (walker.json parameters.images gives each image's node_base)",
            nl.clone(),
        );
        nodes.package = false;
        let mut al = Layout::new();
        al.uint("colour_rgba8", Output, 32, "R in bits 7..0, then G, B, A");
        al.uint(
            "normal_oct16",
            Output,
            32,
            "octahedral normal, u in bits 15..0, v above (snorm16)",
        );
        let mut attrs = VectorTable::new(
            "walker_attrs",
            "every walker image's leaf attributes one after the other (walker.json parameters.images gives each image's attr_base)",
            al.clone(),
        );
        attrs.package = false;
        nodes.push_block(
            Origin::Table,
            self.images
                .iter()
                .flat_map(|n| n.image.nodes().iter())
                .map(|&w| nl.pack(&[u(u64::from(w))]))
                .collect(),
        );
        attrs.push_block(
            Origin::Table,
            self.images
                .iter()
                .flat_map(|n| n.image.attrs().iter())
                .map(|x| al.pack(&[u(u64::from(x.colour_rgba8)), u(u64::from(x.normal_oct16))]))
                .collect(),
        );
        vec![nodes, attrs]
    }

    /// The memory tables of every image: node words (32 bits, `docs/svo-format.md`) and, for
    /// the scene's images (the end-to-end frame shades from them), leaf attributes (64 bits:
    /// normal word high, colour word low).
    pub fn image_tables(&self) -> Vec<VectorTable> {
        let mut out = self.memory_tables();
        for (i, n) in self.images.iter().enumerate() {
            let mut nl = Layout::new();
            nl.uint("word", Output, 32, "node memory word");
            let mut t = VectorTable::new(
                &format!("svo_{}_nodes", n.name),
                "SVO node memory: child descriptors, leaf slots (attribute indices) and far words",
                nl.clone(),
            );
            t.package = false;
            t.push_block(
                Origin::Table,
                n.image
                    .nodes()
                    .iter()
                    .map(|&w| nl.pack(&[u(u64::from(w))]))
                    .collect(),
            );
            out.push(t);
            if i >= self.synthetic {
                continue;
            }
            let mut al = Layout::new();
            al.uint("colour_rgba8", Output, 32, "R in bits 7..0, then G, B, A");
            al.uint(
                "normal_oct16",
                Output,
                32,
                "octahedral normal, u in bits 15..0, v above (snorm16)",
            );
            let mut a = VectorTable::new(
                &format!("svo_{}_attrs", n.name),
                "SVO leaf attributes, one per leaf, indexed by the walker's attr",
                al.clone(),
            );
            a.package = false;
            a.push_block(
                Origin::Table,
                n.image
                    .attrs()
                    .iter()
                    .map(|x| al.pack(&[u(u64::from(x.colour_rgba8)), u(u64::from(x.normal_oct16))]))
                    .collect(),
            );
            out.push(a);
        }
        out
    }
}
