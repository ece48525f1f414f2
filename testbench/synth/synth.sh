#!/usr/bin/env bash
# Synthesises every RTL unit of testbench/synth/units.tsv with Yosys for UltraScale+
# (`synth_xilinx -family xcup -flatten`) and prints, per unit, the mapped cells the resource
# estimate counts — LUTs (LUT1..LUT6), flip-flops (FD*; SRL16E/SRLC32E shift registers
# separately), DSP48E2, block RAM (RAMB18/36) and UltraRAM — and the longest combinational
# path between registers in cells (Yosys `ltp -noff` with registers, shift registers, DSP48E2,
# RAMs and I/O buffers taken out of the selection, so every path ends at one of them; LUTs,
# CARRY4 and MUXF7/8/9 each count one), and the wall time. It also writes the mapped netlist
# as JSON ($logs/UNIT.json), from which `sim hardware --synth` counts logic levels per stage
# (docs/cycle-model.md §1.5).
#
# Usage: testbench/synth/synth.sh [UNIT ...]      (default: every unit of units.tsv)
# Needs yosys (0.23 tested; Debian/Ubuntu: apt-get install yosys). Logs: $SYNTH_LOGS or a
# temporary folder, deleted at exit.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
rtl="$here/../rtl"
vectors="$here/../../vectors"
if ! command -v yosys >/dev/null; then
    echo "synth.sh: yosys not found (apt-get install yosys)" >&2
    exit 2
fi
logs="${SYNTH_LOGS:-}"
if [ -z "$logs" ]; then logs="$(mktemp -d)"; trap 'rm -rf "$logs"' EXIT; fi
mkdir -p "$logs"
want=("$@")
printf '%-12s %7s %7s %6s %8s %6s %6s %7s %7s\n' unit LUT FF SRL DSP48E2 BRAM URAM levels wall_s
status=0
while read -r unit top files params _dsp_vs_model _reason; do
    case "$unit" in ''|'#'*) continue ;; esac
    if [ ${#want[@]} -gt 0 ] && [[ ! " ${want[*]} " =~ " $unit " ]]; then continue; fi
    ys="$logs/$unit.ys"
    {
        printf 'read_verilog -defer'
        IFS=, read -ra fl <<<"$files"
        for f in "${fl[@]}"; do printf ' %s' "$rtl/$f"; done
        printf '\n'
        if [ "$params" != "-" ]; then
            IFS=, read -ra pl <<<"$params"
            for p in "${pl[@]}"; do
                v="${p#*=}"; v="${v//\{vectors\}/$vectors}"
                # A number or a sized constant (e.g. the sorter's PAIRS, 1280'h...) as it is;
                # anything else is a string (a file name).
                if [[ "$v" =~ ^[0-9]+$ || "$v" =~ ^[0-9]+\'[bdh][0-9a-fA-F_]+$ ]]; then
                    printf 'chparam -set %s %s %s\n' "${p%%=*}" "$v" "$top"
                else
                    printf 'chparam -set %s "%s" %s\n' "${p%%=*}" "$v" "$top"
                fi
            done
        fi
        printf 'synth_xilinx -family xcup -flatten -top %s\n' "$top"
        printf 'tee -o %s stat\n' "$logs/$unit.stat"
        printf 'write_json %s\n' "$logs/$unit.json"
        printf 'select -set seq t:FD* t:SRL* t:DSP48E2 t:RAMB* t:URAM* t:BUFG t:IBUF t:OBUF\n'
        printf 'tee -o %s ltp -noff * @seq %%d\n' "$logs/$unit.ltp"
    } >"$ys"
    t0=$(date +%s.%N)
    if ! yosys -q -l "$logs/$unit.log" "$ys" >/dev/null 2>&1; then
        echo "synth.sh: yosys failed on $unit (log: $logs/$unit.log)" >&2
        status=1
        continue
    fi
    t1=$(date +%s.%N)
    cells() { awk -v re="$1" '$1 ~ re { s += $2 } END { print s + 0 }' "$logs/$unit.stat"; }
    levels=$(sed -n 's/.*(length=\([0-9]*\)).*/\1/p' "$logs/$unit.ltp" | head -n 1)
    printf '%-12s %7s %7s %6s %8s %6s %6s %7s %7.1f\n' "$unit" \
        "$(cells '^LUT[1-6]$')" "$(cells '^FD')" "$(cells '^SRL')" "$(cells '^DSP48E2$')" \
        "$(cells '^RAMB')" "$(cells '^URAM')" "${levels:-?}" "$(echo "$t1 - $t0" | bc)"
done <"$here/units.tsv"
exit $status
