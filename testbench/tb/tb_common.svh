// Shared body of the self-checking testbenches (included inside each tb_<unit> module, after
// `import <unit>_vectors_pkg::*;` and a `localparam UNIT = "<unit>"`).
//
// What it does: reads <dir>/<unit>.hex (dir from +vectors=DIR, default "vectors") with
// $readmemh into rows[]; after a short reset drives one row per cycle, leaving a bubble in
// every 17th slot so valid propagation is exercised; remembers the cycle each row entered.
// The including module compares the unit's outputs with the row's expected fields through
// check_field() inside `check_row_begin` / `check_row_end`; a row passes when every field
// matches (4-state: X or Z never match) and it left exactly LATENCY cycles after it entered.
// The last line printed is "N passed, N failed" (rows never seen count as failed).
//
// Units instantiated side by side (the walk-issue units of a k-wide pipeline: the package's
// UNITS, `sim vectors --walk-lanes`) define, before the include:
//   `TB_UNITS          units (default 1); each slot then drives rows g·TB_UNITS + u into unit
//                      u, all in the same cycle, through drive_valid_u[u] and
//                      drive_rows_all[u*WORD_BITS +: WORD_BITS] (drive_valid / drive_row are
//                      unit 0's). The including module checks the units in unit order at each
//                      falling edge, so rows are checked in row order, each against its unit.
// Units with data-dependent timing (the sorter) define, before the include:
//   `TB_READY          the unit accepts a row this cycle (default 1: II = 1), sampled at the
//                      falling edge, so it must be a registered signal;
//   `TB_LATENCY(row)   the cycles a row must take (default LATENCY), e.g. a field of the row;
// and may mark a row failed from their own checks with mark_bad(row, message).
// Runs the same in Icarus Verilog (-g2012) and Verilator (--binary --timing): no fork/join,
// only delays, edges and waits on variables.

`ifndef TB_READY
`define TB_READY 1'b1
`endif
`ifndef TB_LATENCY
`define TB_LATENCY(r) LATENCY
`endif
`ifndef TB_UNITS
`define TB_UNITS 1
`endif

localparam int MAX_REPORTS = 10;    // failures printed in detail
localparam int BUBBLE_EVERY = 17;

reg clk = 1'b0;
always #5 clk = ~clk;
reg rst = 1'b1;

// Rows of the table: DEPTH, or +rows=N. run.sh builds Verilator testbenches against the
// package with DEPTH set to a capacity (so one build serves every table of the same
// formats) and gives the real count as +rows=N, which it checks against the package first.
int depth = DEPTH;
reg [WORD_BITS-1:0] rows [0:DEPTH-1];
reg                 drive_valid = 1'b0;
reg [WORD_BITS-1:0] drive_row = '0;
reg [`TB_UNITS-1:0]           drive_valid_u = '0;
reg [`TB_UNITS*WORD_BITS-1:0] drive_rows_all = '0;
int drive_u;
reg [WORD_BITS-1:0] exp_row;

longint cycle = 0;
longint issued_at [0:DEPTH-1];
bit     row_bad [0:DEPTH-1];
longint max_latency = LATENCY;
int n_issued = 0;
int n_checked = 0;
int n_passed = 0;
int n_failed = 0;
int n_reports = 0;
int slot = 0;
int first_latency = -1;
bit row_ok;
bit format_ok = 1'b1;
string dir;
string path;

always @(posedge clk) cycle <= cycle + 1;

// Drive: one row per unit and cycle at the falling edge; the next rising edge samples it.
always @(negedge clk) begin
    drive_valid_u = '0;
    if (!(rst || n_issued >= depth || !format_ok)
        && !(slot % BUBBLE_EVERY == BUBBLE_EVERY - 1 || `TB_READY !== 1'b1)) begin
        for (drive_u = 0; drive_u < `TB_UNITS && n_issued < depth; drive_u = drive_u + 1) begin
            drive_rows_all[drive_u*WORD_BITS +: WORD_BITS] = rows[n_issued];
            drive_valid_u[drive_u] = 1'b1;
            issued_at[n_issued] = cycle;
            if (longint'(`TB_LATENCY(rows[n_issued])) > max_latency)
                max_latency = longint'(`TB_LATENCY(rows[n_issued]));
            n_issued = n_issued + 1;
        end
    end
    drive_row = drive_rows_all[0 +: WORD_BITS];
    drive_valid = drive_valid_u[0];
    slot = slot + 1;
end

// One failed field of the current row.
task automatic check_field(input string name, input logic [127:0] got, input logic [127:0] expected);
    if (got !== expected) begin
        row_ok = 1'b0;
        if (n_reports < MAX_REPORTS)
            $display("FAIL %s row %0d: %s = %h, expected %h", UNIT, n_checked, name, got, expected);
        n_reports = n_reports + 1;
    end
endtask

// Opens the check of the next expected row (call on each valid output, at the falling edge).
task automatic check_row_begin;
    row_ok = 1'b1;
    if (n_checked < depth) begin
        exp_row = rows[n_checked];
        if (first_latency < 0) first_latency = int'(cycle - issued_at[n_checked]);
        if (row_bad[n_checked]) row_ok = 1'b0;
        if (cycle - issued_at[n_checked] != longint'(`TB_LATENCY(exp_row))) begin
            row_ok = 1'b0;
            if (n_reports < MAX_REPORTS)
                $display("FAIL %s row %0d: left after %0d cycles, the model's latency is %0d",
                         UNIT, n_checked, cycle - issued_at[n_checked], `TB_LATENCY(exp_row));
            n_reports = n_reports + 1;
        end
    end else begin
        exp_row = '0;
        row_ok = 1'b0;
        $display("FAIL %s: an output beyond the %0d rows", UNIT, depth);
    end
endtask

task automatic check_row_end;
    if (row_ok) n_passed = n_passed + 1;
    else n_failed = n_failed + 1;
    n_checked = n_checked + 1;
endtask

// A failure a testbench found outside check_row (e.g. its unit's ready timing): the row
// fails when it is checked.
task automatic mark_bad(input int row, input string what);
    if (row >= 0 && row < depth) row_bad[row] = 1'b1;
    if (n_reports < MAX_REPORTS) $display("FAIL %s row %0d: %s", UNIT, row, what);
    n_reports = n_reports + 1;
endtask

// A port width that disagrees with the manifest: nothing can be checked.
task automatic require_width(input string name, input int rtl, input int manifest);
    if (rtl != manifest) begin
        $display("FAIL %s: field %s is %0d bits in the vectors, %0d in the RTL", UNIT, name, manifest, rtl);
        format_ok = 1'b0;
    end
endtask

integer tail;
initial begin
    for (tail = 0; tail < DEPTH; tail = tail + 1) row_bad[tail] = 1'b0;
    if (!$value$plusargs("vectors=%s", dir)) dir = "vectors";
    if ($value$plusargs("rows=%d", depth) && (depth < 0 || depth > DEPTH)) begin
        $display("FAIL %s: +rows=%0d, this build holds at most %0d rows", UNIT, depth, DEPTH);
        format_ok = 1'b0;
        depth = 0;
    end
    path = $sformatf("%0s/%0s.hex", dir, UNIT);
    $readmemh(path, rows);
    #1;
    if (!format_ok) begin
        $display("%0d passed, %0d failed", 0, depth);
        $finish;
    end
    repeat (3) @(negedge clk);
    rst = 1'b0;
    wait (n_issued == depth);
    // Until every row came out, or long enough after the last went in that none can.
    for (tail = 0; tail < max_latency + 4 * II + 20 && n_checked < depth; tail = tail + 1)
        @(negedge clk);
    repeat (2) @(negedge clk);  // anything beyond the last row is reported too
    if (n_checked < depth) begin
        $display("FAIL %s: %0d rows never came out", UNIT, depth - n_checked);
        n_failed = n_failed + (depth - n_checked);
    end
    $display("%s: %0d rows from %s, latency %0d cycles (model %0d), II %0d, %0d bubbles",
             UNIT, depth, dir, first_latency, LATENCY, II, slot / BUBBLE_EVERY);
    if (`TB_UNITS > 1)
        $display("%s: %0d units side by side, row i checked at unit i mod %0d", UNIT, `TB_UNITS, `TB_UNITS);
    $display("%0d passed, %0d failed", n_passed, n_failed);
    $finish;
end
