#!/usr/bin/env bash
# Regenerates the register block's SystemVerilog from svo_core.rdl with peakrdl-regblock
# (AXI4-Lite, flattened ports; with the hwif report, the list of the core-side signals) into
# testbench/rdl/generated/, which is committed so that
# lint, synthesis, FuseSoC and a Vivado project need no Python. With --check it generates
# into a temporary folder and fails unless the bytes equal the committed files (CI runs
# this through tests/cocotb_units.rs: an edited .rdl without a regeneration fails).
# Usage: testbench/rdl/regen.sh [--check]   (peakrdl from PATH, else $SVO_VENV/bin)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
peakrdl="$(command -v peakrdl || echo "${SVO_VENV:-/opt/svo-venv}/bin/peakrdl")"
if [ ! -x "$peakrdl" ]; then
    echo "regen.sh: peakrdl not found (pip install -r testbench/requirements.txt; .ci/run does)" >&2
    exit 2
fi
out="$here/generated"
if [ "${1:-}" = --check ]; then
    out="$(mktemp -d)"
    trap 'rm -rf "$out"' EXIT
fi
"$peakrdl" regblock "$here/svo_core.rdl" -o "$out" --cpuif axi4-lite-flat --hwif-report
if [ "${1:-}" = --check ]; then
    status=0
    for f in "$out"/*; do
        g="$here/generated/$(basename "$f")"
        if ! cmp -s "$f" "$g"; then
            echo "regen.sh: $g differs from what svo_core.rdl generates (run testbench/rdl/regen.sh)" >&2
            status=1
        fi
    done
    [ "$(ls "$out" | wc -l)" = "$(ls "$here/generated" | wc -l)" ] || { echo "regen.sh: the generated file set differs" >&2; status=1; }
    [ $status = 0 ] && echo "regen.sh: generated/ matches svo_core.rdl"
    exit $status
fi
