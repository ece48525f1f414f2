// svo_fifo_wide: a FIFO of K push and K pop ports, the joint of a K-wide walk section, as the
// cycle model's wide FIFO (rtl_model/src/cycle/fifo.rs, `Fifo::new_wide`; docs/cycle-model.md
// §2.1, "Walk issue of width k").
//
// Pipeline position: the walk section's joints at k walk-issue lanes (check_to_transform,
// loop_back, transform_to_reciprocal, reciprocal_to_root, root_to_dispatch, walker_to_record);
// svo_fifo is the same FIFO at K = 1. Per cycle the producer offers up to K items as a prefix
// (in_valid[0], in_valid[1], ...) and push port j is ready while the registered occupancy plus
// j is below DEPTH: each push sees the registered occupancy less what its own side did in the
// cycle, never the other side's pops. Pop port j is valid while j items were inside at the
// start of the cycle and shows the j-th of them; the consumer takes a prefix (out_ready[j]
// with every port before it taken). Both sides read registers only, as svo_fifo's, so neither
// handshake depends on the other's.
`timescale 1ns/1ps
`default_nettype none
module svo_fifo_wide #(
    parameter K     = 2,                          // ports a side
    parameter DEPTH = 4,                          // 1 .. 65536, the model's MAX_DEPTH
    parameter W     = 32
) (
    input  wire                         clk,
    input  wire                         rst,
    input  wire [K-1:0]                 in_valid,   // a prefix
    output wire [K-1:0]                 in_ready,
    input  wire [K*W-1:0]               in_data,
    output wire [K-1:0]                 out_valid,
    input  wire [K-1:0]                 out_ready,  // taken as a prefix of the valid ports
    output wire [K*W-1:0]               out_data,
    output reg  [$clog2(DEPTH + 1)-1:0] occupancy
);
    localparam NW = $clog2(DEPTH + 1);
    localparam AW = DEPTH > 1 ? $clog2(DEPTH) : 1;
    localparam integer DEPTH_I = DEPTH;

    generate
        if (DEPTH < 1 || DEPTH > 65536 || K < 1 || K > 8) begin : bad_depth
            svo_fifo_wide_DEPTH_1_to_65536_and_K_1_to_8 bad();
        end
    endgenerate

    // Address a + j modulo DEPTH.
    function automatic [AW-1:0] wrap(input [AW-1:0] a, input integer j);
        integer s;
        begin
            s = {{(32 - AW){1'b0}}, a} + j;
            if (s >= DEPTH_I) s = s - DEPTH_I;
            wrap = s[AW-1:0];
        end
    endfunction

    reg [W-1:0]  mem [0:DEPTH-1];
    reg [AW-1:0] rd, wr;
    reg [K-1:0]  push, pop;
    reg          push_on, pop_on;                 // every port before this one moved
    integer j;
    always @* begin
        push_on = 1'b1;
        pop_on = 1'b1;
        for (j = 0; j < K; j = j + 1) begin
            push[j] = push_on && in_valid[j] && in_ready[j];
            pop[j] = pop_on && out_valid[j] && out_ready[j];
            push_on = push[j];
            pop_on = pop[j];
        end
    end
    genvar g;
    generate
        for (g = 0; g < K; g = g + 1) begin : port
            assign in_ready[g] = {{(32 - NW){1'b0}}, occupancy} + g < DEPTH_I;
            assign out_valid[g] = {{(32 - NW){1'b0}}, occupancy} > g;
            assign out_data[g*W +: W] = mem[wrap(rd, g)];
        end
    endgenerate
    reg [NW-1:0] n_push, n_pop;
    integer c;
    always @* begin
        n_push = {NW{1'b0}};
        n_pop = {NW{1'b0}};
        for (c = 0; c < K; c = c + 1) begin
            n_push = n_push + {{(NW - 1){1'b0}}, push[c]};
            n_pop = n_pop + {{(NW - 1){1'b0}}, pop[c]};
        end
    end
    integer p;
    always @(posedge clk) begin
        for (p = 0; p < K; p = p + 1)
            if (push[p]) mem[wrap(wr, p)] <= in_data[p*W +: W];
        if (rst) begin
            rd <= {AW{1'b0}};
            wr <= {AW{1'b0}};
            occupancy <= {NW{1'b0}};
        end else begin
            wr <= wrap(wr, {{(32 - NW){1'b0}}, n_push});
            rd <= wrap(rd, {{(32 - NW){1'b0}}, n_pop});
            occupancy <= occupancy + n_push - n_pop;
        end
    end
endmodule
`default_nettype wire
