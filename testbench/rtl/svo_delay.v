// svo_delay: a D-cycle register delay line of W bits (D >= 1).
//
// Pipeline position: the side-band of every unit here. Values that a stage does not change
// travel beside the arithmetic in one of these, so each unit's latency is simply the length of
// its longest register chain. RESET = 1 clears the line on rst (for valid bits); data lines
// are left without reset, as synthesis prefers.
`timescale 1ns/1ps
`default_nettype none
module svo_delay #(
    parameter W = 1,
    parameter D = 1,
    parameter RESET = 0
) (
    input  wire         clk,
    input  wire         rst,
    input  wire [W-1:0] d,
    output reg  [W-1:0] q
);
    reg [W-1:0] r [0:D-1];
    integer i;
    always @(posedge clk) begin
        if (RESET != 0 && rst) begin
            for (i = 0; i < D; i = i + 1) r[i] <= {W{1'b0}};
        end else begin
            r[0] <= d;
            for (i = 1; i < D; i = i + 1) r[i] <= r[i-1];
        end
    end
    // A combinational read rather than `assign q = r[D-1]`: in the end-to-end top
    // (tb_frame.sv), Icarus 12 never re-evaluated that continuous assignment of an array word
    // for some instances (q stayed x while r[D-1] was 0); the always block reads the same word.
    always @* q = r[D-1];
endmodule
`default_nettype wire
