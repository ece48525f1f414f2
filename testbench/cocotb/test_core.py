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
becomes a fill's (ERROR 10; SVO_CORRUPT=resp expects 6 for it); no failing load at the end.

With the store in front of the cache (run.py SVO_HW=pool_4x2_split, or any package with
onchip.levels 1..8: run.py also sets SVO_ONCHIP_LEVELS and SVO_ONCHIP_MAX_BYTES) both: the bench
finds each used image's on-chip prefix itself (top_levels_prefix, from the descriptor words, not
the model's code), writes it into ONCHIP_WORDS[i], loads the store up to the last prefix's end
(the load's checks 7, 8, 9 as above) and serves the cache as above (ERROR 10 for the SLVERR
frame). SVO_CORRUPT=prefix writes the first used image's prefix one word short: its frames'
cycles differ from the model's. On hardware without the split a START with ONCHIP_WORDS[0] set
must be refused with ERROR 11.

The record's normal is the core's own (svo_normal), from the normal matrix the bench writes
with each instance (its NMAT words in INSTANCE_TABLE, frame_instances nmat_*).

Environment: SVO_VECTORS (the `sim vectors` folder), SVO_MODEL_CYCLES (frame 0's model
cycles), SVO_FRAMES=2 with SVO_MODEL_CYCLES1 (a second frame with the hit buffer kept:
BUFFER_VALID 1; its tables from SVO_VECTORS1, `sim vectors --frame 1` of the same scene, with
the camera and the instances whose registers changed flagged dirty, or without it the same
still frame again, nothing dirty), SVO_CORRUPT=pixel:N (flip
bit 0 of pixel N's expected word) or cycles (one more expected cycle): exactly one failure.
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
SVO_CORRUPT=load expects 8 for the load: exactly one failure. Prints failures (first
10), then "core: N passed, N failed".
"""
import json
import logging
import os
import random
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles, FallingEdge, ReadOnly, RisingEdge
from cocotbext.axi import (AxiLiteBus, AxiLiteMaster, AxiReadBus, AxiRamRead,
                           AxiStreamBus, AxiStreamSink)
from systemrdl import RDLCompiler
from systemrdl.node import MemNode, RegNode

import core_watchdog

RDL = Path(__file__).resolve().parent.parent / "rdl" / "svo_core.rdl"
DIR_BASE = 0x0000_0000      # the direction table (16 bytes a pixel)
NODE_BASE = 0x0100_0000     # walker_nodes.hex, 4 bytes a word
ATTR_BASE = 0x0200_0000     # walker_attrs.hex, 8 bytes a record
MEM_BYTES = 0x0300_0000
MAX_REPORTS = 10
IMAGE_SLOTS = 8             # svo_top's IMAGE registers
TABLE_INSTANCES = 128       # svo_top's NINST: the instance table's instances
TABLE_STRIDE = 0x100        # bytes an instance of the table spans


def register_map():
    """path (without the top's name, e.g. 'IMAGE[0].NODE_BASE_LO', or 'INSTANCE_TABLE' for
    the external instance table) -> byte address; and an instance's word path (e.g.
    'AXIS[3]', from the description's svo_instance_words) -> its offset in the table."""
    rdlc = RDLCompiler()
    rdlc.compile_file(str(RDL))
    root = rdlc.elaborate(top_def_name="svo_core_regs")
    out = {}
    for n in root.descendants(unroll=True):
        if isinstance(n, (RegNode, MemNode)):
            out[n.get_path().split(".", 1)[1]] = n.absolute_address
    rdlc = RDLCompiler()
    rdlc.compile_file(str(RDL))
    words = rdlc.elaborate(top_def_name="svo_instance_words")
    inst = {}
    for n in words.descendants(unroll=True):
        if isinstance(n, RegNode):
            inst[n.get_path().split(".", 2)[2]] = n.absolute_address
    return out, inst


class Table:
    """One vectors table: its rows (ints) and fields (name -> (offset, width, signed))."""

    def __init__(self, folder, name):
        m = json.loads((folder / f"{name}.json").read_text())
        self.fields = {f["name"]: (f["offset"], f["width"], f["signed"]) for f in m["fields"]}
        self.rows = [int(l, 16) for l in (folder / f"{name}.hex").read_text().split("\n")
                     if l and not l.startswith("//")]

    def get(self, r, name, signed=False):
        off, w, _ = self.fields[name]
        v = (self.rows[r] >> off) & ((1 << w) - 1)
        if signed and v >> (w - 1):
            v -= 1 << w
        return v


def hex_words(path):
    return [int(l, 16) for l in path.read_text().split("\n") if l and not l.startswith("//")]


class FixedLatencyRead:
    """An AXI4 read slave whose every read is there L cycles after its AR handshake (the
    model's fixed-latency node memory), a burst's beats on consecutive cycles, arready
    always high. Each cycle: drive R at the falling edge, then sample AR once settled."""

    def __init__(self, dut, prefix, mem, latency, nbytes):
        self.dut, self.p, self.mem, self.lat, self.nbytes = dut, prefix, mem, latency, nbytes
        self.beats = []             # (due cycle, address, last), in order
        self.cycle = 0
        self.fail_next = False      # the next beat answers SLVERR (STATUS.ERROR 5 / 6)
        self.sig("arready").value = 1
        self.sig("rvalid").value = 0
        self.sig("rid").value = 0
        self.sig("rresp").value = 0
        self.sig("rlast").value = 0
        self.sig("rdata").value = 0

    def sig(self, name):
        return getattr(self.dut, f"{self.p}_{name}")

    def drive(self):
        """The falling edge of a cycle: R for this cycle."""
        self.cycle += 1
        if self.beats and self.beats[0][0] <= self.cycle:
            _, addr, last = self.beats.pop(0)
            base = addr - addr % self.nbytes
            self.sig("rdata").value = int.from_bytes(self.mem[base:base + self.nbytes], "little")
            self.sig("rlast").value = int(last)
            self.sig("rvalid").value = 1
            self.sig("rresp").value = 2 if self.fail_next else 0
            self.fail_next = False
        else:
            self.sig("rvalid").value = 0
            self.sig("rresp").value = 0

    def sample(self):
        """Once the cycle has settled: an AR handshake at its closing edge."""
        if self.sig("arvalid").value == 1:
            addr = int(self.sig("araddr").value)
            n = int(self.sig("arlen").value) + 1
            size = 1 << int(self.sig("arsize").value)
            for k in range(n):
                self.beats.append((self.cycle + self.lat + k, addr + k * size, k == n - 1))


class RandomPauses:
    """The random pauses of the stalling slaves below: with pct > 0 a point of the protocol
    (key: "node ar", "load r", ...) pauses in a random pct % of the cycles it is asked about
    (rng, seeded by the bench), counted in stalls[key]."""

    def paused(self, key):
        if self.pct and self.rng.randrange(100) < self.pct:
            self.stalls[key] += 1
            return True
        return False


class NodeLanesRead(RandomPauses):
    """svo_top's node memory with several walkers: one AXI4 read slave per walker's master
    (lane w = bits [w] of the m_axi_* vectors, its address and data the w-th slices), each as
    FixedLatencyRead: single beats, in order, a read there L cycles after its AR handshake.
    With pct > 0 each lane's arready and each due R beat pause in a random pct % of cycles
    (rng), counted in stalls["node ar"] / ["node r"]; a paused beat and those behind it wait."""

    ADDR_W = 40

    def __init__(self, dut, mem, latency, lanes, rng=None, pct=0, stalls=None):
        self.dut, self.mem, self.lat, self.lanes = dut, mem, latency, lanes
        self.rng, self.pct, self.stalls = rng, pct, stalls
        self.q = [[] for _ in range(lanes)]       # (due cycle, address), in order
        self.cycle = 0
        self.fail_next = False                    # the next beat answers SLVERR (STATUS.ERROR 5)
        self.ar = (1 << lanes) - 1
        dut.m_axi_arready.value = self.ar
        for name in ("rvalid", "rid", "rresp", "rlast", "rdata"):
            getattr(dut, f"m_axi_{name}").value = 0

    def drive(self):
        """The falling edge of a cycle: each lane's R and arready for this cycle."""
        self.cycle += 1
        rvalid, rdata, ar, rresp = 0, 0, 0, 0
        for w in range(self.lanes):
            q = self.q[w]
            if q and q[0][0] <= self.cycle and not self.paused("node r"):
                _, addr = q.pop(0)
                base = addr - addr % 8
                rvalid |= 1 << w
                if self.fail_next:
                    rresp |= 2 << (2 * w)
                    self.fail_next = False
                rdata |= int.from_bytes(self.mem[base:base + 8], "little") << (64 * w)
            if not self.paused("node ar"):
                ar |= 1 << w
        self.ar = ar
        self.dut.m_axi_arready.value = ar
        self.dut.m_axi_rvalid.value = rvalid
        self.dut.m_axi_rresp.value = rresp
        self.dut.m_axi_rlast.value = rvalid
        self.dut.m_axi_rdata.value = rdata

    def sample(self):
        """Once the cycle has settled: each lane's AR handshake at its closing edge."""
        arvalid = int(self.dut.m_axi_arvalid.value) & self.ar
        if not arvalid:
            return
        araddr = int(self.dut.m_axi_araddr.value)
        arlen = int(self.dut.m_axi_arlen.value)
        for w in range(self.lanes):
            if arvalid >> w & 1:
                assert (arlen >> (8 * w)) & 0xFF == 0, "node reads are single beats"
                addr = (araddr >> (self.ADDR_W * w)) & ((1 << self.ADDR_W) - 1)
                self.q[w].append((self.cycle + self.lat, addr))


class LoadRead(RandomPauses):
    """svo_top's load master (m_axi_load_*, 8-byte beats, INCR bursts): a burst's beats from
    L cycles after its AR handshake, one a cycle as rready takes them (the DMA takes one every
    other cycle), rvalid held until taken. With pct > 0 arready and each beat not yet shown
    pause in a random pct % of cycles (rng), counted in stalls["load ar"] / ["load r"].
    fail_at = k: the load's beat k answers SLVERR (STATUS.ERROR 9). Checks that no burst
    crosses a 4 KiB page."""

    def __init__(self, dut, mem, latency, rng=None, pct=0, stalls=None):
        self.dut, self.mem, self.lat = dut, mem, latency
        self.rng, self.pct, self.stalls = rng, pct, stalls
        self.bursts = []            # [due cycle, address, beats left]
        self.cycle = 0
        self.shown = False          # a beat is on R, not yet taken
        self.beats = 0              # beats taken since the last reset_count()
        self.fail_at = None
        self.errors = []            # protocol errors seen (bursts crossing a page)
        self.ar = 1
        dut.m_axi_load_arready.value = 1
        for name in ("rvalid", "rid", "rresp", "rlast", "rdata"):
            getattr(dut, f"m_axi_load_{name}").value = 0

    def drive(self):
        self.cycle += 1
        d = self.dut
        if not self.shown and self.bursts and self.bursts[0][0] <= self.cycle and not self.paused("load r"):
            _, addr, left = self.bursts[0]
            d.m_axi_load_rdata.value = int.from_bytes(self.mem[addr:addr + 8], "little")
            d.m_axi_load_rlast.value = int(left == 1)
            d.m_axi_load_rresp.value = 2 if self.fail_at == self.beats else 0
            d.m_axi_load_rvalid.value = 1
            self.shown = True
        elif not self.shown:
            d.m_axi_load_rvalid.value = 0
            d.m_axi_load_rresp.value = 0
        self.ar = 0 if self.paused("load ar") else 1
        d.m_axi_load_arready.value = self.ar

    def sample(self):
        d = self.dut
        if self.shown and d.m_axi_load_rready.value == 1:
            self.shown = False
            self.beats += 1
            b = self.bursts[0]
            b[1] += 8
            b[2] -= 1
            if b[2] == 0:
                self.bursts.pop(0)
        if self.ar and d.m_axi_load_arvalid.value == 1:
            addr = int(d.m_axi_load_araddr.value)
            n = int(d.m_axi_load_arlen.value) + 1
            if int(d.m_axi_load_arsize.value) != 3 or addr % 8:
                self.errors.append(f"a load burst at {addr:#x} of size {1 << int(d.m_axi_load_arsize.value)}")
            if addr // 4096 != (addr + 8 * n - 1) // 4096:
                self.errors.append(f"a load burst of {n} beats at {addr:#x} crosses a 4 KiB page")
            self.bursts.append([self.cycle + self.lat, addr, n])


class NodeCacheDram(RandomPauses):
    """svo_top's node-cache master (m_axi_node_*, hardware with node_memory.onchip.levels 0):
    an AXI4 read slave whose timing is the model's built-in DRAM bus (rtl_model memory/dram.rs)
    as svo_node_cache_axi.v's contract states it and testbench/tb/tb_axi_dram.sv implements it
    (written again here, not shared, because the data must be the node image and the attribute
    records in `mem`, where tb_dram_model returns a hash of the address): the AR of a fill
    taken in cycle a counts as issued in a - 1; the fill starts on the one bus at
    max((a - 1 + LATENCY) * B, the previous fill's end), ends LINE_BYTES later, is done in
    ceil(end / B), and its one beat (RLAST) is on R in done - 2 on the port its AR came on.
    ARs are taken in rotating port order from the port of the next fill (the master stripes
    fill n on port n mod ports), stopping at the first port without one, so the bus order is
    the issue order; ARREADY is high only on the ports taken. (Issue 29, two ports under
    pauses: a READY on a port behind a paused one completed a handshake the bench did not
    take, the master's ports being independent queues, and two ARs taken in one cycle read
    one port twice, the rotation moving inside its own loop: lost fills, frames that never
    ended.) With pct > 0, each port's ARREADY and each due beat pause in a random pct % of
    cycles (rng), counted in stalls["cache ar"] / ["cache r"]; held beats wait in order.
    fail_next: the next beat answers SLVERR (STATUS.ERROR 10)."""

    ADDR_W = 40

    def __init__(self, dut, mem, latency, bpc, line, rng=None, pct=0, stalls=None):
        self.dut, self.mem, self.lat, self.bpc, self.line = dut, mem, latency, bpc, line
        self.rng, self.pct, self.stalls = rng, pct, stalls
        self.ports = len(dut.m_axi_node_arvalid)
        self.idw = len(dut.m_axi_node_arid) // self.ports
        self.q = [[] for _ in range(self.ports)]  # (due cycle, address, id), in order
        self.cycle = 0
        self.bus_end = 0                          # the last fill's end (byte slots)
        self.next_port = 0                        # the port of the next fill
        self.fills = 0
        self.fail_next = False
        self.errors = []
        self.ar = (1 << self.ports) - 1
        dut.m_axi_node_arready.value = self.ar
        for name in ("rvalid", "rid", "rresp", "rlast", "rdata"):
            getattr(dut, f"m_axi_node_{name}").value = 0

    def drive(self):
        """The falling edge of a cycle: each port's R and ARREADY for this cycle."""
        self.cycle += 1
        rvalid, rdata, rresp, rid, ar, free = 0, 0, 0, 0, 0, 0
        for p in range(self.ports):
            q = self.q[p]
            if q and q[0][0] <= self.cycle and not self.paused("cache r"):
                _, addr, i = q.pop(0)
                rvalid |= 1 << p
                rid |= i << (self.idw * p)
                if self.fail_next:
                    rresp |= 2 << (2 * p)
                    self.fail_next = False
                rdata |= int.from_bytes(self.mem[addr:addr + self.line], "little") << (8 * self.line * p)
            if not self.paused("cache ar"):
                free |= 1 << p
        # READY on the ports sample() takes: in rotation from the next fill's, each with ARVALID
        # (the master's queue registers: settled at this edge) and not paused, to the first not.
        arvalid = int(self.dut.m_axi_node_arvalid.value)
        for j in range(self.ports):
            p = (self.next_port + j) % self.ports
            if not (free & arvalid) >> p & 1:
                break
            ar |= 1 << p
        self.ar = ar
        d = self.dut
        d.m_axi_node_arready.value = ar
        d.m_axi_node_rvalid.value = rvalid
        d.m_axi_node_rresp.value = rresp
        d.m_axi_node_rlast.value = rvalid
        d.m_axi_node_rid.value = rid
        d.m_axi_node_rdata.value = rdata

    def sample(self):
        """Once the cycle has settled: the AR handshakes at its closing edge, in fill order."""
        arvalid = int(self.dut.m_axi_node_arvalid.value)
        if not arvalid & self.ar:
            return
        araddr = int(self.dut.m_axi_node_araddr.value)
        arid = int(self.dut.m_axi_node_arid.value)
        arlen = int(self.dut.m_axi_node_arlen.value)
        arsize = int(self.dut.m_axi_node_arsize.value)
        first = self.next_port                    # (next_port moves with each AR taken)
        for j in range(self.ports):
            p = (first + j) % self.ports
            if not (arvalid & self.ar) >> p & 1:
                break                             # the fills behind it wait, in order
            addr = (araddr >> (self.ADDR_W * p)) & ((1 << self.ADDR_W) - 1)
            if (arlen >> (8 * p)) & 0xFF or 1 << ((arsize >> (3 * p)) & 7) != self.line or addr % self.line:
                self.errors.append(f"a fill at {addr:#x} that is not one aligned beat of {self.line} bytes")
            start = max((self.cycle - 1 + self.lat) * self.bpc, self.bus_end)
            self.bus_end = start + self.line
            done = -(-self.bus_end // self.bpc)
            self.q[p].append((done - 2, addr, (arid >> (self.idw * p)) & ((1 << self.idw) - 1)))
            self.next_port = (p + 1) % self.ports
            self.fills += 1


async def every_cycle(dut, slaves):
    """One coroutine for both fixed-latency slaves (fewer simulator callbacks): at the falling
    edge their R, then, settled, their AR handshakes."""
    if not slaves:
        return
    while True:
        await FallingEdge(dut.clk)
        for s in slaves:
            s.drive()
        await ReadOnly()
        for s in slaves:
            s.sample()


def model_writes(path):
    """The hit buffer's writes per cycle in the cycle model's VCD of frame 0 (`sim --frames 1
    --vcd FILE`): the cycles in which top.pipeline.pixels_written grew and by how much, as
    (cycle, writes) with the cycle counted from the first write. Clock cycles from the clk
    variable's rising edges."""
    ids, scope, code_clk, code_w = {}, [], None, None
    lines = open(path)
    for line in lines:
        if line.startswith("$scope"):
            scope.append(line.split()[2])
        elif line.startswith("$upscope"):
            scope.pop()
        elif line.startswith("$var"):
            v = line.split()
            if v[4] == "clk":
                code_clk = v[3]
            elif v[4] == "pixels_written" and scope[-1:] == ["pipeline"]:
                code_w = v[3]
        elif line.startswith("$enddefinitions"):
            break
    assert code_clk and code_w, f"{path}: no clk or pipeline.pixels_written"
    t, rises, changes, prev = 0, [], [], 0
    for line in lines:
        if line.startswith("#"):
            t = int(line[1:])
        elif line.strip() == "1" + code_clk:
            rises.append(t)
        elif line.startswith("b") and line.split()[1] == code_w:
            v = int(line.split()[0][1:], 2)
            if v > prev:
                changes.append((t, v - prev))
            prev = v
    period = rises[1] - rises[0]
    c0 = changes[0][0] // period
    return [(tt // period - c0, n) for tt, n in changes]


async def rtl_writes(dut, out, stop):
    """svo_core's hit-buffer writes per cycle (wr_valid, wr1_valid, wr2_valid; readable with
    core_writes.vlt) into `out` as (cycle, writes), counted from the first write, until
    stop[0]."""
    core = dut.u_core
    c, first = 0, None
    while not stop[0]:
        await RisingEdge(dut.clk)
        await ReadOnly()
        n = int(core.wr_valid.value) + int(core.wr1_valid.value) + int(core.wr2_valid.value)
        if n:
            first = c if first is None else first
            out.append((c - first, n))
        c += 1


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


def stall_gen(rng, pct, counter, key):
    while True:
        s = rng.randrange(100) < pct
        if s:
            counter[key] += 1
        yield s


def top_levels_prefix(words, levels, max_words):
    """The number of an image's first words its top `levels` levels take (docs/svo-format.md
    §4), re-derived here from the descriptor format (docs/svo-format.md: leaf mask bits 7:0,
    valid mask 15:8, far bit 16, pointer 31:17), not the model's code: level 0 is the root
    word, level l the groups (the children's slots and the group's far words) of the internal
    nodes of level l - 1, whole levels while they fit `max_words`. The image lays its top
    levels out first, so they must be one prefix [0, end): checked."""
    if levels == 0 or max_words == 0 or not words:
        return 0
    groups, total, frontier, level = [(0, 1)], 1, [0], 1
    while level < levels and frontier:
        new, nxt, level_words = [], [], 0
        for a in frontier:
            d = words[a]
            valid, leaf = (d >> 8) & 0xFF, d & 0xFF
            if not valid:
                continue
            base = a + (words[a + (d >> 17)] if (d >> 16) & 1 else d >> 17)
            slot, far = base, 0
            for label in range(8):
                if not (valid >> label) & 1:
                    continue
                if not (leaf >> label) & 1:
                    far += (words[slot] >> 16) & 1
                    nxt.append(slot)
                slot += 1
            n = bin(valid).count("1") + far
            new.append((base, base + n))
            level_words += n
        if total + level_words > max_words:
            break
        total, groups, frontier, level = total + level_words, groups + new, nxt, level + 1
    end = 0
    for s, e in sorted(groups):
        assert s <= end, f"the top {levels} levels are not one prefix: a group at word {s}, the prefix ends at {end}"
        end = max(end, e)
    return end


@cocotb.test()
async def frame_against_the_model(dut):
    vec = Path(os.environ["SVO_VECTORS"])
    seed = int(os.environ.get("SVO_SEED", "1"))
    stall = int(os.environ.get("SVO_STALL", "0"))
    latency = int(os.environ.get("SVO_MEM_LATENCY", "3"))
    frames = int(os.environ.get("SVO_FRAMES", "1"))
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
            for _ in range(10000):
                if (await r("STATUS")) & 0x2:
                    break
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
    if stall == 0:
        node_slave, dir_slave = slaves[0], slaves[1]
        # With the node cache, the first fill's beat instead (10; node words and records both
        # come through it).
        first = (10, dram, "a node-cache fill") if cached else (5, node_slave, "an attribute")
        for code, slave, what in (first, (6, dir_slave, "a direction")):
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
            if (status >> 8) & 0xF != want or not status & 0x2 or slave.fail_next:
                b.fail(f"{what} read answering SLVERR: STATUS {status:#x}, want DONE and ERROR {want}"
                       + (" (no read came after the injection)" if slave.fail_next else ""))
            else:
                print(f"core: {what} read answering SLVERR: STATUS {status:#x} (ERROR {code})")
                b.passed += 1
            slave.fail_next = False
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
