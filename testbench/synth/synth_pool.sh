#!/usr/bin/env bash
# synth_pool.sh barrel|pool W R K: Yosys synthesis of the walker pool's parts for UltraScale+
# at a size, the measurements the resource estimate's walker rows are calibrated on
# (rtl_model/src/cost/fabric.rs `calibration::BARREL_K1`, `BARREL_K2`;
# rtl_model/src/cost/core_logic.rs `calibration::POOL_MEASURED`; docs/cycle-model.md §1.5,
# "The default against its RTL"). Prints one line: CLB LUTs (LUT1..6 + LUT-RAM LUTs + SRL),
# flip-flops, RAMB36 (a RAMB18 a half), and Yosys's CPU seconds.
#
#   barrel W R K  one svo_walker_barrel of R contexts and K take/result ports, flattened
#                 (W is ignored; give 1)
#   pool W R K    svo_walker_pool of W walkers × R contexts at K walk-issue lanes, its walkers
#                 (svo_walker_barrel, svo_walker) as black boxes, not flattened: the design
#                 hierarchy's total, i.e. the dispatcher, retire order and the pool's own logic
#
# Both at the default's slot tag (TAG_W 10), step latency 4, and svo_top's node memory behind
# its cache (ATTR_MERGE 0). The environment's CTX_RESP picks the pool's response ports: 2 (the
# default, svo_top's since issue 29's O(N) response side) every response on its context's own
# port; 1 node words there and attribute records on the walker ports, any context on any port
# (the pool svo_top built before, whose response decode grows as N x W).
#
# Pipeline position: none; the calibration of the fabric estimate (testbench/README.md,
# "Synthesis"). Not in CI: a pool of 8 × 16 takes about 8 minutes of Yosys CPU, 16 × 16 over 30.
# SYNTH_LOGS: keep the script, log and statistics in that folder (default: a temporary one).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
rtl="$here/../rtl"
if [ $# -ne 4 ] || { [ "$1" != barrel ] && [ "$1" != pool ]; }; then
    echo "usage: synth_pool.sh barrel|pool W R K (e.g. pool 8 16 2)" >&2
    exit 2
fi
what="$1" w="$2" r="$3" k="$4"
for v in "$w" "$r" "$k"; do
    case "$v" in
        '' | *[!0-9]*) echo "synth_pool.sh: W, R and K must be positive integers, got '$v'" >&2; exit 2 ;;
    esac
    [ "$v" -ge 1 ] || { echo "synth_pool.sh: W, R and K must be at least 1, got $v" >&2; exit 2; }
done
[ "$k" -le 2 ] || { echo "synth_pool.sh: K is 1 or 2 (the RTL refuses more), got $k" >&2; exit 2; }
if [ "$what" = barrel ] && [ "$r" -lt 2 ]; then
    echo "synth_pool.sh: a barrel has 2 or more contexts (one context is svo_walker), got R = $r" >&2
    exit 2
fi
command -v yosys > /dev/null || { echo "synth_pool.sh: yosys not found (apt-get install yosys)" >&2; exit 2; }
if [ -n "${SYNTH_LOGS:-}" ]; then
    logs="$SYNTH_LOGS"
    mkdir -p "$logs"
else
    logs="$(mktemp -d)"
    trap 'rm -rf "$logs"' EXIT
fi
ctx_resp="${CTX_RESP:-2}"
case "$ctx_resp" in
    1 | 2) ;;
    *) echo "synth_pool.sh: CTX_RESP is 1 or 2, got '$ctx_resp'" >&2; exit 2 ;;
esac
n=$(( w * r ))
cw=1
while [ $(( 1 << cw )) -lt "$n" ]; do cw=$(( cw + 1 )); done
ys="$logs/$what.ys"
if [ "$what" = barrel ]; then
    cat > "$ys" <<EOF
read_verilog -defer $rtl/svo_walker_barrel.v
chparam -set CONTEXTS $r -set K $k -set TAG_W 10 -set STEP_LATENCY 4 svo_walker_barrel
synth_xilinx -family xcup -flatten -top svo_walker_barrel
tee -o $logs/$what.stat stat
EOF
else
    cat > "$ys" <<EOF
read_verilog -lib $rtl/svo_walker_barrel.v $rtl/svo_walker.v
read_verilog -defer $rtl/svo_walker_pool_dispatch.v $rtl/svo_walker_pool_retire.v $rtl/svo_walker_pool.v
chparam -set WALKERS $w -set CONTEXTS $r -set K $k -set TAG_W 10 -set CW $cw -set STEP_LATENCY 4 -set CTX_RESP $ctx_resp -set ATTR_MERGE 0 svo_walker_pool
synth_xilinx -family xcup -top svo_walker_pool
tee -o $logs/$what.stat stat
EOF
fi
if ! /usr/bin/time -f '%U %S' -o "$logs/time.txt" yosys -q -l "$logs/$what.log" "$ys" > /dev/null 2>&1; then
    grep -i 'error' "$logs/$what.log" | head -20 >&2
    echo "synth_pool.sh: Yosys failed (log: $logs/$what.log)" >&2
    exit 1
fi
cpu=$(awk '{ printf "%.0f", $1 + $2 }' "$logs/time.txt")
# The flat netlist has one statistics block; the hierarchy's total is the last block after
# "design hierarchy". (Yosys 0.23 prints "CELL COUNT"; newer ones "COUNT CELL".)
awk -v what="$what" -v w="$w" -v r="$r" -v k="$k" -v cpu="$cpu" '
    /=== design hierarchy ===/ { lut = lram = srl = ff = b36 = b18 = 0 }
    { if ($2 ~ /^[0-9]+$/ && $1 ~ /^[A-Z]/) { t = $1; c = $2 } else if ($1 ~ /^[0-9]+$/ && $2 ~ /^[A-Z]/) { t = $2; c = $1 } else next }
    t ~ /^LUT[1-6]$/ { lut += c }
    t ~ /^(RAM32M16|RAM64M8)$/ { lram += 8 * c }
    t ~ /^(RAM32M|RAM64M|RAM128X1D)$/ { lram += 4 * c }
    t ~ /^(RAM32X1D|RAM64X1D|RAM128X1S)$/ { lram += 2 * c }
    t ~ /^(RAM32X1S|RAM64X1S)$/ { lram += c }
    t ~ /^SRL/ { srl += c }
    t ~ /^FD/ { ff += c }
    t ~ /^RAMB36/ { b36 += c }
    t ~ /^RAMB18/ { b18 += c }
    END { printf "%s W %d R %d K %d: %d CLB LUT (%d LUT-RAM, %d SRL), %d FF, %.1f RAMB36; Yosys %s s CPU\n",
          what, w, r, k, lut + lram + srl, lram, srl, ff, b36 + b18 / 2, cpu }' "$logs/$what.stat"
