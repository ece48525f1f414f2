// svo_walker_root: the walker-root unit, the root node's slab times of one walk
// (rtl_model/src/units/walker.rs, walk_fixed_observed before the loop; docs/cycle-model.md §1.4).
//
// Pipeline position: after the reciprocal units, before the walker's dispatcher (the cycle
// model's `root` stage, `units.walker_root`); feeds svo_walker. Per axis k:
//   mirroring   o' = -o when the direction is negative (the sign bit, so -0 counts): exact,
//               one bit wider than pos;
//   zero axis   t0 = -inf, t1 = +inf when -e <= o' < e, else the walk misses;
//   other axes  t0 = (-e - o') * inv, t1 = (e - o') * inv: exact differences (pos + 2 bits),
//               exact products, truncated (toward -inf) by POS_FRAC + INV_FRAC - T_FRAC bits
//               into the t format and saturated to it.
// The walk enters when max(t0) < min(t1) and min(t1) > 0 and no zero axis missed.
// -inf / +inf are the most negative and most positive codes of T_W + 1 bits, outside every
// t code (the model's i64::MIN / i64::MAX sentinels), so comparisons with them are exact.
//
// Widths come from walker_pkg.sv (`sim vectors`): POS_W/POS_FRAC = walker.pos (sQ8.32, 40
// bits), INV_W/INV_FRAC = walker.inv (sQ22.26, 48 bits), T_W/T_FRAC = walker.t (sQ31.31, 62
// bits, truncation, saturation: the only t quantisation this RTL implements).
//
// Stages (LATENCY = 1 + PROD + 1 + 2 = walker::root_latency_cycles, 8 by default, II = 1):
//   1          o', +-e - o', zero-axis slab test
//   2..1+PROD  the six slab products (one DSP product of PROD cycles): in stage 2 each
//              product's NA x NB DSP48E2 tiles (2 x 3), in stage 3 their sum (an adder tree),
//              then delay
//   2+PROD     truncate and saturate into t; the sentinels on zero axes
//   3+PROD     max of t0 and min of t1 over the axes
//   4+PROD     the entry test
// TAG_W bits of side-band (memory bases, a row number) travel beside the walk.
`timescale 1ns/1ps
`default_nettype none
module svo_walker_root #(
    parameter POS_W    = 40,
    parameter POS_FRAC = 32,
    parameter INV_W    = 48,
    parameter INV_FRAC = 26,
    parameter T_W      = 62,
    parameter T_FRAC   = 31,
    parameter PROD     = 4,
    parameter TAG_W    = 1
) (
    input  wire                 clk,
    input  wire                 rst,
    input  wire                 in_valid,
    input  wire [3*POS_W-1:0]   in_o,      // {z, y, x} local origin
    input  wire [3*INV_W-1:0]   in_inv,    // {z, y, x} 1/|d| (ignored on zero axes)
    input  wire [2:0]           in_zero,   // bit k: axis k's direction treated as 0
    input  wire [2:0]           in_neg,    // bit k: axis k's direction negative (mirrored)
    input  wire [3*POS_W-1:0]   in_half,   // {z, y, x} half extents of the octree's box
    input  wire [TAG_W-1:0]     in_tag,
    output wire                 out_valid,
    output wire                 out_enter, // the ray enters the root (else the walk misses)
    output reg  [3*(T_W+1)-1:0] out_t0,    // {z, y, x} root slab entry times, with sentinels
    output reg  [3*(T_W+1)-1:0] out_t1,    // {z, y, x} root slab exit times
    output wire [3*(POS_W+1)-1:0] out_o,   // {z, y, x} mirrored origin o'
    output wire [3*POS_W-1:0]   out_half,
    output wire [2:0]           out_zero,
    output wire [2:0]           out_neg,
    output wire [TAG_W-1:0]     out_tag
);
    localparam LATENCY = 1 + PROD + 1 + 2;
    localparam TI = T_W + 1;                     // t with room for the sentinels
    localparam DW = POS_W + 2;                   // +-e - o'
    localparam PW = DW + INV_W;                  // exact product
    localparam SHIFT = POS_FRAC + INV_FRAC - T_FRAC;
    localparam signed [TI-1:0] NEG_INF = {1'b1, {(TI-1){1'b0}}};
    localparam signed [TI-1:0] POS_INF = {1'b0, {(TI-1){1'b1}}};
    localparam signed [PW-1:0] T_MAX = {{(PW-T_W+1){1'b0}}, {(T_W-1){1'b1}}};
    localparam signed [PW-1:0] T_MIN = ~T_MAX;

    // Valid bits per stage; each stage's data registers load only with a valid walk (a
    // clock enable: idle stages hold still).
    reg       v1, vq, vm, vo;
    reg [PROD-1:0] vp;
    always @(posedge clk) begin
        if (rst) begin
            {v1, vq, vm, vo} <= 4'd0;
            vp <= {PROD{1'b0}};
        end else begin
            v1 <= in_valid;
            vp <= {vp[PROD-2:0], v1};
            vq <= vp[PROD-1];
            vm <= vq;
            vo <= vm;
        end
    end
    assign out_valid = vo;

    // Stage 1.
    reg [TAG_W-1:0]       s1_tag;
    reg [3*(POS_W+1)-1:0] s1_o;
    reg [3*POS_W-1:0]     s1_half;
    reg [2:0]             s1_zero, s1_neg, s1_miss;
    reg signed [DW-1:0]   s1_lo [0:2];
    reg signed [DW-1:0]   s1_hi [0:2];
    reg signed [INV_W-1:0] s1_inv [0:2];
    integer k;
    // The mirrored origin and the half extent, one bit wider (combinational).
    wire signed [POS_W:0] o_m [0:2];
    wire signed [POS_W:0] e_m [0:2];
    genvar g;
    generate
        for (g = 0; g < 3; g = g + 1) begin : axis
            wire signed [POS_W:0] o_in = $signed({in_o[g*POS_W + POS_W-1], in_o[g*POS_W +: POS_W]});
            assign o_m[g] = in_neg[g] ? -o_in : o_in;
            assign e_m[g] = $signed({in_half[g*POS_W + POS_W-1], in_half[g*POS_W +: POS_W]});
        end
    endgenerate
    always @(posedge clk) if (in_valid) begin
        s1_tag  <= in_tag;
        s1_half <= in_half;
        s1_zero <= in_zero;
        s1_neg  <= in_neg;
        for (k = 0; k < 3; k = k + 1) begin
            s1_o[k*(POS_W+1) +: POS_W+1] <= o_m[k];
            s1_miss[k] <= in_zero[k] && !(-e_m[k] <= o_m[k] && o_m[k] < e_m[k]);
            s1_lo[k]  <= -$signed({e_m[k][POS_W], e_m[k]}) - $signed({o_m[k][POS_W], o_m[k]});
            s1_hi[k]  <= $signed({e_m[k][POS_W], e_m[k]}) - $signed({o_m[k][POS_W], o_m[k]});
            s1_inv[k] <= $signed(in_inv[k*INV_W +: INV_W]);
        end
    end

    // The side-band waits beside the arithmetic.
    localparam SW = TAG_W + 3*(POS_W+1) + 3*POS_W + 6;
    reg [SW-1:0] side [0:LATENCY-2];
    wire [LATENCY-2:0] side_en = {vm, vq, vp, v1};   // stage i loads when stage i-1 is valid
    integer si;
    always @(posedge clk) begin
        if (v1) side[0] <= {s1_tag, s1_o, s1_half, s1_zero, s1_neg};
        for (si = 1; si < LATENCY - 1; si = si + 1)
            if (side_en[si]) side[si] <= side[si-1];
    end
    assign {out_tag, out_o, out_half, out_zero, out_neg} = side[LATENCY-2];

    // Stages 2..1+PROD: the six products, each as the DSP48E2 tiles the estimate counts
    // (fixed::dsp48e2_per_product): the difference in NA sub-words of 26 bits on the 27-bit
    // port, 1/|d| in NB sub-words of 17 bits on the 18-bit port, the lower sub-words unsigned
    // (a 0 above), the top one signed; one 27 x 18 signed product per tile (stage 2, the
    // DSP's), their sum pp_ij << (26i + 17j) as a balanced adder tree in stage 3 (the sum of
    // the estimate's multi-slice product), then PROD - 2 more registers. Written as one
    // product, Yosys slices the 52-bit operand in 17-bit steps (9 tiles, not 6) and adds the
    // partial products in four adder levels (16 logic levels, 3.45 ns at 300 MHz).
    localparam NA = (DW - 1 + 25) / 26;          // sub-words of the difference
    localparam NB = (INV_W - 1 + 16) / 17;       // sub-words of 1/|d|
    localparam NT = NA * NB;                     // tiles
    localparam TL = (NT <= 1) ? 1 : $clog2(NT);  // adder-tree levels
    localparam TN = 1 << TL;                     // leaves, zero-padded
    reg signed [44:0] pp_lo [0:2][0:NT-1];
    reg signed [44:0] pp_hi [0:2][0:NT-1];
    reg signed [PW-1:0] p_lo [1:PROD-1][0:2];
    reg signed [PW-1:0] p_hi [1:PROD-1][0:2];
    reg [5:0]           p_miss_zero [0:PROD-1];   // {miss, zero}
    wire signed [PW-1:0] sum_lo [0:2];
    wire signed [PW-1:0] sum_hi [0:2];
    genvar ga, gb;
    generate
        for (g = 0; g < 3; g = g + 1) begin : tiles
            wire signed [26:0] alo [0:NA-1];
            wire signed [26:0] ahi [0:NA-1];
            wire signed [17:0] bv  [0:NB-1];
            for (ga = 0; ga < NA; ga = ga + 1) begin : sa
                if (ga == NA - 1) begin : top
                    // The top sub-word, sign-extended (bits below 26*ga unused here).
                    /* verilator lint_off UNUSEDSIGNAL */
                    wire signed [DW+26:0] xl = {{27{s1_lo[g][DW-1]}}, s1_lo[g]};
                    wire signed [DW+26:0] xh = {{27{s1_hi[g][DW-1]}}, s1_hi[g]};
                    /* verilator lint_on UNUSEDSIGNAL */
                    assign alo[ga] = xl[26*ga +: 27];
                    assign ahi[ga] = xh[26*ga +: 27];
                end else begin : low
                    assign alo[ga] = $signed({1'b0, s1_lo[g][26*ga +: 26]});
                    assign ahi[ga] = $signed({1'b0, s1_hi[g][26*ga +: 26]});
                end
            end
            for (gb = 0; gb < NB; gb = gb + 1) begin : sb
                if (gb == NB - 1) begin : top
                    /* verilator lint_off UNUSEDSIGNAL */
                    wire signed [INV_W+17:0] x = {{18{s1_inv[g][INV_W-1]}}, s1_inv[g]};
                    /* verilator lint_on UNUSEDSIGNAL */
                    assign bv[gb] = x[17*gb +: 18];
                end else begin : low
                    assign bv[gb] = $signed({1'b0, s1_inv[g][17*gb +: 17]});
                end
            end
            for (ga = 0; ga < NA; ga = ga + 1) begin : ta
                for (gb = 0; gb < NB; gb = gb + 1) begin : tb
                    always @(posedge clk) if (v1) begin
                        pp_lo[g][ga*NB + gb] <= alo[ga] * bv[gb];
                        pp_hi[g][ga*NB + gb] <= ahi[ga] * bv[gb];
                    end
                end
            end
            // The tree, heap order: node n = node 2n + node 2n+1, leaves TN..2TN-1.
            // (One array per tree: Verilator cannot tell its nodes apart, no loop exists.)
            /* verilator lint_off UNOPTFLAT */
            wire signed [PW-1:0] nlo [1:2*TN-1];
            wire signed [PW-1:0] nhi [1:2*TN-1];
            /* verilator lint_on UNOPTFLAT */
            genvar gn;
            for (gn = 0; gn < TN; gn = gn + 1) begin : leaf
                if (gn < NT) begin : tile
                    localparam integer SH = 26 * (gn / NB) + 17 * (gn % NB);
                    wire signed [PW-1:0] el = {{(PW-45){pp_lo[g][gn][44]}}, pp_lo[g][gn]};
                    wire signed [PW-1:0] eh = {{(PW-45){pp_hi[g][gn][44]}}, pp_hi[g][gn]};
                    assign nlo[TN + gn] = el <<< SH;
                    assign nhi[TN + gn] = eh <<< SH;
                end else begin : pad
                    assign nlo[TN + gn] = {PW{1'b0}};
                    assign nhi[TN + gn] = {PW{1'b0}};
                end
            end
            for (gn = 1; gn < TN; gn = gn + 1) begin : node
                assign nlo[gn] = nlo[2*gn] + nlo[2*gn + 1];
                assign nhi[gn] = nhi[2*gn] + nhi[2*gn + 1];
            end
            assign sum_lo[g] = nlo[1];
            assign sum_hi[g] = nhi[1];
        end
    endgenerate
    integer s;
    always @(posedge clk) begin
        if (v1) p_miss_zero[0] <= {s1_miss, s1_zero};
        if (vp[0]) begin
            for (k = 0; k < 3; k = k + 1) begin
                p_lo[1][k] <= sum_lo[k];
                p_hi[1][k] <= sum_hi[k];
            end
            p_miss_zero[1] <= p_miss_zero[0];
        end
        for (s = 2; s < PROD; s = s + 1) if (vp[s-1]) begin
            for (k = 0; k < 3; k = k + 1) begin
                p_lo[s][k] <= p_lo[s-1][k];
                p_hi[s][k] <= p_hi[s-1][k];
            end
            p_miss_zero[s] <= p_miss_zero[s-1];
        end
    end

    // Stage 2+PROD: truncate (arithmetic shift) and saturate into t.
    function automatic [TI-1:0] to_t(input signed [PW-1:0] p);
        reg signed [PW-1:0] q;
        begin
            q = p >>> SHIFT;
            if (q > T_MAX) q = T_MAX;
            else if (q < T_MIN) q = T_MIN;
            to_t = q[TI-1:0];
        end
    endfunction
    reg signed [TI-1:0] q_t0 [0:2];
    reg signed [TI-1:0] q_t1 [0:2];
    reg [2:0]           q_miss;
    always @(posedge clk) if (vp[PROD-1]) begin
        for (k = 0; k < 3; k = k + 1) begin
            q_t0[k] <= p_miss_zero[PROD-1][k] ? NEG_INF : to_t(p_lo[PROD-1][k]);
            q_t1[k] <= p_miss_zero[PROD-1][k] ? POS_INF : to_t(p_hi[PROD-1][k]);
        end
        q_miss <= p_miss_zero[PROD-1][5:3];
    end

    // Stage 3+PROD: max of t0, min of t1.
    reg signed [TI-1:0] m_enter, m_exit;
    reg                 m_miss;
    reg [3*TI-1:0]      m_t0, m_t1;
    reg signed [TI-1:0] a, bb;
    always @* begin
        a  = q_t0[0];
        if (q_t0[1] > a) a = q_t0[1];
        if (q_t0[2] > a) a = q_t0[2];
        bb = q_t1[0];
        if (q_t1[1] < bb) bb = q_t1[1];
        if (q_t1[2] < bb) bb = q_t1[2];
    end
    always @(posedge clk) if (vq) begin
        m_enter <= a;
        m_exit  <= bb;
        m_miss  <= |q_miss;
        m_t0    <= {q_t0[2], q_t0[1], q_t0[0]};
        m_t1    <= {q_t1[2], q_t1[1], q_t1[0]};
    end

    // Stage 4+PROD: the entry test.
    reg enter_r;
    always @(posedge clk) if (vm) begin
        enter_r <= !m_miss && m_enter < m_exit && m_exit > $signed({TI{1'b0}});
        out_t0  <= m_t0;
        out_t1  <= m_t1;
    end
    assign out_enter = enter_r;
endmodule
`default_nettype wire
