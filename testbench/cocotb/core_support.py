"""The core bench's helpers that neither drive nor check the frame itself (test_core.py):
the register map from the SystemRDL description, the vectors' tables, the cycle model's VCD
of hit-buffer writes against the RTL's, and each image's on-chip prefix.

Pipeline position: the host's knowledge of svo_top (register addresses, image layout) and the
bench's readers of the model's outputs (`sim vectors`, `sim --vcd`); nothing here shares code
with the Rust model.
"""
import json
import os
from pathlib import Path

from cocotb.triggers import ReadOnly, RisingEdge
from systemrdl import RDLCompiler
from systemrdl.node import MemNode, RegNode

RDL = Path(__file__).resolve().parent.parent / "rdl" / "svo_core.rdl"


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


def backdoor_load(dut, nodes, words, node_base):
    """SVO_STORE_LOAD=backdoor: what a complete CTRL.LOAD of `words` words from `node_base`
    leaves in svo_top, written through VPI (the build's core_preload.vlt makes these writable):
    store word i = nodes[i] in bank i mod BANKS, row i / BANKS (svo_onchip_store's
    word-interleaved banks), and the load DMA's (svo_store_load's) store_ok, store_base (the
    load's source word index) and store_words. Written after reset (reset clears store_ok)
    and before the first START; the bank count is the hardware package's (SVO_ONCHIP_BANKS,
    from run.py)."""
    store, load = dut.u_memory.onchip.u_store, dut.u_load
    banks = int(os.environ["SVO_ONCHIP_BANKS"])
    for i in range(words):
        store.bank[i % banks].mem[i // banks].value = nodes[i]
    load.store_base.value = node_base >> 2
    load.store_words.value = words
    load.store_ok.value = 1
