// svo_f64_to_fixed: an IEEE 754 binary64 value to a signed W-bit fixed-point code with F
// fraction bits, rounded to nearest with ties to even, saturated (rtl_model/src/fixed/ops.rs
// `from_f64` with AP_RND_CONV and AP_SAT, the modes of the default raygen formats).
//
// Pipeline position: inside svo_raygen.v, once per direction component and camera coordinate.
// NaN gives code 0 and raises ov; +-infinity and finite values beyond the format give the
// largest or most negative code and raise ov; -0 and values that round to 0 give 0; the most
// negative code itself is exact (no ov). Subnormals are exact inputs (hidden bit 0).
//
// Stages (4 cycles, II = 1; the latency of units.raygen). The value times 2^F is M * 2^sh with
// sh = exponent - 1075 + F; sh >= 0 only for a normal number (so M >= 2^52 >= 2^W), which
// saturates, and otherwise the value is M shifted right by rsh = -sh, clamped at 56 (from 56
// on, M lies wholly below the guard bit: integer 0, guard 0, sticky M != 0):
//   1  decode: sign, NaN/infinity, significand M (53 bits), rsh clamped to 0..56 (6 bits),
//      "big" when sh >= 0
//   2  align, coarse: {M, 56 zero bits} >> 8*(rsh / 8), the bits from the guard's up kept;
//      sticky = some bit of M at or below rsh - 2 (the bits a full shift leaves below the
//      guard), from M and a mask of rsh, beside the shift
//   3  align, fine: >> rsh % 8, giving the integer part and the guard; "big" once the
//      integer part cannot fit W bits; round half to even: + (guard & (sticky | lsb))
//   4  sign, saturate, flag
// The align used to be one stage (the 53-bit variable shift with the negation of sh, its
// clamp and the sticky OR in series: 25 logic levels, 6.05 ns); split for 300 MHz
// (docs/cycle-model.md §1.5), the rounding moving into the fine shift's stage.
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
    // Stage 1: decode, the shift amount. Subnormals have the exponent of the smallest
    // normal, 1.
    localparam signed [12:0] C = 1075 - F;   // rsh = C - exponent
    reg               s1_sign, s1_nan, s1_inf, s1_big;
    reg        [52:0] s1_m;
    reg         [5:0] s1_r;              // min(rsh, 56)
    wire [10:0] e = in_x[62:52];
    // rsh and its clamp are functions of the input evaluated inside the register's block,
    // not continuous assigns of in_x: in the end-to-end frame (tb_frame.sv, whose step task
    // writes the inputs at the falling edge) Verilator 5.006 registered a stale rsh from such
    // assigns (0 / 768 pixels), while Icarus and the unit testbench did not. Same logic either way.
    function automatic signed [12:0] rsh_of(input [10:0] ex);
        rsh_of = C - $signed({2'b00, (ex == 11'd0) ? 11'd1 : ex});
    endfunction
    function automatic [5:0] clamp_of(input signed [12:0] r);
        clamp_of = (r > 13'sd56) ? 6'd56 : r[5:0];
    endfunction
    always @(posedge clk) begin
        s1_sign <= in_x[63];
        s1_nan  <= (e == 11'h7ff) && (in_x[51:0] != 52'd0);
        s1_inf  <= (e == 11'h7ff) && (in_x[51:0] == 52'd0);
        s1_m    <= {e != 11'd0, in_x[51:0]};
        s1_big  <= rsh_of(e) <= 13'sd0;
        s1_r    <= clamp_of(rsh_of(e));
    end

    // Stage 2: coarse shift by 8*(rsh / 8). Of {M, 56'd0} >> rsh only bits 55 (the guard)
    // and up matter, and bits 55..108 of {M, 56'd0} are {M, 1'b0}: y = bits 55..108 of the
    // coarse shift (no bit below 55 can reach them, all being zero).
    // Bit i of M ends at 56 + i - rsh: below the guard (sticky) iff i <= rsh - 2.
    reg  [52:0] below;
    integer i;
    always @(*) begin
        for (i = 0; i < 53; i = i + 1) below[i] = (i + 2) <= s1_r;
    end
    reg               s2_sign, s2_nan, s2_inf, s2_big, s2_sticky;
    reg        [53:0] s2_y;              // ({M, 56'd0} >> 8*(rsh / 8))[108:55]
    reg         [2:0] s2_f;              // rsh % 8
    always @(posedge clk) begin
        s2_sign   <= s1_sign;
        s2_nan    <= s1_nan;
        s2_inf    <= s1_inf;
        s2_big    <= s1_big;
        s2_y      <= {s1_m, 1'b0} >> {s1_r[5:3], 3'b000};
        s2_f      <= s1_r[2:0];
        s2_sticky <= (s1_m & below) != 53'd0;
    end

    // Stage 3: fine shift, then round half to even (W + 1 bits: rounding may carry to 2^W).
    // z = ({M, 56'd0} >> rsh)[108:55]: z[0] the guard, z[W:1] the integer part.
    wire [53:0] z = s2_y >> s2_f;
    wire [W:0]  q_fl = {1'b0, z[W:1]};
    wire        up = z[0] & (s2_sticky | z[1]);
    reg         s3_sign, s3_nan, s3_inf, s3_big;
    reg [W:0]   s3_q;
    always @(posedge clk) begin
        s3_sign <= s2_sign;
        s3_nan  <= s2_nan;
        s3_inf  <= s2_inf;
        s3_big  <= s2_big || (z[53:W+1] != {(53 - W){1'b0}});
        s3_q    <= q_fl + {{W{1'b0}}, up};
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
