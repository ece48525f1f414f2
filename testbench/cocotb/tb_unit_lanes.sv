// tb_unit_lanes: the k-wide walk-issue glue on its own — an svo_fifo_wide in front of
// svo_unit_lanes with K svo_delay "units" of latency L (each carries the item's number), then
// an svo_fifo_wide behind it — for test_unit_lanes.py, which drives the front FIFO's K push
// ports and the back FIFO's K pop ports and compares every item's cycles with its own model
// of the cycle model's rule (docs/cycle-model.md §2.1, "Walk issue of width k").
//
// Pipeline position: none (a bench top); the chain is transform_to_reciprocal → k units →
// reciprocal_to_root as a k-wide walk section would build it.
`timescale 1ns/1ps
`default_nettype none
module tb_unit_lanes #(
    parameter K = 2,
    parameter L = 9,
    parameter D_IN = 4,
    parameter D_OUT = 4,
    parameter W = 16
) (
    input  wire           clk,
    input  wire           rst,
    input  wire [K-1:0]   push_valid,
    output wire [K-1:0]   push_ready,
    input  wire [K*W-1:0] push_data,
    output wire [K-1:0]   pop_valid,
    input  wire [K-1:0]   pop_ready,
    output wire [K*W-1:0] pop_data
);
    localparam SW = K > 1 ? $clog2(K) : 1;
    wire [K-1:0] a_valid, a_ready, take, u_valid, b_valid, b_ready;
    wire [K*W-1:0] a_data, u_data, b_data;
    wire [K*SW-1:0] src;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo_wide #(.K(K), .DEPTH(D_IN), .W(W)) front (.clk(clk), .rst(rst),
        .in_valid(push_valid), .in_ready(push_ready), .in_data(push_data),
        .out_valid(a_valid), .out_ready(a_ready), .out_data(a_data), .occupancy());
    svo_unit_lanes #(.K(K), .L(L), .W(W)) lanes (.clk(clk), .rst(rst),
        .in_valid(a_valid), .in_ready(a_ready), .lane_take(take), .lane_src(src),
        .unit_valid(u_valid), .unit_data(u_data),
        .out_valid(b_valid), .out_ready(b_ready), .out_data(b_data));
    genvar g;
    generate
        for (g = 0; g < K; g = g + 1) begin : unit
            svo_delay #(.W(1 + W), .D(L), .RESET(1)) u (.clk(clk), .rst(rst),
                .d({take[g], a_data[src[g*SW +: SW]*W +: W]}),
                .q({u_valid[g], u_data[g*W +: W]}));
        end
    endgenerate
    svo_fifo_wide #(.K(K), .DEPTH(D_OUT), .W(W)) back (.clk(clk), .rst(rst),
        .in_valid(b_valid), .in_ready(b_ready), .in_data(b_data),
        .out_valid(pop_valid), .out_ready(pop_ready), .out_data(pop_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
endmodule
`default_nettype wire
