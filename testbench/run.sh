#!/usr/bin/env bash
# Runs the self-checking testbenches of the RTL units in Icarus Verilog against a vector
# folder written by `sim vectors`, and fails unless every testbench ends "N passed, 0 failed".
#
# Usage: testbench/run.sh [VECTORS_DIR] [UNIT ...]
#   VECTORS_DIR  default: the committed golden set, ../vectors
#   UNIT         sqrt, reciprocal, transform, sphere, walker (default: all)
# The walker runs three times, once per memory latency of its cycle predictions (+latency=0..2);
# WALKER_ARGS adds plusargs to those runs (e.g. "+first=0 +count=2000"); WALKER_LATENCIES
# chooses the runs (default "0 1 2").
# Needs iverilog and vvp (Debian/Ubuntu: apt-get install iverilog).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
vec="${1:-$here/../vectors}"
if [ $# -gt 0 ]; then shift; fi
units=("$@")
if [ ${#units[@]} -eq 0 ]; then units=(sqrt reciprocal transform sphere walker); fi
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
    pkgs=("$vec/${u}_pkg.sv")
    runs=("")
    if [ "$u" = walker ]; then
        pkgs+=("$vec/walker_visits_pkg.sv")
        runs=()
        for k in ${WALKER_LATENCIES:-0 1 2}; do runs+=("+latency=$k ${WALKER_ARGS:-}"); done
    fi
    # -Wno-sensitivity-entire-array: the walker's @* blocks read small per-axis arrays whole.
    iverilog -g2012 -Wall -Wno-sensitivity-entire-array -I "$here/tb" -o "$build/tb_$u" \
        "${pkgs[@]}" "$here"/rtl/*.v "$here/tb/tb_$u.sv"
    for extra in "${runs[@]}"; do
        # shellcheck disable=SC2086
        out="$(vvp -n "$build/tb_$u" "+vectors=$vec" $extra)"
        printf '%s\n' "$out"
        last="$(printf '%s\n' "$out" | tail -n 1)"
        if [[ ! "$last" =~ ^([0-9]+)\ passed,\ ([0-9]+)\ failed$ ]] || [ "${BASH_REMATCH[2]}" != 0 ]; then
            status=1
        fi
    done
done
exit $status
