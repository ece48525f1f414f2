// svo_sqrt: square root by the restoring radix-2 digit recurrence, one root bit per pipeline
// stage (rtl_model/src/units/sqrt.rs, docs/units/sqrt.md).
//
// Pipeline position: inside the sphere test (svo_sphere.v), where the entry distance needs
// sqrt(T - p^2). Default format: radicand uQ16.48 (N = 64 bits), root uQ8.24 (N/2 = 32 bits),
// truncated: the alignment shift is 0, so the root of the code is the root of the value.
//
// Stage k brings down the next radicand bit pair and decides one root bit:
//   S = 4*P + pair (the shifted remainder), T = 4*R + 1 (the trial);
//   S >= T: R = 2R + 1, P = S - T;  else R = 2R, P = S (restore: a multiplexer).
// P <= 2R < 2^k after stage k, so N/2 + 2 bits hold every S. Latency N/2 cycles (one register
// per stage), one radicand per cycle (II = 1), no multiplier.
`timescale 1ns/1ps
`default_nettype none
module svo_sqrt #(
    parameter N = 64
) (
    input  wire           clk,
    input  wire           rst,
    input  wire           in_valid,
    input  wire [N-1:0]   in_x,
    output wire           out_valid,
    output wire [N/2-1:0] out_root
);
    localparam S  = N / 2;       // stages = root bits = latency
    localparam RW = S + 2;       // shifted remainder and trial width
    // One stage per root bit; the testbench prints it (tb_*.sv: "rtl LATENCY"), tests/testbench_icarus.rs
    // compares it with the model's units.* latency and with the latency measured.
    /* verilator lint_off UNUSEDPARAM */
    localparam LATENCY = S;
    /* verilator lint_on UNUSEDPARAM */

    genvar k;
    generate
        for (k = 1; k <= S; k = k + 1) begin : st
            wire [S-1:0]  root_p;
            // Lint waiver: the top two bits of rem_p are never read (always 0, see below).
            /* verilator lint_off UNUSEDSIGNAL */
            wire [RW-1:0] rem_p;
            /* verilator lint_on UNUSEDSIGNAL */
            wire [N-1:0]  x_p;
            wire          v_p;
            if (k == 1) begin : first
                assign root_p = {S{1'b0}};
                assign rem_p  = {RW{1'b0}};
                assign x_p    = in_x;
                assign v_p    = in_valid;
            end else begin : next
                assign root_p = st[k-1].root_q;
                assign rem_p  = st[k-1].rem_q;
                assign x_p    = st[k-1].x_q;
                assign v_p    = st[k-1].v_q;
            end
            // The top two bits of rem_p are 0 (P < 2^(k-1) before this stage).
            wire [RW-1:0] shifted = {rem_p[RW-3:0], x_p[N-1:N-2]};
            wire [RW-1:0] trial   = {root_p, 2'b01};
            wire          ge      = shifted >= trial;
            reg  [S-1:0]  root_q;
            // Lint waiver: the last stage's remainder and radicand are not read (only its root
            // is); one generate body for every stage keeps the recurrence in one place, and
            // synthesis removes the unread registers.
            /* verilator lint_off UNUSEDSIGNAL */
            reg  [RW-1:0] rem_q;
            reg  [N-1:0]  x_q;
            /* verilator lint_on UNUSEDSIGNAL */
            reg           v_q;
            always @(posedge clk) begin
                v_q    <= rst ? 1'b0 : v_p;
                root_q <= {root_p[S-2:0], ge};
                rem_q  <= ge ? shifted - trial : shifted;
                x_q    <= {x_p[N-3:0], 2'b00};
            end
        end
    endgenerate

    assign out_root  = st[S].root_q;
    assign out_valid = st[S].v_q;
endmodule
`default_nettype wire
