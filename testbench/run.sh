#!/usr/bin/env bash
# Runs the self-checking testbenches of the RTL units in Icarus Verilog against a vector
# folder written by `sim vectors`, and fails unless every testbench ends "N passed, 0 failed".
#
# Usage: testbench/run.sh [VECTORS_DIR] [UNIT ...]
#   VECTORS_DIR  default: the committed golden set, ../vectors
#   UNIT         sqrt, reciprocal, transform, sphere (default: all four)
# Needs iverilog and vvp (Debian/Ubuntu: apt-get install iverilog).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
vec="${1:-$here/../vectors}"
if [ $# -gt 0 ]; then shift; fi
units=("$@")
if [ ${#units[@]} -eq 0 ]; then units=(sqrt reciprocal transform sphere); fi
if ! command -v iverilog >/dev/null || ! command -v vvp >/dev/null; then
    echo "run.sh: iverilog/vvp not found; install Icarus Verilog (apt-get install iverilog)" >&2
    exit 2
fi
if [ ! -d "$vec" ]; then
    echo "run.sh: vector folder $vec does not exist (write one with: sim vectors --out DIR)" >&2
    exit 2
fi
build="$(mktemp -d)"
trap 'rm -rf "$build"' EXIT
status=0
for u in "${units[@]}"; do
    echo "== $u: testbench/tb/tb_$u.sv, vectors $vec/$u.hex"
    if [ ! -f "$here/tb/tb_$u.sv" ] || [ ! -f "$vec/${u}_pkg.sv" ]; then
        echo "run.sh: no testbench or package for unit '$u'" >&2
        status=1
        continue
    fi
    iverilog -g2012 -Wall -I "$here/tb" -o "$build/tb_$u" \
        "$vec/${u}_pkg.sv" "$here"/rtl/*.v "$here/tb/tb_$u.sv"
    out="$(vvp -n "$build/tb_$u" "+vectors=$vec")"
    printf '%s\n' "$out"
    last="$(printf '%s\n' "$out" | tail -n 1)"
    if [[ ! "$last" =~ ^([0-9]+)\ passed,\ ([0-9]+)\ failed$ ]] || [ "${BASH_REMATCH[2]}" != 0 ]; then
        status=1
    fi
done
exit $status
