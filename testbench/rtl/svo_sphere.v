// svo_sphere: the conservative ray / bounding-sphere test with its entry distance
// (rtl_model/src/units/sphere.rs, paper Eq. 4), square root included.
//
// Pipeline position: after ray generation, once per (ray, instance), in world space; the
// entry distance is the sorter's key. Default formats: positions sQ8.32 (40 bits), direction
// sQ2.30 (32), t_ca sQ10.24 (34, truncated), squares uQ16.48 (64), entry uQ10.22 (32,
// truncated). The host programs per instance T (threshold), the inside threshold, and the
// constants dt, reach and reach^2 (the model's sphere unit holds reach as a constant of the
// configuration, units::sphere::SphereUnit; its square is a constant too, so the lane spends
// no multiplier on it, as the resource estimate counts); they arrive with each transaction.
//
// Stages (rtl_model units::sphere::latency_cycles + the square root: 16 + 32 = 48 cycles,
// II = 1):
//   1        l = c - o (exact, 41 bits); far = some |l_k| > reach (kept, t_enter 0, flagged)
//   2..5     l_k * d_k and l_k * l_k (one DSP product: 4 cycles)
//   6, 7     the dot sums, (p0 + p1) + p2
//   8        t_ca = floor(l.d) into sQ10.24, saturated
//   9..12    t_ca^2 (48 fraction bits)
//   13       p2 = l.l - t_ca^2 (64 fraction bits: t_ca^2 shifted up by 16); inside iff
//            l.l <= inside; far by length iff l.l > reach^2
//   14       cull iff p2 > T (at the same scale); radicand = floor((T - max(p2, 0)) / 2^16)
//            in uQ16.48. Stages 13 and 14 were one (two 86-bit carry chains in series, 25
//            logic levels, 4.35 ns): split for 300 MHz (docs/cycle-model.md §1.5)
//   15..46   svo_sqrt: root = floor(sqrt(radicand)), uQ8.24
//   47       behind iff t_ca + dt + root < 0 (culled); t = t_ca - dt - root (24 fraction bits,
//            those of t_ca and of the root alike)
//   48       decide in the model's order: far, culled, behind, inside, else
//            t_enter = floor(max(t, 0) / 2^2), saturated to 32 bits (flagged)
`timescale 1ns/1ps
`default_nettype none
module svo_sphere (
    input  wire             clk,
    input  wire             rst,
    input  wire             in_valid,
    input  wire [3*40-1:0]  in_o,          // ray origin {z, y, x}, sQ8.32
    input  wire [3*32-1:0]  in_d,          // ray direction {z, y, x}, sQ2.30
    input  wire [3*40-1:0]  in_c,          // sphere centre {z, y, x}, sQ8.32
    input  wire [63:0]      in_threshold,  // T, uQ16.48
    input  wire [63:0]      in_inside,     // inside threshold, uQ16.48
    input  wire [33:0]      in_delta_t,    // dt, sQ10.24
    input  wire [39:0]      in_reach,      // reach, sQ8.32
    input  wire [79:0]      in_reach2,     // reach^2, uQ16.64 (the host squares the constant)
    output wire             out_valid,
    output reg              out_hit,
    output reg  [31:0]      out_t_enter,   // uQ10.22
    output reg              out_ov_reach,
    output reg              out_ov_t_enter
);
    localparam PROD = 4;       // cycles of one DSP product
    localparam ROOT = 32;      // square-root stages
    localparam LATENCY = 16 + ROOT;

    svo_delay #(.W(1), .D(LATENCY), .RESET(1)) valid_line (
        .clk(clk), .rst(rst), .d(in_valid), .q(out_valid));

    // ---- Stage 1: l = c - o, the reach test. -------------------------------------------
    reg signed [40:0] l1 [0:2];
    reg signed [31:0] d1 [0:2];
    reg               far1;
    reg        [79:0] reach2_1;   // reach^2 (64 fraction bits), for the length test at stage 13
    reg        [63:0] thr1, ins1;
    reg signed [33:0] dt1;
    wire signed [40:0] l_now [0:2];
    wire signed [40:0] reach_s = $signed({1'b0, in_reach});
    genvar k;
    generate
        for (k = 0; k < 3; k = k + 1) begin : diff
            assign l_now[k] = $signed({in_c[k*40 + 39], in_c[k*40 +: 40]})
                            - $signed({in_o[k*40 + 39], in_o[k*40 +: 40]});
        end
    endgenerate
    integer j;
    always @(posedge clk) begin
        for (j = 0; j < 3; j = j + 1) begin
            l1[j] <= l_now[j];
            d1[j] <= $signed(in_d[j*32 +: 32]);
        end
        far1 <= (l_now[0] > reach_s) || (l_now[0] < -reach_s)
             || (l_now[1] > reach_s) || (l_now[1] < -reach_s)
             || (l_now[2] > reach_s) || (l_now[2] < -reach_s);
        reach2_1 <= in_reach2;
        thr1 <= in_threshold;
        ins1 <= in_inside;
        dt1  <= $signed(in_delta_t);
    end

    // ---- Stages 2..5: products. -------------------------------------------------------
    wire signed [72:0] pd [0:2];
    wire        [81:0] pl [0:2];
    generate
        for (k = 0; k < 3; k = k + 1) begin : prod
            wire signed [72:0] pd_now = l1[k] * d1[k];
            wire signed [81:0] pl_now = l1[k] * l1[k];
            svo_delay #(.W(73), .D(PROD)) pd_line (.clk(clk), .rst(1'b0), .d(pd_now), .q(pd[k]));
            svo_delay #(.W(82), .D(PROD)) pl_line (.clk(clk), .rst(1'b0), .d(pl_now), .q(pl[k]));
        end
    endgenerate
    // Side-band of stages 2..12 (11 cycles after stage 1's registers, beside the products).
    wire        far13;
    wire [79:0] reach2_13;
    wire [63:0] thr13, ins13;
    wire [33:0] dt13;
    svo_delay #(.W(1 + 80 + 64 + 64 + 34), .D(11)) side13 (
        .clk(clk), .rst(1'b0), .d({far1, reach2_1, thr1, ins1, dt1}),
        .q({far13, reach2_13, thr13, ins13, dt13}));

    // ---- Stages 6, 7: (p0 + p1) + p2. ------------------------------------------------
    reg signed [74:0] dot01, dot7;
    reg signed [72:0] pd2_6;
    reg        [83:0] l2_01, l2_7;
    reg        [81:0] pl2_6;
    always @(posedge clk) begin
        dot01 <= {{2{pd[0][72]}}, pd[0]} + {{2{pd[1][72]}}, pd[1]};
        pd2_6 <= pd[2];
        l2_01 <= {2'b00, pl[0]} + {2'b00, pl[1]};
        pl2_6 <= pl[2];
        dot7  <= dot01 + {{2{pd2_6[72]}}, pd2_6};
        l2_7  <= l2_01 + {2'b00, pl2_6};
    end

    // ---- Stage 8: t_ca = floor(l.d / 2^38), saturated into sQ10.24. ------------------
    wire signed [74:0] tca_fl = dot7 >>> 38;
    wire tca_hi = tca_fl > 75'sd8589934591;          //  2^33 - 1
    wire tca_lo = tca_fl < -75'sd8589934592;         // -2^33
    reg signed [33:0] tca8;
    reg        [83:0] l2_8;
    always @(posedge clk) begin
        tca8 <= tca_hi ? 34'sh1_ffff_ffff : tca_lo ? -34'sh2_0000_0000 : tca_fl[33:0];
        l2_8 <= l2_7;
    end

    // ---- Stages 9..12: t_ca^2 (uQ20.48: below 2^66, so 67 bits hold it). --------------
    wire signed [66:0] tca2_now = tca8 * tca8;
    wire signed [66:0] tca2;
    wire        [83:0] l2_12;
    wire signed [33:0] tca12;
    svo_delay #(.W(67), .D(PROD)) tca2_line (.clk(clk), .rst(1'b0), .d(tca2_now), .q(tca2));
    svo_delay #(.W(84 + 34), .D(PROD)) side12 (
        .clk(clk), .rst(1'b0), .d({l2_8, tca8}), .q({l2_12, tca12}));

    // ---- Stage 13: p2, inside, far by length. ------------------------------------------
    wire signed [85:0] p2_now = $signed({2'b00, l2_12}) - $signed({3'b000, tca2[66:0], 16'b0});
    wire inside_now = {2'b00, l2_12} <= {6'b0, ins13, 16'b0};
    reg  signed [85:0] p2_13;
    reg  [63:0] thr13r;
    reg         inside13, far13r;
    reg  signed [33:0] tca13, dt13r;
    always @(posedge clk) begin
        p2_13    <= p2_now;
        thr13r   <= thr13;
        inside13 <= inside_now;
        // Beyond the reach by length (exact l.l against reach^2), not only by component:
        // along a diagonal every |l_k| can be within the reach while |l| is not.
        far13r   <= far13 || (l2_12 > {4'b0, reach2_13});
        tca13    <= tca12;
        dt13r    <= $signed(dt13);
    end

    // ---- Stage 14: cull, radicand. ---------------------------------------------------------
    wire signed [85:0] thr = $signed({6'b0, thr13r, 16'b0});
    wire signed [85:0] p2_pos = (p2_13 < 0) ? 86'sd0 : p2_13;
    wire signed [85:0] room = thr - p2_pos;
    wire cull_now = p2_13 > thr;
    wire [63:0] radicand_now = (room < 0) ? 64'd0 : room[79:16];
    reg  [63:0] radicand14;
    reg         cull14, inside14, far14;
    reg  signed [33:0] tca14, dt14;
    always @(posedge clk) begin
        radicand14 <= radicand_now;
        cull14     <= cull_now;
        inside14   <= inside13;
        far14      <= far13r;
        tca14      <= tca13;
        dt14       <= dt13r;
    end

    // ---- Stages 15..46: the square root. -------------------------------------------------
    wire [31:0] root;
    /* verilator lint_off UNUSEDSIGNAL */
    wire        root_valid;  // unused: the valid line above carries validity
    /* verilator lint_on UNUSEDSIGNAL */
    svo_sqrt #(.N(64)) sqrt_unit (
        .clk(clk), .rst(rst), .in_valid(1'b1), .in_x(radicand14),
        .out_valid(root_valid), .out_root(root));
    wire        far46, cull46, inside46;
    wire signed [33:0] tca46, dt46;
    svo_delay #(.W(3 + 34 + 34), .D(ROOT)) side46 (
        .clk(clk), .rst(1'b0), .d({far14, cull14, inside14, tca14, dt14}),
        .q({far46, cull46, inside46, tca46, dt46}));

    // ---- Stage 47: behind, t. ------------------------------------------------------------
    wire signed [35:0] root_f = $signed({4'b0, root});            // uQ8.24, as t_ca
    reg  signed [35:0] t47;
    reg                behind47, far47, cull47, inside47;
    always @(posedge clk) begin
        behind47 <= ($signed({{2{tca46[33]}}, tca46}) + $signed({{2{dt46[33]}}, dt46}) + root_f) < 0;
        t47      <= $signed({{2{tca46[33]}}, tca46}) - $signed({{2{dt46[33]}}, dt46}) - root_f;
        far47    <= far46;
        cull47   <= cull46;
        inside47 <= inside46;
    end

    // ---- Stage 48: decide. ---------------------------------------------------------------
    wire [33:0] t_q   = (t47 < 0) ? 34'd0 : t47[35:2];      // max(t, 0), 24 -> 22 fraction bits, floor
    wire        t_sat = t_q > 34'h0_ffff_ffff;
    always @(posedge clk) begin
        out_ov_reach   <= far47;
        out_ov_t_enter <= 1'b0;
        out_t_enter    <= 32'd0;
        if (far47) begin
            out_hit <= 1'b1;
        end else if (cull47 || behind47) begin
            out_hit <= 1'b0;
        end else if (inside47) begin
            out_hit <= 1'b1;
        end else begin
            out_hit        <= 1'b1;
            out_t_enter    <= t_sat ? 32'hffff_ffff : t_q[31:0];
            out_ov_t_enter <= t_sat;
        end
    end
endmodule
`default_nettype wire
