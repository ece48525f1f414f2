#!/usr/bin/env bash
# Runs the self-checking testbenches of the RTL units against a vector folder written by
# `sim vectors`, in Icarus Verilog or Verilator, and fails unless every testbench ends
# "N passed, 0 failed"; or lints every RTL file with Verilator.
#
# Usage: testbench/run.sh [--sim icarus|verilator] [VECTORS_DIR] [UNIT ...]
#        testbench/run.sh --lint
#   --sim        simulator (default: $SIM, else icarus)
#   VECTORS_DIR  default: the committed golden set, ../vectors
#   UNIT         a unit of the list below (default: all of them)
#   --lint       verilator --lint-only -Wall on each file of rtl/ (with the modules it
#                instantiates), prints every warning and the total, fails on any
# Verilator builds each testbench against the unit's package with DEPTH set to a capacity of
# CAPACITY rows and the row blocks left out, so tables of the same formats (the golden set, a
# large set) share one build; the real row count, checked against the package, is given as
# +rows=N. Environment: SIM_CACHE=DIR keeps those builds there, keyed by a hash of everything
# that goes into them (normalised package, RTL, testbenches, Verilator version and flags);
# without it each run builds in a temporary folder.
# The walker runs once per memory latency of its cycle predictions (+latency=0..2);
# WALKER_ARGS adds plusargs to those runs (e.g. "+first=0 +count=2000"); WALKER_LATENCIES
# chooses the runs (default "0 1 2"). Its Verilator build uses the folder's own packages (its
# memory images differ per table), so it is cached per vector folder's packages.
# The frame (tb_frame.sv, last in the default list) chains every unit over the folder's
# end-to-end frame (frame_*.hex) with the image bases of walker.json; FRAME_ARGS adds plusargs
# and must hold "+model_cycles=N" (with "+latency=3", the cycle model's frame cycles on the
# testbench's hardware, testbench/README.md): without it the frame's cycles row fails, and so
# does this script. Its Verilator build, like the walker's, uses the folder's own packages.
# FRAME_HW_PKG is the frame's hardware package (default testbench/hw/frame_hw_pkg.sv, from
# testbench/hw/frame_hw.ron by `sim hardware --hw F --sv-package P`): the model's cycles must be
# for the same hardware file.
# Needs iverilog and vvp (apt-get install iverilog), or verilator 5 (apt-get install verilator).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"

# The units with a testbench tb/tb_<unit>.sv, one a line.
all_units=(
    raygen
    sqrt
    sphere
    sorter
    transform
    reciprocal
    hit_record
    normal
    walker_root
    walker
    frame
)

sim="${SIM:-icarus}"
lint=0
while [ $# -gt 0 ]; do
    case "$1" in
        --sim) sim="${2:-}"; shift 2 ;;
        --sim=*) sim="${1#--sim=}"; shift ;;
        --lint) lint=1; shift ;;
        *) break ;;
    esac
done

need() {
    for tool in "$@"; do
        if ! command -v "$tool" >/dev/null; then
            echo "run.sh: $tool not found; install it (Debian/Ubuntu: apt-get install ${tool/vvp/iverilog})" >&2
            exit 2
        fi
    done
}

# Verilator flags: the testbenches are built with lint warnings off (the RTL is linted on
# its own with -Wall); one make job, since the tests run two testbenches at a time.
vl_flags=(--binary --timing -j 1 -Wno-fatal -Wno-lint -Wno-style -Wno-TIMESCALEMOD)
capacity=32768

if [ $lint -eq 1 ]; then
    need verilator
    total=0
    for f in "$here"/rtl/*.v; do
        m="$(basename "$f" .v)"
        out="$(verilator --lint-only -Wall -y "$here/rtl" --top-module "$m" "$f" 2>&1 || true)"
        n="$(printf '%s\n' "$out" | grep -c '^%Warning' || true)"
        e="$(printf '%s\n' "$out" | grep -c '^%Error' || true)"
        if [ "$n" != 0 ] || { [ "$e" != 0 ] && ! printf '%s\n' "$out" | grep -q 'Exiting due to .* warning'; }; then
            printf '%s\n' "$out" | grep '^%' || true
        fi
        if [ "$e" != 0 ] && [ "$n" = 0 ]; then n=1; fi
        echo "lint $m: $n warnings"
        total=$((total + n))
    done
    echo "lint: $total warnings"
    [ $total -eq 0 ]
    exit $?
fi

vec="${1:-$here/../vectors}"
if [ $# -gt 0 ]; then shift; fi
units=("$@")
if [ ${#units[@]} -eq 0 ]; then units=("${all_units[@]}"); fi
case "$sim" in
    icarus) need iverilog vvp ;;
    verilator) need verilator ;;
    *) echo "run.sh: unknown simulator '$sim' (icarus or verilator)" >&2; exit 2 ;;
esac
if [ ! -d "$vec" ]; then
    echo "run.sh: vector folder $vec does not exist (write one with: sim vectors --out DIR)" >&2
    exit 2
fi
build="$(mktemp -d)"
trap 'rm -rf "$build"' EXIT

# Builds tb_<unit> with Verilator (or takes it from SIM_CACHE); prints the binary's path.
verilator_build() {
    local u="$1" key dir tmp pkg="$build/${u}_pkg.sv"
    local pkgs=("$pkg")
    if [ "$u" = walker ]; then
        pkgs=("$vec/walker_pkg.sv" "$vec/walker_visits_pkg.sv")
    elif [ "$u" = frame ]; then
        pkgs=("${frame_pkgs[@]}")
    else
        sed -E -e "s/^( *localparam int DEPTH = )[0-9]+;.*/\1$capacity;  \/\/ capacity (run.sh)/" \
            -e '/^ *localparam int [A-Z]+_(FIRST|COUNT) = /d' "$vec/${u}_pkg.sv" >"$pkg"
    fi
    key="$( { verilator --version; printf '%s\n' "${vl_flags[@]}"; cat "${pkgs[@]}" \
        "$here"/rtl/*.v "$here"/tb/*.sv "$here"/tb/*.svh; } | sha256sum | cut -c1-16)"
    if [ -n "${SIM_CACHE:-}" ]; then
        mkdir -p "$SIM_CACHE"
        dir="$SIM_CACHE/tb_$u-$key"
    else
        dir="$build/tb_$u-$key"
    fi
    if [ ! -x "$dir/Vtb_$u" ]; then
        tmp="$(mktemp -d "${dir}.XXXXXX")"
        if ! verilator "${vl_flags[@]}" -I"$here/tb" -y "$here/rtl" --top-module "tb_$u" \
            -Mdir "$tmp" "${pkgs[@]}" "$here/tb/tb_$u.sv" >"$tmp/build.log" 2>&1; then
            cat "$tmp/build.log" >&2
            rm -rf "$tmp"
            return 1
        fi
        # Another run may have built the same key meanwhile: either copy is the same.
        mv -T "$tmp" "$dir" 2>/dev/null || rm -rf "$tmp"
    fi
    echo "$dir/Vtb_$u"
}

# The frame's packages (the sorter's for its network: N, D and the model's pairs), and the plusargs of its images' memory bases (walker.json's
# parameters.images, whose keys are written sorted: attr_base, index, node_base).
frame_pkgs=("${FRAME_HW_PKG:-$here/hw/frame_hw_pkg.sv}" "$vec/frame_pixels_pkg.sv" "$vec/frame_instances_pkg.sv" "$vec/frame_camera_pkg.sv"
    "$vec/walker_pkg.sv" "$vec/sorter_pkg.sv")
frame_bases() {
    sed -n '/"images": \[/,/^    \]/p' "$vec/walker.json" | awk -F': ' '
        /"attr_base"/ { a = $2 + 0 }
        /"index"/ { i = $2 + 0 }
        /"node_base"/ { printf "+nb%d=%d +ab%d=%d ", i, $2 + 0, i, a }'
}

status=0
for u in "${units[@]}"; do
    echo "== $u ($sim): testbench/tb/tb_$u.sv, vectors $vec/$u.hex"
    pkg0="$vec/${u}_pkg.sv"
    if [ "$u" = frame ]; then pkg0="$vec/frame_pixels_pkg.sv"; fi
    if [ ! -f "$here/tb/tb_$u.sv" ] || [ ! -f "$pkg0" ]; then
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
    elif [ "$u" = frame ]; then
        pkgs=("${frame_pkgs[@]}")
        runs=("$(frame_bases) ${FRAME_ARGS:-}")
    fi
    if [ "$sim" = icarus ]; then
        # -Wno-sensitivity-entire-array: the walker's @* blocks read small per-axis arrays whole.
        iverilog -g2012 -Wall -Wno-sensitivity-entire-array -s "tb_$u" -I "$here/tb" -o "$build/tb_$u" \
            "${pkgs[@]}" "$here"/rtl/*.v "$here/tb/tb_$u.sv"
        cmd=(vvp -n "$build/tb_$u" "+vectors=$vec")
    elif [ "$u" = frame ]; then
        bin="$(verilator_build "$u")" || { status=1; continue; }
        cmd=("$bin" "+vectors=$vec")
    else
        rows="$(grep -cv -e '^//' -e '^$' "$vec/$u.hex" || true)"
        depth="$(sed -nE 's/^ *localparam int DEPTH = ([0-9]+);.*/\1/p' "$vec/${u}_pkg.sv")"
        if [ "$rows" != "$depth" ] || [ "$rows" -gt $capacity ]; then
            echo "run.sh: $u.hex has $rows rows, its package says $depth (at most $capacity)" >&2
            status=1
            continue
        fi
        bin="$(verilator_build "$u")" || { status=1; continue; }
        cmd=("$bin" "+vectors=$vec" "+rows=$rows")
    fi
    for extra in "${runs[@]}"; do
        # Verilator reports $finish on a line of its own: not part of the testbench's output.
        # shellcheck disable=SC2086
        # A testbench that stops with $fatal exits non-zero: print what it said, fail.
        out="$("${cmd[@]}" $extra | grep -v '^- .*Verilog \$finish$')" || status=1
        printf '%s\n' "$out"
        last="$(printf '%s\n' "$out" | tail -n 1)"
        if [[ ! "$last" =~ ^([0-9]+)\ passed,\ ([0-9]+)\ failed$ ]] || [ "${BASH_REMATCH[2]}" != 0 ]; then
            status=1
        fi
    done
done
exit $status
