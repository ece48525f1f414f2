// svo_f64_to_fixed: an IEEE 754 binary64 value to a signed W-bit fixed-point code with F
// fraction bits, rounded to nearest with ties to even, saturated (rtl_model/src/fixed/ops.rs
// `from_f64` with AP_RND_CONV and AP_SAT, the modes of the default raygen formats).
//
// Pipeline position: inside svo_raygen.v, once per direction component and camera coordinate.
// NaN gives code 0 and raises ov; +-infinity and finite values beyond the format give the
// largest or most negative code and raise ov; -0 and values that round to 0 give 0; the most
// negative code itself is exact (no ov). Subnormals are exact inputs (hidden bit 0).
//
// Stages (4 cycles, II = 1; the latency of units.raygen):
//   1  decode: sign, NaN/infinity, significand M (53 bits), scale sh = exponent - 1075 + F,
//      so the value times 2^F is M * 2^sh
//   2  align: M << sh (sh >= 0) or M >> -sh with the guard bit and the sticky OR below it;
//      "big" once the integer part cannot fit W bits
//   3  round half to even: + (guard & (sticky | lsb))
//   4  sign, saturate, flag
`timescale 1ns/1ps
`default_nettype none
module svo_f64_to_fixed #(
    parameter W = 32,                    // 2 <= W <= 52
    parameter F = 30
) (
    input  wire         clk,
    input  wire [63:0]  in_x,
    output reg  [W-1:0] out_code,
    output reg          out_ov
);
    // Stage 1: decode.
    reg               s1_sign, s1_nan, s1_inf;
    reg        [52:0] s1_m;
    reg signed [12:0] s1_sh;
    wire [10:0] e = in_x[62:52];
    always @(posedge clk) begin
        s1_sign <= in_x[63];
        s1_nan  <= (e == 11'h7ff) && (in_x[51:0] != 52'd0);
        s1_inf  <= (e == 11'h7ff) && (in_x[51:0] == 52'd0);
        s1_m    <= {e != 11'd0, in_x[51:0]};
        // Subnormals have the exponent of the smallest normal, 1.
        s1_sh   <= $signed({2'b00, (e == 11'd0) ? 11'd1 : e}) - 13'sd1075 + F;
    end

    // Stage 2: align. Right shifts beyond 55 leave only the sticky bit.
    localparam XW = 53 + 56;             // M followed by 56 fraction bits
    wire        [12:0]   rsh = -s1_sh;
    wire                 left = !s1_sh[12];
    wire        [XW-1:0] xr  = {s1_m, 56'd0} >> ((rsh > 13'd56) ? 13'd56 : rsh);
    // Left shift: only shifts up to W can leave the value below 2^W.
    wire        [6:0]    lsh = (s1_sh > 13'sd64) ? 7'd64 : s1_sh[6:0];
    wire        [116:0]  xl  = {64'd0, s1_m} << lsh;
    reg                  s2_sign, s2_nan, s2_inf, s2_big, s2_guard, s2_sticky;
    reg         [W:0]    s2_int;
    always @(posedge clk) begin
        s2_sign <= s1_sign;
        s2_nan  <= s1_nan;
        s2_inf  <= s1_inf;
        if (left) begin
            s2_big    <= (s1_m != 53'd0) && ((s1_sh > W) || (xl[116:W] != {(117 - W){1'b0}}));
            s2_int    <= {1'b0, xl[W-1:0]};
            s2_guard  <= 1'b0;
            s2_sticky <= 1'b0;
        end else if (rsh > 13'd55) begin
            s2_big    <= 1'b0;
            s2_int    <= {(W + 1){1'b0}};
            s2_guard  <= 1'b0;
            s2_sticky <= s1_m != 53'd0;
        end else begin
            s2_big    <= xr[XW-1:56+W] != {(53 - W){1'b0}};
            s2_int    <= {1'b0, xr[56 +: W]};
            s2_guard  <= xr[55];
            s2_sticky <= xr[54:0] != 55'd0;
        end
    end

    // Stage 3: round half to even (W + 1 bits: rounding may carry to 2^W).
    reg         s3_sign, s3_nan, s3_inf, s3_big;
    reg [W:0]   s3_q;
    always @(posedge clk) begin
        s3_sign <= s2_sign;
        s3_nan  <= s2_nan;
        s3_inf  <= s2_inf;
        s3_big  <= s2_big;
        s3_q    <= s2_int + {{W{1'b0}}, s2_guard & (s2_sticky | s2_int[0])};
    end

    // Stage 4: sign and saturate: +max = 2^(W-1) - 1, -min = 2^(W-1) in magnitude.
    localparam [W:0] HALF = {2'b01, {(W - 1){1'b0}}};
    wire [W-1:0] max_code = {1'b0, {(W - 1){1'b1}}};
    wire [W-1:0] min_code = {1'b1, {(W - 1){1'b0}}};
    wire over = s3_inf || s3_big || (s3_sign ? (s3_q > HALF) : (s3_q >= HALF));
    wire [W-1:0] neg_q = -s3_q[W-1:0];
    always @(posedge clk) begin
        if (s3_nan) begin
            out_code <= {W{1'b0}};
            out_ov   <= 1'b1;
        end else if (over) begin
            out_code <= s3_sign ? min_code : max_code;
            out_ov   <= 1'b1;
        end else begin
            out_code <= s3_sign ? neg_q : s3_q[W-1:0];
            out_ov   <= 1'b0;
        end
    end
endmodule
`default_nettype wire
