// svo_reciprocal: 1/d of one direction component by normalisation, a seed ROM and two
// Newton-Raphson iterations (rtl_model/src/units/reciprocal.rs, docs/units/reciprocal.md).
//
// Pipeline position: between the transform and the walker, three per (ray, candidate).
// Default formats: d sQ2.30 (32 bits) with the transform's sign bit (so -0 is negative),
// 1/d sQ22.30 (52 bits) rounded to nearest, ties to even, saturated; mantissa uQ1.32
// (G = 32, 33 bits: the 32-bit input normalised, one zero bit below), seed ROM of 2^8
// entries in uQ0.10 (loaded from reciprocal_seed.hex, which `sim vectors` generates from the
// model), 2 iterations.
//
// Stages (rtl_model units::reciprocal::latency_cycles, 26 cycles, II = 1; every stage within
// the clock rule at 300 MHz, docs/cycle-model.md §1.5):
//   1        sign (the code's, or sign_negative for code 0), a = |d|, zero = a <= 2^9
//   2        leading-zero count lz of a
//   3        normalise: m = {32 normalised bits, 0} (uQ1.32), idx = the 8 bits after the
//            leading one
//   4        y0 = ROM[idx] (uQ0.10; its value in uQ1.32 is y0 * 2^22)
//   5..13    iteration 1: P = m*y (4), q = 2 - floor(P) (1), Y = y*q (4), y = floor(Y); the
//            seed enters its two products as the 10-bit code (33 x 10 and 10 x 33 bits), the
//            shift by 22 folded into the truncations, so they are narrow multipliers
//   14..22   iteration 2, the same on 33-bit y (33 x 33 bits)
//   23       sign: code = +-y
//   24       denormalise: code * 2^(lead - 30) to 30 fraction bits, a left shift, or a right
//            shift of up to 3 bits with its round-half-to-even increment decided
//   25       the increment added
//   26       saturate to 52 bits (flagged); zero components give +-max
`timescale 1ns/1ps
`default_nettype none
module svo_reciprocal #(
    parameter SEED_FILE = ""    // optional: a testbench may load the ROM itself
) (
    input  wire         clk,
    input  wire         rst,
    input  wire         in_valid,
    input  wire [31:0]  in_d,            // sQ2.30
    input  wire         in_sign_negative,
    output wire         out_valid,
    output reg  [51:0]  out_inv,         // sQ22.30
    output reg          out_zero,
    output reg          out_negative,
    output reg          out_flushed,
    output reg          out_ov
);
    localparam G = 32;                   // mantissa fraction bits (output fraction bits + 2)
    localparam SEED = 10;                // seed code bits, uQ0.10
    localparam PROD = 4;                 // cycles of one multi-slice DSP product
    localparam LATENCY = 26;

    reg [9:0] rom [0:255];               // seed entries, uQ0.10
    initial if (SEED_FILE != "") $readmemh(SEED_FILE, rom);

    svo_delay #(.W(1), .D(LATENCY), .RESET(1)) valid_line (
        .clk(clk), .rst(rst), .d(in_valid), .q(out_valid));

    // ---- Stage 1: sign, magnitude, zero test. --------------------------------------------
    wire        d_neg = in_d[31];
    wire [31:0] a_now = d_neg ? (~in_d + 32'd1) : in_d;      // |-2^31| = 2^31 fits
    reg  [31:0] a1;
    reg         neg1, zero1;
    always @(posedge clk) begin
        a1    <= a_now;
        neg1  <= (in_d == 32'd0) ? in_sign_negative : d_neg;
        zero1 <= a_now <= 32'd512;                            // |d| <= 2^-21
    end

    // ---- Stage 2: leading-zero count. ----------------------------------------------------
    // Its own stage: the count and the 32-bit shift by it are too deep for one cycle.
    function [5:0] lzc32(input [31:0] v);
        integer i;
        begin
            lzc32 = 6'd32;
            for (i = 0; i < 32; i = i + 1)
                if (v[i]) lzc32 = 6'd31 - i[5:0];
        end
    endfunction
    reg  [5:0]  lz2;
    reg  [31:0] a2;
    reg         neg2, zero2, flushed2;
    always @(posedge clk) begin
        lz2      <= lzc32(a1);
        a2       <= a1;
        neg2     <= neg1;
        zero2    <= zero1;
        flushed2 <= zero1 && (a1 != 32'd0);
    end

    // ---- Stage 3: normalise. ---------------------------------------------------------------
    wire [31:0] norm    = a2 << lz2;
    reg  [G:0]  m3;
    reg  [7:0]  idx3;
    reg  [4:0]  lead3;
    reg         neg3, zero3, flushed3;
    always @(posedge clk) begin
        m3       <= {norm, 1'b0};
        idx3     <= norm[30:23];
        lead3    <= 5'd31 - lz2[4:0];
        neg3     <= neg2;
        zero3    <= zero2;
        flushed3 <= flushed2;
    end

    // ---- Stage 4: seed ROM (registered read). --------------------------------------------
    reg [SEED-1:0] y4;
    reg [G:0]      m4;
    always @(posedge clk) begin
        y4 <= rom[idx3];                                      // uQ0.10 (= y0 * 2^22 in uQ1.32)
        m4 <= m3;
    end

    // ---- Stages 5..22: two Newton-Raphson iterations. ------------------------------------
    wire [G:0] y13, y22;
    wire [G:0] m13;
    // The last iteration's m output is not needed (only y goes on); the port stays so that
    // both iterations are one module.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [G:0] m22;
    /* verilator lint_on UNUSEDSIGNAL */
    svo_newton_step #(.G(G), .YW(SEED), .YF(SEED), .PROD(PROD)) it1 (
        .clk(clk), .m_in(m4), .y_in(y4), .m_out(m13), .y_out(y13));
    svo_newton_step #(.G(G), .YW(G + 1), .YF(G), .PROD(PROD)) it2 (
        .clk(clk), .m_in(m13), .y_in(y13), .m_out(m22), .y_out(y22));
    wire [4:0] lead22;
    wire       neg22, zero22, flushed22;
    svo_delay #(.W(8), .D(19)) side22 (
        .clk(clk), .rst(1'b0), .d({lead3, neg3, zero3, flushed3}),
        .q({lead22, neg22, zero22, flushed22}));

    // ---- Stage 23: sign. --------------------------------------------------------------------
    reg  signed [G+1:0] code23;
    reg         [4:0]   lead23;
    reg                 neg23, zero23, flushed23;
    always @(posedge clk) begin
        code23    <= neg22 ? -$signed({1'b0, y22}) : $signed({1'b0, y22});
        lead23    <= lead22;
        neg23     <= neg22;
        zero23    <= zero22;
        flushed23 <= flushed22;
    end

    // ---- Stage 24: denormalise; the rounding increment decided. ----------------------------
    reg         [1:0]  s;
    reg  signed [G+1:0] fl;
    reg         [2:0]  rem, half;
    always @(*) begin
        s    = 2'd0;
        fl   = code23;
        rem  = 3'd0;
        half = 3'd0;
        if (lead23 > 5'd28) begin
            s    = lead23[1:0];                               // lead - 28 = 1..3 (28 = 0 mod 4)
            fl   = code23 >>> s;
            rem  = code23[2:0] & ((3'd1 << s) - 3'd1);
            half = 3'd1 << (s - 2'd1);
        end
    end
    wire up = (lead23 > 5'd28) && ((rem > half) || (rem == half && fl[0]));
    reg  signed [57:0] sh24;
    reg                up24, neg24, zero24, flushed24;
    always @(posedge clk) begin
        if (lead23 > 5'd28)
            sh24 <= $signed({{(56 - G){fl[G+1]}}, fl});
        else
            sh24 <= $signed({{(56 - G){code23[G+1]}}, code23} << (5'd28 - lead23));
        up24      <= up;
        neg24     <= neg23;
        zero24    <= zero23;
        flushed24 <= flushed23;
    end

    // ---- Stage 25: the increment added. -------------------------------------------------
    // A separate stage: the 58-bit carry chain after the shift and the decision would not
    // fit one cycle.
    reg  signed [57:0] val25;
    reg                neg25, zero25, flushed25;
    always @(posedge clk) begin
        val25     <= sh24 + $signed({57'd0, up24});
        neg25     <= neg24;
        zero25    <= zero24;
        flushed25 <= flushed24;
    end

    // ---- Stage 26: saturate; zero components. --------------------------------------------
    localparam signed [57:0] MAX = 58'sd2251799813685247;   //  2^51 - 1
    localparam signed [57:0] MIN = -58'sd2251799813685248;  // -2^51
    wire sat_hi = val25 > MAX;
    wire sat_lo = val25 < MIN;
    always @(posedge clk) begin
        out_zero     <= zero25;
        out_negative <= neg25;
        out_flushed  <= flushed25;
        if (zero25) begin
            out_inv <= neg25 ? 52'h8_0000_0000_0001 : 52'h7_ffff_ffff_ffff;
            out_ov  <= 1'b0;
        end else begin
            out_inv <= sat_hi ? 52'h7_ffff_ffff_ffff : sat_lo ? 52'h8_0000_0000_0000 : val25[51:0];
            out_ov  <= sat_hi | sat_lo;
        end
    end
endmodule

// svo_newton_step: one Newton-Raphson iteration y <- y * (2 - m*y), every product truncated
// to G fraction bits (uQ1.G operands). The incoming y arrives as a YW-bit code with YF
// fraction bits (YF <= G; the seed: 10 and 10), so its products are YW bits wide rather than
// G + 1: y * 2^(G - YF) is the uQ1.G value, and the shift is folded into the truncations
// (the bits it would append are zero, so floor(m*y / 2^YF) is floor(m*y' / 2^G) exactly).
// 2 * PROD + 1 cycles: P = m*y, q = 2 - floor(P), Y = y*q.
// Widths: the model's invariants (docs/units/reciprocal.md: y in [1/2, 1], m in [1, 2),
// p = floor(m*y) < 2, so q = 2 - p in (0, 2)) keep p in G + 2 bits (uQ2.G), q and the new y
// in G + 1 (uQ1.G); the subtraction still clamps at 0 as the model's saturating_sub does.
// Lint: DECLFILENAME is waived for this module alone: it is the reciprocal's private
// iteration, kept in the reciprocal's file so that the unit is one file (units.tsv, run.sh).
/* verilator lint_off DECLFILENAME */
module svo_newton_step #(
    parameter G = 32,
    parameter YW = G + 1,
    parameter YF = G,
    parameter PROD = 4
) (
    input  wire          clk,
    input  wire [G:0]    m_in,
    input  wire [YW-1:0] y_in,
    output wire [G:0]    m_out,
    output wire [G:0]    y_out
);
/* verilator lint_on DECLFILENAME */
    // One bit above the product, so that p's G + 2 bits can be selected when YF = YW.
    wire [G+YW:0]   p_mul = m_in * y_in;
    wire [G+YW+1:0] p_now = {1'b0, p_mul};
    // p_full's low YF bits (and, when YF < YW, its top bits, zero by the invariants) are what
    // the floor to uQ2.G drops.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [G+YW+1:0] p_full;
    /* verilator lint_on UNUSEDSIGNAL */
    svo_delay #(.W(G + YW + 2), .D(PROD)) p_line (.clk(clk), .rst(1'b0), .d(p_now), .q(p_full));
    wire [G+1:0] p   = p_full[YF +: G + 2];              // floor, uQ2.G
    wire [G+1:0] two = {2'b10, {G{1'b0}}};
    /* verilator lint_off UNUSEDSIGNAL */
    wire [G+1:0] q_now = (p > two) ? {(G + 2){1'b0}} : two - p;   // top bit dropped below
    /* verilator lint_on UNUSEDSIGNAL */
    reg  [G:0]   q;                                      // q < 2: its top bit is always 0
    always @(posedge clk) q <= q_now[G:0];
    wire [YW-1:0] y_d;
    svo_delay #(.W(YW), .D(PROD + 1)) y_line (.clk(clk), .rst(1'b0), .d(y_in), .q(y_d));
    wire [YW+G:0] yq_now = y_d * q;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [YW+G:0] yq;                                    // low YF bits: dropped by the floor
    /* verilator lint_on UNUSEDSIGNAL */
    svo_delay #(.W(YW + G + 1), .D(PROD)) yq_line (.clk(clk), .rst(1'b0), .d(yq_now), .q(yq));
    assign y_out = yq[YF +: G + 1];                      // floor, uQ1.G
    svo_delay #(.W(G + 1), .D(2 * PROD + 1)) m_line (.clk(clk), .rst(1'b0), .d(m_in), .q(m_out));
endmodule
`default_nettype wire
