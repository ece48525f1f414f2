// tb_elastic2: svo_elastic2 around a unit of latency L (an svo_delay carrying each item's
// number), for test_elastic2.py, which drives the input and both out ports' readies at random
// and compares every item's leaving cycle and port with its own model of the rule.
//
// Pipeline position: none (a bench top); in svo_walk_wide the pipe is the record stage's packing
// lane (svo_normal + svo_hit_pack) handing on into record_to_write's two push ports.
`timescale 1ns/1ps
`default_nettype none
module tb_elastic2 #(
    parameter L = 14,
    parameter W = 16
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         in_valid,
    output wire         in_ready,
    input  wire [W-1:0] in_data,
    output wire         out_valid,
    input  wire         out_ready,
    output wire [W-1:0] out_data,
    output wire         out2_valid,
    input  wire         out2_ready,
    output wire [W-1:0] out2_data
);
    wire         unit_valid;
    wire [W-1:0] unit_data;
    svo_delay #(.W(1 + W), .D(L), .RESET(1)) unit (.clk(clk), .rst(rst),
        .d({in_valid && in_ready, in_data}), .q({unit_valid, unit_data}));
    svo_elastic2 #(.L(L), .W(W)) pipe (.clk(clk), .rst(rst), .in_valid(in_valid),
        .in_ready(in_ready), .unit_valid(unit_valid), .unit_data(unit_data),
        .out_valid(out_valid), .out_ready(out_ready), .out_data(out_data),
        .out2_valid(out2_valid), .out2_ready(out2_ready), .out2_data(out2_data));
endmodule
`default_nettype wire
