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

mod adversarial;
mod images;

use crate::cycle::hw_config::{HwConfig, WalkerPool};
use crate::cycle::walk_op::OpRecorder;
use crate::cycle::walk_timing::WalkTiming;
use crate::datapath::DatapathConfig;
use crate::fixed::{from_f64, Format, Overflows, SignalId};
use crate::svo::FetchKind;
use crate::svo::SvoImage;
use crate::units::reciprocal::ReciprocalUnit;
use crate::units::walker::{
    root_latency_cycles, walk_fixed_observed, WalkObserver, WalkOutcome, WalkerConfig, WalkerInput,
    WalkerPos, WalkerStats,
};
use crate::vectors::layout::{b, s, u, Direction::*, Layout};
use crate::vectors::rng::Rng;
use crate::vectors::table::{plan_rows, spread, Origin, RowTiming, VectorTable};
use crate::vectors::VectorError;
use images::{synthetic_images, DEEP_VOXELS};

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
    /// The walker pool of the default hardware (step timing, stack depth).
    pool: WalkerPool,
    /// The fixed memory latencies the rows' cycle predictions are for: 1, the on-chip
    /// store's and the DRAM's of the default hardware.
    latencies: [u32; 3],
    /// The walker-root unit's latency (the testbench's root stage).
    root_latency: u32,
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

/// Records a walk's ops (for its timing) and the nodes it enters (for the visit table).
struct Recording<'a> {
    ops: OpRecorder<'a>,
    path: &'a mut Vec<(u8, [u32; 3])>,
}

impl WalkObserver for Recording<'_> {
    fn enter(&mut self, level: u8, coords: [u32; 3]) {
        self.path.push((level, coords));
    }
    fn step(&mut self) {
        self.ops.step();
    }
    fn pop(&mut self) {
        self.ops.pop();
    }
    fn read(&mut self, kind: FetchKind, addr: u32) {
        self.ops.read(kind, addr);
    }
}

impl WalkerStage {
    /// The walker of `dp` over `scene_images` (the captured walks' images, by asset index)
    /// followed by the synthetic ones.
    pub fn new(dp: &DatapathConfig, scene_images: Vec<NamedImage>) -> Result<Self, VectorError> {
        let synthetic = scene_images.len();
        let mut images = scene_images;
        images.extend(synthetic_images()?);
        let hw = HwConfig::for_datapath(dp);
        Ok(Self {
            cfg: dp.walker,
            pool: hw.walker_pool.clone(),
            latencies: [
                1,
                hw.node_memory.onchip.latency,
                hw.node_memory.dram.latency,
            ],
            root_latency: root_latency_cycles(&dp.walker),
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
        l.uint(
            "node_base",
            Input,
            32,
            "first word of the image in walker_nodes.hex (added to every node address)",
        );
        l.uint(
            "attr_base",
            Input,
            32,
            "first record of the image in walker_attrs.hex (added to every attribute index)",
        );
        walk_input_fields(&mut l, c);
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
        for (k, lat) in self.latencies.iter().enumerate() {
            l.uint(
                &format!("cycles_{k}"),
                Output,
                COUNT_BITS,
                &format!("cycle model: cycles from accept to result, every read taking {lat} cycles (MEM_LATENCY_{k})"),
            );
        }
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

    /// First node word and first attribute record of each image in the concatenated memory
    /// tables (`walker_nodes`, `walker_attrs`), and the totals.
    fn bases(&self) -> (Vec<(u64, u64)>, u64, u64) {
        let (mut n, mut a) = (0u64, 0u64);
        let mut v = Vec::with_capacity(self.images.len());
        for im in &self.images {
            v.push((n, a));
            n += im.image.nodes().len() as u64;
            a += im.image.attrs().len() as u64;
        }
        (v, n, a)
    }

    /// The walks of the walk table, in row order, by origin: every adversarial walk, `count`/2
    /// captured ones spread over `captured` (or fewer, if fewer were captured), the rest
    /// random from `seed`. The walker-root table (`super::walker_root`) has the same walks.
    pub fn walk_blocks(
        &self,
        captured: &[WalkTxn],
        count: usize,
        seed: u64,
    ) -> [(Origin, Vec<WalkTxn>); 3] {
        let (n_captured, n_random) = plan_rows(captured.len(), count);
        let mut rng = Rng::for_stage(seed, "walker");
        let random: Vec<WalkTxn> = (0..n_random).map(|_| self.random(&mut rng)).collect();
        [
            (Origin::Adversarial, self.adversarial()),
            (Origin::Captured, spread(captured, n_captured)),
            (Origin::Random, random),
        ]
    }

    /// The walk table (adversarial walks, `count`/2 captured ones spread over `captured`, the
    /// rest random) and its visit table. Each walk's cycles come from the cycle model
    /// ([`WalkTiming`]: one walker, one context, every read taking one of the three
    /// latencies).
    pub fn build(
        &self,
        captured: &[WalkTxn],
        count: usize,
        seed: u64,
    ) -> Result<(VectorTable, VectorTable), VectorError> {
        let layout = self.layout();
        let vlayout = Self::visit_layout();
        let mut walks = VectorTable::new(
            "walker",
            "one octree walk per row: image, its memory bases, local origin, 1/|d|, zero and negative flags, half extents in; outcome, hit, counts, the walk's rows in walker_visits.hex and the cycle model's cycles at three memory latencies out",
            layout.clone(),
        );
        let mut visits = VectorTable::new(
            "walker_visits",
            "one node entered per row, in walk order: the walk's row in walker.hex, the node's level and coordinates",
            vlayout.clone(),
        );
        let (bases, node_words, attr_records) = self.bases();
        let mut visit_rows = Vec::new();
        let mut ops = Vec::new();
        for (origin, txns) in self.walk_blocks(captured, count, seed) {
            let mut rows = Vec::with_capacity(txns.len());
            for t in txns {
                let walk = walks.rows.len() + rows.len();
                let first = visit_rows.len();
                let mut path: Vec<(u8, [u32; 3])> = Vec::new();
                let mut st = WalkerStats::default();
                let image = t.image.min(self.images.len() - 1);
                let img = &self.images[image].image;
                ops.clear();
                let mut rec = Recording {
                    ops: OpRecorder::new(&mut ops),
                    path: &mut path,
                };
                let out = walk_fixed_observed(
                    img,
                    &t.input,
                    &self.cfg,
                    &mut Overflows::new(&["walker"]),
                    SignalId(0),
                    &mut st,
                    &mut rec,
                );
                rec.ops.finish();
                let timing = WalkTiming::new(
                    &self.pool,
                    img.nodes().len() as u64,
                    img.attrs().len() as u64,
                );
                let mut cycles = [0u64; 3];
                for (c, &lat) in cycles.iter_mut().zip(&self.latencies) {
                    *c = timing.cycles(&ops, lat)?;
                }
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
                let (nb, ab) = bases[image];
                let mut v = vec![u(image as u64), u(nb), u(ab)];
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
                v.extend(cycles.map(u));
                rows.push(layout.pack(&v));
            }
            walks.push_block(origin, rows);
        }
        walks.row_timing = Some(RowTiming {
            cycles: "from the cycle the walker accepts a walk (in_valid and in_ready) to the cycle its result leaves (out_valid and out_ready), the result port always ready".into(),
            fields: (0..self.latencies.len()).map(|k| format!("cycles_{k}")).collect(),
            memory_latencies: self.latencies.to_vec(),
            model: format!(
                "rtl_model::cycle::walk_timing: the walker pool with one walker and one context (step_cycles {}, step_latency_cycles {}) and a node memory whose every read takes the latency",
                self.pool.step_cycles, self.pool.step_latency_cycles
            ),
        });
        let consts = [
            (
                "MEM_LATENCY_0",
                i64::from(self.latencies[0]),
                "cycles per read of cycles_0",
            ),
            (
                "MEM_LATENCY_1",
                i64::from(self.latencies[1]),
                "cycles per read of cycles_1: the on-chip node store's",
            ),
            (
                "MEM_LATENCY_2",
                i64::from(self.latencies[2]),
                "cycles per read of cycles_2: the DRAM's",
            ),
            (
                "STEP_CYCLES",
                i64::from(self.pool.step_cycles),
                "walker issue interval, cycles",
            ),
            (
                "STEP_LATENCY",
                i64::from(self.pool.step_latency_cycles),
                "cycles from a step to the context's next step or read",
            ),
            (
                "STACK_DEPTH",
                i64::from(self.pool.stack_depth),
                "stack frames per context",
            ),
            (
                "MAX_STEPS",
                i64::from(self.cfg.max_steps),
                "step limit of a walk",
            ),
            (
                "ROOT_LATENCY",
                i64::from(self.root_latency),
                "walker-root unit latency, cycles",
            ),
            ("NODE_WORDS", node_words as i64, "words in walker_nodes.hex"),
            (
                "ATTR_RECORDS",
                attr_records as i64,
                "records in walker_attrs.hex",
            ),
        ];
        walks.constants = consts
            .iter()
            .map(|&(n, v, c)| (n.to_string(), v, c.to_string()))
            .collect();
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
                    "node_base": bases[i].0,
                    "attr_base": bases[i].1,
                    "node_words": n.image.nodes().len(),
                    "leaves": n.image.attrs().len(),
                    "synthetic": i >= self.synthetic,
                })
            })
            .collect();
        walks.param("images", images);
        walks.param("visits_file", "walker_visits.hex");
        walks.param("nodes_file", "walker_nodes.hex");
        walks.param("attrs_file", "walker_attrs.hex");
        Ok((walks, visits))
    }
}

/// The input fields of a walk, per axis: local origin, 1/|d|, the zero and negative flags and
/// the box's half extent. The walker's rows and the walker root's (`walker_root.rs`, the same
/// walks) share them field for field.
pub(super) fn walk_input_fields(l: &mut Layout, c: &WalkerConfig) {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walks_and_visits_agree() {
        let st =
            WalkerStage::new(&DatapathConfig::default(), Vec::new()).expect("synthetic images");
        let (walks, visits) = st.build(&[], 50, 1).expect("timed");
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
