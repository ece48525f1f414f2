// svo_unit_lanes: the back-pressure and order around K identical fixed-latency units side by
// side, as the cycle model's unit lanes (rtl_model/src/cycle/unit_lanes.rs): up to K
// transactions enter a cycle, each into the first lane that can take it, and the ready
// results leave oldest first, ties in lane order, up to K a cycle.
//
// Pipeline position: around the k transforms, the k walk lanes of three reciprocals and the k
// walker roots of a k-wide walk section (docs/cycle-model.md §2.1, "Walk issue of width k"),
// between two svo_fifo_wide joints; svo_elastic is the same at K = 1. The units are outside
// this module, as svo_elastic's: lane l's unit takes lane_take[l] with the offered item
// lane_src[l] (the caller's multiplexer) and brings its registered result back on
// unit_valid[l] / unit_data[l], L cycles later.
//
// Per cycle, as the model's stage (results handed on first, then the inputs):
// - out: the results in the order they became ready — first those waiting in the result queue
//   (one queue for all lanes, in ready order), then this cycle's new results in lane order —
//   shown on out port j for the j-th; the consumer takes a prefix (out_ready, a wide FIFO's
//   registered ready). With II 1 a lane's results become ready one a cycle in its accept
//   order, so the order of becoming ready with same-cycle ties in lane order is the model's
//   "oldest ready head first, ties lowest lane" merge of the lanes.
// - in: lane l can take a transaction while fewer than L of its own are in flight or waiting
//   after this cycle's leaves (the model's pipe capacity, ceil(L / II) at II 1); the offered
//   items (a prefix, in_valid) go in order to the lanes that can, lowest lane first, one a
//   lane. in_ready[j]: at least j + 1 lanes can take one. It depends combinationally on
//   out_ready, as svo_elastic's in_ready does.
`timescale 1ns/1ps
`default_nettype none
module svo_unit_lanes #(
    parameter K  = 2,                             // lanes (units)
    parameter L  = 4,                             // a unit's latency = a lane's capacity
    parameter W  = 32,
    parameter SW = K > 1 ? $clog2(K) : 1          // a lane's source index (do not set)
) (
    input  wire           clk,
    input  wire           rst,
    input  wire [K-1:0]   in_valid,               // a prefix
    output wire [K-1:0]   in_ready,
    output reg  [K-1:0]   lane_take,              // unit l takes an item this cycle ...
    output reg  [K*SW-1:0] lane_src,              // ... the offered item lane_src[l]
    input  wire [K-1:0]   unit_valid,
    input  wire [K*W-1:0] unit_data,
    output reg  [K-1:0]   out_valid,
    input  wire [K-1:0]   out_ready,              // taken as a prefix of the valid ports
    output reg  [K*W-1:0] out_data
);
    localparam QD = K * L;                        // every lane full and waiting
    localparam QA = QD > 1 ? $clog2(QD) : 1;
    localparam QN = $clog2(QD + 1);
    localparam CN = $clog2(L + 1);
    localparam LW = K > 1 ? $clog2(K) : 1;
    localparam integer QD_I = QD;
    localparam integer L_I = L;

    generate
        if (L < 1 || K < 1 || K > 8) begin : bad_lanes
            svo_unit_lanes_needs_L_at_least_1_and_K_1_to_8 bad();
        end
    endgenerate

    function automatic [QA-1:0] wrap(input [QA-1:0] a, input integer j);
        integer s;
        begin
            s = {{(32 - QA){1'b0}}, a} + j;
            if (s >= QD_I) s = s - QD_I;
            wrap = s[QA-1:0];
        end
    endfunction

    reg [W-1:0]  q_data [0:QD-1];                 // results waiting, in ready order
    reg [LW-1:0] q_lane [0:QD-1];                 // ... and the lane each came from
    reg [QA-1:0] rd, wr;
    reg [QN-1:0] qn;                              // results waiting
    reg [CN-1:0] n [0:K-1];                       // lane l: in flight + waiting

    // This cycle's stream: the queue, then the new results in lane order.
    integer j, l, t, qn_i, c, new_taken, taken_q;
    /* verilator lint_off UNUSEDSIGNAL */
    integer qn_sum, n_sum;                        // 32-bit sums: their low bits are the counts
    /* verilator lint_on UNUSEDSIGNAL */
    reg [LW-1:0] o_lane [0:K-1];                  // the lane of out port j's result
    reg [K-1:0]  taken;                           // out port j's result leaves
    reg          on;
    integer rank_new [0:K-1];                     // lane l's place among the new results
    integer leave [0:K-1];
    reg [K-1:0]  free;
    integer nf;
    reg [QN-1:0] qn_nx;                           // the next cycle's counts
    reg [CN-1:0] n_nx [0:K-1];
    always @* begin
        qn_i = {{(32 - QN){1'b0}}, qn};
        t = 0;
        for (l = 0; l < K; l = l + 1) begin
            rank_new[l] = t;
            if (unit_valid[l]) t = t + 1;
        end
        for (j = 0; j < K; j = j + 1) begin
            out_valid[j] = 1'b0;
            out_data[j*W +: W] = {W{1'b0}};
            o_lane[j] = {LW{1'b0}};
            if (j < qn_i) begin
                out_valid[j] = 1'b1;
                out_data[j*W +: W] = q_data[wrap(rd, j)];
                o_lane[j] = q_lane[wrap(rd, j)];
            end else begin
                for (l = 0; l < K; l = l + 1)
                    if (unit_valid[l] && rank_new[l] == j - qn_i) begin
                        out_valid[j] = 1'b1;
                        out_data[j*W +: W] = unit_data[l*W +: W];
                        o_lane[j] = l[LW-1:0];
                    end
            end
        end
        on = 1'b1;
        c = 0;
        for (j = 0; j < K; j = j + 1) begin
            taken[j] = on && out_valid[j] && out_ready[j];
            on = taken[j];
            if (taken[j]) c = c + 1;
        end
        new_taken = c > qn_i ? c - qn_i : 0;
        for (l = 0; l < K; l = l + 1) begin
            leave[l] = 0;
            for (j = 0; j < K; j = j + 1)
                if (taken[j] && o_lane[j] == l[LW-1:0]) leave[l] = leave[l] + 1;
            free[l] = {{(32 - CN){1'b0}}, n[l]} - leave[l] < L_I;
        end
        // The offered items, in order, to the lanes that can take one, lowest first.
        nf = 0;
        for (l = 0; l < K; l = l + 1) begin
            lane_take[l] = 1'b0;
            lane_src[l*SW +: SW] = {SW{1'b0}};
            if (free[l]) begin
                lane_take[l] = in_valid[nf];
                lane_src[l*SW +: SW] = nf[SW-1:0];
                nf = nf + 1;
            end
        end
        taken_q = c < qn_i ? c : qn_i;
        qn_sum = qn_i + (t - new_taken) - taken_q;
        qn_nx = qn_sum[QN-1:0];
        for (l = 0; l < K; l = l + 1) begin
            n_sum = {{(32 - CN){1'b0}}, n[l]} + (lane_take[l] ? 1 : 0) - leave[l];
            n_nx[l] = n_sum[CN-1:0];
        end
    end
    genvar g;
    generate
        for (g = 0; g < K; g = g + 1) begin : port
            assign in_ready[g] = nf > g;
        end
    endgenerate
    // Taking an item needs every item before it taken (the caller's prefix); lane_take says
    // which lanes do.
    integer p;
    always @(posedge clk) begin
        // New results that did not leave join the queue behind the waiting ones.
        for (p = 0; p < K; p = p + 1)
            if (unit_valid[p] && rank_new[p] >= new_taken) begin
                q_data[wrap(wr, rank_new[p] - new_taken)] <= unit_data[p*W +: W];
                q_lane[wrap(wr, rank_new[p] - new_taken)] <= p[LW-1:0];
            end
        if (rst) begin
            rd <= {QA{1'b0}};
            wr <= {QA{1'b0}};
            qn <= {QN{1'b0}};
            for (p = 0; p < K; p = p + 1) n[p] <= {CN{1'b0}};
        end else begin
            rd <= wrap(rd, taken_q);
            wr <= wrap(wr, t - new_taken);
            qn <= qn_nx;
            for (p = 0; p < K; p = p + 1) n[p] <= n_nx[p];
        end
    end
endmodule
`default_nettype wire
