// svo_transform: a world ray into an instance's local frame, o' = R^T (o - c), d' = R^T d
// (rtl_model/src/units/transform.rs, paper Eq. 3).
//
// Pipeline position: after the sorter, once per (ray, candidate); feeds the reciprocal units
// and the walker. Default formats: positions sQ8.32 (40 bits), directions and matrix entries
// sQ2.30 (32 bits), outputs in the input formats, rounded to nearest, ties to even, saturated.
//
// Stages (rtl_model units::transform::latency_cycles, 9 cycles, II = 1; every stage within the
// clock rule at 300 MHz, docs/cycle-model.md §1.5):
//   1      rel = o - c, exact (41 bits)
//   2..5   the 18 products R_jk * rel_j and R_jk * d_j, exact (one DSP product: 4 cycles)
//   6      p0 + p1
//   7      (p0 + p1) + p2: the summation order of the model and the f64 reference
//   8      round half to even by 30 bits: the increment decided, and saturation decided from
//          the floor and the increment (floor + up > MAX when floor > MAX or floor = MAX and
//          up; < MIN when floor < MIN unless floor = MIN - 1 and up); sign of the exact
//          direction sum (a sum that rounds to code 0 keeps its sign: -0 reaches the
//          reciprocal unit)
//   9      the increment added; saturate, flag. (Rounding, comparing the rounded value and
//          saturating in one stage were 5 LUT + 8 CARRY8 + 1 MUXF levels, 3.55 ns.)
`timescale 1ns/1ps
`default_nettype none
module svo_transform (
    input  wire              clk,
    input  wire              rst,
    input  wire              in_valid,
    input  wire [3*40-1:0]   in_o,       // {z, y, x}, sQ8.32
    input  wire [3*32-1:0]   in_d,       // {z, y, x}, sQ2.30
    input  wire [9*32-1:0]   in_axes,    // axis k component j at [(3k + j)*32 +: 32], sQ2.30
    input  wire [3*40-1:0]   in_c,       // {z, y, x}, sQ8.32
    output wire              out_valid,
    output reg  [3*40-1:0]   out_o,      // local origin, sQ8.32
    output reg  [3*32-1:0]   out_d,      // local direction, sQ2.30
    output reg  [2:0]        out_sign,   // exact direction sums negative
    output reg               out_ov_origin,
    output reg               out_ov_dir
);
    localparam LATENCY = 9;
    localparam PROD = 4;                 // cycles of one DSP product

    svo_delay #(.W(1), .D(LATENCY), .RESET(1)) valid_line (
        .clk(clk), .rst(rst), .d(in_valid), .q(out_valid));

    // Stage 1: rel = o - c (exact in 41 bits).
    reg signed [40:0] rel [0:2];
    reg signed [31:0] d1 [0:2];
    reg signed [31:0] m1 [0:8];
    integer j;
    always @(posedge clk) begin
        for (j = 0; j < 3; j = j + 1) begin
            rel[j] <= $signed({in_o[j*40 + 39], in_o[j*40 +: 40]}) - $signed({in_c[j*40 + 39], in_c[j*40 +: 40]});
            d1[j]  <= $signed(in_d[j*32 +: 32]);
        end
        for (j = 0; j < 9; j = j + 1) m1[j] <= $signed(in_axes[j*32 +: 32]);
    end

    // Stages 2..5: products, registered, then three more registers (the DSP pipeline).
    genvar k, q;
    generate
        for (k = 0; k < 3; k = k + 1) begin : col
            wire signed [72:0] po [0:2];
            wire signed [63:0] pd [0:2];
            for (q = 0; q < 3; q = q + 1) begin : prod
                wire signed [72:0] po_now = m1[3*k + q] * rel[q];
                wire signed [63:0] pd_now = m1[3*k + q] * d1[q];
                svo_delay #(.W(73), .D(PROD)) po_line (.clk(clk), .rst(1'b0), .d(po_now), .q(po[q]));
                svo_delay #(.W(64), .D(PROD)) pd_line (.clk(clk), .rst(1'b0), .d(pd_now), .q(pd[q]));
            end
            // Stage 6: p0 + p1; stage 7: + p2.
            reg signed [74:0] so01, so;
            reg signed [65:0] sd01, sd;
            reg signed [72:0] po2;
            reg signed [63:0] pd2;
            always @(posedge clk) begin
                // Sign-extended to the sum's width first: the sums are exact.
                so01 <= {{2{po[0][72]}}, po[0]} + {{2{po[1][72]}}, po[1]};
                sd01 <= {{2{pd[0][63]}}, pd[0]} + {{2{pd[1][63]}}, pd[1]};
                po2  <= po[2];
                pd2  <= pd[2];
                so   <= so01 + {{2{po2[72]}}, po2};
                sd   <= sd01 + {{2{pd2[63]}}, pd2};
            end
            // Stage 8: round half to even by 30 bits: the increment and the saturation
            // decided on the floor (the increment is 0 or 1, so only the codes next to the
            // limits need it).
            localparam signed [74:0] O_MAX = 75'sd549755813887;     //  2^39 - 1
            localparam signed [74:0] O_MIN = -75'sd549755813888;    // -2^39
            localparam signed [65:0] D_MAX = 66'sd2147483647;       //  2^31 - 1
            localparam signed [65:0] D_MIN = -66'sd2147483648;      // -2^31
            wire signed [74:0] o_fl  = so >>> 30;
            wire        [29:0] o_rem = so[29:0];
            wire o_up = (o_rem > 30'h2000_0000) || (o_rem == 30'h2000_0000 && o_fl[0]);
            wire signed [65:0] d_fl  = sd >>> 30;
            wire        [29:0] d_rem = sd[29:0];
            wire d_up = (d_rem > 30'h2000_0000) || (d_rem == 30'h2000_0000 && d_fl[0]);
            reg  [39:0] o_fl8;
            reg  [31:0] d_fl8;
            reg         o_up8, o_hi8, o_lo8, d_up8, d_hi8, d_lo8, neg;
            always @(posedge clk) begin
                o_fl8 <= o_fl[39:0];
                o_up8 <= o_up;
                o_hi8 <= (o_fl > O_MAX) || (o_fl == O_MAX && o_up);
                o_lo8 <= (o_fl < O_MIN) && !(o_fl == O_MIN - 75'sd1 && o_up);
                d_fl8 <= d_fl[31:0];
                d_up8 <= d_up;
                d_hi8 <= (d_fl > D_MAX) || (d_fl == D_MAX && d_up);
                d_lo8 <= (d_fl < D_MIN) && !(d_fl == D_MIN - 66'sd1 && d_up);
                neg   <= sd < 0;
            end
            // Stage 9 (the output register below): the increment added, saturated.
            wire [39:0] o_q   = o_fl8 + {39'd0, o_up8};
            wire [31:0] d_q   = d_fl8 + {31'd0, d_up8};
            wire [39:0] o_out = o_hi8 ? 40'h7f_ffff_ffff : o_lo8 ? 40'h80_0000_0000 : o_q;
            wire [31:0] d_out = d_hi8 ? 32'h7fff_ffff : d_lo8 ? 32'h8000_0000 : d_q;
            wire ov_o = o_hi8 | o_lo8;
            wire ov_d = d_hi8 | d_lo8;
        end
    endgenerate

    always @(posedge clk) begin
        out_o         <= {col[2].o_out, col[1].o_out, col[0].o_out};
        out_d         <= {col[2].d_out, col[1].d_out, col[0].d_out};
        out_sign      <= {col[2].neg, col[1].neg, col[0].neg};
        out_ov_origin <= col[0].ov_o | col[1].ov_o | col[2].ov_o;
        out_ov_dir    <= col[0].ov_d | col[1].ov_d | col[2].ov_d;
    end
endmodule
`default_nettype wire
