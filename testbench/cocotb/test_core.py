"""The whole accelerator (svo_top: svo_core behind AXI4-Lite, its AXI4 read masters and an
AXI4-Stream) rendering a frame of `sim vectors`, against the model's pixels and cycles.

Pipeline position: all of it, from the host's side. The bench is the host and the memory:
it writes the frame's registers over AXI4-Lite (cocotbext-axi AxiLiteMaster; addresses from
testbench/rdl/svo_core.rdl through systemrdl-compiler, not a hand list), puts the direction
table and the images in memory, loads the images' node words into svo_top's on-chip node
store (CTRL.LOAD: LOAD_SRC = NODE_BASE, the images one after the other as the model places
them, so a store word's address is the model's node address; the load's master m_axi_load is
served by LoadRead), starts the frame, takes the pixel stream (AxiStreamSink),
waits for STATUS.DONE and reads the counters. Every pixel must arrive exactly once with the
word of frame_pixels.hex (the model's), and CYCLES must equal the cycle model's frame cycles.

Memory, two modes (SVO_STALL):
- 0 (default): a read slave of fixed latency SVO_MEM_LATENCY (the model's uncached attribute
  read of the frame's hardware, testbench/hw/frame_hw.ron: a read asked in cycle c is there in
  cycle c + L) on the attribute and direction masters, the stream always ready: the frame's
  cycles must be the model's. The load's slave has the same latency and no pauses.
- P > 0: cocotbext-axi AxiRamRead on the attribute and direction masters with random pauses
  (P % of cycles) on AR and R, LoadRead's own on the load's AR and R, and on the stream's
  tready (seeded: SVO_SEED, printed): the pixels must still all arrive once and right, with
  no deadlock; the cycles are reported, not compared.

With several walkers (run.py SVO_HW=pool_2x4 or pool_4x2: svo_top built on hw/<HW>_pkg.sv)
svo_top has one attribute master per walker, as vectors; NodeLanesRead serves them in both
modes (fixed latency, or with its own random pauses on each lane's AR and R), the direction
master as above. The other SVO_HW packages (frame_hw, pool_1x4) have one walker and one plain
master.

With the node cache (run.py SVO_HW=pool_4x2_cache, or any package with onchip.levels 0: run.py
sets SVO_NODE_CACHE=1 and the package's SVO_DRAM_LATENCY, SVO_DRAM_BPC, SVO_LINE_BYTES) every
node word and attribute record comes through svo_top's cache and its master m_axi_node_*,
served by NodeCacheDram: the model's built-in DRAM timing, the node image at NODE_BASE and the
records at ATTR_BASE (both multiples of the cache's set span, so the cache's sets and banks are
the model's); with SVO_STALL=P its AR and R pause as the others. There is no node store: the
load's checks become one, a LOAD refused with STATUS.ERROR 7; the attribute-read SLVERR frame
becomes a fill's (ERROR 10; SVO_CORRUPT=resp expects 6 for it), its records read from a copy at
ATTR_COPY that no frame read before, so that it fills whatever the cache still holds (the
default hardware's 256 KiB keeps every line of the frames); no failing load at the end.

With the store in front of the cache (run.py SVO_HW=pool_4x2_split, or any package with
onchip.levels 1..8: run.py also sets SVO_ONCHIP_LEVELS and SVO_ONCHIP_MAX_BYTES) both: the bench
finds each used image's on-chip prefix itself (top_levels_prefix, from the descriptor words, not
the model's code), writes it into ONCHIP_WORDS[i], loads the store up to the last prefix's end
(the load's checks 7, 8, 9 as above) and serves the cache as above (ERROR 10 for the SLVERR
frame). SVO_CORRUPT=prefix writes the first used image's prefix one word short: its frames'
cycles differ from the model's. On hardware without the split a START with ONCHIP_WORDS[0] set
must be refused with ERROR 11.

SVO_STORE_LOAD=backdoor (hardware with a node store; run.py builds with core_preload.vlt in a
folder of its own): instead of CTRL.LOAD, which writes one store word a cycle (the default
hardware's car at depth 8: 199,583 words, about 34 minutes of simulation at the default's
speed), the bench writes the same words into the store's banks (word i in bank i mod BANKS,
row i / BANKS) and svo_top's record of a complete load (store_ok, store_base, store_words)
through VPI after reset, in seconds. The START before the load is still refused (7); the START
during a load is not tried, and the failing load at the end still runs through CTRL.LOAD.
The other store cases run CTRL.LOAD, so the load's path stays checked; a wrong backdoor word
shows as a wrong pixel or cycle count.

The record's normal is the core's own (svo_normal), from the normal matrix the bench writes
with each instance (its NMAT words in INSTANCE_TABLE, frame_instances nmat_*).

Environment: SVO_VECTORS (the `sim vectors` folder), SVO_MODEL_CYCLES (frame 0's model
cycles), SVO_FRAMES=2 with SVO_MODEL_CYCLES1 (a second frame with the hit buffer kept:
BUFFER_VALID 1; its tables from SVO_VECTORS1, `sim vectors --frame 1` of the same scene, with
the camera and the instances whose registers changed flagged dirty, or without it the same
still frame again, nothing dirty), SVO_CORRUPT=pixel:N (flip
bit 0 of pixel N's expected word), cycles (one more expected cycle) or done (frame 0's
STATUS.DONE read as 0: a frame that streams every pixel must also end DONE, or the watchdog
fires): exactly one failure.
SVO_MODEL_VCD=FILE (the model's `sim --frames 1 --vcd FILE` of frame 0; run.py then builds
with core_writes.vlt in a folder of its own): frame 0's hit-buffer writes cycle by cycle (how
many in each cycle, counted from the first write) must be the model's pixels_written steps, a
check finer than the frame's cycles (issue 29: the record FIFO's second push moves a write by
a cycle without moving the frame's end).
SVO_WATCHDOG=N: a frame not finished N cycles after its START (default 50 x the model's
cycles + 10,000) fails the bench with the state that explains the hang (core_watchdog.py).
Before the first frame, a START before the load must be refused with STATUS.ERROR 7 and one
during the load with 8 (LOADING set); the load's cycles (LOAD_CYCLES) are printed. Then five
STARTs with one bad register each must be refused with
svo_top's STATUS.ERROR code and neither BUSY nor DONE: a frame size of 0 (1), a direction table
base off its burst alignment (2), a node base off 4 bytes (3), an instance count of 0 and one
over the table's 128 (4); SVO_CORRUPT=error expects 3 for the first: exactly one failure.
After the frames (without SVO_STALL), two more frames in each of which one read answers
SLVERR must end DONE with STATUS.ERROR 5 (an attribute read) and 6 (a direction-table read);
SVO_CORRUPT=resp expects 6 for the attribute read: exactly one failure. Then a load whose beat
answers SLVERR must end with STATUS.ERROR 9 and the next START be refused with 7;
SVO_CORRUPT=load expects 8 for the load: exactly one failure. SVO_ERROR_FRAMES=0 leaves the
two SLVERR frames out (long runs; the failing load stays). Prints each frame's wall time,
failures (first 10), then "core: N passed, N failed".
"""
import json
import logging
import os
import random
import time
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles
from cocotbext.axi import (AxiLiteBus, AxiLiteMaster, AxiReadBus, AxiRamRead,
                           AxiStreamBus, AxiStreamSink)

from core_memory import (FixedLatencyRead, LoadRead, NodeCacheDram, NodeLanesRead,
                         every_cycle, stall_gen)
import core_watchdog
from core_support import (Table, backdoor_load, hex_words, model_writes, register_map,
                          rtl_writes, top_levels_prefix)

DIR_BASE = 0x0000_0000      # the direction table (16 bytes a pixel)
NODE_BASE = 0x0100_0000     # walker_nodes.hex, 4 bytes a word
ATTR_BASE = 0x0200_0000     # walker_attrs.hex, 8 bytes a record
ATTR_COPY = 0x0300_0000     # a copy of the records, read only by the node cache's SLVERR frame
MEM_BYTES = 0x0400_0000
MAX_REPORTS = 10
IMAGE_SLOTS = 8             # svo_top's IMAGE registers
TABLE_INSTANCES = 128       # svo_top's NINST: the instance table's instances
TABLE_STRIDE = 0x100        # bytes an instance of the table spans


class Bench:
    def __init__(self, dut):
        self.dut = dut
        self.failed = 0
        self.passed = 0
        self.reports = 0

    def fail(self, what):
        self.failed += 1
        if self.reports < MAX_REPORTS:
            print(f"FAIL core {what}")
        self.reports += 1


@cocotb.test()
async def frame_against_the_model(dut):
    vec = Path(os.environ["SVO_VECTORS"])
    seed = int(os.environ.get("SVO_SEED", "1"))
    stall = int(os.environ.get("SVO_STALL", "0"))
    latency = int(os.environ.get("SVO_MEM_LATENCY", "3"))
    frames = int(os.environ.get("SVO_FRAMES", "1"))
    # SVO_ERROR_FRAMES=0 leaves out the two SLVERR frames (each a whole frame: hours of
    # simulation at the default hardware's 128 x 96); the failing load stays.
    error_frames = os.environ.get("SVO_ERROR_FRAMES", "1") != "0"
    backdoor = os.environ.get("SVO_STORE_LOAD", "ctrl") == "backdoor"  # core_preload.vlt
    model_vcd = os.environ.get("SVO_MODEL_VCD")      # frame 0's writes cycle by cycle
    model = [int(os.environ.get("SVO_MODEL_CYCLES", "-1")),
             int(os.environ.get("SVO_MODEL_CYCLES1", "-1"))]
    corrupt = os.environ.get("SVO_CORRUPT", "")
    # Hardware with the node cache (run.py sets these from the package: onchip.levels 0).
    cached = os.environ.get("SVO_NODE_CACHE", "0") == "1"
    # With the store in front of the cache (onchip.levels 1..8) both: each image's top levels
    # (its first ONCHIP_WORDS[i] words, which the bench computes) from the store, the rest
    # through the cache.
    onchip_levels = int(os.environ.get("SVO_ONCHIP_LEVELS", "0"))
    split = cached and onchip_levels > 0
    store = split or not cached                     # svo_top has a node store to load
    rng = random.Random(seed)
    t_start = time.monotonic()
    print(f"core: vectors {vec}, seed {seed}, stall {stall} %, memory latency {latency}, {frames} frame(s)"
          + (f", corrupted {corrupt}" if corrupt else ""))
    regs, inst_words = register_map()
    b = Bench(dut)

    # Frame f's tables: SVO_VECTORS for frame 0, SVO_VECTORS1 (`sim vectors --frame 1` of the
    # same scene) for frame 1 if given, else frame 0's again (a still scene).
    vec1 = os.environ.get("SVO_VECTORS1")
    folders = [vec, Path(vec1) if vec1 else vec]
    pix = [Table(d, "frame_pixels") for d in folders]
    ins = [Table(d, "frame_instances") for d in folders]
    cam = [Table(d, "frame_camera") for d in folders]
    images = json.loads((vec / "walker.json").read_text())["parameters"]["images"]
    nodes = hex_words(vec / "walker_nodes.hex")
    attrs = hex_words(vec / "walker_attrs.hex")
    for d in folders[1:]:
        assert hex_words(d / "walker_nodes.hex") == nodes and hex_words(d / "walker_attrs.hex") == attrs, \
            f"{d}: the images differ from frame 0's (the same scene and depth are needed)"
    npix = len(pix[0].rows)
    width, height = cam[0].get(0, "width"), cam[0].get(0, "height")
    assert width * height == npix, f"frame_camera says {width}x{height}, frame_pixels has {npix} rows"
    assert all(len(t.rows) == npix for t in pix), "the frames differ in size"

    mem = bytearray(MEM_BYTES)

    def put_directions(t):
        for p in range(npix):
            for j, a in enumerate("xyz"):
                mem[DIR_BASE + 16 * p + 4 * j:DIR_BASE + 16 * p + 4 * j + 4] = \
                    t.get(p, f"dir_{a}").to_bytes(4, "little")
    put_directions(pix[0])
    for i, w in enumerate(nodes):
        mem[NODE_BASE + 4 * i:NODE_BASE + 4 * i + 4] = w.to_bytes(4, "little")
    for i, w in enumerate(attrs):
        mem[ATTR_BASE + 8 * i:ATTR_BASE + 8 * i + 8] = w.to_bytes(8, "little")
    assert 8 * len(attrs) <= ATTR_COPY - ATTR_BASE, f"{len(attrs)} records overrun the copy at {ATTR_COPY:#x}"
    mem[ATTR_COPY:ATTR_COPY + 8 * len(attrs)] = mem[ATTR_BASE:ATTR_BASE + 8 * len(attrs)]

    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.rst.value = 1
    stalls = {"node ar": 0, "node r": 0, "dir ar": 0, "dir r": 0, "stream": 0,
              "load ar": 0, "load r": 0}
    if cached:
        stalls.update({"cache ar": 0, "cache r": 0})
    rams = []
    load = LoadRead(dut, mem, latency, rng, stall, stalls)
    slaves = []
    lanes = len(dut.m_axi_arvalid)                  # walkers: one node master each
    if lanes > 1:
        # Several walkers (hw/pool_2x4.ron): the node masters are vectors, which the
        # cocotbext-axi slaves do not take; NodeLanesRead pauses them itself.
        slaves = [NodeLanesRead(dut, mem, latency, lanes, rng, stall, stalls)]
        if stall == 0:
            slaves.append(FixedLatencyRead(dut, "m_axi_dir", mem, latency, 16))
        else:
            dirs = AxiRamRead(AxiReadBus.from_prefix(dut, "m_axi_dir"), dut.clk, dut.rst, size=MEM_BYTES)
            rams = [dirs]
            dirs.write(0, bytes(mem))
            dirs.ar_channel.set_pause_generator(stall_gen(rng, stall, stalls, "dir ar"))
            dirs.r_channel.set_pause_generator(stall_gen(rng, stall, stalls, "dir r"))
    elif stall == 0:
        slaves = [FixedLatencyRead(dut, "m_axi", mem, latency, 8),
                  FixedLatencyRead(dut, "m_axi_dir", mem, latency, 16)]
    else:
        node = AxiRamRead(AxiReadBus.from_prefix(dut, "m_axi"), dut.clk, dut.rst, size=MEM_BYTES)
        dirs = AxiRamRead(AxiReadBus.from_prefix(dut, "m_axi_dir"), dut.clk, dut.rst, size=MEM_BYTES)
        rams = [node, dirs]
        for ram in rams:
            ram.write(0, bytes(mem))
        node.ar_channel.set_pause_generator(stall_gen(rng, stall, stalls, "node ar"))
        node.r_channel.set_pause_generator(stall_gen(rng, stall, stalls, "node r"))
        dirs.ar_channel.set_pause_generator(stall_gen(rng, stall, stalls, "dir ar"))
        dirs.r_channel.set_pause_generator(stall_gen(rng, stall, stalls, "dir r"))
    sink = AxiStreamSink(AxiStreamBus.from_prefix(dut, "m_axis"), dut.clk, dut.rst)
    if stall:
        sink.set_pause_generator(stall_gen(rng, stall, stalls, "stream"))
    axil = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), dut.clk, dut.rst)
    # The agents log every transfer at INFO: keep the bench's own lines readable.
    for name in ("s_axil", "m_axi", "m_axi_dir", "m_axi_load", "m_axis"):
        logging.getLogger(f"cocotb.{dut._name}.{name}").setLevel(logging.WARNING)

    slaves.append(load)
    dram = None
    if cached:
        dram = NodeCacheDram(dut, mem, int(os.environ["SVO_DRAM_LATENCY"]),
                             int(os.environ["SVO_DRAM_BPC"]), int(os.environ["SVO_LINE_BYTES"]),
                             rng, stall, stalls)
        slaves.append(dram)
        print(f"core: node cache: {dram.ports} AXI port(s) of {dram.line} bytes, DRAM latency "
              f"{dram.lat}, {dram.bpc} bytes a cycle")
    cocotb.start_soon(every_cycle(dut, slaves))

    await ClockCycles(dut.clk, 8)
    dut.rst.value = 0
    await ClockCycles(dut.clk, 2)

    async def w(path, value):
        await axil.write_dword(regs[path], value & 0xFFFF_FFFF)

    async def w_inst(k, path, value):
        addr = regs["INSTANCE_TABLE"] + TABLE_STRIDE * k + inst_words[path]
        await axil.write_dword(addr, value & 0xFFFF_FFFF)

    async def w_dirty(flags, moved):
        await w("DIRTY", flags)
        for j in range(TABLE_INSTANCES // 32):
            await w(f"DIRTY_INSTANCE[{j}]", moved >> (32 * j))

    async def r(path):
        return await axil.read_dword(regs[path])

    async def r64(name):
        return (await r(f"{name}.LO")) | ((await r(f"{name}.HI")) << 32)

    # The frame's registers (the host's side).
    async def write_frame(it, ct, prev_ins):
        await w("FRAME_SIZE", width | (height << 16))
        assert len(it.rows) <= TABLE_INSTANCES, f"{len(it.rows)} instances; the table holds {TABLE_INSTANCES}"
        await w("INSTANCES", len(it.rows))
        for j, a in enumerate("xyz"):
            o = ct.get(0, f"o_{a}")
            await w(f"CAMERA_O_LO[{j}]", o)
            await w(f"CAMERA_O_HI[{j}]", o >> 32)
        miss = ct.get(0, "miss_word")
        for j in range(3):
            await w(f"MISS_WORD[{j}]", miss >> (32 * j))
        await w("DIR_TABLE_BASE_LO", DIR_BASE)
        await w("DIR_TABLE_BASE_HI", 0)
        # The image slots the instances use (walker.json also lists the unit vectors'
        # synthetic images, which no instance reads).
        used = sorted({it.get(k, "image") for k in range(len(it.rows))})
        assert used[-1] < IMAGE_SLOTS, f"an instance reads image {used[-1]}; svo_top has {IMAGE_SLOTS} image slots"
        for im in (images[i] for i in used):
            i = im["index"]
            nb, ab = NODE_BASE + 4 * im["node_base"], ATTR_BASE + 8 * im["attr_base"]
            await w(f"IMAGE[{i}].NODE_BASE_LO", nb)
            await w(f"IMAGE[{i}].NODE_BASE_HI", nb >> 32)
            await w(f"IMAGE[{i}].ATTR_BASE_LO", ab)
            await w(f"IMAGE[{i}].ATTR_BASE_HI", ab >> 32)
            if split:
                await w(f"ONCHIP_WORDS[{i}]", prefix[i])
        # The instances into the instance table (INSTANCE_TABLE), each word at its offset
        # from the description's instance layout; only the instances whose row changed.
        for k in range(len(it.rows)):
            if prev_ins is not None and k < len(prev_ins.rows) and prev_ins.rows[k] == it.rows[k]:
                continue
            for c in range(3):
                for j, a in enumerate("xyz"):
                    await w_inst(k, f"AXIS[{3 * c + j}]", it.get(k, f"axis{c}_{a}"))
            for j, a in enumerate("xyz"):
                await w_inst(k, f"C_LO[{j}]", it.get(k, f"c_{a}"))
                await w_inst(k, f"C_HI[{j}]", it.get(k, f"c_{a}") >> 32)
                await w_inst(k, f"HALF_LO[{j}]", it.get(k, f"half_{a}"))
                await w_inst(k, f"HALF_HI[{j}]", it.get(k, f"half_{a}") >> 32)
            for name in ("reach", "threshold", "inside", "delta_t"):
                v = it.get(k, name)
                await w_inst(k, f"{name.upper()}_LO", v)
                await w_inst(k, f"{name.upper()}_HI", v >> 32)
            await w_inst(k, "IMAGE", it.get(k, "image"))
            for j, e in enumerate(("xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz")):
                await w_inst(k, f"NMAT[{j}]", it.get(k, f"nmat_{e}"))

    # A refused START: one register made bad, START, then STATUS must read ERROR `code` with
    # neither BUSY nor DONE; the register is put back.
    async def refused(code, what, path, bad, good):
        await w(path, bad)
        await w("CTRL", 0x1)
        await ClockCycles(dut.clk, 4)
        status = await r("STATUS")
        await w(path, good)
        if (status >> 8) & 0xF != code or status & 0x3:
            b.fail(f"a START with {what}: STATUS {status:#x}, want ERROR {code}, not BUSY, not DONE")
        else:
            b.passed += 1

    # The node store's load: the words of the images the frames use (walker.json lists the
    # images in the model's node space, the scene's first; the unit vectors' synthetic images
    # after them are not read), from NODE_BASE, so that store word = the model's node address.
    used_all = {t.get(k, "image") for t in ins for k in range(len(t.rows))}
    ends = {im["index"]: (images[j + 1]["node_base"] if j + 1 < len(images) else len(nodes))
            for j, im in enumerate(images)}
    load_words = max(ends[i] for i in used_all)
    # Each used image's on-chip prefix (split hardware): ONCHIP_WORDS[i].
    prefix = {}
    if split:
        max_words = int(os.environ["SVO_ONCHIP_MAX_BYTES"]) // 4
        for i in sorted(used_all):
            nb = images[i]["node_base"]
            prefix[i] = top_levels_prefix(nodes[nb:ends[i]], onchip_levels, max_words)
        if corrupt == "prefix":
            # The first used image's last top-level word read through the cache instead.
            prefix[min(prefix)] -= 1
        print(f"core: on chip: the top {onchip_levels} levels, words per image "
              + ", ".join(f"{i}: {n}/{ends[i] - images[i]['node_base']}" for i, n in prefix.items()))
        # Only on-chip words are read from the store: load up to the last prefix's end.
        load_words = max(images[i]["node_base"] + n for i, n in prefix.items())

    async def run_load(words):
        """CTRL.LOAD of `words` words from NODE_BASE; returns STATUS at its end and the
        load's cycles (LOAD_CYCLES)."""
        await w("LOAD_SRC_LO", NODE_BASE)
        await w("LOAD_SRC_HI", NODE_BASE >> 32)
        await w("LOAD_WORDS", words)
        await w("CTRL", 0x4)
        return await load_end()

    async def load_end():
        while True:
            status = await r("STATUS")
            if not status & 0x4:
                return status, await r64("LOAD_CYCLES")
            await ClockCycles(dut.clk, 100)

    for f in range(frames):
        for k in stalls:
            stalls[k] = 0                           # this frame's paused cycles
        expected = [pix[f].get(p, "word") for p in range(npix)]
        if corrupt.startswith("pixel:") and f == 0:
            expected[int(corrupt.split(":")[1])] ^= 1
        if f == 0:
            dirty, moved_bits = 0x2, (1 << TABLE_INSTANCES) - 1   # nothing to reuse: all dirty
        else:
            # The host's dirty flags: the camera (its position or any direction) and each
            # instance whose registers changed since the frame the buffer holds.
            cam_moved = cam[f].rows[0] != cam[f - 1].rows[0] or any(
                pix[f].get(p, f"dir_{a}") != pix[f - 1].get(p, f"dir_{a}") for p in range(npix) for a in "xyz")
            moved = [k for k in range(len(ins[f].rows))
                     if k >= len(ins[f - 1].rows) or ins[f].rows[k] != ins[f - 1].rows[k]]
            dirty, moved_bits = 0x1 | (0x2 if cam_moved else 0), sum(1 << k for k in moved)
            print(f"core: frame {f}: camera {'moved' if cam_moved else 'still'}, instances moved {moved}")
            if cam_moved:
                put_directions(pix[f])
                for ram in rams:
                    ram.write(DIR_BASE, bytes(mem[DIR_BASE:DIR_BASE + 16 * npix]))
        if f == 0 or folders[f] != folders[f - 1]:
            await write_frame(ins[f], cam[f], ins[f - 1] if f else None)
        await w_dirty(dirty, moved_bits)
        if f == 0:
            # svo_top's STATUS.ERROR codes 1-4, each provoked alone on frame 0's registers
            # (SVO_CORRUPT=error: expect code 3 for the frame size, exactly one failure).
            n0 = len(ins[0].rows)
            im0 = images[sorted({ins[0].get(k, "image") for k in range(n0)})[0]]
            i0, nb0 = im0["index"], NODE_BASE + 4 * im0["node_base"]
        if f == 0 and not store:
            # No node store: a LOAD is refused with STATUS.ERROR 7 (the cache reads the images
            # from memory; nothing to load), and a START needs none.
            await w("LOAD_SRC_LO", NODE_BASE)
            await w("LOAD_SRC_HI", NODE_BASE >> 32)
            await w("LOAD_WORDS", load_words)
            await w("CTRL", 0x4)
            await ClockCycles(dut.clk, 4)
            status = await r("STATUS")
            if (status >> 8) & 0xF != 7 or status & 0x7:
                b.fail(f"a LOAD on the node cache's hardware: STATUS {status:#x}, want ERROR 7, not BUSY, DONE or LOADING")
            else:
                b.passed += 1
        if f == 0 and store:
            # STATUS.ERROR 7 and 8: a START before the node store is loaded, and one while it
            # loads; then the load (its cycles are the load's, not the frame's).
            await w("CTRL", 0x1)
            await ClockCycles(dut.clk, 4)
            status = await r("STATUS")
            if (status >> 8) & 0xF != 7 or status & 0x7:
                b.fail(f"a START before the store's load: STATUS {status:#x}, want ERROR 7, not BUSY, DONE or LOADING")
            else:
                b.passed += 1
        if f == 0 and store and backdoor:
            # SVO_STORE_LOAD=backdoor: the store's banks and svo_top's record of a complete
            # load written through VPI (core_preload.vlt) instead of CTRL.LOAD's one word a
            # cycle; the START during a load is not tried (no load runs).
            t_load = time.monotonic()
            backdoor_load(dut, nodes, load_words, NODE_BASE)
            await ClockCycles(dut.clk, 1)
            print(f"core: load: {load_words} node words from {NODE_BASE:#x} written through the"
                  + f" backdoor in {time.monotonic() - t_load:.1f} s (no load cycles;"
                  + " the START during a load not tried)")
        if f == 0 and store and not backdoor:
            await w("LOAD_SRC_LO", NODE_BASE)
            await w("LOAD_SRC_HI", NODE_BASE >> 32)
            await w("LOAD_WORDS", load_words)
            await w("CTRL", 0x4)
            await w("CTRL", 0x1)
            await ClockCycles(dut.clk, 4)
            status = await r("STATUS")
            if (status >> 8) & 0xF != 8 or status & 0x7 != 0x4:
                b.fail(f"a START while the store loads: STATUS {status:#x}, want ERROR 8 and LOADING, not BUSY or DONE")
            else:
                b.passed += 1
            status, ld_cycles = await load_end()
            print(f"core: load: {load_words} node words from {NODE_BASE:#x} in {ld_cycles} cycles"
                  + f" (wall {time.monotonic() - t_start:.1f} s since the bench started)"
                  + (f"; protocol errors {load.errors[:3]}" if load.errors else ""))
            if load.errors:
                b.fail(f"the load's bursts: {load.errors[:3]}")
        if f == 0:
            await refused(3 if corrupt == "error" else 1, "a frame size of 0", "FRAME_SIZE",
                          0, width | (height << 16))
            await refused(2, "a direction table base off its burst alignment",
                          "DIR_TABLE_BASE_LO", DIR_BASE + 16, DIR_BASE)
            await refused(3, f"image slot {i0}'s node base off 4 bytes",
                          f"IMAGE[{i0}].NODE_BASE_LO", nb0 + 2, nb0)
            await refused(4, "an instance count of 0", "INSTANCES", 0, n0)
            await refused(4, f"an instance count over the table's {TABLE_INSTANCES}",
                          "INSTANCES", TABLE_INSTANCES + 1, n0)
            if not split:
                # ONCHIP_WORDS means nothing without the store in front of the cache: refused.
                await refused(11, "ONCHIP_WORDS[0] set on hardware without the split",
                              "ONCHIP_WORDS[0]", 1, 0)
        await w("STATUS", 0x2)                      # clear DONE
        writes, writes_stop = [], [False]
        if f == 0 and model_vcd:
            cocotb.start_soon(rtl_writes(dut, writes, writes_stop))
        await w("CTRL", 0x1)
        t_frame = time.monotonic()
        seen = {}

        async def frame_end():
            while True:
                frame = await sink.recv()
                data = bytes(frame.tdata)
                for s in range(0, len(data), 16):
                    slot = int.from_bytes(data[s:s + 16], "little")
                    p, word = slot & 0xFFFF_FFFF, (slot >> 32) & ((1 << 72) - 1)
                    seen.setdefault(p, []).append(word)
                if sum(len(v) for v in seen.values()) >= npix:
                    break
            # Then DONE, for as long as the watchdog allows (SVO_CORRUPT=done: frame 0's DONE
            # read as 0, so that the watchdog fires with every pixel streamed).
            while not (await r("STATUS")) & 0x2 or (corrupt == "done" and f == 0):
                await ClockCycles(dut.clk, 10)
        # The watchdog (core_watchdog.py): a frame not finished within its bound ends the bench
        # with the state that explains the hang.
        started, limit = core_watchdog.cycle(), core_watchdog.bound(model[f])
        if not await core_watchdog.frame_within(frame_end(), limit):
            print(core_watchdog.hang_report(dut, started, limit))
            if dram:
                print(f"watchdog: the bench's node-cache memory: {dram.fills} fills taken, beats due "
                      f"per port {[[(c, hex(a), i) for c, a, i in q[:4]] for q in dram.q]} "
                      f"(its cycle {dram.cycle}), next fill's port {dram.next_port}")
            b.fail(f"frame {f}: not finished {limit} cycles after its START (watchdog; "
                   f"{sum(len(v) for v in seen.values())}/{npix} pixels streamed, STATUS "
                   f"{await r('STATUS'):#x}, stalls {stalls})")
            print(f"core: {b.passed} passed, {b.failed} failed")
            assert False, "the watchdog fired"
        writes_stop[0] = True
        if f == 0 and model_vcd:
            # The hit buffer's writes cycle by cycle (SVO_MODEL_VCD): each cycle's number of
            # writes, from the first, the model's.
            want_w = model_writes(model_vcd)
            if os.environ.get("SVO_WRITES_OUT"):
                Path(os.environ["SVO_WRITES_OUT"]).write_text(json.dumps(writes))
            if writes == want_w:
                print(f"core: frame 0: the hit buffer's writes cycle by cycle the model's: "
                      f"{sum(n for _, n in writes)} writes in {len(writes)} cycles, the last "
                      f"{writes[-1][0]} cycles after the first")
                b.passed += 1
            else:
                i = next((i for i, (a, m) in enumerate(zip(writes, want_w)) if a != m),
                         min(len(writes), len(want_w)))
                got_i = writes[i] if i < len(writes) else None
                want_i = want_w[i] if i < len(want_w) else None
                b.fail(f"frame 0: the hit buffer's writes differ from the model's from the "
                       f"{i}th cycle with writes: RTL (cycle, writes) {got_i}, model {want_i} "
                       f"(cycles counted from the first write)")
        status = await r("STATUS")
        cycles = await r64("CYCLES")
        counters = {n: await r64(n) for n in ("WALKS", "STALL_WALK_ISSUE", "STALL_WRITE_PORT",
                                               "STALL_MEMORY", "STALL_DIRECTIONS", "STALL_STREAM",
                                               "NODE_READS", "REUSED")}
        equal = 0
        for p in range(npix):
            got = seen.get(p, [])
            if len(got) != 1:
                b.fail(f"frame {f} pixel {p}: streamed {len(got)} times")
            elif got[0] != expected[p]:
                b.fail(f"frame {f} pixel {p}: word {got[0]:018x}, the model's {expected[p]:018x}")
            else:
                equal += 1
                b.passed += 1
        stray = [p for p in seen if p >= npix]
        if stray:
            b.fail(f"frame {f}: pixels outside the frame streamed: {stray[:5]}")
        if (status >> 8) & 0xF or (status >> 12) & 0xE:
            b.fail(f"frame {f}: STATUS {status:#x} (ERROR {(status >> 8) & 0xF}, FAULT {(status >> 12) & 0xF})")
        want = model[f] + (1 if corrupt == "cycles" and f == 0 else 0)
        print(f"core: frame {f}: {equal}/{npix} pixels equal, RTL {cycles} cycles, model {model[f]} cycles; "
              + ", ".join(f"{k} {v}" for k, v in counters.items()))
        print(f"core: frame {f}: wall {time.monotonic() - t_frame:.1f} s")
        if stall:
            print("core: frame {}: random stalls (seed {}): {}".format(
                f, seed, ", ".join(f"{k} {v}" for k, v in stalls.items())))
            if counters["STALL_MEMORY"] == 0 or sum(stalls.values()) == 0:
                b.fail(f"frame {f}: no stall was injected")
            else:
                b.passed += 1
        elif model[f] < 0:
            b.fail(f"frame {f}: no SVO_MODEL_CYCLES given")
        elif cycles != want:
            b.fail(f"frame {f}: {cycles} cycles, the cycle model's {want}")
        else:
            b.passed += 1
    # STATUS.ERROR 5 and 6: after the frames, two more frames with every pixel traced (the
    # buffer valid, the camera dirty), in each of which one read answers SLVERR: an attribute
    # read (5; node words come from the on-chip store), then a direction-table read (6). The frame still runs to its end (the data is
    # right, only the response says otherwise), so the stream is drained; STATUS must read
    # DONE with that ERROR code. The fixed-latency slaves inject it (not run with SVO_STALL,
    # whose slaves are cocotbext-axi's). SVO_CORRUPT=resp expects 6 for the attribute read.
    # Then STATUS.ERROR 9: a load whose beat in the middle answers SLVERR ends with ERROR 9,
    # not LOADING, and leaves the store without a load: the next START is refused with 7.
    # SVO_CORRUPT=load expects 8 for the load: exactly one failure.
    if stall == 0 and not error_frames:
        print("core: the SLVERR frames left out (SVO_ERROR_FRAMES=0)")
    if stall == 0 and error_frames:
        node_slave, dir_slave = slaves[0], slaves[1]
        # With the node cache, a fill's beat instead (10; node words and records both come
        # through it). The cache keeps its lines across frames, and a large one (the default
        # hardware's 256 KiB) still holds every line the frames read, so a frame on the same
        # addresses may fill nothing: this frame reads its records from the copy at ATTR_COPY
        # (each used image's ATTR_BASE moved there, put back after it), lines the cache has
        # not seen, so every record read of the frame misses and it fills on any cache size.
        first = (10, dram, "a node-cache fill") if cached else (5, node_slave, "an attribute")
        for code, slave, what in (first, (6, dir_slave, "a direction")):
            copy = code == 10
            for im in (images[i] for i in sorted(used_all)) if copy else ():
                ab = ATTR_COPY + 8 * im["attr_base"]
                await w(f"IMAGE[{im['index']}].ATTR_BASE_LO", ab)
                await w(f"IMAGE[{im['index']}].ATTR_BASE_HI", ab >> 32)
            await w_dirty(0x3, (1 << TABLE_INSTANCES) - 1)
            await w("STATUS", 0x2)
            slave.fail_next = True                  # the frame's first read of that master
            await w("CTRL", 0x1)
            got = 0
            while got < npix:
                frame = await sink.recv()
                got += len(bytes(frame.tdata)) // 16
            for _ in range(10000):
                if (await r("STATUS")) & 0x2:
                    break
                await ClockCycles(dut.clk, 10)
            status = await r("STATUS")
            want = 6 if corrupt == "resp" and code in (5, 10) else code
            if (status >> 8) & 0xF != want or not status & 0x2 or slave.fail_next or (status >> 12) & 0xE:
                b.fail(f"{what} read answering SLVERR: STATUS {status:#x}, want DONE and ERROR {want}"
                       + (" and no FAULT" if (status >> 12) & 0xE else "")
                       + (" (no read came after the injection)" if slave.fail_next else ""))
            else:
                print(f"core: {what} read answering SLVERR: STATUS {status:#x} (ERROR {code})")
                b.passed += 1
            slave.fail_next = False
            for im in (images[i] for i in sorted(used_all)) if copy else ():
                ab = ATTR_BASE + 8 * im["attr_base"]
                await w(f"IMAGE[{im['index']}].ATTR_BASE_LO", ab)
                await w(f"IMAGE[{im['index']}].ATTR_BASE_HI", ab >> 32)
    if stall == 0 and store:
        # A short load (the store is not read again): a beat in its middle fails.
        await w("STATUS", 0x2)                      # clear DONE
        short = min(load_words, 512)
        load.fail_at = load.beats + (short + 1) // 4
        status, ld_cycles = await run_load(short)
        want = 8 if corrupt == "load" else 9
        if (status >> 8) & 0xF != want or status & 0x7 or load.fail_at >= load.beats:
            b.fail(f"a load read answering SLVERR: STATUS {status:#x}, want ERROR {want}, not LOADING, BUSY or DONE")
        else:
            print(f"core: a load read answering SLVERR: STATUS {status:#x} (ERROR 9) after {ld_cycles} cycles")
            b.passed += 1
        load.fail_at = None
        await w("CTRL", 0x1)
        await ClockCycles(dut.clk, 4)
        status = await r("STATUS")
        if (status >> 8) & 0xF != 7 or status & 0x7:
            b.fail(f"a START after the failed load: STATUS {status:#x}, want ERROR 7, not BUSY, DONE or LOADING")
        else:
            b.passed += 1
    if cached:
        print(f"core: node cache: {dram.fills} fills"
              + (f"; protocol errors {dram.errors[:3]}" if dram.errors else ""))
        if dram.errors:
            b.fail(f"the node cache's fills: {dram.errors[:3]}")
    print(f"core: {b.passed} passed, {b.failed} failed")
    assert b.failed == 0, f"{b.failed} checks failed"
