//! The octree walker against the form it had before issue 30's speed work, kept here: the same
//! outcome, counters, saturation counts and observer events (every step, pop, read and node
//! entered, in order) for seeded random images and rays.
//!
//! The kept form (`old_walk` below) is the walker as it was at commit ad97d26, copied with its
//! `Frame`, `Axes` and the image accessors it called (`SvoImage::child`, `group_base`), so
//! that the rewritten loop (`units/walker/walk_loop.rs`: unpacked descriptors, empty children
//! passed over first, counters added once per walk) is checked against the loop it replaced
//! rather than against itself. Images: random leaf sets from depth 1 to 9, sparse and dense,
//! and one large enough for far pointers (the test asserts the far path ran); rays: origins
//! inside and outside the box, zero, negative and tiny direction components, and step limits
//! small enough to stop some walks.

mod common;

use common::{printed_seed, Rng};
use rtl_model::fixed::{quantize, Format, Overflows, Quant, SignalId};
use rtl_model::svo::{ChildDescriptor, ChildRef, FetchKind, LeafAttr, LeafSet, SvoImage};
use rtl_model::units::walker::{
    walk_fixed_observed, WalkObserver, WalkOutcome, WalkerConfig, WalkerHit, WalkerInput,
    WalkerInv, WalkerPos, WalkerStats, WalkerT,
};

/// Everything a walk reports, in order.
#[derive(Debug, PartialEq, Eq, Clone, Copy)]
enum Event {
    Enter(u8, [u32; 3]),
    Step,
    Pop,
    Read(FetchKind, u32),
}

#[derive(Default)]
struct Recorder(Vec<Event>);

impl WalkObserver for Recorder {
    fn enter(&mut self, level: u8, coords: [u32; 3]) {
        self.0.push(Event::Enter(level, coords));
    }
    fn step(&mut self) {
        self.0.push(Event::Step);
    }
    fn pop(&mut self) {
        self.0.push(Event::Pop);
    }
    fn read(&mut self, kind: FetchKind, addr: u32) {
        self.0.push(Event::Read(kind, addr));
    }
}

// ---- The walker before issue 30's speed work (commit ad97d26), unchanged but for names. ----

#[derive(Clone, Copy, Default)]
struct Frame {
    t0: [WalkerT; 3],
    t1: [WalkerT; 3],
    tm: [WalkerT; 3],
    addr: u32,
    desc: u32,
    next: u8,
    level: u8,
    coords: [u32; 3],
}

fn midpoint(s: WalkerT, o: WalkerT) -> WalkerT {
    let (a, b) = (s.raw, o.raw);
    WalkerT {
        raw: (a >> 1) + (b >> 1) + (a & b & 1),
    }
}

fn max3(v: [WalkerT; 3]) -> WalkerT {
    v[0].max(v[1]).max(v[2])
}

fn min3(v: [WalkerT; 3]) -> WalkerT {
    v[0].min(v[1]).min(v[2])
}

struct Axes {
    o: [WalkerPos; 3],
    zero: [bool; 3],
    a: u8,
    half: [WalkerPos; 3],
}

impl Axes {
    fn mid(&self, k: usize, t0: WalkerT, t1: WalkerT, level: u8, c: u32) -> WalkerT {
        if !self.zero[k] {
            return midpoint(t0, t1);
        }
        let n = 1u64 << level;
        let m = if self.a & (4 >> k) != 0 {
            n - 1 - u64::from(c)
        } else {
            u64::from(c)
        };
        let e = i128::from(self.half[k].raw);
        let centre = -e + ((i128::from(2 * m + 1) * (2 * e)) >> (level + 1));
        if i128::from(self.o[k].raw) < centre {
            WalkerT::POS_INF
        } else {
            WalkerT::NEG_INF
        }
    }
}

fn old_slab_t(cfg: &WalkerConfig, dist: i64, inv: WalkerInv, ov: &mut Overflows) -> WalkerT {
    let prod_frac = i32::from(cfg.pos.frac) + i32::from(cfg.inv.frac);
    WalkerT {
        raw: quantize(
            i128::from(dist) * i128::from(inv.raw),
            prod_frac,
            cfg.t,
            ov,
            SignalId(0),
        ),
    }
}

fn old_walk<O: WalkObserver>(
    img: &SvoImage,
    inp: &WalkerInput,
    cfg: &WalkerConfig,
    ov: &mut Overflows,
    st: &mut WalkerStats,
    obs: &mut O,
) -> WalkOutcome {
    let mut ax = Axes {
        o: [WalkerPos::default(); 3],
        zero: inp.zero,
        a: 0,
        half: inp.half,
    };
    let mut t0 = [WalkerT::ZERO; 3];
    let mut t1 = [WalkerT::ZERO; 3];
    for k in 0..3 {
        let mut o = i128::from(inp.origin[k].raw);
        if inp.negative[k] {
            o = -o;
            ax.a |= 4 >> k;
        }
        ax.o[k] = WalkerPos {
            raw: o.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64,
        };
        let e = i128::from(inp.half[k].raw);
        if inp.zero[k] {
            if !(-e <= o && o < e) {
                return WalkOutcome::Miss;
            }
            t0[k] = WalkerT::NEG_INF;
            t1[k] = WalkerT::POS_INF;
        } else {
            let (lo, hi) = ((-e - o) as i64, (e - o) as i64);
            t0[k] = old_slab_t(cfg, lo, inp.inv[k], ov);
            t1[k] = old_slab_t(cfg, hi, inp.inv[k], ov);
        }
    }
    if !(max3(t0) < min3(t1) && min3(t1) > WalkerT::ZERO) {
        return WalkOutcome::Miss;
    }
    st.fetches += 1;
    st.max_stack = st.max_stack.max(1);
    let root = SvoImage::root();
    obs.read(FetchKind::Node, root);
    let mut f = Frame {
        t0,
        t1,
        addr: root,
        desc: img.nodes()[root as usize],
        ..Frame::default()
    };
    f.tm = std::array::from_fn(|k| ax.mid(k, t0[k], t1[k], 0, 0));
    f.next = first_child(f.t0, f.tm);
    let mut stack = vec![f];
    old_loop(img, &ax, cfg, st, obs, &mut stack)
}

fn old_loop<O: WalkObserver>(
    img: &SvoImage,
    ax: &Axes,
    cfg: &WalkerConfig,
    st: &mut WalkerStats,
    obs: &mut O,
    stack: &mut Vec<Frame>,
) -> WalkOutcome {
    let mut steps = 0u32;
    loop {
        let Some(top) = stack.last_mut() else {
            return WalkOutcome::Miss;
        };
        let c = top.next;
        if c >= 8 {
            stack.pop();
            obs.pop();
            continue;
        }
        steps += 1;
        st.steps += 1;
        obs.step();
        if steps > cfg.max_steps {
            st.step_limit_hits += 1;
            return WalkOutcome::StepLimit;
        }
        let mut ct0 = [WalkerT::ZERO; 3];
        let mut ct1 = [WalkerT::ZERO; 3];
        for k in 0..3 {
            if c & (4 >> k) != 0 {
                ct0[k] = top.tm[k];
                ct1[k] = top.t1[k];
            } else {
                ct0[k] = top.t0[k];
                ct1[k] = top.tm[k];
            }
        }
        top.next = next_child(c, ct1);
        let enter = max3(ct0);
        let exit = min3(ct1);
        if !(enter < exit && exit > WalkerT::ZERO) {
            continue;
        }
        let real = c ^ ax.a;
        let desc = ChildDescriptor::unpack(top.desc);
        let level = top.level + 1;
        let coords = [
            (top.coords[0] << 1) | u32::from((real >> 2) & 1),
            (top.coords[1] << 1) | u32::from((real >> 1) & 1),
            (top.coords[2] << 1) | u32::from(real & 1),
        ];
        let child = img.child(top.addr, desc, real);
        if child != ChildRef::Empty {
            if desc.far {
                obs.read(FetchKind::Far, top.addr + u32::from(desc.ptr));
            }
            let slot = match child {
                ChildRef::Node(a) => a,
                _ => img.group_base(top.addr, desc) + desc.slot(real),
            };
            obs.read(FetchKind::Node, slot);
            obs.enter(level, coords);
        }
        match child {
            ChildRef::Empty => {}
            ChildRef::Leaf(attr) => {
                let entry_axis = if ct0[0] >= ct0[1] && ct0[0] >= ct0[2] {
                    0
                } else if ct0[1] >= ct0[2] {
                    1
                } else {
                    2
                };
                obs.read(FetchKind::Attr, attr);
                return WalkOutcome::Hit(WalkerHit {
                    t: enter.max(WalkerT::ZERO),
                    voxel: coords,
                    level,
                    attr,
                    entry_axis,
                });
            }
            ChildRef::Node(addr) => {
                st.fetches += 1;
                let mut child = Frame {
                    t0: ct0,
                    t1: ct1,
                    tm: [WalkerT::ZERO; 3],
                    addr,
                    desc: img.nodes()[addr as usize],
                    next: 0,
                    level,
                    coords,
                };
                child.tm = std::array::from_fn(|k| ax.mid(k, ct0[k], ct1[k], level, coords[k]));
                child.next = first_child(child.t0, child.tm);
                stack.push(child);
                st.max_stack = st.max_stack.max(stack.len() as u32);
            }
        }
    }
}

fn first_child(t0: [WalkerT; 3], tm: [WalkerT; 3]) -> u8 {
    let enter = max3(t0);
    (u8::from(tm[0] < enter) << 2) | (u8::from(tm[1] < enter) << 1) | u8::from(tm[2] < enter)
}

fn next_child(c: u8, t1: [WalkerT; 3]) -> u8 {
    let bit = if t1[0] <= t1[1] && t1[0] <= t1[2] {
        4
    } else if t1[1] <= t1[2] {
        2
    } else {
        1
    };
    if c & bit != 0 {
        8
    } else {
        c | bit
    }
}

// ---- The comparison. ----

fn config(max_steps: u32) -> WalkerConfig {
    WalkerConfig {
        pos: Format::sq(8, 32).with_quant(Quant::RndConv),
        inv: Format::sq(22, 30).with_quant(Quant::RndConv),
        t: Format::sq(31, 31),
        max_steps,
    }
}

/// A random leaf set at `depth`: `count` leaves, uniformly placed or clustered in a random
/// octant chain (dense subtrees), each with its own attribute.
fn image(rng: &mut Rng, depth: u8, count: usize) -> SvoImage {
    let n = 1u64 << depth;
    let cluster = rng.below(2) == 0;
    let corner: [u64; 3] = std::array::from_fn(|_| rng.below(n));
    let leaves = (0..count).map(|i| {
        let c: [u32; 3] = std::array::from_fn(|k| {
            if cluster {
                ((corner[k] + rng.below(n / 4 + 1)) % n) as u32
            } else {
                rng.below(n) as u32
            }
        });
        let rgba = [(i % 251) as u8, (i / 251 % 251) as u8, 7, 255];
        (c, LeafAttr::new(rgba, [0.0, 0.0, 1.0]))
    });
    let set = LeafSet::from_coords(depth, leaves).expect("valid leaf set");
    SvoImage::build(&set).expect("image builds")
}

/// A random walk input for a box of half extents `half` (metres): the origin inside or
/// outside, each direction component random, zero, tiny or negative.
fn input(rng: &mut Rng, half: [f64; 3]) -> WalkerInput {
    let cfg = config(1);
    let pos = |x: f64| (x * 2f64.powi(i32::from(cfg.pos.frac))).round() as i64;
    let mut inp = WalkerInput {
        half: half.map(|h| WalkerPos { raw: pos(h) }),
        ..WalkerInput::default()
    };
    let spread = if rng.below(3) == 0 { 1.0 } else { 3.0 };
    for (k, &h) in half.iter().enumerate() {
        let u = rng.below(1 << 30) as f64 / f64::from(1 << 30);
        inp.origin[k] = WalkerPos {
            raw: pos((2.0 * u - 1.0) * spread * h),
        };
        let negative = rng.below(2) == 0;
        let kind = rng.below(10);
        inp.negative[k] = negative;
        if kind == 0 {
            inp.zero[k] = true;
            inp.inv[k] = WalkerInv { raw: 0 };
        } else {
            // 1/|d| from 1 up to about 2^20 (tiny components), in `inv`.
            let mag = if kind == 1 {
                2f64.powi(rng.range(8, 20) as i32)
            } else {
                1.0 + rng.below(1 << 20) as f64 / 1024.0
            };
            inp.inv[k] = WalkerInv {
                raw: (mag * 2f64.powi(i32::from(cfg.inv.frac))) as i64,
            };
        }
    }
    inp
}

#[test]
fn rewritten_walker_matches_the_loop_it_replaced() {
    let seed = printed_seed("rewritten_walker_matches_the_loop_it_replaced", 0x3a1_4e30);
    let mut rng = Rng::new(seed);
    let mut images: Vec<SvoImage> = (0..24)
        .map(|i| {
            let depth = 1 + (i % 9) as u8;
            let cap = (1usize << (3 * u32::from(depth))).min(4000);
            let count = 1 + rng.below(cap as u64) as usize;
            image(&mut rng, depth, count)
        })
        .collect();
    // Large enough for far pointers (groups more than 2^15 words from their parent).
    images.push(image(&mut Rng::new(seed ^ 0xfa4), 10, 300_000));
    let (mut walks, mut hits, mut limits, mut far_reads) = (0u32, 0u32, 0u32, 0u32);
    for (i, img) in images.iter().enumerate() {
        let half: [f64; 3] = std::array::from_fn(|_| 0.25 + rng.below(1000) as f64 / 100.0);
        for case in 0..1200 {
            let inp = input(&mut rng, half);
            let max_steps = if rng.below(8) == 0 {
                1 + rng.below(12) as u32
            } else {
                100_000
            };
            let cfg = config(max_steps);
            let (mut ov_old, mut ov_new) = (Overflows::new(&["t"]), Overflows::new(&["t"]));
            let (mut st_old, mut st_new) = (WalkerStats::default(), WalkerStats::default());
            let (mut ev_old, mut ev_new) = (Recorder::default(), Recorder::default());
            let old = old_walk(img, &inp, &cfg, &mut ov_old, &mut st_old, &mut ev_old);
            let new = walk_fixed_observed(
                img,
                &inp,
                &cfg,
                &mut ov_new,
                SignalId(0),
                &mut st_new,
                &mut ev_new,
            );
            let at = format!("seed {seed} image {i} case {case}: {inp:?}");
            assert_eq!(new, old, "outcome, {at}");
            assert_eq!(st_new, st_old, "counters, {at}");
            assert_eq!(ov_new, ov_old, "saturations, {at}");
            assert_eq!(ev_new.0, ev_old.0, "events, {at}");
            walks += 1;
            hits += u32::from(matches!(old, WalkOutcome::Hit(_)));
            limits += u32::from(old == WalkOutcome::StepLimit);
            far_reads += ev_old
                .0
                .iter()
                .filter(|e| matches!(e, Event::Read(FetchKind::Far, _)))
                .count() as u32;
        }
    }
    println!("{walks} walks: {hits} hits, {limits} step limits, {far_reads} far reads");
    assert!(
        hits > 1000 && limits > 100 && far_reads > 0,
        "every path taken"
    );
}
