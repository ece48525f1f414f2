//! The resource estimate of a hardware configuration with its datapath: DSP48E2, BRAM36 and
//! URAM288 per component, added up against the part's budget ([`HwConfig::resources`]), and
//! the RAM bits the datapath's formats size (walker stacks, hit buffer, direction table).
//!
//! Pipeline position: read once per run, beside the configurations; the report's resource
//! table, `sim hardware`, `sim sweep` (`cost::pricing`) and the elaboration's savings all
//! come from here. Each unit counts its own DSP48E2 (`units::sphere::dsp48e2_count`,
//! `units::transform::dsp48e2_count`, `units::reciprocal::dsp48e2_count`,
//! `units::walker::root_dsp48e2_count`, `units::sqrt::dsp48e2_count`); this module multiplies
//! them by the instances the hardware has and adds the memories.

use crate::cycle::hw_config::{HwConfig, Placement, StackStorage};
use crate::datapath::DatapathConfig;
use crate::resources::{ResourceItem, ResourceReport, Resources};
use crate::units::hit_record::{bram36_count, uram288_count};
use crate::units::{raygen, reciprocal, sorter, sphere, sqrt, transform, walker};

/// Bits of a node-memory word address: the walker's node addresses are `u32` word indices
/// (`svo::SvoImage::nodes`), and a descriptor is one 32-bit word.
const NODE_ADDRESS_BITS: u32 = 32;
/// Bits of a child descriptor (`docs/svo-format.md` §3).
const DESCRIPTOR_BITS: u32 = 32;
/// Bits of the walker's "next child" state: labels 0..=7 and 8 = done.
const NEXT_CHILD_BITS: u32 = 4;
/// Bits of a stacked frame's level (0..=31), as the RTL walkers stack it.
const LEVEL_BITS: u32 = 5;
/// Bits of a stacked frame's integer coordinates, three of 20 bits, as the RTL walkers stack
/// them.
const COORDINATE_BITS: u32 = 60;
/// Bytes of one node word.
const NODE_WORD_BYTES: u64 = 4;

impl HwConfig {
    /// Estimated DSP48E2, BRAM36 and URAM288 of this configuration with datapath `dp`,
    /// against the part's budget; [`ResourceReport::fits`] says whether it fits. An error
    /// when either configuration is invalid (the counts are only defined for valid ones).
    ///
    /// What is counted (assumptions, `docs/cycle-model.md` has the reasons):
    /// - DSP48E2: per unit the products of its formats split into 27×18 tiles
    ///   (`fixed::dsp48e2_per_product`, as `sim datapath` prints), times the instances:
    ///   sphere lanes, transform, reciprocal (per axis) and walker-root units. The square
    ///   root, sorter, walkers' steps, hit record and svo_front's candidate gathering (a
    ///   decoder per key slot since issue 29; its running-index version took one per sphere
    ///   lane) use none.
    /// - Block RAM: the hit buffer and direction table when on chip
    ///   (`units::hit_record::bram36_count` / `uram288_count` of the frame's pixels); one
    ///   stack RAM per walker (contexts × stack depth frames) in BRAM; the node memory by the
    ///   memory model's rule (`NodeMemoryConfig::resources`), the on-chip store at its
    ///   capacity `max_bytes`.
    /// - Not counted: LUTs and flip-flops (pipeline registers, sorter comparators, walker
    ///   context registers, miss-status registers), FIFOs (LUTRAM), the reciprocal's
    ///   256-entry seed ROM (LUTs), and the memory controller and host interface.
    pub fn resources(&self, dp: &DatapathConfig) -> Result<ResourceReport, String> {
        self.validate()?;
        dp.validate().map_err(|m| format!("datapath: {m}"))?;
        // Units with products: instances × the unit's own DSP48E2 count.
        let dsp_item = |name: &str, n: u32, per: u32, note: String| {
            let used = Resources::dsp48e2(u64::from(n) * u64::from(per));
            ResourceItem::new(name, u64::from(n), used, note)
        };
        let sphere = sphere::dsp48e2_count(&dp.sphere);
        let sq = sqrt::dsp48e2_count(&sphere::sqrt_config(&dp.sphere));
        let sorter_res = sorter::resources(&dp.sorter, dp.hit_record.instance_bits);
        let transform = match self.transform_products {
            true => transform::dsp48e2_count(&dp.transform),
            false => 0,
        };
        let rc = reciprocal::dsp48e2_count(&dp.reciprocal);
        let wr = walker::root_dsp48e2_count(&dp.walker);
        let mut items = vec![
            dsp_item(
                "sphere",
                self.sphere_units,
                sphere,
                format!("{sphere} DSP per lane: l·d 3, l·l 3, t_ca² 1 products"),
            ),
            dsp_item(
                "sqrt",
                self.sphere_units,
                sq,
                "one per sphere lane; digit recurrence, subtractors only".into(),
            ),
            ResourceItem::new(
                "sorter",
                1,
                Resources::default(),
                format!(
                    "{} comparators of {} bits (LUTs)",
                    sorter_res.comparators, sorter_res.compare_bits
                ),
            ),
            dsp_item(
                "transform",
                self.transform_units,
                transform,
                match self.transform_products {
                    true => format!("{transform} DSP per unit: 9 origin + 9 direction products"),
                    false => "no products (no instance rotates): o − c and rounding only".into(),
                },
            ),
            dsp_item(
                "reciprocal",
                self.reciprocal_units,
                rc,
                format!("{rc} DSP per axis unit (Newton-Raphson)"),
            ),
            dsp_item(
                "walker_root",
                self.walker_root_units,
                wr,
                format!("{wr} DSP per unit: 6 slab products"),
            ),
            dsp_item(
                "normal",
                1,
                crate::units::normal::DSP48E2_COUNT,
                "record normal unit: 9 products of the normal matrix".into(),
            ),
        ];
        items.push(self.stack_item(dp));
        items.push(self.hit_buffer_item(dp));
        items.push(self.direction_table_item(dp));
        items.extend(self.node_memory_items());
        items.extend(self.fifo_bram_items(dp));
        let used = items
            .iter()
            .fold(Resources::default(), |a, it| a.saturating_add(it.used));
        Ok(ResourceReport {
            part: self.part.name.clone(),
            items,
            used,
            available: Resources {
                dsp48e2: u64::from(self.part.dsp48e2),
                bram36: u64::from(self.part.bram36),
                uram288: u64::from(self.part.uram288),
            },
        })
    }

    /// Bits of one walker stack frame. [`StackStorage::FullT`] is what the RTL walkers stack
    /// (`svo_walker_barrel.v`'s `FW`, issue 29's recalibration): the frame's t0, t1 and
    /// midpoints per axis (9 × (t + 1), the ±∞ sentinel bit each), node address, descriptor
    /// (kept so a pop needs no refetch), next child, level and the three 20-bit coordinates,
    /// 700 bits at the default, where the estimate had priced 6t + 68 = 440 (midpoints
    /// recomputed, level and coordinates not stacked: a design the RTL does not build; the
    /// barrel's synthesis gave 10 RAMB36 a walker against 7). [`StackStorage::ExactPop`], which
    /// has no RTL, keeps the model's idealised frame: the three dropped midpoint bits, node
    /// address, descriptor and next child.
    pub fn stack_frame_bits(&self, dp: &DatapathConfig) -> u32 {
        match self.walker_pool.stack {
            StackStorage::FullT => {
                9 * (u32::from(dp.walker.t.width) + 1)
                    + NODE_ADDRESS_BITS
                    + DESCRIPTOR_BITS
                    + NEXT_CHILD_BITS
                    + LEVEL_BITS
                    + COORDINATE_BITS
            }
            StackStorage::ExactPop => 3 + NODE_ADDRESS_BITS + DESCRIPTOR_BITS + NEXT_CHILD_BITS,
        }
    }

    /// Bits of all walker stacks holding `frames` frames per context: walkers × contexts ×
    /// `frames` × [`stack_frame_bits`](Self::stack_frame_bits), before block rounding. With
    /// `walker_pool.stack_depth` it is the whole stack store (`sim sweep`'s `stack_bits`).
    pub fn stack_bits(&self, dp: &DatapathConfig, frames: u8) -> u64 {
        let w = &self.walker_pool;
        u64::from(w.walkers)
            * u64::from(w.contexts_per_walker)
            * u64::from(frames)
            * u64::from(self.stack_frame_bits(dp))
    }

    /// Bits of the hit buffer, before block rounding: one record word per pixel of the frame
    /// it is built for, wherever it is placed.
    pub fn hit_buffer_bits(&self, dp: &DatapathConfig) -> u64 {
        self.frame.pixels() * u64::from(dp.hit_record.word_bits())
    }

    /// Bits of the direction table, before block rounding (`units::raygen::table_bits` of the
    /// frame), wherever it is placed.
    pub fn direction_table_bits(&self, dp: &DatapathConfig) -> u64 {
        raygen::table_bits(&dp.raygen, self.frame.width, self.frame.height)
    }

    /// Block RAMs of one walker's stacks as the RTL builds them: R × (stack_depth − 1)
    /// frames (the top frame is in the walker's registers) of
    /// [`stack_frame_bits`](Self::stack_frame_bits) in one array; up to 64 frames Yosys maps
    /// it to LUT-RAM (svo_walker's 20 frames, the barrel's 40 at R = 2), which the walker's and
    /// the barrel's LUT calibrations already hold, so no BRAM36; more frames are block RAM
    /// (the barrel's 320 frames of 700 bits at R = 16: 10 RAMB36, as synthesised).
    pub fn stack_bram36_per_walker(&self, dp: &DatapathConfig) -> u64 {
        self.stack_bram36(dp, u64::from(self.walker_pool.contexts_per_walker))
    }

    /// Block RAMs of the stacks of a walker of `contexts` contexts
    /// ([`stack_bram36_per_walker`](Self::stack_bram36_per_walker)).
    pub fn stack_bram36(&self, dp: &DatapathConfig, contexts: u64) -> u64 {
        let frames = contexts * self.stack_ram_frames();
        if crate::cost::structures::fifo_in_bram(frames) {
            bram36_count(self.stack_frame_bits(dp), frames)
        } else {
            0
        }
    }

    /// Frames a context keeps in the stack array: stack_depth − 1 (the top frame is in
    /// registers), at least one.
    fn stack_ram_frames(&self) -> u64 {
        u64::from(self.walker_pool.stack_depth.saturating_sub(1)).max(1)
    }

    fn stack_item(&self, dp: &DatapathConfig) -> ResourceItem {
        let w = &self.walker_pool;
        let bits = self.stack_frame_bits(dp);
        let per = self.stack_bram36_per_walker(dp);
        let (contexts, frames) = (w.contexts_per_walker, self.stack_ram_frames());
        ResourceItem::new(
            "walker_stacks",
            u64::from(w.walkers),
            Resources::bram36(per.saturating_mul(u64::from(w.walkers))),
            if per == 0 {
                format!(
                    "{contexts} contexts × {frames} frames × {bits} bits in LUT-RAM (in the walker's LUTs)"
                )
            } else {
                format!(
                    "{per} BRAM36 per walker: {contexts} contexts × {frames} frames × {bits} bits ({} deep)",
                    u64::from(contexts) * frames
                )
            },
        )
    }

    /// The FIFOs deep enough to be built in block RAM (`cost::structures::fifo_in_bram`);
    /// their pointers and output registers are in the fabric estimate.
    fn fifo_bram_items(&self, dp: &DatapathConfig) -> Vec<ResourceItem> {
        crate::cost::structures::fifo_entries(self, dp)
            .into_iter()
            .filter(|&(_, depth, _)| crate::cost::structures::fifo_in_bram(depth))
            .map(|(name, depth, bits)| {
                let n = crate::cost::structures::fifo_bram36(depth, bits);
                ResourceItem::new(
                    name,
                    1,
                    Resources::bram36(n),
                    format!("{depth} × {bits} bits, {n} BRAM36"),
                )
            })
            .collect()
    }

    fn hit_buffer_item(&self, dp: &DatapathConfig) -> ResourceItem {
        if !self.hit_buffer.present {
            let note = "absent: no pixel can be reused".into();
            return ResourceItem::new("hit_buffer", 0, Resources::default(), note);
        }
        let bits = dp.hit_record.word_bits();
        let item = self.per_pixel_item("hit_buffer", self.hit_buffer.placement, bits, "records");
        if self.hit_buffer.write_ports < 2 || self.hit_buffer.placement == Placement::External {
            return item;
        }
        // Two write paths: two banks on pixel parity, each of half the pixels rounded up to
        // whole blocks (`HitBuffer::write_ports`).
        let half = self.frame.pixels().div_ceil(2);
        let used = match self.hit_buffer.placement {
            Placement::Bram => Resources::bram36(2 * bram36_count(bits, half)),
            _ => Resources::uram288(2 * uram288_count(bits, half)),
        };
        ResourceItem::new(
            "hit_buffer",
            2,
            used,
            format!(
                "{}; 2 banks on pixel parity, one write path each",
                item.note
            ),
        )
    }

    fn direction_table_item(&self, dp: &DatapathConfig) -> ResourceItem {
        let bits = raygen::entry_bits(&dp.raygen);
        self.per_pixel_item("direction_table", self.direction_table, bits, "directions")
    }

    /// A per-pixel table of `bits`-bit `what` over the frame, where `placement` puts it.
    fn per_pixel_item(
        &self,
        name: &str,
        placement: Placement,
        bits: u32,
        what: &str,
    ) -> ResourceItem {
        let pixels = self.frame.pixels();
        let (used, where_) = match placement {
            Placement::Bram => (Resources::bram36(bram36_count(bits, pixels)), "BRAM36"),
            Placement::Uram => (
                Resources::uram288(uram288_count(bits, pixels)),
                "URAM288 (4K×72)",
            ),
            Placement::External => (Resources::default(), "external DRAM"),
        };
        let (w, h) = (self.frame.width, self.frame.height);
        ResourceItem::new(
            name,
            1,
            used,
            format!("{w}×{h} × {bits}-bit {what}, {where_}"),
        )
    }

    /// Words of on-chip node store the hardware is built with: its capacity cap (the RAM is
    /// sized for the largest scene it accepts, not for one scene's top levels), none when
    /// no level is on chip.
    pub fn onchip_node_words(&self) -> u64 {
        let oc = &self.node_memory.onchip;
        if oc.levels == 0 {
            0
        } else {
            oc.max_bytes / NODE_WORD_BYTES
        }
    }

    fn node_memory_items(&self) -> [ResourceItem; 3] {
        let nm = &self.node_memory;
        let m = nm.resources(self.onchip_node_words());
        let (oc, c) = (&nm.onchip, &nm.cache);
        let (levels, cap, banks) = (oc.levels, oc.max_bytes, oc.banks);
        let (size, ways, line, sets) = (c.size_bytes, c.ways, c.line_bytes, nm.cache_sets());
        let onchip = format!(
            "top {levels} levels, capacity {cap} bytes in {banks} banks of 1024 × 32-bit BRAM36"
        );
        let cb = c.banks;
        let data = format!(
            "{size} bytes, {ways} ways, {line}-byte lines in {cb} banks; one URAM copy per bank \
             and lookup port"
        );
        let tags = format!(
            "{sets} sets × {ways} ways in {cb} banks, one BRAM36 copy per bank and lookup port"
        );
        let ports = u64::from(c.ports) * u64::from(cb);
        [
            (
                "node_onchip",
                u64::from(banks),
                Resources::bram36(m.onchip_bram36),
                onchip,
            ),
            ("cache_data", ports, Resources::uram288(m.cache_uram), data),
            (
                "cache_tags",
                ports,
                Resources::bram36(m.cache_tag_bram36),
                tags,
            ),
        ]
        .map(|(name, n, used, note)| ResourceItem::new(name, n, used, note))
    }
}
