#!/usr/bin/env bash
# Synthesises svo_node_cache (testbench/rtl/svo_node_cache.v) — or, with --axi, svo_node_cache_axi
# (svo_node_cache_axi.v: the cache with its fills on AXI4 read ports) — with Yosys for
# UltraScale+ (`synth_xilinx -family xcup -flatten`) at one geometry and prints the mapped cells
# the resource estimate counts: LUTs (LUT1..LUT6), flip-flops (FD*), LUT RAM (RAM32M/RAM64M/
# RAM*X1*), block RAM (RAMB18/36), UltraRAM, and the wall time. Not in units.tsv (and so not in
# CI): the reference structure grows with SETS x WAYS x REQUESTERS, so only small geometries
# run in minutes (the numbers of the notes are from here).
#
# Usage: testbench/synth/synth_node_cache.sh [--axi] NAME=VALUE ...   (the top's parameters;
#        unset ones keep the module's defaults). SYNTH_LOGS keeps the log folder.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
top=svo_node_cache
files="$here/../rtl/svo_node_cache.v"
if [ "${1:-}" = "--axi" ]; then
    top=svo_node_cache_axi
    files="$files $here/../rtl/svo_node_cache_axi.v"
    shift
fi
command -v yosys >/dev/null || { echo "synth_node_cache.sh: yosys not found" >&2; exit 2; }
logs="${SYNTH_LOGS:-}"
if [ -z "$logs" ]; then logs="$(mktemp -d)"; trap 'rm -rf "$logs"' EXIT; fi
mkdir -p "$logs"
ys="$logs/$top.ys"
{
    echo "read_verilog -defer $files"
    # One chparam for all (each chparam elaborates the module again).
    if [ $# -gt 0 ]; then
        printf 'chparam'
        for p in "$@"; do printf ' -set %s %s' "${p%%=*}" "${p#*=}"; done
        printf ' %s\n' "$top"
    fi
    echo "synth_xilinx -family xcup -flatten -top $top"
    echo "tee -o $logs/$top.stat stat"
} >"$ys"
t0=$(date +%s)
yosys -q -l "$logs/$top.log" "$ys" >/dev/null
t1=$(date +%s)
cells() { awk -v re="$1" '$1 ~ re { s += $2 } END { print s + 0 }' "$logs/$top.stat"; }
printf '%7s %7s %7s %6s %6s %7s\n' LUT FF LUTRAM BRAM URAM wall_s
printf '%7s %7s %7s %6s %6s %7s\n' "$(cells '^LUT[1-6]$')" "$(cells '^FD')" \
    "$(cells '^RAM(32|64|128|256)')" "$(cells '^RAMB')" "$(cells '^URAM')" "$((t1 - t0))"
