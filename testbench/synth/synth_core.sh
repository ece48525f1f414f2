#!/usr/bin/env bash
# synth_core.sh [--per-module] HW_PKG [TOP]: Yosys synthesis of the whole svo_core (front end,
# hit buffer, walk section with its walker pool) for UltraScale+ (`synth_xilinx -family xcup
# -flatten`) with its parameters from a hardware package of testbench/hw/ (`sim hardware
# --sv-package`), and prints the mapped cells the resource estimate counts: LUT1..LUT6,
# LUT-RAM (RAM32M/RAM64M/RAM*X1*), shift registers (SRL16E/SRLC32E), flip-flops (FD*),
# DSP48E2, RAMB36/RAMB18, URAM288, with Yosys's CPU time and the wall time; with SIM=path to
# `sim` (release build), the model's estimate for the same hardware file below it. It writes
# the mapped netlist as JSON, for `sim hardware --levels JSON --top svo_core` and
# netlist_blocks.py (the cells per RTL instance).
#
# Pipeline position: none; the whole core's synthesis against the model's estimate
# (testbench/README.md, "Synthesis", and docs/cycle-model.md §1.5). Not in CI: one run takes
# tens of minutes of Yosys CPU.
#
# svo_core is plain Verilog below the PeakRDL register block, so Debian's Yosys reads it
# without yosys-slang. Its parameters are svo_top's (svo_top.sv's `svo_core #(...)`) computed
# here from the package's constants, so that the netlist is the core svo_top builds on that
# hardware; svo_top's own parts (the register block, the instance table, the node store or
# cache, the AXI masters and the stream FIFO) are not in it. The core's ports are the
# netlist's: what svo_top ties to constants (origin_f64, dir_f64's high 96 bits) stays a
# port here, so svo_raygen's three origin converters keep the
# logic their overflow flag needs. NPIX (environment, default 768,
# svo_top's default) sizes the hit buffer, as svo_top's parameter does.
#
# --per-module: synthesise without -flatten and print `stat` per module instead (the blocks'
# mapped cells, for telling which block a difference from the estimate comes from; each
# module is optimised on its own, so the sum can differ a little from the flat run).
# TOP: the module (default svo_core). SYNTH_LOGS: keep the logs, the script and the JSON in
# that folder (default: a temporary folder, deleted at exit, JSON copied to SYNTH_JSON if set).
# RECIP_SEED: the reciprocal seed ROM (default vectors/reciprocal_seed.hex).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
rtl="$here/../rtl"
per_module=0
if [ "${1:-}" = --per-module ]; then per_module=1; shift; fi
if [ $# -lt 1 ]; then
    echo "usage: synth_core.sh [--per-module] HW_PKG [TOP]" >&2
    exit 2
fi
pkg="$1"
top="${2:-svo_core}"
[ -f "$pkg" ] || { echo "synth_core.sh: no package $pkg" >&2; exit 2; }
command -v yosys >/dev/null || { echo "synth_core.sh: yosys not found (apt-get install yosys)" >&2; exit 2; }
seed="${RECIP_SEED:-$here/../../vectors/reciprocal_seed.hex}"
[ -f "$seed" ] || { echo "synth_core.sh: no reciprocal seed ROM at $seed" >&2; exit 2; }
npix="${NPIX:-768}"
logs="${SYNTH_LOGS:-}"
if [ -z "$logs" ]; then logs="$(mktemp -d)"; trap 'rm -rf "$logs"' EXIT; fi
mkdir -p "$logs"

# The package's `localparam [int|bit [..]] NAME = VALUE;` lines, by name.
declare -A P
while read -r name value; do P[$name]="$value"; done < <(
    sed -n 's/^ *localparam \(int \|bit \(\[[0-9:]*\] \)\?\)\?\([A-Z0-9_]*\) = \([^;]*\);.*/\3 \4/p' "$pkg")
need() { [ -n "${P[$1]:-}" ] || { echo "synth_core.sh: $pkg has no $1" >&2; exit 2; }; echo "${P[$1]}"; }
clog2() { local v=$(( $1 - 1 )) n=0; while [ $v -gt 0 ]; do v=$(( v >> 1 )); n=$(( n + 1 )); done; echo $n; }

# Every constant used below, checked here: a `$(need ...)` inside the array below could not
# stop the script.
for name in RAY_SLOTS WALKER_POOL_WALKERS WALKER_POOL_CONTEXTS_PER_WALKER SORTER_LANES \
    NODE_MEMORY_ONCHIP_LEVELS SPHERE_UNITS WALKER_POOL_STEP_LATENCY_CYCLES \
    UNITS_RAYGEN_LATENCY_CYCLES UNITS_SPHERE_LATENCY_CYCLES UNITS_SQRT_LATENCY_CYCLES \
    SORTER_NET_DEPTH SORTER_NET_SLOTS SORTER_NET_PAIRS UNITS_TRANSFORM_LATENCY_CYCLES \
    UNITS_RECIPROCAL_LATENCY_CYCLES UNITS_WALKER_ROOT_LATENCY_CYCLES \
    HIT_BUFFER_READ_LATENCY_CYCLES HIT_BUFFER_WRITE_PORTS HIT_BUFFER_RECORD_WRITES \
    FIFOS_RAYGEN_TO_SPHERE FIFOS_SPHERE_TO_SORTER FIFOS_SORTER_TO_CHECK \
    FIFOS_CHECK_TO_TRANSFORM FIFOS_TRANSFORM_TO_RECIPROCAL FIFOS_RECIPROCAL_TO_ROOT \
    FIFOS_ROOT_TO_DISPATCH FIFOS_WALKER_TO_RECORD FIFOS_RECORD_TO_WRITE \
    TRANSFORM_UNITS RECIPROCAL_UNITS WALKER_ROOT_UNITS WALKER_POOL_STEP_CYCLES \
    WALKER_POOL_RESPONSE_REGISTER_CYCLES WALKER_POOL_REQUEST_REGISTER_CYCLES; do
    need "$name" >/dev/null
done
# What svo_core does not build, refused by name as svo_top refuses it (svo_top.sv's
# `unsupported_*` blocks), so that a package is never synthesised as something else.
refuse() { echo "synth_core.sh: $pkg: svo_core builds $1" >&2; exit 2; }
# Walk-issue lanes k = transform_units, with 3k reciprocals and k walker roots: svo_walk_wide
# at k = 1 or 2 (svo_top's `unsupported_walk_lanes`).
wk=$(need TRANSFORM_UNITS)
{ [ "$wk" = 1 ] || [ "$wk" = 2 ]; } && [ "$(need RECIPROCAL_UNITS)" = $(( 3 * wk )) ] \
    && [ "$(need WALKER_ROOT_UNITS)" = "$wk" ] \
    || refuse "one or two walk-issue lanes (transform k, reciprocal 3k, walker root k)"
[ "$(need WALKER_POOL_STEP_CYCLES)" = 1 ] || refuse "walker_pool.step_cycles 1"
[ "$(need WALKER_POOL_RESPONSE_REGISTER_CYCLES)" -le 1 ] \
    || refuse "walker_pool.response_register_cycles 0 or 1"
[ "$(need WALKER_POOL_REQUEST_REGISTER_CYCLES)" -le 1 ] \
    || refuse "walker_pool.request_register_cycles 0 or 1"
# svo_top's localparams and its svo_core instance, in its order.
slots=$(need RAY_SLOTS)
walkers=$(need WALKER_POOL_WALKERS)
contexts=$(need WALKER_POOL_CONTEXTS_PER_WALKER)
lanes_so=$(need SORTER_LANES)
nctx=$(( walkers * contexts ))
has_cache=$([ "$(need NODE_MEMORY_ONCHIP_LEVELS)" != 21 ] && echo 1 || echo 0)
params=(
    LANES="$(need SPHERE_UNITS)" NPIX="$npix" AW="$(clog2 "$npix")" PIXW=32
    SLOTS="$slots" TAGW="$([ "$slots" -gt 1 ] && clog2 "$slots" || echo 1)"
    STEP_LATENCY="$(need WALKER_POOL_STEP_LATENCY_CYCLES)"
    RG_L="$(need UNITS_RAYGEN_LATENCY_CYCLES)"
    SP_L="$(( $(need UNITS_SPHERE_LATENCY_CYCLES) + $(need UNITS_SQRT_LATENCY_CYCLES) ))"
    SO_N="$lanes_so" SO_D="$(need SORTER_NET_DEPTH)" SO_S="$(need SORTER_NET_SLOTS)"
    SO_PAIRS="$(need SORTER_NET_PAIRS)" SO_MAX_KEYS="$(( 2 * lanes_so ))"
    TR_L="$(need UNITS_TRANSFORM_LATENCY_CYCLES)" RC_L="$(need UNITS_RECIPROCAL_LATENCY_CYCLES)"
    RT_L="$(need UNITS_WALKER_ROOT_LATENCY_CYCLES)" HB_READ="$(need HIT_BUFFER_READ_LATENCY_CYCLES)"
    WRITE_PORTS="$(need HIT_BUFFER_WRITE_PORTS)" RECORD_WRITES="$(need HIT_BUFFER_RECORD_WRITES)"
    D_RG_SP="$(need FIFOS_RAYGEN_TO_SPHERE)" D_SP_SO="$(need FIFOS_SPHERE_TO_SORTER)"
    D_SO_CK="$(need FIFOS_SORTER_TO_CHECK)" D_CK_TR="$(need FIFOS_CHECK_TO_TRANSFORM)"
    D_TR_RC="$(need FIFOS_TRANSFORM_TO_RECIPROCAL)" D_RC_RT="$(need FIFOS_RECIPROCAL_TO_ROOT)"
    D_RT_DP="$(need FIFOS_ROOT_TO_DISPATCH)" D_WK_RC="$(need FIFOS_WALKER_TO_RECORD)"
    D_RC_WR="$(need FIFOS_RECORD_TO_WRITE)" DIR_FIXED=1 NINST=128 KEYN="$(( 2 * lanes_so ))"
    CONTEXTS="$contexts" WALKERS="$walkers" CW="$([ $nctx -gt 1 ] && clog2 $nctx || echo 1)"
    CTX_RESP="$([ "$has_cache" = 1 ] && echo 2 || echo 1)"
    ATTR_MERGE="$([ "$has_cache" = 1 ] && echo 0 || echo 1)"
    RESP_REG="$(need WALKER_POOL_RESPONSE_REGISTER_CYCLES)"
    REQ_REG="$(need WALKER_POOL_REQUEST_REGISTER_CYCLES)" K="$wk"
)
files=(svo_delay svo_fifo svo_elastic svo_elastic2 svo_f64_to_fixed svo_sqrt svo_raygen
    svo_sphere svo_sorter svo_front svo_transform svo_reciprocal svo_walker_root svo_walker
    svo_walker_barrel svo_walker_pool_dispatch svo_walker_pool_retire svo_walker_pool svo_normal
    svo_hit_pack svo_hit_check svo_hit_buffer svo_fifo_wide svo_unit_lanes svo_walk_pack
    svo_walk_wide svo_core)
ys="$logs/$top.ys"
{
    printf 'read_verilog -defer'
    for f in "${files[@]}"; do printf ' %s' "$rtl/$f.v"; done
    printf '\n'
    # One chparam for all (each chparam elaborates the module again).
    printf 'chparam'
    for p in "${params[@]}"; do printf ' -set %s %s' "${p%%=*}" "${p#*=}"; done
    printf ' -set RECIP_SEED_FILE "%s" %s\n' "$seed" "$top"
    if [ $per_module = 1 ]; then
        printf 'synth_xilinx -family xcup -top %s\n' "$top"
        printf 'tee -o %s stat\n' "$logs/$top.stat"
    else
        printf 'synth_xilinx -family xcup -flatten -top %s\n' "$top"
        printf 'tee -o %s stat\n' "$logs/$top.stat"
        printf 'write_json %s\n' "$logs/$top.json"
    fi
} >"$ys"
echo "synth_core.sh: $top on $(basename "$pkg"), NPIX $npix, logs in $logs" >&2
t0=$(date +%s)
# Yosys's user + system CPU time (GNU time).
cpu=$( { /usr/bin/time -f '%U %S' yosys -q -l "$logs/$top.log" "$ys" >/dev/null 2>"$logs/time.txt" \
    && tail -n 1 "$logs/time.txt" | awk '{ printf "%.0f", $1 + $2 }'; } ) || {
    grep -i 'error' "$logs/$top.log" | head -20 >&2
    echo "synth_core.sh: Yosys failed (log: $logs/$top.log)" >&2
    exit 1
}
wall=$(( $(date +%s) - t0 ))
if [ -n "${SYNTH_JSON:-}" ] && [ $per_module = 0 ]; then cp "$logs/$top.json" "$SYNTH_JSON"; fi
# Mapped cells of a `stat` block by class, weighted as src/studies/synthesis/mod.rs
# (Cells::from_stat) counts them: LUT-RAM in the LUTs it takes (8 per RAM32M16/RAM64M8, 4 per
# RAM32M/RAM64M/RAM128X1D, 2 per RAM32X1D/RAM64X1D/RAM128X1S, 1 per other).
# (Yosys 0.23 prints "CELL COUNT"; newer ones "COUNT CELL".)
classify='
function add(t, n) {
    if (t ~ /^LUT[1-6]$/) lut += n
    else if (t ~ /^(RAM32M16|RAM64M8)$/) lram += 8 * n
    else if (t ~ /^(RAM32M|RAM64M|RAM128X1D)$/) lram += 4 * n
    else if (t ~ /^(RAM32X1D|RAM64X1D|RAM128X1S)$/) lram += 2 * n
    else if (t ~ /^(RAM32X1S|RAM64X1S)$/) lram += n
    else if (t ~ /^SRL/) srl += n
    else if (t ~ /^FD/) ff += n
    else if (t == "DSP48E2") dsp += n
    else if (t ~ /^RAMB36/) b36 += n
    else if (t ~ /^RAMB18/) b18 += n
    else if (t ~ /^URAM/) uram += n
}
function row(name) {
    printf "%-34s %7d %6d %6d %7d %7d %4d %6d %6d %4d", name, lut, lram, srl, lut + lram + srl, ff, dsp, b36, b18, uram
    lut = lram = srl = ff = dsp = b36 = b18 = uram = 0
}
$2 ~ /^[0-9]+$/ && $1 ~ /^[A-Z]/ { t = $1; n = $2 }
$1 ~ /^[0-9]+$/ && $2 ~ /^[A-Z]/ { t = $2; n = $1 }
'
header() { printf '%-34s %7s %6s %6s %7s %7s %4s %6s %6s %4s%s\n' "$1" LUT LUTRAM SRL CLB_LUT FF DSP RAMB36 RAMB18 URAM "$2"; }
if [ $per_module = 1 ]; then
    # Every module's block of the statistics (a parameterised module once per parameter set);
    # the design hierarchy's total last.
    header module ''
    awk "$classify"'
        /^=== design hierarchy ===/ { if (m != "") { row(m); print "" }; m = ""; next }
        /^=== / { if (m != "") { row(m); print "" }; m = $2; next }
        m != "" && t != "" { add(t, n) } { t = "" }
        END { if (m != "") { row(m); print "" } }' "$logs/$top.stat" | sort -k5,5nr
    echo "per module as defined once (the design hierarchy's instance counts: $logs/$top.stat); Yosys CPU ${cpu} s, wall ${wall} s"
    exit 0
fi
header "$top" '  cpu_s wall_s'
awk "$classify"' t != "" { add(t, n) } { t = "" } END { row(top) }' top="$top" "$logs/$top.stat"
printf ' %6s %6s\n' "$cpu" "$wall"
# The model's estimate for the same hardware file (HW_PKG's RON: X_pkg.sv -> X.ron), its rows
# that svo_core builds: the units, the logic around them (front_gather, hit_check_pipe,
# ray_slots, elastic_pipes), the walker's contexts, every FIFO and the record write path (LUT,
# FF), their DSP48E2, the walker stacks and the deep FIFOs' BRAM36 (in the
# RAMB36 column); testbench/synth/svo_core_frame_hw.tsv groups the same rows per block.
# Not svo_core's, left out: the direction table, the hit buffer's URAM at the frame's size (the
# core's hit buffer has NPIX pixels), the node memory (on-chip banks, cache, crossbars, queues,
# MSHRs) and svo_raygen's converters (not in the estimate's totals).
ron="${pkg%_pkg.sv}.ron"
if [ -n "${SIM:-}" ] && [ -f "$ron" ]; then
    "$SIM" hardware --hw "$ron" | awk '
        /resources on/ { sec = "res"; next }
        /fabric \(estimate/ { sec = "fab"; next }
        sec == "res" && $2 ~ /^(sphere|transform|reciprocal|walker_root|normal|walker_stacks|fifo\.[a-z_]+)$/ { dsp += $4; bram += $5 }
        sec == "fab" && $2 ~ /^(sphere|sqrt|sorter|transform|reciprocal|walker_root|walker|hit_check|normal|hit_pack|front_gather|hit_check_pipe|ray_slots|elastic_pipes|walker_contexts|record_write_path|fifo\.[a-z_]+)$/ { lut += $4; ff += $5 }
        END { printf "%-34s %7s %6s %6s %7d %7d %4d %6d %6s %4s\n", "estimate (" f ")", "", "", "", lut, ff, dsp, bram, "", "" }' f="$(basename "$ron")"
fi
