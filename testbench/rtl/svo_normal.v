// svo_normal: the hit record's octahedral normal code from the leaf's stored normal and the
// instance's normal matrix, in integers (rtl_model/src/units/normal.rs `normal_code`,
// docs/units/normal.md).
//
// Pipeline position: the record stage, in front of svo_hit_pack (svo_walk): when a ray's
// record is decided, its best hit's attribute word (normal: {v, u} snorm16) and its
// instance's matrix (R·diag(1/scale) scaled to a largest element of ±1, sQ2.16, row-major:
// element 3i+j at [(3i+j)*18 +: 18] multiplies component j into world component i) enter;
// {v, u} (N_W-bit signed codes) leave LATENCY cycles later. Octahedral encoding is
// scale-invariant, so nothing is normalised and no square root is taken.
//
// Stages: (1) unfold the snorm16 code to the octahedron point p (|p|1 = 32767, exact
// integers), 9 products sQ2.16 x int17 (DSP48E2 27x18 each, registered); (2) the sums w = M·p,
// the L1 norm l1 = |w|1 and the numerators (|x|, |y| on the upper hemisphere, |x| + |z|,
// |y| + |z| folded on the lower); (3) the rounded division q = floor((2s·a + l1) / (2·l1)),
// s = 2^(N_W-1) - 1, quotient bits N_W-2 .. H by restoring steps; (4) bits H-1 .. 0 and the
// sign (x < 0: negative; 0 counts as positive). l1 = 0 (a zero matrix) gives {0, 0}.
// II = 1.
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
    // The output register is the fourth; the testbench prints it (tb_normal.sv), and
    // tests/testbench_icarus.rs compares it with rtl_model units::normal::LATENCY_CYCLES.
    /* verilator lint_off UNUSEDPARAM */
    localparam LATENCY = 4;
    /* verilator lint_on UNUSEDPARAM */
    localparam QB = N_W - 1;                   // quotient bits: q <= s < 2^QB
    localparam H  = QB / 2;                    // bits decided in stage 4
    localparam LW = 35;                        // |w|1 < 3 * 2^16 * 32767 < 2^33; room to spare
    localparam NB = LW + N_W + 1;              // 2s·a + l1 < 2^N_W * l1
    localparam [NB-1:0] S2 = (1 << N_W) - 2;   // 2s

    // ---------------------------------------------------------------- stage 1
    wire signed [16:0] u_raw = $signed({in_oct[15], in_oct[15:0]});
    wire signed [16:0] v_raw = $signed({in_oct[31], in_oct[31:16]});
    wire signed [16:0] u = (u_raw < -17'sd32767) ? -17'sd32767 : u_raw;   // -32768 reads as -1
    wire signed [16:0] v = (v_raw < -17'sd32767) ? -17'sd32767 : v_raw;
    wire signed [16:0] au = u[16] ? -u : u;
    wire signed [16:0] av = v[16] ? -v : v;
    wire signed [16:0] z = 17'sd32767 - au - av;
    wire signed [16:0] fx = 17'sd32767 - av;   // the fold: sign(u)·(1 − |v|)
    wire signed [16:0] fy = 17'sd32767 - au;
    wire signed [16:0] p0 = z[16] ? (u[16] ? -fx : fx) : u;
    wire signed [16:0] p1 = z[16] ? (v[16] ? -fy : fy) : v;
    wire signed [16:0] p2 = z;

    // Operands sign-extended to the product's 35 bits (synthesis trims the copies of the sign).
    wire [3*35-1:0] p_ext = {{{18{p2[16]}}, p2}, {{18{p1[16]}}, p1}, {{18{p0[16]}}, p0}};
    reg signed [34:0] prod [0:8];
    reg v1;
    integer k;
    always @(posedge clk) begin
        v1 <= rst ? 1'b0 : in_valid;
        for (k = 0; k < 9; k = k + 1)
            prod[k] <= $signed({{17{in_mat[k*18+17]}}, in_mat[k*18 +: 18]})
                     * $signed(p_ext[(k % 3)*35 +: 35]);
    end
    function automatic signed [36:0] sx37(input signed [34:0] x);
        sx37 = {{2{x[34]}}, x};
    endfunction

    // ---------------------------------------------------------------- stage 2
    wire signed [36:0] wx = sx37(prod[0]) + sx37(prod[1]) + sx37(prod[2]);
    wire signed [36:0] wy = sx37(prod[3]) + sx37(prod[4]) + sx37(prod[5]);
    wire signed [36:0] wz = sx37(prod[6]) + sx37(prod[7]) + sx37(prod[8]);
    wire [36:0] ax = wx[36] ? -wx : wx;
    wire [36:0] ay = wy[36] ? -wy : wy;
    wire [36:0] az = wz[36] ? -wz : wz;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [36:0] l1_w = ax + ay + az;            // < 2^33
    wire [36:0] nu_w = wz[36] ? ax + az : ax;   // <= l1 < 2^LW
    wire [36:0] nv_w = wz[36] ? ay + az : ay;
    /* verilator lint_on UNUSEDSIGNAL */

    reg [LW-1:0] l1_2, nu_2, nv_2;
    reg sx_2, sy_2, v2;
    always @(posedge clk) begin
        v2   <= rst ? 1'b0 : v1;
        l1_2 <= l1_w[LW-1:0];
        nu_2 <= nu_w[LW-1:0];
        nv_2 <= nv_w[LW-1:0];
        sx_2 <= wx[36];
        sy_2 <= wy[36];
    end

    // ---------------------------------------------------------------- stages 3 and 4
    // Restoring division steps for quotient bits hi-1 .. lo of r / d: {remainder, bits}.
    function automatic [NB+QB-1:0] divide_steps(input [NB-1:0] r_in, input [NB-1:0] d,
                                                input integer hi, input integer lo);
        reg [NB-1:0] r, t;
        reg [QB-1:0] q;
        integer i;
        begin
            r = r_in;
            q = {QB{1'b0}};
            for (i = QB - 1; i >= 0; i = i - 1)
                if (i < hi && i >= lo) begin
                    t = d << i;
                    if (r >= t) begin
                        r = r - t;
                        q[i] = 1'b1;
                    end
                end
            divide_steps = {r, q};
        end
    endfunction

    wire [NB-1:0] d_2 = {{(NB-LW-1){1'b0}}, l1_2, 1'b0};
    wire [NB-1:0] n_u2 = S2 * {{(NB-LW){1'b0}}, nu_2} + {{(NB-LW){1'b0}}, l1_2};
    wire [NB-1:0] n_v2 = S2 * {{(NB-LW){1'b0}}, nv_2} + {{(NB-LW){1'b0}}, l1_2};
    wire [NB+QB-1:0] su3 = divide_steps(n_u2, d_2, QB, H);
    wire [NB+QB-1:0] sv3 = divide_steps(n_v2, d_2, QB, H);

    reg [NB-1:0] ru_3, rv_3, d_3;
    reg [QB-1:0] qu_3, qv_3;
    reg sx_3, sy_3, zero_3, v3;
    always @(posedge clk) begin
        v3     <= rst ? 1'b0 : v2;
        ru_3   <= su3[NB+QB-1:QB];
        rv_3   <= sv3[NB+QB-1:QB];
        qu_3   <= su3[QB-1:0];
        qv_3   <= sv3[QB-1:0];
        d_3    <= d_2;
        sx_3   <= sx_2;
        sy_3   <= sy_2;
        zero_3 <= l1_2 == {LW{1'b0}};
    end

    /* verilator lint_off UNUSEDSIGNAL */
    wire [NB+QB-1:0] su4 = divide_steps(ru_3, d_3, H, 0);
    wire [NB+QB-1:0] sv4 = divide_steps(rv_3, d_3, H, 0);
    /* verilator lint_on UNUSEDSIGNAL */
    wire [N_W-1:0] qu = {1'b0, qu_3 | su4[QB-1:0]};
    wire [N_W-1:0] qv = {1'b0, qv_3 | sv4[QB-1:0]};

    always @(posedge clk) begin
        out_valid <= rst ? 1'b0 : v3;
        out_code  <= zero_3 ? {(2*N_W){1'b0}}
                   : {sy_3 ? -qv : qv, sx_3 ? -qu : qu};
    end
endmodule
`default_nettype wire
