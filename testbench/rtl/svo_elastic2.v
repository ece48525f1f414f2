// svo_elastic2: svo_elastic with a second out port — up to two waiting results leave in a
// cycle, as the cycle model's unit lane hands on into a FIFO of two push ports.
//
// Pipeline position: around the record stage's packing unit (svo_normal + svo_hit_pack in
// svo_walk_wide), in front of the hit buffer's record FIFO (record_to_write). At k = 1 that FIFO
// has max(k, hit_buffer.record_writes) = 2 push ports in the model
// (src/models/cycle/fifos.rs), and the record stage's `hand_on_lanes` (stages/mod.rs) moves
// ready results while the FIFO takes a push: after the FIFO was full and the write stage
// took two records in one cycle, two records that waited here enter it in one cycle.
// Everything else is svo_elastic's rule (rtl_model/src/cycle/unit_pipe.rs): a unit of latency
// L that never stalls inside, a result queue of L entries behind it, the unit takes a
// transaction whenever fewer than L are in flight or waiting, counting those that leave in
// this cycle.
// The ready results, oldest first, are the queue's entries, then the unit's result of this
// cycle. `out_*` shows the first, `out2_*` the second; the second leaves only with the first
// (`out2_ready` is taken as "the FIFO has room for a second push in this cycle"), so the
// two ports take a prefix of the ready results, as the model's FIFO takes its pushes.
`timescale 1ns/1ps
`default_nettype none
module svo_elastic2 #(
    parameter L = 4,                              // the unit's latency = this pipe's capacity
    parameter W = 32
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         in_valid,
    output wire         in_ready,
    input  wire         unit_valid,
    input  wire [W-1:0] unit_data,
    output wire         out_valid,
    input  wire         out_ready,
    output wire [W-1:0] out_data,
    output wire         out2_valid,               // a second ready result behind out_*
    input  wire         out2_ready,               // a second push this cycle (with out_*'s)
    output wire [W-1:0] out2_data
);
    localparam CW = $clog2(L + 2);                // 0..L, and at least two bits for two leaves
    localparam QW = L > 1 ? $clog2(L) : 1;
    localparam integer LAST_I = L - 1;
    localparam integer L_I = L;
    localparam [QW-1:0] LAST = LAST_I[QW-1:0];
    localparam [CW-1:0] CAP = L_I[CW-1:0];
    localparam [CW-1:0] ONE = 1;
    localparam [CW-1:0] TWO = 2;

    generate
        if (L < 1) begin : bad_latency
            svo_elastic2_L_must_be_at_least_1 bad();
        end
    endgenerate

    reg [W-1:0]  q [0:L-1];
    reg [QW-1:0] rd, wr;
    reg [CW-1:0] qn;                              // results waiting
    reg [CW-1:0] n;                               // in flight + waiting
    wire [QW-1:0] rd1 = (rd == LAST) ? {QW{1'b0}} : rd + 1'b1;
    wire q_any = qn != {CW{1'b0}};
    wire q_one = qn == ONE;
    wire q_two = qn >= TWO;
    assign out_valid = q_any || unit_valid;
    assign out_data = q_any ? q[rd] : unit_data;
    assign out2_valid = q_two || (q_one && unit_valid);
    assign out2_data = q_two ? q[rd1] : unit_data;
    wire leave = out_valid && out_ready;
    wire leave2 = leave && out2_valid && out2_ready;
    // The unit's result of this cycle leaves on out (queue empty) or on out2 (one waiting).
    wire u_leave = unit_valid && ((!q_any && leave) || (q_one && leave2));
    // Waiting results that leave: the ones among the first two that are not the unit's.
    wire [CW-1:0] q_pops = {{(CW-1){1'b0}}, leave && q_any} + {{(CW-1){1'b0}}, leave2 && q_two};
    wire [CW-1:0] leaves = {{(CW-1){1'b0}}, leave} + {{(CW-1){1'b0}}, leave2};
    // n <= L, so "fewer than L after this cycle's leaves" is n < L or one leaving.
    assign in_ready = n < CAP || leave;
    wire accept = in_valid && in_ready;
    wire q_push = unit_valid && !u_leave;
    wire [QW-1:0] rd_next = q_pops == TWO ? ((rd1 == LAST) ? {QW{1'b0}} : rd1 + 1'b1)
                          : q_pops == ONE ? rd1 : rd;
    always @(posedge clk) begin
        if (q_push) q[wr] <= unit_data;
        if (rst) begin
            rd <= {QW{1'b0}};
            wr <= {QW{1'b0}};
            qn <= {CW{1'b0}};
            n <= {CW{1'b0}};
        end else begin
            if (q_push) wr <= (wr == LAST) ? {QW{1'b0}} : wr + 1'b1;
            rd <= rd_next;
            qn <= qn + {{(CW-1){1'b0}}, q_push} - q_pops;
            n <= n + {{(CW-1){1'b0}}, accept} - leaves;
        end
    end
endmodule
`default_nettype wire
