// svo_raygen: ray generation's quantisation: a pixel's f64 unit direction into its
// direction-table entry and the f64 camera position into its register (rtl_model/src/units/
// raygen.rs `direction_entry`, fixed::from_f64; docs/number-formats.md §3.1).
//
// Pipeline position: the first stage. In the model's design the host writes these codes
// (the direction table, rewritten when the camera moves; the camera register per frame) and
// the pipeline reads the table; this unit is that quantisation in hardware, for a design that
// fills the table on chip or checks the host's entries, pipelined to the raygen stage's
// latency so it can stand in for the table read. The pixel travels beside the values.
// Formats (parameters, default from the vectors' package): directions sQ2.30 (DW = 32,
// DF = 30), positions sQ8.32 (PW = 40, PF = 32), each rounded half to even and saturated;
// out_ov_dir / out_ov_origin: a component saturated or was NaN.
//
// Latency 4 (units.raygen: the direction table's URAM read), II = 1: svo_f64_to_fixed's four
// stages; the flags are ORs of its registered flags.
// DIR_FIXED = 1: the table holds the codes already (the model's design: the host writes sQ2.30
// entries), in_dir's low 3·DW bits are {z, y, x} codes and only ride the same 4 registers (the
// table read's pipeline); out_ov_dir is then 0. svo_top builds it so, reading the table from
// external memory.
`timescale 1ns/1ps
`default_nettype none
module svo_raygen #(
    parameter DW = 32,
    parameter DF = 30,
    parameter PW = 40,
    parameter PF = 32,
    parameter DIR_FIXED = 0
) (
    input  wire            clk,
    input  wire            rst,
    input  wire            in_valid,
    input  wire [31:0]     in_pixel,     // {y, x}
    input  wire [3*64-1:0] in_dir,       // {z, y, x}, IEEE 754 binary64
    input  wire [3*64-1:0] in_origin,    // {z, y, x}, IEEE 754 binary64, metres
    output wire            out_valid,
    output wire [31:0]     out_pixel,
    output wire [3*DW-1:0] out_dir,      // {z, y, x}, sQ2.30
    output wire [3*PW-1:0] out_origin,   // {z, y, x}, sQ8.32
    output wire            out_ov_dir,
    output wire            out_ov_origin
);
    localparam LATENCY = 4;

    svo_delay #(.W(1), .D(LATENCY), .RESET(1)) valid_line (
        .clk(clk), .rst(rst), .d(in_valid), .q(out_valid));
    svo_delay #(.W(32), .D(LATENCY)) pixel_line (
        .clk(clk), .rst(1'b0), .d(in_pixel), .q(out_pixel));

    wire [2:0] ov_d, ov_o;
    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : axis
            if (DIR_FIXED != 0) begin : dir_code
                svo_delay #(.W(DW), .D(LATENCY)) dir_line (
                    .clk(clk), .rst(1'b0), .d(in_dir[k*DW +: DW]), .q(out_dir[k*DW +: DW]));
                assign ov_d[k] = 1'b0;
            end else begin : dir_f64
                svo_f64_to_fixed #(.W(DW), .F(DF)) dir_q (
                    .clk(clk), .in_x(in_dir[k*64 +: 64]),
                    .out_code(out_dir[k*DW +: DW]), .out_ov(ov_d[k]));
            end
            svo_f64_to_fixed #(.W(PW), .F(PF)) pos_q (
                .clk(clk), .in_x(in_origin[k*64 +: 64]),
                .out_code(out_origin[k*PW +: PW]), .out_ov(ov_o[k]));
        end
        if (DIR_FIXED != 0) begin : dir_code_unused
            // The codes are the low 3·DW bits.
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused_hi = &{1'b0, in_dir[3*64-1:3*DW]};
            /* verilator lint_on UNUSEDSIGNAL */
        end
    endgenerate
    assign out_ov_dir    = |ov_d;
    assign out_ov_origin = |ov_o;
endmodule
`default_nettype wire
