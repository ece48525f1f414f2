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
// integers), 9 products sQ2.16 x int17 (DSP48E2 27x18 each, registered); (2) the sums
// w = M·p; (3) the L1 norm l1 = |w|1 and the numerators (|x|, |y| on the upper hemisphere,
// |x| + |z|, |y| + |z| folded on the lower); (4) l1 and both numerators shifted right together
// (truncating) until l1 has at most DB bits (units::normal::DIV_BITS); (5) the rounded
// division q = floor((2s·a + l1) / (2·l1)), s = 2^(N_W-1) - 1, quotient bits N_W-2 .. H by
// restoring steps; (6) bits H-1 .. 0 and the sign (x < 0: negative; 0 counts as positive).
// l1 = 0 (a zero matrix) gives {0, 0}. II = 1.
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
    // The output register is the sixth; the testbench prints it (tb_normal.sv), and
    // tests/testbench_icarus.rs compares it with rtl_model units::normal::LATENCY_CYCLES.
    /* verilator lint_off UNUSEDPARAM */
    localparam LATENCY = 6;
    /* verilator lint_on UNUSEDPARAM */
    localparam QB = N_W - 1;                   // quotient bits: q <= s < 2^QB
    localparam H  = QB / 2;                    // bits decided in stage 4
    localparam LW = 35;                        // |w|1 < 3 * 2^16 * 32767 < 2^33; room to spare
    localparam DB = 18;                        // divisor bits kept (units::normal::DIV_BITS)
    localparam NB = DB + N_W + 1;              // 2s·a + l1 < 2^N_W * l1

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
    reg signed [36:0] wx, wy, wz;
    reg v2;
    always @(posedge clk) begin
        v2 <= rst ? 1'b0 : v1;
        wx <= sx37(prod[0]) + sx37(prod[1]) + sx37(prod[2]);
        wy <= sx37(prod[3]) + sx37(prod[4]) + sx37(prod[5]);
        wz <= sx37(prod[6]) + sx37(prod[7]) + sx37(prod[8]);
    end

    // ---------------------------------------------------------------- stage 3
    wire [36:0] ax = wx[36] ? -wx : wx;
    wire [36:0] ay = wy[36] ? -wy : wy;
    wire [36:0] az = wz[36] ? -wz : wz;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [36:0] l1_w = ax + ay + az;            // < 2^33
    wire [36:0] nu_w = wz[36] ? ax + az : ax;   // <= l1
    wire [36:0] nv_w = wz[36] ? ay + az : ay;
    /* verilator lint_on UNUSEDSIGNAL */
    reg [LW-1:0] l1_3, nu_3, nv_3;
    reg sx_3, sy_3, v3;
    always @(posedge clk) begin
        v3   <= rst ? 1'b0 : v2;
        l1_3 <= l1_w[LW-1:0];
        nu_3 <= nu_w[LW-1:0];
        nv_3 <= nv_w[LW-1:0];
        sx_3 <= wx[36];
        sy_3 <= wy[36];
    end

    // ---------------------------------------------------------------- stage 4
    // The shift: l1's bit length above DB (units::normal::normalise_shift).
    function automatic [5:0] shift_of(input [LW-1:0] x);
        integer i;
        begin
            shift_of = 6'd0;
            for (i = DB; i < LW; i = i + 1)
                if (x[i]) shift_of = i[5:0] - DB[5:0] + 6'd1;
        end
    endfunction
    wire [5:0] sh = shift_of(l1_3);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [LW-1:0] l1_s = l1_3 >> sh;
    wire [LW-1:0] nu_s = nu_3 >> sh;
    wire [LW-1:0] nv_s = nv_3 >> sh;
    /* verilator lint_on UNUSEDSIGNAL */
    reg [DB-1:0] l1_4, nu_4, nv_4;
    reg sx_4, sy_4, v4;
    always @(posedge clk) begin
        v4   <= rst ? 1'b0 : v3;
        l1_4 <= l1_s[DB-1:0];
        nu_4 <= nu_s[DB-1:0];
        nv_4 <= nv_s[DB-1:0];
        sx_4 <= sx_3;
        sy_4 <= sy_3;
    end

    // ---------------------------------------------------------------- stages 5 and 6
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

    // 2s·a = a·2^N_W − 2a: shifts and one subtractor, no multiplier.
    function automatic [NB-1:0] numerator(input [DB-1:0] a, input [DB-1:0] l1);
        numerator = ({{(NB-DB){1'b0}}, a} << N_W) - ({{(NB-DB){1'b0}}, a} << 1)
                  + {{(NB-DB){1'b0}}, l1};
    endfunction
    wire [NB-1:0] d_4 = {{(NB-DB-1){1'b0}}, l1_4, 1'b0};
    wire [NB+QB-1:0] su5 = divide_steps(numerator(nu_4, l1_4), d_4, QB, H);
    wire [NB+QB-1:0] sv5 = divide_steps(numerator(nv_4, l1_4), d_4, QB, H);

    reg [NB-1:0] ru_5, rv_5, d_5;
    reg [QB-1:0] qu_5, qv_5;
    reg sx_5, sy_5, zero_5, v5;
    always @(posedge clk) begin
        v5     <= rst ? 1'b0 : v4;
        ru_5   <= su5[NB+QB-1:QB];
        rv_5   <= sv5[NB+QB-1:QB];
        qu_5   <= su5[QB-1:0];
        qv_5   <= sv5[QB-1:0];
        d_5    <= d_4;
        sx_5   <= sx_4;
        sy_5   <= sy_4;
        zero_5 <= l1_4 == {DB{1'b0}};
    end

    /* verilator lint_off UNUSEDSIGNAL */
    wire [NB+QB-1:0] su6 = divide_steps(ru_5, d_5, H, 0);
    wire [NB+QB-1:0] sv6 = divide_steps(rv_5, d_5, H, 0);
    /* verilator lint_on UNUSEDSIGNAL */
    wire [N_W-1:0] qu = {1'b0, qu_5 | su6[QB-1:0]};
    wire [N_W-1:0] qv = {1'b0, qv_5 | sv6[QB-1:0]};

    always @(posedge clk) begin
        out_valid <= rst ? 1'b0 : v5;
        out_code  <= zero_5 ? {(2*N_W){1'b0}}
                   : {sy_5 ? -qv : qv, sx_5 ? -qu : qu};
    end
endmodule
`default_nettype wire
