// svo_hit_pack: packs one pixel's record into its hit-buffer word, saturating every field
// (rtl_model/src/units/hit_record.rs `pack`, docs/units/hit-record.md).
//
// Pipeline position: the record stage, after early termination picked the ray's best hit;
// the word goes to the hit-buffer write port and the frame buffer. Word layout from bit 0
// (default widths): kind 2 | instance INST_W (8) | t T_W (22, uQ8.14) | normal u N_W (8) |
// normal v N_W (8) | colour b, g, r 8 each (RGB888): WB = 72 bits.
// Inputs are wider than the fields, as the model's: kind 0..3 (3, reserved, packs as 2);
// instance 16 bits with a valid bit (not valid, or at or above the none code 2^INST_W - 1,
// packs as none; the latter is flagged); t a signed 64-bit code of the t format (unsigned
// format: clamped into 0..2^T_W - 1); normals signed 32-bit codes clamped into N_W signed
// bits. out_ov: some field saturated. The colour is RGB888 only (the default).
//
// Latency 1 (units.hit_pack, rtl_model cycle::hw_config): compares, muxes and concatenation
// before one output register. II = 1.
`timescale 1ns/1ps
`default_nettype none
module svo_hit_pack #(
    parameter INST_W = 8,
    parameter T_W    = 22,
    parameter N_W    = 8,
    parameter WB     = 2 + INST_W + T_W + 2 * N_W + 24
) (
    input  wire          clk,
    input  wire          rst,
    input  wire          in_valid,
    input  wire [1:0]    in_kind,
    input  wire          in_instance_valid,
    input  wire [15:0]   in_instance,
    input  wire [63:0]   in_t,
    input  wire [31:0]   in_normal_u,
    input  wire [31:0]   in_normal_v,
    input  wire [7:0]    in_colour_r,
    input  wire [7:0]    in_colour_g,
    input  wire [7:0]    in_colour_b,
    output reg           out_valid,
    output reg  [WB-1:0] out_word,
    output reg           out_ov
);
    localparam [15:0] NONE = (16'd1 << INST_W) - 16'd1;
    // The one output register of the always block below; the testbench prints it (tb_*.sv: "rtl LATENCY"), tests/testbench_icarus.rs
    // compares it with the model's units.* latency and with the latency measured.
    /* verilator lint_off UNUSEDPARAM */
    localparam LATENCY = 1;
    /* verilator lint_on UNUSEDPARAM */

    // Kind: the reserved code 3 reads as several spheres (2).
    wire [1:0] kind = (in_kind == 2'd3) ? 2'd2 : in_kind;

    // Instance: ids at or above the none code become none, flagged.
    wire inst_big = in_instance_valid && (in_instance >= NONE);
    wire [INST_W-1:0] inst = (!in_instance_valid || inst_big) ? {INST_W{1'b1}} : in_instance[INST_W-1:0];

    // t: clamp a signed 64-bit code into the unsigned T_W-bit format.
    wire t_neg = in_t[63];
    wire t_big = !t_neg && (in_t[62:0] > {{(63 - T_W){1'b0}}, {T_W{1'b1}}});
    wire [T_W-1:0] t = t_neg ? {T_W{1'b0}} : t_big ? {T_W{1'b1}} : in_t[T_W-1:0];

    // Normals: clamp a signed 32-bit code into N_W signed bits.
    function [N_W:0] clamp_normal(input [31:0] c);   // {saturated, code}
        reg signed [31:0] v;
        begin
            v = $signed(c);
            if (v > $signed((32'sd1 <<< (N_W - 1)) - 32'sd1))
                clamp_normal = {1'b1, 1'b0, {(N_W - 1){1'b1}}};
            else if (v < -$signed(32'sd1 <<< (N_W - 1)))
                clamp_normal = {1'b1, 1'b1, {(N_W - 1){1'b0}}};
            else
                clamp_normal = {1'b0, c[N_W-1:0]};
        end
    endfunction
    wire [N_W:0] nu = clamp_normal(in_normal_u);
    wire [N_W:0] nv = clamp_normal(in_normal_v);

    always @(posedge clk) begin
        out_valid <= rst ? 1'b0 : in_valid;
        out_word  <= {in_colour_r, in_colour_g, in_colour_b, nv[N_W-1:0], nu[N_W-1:0], t,
                      inst, kind};
        out_ov    <= inst_big | t_neg | t_big | nu[N_W] | nv[N_W];
    end
endmodule
`default_nettype wire
