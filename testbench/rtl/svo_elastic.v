// svo_elastic: the back-pressure around a fixed-latency unit, as the cycle model's unit pipe
// (rtl_model/src/cycle/unit_pipe.rs): a unit of latency L that never stalls inside, and a
// result queue of L entries behind it, so that the unit takes a transaction whenever fewer
// than L are in flight or waiting.
//
// Pipeline position: around svo_raygen, svo_sphere, svo_sorter (for rays of at most N keys),
// svo_transform, svo_reciprocal and svo_walker_root. The unit is outside this module: the
// caller drives the unit's input with `in_valid && in_ready` and brings its registered output
// back on `unit_valid`/`unit_data`, L cycles later. A result leaves on `out_*` in the cycle the
// unit presents it if the queue is empty and `out_ready` is high (no register on the way),
// else it waits in order. `in_ready` counts the result leaving in this cycle: it depends
// combinationally on `out_ready`, as the model's pipe frees its place before it accepts (the
// consumer is evaluated first), and `out_ready` is a FIFO's registered not-full, so the path
// stays one stage long.
`timescale 1ns/1ps
`default_nettype none
module svo_elastic #(
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
    output wire [W-1:0] out_data
);
    localparam CW = $clog2(L + 1);
    localparam QW = L > 1 ? $clog2(L) : 1;
    localparam integer LAST_I = L - 1;
    localparam integer L_I = L;
    localparam [QW-1:0] LAST = LAST_I[QW-1:0];
    localparam [CW-1:0] CAP = L_I[CW-1:0];

    generate
        if (L < 1) begin : bad_latency
            svo_elastic_L_must_be_at_least_1 bad();
        end
    endgenerate

    reg [W-1:0]  q [0:L-1];
    reg [QW-1:0] rd, wr;
    reg [CW-1:0] qn;                              // results waiting
    reg [CW-1:0] n;                               // in flight + waiting
    wire q_any = qn != {CW{1'b0}};
    assign out_valid = q_any || unit_valid;
    assign out_data = q_any ? q[rd] : unit_data;
    wire leave = out_valid && out_ready;
    assign in_ready = n < CAP || (leave && n == CAP);
    wire accept = in_valid && in_ready;
    wire q_push = unit_valid && (q_any || !leave);
    wire q_pop = q_any && leave;
    always @(posedge clk) begin
        if (q_push) q[wr] <= unit_data;
        if (rst) begin
            rd <= {QW{1'b0}};
            wr <= {QW{1'b0}};
            qn <= {CW{1'b0}};
            n <= {CW{1'b0}};
        end else begin
            if (q_push) wr <= (wr == LAST) ? {QW{1'b0}} : wr + 1'b1;
            if (q_pop) rd <= (rd == LAST) ? {QW{1'b0}} : rd + 1'b1;
            if (q_push && !q_pop) qn <= qn + 1'b1;
            else if (q_pop && !q_push) qn <= qn - 1'b1;
            if (accept && !leave) n <= n + 1'b1;
            else if (leave && !accept) n <= n - 1'b1;
        end
    end
endmodule
`default_nettype wire
