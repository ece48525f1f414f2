// svo_walker_pool_retire: the walker pool's retire order — which finished walks leave in a
// cycle, up to K (the walk-issue lanes), in the order they finished — as the cycle model's pool
// retires them (rtl_model/src/cycle/walker_pool.rs `retire`, its finished queue; called up to
// K times a cycle by src/models/cycle/stages/walkers.rs while walker_to_record takes pushes).
//
// Pipeline position: inside svo_walker_pool, between the walkers' finished contexts and
// walker_to_record; its retiring contexts count as free for the pool's dispatcher in the same
// cycle (the model retires before it dispatches).
//
// Contexts of different walkers are ordered by the model in one place only: this queue
// (finish order), where walks that finish in one cycle leave in that cycle's wake-up order —
// step latencies by walker, the dispatched walks in dispatch order (the lane that dispatched
// them, disp_lane), completions by request age (the node memory's id order, the pool's read
// ids). Each finished walk keeps a finish key {finish stamp (counts the cycles in which a walk
// finished), wake-up class, its read's id, its dispatch lane}; each walker's oldest finished
// walk (fin_head, from the walker's R x R age order in the pool) and at K = 2 its second oldest
// (fin_head2) carry their keys here. Lane 0 is the oldest of the W heads (a chain of W key
// compares); lane 1 the oldest of the other walkers' heads and lane 0's walker's second (a
// second chain). Stamps compare modulo 2^FS_W: the finish stamps of waiting walks span fewer
// than N values (FS_W = clog2(N) + 1 bits); ids as the pool says (modulo 2^ID_W).
// Lane j retires iff out_valid[j] && out_ready[j] (the sink takes a prefix; lane 1 only with
// lane 0).
`timescale 1ns/1ps
`default_nettype none
module svo_walker_pool_retire #(
    parameter WALKERS  = 1,
    parameter CONTEXTS = 1,
    parameter K        = 1,                      // walk-issue lanes: 1 or 2
    parameter ID_W     = 25                      // the pool's read ids
) (
    input  wire                          clk,
    input  wire                          rst,
    input  wire [WALKERS*CONTEXTS-1:0]   fin_head,   // per walker its oldest finished context
    input  wire [WALKERS*CONTEXTS-1:0]   fin_head2,  // and its second oldest (K = 2)
    input  wire [WALKERS*CONTEXTS-1:0]   fin_ev,     // finished in this cycle
    input  wire [WALKERS*CONTEXTS-1:0]   ev_lat,
    input  wire [WALKERS*CONTEXTS-1:0]   ev_disp,
    input  wire [WALKERS*CONTEXTS-1:0]   disp_lane,  // the lane that dispatched the context
    input  wire [WALKERS*CONTEXTS*ID_W-1:0] req_id,  // each context's last read's id
    input  wire [K-1:0]                  out_ready,
    output wire                          have1,      // a second finished walk (lane 1 valid)
    output wire [WALKERS*CONTEXTS-1:0]   retiring,   // the contexts retiring in this cycle
    output wire [K*(WALKERS > 1 ? $clog2(WALKERS) : 1)-1:0] lane_w,  // lane j's walker
    output wire [K-1:0]                  lane_second // lane j is its walker's second oldest
);
    localparam R = CONTEXTS;
    localparam W = WALKERS;
    localparam N = W * R;
    localparam WI = W > 1 ? $clog2(W) : 1;
    localparam FS_W = (N > 1 ? $clog2(N) : 1) + 1;

    generate
        if (K < 1 || K > 2) begin : bad_lanes
            svo_walker_pool_retire_builds_1_or_2_walk_lanes bad();
        end
    endgenerate

    function automatic id_before(input [ID_W-1:0] a, input [ID_W-1:0] b);
        reg [ID_W-1:0] d;
        begin
            d = a - b;
            id_before = d[ID_W-1];
        end
    endfunction
    function automatic [1:0] ev_class(input lat, input disp);
        ev_class = lat ? 2'd0 : disp ? 2'd1 : 2'd2;
    endfunction
    // Key a before key b: an earlier finish, or the same cycle and earlier in its wake-up
    // order (two step latencies: the lower walker first, which the chains' order gives).
    function automatic key_before(input [FS_W-1:0] a_s, input [1:0] ac, input [ID_W-1:0] ai,
                              input a_l, input [FS_W-1:0] b_s, input [1:0] bc,
                              input [ID_W-1:0] bi, input b_l);
        reg [FS_W-1:0] d;
        begin
            d = a_s - b_s;
            key_before = d[FS_W-1] || (d == {FS_W{1'b0}} && (ac < bc
                || (ac == 2'd2 && bc == 2'd2 && id_before(ai, bi))
                || (ac == 2'd1 && bc == 2'd1 && !a_l && b_l)));
        end
    endfunction

    reg [FS_W-1:0] fcount;
    reg [FS_W-1:0] fstamp [0:N-1];
    reg [1:0]      fcls   [0:N-1];
    genvar gn;
    generate
        for (gn = 0; gn < N; gn = gn + 1) begin : ctx
            always @(posedge clk)
                if (fin_ev[gn]) begin
                    fstamp[gn] <= fcount;
                    fcls[gn] <= ev_class(ev_lat[gn], ev_disp[gn]);
                end
        end
    endgenerate
    always @(posedge clk)
        if (rst) fcount <= {FS_W{1'b0}};
        else if (|fin_ev) fcount <= fcount + 1'b1;

    // Each walker's head keys (fin_head, fin_head2 one-hot: AND-OR, no priority chain).
    reg [W-1:0]    h_valid, h2_valid, h_lane, h2_lane;
    reg [FS_W-1:0] h_stamp [0:W-1];
    reg [FS_W-1:0] h2_stamp [0:W-1];
    reg [1:0]      h_cls [0:W-1];
    reg [1:0]      h2_cls [0:W-1];
    reg [ID_W-1:0] h_id [0:W-1];
    reg [ID_W-1:0] h2_id [0:W-1];
    integer w_h, k_h;
    /* verilator lint_off UNUSEDSIGNAL */
    integer n_h;                                  // a context index
    /* verilator lint_on UNUSEDSIGNAL */
    always @* begin
        for (w_h = 0; w_h < W; w_h = w_h + 1) begin
            h_valid[w_h] = |fin_head[w_h * R +: R];
            h2_valid[w_h] = K > 1 && |fin_head2[w_h * R +: R];
            h_stamp[w_h] = {FS_W{1'b0}};
            h2_stamp[w_h] = {FS_W{1'b0}};
            h_cls[w_h] = 2'd0;
            h2_cls[w_h] = 2'd0;
            h_id[w_h] = {ID_W{1'b0}};
            h2_id[w_h] = {ID_W{1'b0}};
            h_lane[w_h] = 1'b0;
            h2_lane[w_h] = 1'b0;
            for (k_h = 0; k_h < R; k_h = k_h + 1) begin
                n_h = w_h * R + k_h;
                h_stamp[w_h] = h_stamp[w_h]
                    | ({FS_W{fin_head[n_h]}} & (fin_ev[n_h] ? fcount : fstamp[n_h]));
                h_cls[w_h] = h_cls[w_h] | ({2{fin_head[n_h]}}
                    & (fin_ev[n_h] ? ev_class(ev_lat[n_h], ev_disp[n_h]) : fcls[n_h]));
                h_id[w_h] = h_id[w_h] | ({ID_W{fin_head[n_h]}} & req_id[n_h * ID_W +: ID_W]);
                h_lane[w_h] = h_lane[w_h] | (fin_head[n_h] & disp_lane[n_h]);
                h2_stamp[w_h] = h2_stamp[w_h]
                    | ({FS_W{fin_head2[n_h]}} & (fin_ev[n_h] ? fcount : fstamp[n_h]));
                h2_cls[w_h] = h2_cls[w_h] | ({2{fin_head2[n_h]}}
                    & (fin_ev[n_h] ? ev_class(ev_lat[n_h], ev_disp[n_h]) : fcls[n_h]));
                h2_id[w_h] = h2_id[w_h] | ({ID_W{fin_head2[n_h]}} & req_id[n_h * ID_W +: ID_W]);
                h2_lane[w_h] = h2_lane[w_h] | (fin_head2[n_h] & disp_lane[n_h]);
            end
        end
    end

    // Lane 0: the oldest of the W heads. Lane 1: the oldest of the other walkers' heads and
    // lane 0's walker's second.
    reg [WI-1:0] fin_w0, fin_w1;
    reg          have0, have1_r, c_valid, c_lane;
    reg [FS_W-1:0] c_stamp;
    reg [1:0]      c_cls;
    reg [ID_W-1:0] c_id;
    reg [FS_W-1:0] b_stamp;
    reg [1:0]      b_cls;
    reg [ID_W-1:0] b_id;
    reg            b_lane, second;
    integer w_c;
    always @* begin
        fin_w0 = {WI{1'b0}};
        have0 = 1'b0;
        for (w_c = 0; w_c < W; w_c = w_c + 1)
            if (h_valid[w_c] && (!have0 || key_before(h_stamp[w_c], h_cls[w_c], h_id[w_c],
                    h_lane[w_c], h_stamp[fin_w0], h_cls[fin_w0], h_id[fin_w0], h_lane[fin_w0])))
            begin
                fin_w0 = w_c[WI-1:0];
                have0 = 1'b1;
            end
        fin_w1 = {WI{1'b0}};
        have1_r = 1'b0;
        second = 1'b0;
        b_stamp = {FS_W{1'b0}};
        b_cls = 2'd0;
        b_id = {ID_W{1'b0}};
        b_lane = 1'b0;
        for (w_c = 0; w_c < W; w_c = w_c + 1) begin
            if (w_c[WI-1:0] == fin_w0) begin
                c_valid = h2_valid[w_c];
                c_stamp = h2_stamp[w_c];
                c_cls = h2_cls[w_c];
                c_id = h2_id[w_c];
                c_lane = h2_lane[w_c];
            end else begin
                c_valid = h_valid[w_c];
                c_stamp = h_stamp[w_c];
                c_cls = h_cls[w_c];
                c_id = h_id[w_c];
                c_lane = h_lane[w_c];
            end
            if (K > 1 && c_valid
                    && (!have1_r || key_before(c_stamp, c_cls, c_id, c_lane, b_stamp, b_cls, b_id, b_lane)))
            begin
                fin_w1 = w_c[WI-1:0];
                have1_r = 1'b1;
                second = w_c[WI-1:0] == fin_w0;
                b_stamp = c_stamp;
                b_cls = c_cls;
                b_id = c_id;
                b_lane = c_lane;
            end
        end
    end
    assign have1 = have1_r;

    reg [N-1:0] pick0;
    /* verilator lint_off UNUSEDSIGNAL */
    reg [N-1:0] pick1;                            // (unused at K = 1)
    /* verilator lint_on UNUSEDSIGNAL */
    integer w_p;
    always @* begin
        for (w_p = 0; w_p < W; w_p = w_p + 1) begin
            pick0[w_p * R +: R] = have0 && fin_w0 == w_p[WI-1:0] ? fin_head[w_p * R +: R]
                                                               : {R{1'b0}};
            pick1[w_p * R +: R] = !have1_r || fin_w1 != w_p[WI-1:0] ? {R{1'b0}}
                : second ? fin_head2[w_p * R +: R] : fin_head[w_p * R +: R];
        end
    end
    assign lane_w[0 +: WI] = fin_w0;
    assign lane_second[0] = 1'b0;
    generate
        if (K > 1) begin : lane1
            assign retiring = (out_ready[0] ? pick0 : {N{1'b0}})
                            | (out_ready[0] && out_ready[1] ? pick1 : {N{1'b0}});
            assign lane_w[WI +: WI] = fin_w1;
            assign lane_second[1] = second;
        end else begin : one_lane
            assign retiring = out_ready[0] ? pick0 : {N{1'b0}};
        end
    endgenerate
endmodule
`default_nettype wire
