// svo_normal: the hit record's octahedral normal code from the leaf's stored normal and the
// instance's normal matrix, in integers (rtl_model/src/units/normal.rs `normal_code`,
// docs/units/normal.md).
//
// Pipeline position: the record stage, in front of svo_hit_pack (svo_walk_wide): when a ray's
// record is decided, its best hit's attribute word (normal: {v, u} snorm16) and its
// instance's matrix (R·diag(1/scale) scaled to a largest element of ±1, sQ2.16, row-major:
// element 3i+j at [(3i+j)*18 +: 18] multiplies component j into world component i) enter;
// {v, u} (N_W-bit signed codes) leave LATENCY cycles later. Octahedral encoding is
// scale-invariant, so nothing is normalised and no square root is taken.
//
// Stages, each within the clock rule's 300 MHz (docs/cycle-model.md §1.5; 13 at N_W = 8):
// (1a, 1b) unfold the snorm16 code to the octahedron point p (|p|1 = 32767, exact integers):
// magnitudes, then z and the fold, the matrix registered beside; (2) 9 products sQ2.16 x int17 (DSP48E2 27x18 each);
// (3) the sums w = M·p; (4) |w| and the signs; (5) the L1 norm l1 = |w|1 and the numerators
// (|x|, |y| on the upper hemisphere, |x| + |z|, |y| + |z| folded on the lower); (6) the shift
// that leaves l1 at most DB bits (units::normal::DIV_BITS); (7) l1 and both numerators shifted
// right by it (truncating); (8) the dividends 2s·a + l1 (shifts and adders),
// s = 2^(N_W-1) - 1; (9)-(11) the restoring division q = floor((2s·a + l1) / (2·l1)), two
// quotient bits a stage from the top, and in (12) the last bit and the sign (x < 0: negative;
// 0 counts as positive) into the output register. l1 = 0 (a zero matrix) gives {0, 0}. II = 1.
`timescale 1ns/1ps
`default_nettype none
module svo_normal #(
    parameter N_W = 8                          // bits per output component
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              in_valid,
    input  wire [31:0]       in_oct,           // {v, u} snorm16
    input  wire [9*18-1:0]   in_mat,           // sQ2.16, row-major
    output reg               out_valid,
    output reg  [2*N_W-1:0]  out_code          // {v, u}
);
    // The output register is the thirteenth; the testbench prints it (tb_normal.sv), and
    // tests/testbench_icarus.rs compares it with rtl_model units::normal::LATENCY_CYCLES.
    /* verilator lint_off UNUSEDPARAM */
    localparam LATENCY = 9 + N_W / 2;         // 13 at N_W = 8
    /* verilator lint_on UNUSEDPARAM */
    localparam QB = N_W - 1;                   // quotient bits: q <= s < 2^QB
    localparam LAST = 6 + (QB + 1) / 2;        // the output stage: two quotient bits a stage
    localparam LW = 35;                        // |w|1 < 3 * 2^16 * 32767 < 2^33; room to spare
    localparam DB = 18;                        // divisor bits kept (units::normal::DIV_BITS)
    localparam NB = DB + N_W + 1;              // 2s·a + l1 < 2^N_W * l1

    // ---------------------------------------------------------------- stages 1 and 2: unfold, products
    // (1a) The -32768 clamp (it reads as -1) and the magnitudes, registered.
    wire [15:0] u_raw = in_oct[15:0];
    wire [15:0] v_raw = in_oct[31:16];
    wire [15:0] u_c = {u_raw[15:1], u_raw[0] | (u_raw == 16'h8000)};   // 0x8000 -> 0x8001
    wire [15:0] v_c = {v_raw[15:1], v_raw[0] | (v_raw == 16'h8000)};
    reg [15:0] au, av;                          // |u|, |v| <= 32767
    reg su, sv, va;
    reg [9*18-1:0] mat_a;
    always @(posedge clk) begin
        va    <= rst ? 1'b0 : in_valid;
        au    <= u_c[15] ? 16'd0 - u_c : u_c;
        av    <= v_c[15] ? 16'd0 - v_c : v_c;
        su    <= u_c[15];
        sv    <= v_c[15];
        mat_a <= in_mat;
    end
    // (1b) z and the fold, every candidate in parallel, one select; registered.
    wire signed [17:0] z  = 18'sd32767 - $signed({2'b00, au}) - $signed({2'b00, av});
    wire signed [16:0] su_a = su ? -$signed({1'b0, au}) : $signed({1'b0, au});   // u
    wire signed [16:0] sv_a = sv ? -$signed({1'b0, av}) : $signed({1'b0, av});   // v
    wire signed [16:0] fx = su ? $signed({1'b0, av}) - 17'sd32767 : 17'sd32767 - $signed({1'b0, av});
    wire signed [16:0] fy = sv ? $signed({1'b0, au}) - 17'sd32767 : 17'sd32767 - $signed({1'b0, au});
    reg signed [16:0] p0, p1, p2;
    reg [9*18-1:0] mat;
    reg v0;
    always @(posedge clk) begin
        v0  <= rst ? 1'b0 : va;
        p0  <= z[17] ? fx : su_a;
        p1  <= z[17] ? fy : sv_a;
        p2  <= z[16:0];
        mat <= mat_a;
    end

    // Operands sign-extended to the product's 35 bits (synthesis trims the copies of the sign).
    wire [3*35-1:0] p_ext = {{{18{p2[16]}}, p2}, {{18{p1[16]}}, p1}, {{18{p0[16]}}, p0}};
    reg signed [34:0] prod [0:8];
    reg v1;
    integer k;
    always @(posedge clk) begin
        v1 <= rst ? 1'b0 : v0;
        for (k = 0; k < 9; k = k + 1)
            prod[k] <= $signed({{17{mat[k*18+17]}}, mat[k*18 +: 18]})
                     * $signed(p_ext[(k % 3)*35 +: 35]);
    end
    function automatic signed [36:0] sx37(input signed [34:0] x);
        sx37 = {{2{x[34]}}, x};
    endfunction

    // ---------------------------------------------------------------- stage 3: sums
    reg signed [36:0] wx, wy, wz;
    reg v2;
    always @(posedge clk) begin
        v2 <= rst ? 1'b0 : v1;
        wx <= sx37(prod[0]) + sx37(prod[1]) + sx37(prod[2]);
        wy <= sx37(prod[3]) + sx37(prod[4]) + sx37(prod[5]);
        wz <= sx37(prod[6]) + sx37(prod[7]) + sx37(prod[8]);
    end

    // ---------------------------------------------------------------- stage 4: |w|
    reg [36:0] ax, ay, az;
    reg sx_3, sy_3, szn_3, v3;
    always @(posedge clk) begin
        v3    <= rst ? 1'b0 : v2;
        ax    <= wx[36] ? -wx : wx;
        ay    <= wy[36] ? -wy : wy;
        az    <= wz[36] ? -wz : wz;
        sx_3  <= wx[36];
        sy_3  <= wy[36];
        szn_3 <= wz[36];
    end

    // ---------------------------------------------------------------- stage 5: l1, numerators
    /* verilator lint_off UNUSEDSIGNAL */
    wire [36:0] l1_w = ax + ay + az;            // < 2^33
    wire [36:0] nu_w = szn_3 ? ax + az : ax;    // <= l1
    wire [36:0] nv_w = szn_3 ? ay + az : ay;
    /* verilator lint_on UNUSEDSIGNAL */
    reg [LW-1:0] l1_4, nu_4, nv_4;
    reg sx_4, sy_4, v4;
    always @(posedge clk) begin
        v4   <= rst ? 1'b0 : v3;
        l1_4 <= l1_w[LW-1:0];
        nu_4 <= nu_w[LW-1:0];
        nv_4 <= nv_w[LW-1:0];
        sx_4 <= sx_3;
        sy_4 <= sy_3;
    end

    // ---------------------------------------------------------------- stages 6 and 7: normalise
    // The shift: l1's bit length above DB (units::normal::normalise_shift).
    function automatic [5:0] shift_of(input [LW-1:0] x);
        integer i;
        begin
            shift_of = 6'd0;
            for (i = DB; i < LW; i = i + 1)
                if (x[i]) shift_of = i[5:0] - DB[5:0] + 6'd1;
        end
    endfunction
    // The shift amount in its own stage (the priority encoder), then the shift.
    reg [5:0] sh;
    reg [LW-1:0] l1_4s, nu_4s, nv_4s;
    reg sx_4s, sy_4s, v4s;
    always @(posedge clk) begin
        v4s   <= rst ? 1'b0 : v4;
        sh    <= shift_of(l1_4);
        l1_4s <= l1_4;
        nu_4s <= nu_4;
        nv_4s <= nv_4;
        sx_4s <= sx_4;
        sy_4s <= sy_4;
    end
    /* verilator lint_off UNUSEDSIGNAL */
    wire [LW-1:0] l1_s = l1_4s >> sh;
    wire [LW-1:0] nu_s = nu_4s >> sh;
    wire [LW-1:0] nv_s = nv_4s >> sh;
    /* verilator lint_on UNUSEDSIGNAL */
    reg [DB-1:0] l1_5, nu_5, nv_5;
    reg sx_5, sy_5, v5;
    always @(posedge clk) begin
        v5   <= rst ? 1'b0 : v4s;
        l1_5 <= l1_s[DB-1:0];
        nu_5 <= nu_s[DB-1:0];
        nv_5 <= nv_s[DB-1:0];
        sx_5 <= sx_4s;
        sy_5 <= sy_4s;
    end

    // ---------------------------------------------------------------- stage 8: dividends
    // 2s·a = a·2^N_W − 2a: shifts and adders, no multiplier.
    function automatic [NB-1:0] numerator(input [DB-1:0] a, input [DB-1:0] l1);
        numerator = ({{(NB-DB){1'b0}}, a} << N_W) - ({{(NB-DB){1'b0}}, a} << 1)
                  + {{(NB-DB){1'b0}}, l1};
    endfunction
    reg [NB-1:0] r_u [6:LAST];                  // the dividers' registers, index k = stage k + 2
    reg [NB-1:0] r_v [6:LAST];
    reg [NB-1:0] d_k [6:LAST];                  // the divisor 2·l1 beside them
    reg [QB-1:0] q_u [6:LAST];
    reg [QB-1:0] q_v [6:LAST];
    reg sx_k [6:LAST];
    reg sy_k [6:LAST];
    reg zero_k [6:LAST];
    reg v_k [6:LAST];
    always @(posedge clk) begin
        v_k[6]    <= rst ? 1'b0 : v5;
        r_u[6]    <= numerator(nu_5, l1_5);
        r_v[6]    <= numerator(nv_5, l1_5);
        d_k[6]    <= {{(NB-DB-1){1'b0}}, l1_5, 1'b0};
        q_u[6]    <= {QB{1'b0}};
        q_v[6]    <= {QB{1'b0}};
        sx_k[6]   <= sx_5;
        sy_k[6]   <= sy_5;
        zero_k[6] <= l1_5 == {DB{1'b0}};
    end

    // ---------------------------------------------------------------- stages 9 .. 12: division
    // One restoring step for quotient bit i: one subtractor, its borrow selects.
    function automatic [NB:0] step(input [NB-1:0] r, input [NB-1:0] d, input integer i);
        reg [NB:0] diff;
        begin
            diff = {1'b0, r} - ({1'b0, d} << i);
            step = diff[NB] ? {1'b0, r} : {1'b1, diff[NB-1:0]};   // {quotient bit, remainder}
        end
    endfunction
    // Index k (7 .. LAST, stages 9 .. 12) decides quotient bits QB-1-2(k-7) and the one below.
    genvar g;
    generate
        for (g = 7; g <= LAST; g = g + 1) begin : div
            localparam integer HI = QB - 1 - 2 * (g - 7);
            wire [NB:0] a_u = step(r_u[g-1], d_k[g-1], HI);
            wire [NB:0] a_v = step(r_v[g-1], d_k[g-1], HI);
            localparam integer LO = HI > 0 ? HI - 1 : 0;   // the second bit, if HI > 0
            wire [NB:0] b_u, b_v;
            if (HI > 0) begin : two
                assign b_u = step(a_u[NB-1:0], d_k[g-1], LO);
                assign b_v = step(a_v[NB-1:0], d_k[g-1], LO);
            end else begin : one
                assign b_u = {1'b0, a_u[NB-1:0]};
                assign b_v = {1'b0, a_v[NB-1:0]};
            end
            wire [QB-1:0] bit_hi = {{(QB-1){1'b0}}, 1'b1} << HI;
            wire [QB-1:0] bit_lo = HI > 0 ? {{(QB-1){1'b0}}, 1'b1} << LO : {QB{1'b0}};
            wire [QB-1:0] nq_u = q_u[g-1] | (a_u[NB] ? bit_hi : {QB{1'b0}})
                                          | (b_u[NB] ? bit_lo : {QB{1'b0}});
            wire [QB-1:0] nq_v = q_v[g-1] | (a_v[NB] ? bit_hi : {QB{1'b0}})
                                          | (b_v[NB] ? bit_lo : {QB{1'b0}});
            if (g < LAST) begin : mid
                always @(posedge clk) begin
                    v_k[g]    <= rst ? 1'b0 : v_k[g-1];
                    r_u[g]    <= b_u[NB-1:0];
                    r_v[g]    <= b_v[NB-1:0];
                    d_k[g]    <= d_k[g-1];
                    q_u[g]    <= nq_u;
                    q_v[g]    <= nq_v;
                    sx_k[g]   <= sx_k[g-1];
                    sy_k[g]   <= sy_k[g-1];
                    zero_k[g] <= zero_k[g-1];
                end
            end else begin : last
                wire [N_W-1:0] qu = {1'b0, nq_u};
                wire [N_W-1:0] qv = {1'b0, nq_v};
                always @(posedge clk) begin
                    out_valid <= rst ? 1'b0 : v_k[g-1];
                    out_code  <= zero_k[g-1] ? {(2*N_W){1'b0}}
                               : {sy_k[g-1] ? -qv : qv, sx_k[g-1] ? -qu : qu};
                end
            end
        end
    endgenerate
endmodule
`default_nettype wire
