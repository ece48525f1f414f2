// tb_sorter: svo_sorter against sorter.hex (`sim vectors`), one ray per row: every output key
// and the count, the cycles from accept to result against the row's `cycles` (the cycle
// model's), and in_ready: low for exactly the row's `busy` - 1 cycles after each accept, as
// the cycle model holds its input; see tb_common.svh.
`timescale 1ns/1ps
module tb_sorter;
    import sorter_vectors_pkg::*;
    localparam UNIT = "sorter";
    wire dut_ready;                      // before the include: the driver reads it
    `define TB_READY dut_ready
    `define TB_LATENCY(r) r[CYCLES_LSB +: CYCLES_WIDTH]
    `include "tb_common.svh"

    localparam KW = IN_T0_WIDTH, IW = IN_ID0_WIDTH, KB = KW + IW;
    localparam MK = (OUT_T0_LSB - IN_T0_LSB) / KB;   // keys per row
    wire              got_valid;
    wire [COUNT_WIDTH-1:0] got_count;
    wire [MK*KB-1:0]  got_keys;
    // The network is the model's, from the package (NET_*): N lanes, D layers, the pairs.
    svo_sorter #(.KW(KW), .IW(IW), .N(NET_LANES), .D(NET_DEPTH), .S(NET_SLOTS),
                 .PAIRS(NET_PAIRS), .MAX_KEYS(MK), .CW(COUNT_WIDTH)) dut (
        .clk(clk), .rst(rst), .in_valid(drive_valid), .in_ready(dut_ready),
        .in_count(drive_row[COUNT_LSB +: COUNT_WIDTH]), .in_keys(drive_row[IN_T0_LSB +: MK*KB]),
        .out_valid(got_valid), .out_count(got_count), .out_keys(got_keys));

    initial begin
        // Keys are contiguous (t, id) pairs, inputs then outputs, then the timing fields.
        require_width("in_id0 after in_t0", IN_T0_LSB + KW, IN_ID0_LSB);
        require_width("in_t1 after in_id0", IN_T0_LSB + KB, IN_T1_LSB);
        require_width("out_id0 after out_t0", OUT_T0_LSB + KW, OUT_ID0_LSB);
        require_width("cycles after the keys", OUT_T0_LSB + MK * KB, CYCLES_LSB);
        require_width("keys per row (N-lane network, 4 issues)", 4 * NET_LANES, MK);
        // The RTL's default network (its standalone synthesis) is the model's BEST_8.
        if (NET_LANES == 8 && NET_DEPTH == 6 && NET_SLOTS == 4)
            require_width("svo_sorter's default PAIRS are the package's NET_PAIRS (1 = equal)",
                          1, int'(NET_PAIRS == dut.BEST_8_PAIRS));
        require_width("t", 32, KW);
    end

    // in_ready after each accept: low while fewer than `busy` cycles passed, then high.
    longint accepted_at = -1;
    longint busy = 0;
    int     accepted_row = -1;
    always @(posedge clk) if (!rst) begin
        if (accepted_at >= 0 && cycle - accepted_at <= busy &&
            dut_ready !== (cycle - accepted_at >= busy))
            mark_bad(accepted_row, $sformatf("in_ready %b %0d cycles after the accept, busy %0d",
                                             dut_ready, cycle - accepted_at, busy));
        if (drive_valid === 1'b1 && dut_ready === 1'b1) begin
            accepted_at = cycle;
            busy = longint'(drive_row[BUSY_LSB +: BUSY_WIDTH]);
            accepted_row = n_issued - 1;
        end
    end

    integer k;
    always @(negedge clk) if (!rst && got_valid === 1'b1) begin
        check_row_begin();
        check_field("count", got_count, exp_row[COUNT_LSB +: COUNT_WIDTH]);
        for (k = 0; k < MK; k = k + 1) begin
            check_field($sformatf("out_t%0d", k), got_keys[k*KB +: KW],
                        exp_row[OUT_T0_LSB + k*KB +: KW]);
            check_field($sformatf("out_id%0d", k), got_keys[k*KB + KW +: IW],
                        exp_row[OUT_T0_LSB + k*KB + KW +: IW]);
        end
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_sorter %0d", dut.LATENCY);
endmodule
