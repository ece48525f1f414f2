// svo_walker_pool_dispatch: the walker pool's dispatcher — which context takes each of the
// cycle's K walks (K walk-issue lanes, HwConfig::walk_lanes) — as the cycle model's pool
// dispatches (rtl_model/src/cycle/walker_pool.rs `dispatch_with`, called once a lane by
// src/models/cycle/stages/walkers.rs after the cycle's retires).
//
// Pipeline position: inside svo_walker_pool, between root_to_dispatch (the walks offered, a
// prefix of K lanes) and the walkers' take ports; after the pool's retire pick, whose
// retiring contexts count as free in the same cycle.
//
// The rule, per cycle: lane 0's walk goes to the walker with the most free contexts (idle, or
// retiring in this cycle), the lowest index on ties; lane 1's to the walker with the most free
// contexts after lane 0's (its walker counts one fewer), so both can go to one walker. Within
// the walker a lane takes its lowest idle context, else its lowest retiring one (which free
// context takes it changes no cycle: the pool's age orders rank contexts by events, not by
// index). The pool keeps "idle" itself (busy: taken, not retired), from flip-flops, so the
// retire does not run through the free contexts' carry chain into the take.
// in_ready is a prefix (lane 1 is ready when a second context is free); lane j is taken iff
// in_valid[j] && in_ready[j].
`timescale 1ns/1ps
`default_nettype none
module svo_walker_pool_dispatch #(
    parameter WALKERS  = 1,
    parameter CONTEXTS = 1,
    parameter K        = 1                       // walk-issue lanes: 1 or 2
) (
    input  wire                            clk,
    input  wire                            rst,
    input  wire [K-1:0]                    in_valid,
    output wire [K-1:0]                    in_ready,
    input  wire [WALKERS*CONTEXTS-1:0]     retiring,  // contexts retiring in this cycle
    output wire [K*WALKERS*CONTEXTS-1:0]   take,      // lane j's context: [j*N +: N], one-hot or 0
    output reg  [WALKERS*CONTEXTS-1:0]     busy       // taken and not retired
);
    localparam R = CONTEXTS;
    localparam W = WALKERS;
    localparam N = W * R;
    localparam WI = W > 1 ? $clog2(W) : 1;

    generate
        if (K < 1 || K > 2) begin : bad_lanes
            svo_walker_pool_dispatch_builds_1_or_2_walk_lanes bad();
        end
    endgenerate

    function automatic [R-1:0] lowest(input [R-1:0] m);  // m & -m
        lowest = m & (~m + 1'b1);
    endfunction
    function automatic [5:0] count(input [R-1:0] m);
        integer c;
        begin
            count = 6'd0;
            for (c = 0; c < R; c = c + 1) count = count + {5'd0, m[c]};
        end
    endfunction

    // Lane 0: the walker with the most free contexts (a context retiring now counts).
    reg [N-1:0] pick0;
    /* verilator lint_off UNUSEDSIGNAL */
    reg [N-1:0] pick1;                            // (unused at K = 1)
    /* verilator lint_on UNUSEDSIGNAL */
    reg [5:0]   nfree [0:W-1];
    reg [5:0]   best_n;
    reg [WI-1:0] best0, best1;
    reg [R-1:0] t_idle, t_ret;
    integer w_d;
    always @* begin
        best0 = {WI{1'b0}};
        best_n = 6'd0;
        for (w_d = 0; w_d < W; w_d = w_d + 1) begin
            // (at K = 1 at most one context of the pool retires: its walker's OR)
            nfree[w_d] = count(~busy[w_d * R +: R])
                + (K > 1 ? count(retiring[w_d * R +: R]) : {5'd0, |retiring[w_d * R +: R]});
            if (nfree[w_d] > best_n) begin
                best_n = nfree[w_d];
                best0 = w_d[WI-1:0];
            end
        end
        // Per walker its lowest idle context, or its lowest retiring one, kept for the best.
        for (w_d = 0; w_d < W; w_d = w_d + 1) begin
            t_idle = ~busy[w_d * R +: R];
            t_ret = retiring[w_d * R +: R];
            pick0[w_d * R +: R] = w_d[WI-1:0] != best0 ? {R{1'b0}}
                : |t_idle ? lowest(t_idle) : lowest(t_ret);
        end
        // Lane 1: the same after lane 0's pick (its walker has one free context fewer).
        best1 = {WI{1'b0}};
        best_n = 6'd0;
        for (w_d = 0; w_d < W; w_d = w_d + 1)
            if (nfree[w_d] - {5'd0, |pick0[w_d * R +: R]} > best_n) begin
                best_n = nfree[w_d] - {5'd0, |pick0[w_d * R +: R]};
                best1 = w_d[WI-1:0];
            end
        for (w_d = 0; w_d < W; w_d = w_d + 1) begin
            t_idle = ~busy[w_d * R +: R] & ~pick0[w_d * R +: R];
            t_ret = retiring[w_d * R +: R] & ~pick0[w_d * R +: R];
            pick1[w_d * R +: R] = K < 2 || w_d[WI-1:0] != best1 ? {R{1'b0}}
                : |t_idle ? lowest(t_idle) : lowest(t_ret);
        end
    end

    wire [N-1:0] free = ~busy | retiring;
    wire [N-1:0] take0 = in_valid[0] ? pick0 : {N{1'b0}};
    assign in_ready[0] = |free;
    assign take[0 +: N] = take0;
    wire [N-1:0] e_take;
    generate
        if (K > 1) begin : lane1
            wire [N-1:0] take1 = in_valid[1] ? pick1 : {N{1'b0}};
            assign in_ready[1] = |(free & ~pick0);
            assign take[N +: N] = take1;
            assign e_take = take0 | take1;
        end else begin : one_lane
            assign e_take = take0;
        end
    endgenerate
    always @(posedge clk) busy <= rst ? {N{1'b0}} : (busy & ~retiring) | e_take;
endmodule
`default_nettype wire
