"""Register tests of svo_core_regs, driven by testbench/rdl/svo_core.rdl (not a hand list).

Pipeline position: beside the core (the host interface). systemrdl-compiler elaborates the
description; every register it holds is read after reset, written with a seeded random word
and read back, and read again with the core's side of every field driven all-ones
(tb_regs.sv's hw_pattern). Each read is one check; the expected value of each is computed
from the field properties (sw/hw access, reset, singlepulse, woclr, hwset) alone, so the
oracle shares nothing with the generated RTL but the description.

Environment: SVO_SEED (default 29, printed), SVO_CORRUPT=PHASE:PATH flips bit 0 of one
expected value (PHASE reset|write|hw, PATH the register's path, e.g. svo_core_regs.CTRL),
which must give exactly one failure. Prints every failure, then "regs: N passed, N failed".
"""
import os
import random
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ClockCycles
from cocotbext.axi import AxiLiteBus, AxiLiteMaster
from systemrdl import RDLCompiler
from systemrdl.node import RegNode
from systemrdl.rdltypes import OnWriteType

RDL = Path(__file__).resolve().parent.parent / "rdl" / "svo_core.rdl"


def registers():
    """Every register of the description, in address order, with its path and address."""
    rdlc = RDLCompiler()
    rdlc.compile_file(str(RDL))
    root = rdlc.elaborate()
    regs = [n for n in root.descendants(unroll=True) if isinstance(n, RegNode)]
    return sorted(regs, key=lambda r: r.absolute_address)


def mask(f):
    return ((1 << f.width) - 1) << f.low


def expect(reg, written, hw_ones):
    """The value a read of `reg` returns, from its fields' properties: `written` is the last
    word software wrote to it (None: none since reset), `hw_ones` whether the core's side of
    every field is driven all-ones."""
    v = 0
    for f in reg.fields():
        if not f.is_sw_readable:
            continue  # write-only (START): reads 0
        reset = f.get_property("reset")
        hw_writes = f.is_hw_writable and not f.get_property("hwset")
        if hw_writes:
            x = (1 << f.width) - 1 if hw_ones else 0
        else:
            x = reset if reset is not None else 0
            if written is not None and f.is_sw_writable:
                w = (written >> f.low) & ((1 << f.width) - 1)
                if f.get_property("onwrite") == OnWriteType.woclr:
                    x &= ~w
                else:
                    x = w
            if f.get_property("hwset") and hw_ones:
                x = (1 << f.width) - 1
        v |= (x << f.low) & mask(f)
    return v


@cocotb.test()
async def registers_from_the_description(dut):
    seed = int(os.environ.get("SVO_SEED", "29"))
    corrupt = os.environ.get("SVO_CORRUPT", "")
    print(f"regs: seed {seed}" + (f", corrupted expectation {corrupt}" if corrupt else ""))
    rng = random.Random(seed)
    regs = registers()
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.hw_pattern.value = 0
    dut.rst.value = 1
    axil = AxiLiteMaster(AxiLiteBus.from_prefix(dut, "s_axil"), dut.clk, dut.rst)
    await ClockCycles(dut.clk, 4)
    dut.rst.value = 0
    await ClockCycles(dut.clk, 2)
    passed = 0
    failures = []

    async def check(phase, reg, want):
        nonlocal passed
        path = reg.get_path()
        if corrupt == f"{phase}:{path}":
            want ^= 1
        got = await axil.read_dword(reg.absolute_address)
        if got == want:
            passed += 1
        else:
            failures.append(
                f"FAIL {phase} {path} @0x{reg.absolute_address:03x}: read 0x{got:08x}, expected 0x{want:08x}"
            )

    for r in regs:
        await check("reset", r, expect(r, None, False))
    written = {}
    for r in regs:
        if any(f.is_sw_writable for f in r.fields()):
            w = rng.getrandbits(32)
            written[r.absolute_address] = w
            await axil.write_dword(r.absolute_address, w)
    for r in regs:
        await check("write", r, expect(r, written.get(r.absolute_address), False))
    dut.hw_pattern.value = 1
    await ClockCycles(dut.clk, 2)
    for r in regs:
        await check("hw", r, expect(r, written.get(r.absolute_address), True))
    for line in failures:
        print(line)
    print(f"regs: {len(regs)} registers, {len(written)} written")
    print(f"regs: {passed} passed, {len(failures)} failed")
    assert not failures, f"{len(failures)} register checks failed"
