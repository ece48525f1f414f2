#!/usr/bin/env python3
"""netlist_blocks.py JSON TOP [DEPTH]: the mapped cells of a flat Yosys netlist per RTL instance.

Pipeline position: none; reads the JSON that synth_core.sh writes (`synth_xilinx -flatten` of the
whole svo_core) and tells which block the cells belong to, for comparing the whole core with the
model's estimate per unit (docs/cycle-model.md section 1.5). Prints, per instance path cut at
DEPTH levels (default 3), the cells in the classes synth_core.sh counts: LUT1..6, LUTs used as
LUT-RAM (8 per RAM32M16/RAM64M8, ...), SRL16E/SRLC32E, flip-flops, DSP48E2, RAMB36/18, URAM.

How a cell finds its instance, first rule that applies:
1. its own name, when flattening kept the RTL's: `$flatten\\u_front.\\lane[0].u_sphere.$mul$...`
   (products, processes) or `u_walk.s_keys.0.3` (a memory's LUT-RAM or block RAM);
2. the public net it drives (a register's or a named wire's instance);
3. otherwise (most LUTs after ABC, which names its nets `$abc$...`) the instance most of its
   inputs come from, named nets or already placed cells, repeated until nothing changes.
Rule 3 is a vote: logic between two blocks can land in either, so the LUT column of small glue
rows is approximate; registers, LUT-RAM, block RAM and DSP48E2 follow rules 1 and 2.
"""
import collections
import json
import re
import sys

WEIGHTS = [
    (r"LUT[1-6]", "LUT", 1),
    (r"RAM32M16|RAM64M8", "LUTRAM", 8),
    (r"RAM32M|RAM64M|RAM128X1D", "LUTRAM", 4),
    (r"RAM32X1D|RAM64X1D|RAM128X1S", "LUTRAM", 2),
    (r"RAM32X1S|RAM64X1S", "LUTRAM", 1),
    (r"SRL.*", "SRL", 1),
    (r"FD.*", "FF", 1),
    (r"DSP48E2", "DSP", 1),
    (r"RAMB36.*", "RAMB36", 1),
    (r"RAMB18.*", "RAMB18", 1),
    (r"URAM.*", "URAM", 1),
]
COLUMNS = ["LUT", "LUTRAM", "SRL", "FF", "DSP", "RAMB36", "RAMB18", "URAM"]


def weight(cell_type):
    for pattern, kind, n in WEIGHTS:
        if re.fullmatch(pattern, cell_type):
            return kind, n
    return None, 0


def cut(parts, depth):
    return ".".join(parts[:depth]) or "(top)"


def name_path(name, depth):
    """The instance in a cell's own name (rule 1), or None."""
    if name.startswith("$flatten\\"):
        body = name[len("$flatten\\"):].split(".$", 1)[0]
        return cut(body.replace("\\", "").split("."), depth)
    if name.startswith("$"):
        return None
    parts = name.split(".")
    while parts and parts[-1].isdigit():
        parts.pop()
    return cut(parts[:-1], depth)  # without the memory's own name


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: netlist_blocks.py JSON TOP [DEPTH]")
    depth = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    with open(sys.argv[1]) as f:
        module = json.load(f)["modules"][sys.argv[2]]
    bit_block = {}
    for name, net in module["netnames"].items():
        if name.startswith("$"):
            continue
        block = cut(name.split(".")[:-1], depth)
        for b in net["bits"]:
            # The shortest public name of a bit is its own (longer ones are ports it reaches).
            if isinstance(b, int) and (b not in bit_block or len(block) < len(bit_block[b])):
                bit_block[b] = block
    cells = {}
    driver = {}
    for name, c in module["cells"].items():
        bits = {"output": [], "input": []}
        for port, direction in c["port_directions"].items():
            bits.setdefault(direction, []).extend(
                b for b in c["connections"][port] if isinstance(b, int))
        block = name_path(name, depth)
        if block is None:
            block = next((bit_block[b] for b in bits["output"] if b in bit_block), None)
        cells[name] = [c["type"], bits["output"], bits["input"], block]
        for b in bits["output"]:
            driver[b] = name
    changed = True
    while changed:
        changed = False
        for cell in cells.values():
            if cell[3] is not None:
                continue
            votes = collections.Counter()
            for b in cell[2]:
                block = bit_block.get(b)
                if block is None and b in driver:
                    block = cells[driver[b]][3]
                if block is not None:
                    votes[block] += 1
            if votes:
                cell[3] = votes.most_common(1)[0][0]
                changed = True
    totals = collections.defaultdict(collections.Counter)
    for cell_type, _, _, block in cells.values():
        kind, n = weight(cell_type)
        if kind is not None:
            totals[block or "(unplaced)"][kind] += n
    clb = lambda t: t["LUT"] + t["LUTRAM"] + t["SRL"]
    print("%-44s" % "instance" + "".join("%8s" % c for c in COLUMNS) + "%9s" % "CLB_LUT")
    for block in sorted(totals, key=lambda k: (-clb(totals[k]), k)):
        t = totals[block]
        print("%-44s" % block + "".join("%8d" % t[c] for c in COLUMNS) + "%9d" % clb(t))


if __name__ == "__main__":
    main()
