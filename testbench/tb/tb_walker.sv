// tb_walker: svo_walker_root + svo_walker against walker.hex and walker_visits.hex
// (`sim vectors`), the walks reading walker_nodes.hex / walker_attrs.hex through a memory
// model with a fixed latency.
//
// What it does: NW independent walkers (each a root unit, a one-context walker and its own
// memory port of latency L = MEM_LATENCY_<k>, k from +latency=K, default 0) take the rows
// first..first+count-1 (+first=, +count=; default all) in turn; each walker takes its next
// row when its previous walk has left. Per row it checks every output field of walker.hex
// (outcome, t, voxel, level, attr, entry axis, steps, fetches, the number of nodes entered),
// every node entered against the walk's rows of walker_visits.hex in order, the hit's
// attribute record against walker_attrs.hex, the root unit's latency (ROOT_LATENCY), and the
// walker's cycles from accept to result against the row's cycles_<k>, the cycle model's
// prediction. The memory refuses nothing (one read outstanding per walker) and returns every
// read exactly L cycles after the cycle it was requested in. The first failures are printed;
// the last line is "N passed, N failed".
`timescale 1ns/1ps
module tb_walker;
    import walker_vectors_pkg::*;
    localparam UNIT = "walker";
    localparam int NW = 16;                    // walkers in parallel
    localparam int MAX_REPORTS = 10;
    localparam int TI = T_WIDTH + 1;
    localparam int PW = O_X_WIDTH;
    localparam int VBITS = walker_visits_vectors_pkg::WORD_BITS;
    localparam int VDEPTH = walker_visits_vectors_pkg::DEPTH;

    reg clk = 1'b0;
    always #5 clk = ~clk;
    reg rst = 1'b1;
    longint cyc = 0;
    always @(posedge clk) cyc <= cyc + 1;

    reg [WORD_BITS-1:0] rows [0:DEPTH-1];
    reg [VBITS-1:0]     visits [0:(VDEPTH > 0 ? VDEPTH : 1)-1];
    reg [31:0]          nodes [0:NODE_WORDS-1];
    reg [63:0]          attrs [0:(ATTR_RECORDS > 0 ? ATTR_RECORDS : 1)-1];

    int lat_index = 0, mem_latency = 1, first = 0, count = DEPTH, last = DEPTH;
    int next_row = 0, n_passed = 0, n_failed = 0, n_timed = 0, n_reports = 0, n_done = 0;
    longint total_cycles = 0;
    bit format_ok = 1'b1;
    string dir;

    // Per walker: what the driver issued and the checker finished (free when equal).
    int  issued [0:NW-1];
    int  finished [0:NW-1];
    reg  drive_valid [0:NW-1];
    reg [WORD_BITS-1:0] drive_row [0:NW-1];
    reg [31:0] drive_tag [0:NW-1];
    longint issue_cyc [0:NW-1];

    task automatic report(input string what);
        if (n_reports < MAX_REPORTS) $display("FAIL %s %s", UNIT, what);
        n_reports = n_reports + 1;
    endtask

    task automatic require_width(input string name, input int rtl, input int manifest);
        if (rtl != manifest) begin
            $display("FAIL %s: field %s is %0d bits in the vectors, %0d in the RTL", UNIT, name, manifest, rtl);
            format_ok = 1'b0;
        end
    endtask

    genvar gi;
    generate
        for (gi = 0; gi < NW; gi = gi + 1) begin : lane
            wire [WORD_BITS-1:0] r = drive_row[gi];
            wire          root_valid, root_enter;
            wire [3*TI-1:0] root_t0, root_t1;
            wire [3*(PW+1)-1:0] root_o;
            wire [3*PW-1:0] root_half;
            wire [2:0]    root_zero, root_neg;
            wire [31:0]   root_tag;
            svo_walker_root #(
                .POS_W(PW), .POS_FRAC(O_X_FRAC), .INV_W(INV_X_WIDTH), .INV_FRAC(INV_X_FRAC),
                .T_W(T_WIDTH), .T_FRAC(T_FRAC), .PROD(ROOT_LATENCY - 4), .TAG_W(32)
            ) root (
                .clk(clk), .rst(rst), .in_valid(drive_valid[gi]),
                .in_o({r[O_Z_LSB +: PW], r[O_Y_LSB +: PW], r[O_X_LSB +: PW]}),
                .in_inv({r[INV_Z_LSB +: INV_X_WIDTH], r[INV_Y_LSB +: INV_X_WIDTH], r[INV_X_LSB +: INV_X_WIDTH]}),
                .in_zero({r[ZERO_Z_LSB], r[ZERO_Y_LSB], r[ZERO_X_LSB]}),
                .in_neg({r[NEGATIVE_Z_LSB], r[NEGATIVE_Y_LSB], r[NEGATIVE_X_LSB]}),
                .in_half({r[HALF_Z_LSB +: PW], r[HALF_Y_LSB +: PW], r[HALF_X_LSB +: PW]}),
                .in_tag(drive_tag[gi]),
                .out_valid(root_valid), .out_enter(root_enter), .out_t0(root_t0),
                .out_t1(root_t1), .out_o(root_o), .out_half(root_half), .out_zero(root_zero),
                .out_neg(root_neg), .out_tag(root_tag));

            // The root's row is still in drive_row (the walker takes one walk at a time).
            wire         in_ready, mem_req_valid, mem_req_attr, out_valid;
            wire [31:0]  mem_req_addr;
            wire         mem_resp_valid;
            reg  [63:0]  mem_resp_data;
            wire [1:0]   outcome, entry_axis;
            wire [T_WIDTH-1:0] t;
            wire [59:0]  voxel, visit_coords;
            wire [4:0]   level, visit_level;
            wire [31:0]  attr, steps, fetches, out_tag;
            wire [63:0]  attr_data;
            wire         visit_valid;
            int          left = 0;
            svo_walker #(
                .POS_W(PW), .T_W(T_WIDTH), .STACK_DEPTH(STACK_DEPTH), .MAX_STEPS(MAX_STEPS),
                .STEP_LATENCY(STEP_LATENCY), .TAG_W(32)
            ) walker (
                .clk(clk), .rst(rst),
                .in_valid(root_valid), .in_ready(in_ready), .in_enter(root_enter),
                .in_t0(root_t0), .in_t1(root_t1), .in_o(root_o), .in_half(root_half),
                .in_zero(root_zero), .in_neg(root_neg),
                .in_node_base(r[NODE_BASE_LSB +: 32]), .in_attr_base(r[ATTR_BASE_LSB +: 32]),
                .in_tag(root_tag),
                .mem_req_valid(mem_req_valid), .mem_req_ready(left <= 1),
                .mem_req_attr(mem_req_attr), .mem_req_addr(mem_req_addr),
                .mem_resp_valid(mem_resp_valid), .mem_resp_data(mem_resp_data),
                .out_valid(out_valid), .out_ready(1'b1), .out_outcome(outcome), .out_t(t),
                .out_voxel(voxel), .out_level(level), .out_attr(attr),
                .out_entry_axis(entry_axis), .out_steps(steps), .out_fetches(fetches),
                .out_attr_data(attr_data), .out_tag(out_tag),
                .visit_valid(visit_valid), .visit_level(visit_level),
                .visit_coords(visit_coords), .issue_grant(1'b1), .issue_req(), .ev_lat(),
                .ev_disp(), .ev_resp());

            // The memory: a read requested in cycle c is valid in cycle c + L.
            `define TB_MEM_WHERE $sformatf("row %0d: ", drive_tag[gi])
            `include "tb_fixed_latency_mem.svh"

            // The checker.
            longint accept_cyc;
            int     nvisit;
            bit     ok;
            reg [WORD_BITS-1:0] e;
            reg [VBITS-1:0] v;
            int vfirst, vcount;
            always @(posedge clk) if (!rst) begin
                if (root_valid) begin
                    accept_cyc = cyc;
                    nvisit = 0;
                    ok = 1'b1;
                    if (in_ready !== 1'b1) begin
                        ok = 1'b0;
                        report($sformatf("row %0d: the walker was not ready for its walk", root_tag));
                    end
                    if (cyc - issue_cyc[gi] != ROOT_LATENCY) begin
                        ok = 1'b0;
                        report($sformatf("row %0d: root unit took %0d cycles, the model's %0d",
                                         root_tag, cyc - issue_cyc[gi], ROOT_LATENCY));
                    end
                end
                if (visit_valid) begin
                    e = rows[out_tag];
                    vfirst = e[VISITS_FIRST_LSB +: 32];
                    vcount = e[VISITS_COUNT_LSB +: 32];
                    if (nvisit >= vcount) begin
                        ok = 1'b0;
                        report($sformatf("row %0d: node %0d entered (level %0d), the model entered %0d",
                                         out_tag, nvisit + 1, visit_level, vcount));
                    end else begin
                        v = visits[vfirst + nvisit];
                        if (visit_level !== v[walker_visits_vectors_pkg::LEVEL_LSB +: 5]
                            || visit_coords[19:0] !== v[walker_visits_vectors_pkg::X_LSB +: 20]
                            || visit_coords[39:20] !== v[walker_visits_vectors_pkg::Y_LSB +: 20]
                            || visit_coords[59:40] !== v[walker_visits_vectors_pkg::Z_LSB +: 20]
                            || v[walker_visits_vectors_pkg::WALK_LSB +: 32] != out_tag) begin
                            ok = 1'b0;
                            report($sformatf("row %0d: node %0d entered is level %0d (%0d, %0d, %0d), visit row %0d says level %0d (%0d, %0d, %0d)",
                                   out_tag, nvisit, visit_level, visit_coords[19:0], visit_coords[39:20],
                                   visit_coords[59:40], vfirst + nvisit,
                                   v[walker_visits_vectors_pkg::LEVEL_LSB +: 5], v[walker_visits_vectors_pkg::X_LSB +: 20],
                                   v[walker_visits_vectors_pkg::Y_LSB +: 20], v[walker_visits_vectors_pkg::Z_LSB +: 20]));
                        end
                    end
                    nvisit = nvisit + 1;
                end
                if (out_valid) begin
                    e = rows[out_tag];
                    check(out_tag, "outcome", outcome, e[OUTCOME_LSB +: 2], ok);
                    check(out_tag, "t", t, e[T_LSB +: T_WIDTH], ok);
                    check(out_tag, "voxel_x", voxel[19:0], e[VOXEL_X_LSB +: 20], ok);
                    check(out_tag, "voxel_y", voxel[39:20], e[VOXEL_Y_LSB +: 20], ok);
                    check(out_tag, "voxel_z", voxel[59:40], e[VOXEL_Z_LSB +: 20], ok);
                    check(out_tag, "level", level, e[LEVEL_LSB +: 5], ok);
                    check(out_tag, "attr", attr, e[ATTR_LSB +: 32], ok);
                    check(out_tag, "entry_axis", entry_axis, e[ENTRY_AXIS_LSB +: 2], ok);
                    check(out_tag, "steps", steps, e[STEPS_LSB +: 32], ok);
                    check(out_tag, "fetches", fetches, e[FETCHES_LSB +: 32], ok);
                    check(out_tag, "visits_count", nvisit, e[VISITS_COUNT_LSB +: 32], ok);
                    if (e[OUTCOME_LSB +: 2] == 1)
                        check(out_tag, "attribute record", attr_data,
                              attrs[e[ATTR_BASE_LSB +: 32] + e[ATTR_LSB +: 32]], ok);
                    if (cyc - accept_cyc == expected_cycles(e)) n_timed = n_timed + 1;
                    else begin
                        ok = 1'b0;
                        report($sformatf("row %0d: %0d cycles from accept to result, the model predicts %0d (memory latency %0d)",
                                         out_tag, cyc - accept_cyc, expected_cycles(e), mem_latency));
                    end
                    total_cycles = total_cycles + (cyc - accept_cyc);
                    if (ok) n_passed = n_passed + 1;
                    else n_failed = n_failed + 1;
                    n_done = n_done + 1;
                    finished[gi] = finished[gi] + 1;
                end
            end
        end
    endgenerate

    function automatic longint expected_cycles(input reg [WORD_BITS-1:0] e);
        case (lat_index)
            0: expected_cycles = e[CYCLES_0_LSB +: 32];
            1: expected_cycles = e[CYCLES_1_LSB +: 32];
            default: expected_cycles = e[CYCLES_2_LSB +: 32];
        endcase
    endfunction

    task automatic check(input int row, input string name, input logic [63:0] got,
                         input logic [63:0] expected, inout bit ok);
        if (got !== expected) begin
            ok = 1'b0;
            report($sformatf("row %0d: %s = %h, expected %h", row, name, got, expected));
        end
    endtask

    // Drive: a free walker takes the next row at the falling edge.
    integer w;
    always @(negedge clk) begin
        for (w = 0; w < NW; w = w + 1) drive_valid[w] = 1'b0;
        if (!rst && format_ok) begin
            for (w = 0; w < NW; w = w + 1) begin
                if (issued[w] == finished[w] && next_row < last) begin
                    drive_row[w] = rows[next_row];
                    drive_tag[w] = next_row;
                    drive_valid[w] = 1'b1;
                    issue_cyc[w] = cyc;
                    issued[w] = issued[w] + 1;
                    next_row = next_row + 1;
                end
            end
        end
    end

    initial begin
        for (int i = 0; i < NW; i++) begin
            issued[i] = 0; finished[i] = 0; drive_valid[i] = 1'b0; drive_row[i] = '0;
            drive_tag[i] = 0;
        end
        if (!$value$plusargs("vectors=%s", dir)) dir = "vectors";
        if (!$value$plusargs("latency=%d", lat_index)) lat_index = 0;
        if (!$value$plusargs("first=%d", first)) first = 0;
        if (!$value$plusargs("count=%d", count)) count = DEPTH;
        mem_latency = lat_index == 0 ? MEM_LATENCY_0 : lat_index == 1 ? MEM_LATENCY_1 : MEM_LATENCY_2;
        if (first < 0 || first > DEPTH) first = DEPTH;
        last = (count < 0 || first + count > DEPTH) ? DEPTH : first + count;
        next_row = first;
        require_width("t", 62, T_WIDTH);
        require_width("outcome", 2, OUTCOME_WIDTH);
        require_width("voxel_x", 20, VOXEL_X_WIDTH);
        require_width("level", 5, LEVEL_WIDTH);
        require_width("inv_x", INV_X_WIDTH, INV_Y_WIDTH);
        require_width("visit x", 20, walker_visits_vectors_pkg::X_WIDTH);
        $readmemh($sformatf("%0s/walker.hex", dir), rows);
        if (VDEPTH > 0) $readmemh($sformatf("%0s/walker_visits.hex", dir), visits);
        $readmemh($sformatf("%0s/walker_nodes.hex", dir), nodes);
        if (ATTR_RECORDS > 0) $readmemh($sformatf("%0s/walker_attrs.hex", dir), attrs);
        if (!format_ok) begin
            $display("%0d passed, %0d failed", 0, last - first);
            $finish;
        end
        repeat (3) @(negedge clk);
        rst = 1'b0;
        fork
            wait (n_done == last - first);
            begin : watchdog  // a walk that never ends fails the run instead of hanging it
                int seen;
                longint since;
                seen = -1;
                since = 0;
                while (since < 2000000) begin
                    @(negedge clk);
                    if (n_done != seen) begin seen = n_done; since = 0; end
                    else since = since + 1;
                end
            end
        join_any
        if (n_done < last - first) begin
            $display("FAIL %s: %0d rows never came out", UNIT, last - first - n_done);
            n_failed = n_failed + (last - first - n_done);
        end
        repeat (2) @(negedge clk);
        $display("%s: rows %0d..%0d of %0d from %s, %0d walkers, memory latency %0d (MEM_LATENCY_%0d): %0d of %0d took the model's cycles (%0d walk cycles in all, %0d clock cycles)",
                 UNIT, first, last - 1, DEPTH, dir, NW, mem_latency, lat_index, n_timed, n_done,
                 total_cycles, cyc);
        $display("%0d passed, %0d failed", n_passed, n_failed);
        $finish;
    end
endmodule
