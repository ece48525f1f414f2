//! Walker vectors: whole walks of the fixed-point octree walker
//! (`units::walker::walk_fixed_visiting`), one row per walk (inputs, result, step and fetch
//! counts, where its visits start), one row per visited node in a second table, and the SVO
//! memory images the walks read, as memory tables.
//!
//! The walker is iterative (its cycles depend on the octree), so it has no fixed latency and
//! no RTL here; these rows check a walker RTL's path node by node.
//!
//! Images: the scene's assets (captured walks) followed by small synthetic octrees for the
//! adversarial and random walks. Adversarial walks: axis-parallel rays along every axis both
//! ways, −0 components (zero and negative flags both set), origins on the box's faces, on
//! its centre planes and on inner node planes, rays through corners and the centre, origins
//! inside solid and empty voxels, boxes behind the origin, zero axes outside the slab, and a
//! ray with all three axes zero.

use super::dedup;
use crate::datapath::DatapathConfig;
use crate::fixed::{from_f64, Format, Overflows, SignalId};
use crate::svo::{LeafAttr, LeafSet, SvoImage};
use crate::units::reciprocal::ReciprocalUnit;
use crate::units::walker::{
    walk_fixed_visiting, WalkOutcome, WalkerConfig, WalkerInput, WalkerPos, WalkerStats,
};
use crate::vectors::layout::{b, s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{plan_rows, spread, Origin, VectorTable};
use crate::vectors::VectorError;

/// One walk: which image, and the walker's inputs (raw codes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WalkTxn {
    /// Index into the stage's images.
    pub image: usize,
    /// Origin, 1/|d|, zero and negative flags, half extents.
    pub input: WalkerInput,
}

/// A named memory image.
pub struct NamedImage {
    /// File-name stem (`[a-z0-9_]`).
    pub name: String,
    /// The image.
    pub image: SvoImage,
}

/// The walker stage: its configuration, the images, and the host path that turns an f64
/// ray into walker inputs (direction codes through the reciprocal unit).
pub struct WalkerStage {
    cfg: WalkerConfig,
    dir: Format,
    recip: ReciprocalUnit,
    images: Vec<NamedImage>,
    /// Index of the first synthetic image.
    synthetic: usize,
}

const AXES: [&str; 3] = ["x", "y", "z"];
/// Bits of a coordinate and of a level (depth ≤ 20).
const COORD_BITS: u32 = 20;
const LEVEL_BITS: u32 = 5;
const COUNT_BITS: u32 = 32;

/// A stem usable in a file name: lower-case letters, digits and `_`.
pub fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        "image".into()
    } else {
        s
    }
}

fn attr(c: [u32; 3]) -> LeafAttr {
    LeafAttr::new(
        [c[0] as u8 * 16, c[1] as u8 * 16, c[2] as u8 * 16, 255],
        [0.0, 0.0, 1.0],
    )
}

/// The synthetic octrees: a full depth-3 cube, two opposite corner voxels at depth 4, and a
/// sparse lattice at depth 4.
fn synthetic_images() -> Result<Vec<NamedImage>, VectorError> {
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
    ]
    .into_iter()
    .map(|(name, depth, coords)| {
        let set = LeafSet::from_coords(depth, coords.into_iter().map(|c| (c, attr(c))))?;
        Ok(NamedImage {
            name: name.to_string(),
            image: SvoImage::build(&set)?,
        })
    })
    .collect()
}

impl WalkerStage {
    /// The walker of `dp` over `scene_images` (the captured walks' images, by asset index)
    /// followed by the synthetic ones.
    pub fn new(dp: &DatapathConfig, scene_images: Vec<NamedImage>) -> Result<Self, VectorError> {
        let synthetic = scene_images.len();
        let mut images = scene_images;
        images.extend(synthetic_images()?);
        Ok(Self {
            cfg: dp.walker,
            dir: dp.transform.local_dir,
            recip: ReciprocalUnit::new(&dp.reciprocal),
            images,
            synthetic,
        })
    }

    /// The images, scene assets first.
    pub fn images(&self) -> &[NamedImage] {
        &self.images
    }

    /// Walker inputs for an f64 local ray, as the pipeline forms them: the origin and half
    /// extents rounded into `pos`, the direction into the transform's output format and
    /// through the reciprocal unit (the f64 sign bit as the sign, so −0 is negative).
    pub fn input_for(&self, origin: [f64; 3], dir: [f64; 3], half: [f64; 3]) -> WalkerInput {
        let mut ov = Overflows::new(&["host"]);
        let p = |x: f64, ov: &mut Overflows| WalkerPos {
            raw: from_f64(x, self.cfg.pos, ov, SignalId(0)),
        };
        let mut inp = WalkerInput {
            origin: origin.map(|x| p(x, &mut ov)),
            half: half.map(|x| p(x, &mut ov)),
            ..WalkerInput::default()
        };
        for (k, &x) in dir.iter().enumerate() {
            let code = from_f64(x, self.dir, &mut ov, SignalId(0));
            let r = self
                .recip
                .eval(code, x.is_sign_negative(), &mut ov, SignalId(0));
            inp.set_axis(k, &r);
        }
        inp
    }

    /// The walk-row layout.
    pub fn layout(&self) -> Layout {
        let c = &self.cfg;
        let mut l = Layout::new();
        l.uint("image", Input, 8, "memory image index (parameters.images)");
        for a in AXES {
            l.fixed(&format!("o_{a}"), Input, c.pos, "local ray origin, m");
        }
        for a in AXES {
            l.fixed(
                &format!("inv_{a}"),
                Input,
                c.inv,
                "1/|d| (ignored on zero axes)",
            );
        }
        for a in AXES {
            l.flag(
                &format!("zero_{a}"),
                Input,
                "axis direction treated as 0 (1/d flagged zero)",
            );
        }
        for a in AXES {
            l.flag(
                &format!("negative_{a}"),
                Input,
                "axis direction negative (-0 included): mirrored",
            );
        }
        for a in AXES {
            l.fixed(
                &format!("half_{a}"),
                Input,
                c.pos,
                "half extent of the octree's box, m",
            );
        }
        l.uint(
            "outcome",
            Output,
            2,
            "0 miss, 1 hit, 2 stopped by the step limit",
        );
        l.fixed(
            "t",
            Output,
            c.t,
            "max(entry, 0) of the hit leaf, m (0 unless a hit)",
        );
        for a in AXES {
            l.uint(
                &format!("voxel_{a}"),
                Output,
                COORD_BITS,
                "hit leaf coordinate",
            );
        }
        l.uint("level", Output, LEVEL_BITS, "hit leaf level");
        l.uint("attr", Output, 32, "hit leaf attribute index");
        l.uint(
            "entry_axis",
            Output,
            2,
            "entry plane of the hit leaf: 0 x, 1 y, 2 z",
        );
        l.uint(
            "steps",
            Output,
            COUNT_BITS,
            "walker loop iterations (children examined)",
        );
        l.uint("fetches", Output, COUNT_BITS, "descriptor fetches");
        l.uint(
            "visits_first",
            Output,
            COUNT_BITS,
            "first row of this walk in walker_visits.hex",
        );
        l.uint(
            "visits_count",
            Output,
            COUNT_BITS,
            "nodes entered, in walker_visits.hex",
        );
        l
    }

    /// The visit-row layout.
    pub fn visit_layout() -> Layout {
        let mut l = Layout::new();
        l.uint("walk", Output, COUNT_BITS, "row of the walk in walker.hex");
        l.uint(
            "level",
            Output,
            LEVEL_BITS,
            "level of the node entered (1 = a child of the root)",
        );
        for a in AXES {
            l.uint(a, Output, COORD_BITS, "node coordinate at its level");
        }
        l
    }

    fn adversarial(&self) -> Vec<WalkTxn> {
        let (cube, corners, lattice) = (self.synthetic, self.synthetic + 1, self.synthetic + 2);
        let cubic = [1.0; 3];
        let aniso = [2.0, 0.5, 1.0];
        let mut v = Vec::new();
        let mut walk = |image: usize, o: [f64; 3], d: [f64; 3], half: [f64; 3]| {
            v.push(WalkTxn {
                image,
                input: self.input_for(o, d, half),
            });
        };
        for (image, half) in [
            (cube, cubic),
            (corners, cubic),
            (lattice, cubic),
            (lattice, aniso),
        ] {
            {
                // Axis-parallel rays, both ways, through the centre and off it; −0 on the
                // other axes.
                for k in 0..3 {
                    for sign in [1.0, -1.0] {
                        for off in [0.0, -0.77] {
                            let mut o = [off * half[0], -off * half[1], off * half[2]];
                            o[k] = -sign * 3.0 * half[k];
                            let mut d = [0.0, -0.0, 0.0];
                            d[(k + 1) % 3] = -0.0;
                            d[(k + 2) % 3] = 0.0;
                            d[k] = sign;
                            walk(image, o, d, half);
                        }
                    }
                }
                // Origins on faces, centre planes and level-2 node planes, axis-parallel.
                for plane in [-1.0, -0.5, 0.0, 0.25, 0.5, 1.0] {
                    walk(
                        image,
                        [plane * half[0], -3.0 * half[1], 0.1],
                        [0.0, 1.0, -0.0],
                        half,
                    );
                    walk(
                        image,
                        [-3.0 * half[0], plane * half[1], plane * half[2]],
                        [1.0, 0.0, 0.0],
                        half,
                    );
                }
                // Through the corners and the centre.
                let s = 1.0 / 3f64.sqrt();
                walk(image, half.map(|h| -2.0 * h), [s, s, s], half);
                walk(image, half.map(|h| 2.0 * h), [-s, -s, -s], half);
                walk(
                    image,
                    [-2.0 * half[0], 2.0 * half[1], -2.0 * half[2]],
                    [s, -s, s],
                    half,
                );
                // Inside the box; behind it; missing it; zero axes outside the slab.
                walk(image, [0.01, 0.02, -0.03], [0.6, 0.0, 0.8], half);
                walk(image, half.map(|h| -0.9 * h), [0.0, 0.0, 1.0], half);
                walk(image, half.map(|h| 3.0 * h), [s, s, s], half);
                walk(
                    image,
                    [-3.0 * half[0], 2.0 * half[1], 0.0],
                    [1.0, 0.0, 0.0],
                    half,
                );
                walk(
                    image,
                    [-3.0 * half[0], half[1], 0.0],
                    [1.0, 0.0, -0.0],
                    half,
                );
                walk(
                    image,
                    [-3.0 * half[0], -half[1], 0.0],
                    [1.0, -0.0, 0.0],
                    half,
                );
                walk(image, [0.0, 0.0, 0.0], [0.0, -0.0, 0.0], half);
            }
        }
        dedup(v)
    }

    fn random(&self, rng: &mut Rng) -> WalkTxn {
        let image = self.synthetic + rng.below(3) as usize;
        let half = [0; 3].map(|_| rng.range(0.25, 3.0));
        let o = [0; 3].map(|k| rng.range(-2.5, 2.5) * half[k]);
        let mut d = rng.unit_vector();
        if rng.one_in(4) {
            d[rng.below(3) as usize] = if rng.one_in(2) { 0.0 } else { -0.0 };
        }
        WalkTxn {
            image,
            input: self.input_for(o, d, half),
        }
    }

    /// The walk table (adversarial walks, `count`/2 captured ones spread over `captured`, the
    /// rest random) and its visit table.
    pub fn build(
        &self,
        captured: &[WalkTxn],
        count: usize,
        seed: u64,
    ) -> (VectorTable, VectorTable) {
        let layout = self.layout();
        let vlayout = Self::visit_layout();
        let mut walks = VectorTable::new(
            "walker",
            "one octree walk per row: image, local origin, 1/|d|, zero and negative flags, half extents in; outcome, hit, counts and the walk's rows in walker_visits.hex out",
            layout.clone(),
        );
        let mut visits = VectorTable::new(
            "walker_visits",
            "one node entered per row, in walk order: the walk's row in walker.hex, the node's level and coordinates",
            vlayout.clone(),
        );
        let (n_captured, n_random) = plan_rows(captured.len(), count);
        let mut rng = Rng::for_stage(seed, "walker");
        let random: Vec<WalkTxn> = (0..n_random).map(|_| self.random(&mut rng)).collect();
        let mut visit_rows = Vec::new();
        for (origin, txns) in [
            (Origin::Adversarial, self.adversarial()),
            (Origin::Captured, spread(captured, n_captured)),
            (Origin::Random, random),
        ] {
            let mut rows = Vec::with_capacity(txns.len());
            for t in txns {
                let walk = walks.rows.len() + rows.len();
                let first = visit_rows.len();
                let mut path: Vec<(u8, [u32; 3])> = Vec::new();
                let mut st = WalkerStats::default();
                let img = &self.images[t.image.min(self.images.len() - 1)].image;
                let out = walk_fixed_visiting(
                    img,
                    &t.input,
                    &self.cfg,
                    &mut Overflows::new(&["walker"]),
                    SignalId(0),
                    &mut st,
                    &mut |level, c| path.push((level, c)),
                );
                for &(level, c) in &path {
                    visit_rows.push(vlayout.pack(&[
                        u(walk as u64),
                        u(u64::from(level)),
                        u(u64::from(c[0])),
                        u(u64::from(c[1])),
                        u(u64::from(c[2])),
                    ]));
                }
                let inp = &t.input;
                let mut v = vec![u(t.image as u64)];
                v.extend(inp.origin.map(|p| s(p.raw)));
                v.extend(inp.inv.map(|i| s(i.raw)));
                v.extend(inp.zero.map(b));
                v.extend(inp.negative.map(b));
                v.extend(inp.half.map(|p| s(p.raw)));
                let (outcome, hit) = match out {
                    WalkOutcome::Miss => (0, None),
                    WalkOutcome::Hit(h) => (1, Some(h)),
                    WalkOutcome::StepLimit => (2, None),
                };
                v.push(u(outcome));
                v.push(s(hit.map_or(0, |h| h.t.raw)));
                v.extend(hit.map_or([0; 3], |h| h.voxel).map(|c| u(u64::from(c))));
                v.push(u(hit.map_or(0, |h| u64::from(h.level))));
                v.push(u(hit.map_or(0, |h| u64::from(h.attr))));
                v.push(u(hit.map_or(0, |h| u64::from(h.entry_axis))));
                v.push(u(st.steps));
                v.push(u(st.fetches));
                v.push(u(first as u64));
                v.push(u(path.len() as u64));
                rows.push(layout.pack(&v));
            }
            walks.push_block(origin, rows);
        }
        visits.push_block(Origin::Table, visit_rows);
        visits.package = true;
        walks.param("config", self.cfg);
        let images: Vec<serde_json::Value> = self
            .images
            .iter()
            .enumerate()
            .map(|(i, n)| {
                serde_json::json!({
                    "index": i,
                    "name": n.name,
                    "nodes_file": format!("svo_{}_nodes.hex", n.name),
                    "attrs_file": (i < self.synthetic).then(|| format!("svo_{}_attrs.hex", n.name)),
                    "depth": n.image.depth(),
                    "node_words": n.image.nodes().len(),
                    "leaves": n.image.attrs().len(),
                    "synthetic": i >= self.synthetic,
                })
            })
            .collect();
        walks.param("images", images);
        walks.param("visits_file", "walker_visits.hex");
        (walks, visits)
    }

    /// The memory tables of every image: node words (32 bits, `docs/svo-format.md`) and, for
    /// the scene's images (the end-to-end frame shades from them), leaf attributes (64 bits:
    /// normal word high, colour word low).
    pub fn image_tables(&self) -> Vec<VectorTable> {
        let mut out = Vec::new();
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_and_visits_agree() {
        let st =
            WalkerStage::new(&DatapathConfig::default(), Vec::new()).expect("synthetic images");
        let (walks, visits) = st.build(&[], 50, 1);
        let (l, vl) = (st.layout(), WalkerStage::visit_layout());
        let mut hits = 0;
        let mut total_visits = 0;
        for (i, w) in walks.rows.iter().enumerate() {
            let first = l.read(w, "visits_first").unwrap_or(-1) as usize;
            let n = l.read(w, "visits_count").unwrap_or(-1) as usize;
            assert_eq!(first, total_visits);
            total_visits += n;
            for v in &visits.rows[first..first + n] {
                assert_eq!(vl.read(v, "walk"), Some(i as i128));
            }
            if l.read(w, "outcome") == Some(1) {
                hits += 1;
                // The last node entered is the hit leaf.
                let last = &visits.rows[first + n - 1];
                assert_eq!(vl.read(last, "x"), l.read(w, "voxel_x"));
                assert_eq!(vl.read(last, "level"), l.read(w, "level"));
            }
        }
        assert_eq!(total_visits, visits.rows.len());
        assert!(hits > 20, "{hits} hits");
        assert!(walks.count(Origin::Adversarial) > 100);
    }
}
