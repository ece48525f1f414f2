// svo_walker_barrel: one octree walker of CONTEXTS ray contexts (a barrel walker): ONE step
// datapath, the contexts' state in RAMs indexed by context, each context's walk the
// single-context walker's (svo_walker.v) cycle for cycle, as the cycle model's walker pool times
// a walker of R contexts (rtl_model/src/cycle/walker_pool.rs, §2.3 of docs/cycle-model.md).
//
// Pipeline position: inside svo_walker_pool, one per walker when contexts_per_walker > 1
// (at R = 1 the pool keeps svo_walker, whose registers are the one context: the estimate's
// calibration, rtl_model/src/cost/structures.rs `walker_contexts`, adds nothing at R = 1). The
// pool's scheduler grants the issue slot (one context a cycle), the request port and the retire;
// this module is what each context does with them.
//
// What is where (per walker; W walkers = W copies of this module):
//   context RAMs (LUT-RAM: each array written at one point, read asynchronously):
//     wram  the walk's constants and root, written when a walk is taken: zero axes, mirror mask,
//           attribute base, tag, the root's t0/t1 and midpoints, origin and half extent;
//     fram  the top frame, written at the end of stage A (issue + 2): t0, t1, midpoints,
//           zero-axis g and d, address, descriptor, level, coordinates;
//     cram  the child in flight, written at the end of stage B of a step (not a pop): its t0, t1,
//           midpoints, g, coordinates, level;
//     nram  written at the end of stage B (issue + 3): next child, step count, the hit's t and
//           voxel, the far-escape address;
//   stack RAM (block RAM: one synchronous port, depth CONTEXTS x (STACK_DEPTH - 1)): frames
//     below each context's top, written by a descriptor's push in the apply cycle (issue + 1),
//     read for a pop in the same cycle (its data in stage A);
//   per context registers (the sequencer, a few bits of each context beside the RAMs): state,
//     pending read, hold count, stack pointer, the request address, the outcome, the chaining
//     bases (the far-escape address and the attribute base, each with an adder for the word
//     that chains a read in the cycle it arrives), and one 64-bit
//     word for the arrived descriptor (until it is applied) or the attribute record (until the
//     walk retires; several records can arrive in one cycle when reads merge).
// The step (four stages, so STEP_LATENCY >= 4; svo_walker.v, one context, does it in three):
//   X      the issue: the pool's scheduler grants the context (issue_grant, late in the cycle);
//          only the selection is done: the context's index (an encoding of the one-hot grant),
//          its wram and cram words and two flags (apply, root) registered;
//   X + 1  apply (fram and nram read here by the registered index): a descriptor that arrived
//          (the word in r_data) is applied: the child becomes the top frame, its first child
//          found from its midpoints (in cram, or wram for the root), the parent pushed;
//          otherwise the stored top frame and next child pass. The stack is read for a pop.
//          Into stage A's registers;
//   X + 2  stage A (svo_walker.v's S_COMP), the top frame written back into fram;
//   X + 3  stage B (its first S_HOLD cycle), written back into nram; the step's child and its
//          midpoints (computed here from stage A's registers) into cram. STEP_LATENCY - 4 hold
//          cycles follow.
// At most one context is in each stage (one issue a cycle), so one datapath serves all
// contexts; a context's next issue is at X + STEP_LATENCY >= X + 4, after its write-back. The
// cycles each context sees are svo_walker.v's at the same STEP_LATENCY (the model's
// walker_pool.step_latency_cycles): the apply stage and stage B's midpoints only move work the
// single-context walker does in its registers (its c_tm, c_first) into the step.
// Why the apply stage: with the apply in the issue cycle (the step in three stages) the
// selection (the grant, the LUT-RAM reads by the granted index) and the midpoints' 63-bit
// adds and their comparisons were one path, 28 levels at CONTEXTS = 16 by the clock rule
// (149 MHz); see testbench/README for the figures now.
//
// Responses: any of the walker's contexts in a cycle. A node or leaf word chains a request in
// the cycle it arrives (its own adder, chain_addr); when several arrive together (issue 29:
// svo_top's store and cache answering in one cycle, two reads completing on one fill, a bank
// port that made the earlier of two reads wait) each context requests, the pool's port takes
// one and the others wait in S_REQ with their chained address: the model's send queue
// (walker_pool.rs, "Request ports"), oldest by the wake-up order the pool keeps. Attribute
// records may arrive several a cycle (merged reads).
`timescale 1ns/1ps
`default_nettype none
module svo_walker_barrel #(
    parameter POS_W        = 40,
    parameter T_W          = 62,
    parameter STACK_DEPTH  = 21,
    parameter MAX_STEPS    = 100000,
    parameter STEP_LATENCY = 4,
    parameter TAG_W        = 1,
    parameter CONTEXTS     = 2,
    parameter RI           = CONTEXTS > 1 ? $clog2(CONTEXTS) : 1,  // context index bits
    parameter K            = 1    // take and result ports (the pool's walk lanes): 1 or 2
) (
    input  wire                    clk,
    input  wire                    rst,
    // K take ports (lane j's fields at [j*WIDTH +: WIDTH]): lane j's walk is taken by the
    // context whose bit of in_take[j*CONTEXTS +: CONTEXTS] is set (the pool's dispatcher; the
    // lanes take different contexts).
    input  wire [K*CONTEXTS-1:0]     in_take,
    output wire [CONTEXTS-1:0]       in_ready,
    input  wire [K-1:0]              in_enter,
    input  wire [K*3*(T_W+1)-1:0]    in_t0,
    input  wire [K*3*(T_W+1)-1:0]    in_t1,
    input  wire [K*3*(POS_W+1)-1:0]  in_o,
    input  wire [K*3*POS_W-1:0]      in_half,
    input  wire [K*3-1:0]            in_zero,
    input  wire [K*3-1:0]            in_neg,
    input  wire [K*32-1:0]           in_node_base,
    input  wire [K*32-1:0]           in_attr_base,
    input  wire [K*TAG_W-1:0]        in_tag,
    // Per context, as svo_walker's ports of the same names.
    output wire [CONTEXTS-1:0]     mem_req_valid,
    input  wire [CONTEXTS-1:0]     mem_req_ready,
    output wire [CONTEXTS-1:0]     mem_req_attr,
    output wire [CONTEXTS*32-1:0]  mem_req_addr,
    input  wire [CONTEXTS-1:0]     mem_resp_valid,
    input  wire [CONTEXTS*64-1:0]  mem_resp_data,
    output wire [CONTEXTS-1:0]     out_valid,
    input  wire [CONTEXTS-1:0]     out_ready,
    input  wire [CONTEXTS-1:0]     issue_grant,
    output wire [CONTEXTS-1:0]     issue_req,
    output reg  [CONTEXTS-1:0]     ev_lat,
    output reg  [CONTEXTS-1:0]     ev_disp,
    output wire [CONTEXTS-1:0]     ev_resp,
    // K result ports: port j the result of context fin[j*RI +: RI] (the pool's retire picks).
    input  wire [K*RI-1:0]         fin,
    output wire [K*2-1:0]          out_outcome,
    output wire [K*T_W-1:0]        out_t,
    output wire [K*60-1:0]         out_voxel,
    output wire [K*64-1:0]         out_attr_data,
    output wire [K*TAG_W-1:0]      out_tag
);
    localparam R = CONTEXTS;
    localparam TI = T_W + 1;
    localparam signed [TI-1:0] NEG_INF = {1'b1, {(TI-1){1'b0}}};
    localparam signed [TI-1:0] POS_INF = {1'b0, {(TI-1){1'b1}}};
    localparam signed [TI-1:0] T_ZERO = {TI{1'b0}};
    localparam F = STACK_DEPTH;
    localparam GW = POS_W + 2 + F;
    localparam FW = 9*TI + 32 + 32 + 4 + 5 + 60;   // a stack frame
    localparam [31:0] HOLD1 = STEP_LATENCY - 4;    // hold cycles after stage B
    localparam SPW = $clog2(STACK_DEPTH) + 1;
    localparam SD = R * (STACK_DEPTH - 1);         // stack RAM depth
    localparam SAW = $clog2(SD) > 0 ? $clog2(SD) : 1;
    // RAM word widths.
    localparam WRW = 3 + 3 + 32 + TAG_W + 9*TI + 3*(POS_W+1) + 3*POS_W;
    localparam FRW = 9*TI + 6*GW + 32 + 32 + 5 + 60;
    localparam CRW = 9*TI + 3*GW + 60 + 5;
    localparam NRW = 4 + 32 + T_W + 60 + 32;

    localparam [2:0] S_IDLE = 3'd0, S_REQ = 3'd1, S_MEMW = 3'd2, S_ISSUE = 3'd3,
                     S_COMP = 3'd4, S_HOLD = 3'd5, S_OUT = 3'd6, S_APPL = 3'd7;
    localparam [1:0] P_DESC = 2'd0, P_FAR = 2'd1, P_LEAF = 2'd2, P_ATTR = 2'd3;
    localparam [1:0] A_ISSUE = 2'd0, A_REQ = 2'd1, A_OUT = 2'd2;

    generate
        if (STEP_LATENCY > 200 || STACK_DEPTH < 2 || STACK_DEPTH > 64
            || CONTEXTS < 2 || CONTEXTS > 16 || K < 1 || K > 2)
        begin : bad_parameters
            svo_walker_barrel_unsupported_parameters fail ();
        end
        // The step is issue, apply, stage A, stage B: a context's next issue comes after its
        // stage B's write-back (walker_pool.step_latency_cycles >= 4 when contexts_per_walker > 1).
        if (STEP_LATENCY < 4) begin : step_latency_below_4
            svo_walker_barrel_needs_step_latency_4_or_more fail ();
        end
    endgenerate

    function automatic signed [TI-1:0] mid_t(input signed [TI-1:0] a, input signed [TI-1:0] b);
        mid_t = (a >>> 1) + (b >>> 1) + $signed({{(TI-1){1'b0}}, a[0] & b[0]});
    endfunction
    function automatic [2:0] popcount7(input [6:0] v);
        reg s1, c1, s2, c2, c3;
        begin
            s1 = v[0] ^ v[1] ^ v[2];
            c1 = (v[0] & v[1]) | (v[0] & v[2]) | (v[1] & v[2]);
            s2 = v[3] ^ v[4] ^ v[5];
            c2 = (v[3] & v[4]) | (v[3] & v[5]) | (v[4] & v[5]);
            popcount7[0] = s1 ^ s2 ^ v[6];
            c3 = (s1 & s2) | (s1 & v[6]) | (s2 & v[6]);
            popcount7[1] = c1 ^ c2 ^ c3;
            popcount7[2] = (c1 & c2) | (c1 & c3) | (c2 & c3);
        end
    endfunction
    function automatic [23:0] prefix_counts(input [6:0] valid);
        integer r;
        begin
            for (r = 0; r < 8; r = r + 1)
                prefix_counts[3*r +: 3] = popcount7(valid & ~(7'h7f << r));
        end
    endfunction

    // ---------------------------------------------------------------- the RAMs
    reg [WRW-1:0] wram [0:R-1];
    reg [FRW-1:0] fram [0:R-1];
    reg [CRW-1:0] cram [0:R-1];
    reg [NRW-1:0] nram [0:R-1];
    reg [FW-1:0]  stk  [0:SD-1];
    reg [FW-1:0]  stk_q;                           // the stack's read, in stage A

    // ---------------------------------------------------------------- per context registers
    reg [2:0]     st        [0:R-1];
    reg [1:0]     pend      [0:R-1];
    reg [1:0]     act       [0:R-1];
    reg [7:0]     hold_left [0:R-1];
    reg [SPW-1:0] sp        [0:R-1];
    reg [31:0]    req_addr  [0:R-1];
    reg [1:0]     outcome   [0:R-1];
    reg [63:0]    r_data    [0:R-1];               // the descriptor, then the attribute record
    reg [R-1:0]   b_dec, c_root, c_leaf, apf, req_attr;

    wire [63:0] rdata [0:R-1];                     // the responses, per context
    wire [R-1:0] resp, chain;
    // ---------------------------------------------------------------- the chaining response
    // A far word's child slot and a leaf's attribute record are requested in the cycle the
    // word arrives: per context its base (the far-escape address c_fa, kept beside nram's copy;
    // the walk's attribute base, kept beside wram's) plus its word, one adder a context, so
    // the response's path is base + word (no selection of the responding context, no RAM read
    // by its index: that path was 16 levels, 4.5 ns, at CONTEXTS = 16).
    reg [31:0] fa [0:R-1];                         // c_fa, written with nram
    reg [31:0] ab [0:R-1];                         // the attribute base, written with wram
    reg [31:0] chain_addr [0:R-1];
    integer ir;
    always @* begin
        for (ir = 0; ir < R; ir = ir + 1)
            chain_addr[ir] = (pend[ir] == P_FAR ? fa[ir] : ab[ir]) + rdata[ir][31:0];
    end

    genvar gc;
    generate
        for (gc = 0; gc < R; gc = gc + 1) begin : port
            assign rdata[gc] = mem_resp_data[gc*64 +: 64];
            assign resp[gc] = st[gc] == S_MEMW && mem_resp_valid[gc];
            assign chain[gc] = resp[gc] && (pend[gc] == P_FAR || pend[gc] == P_LEAF);
            assign in_ready[gc] = st[gc] == S_IDLE || (out_valid[gc] && out_ready[gc]);
            assign out_valid[gc] = st[gc] == S_OUT || (resp[gc] && pend[gc] == P_ATTR);
            assign issue_req[gc] = st[gc] == S_ISSUE || (resp[gc] && pend[gc] == P_DESC);
            assign ev_resp[gc] = resp[gc];
            assign mem_req_valid[gc] = st[gc] == S_REQ || chain[gc];
            assign mem_req_attr[gc] = chain[gc] ? pend[gc] == P_LEAF : req_attr[gc];
            assign mem_req_addr[gc*32 +: 32] = chain[gc] ? chain_addr[gc] : req_addr[gc];
        end
    endgenerate

    // ---------------------------------------------------------------- stage 0: the issue (X)
    // Only the selection: the granted context's index and its four RAM words, registered, and
    // two of its flags. issue_grant is one-hot (or zero) and only to a context with issue_req
    // (the pool's scheduler: the oldest requester of the walker), so the index is a plain
    // encoding of it; nothing of the issue cycle waits on arithmetic (the grant comes late in
    // the cycle from the scheduler). The per-context registers req_addr, sp and r_data are read
    // in the apply cycle by the registered index: they do not change in between.
    reg [RI-1:0] k0;
    integer ig;
    always @* begin
        k0 = {RI{1'b0}};
        for (ig = 0; ig < R; ig = ig + 1) if (issue_grant[ig]) k0 = k0 | ig[RI-1:0];
    end
    wire s0 = |issue_grant;
    reg [R-1:0] arrive;                            // a descriptor arrives (applied at this issue)
    integer ia;
    always @* for (ia = 0; ia < R; ia = ia + 1) arrive[ia] = resp[ia] && pend[ia] == P_DESC;
    reg           q_valid, q_apply, q_root;
    reg [RI-1:0]  q_k;
    // wram and cram, which feed the first child's comparisons, are read here and registered;
    // fram and nram, which only pass or are pushed, are read in the apply cycle by q_k (their
    // words' registers would be 1,264 flip-flops; nothing writes the context's words between).
    // (each register takes the whole word; the apply cycle uses some fields, Yosys drops the rest)
    wire [WRW-1:0] wr_k0;                          // wram's word of context k0 (declared
                                                   // before its first use: slang, Vivado)
    /* verilator lint_off UNUSEDSIGNAL */
    reg [WRW-1:0] w0;
    reg [CRW-1:0] c0;
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        q_valid <= !rst && s0;
        q_apply <= |(issue_grant & (apf | arrive));
        q_root <= |(issue_grant & c_root);
        q_k <= k0;
        w0 <= wr_k0;
        c0 <= cram[k0];
    end

    // ---------------------------------------------------------------- the apply cycle (X + 1)
    // A descriptor that arrived is applied here: the child becomes the top frame, its first
    // child found from its midpoints (computed with the child in stage B, the root's at the
    // take: no adder here), the parent pushed; otherwise the stored top frame passes. Also the
    // stack's read for a pop.
    wire [31:0] q_desc = r_data[q_k][31:0];
    /* verilator lint_off UNUSEDSIGNAL */
    wire [FRW-1:0] f0 = fram[q_k];
    wire [NRW-1:0] n0 = nram[q_k];
    /* verilator lint_on UNUSEDSIGNAL */
    // wram's fields.
    wire [2:0] w0_a = w0[WRW-4 -: 3];
    wire [3*TI-1:0] w0_t0 = w0[WRW-39-TAG_W -: 3*TI];
    wire [3*TI-1:0] w0_t1 = w0[WRW-39-TAG_W-3*TI -: 3*TI];
    wire [3*TI-1:0] w0_tm = w0[WRW-39-TAG_W-6*TI -: 3*TI];
    wire [3*(POS_W+1)-1:0] w0_o = w0[3*POS_W +: 3*(POS_W+1)];
    wire [3*POS_W-1:0] w0_half = w0[0 +: 3*POS_W];
    // The applied frame (a descriptor's child) or the stored one.
    reg signed [TI-1:0] a0_t0 [0:2];
    reg signed [TI-1:0] a0_t1 [0:2];
    reg signed [TI-1:0] a0_tm [0:2];
    reg signed [GW-1:0] a0_g [0:2];
    reg signed [GW-1:0] a0_d [0:2];
    reg [3:0]  a0_first;
    reg [19:0] a0_c [0:2];
    reg [4:0]  a0_level;
    integer j0;
    always @* begin
        for (j0 = 0; j0 < 3; j0 = j0 + 1) begin
            if (q_root) begin
                a0_t0[j0] = w0_t0[j0*TI +: TI];
                a0_t1[j0] = w0_t1[j0*TI +: TI];
                a0_tm[j0] = w0_tm[j0*TI +: TI];
                a0_g[j0] = {~{{(GW-F-POS_W-1){w0_o[j0*(POS_W+1) + POS_W]}},
                              w0_o[j0*(POS_W+1) +: POS_W+1]}, {F{1'b0}}};
                a0_d[j0] = {{(GW-F-POS_W){w0_half[j0*POS_W + POS_W-1]}},
                            w0_half[j0*POS_W +: POS_W], {F{1'b0}}} >>> 1;
                a0_c[j0] = 20'd0;
            end else begin
                a0_t0[j0] = c0[CRW-1-j0*TI -: TI];
                a0_t1[j0] = c0[CRW-1-(3+j0)*TI -: TI];
                a0_tm[j0] = c0[CRW-1-(6+j0)*TI -: TI];
                a0_g[j0] = c0[CRW-1-9*TI-j0*GW -: GW];
                a0_d[j0] = $signed(f0[FRW-1-9*TI-(3+j0)*GW -: GW]) >>> 1;
                a0_c[j0] = c0[5 + (2-j0)*20 +: 20];
            end
        end
        for (j0 = 0; j0 < 3; j0 = j0 + 1)
            a0_first[2-j0] = a0_tm[j0] < a0_t0[0] || a0_tm[j0] < a0_t0[1] || a0_tm[j0] < a0_t0[2];
        a0_first[3] = 1'b0;
        a0_level = q_root ? 5'd0 : c0[4:0];
    end
    // The frame into stage A.
    wire [FRW-1:0] s0_frame = q_apply
        ? {a0_t0[0], a0_t0[1], a0_t0[2], a0_t1[0], a0_t1[1], a0_t1[2], a0_tm[0], a0_tm[1],
           a0_tm[2], a0_g[0], a0_g[1], a0_g[2], a0_d[0], a0_d[1], a0_d[2], req_addr[q_k],
           q_desc, a0_level, a0_c[0], a0_c[1], a0_c[2]}
        : f0;
    wire [3:0]  s0_next = q_apply ? a0_first : n0[NRW-1 -: 4];
    wire [31:0] s0_steps = q_apply && q_root ? 32'd0 : n0[NRW-5 -: 32];
    // The stack: a descriptor (not the root's) pushes the parent; otherwise read the frame a
    // pop would take.
    wire s0_push = q_valid && q_apply && !q_root;
    wire [SPW-1:0] sp0 = sp[q_k];
    /* verilator lint_off UNUSEDSIGNAL */
    wire [31:0] s0_base = q_k * (STACK_DEPTH - 1);
    wire [31:0] s0_slot = s0_base + (s0_push || sp0 == {SPW{1'b0}} ? {{(32-SPW){1'b0}}, sp0}
                                                                    : {{(32-SPW){1'b0}}, sp0} - 32'd1);
    /* verilator lint_on UNUSEDSIGNAL */
    wire [FW-1:0] s0_push_frame = {f0[FRW-1 -: 9*TI], f0[FRW-1-9*TI-6*GW -: 64], n0[NRW-1 -: 4],
                                   f0[64:0]};
    always @(posedge clk) begin
        if (s0_push) stk[s0_slot[SAW-1:0]] <= s0_push_frame;
        stk_q <= stk[s0_slot[SAW-1:0]];
    end

    // ---------------------------------------------------------------- stage A (issue + 2)
    reg           p1_valid;
    reg [RI-1:0]  p1_k;
    reg [FRW-1:0] p1_f;
    reg [3:0]     f_next;
    reg [31:0]    p1_steps;
    reg [2:0]     w_a, w_z;
    reg [2:0]     f_pc [0:7];
    // (each read port takes the whole word; some ports use some fields)
    /* verilator lint_off UNUSEDSIGNAL */
    wire [31:0] s0_fdesc = s0_frame[FRW-1-9*TI-6*GW-32 -: 32];
    /* verilator lint_on UNUSEDSIGNAL */
    wire [23:0] pc0 = prefix_counts(s0_fdesc[14:8]);
    integer jp;
    always @(posedge clk) begin
        p1_valid <= !rst && q_valid;
        p1_k <= q_k;
        p1_f <= s0_frame;
        f_next <= s0_next;
        p1_steps <= s0_steps;
        w_a <= w0_a;
        w_z <= w0[WRW-1 -: 3];
        for (jp = 0; jp < 8; jp = jp + 1) f_pc[jp] <= pc0[3*jp +: 3];
    end
    // The top frame's fields.
    reg signed [TI-1:0] f_t0 [0:2];
    reg signed [TI-1:0] f_t1 [0:2];
    reg signed [TI-1:0] f_tm [0:2];
    reg signed [GW-1:0] f_g [0:2];
    reg signed [GW-1:0] f_d [0:2];
    reg [19:0] f_c [0:2];
    wire [31:0] f_addr = p1_f[FRW-1-9*TI-6*GW -: 32];
    wire [31:0] f_desc = p1_f[FRW-1-9*TI-6*GW-32 -: 32];
    wire [4:0]  f_level = p1_f[60 +: 5];
    integer jf;
    always @* for (jf = 0; jf < 3; jf = jf + 1) begin
        f_t0[jf] = p1_f[FRW-1-jf*TI -: TI];
        f_t1[jf] = p1_f[FRW-1-(3+jf)*TI -: TI];
        f_tm[jf] = p1_f[FRW-1-(6+jf)*TI -: TI];
        f_g[jf] = p1_f[FRW-1-9*TI-jf*GW -: GW];
        f_d[jf] = p1_f[FRW-1-9*TI-(3+jf)*GW -: GW];
        f_c[jf] = p1_f[(2-jf)*20 +: 20];
    end
    wire [SPW-1:0] sp1 = sp[p1_k];
    wire [2:0]  cc = f_next[2:0];
    wire        popping = f_next[3];
    reg signed [TI-1:0] s_t0 [0:2];
    reg signed [TI-1:0] s_t1 [0:2];
    reg signed [GW-1:0] s_g [0:2];
    reg signed [GW-1:0] s_y;
    reg        s_neg;
    reg [2:0]  s_real;
    reg [19:0] s_c [0:2];
    reg [8:0]  s_lt;
    integer k, b;
    always @* begin
        for (k = 0; k < 3; k = k + 1) begin
            s_t0[k] = cc[2-k] ? f_tm[k] : f_t0[k];
            s_t1[k] = cc[2-k] ? f_t1[k] : f_tm[k];
        end
        for (k = 0; k < 3; k = k + 1)
            for (b = 0; b < 3; b = b + 1)
                s_lt[3*k + b] = s_t0[k] < s_t1[b];
        s_real = cc ^ w_a;
        for (k = 0; k < 3; k = k + 1) s_c[k] = {f_c[k][18:0], s_real[2-k]};
        for (k = 0; k < 3; k = k + 1) begin
            s_y = popping ? f_d[k] <<< 1 : f_d[k];
            s_neg = popping ? f_c[k][0] ^ w_a[2-k] : !cc[2-k];
            s_g[k] = f_g[k] + (s_y ^ {GW{s_neg}}) + {{(GW-1){1'b0}}, s_neg};
        end
    end
    // Write-back of stage A: the top frame (a pop's parent from the stack, its g and d).
    wire [FW-1:0] sq = stk_q;
    wire [FRW-1:0] pop_frame = {sq[FW-1 -: 9*TI], s_g[0], s_g[1], s_g[2], f_d[0] <<< 1,
                                f_d[1] <<< 1, f_d[2] <<< 1, sq[FW-1-9*TI -: 64], sq[64:0]};
    always @(posedge clk) begin
        if (p1_valid) fram[p1_k] <= popping ? pop_frame : p1_f;
    end
    // Stage A's registers (svo_walker's a_* and the child's fields stage B reads).
    reg           p2_valid, p2_pop;
    reg [RI-1:0]  p2_k;
    reg [3:0]     p2_next;
    reg [31:0]    p2_steps, p2_addr;
    reg signed [TI-1:0] c_t0 [0:2];
    reg signed [TI-1:0] c_t1 [0:2];
    reg signed [GW-1:0] c_g [0:2];
    reg [19:0] c_c [0:2];
    reg [4:0]  c_level;
    reg [2:0]  c_z;
    reg [8:0]  a_lt;
    reg [2:0]  a_pos, a_t0pos;
    reg        a_n01, a_n02, a_n12, a_e01, a_e02, a_e12;
    reg        a_valid, a_leaf, a_far, a_lim, a_ovf;
    reg [3:0]  a_slot;
    reg [31:0] a_base;
    integer j;
    always @(posedge clk) begin
        p2_valid <= !rst && p1_valid;
        p2_k <= p1_k;
        p2_pop <= popping;
        p2_next <= popping ? sq[FW-1-9*TI-64 -: 4] : f_next;
        p2_steps <= p1_steps;
        p2_addr <= f_addr;
        for (j = 0; j < 3; j = j + 1) begin
            c_t0[j] <= s_t0[j];
            c_t1[j] <= s_t1[j];
            c_g[j] <= s_g[j];
            c_c[j] <= s_c[j];
            a_pos[j] <= s_t1[j] > T_ZERO;
            a_t0pos[j] <= s_t0[j] > T_ZERO;
        end
        a_lt <= s_lt;
        c_level <= f_level + 5'd1;
        c_z <= w_z;
        a_n01 <= s_t1[0] <= s_t1[1];
        a_n02 <= s_t1[0] <= s_t1[2];
        a_n12 <= s_t1[1] <= s_t1[2];
        a_e01 <= s_t0[0] >= s_t0[1];
        a_e02 <= s_t0[0] >= s_t0[2];
        a_e12 <= s_t0[1] >= s_t0[2];
        a_valid <= f_desc[8 + s_real];
        a_leaf <= f_desc[{2'b00, s_real}];
        a_far <= f_desc[16];
        a_slot <= {1'b0, f_pc[s_real]};
        a_base <= f_addr + {17'd0, f_desc[31:17]};
        a_lim <= p1_steps + 32'd1 > MAX_STEPS;
        a_ovf <= {{(32-SPW){1'b0}}, sp1} + 32'd1 >= STACK_DEPTH;
    end

    // ---------------------------------------------------------------- stage B (issue + 3)
    wire        b_in = &a_lt && &a_pos;
    wire        b_enter = b_in && a_valid;
    wire [2:0]  b_cc = p2_next[2:0];
    wire [2:0]  b_bit = a_n01 && a_n02 ? 3'b100 : a_n12 ? 3'b010 : 3'b001;
    wire [3:0]  b_next = (b_cc & b_bit) != 3'b000 ? 4'd8 : {1'b0, b_cc | b_bit};
    wire [1:0]  b_axis = a_e01 && a_e02 ? 2'd0 : a_e12 ? 2'd1 : 2'd2;
    wire [1:0]  b_act = a_lim ? A_OUT : !b_enter ? A_ISSUE
                      : (!a_leaf && a_ovf) ? A_OUT : A_REQ;
    wire [31:0] b_slot_addr = a_base + {28'd0, a_slot};
    wire [T_W-1:0] b_t = a_t0pos[b_axis] ? c_t0[b_axis][T_W-1:0] : {T_W{1'b0}};
    // The step's child (not a pop's) into cram with its midpoints, so that applying its
    // descriptor has no adder: tm = floor((t0 + t1) / 2), on a zero axis +-inf by the side of
    // its centre (g >= 0: +inf).
    reg signed [TI-1:0] c_tm [0:2];
    integer jb;
    always @* for (jb = 0; jb < 3; jb = jb + 1)
        c_tm[jb] = !c_z[jb] ? mid_t(c_t0[jb], c_t1[jb]) : c_g[jb][GW-1] ? NEG_INF : POS_INF;
    always @(posedge clk)
        if (p2_valid && !p2_pop)
            cram[p2_k] <= {c_t0[0], c_t0[1], c_t0[2], c_t1[0], c_t1[1], c_t1[2], c_tm[0], c_tm[1],
                           c_tm[2], c_g[0], c_g[1], c_g[2], c_c[0], c_c[1], c_c[2], c_level};
    always @(posedge clk)
        if (p2_valid)
            nram[p2_k] <= {p2_pop || a_lim ? p2_next : b_next,
                           p2_pop ? p2_steps : p2_steps + 32'd1,
                           b_t, c_c[2], c_c[1], c_c[0], p2_addr + {28'd0, a_slot}};

    // ---------------------------------------------------------------- the sequencers
    // The take ports: port j's context kt[j] (its one-hot OR-encoded) and its wram word. Each
    // port writes a wram bank of its own (LUT-RAM: one write port a bank); at K = 2 a bit per
    // context (lane1, a live-value table) says which bank holds its walk, read with the word.
    wire [R-1:0]   tk;                             // taken, on any port
    wire [R-1:0]   tk1;                            // taken on port 1 (K = 2)
    wire [RI-1:0]  kt    [0:K-1];
    wire [WRW-1:0] wword [0:K-1];
    wire [WRW-1:0] wr_fin [0:K-1];                 // ... of result port j's context
    genvar gk;
    generate
        for (gk = 0; gk < K; gk = gk + 1) begin : take_port
            reg [RI-1:0] kq;
            integer it;
            always @* begin                        // in_take is one-hot (or zero): OR-encode it
                kq = {RI{1'b0}};
                for (it = 0; it < R; it = it + 1) if (in_take[gk*R + it]) kq = kq | it[RI-1:0];
            end
            assign kt[gk] = kq;
            // The root's midpoints (its zero axes' +-inf by the side of its centre 0: g = ~ox
            // >= 0, +inf, iff ox < 0), ready for its descriptor's apply as a child's are.
            wire [2:0]             z  = in_zero[gk*3 +: 3];
            wire [2:0]             ng = in_neg[gk*3 +: 3];
            wire [3*TI-1:0]        t0 = in_t0[gk*3*TI +: 3*TI];
            wire [3*TI-1:0]        t1 = in_t1[gk*3*TI +: 3*TI];
            wire [3*(POS_W+1)-1:0] o  = in_o[gk*3*(POS_W+1) +: 3*(POS_W+1)];
            reg  [3*TI-1:0]        in_tm;
            integer jt;
            always @* for (jt = 0; jt < 3; jt = jt + 1)
                in_tm[jt*TI +: TI] = !z[jt] ? mid_t(t0[jt*TI +: TI], t1[jt*TI +: TI])
                                   : !o[jt*(POS_W+1) + POS_W] ? NEG_INF : POS_INF;
            assign wword[gk] = {z, ng[0], ng[1], ng[2], in_attr_base[gk*32 +: 32],
                                in_tag[gk*TAG_W +: TAG_W], t0, t1, in_tm, o,
                                in_half[gk*3*POS_W +: 3*POS_W]};
        end
        if (K > 1) begin : two_banks
            reg [WRW-1:0] wram1 [0:R-1];
            reg [R-1:0]   lane1;
            assign tk = in_take[0 +: R] | in_take[R +: R];
            assign tk1 = in_take[R +: R];
            always @(posedge clk) begin
                if (|in_take[R +: R]) wram1[kt[1]] <= wword[1];
                lane1 <= rst ? {R{1'b0}} : (lane1 & ~tk) | tk1;
            end
            assign wr_k0 = lane1[k0] ? wram1[k0] : wram[k0];
            for (gk = 0; gk < K; gk = gk + 1) begin : fin_read
                assign wr_fin[gk] = lane1[fin[gk*RI +: RI]] ? wram1[fin[gk*RI +: RI]]
                                                            : wram[fin[gk*RI +: RI]];
            end
        end else begin : one_bank
            assign tk = in_take[0 +: R];
            assign tk1 = {R{1'b0}};
            assign wr_k0 = wram[k0];
            assign wr_fin[0] = wram[fin[0 +: RI]];
        end
    endgenerate
    always @(posedge clk)
        if (|in_take[0 +: R]) wram[kt[0]] <= wword[0];

    integer n;
    always @(posedge clk) begin
        for (n = 0; n < R; n = n + 1) begin
            ev_lat[n] <= !rst && st[n] == S_HOLD && hold_left[n] == 8'd0;
            ev_disp[n] <= !rst && tk[n];
            if (rst) begin
                st[n] <= S_IDLE;
                b_dec[n] <= 1'b0;
                apf[n] <= 1'b0;
            end else begin
                if (out_valid[n] && out_ready[n]) begin
                    st[n] <= S_IDLE;
                end else if (resp[n] && pend[n] == P_ATTR) begin
                    r_data[n] <= rdata[n];
                    st[n] <= S_OUT;
                end
                case (st[n])
                S_REQ: if (mem_req_ready[n]) st[n] <= S_MEMW;
                S_MEMW: if (mem_resp_valid[n]) begin
                    case (pend[n])
                    P_DESC: begin
                        r_data[n] <= rdata[n];
                        apf[n] <= 1'b1;
                        st[n] <= issue_grant[n] ? S_APPL : S_ISSUE;
                    end
                    P_FAR: begin
                        pend[n] <= c_leaf[n] ? P_LEAF : P_DESC;
                        req_addr[n] <= chain_addr[n];
                        req_attr[n] <= 1'b0;
                        st[n] <= mem_req_ready[n] ? S_MEMW : S_REQ;
                    end
                    P_LEAF: begin
                        pend[n] <= P_ATTR;
                        req_addr[n] <= chain_addr[n];
                        req_attr[n] <= 1'b1;
                        st[n] <= mem_req_ready[n] ? S_MEMW : S_REQ;
                    end
                    default: ;
                    endcase
                end
                S_ISSUE: if (issue_grant[n]) st[n] <= S_APPL;
                S_APPL: st[n] <= S_COMP;
                S_COMP: begin
                    st[n] <= S_HOLD;
                    hold_left[n] <= HOLD1[7:0];
                    if (popping) begin
                        b_dec[n] <= 1'b0;
                        if (sp[n] == {SPW{1'b0}}) begin
                            outcome[n] <= 2'd0;
                            act[n] <= A_OUT;
                        end else begin
                            act[n] <= A_ISSUE;
                            sp[n] <= sp[n] - 1'b1;
                        end
                    end else begin
                        b_dec[n] <= 1'b1;
                        c_leaf[n] <= f_desc[{2'b00, s_real}];
                        c_root[n] <= 1'b0;
                    end
                end
                S_HOLD: begin
                    if (b_dec[n]) begin
                        b_dec[n] <= 1'b0;
                        if (a_lim) begin
                            outcome[n] <= 2'd2;
                        end else if (b_enter) begin
                            req_attr[n] <= 1'b0;
                            if (a_leaf) outcome[n] <= 2'd1;
                            if (!a_leaf && a_ovf) begin
                                outcome[n] <= 2'd3;
                            end else if (a_far) begin
                                pend[n] <= P_FAR;
                                req_addr[n] <= a_base;
                            end else begin
                                pend[n] <= a_leaf ? P_LEAF : P_DESC;
                                req_addr[n] <= b_slot_addr;
                            end
                        end
                    end
                    act[n] <= b_dec[n] ? b_act : act[n];
                    if (hold_left[n] == 8'd0)
                        st[n] <= (b_dec[n] ? b_act : act[n]) == A_ISSUE ? S_ISSUE
                               : (b_dec[n] ? b_act : act[n]) == A_REQ ? S_REQ : S_OUT;
                    else
                        hold_left[n] <= hold_left[n] - 8'd1;
                end
                default: ;
                endcase
                // The apply cycle: the descriptor is applied (the parent pushed).
                if (q_valid && q_k == n[RI-1:0]) begin
                    apf[n] <= 1'b0;
                    if (s0_push) sp[n] <= sp[n] + 1'b1;
                end
                // Stage B's far-escape address (as nram's).
                if (p2_valid && p2_k == n[RI-1:0]) fa[n] <= p2_addr + {28'd0, a_slot};
                // A new walk (possibly in the cycle the previous result leaves).
                if (tk[n]) begin
                    ab[n] <= tk1[n] ? in_attr_base[(K-1)*32 +: 32] : in_attr_base[0 +: 32];
                    c_root[n] <= 1'b1;
                    c_leaf[n] <= 1'b0;
                    req_addr[n] <= tk1[n] ? in_node_base[(K-1)*32 +: 32] : in_node_base[0 +: 32];
                    req_attr[n] <= 1'b0;
                    pend[n] <= P_DESC;
                    sp[n] <= {SPW{1'b0}};
                    outcome[n] <= 2'd0;
                    apf[n] <= 1'b0;
                    st[n] <= (tk1[n] ? in_enter[K-1] : in_enter[0]) ? S_REQ : S_OUT;
                end
            end
        end
    end

    // ---------------------------------------------------------------- the result
    // K result ports: port j reads context fin[j]'s state (at K = 2 the pool's second retire
    // lane, when both lanes retire from this walker).
    generate
        for (gk = 0; gk < K; gk = gk + 1) begin : result
            wire [RI-1:0] f = fin[gk*RI +: RI];
            // (each read port takes the whole word; some ports use some fields)
            /* verilator lint_off UNUSEDSIGNAL */
            wire [NRW-1:0] fin_n = nram[f];
            wire [WRW-1:0] fin_w = wr_fin[gk];
            /* verilator lint_on UNUSEDSIGNAL */
            assign out_outcome[gk*2 +: 2] = outcome[f];
            assign out_t[gk*T_W +: T_W] = fin_n[NRW-37 -: T_W];
            assign out_voxel[gk*60 +: 60] = fin_n[32 +: 60];
            assign out_attr_data[gk*64 +: 64] = st[f] == S_OUT ? r_data[f] : rdata[f];
            assign out_tag[gk*TAG_W +: TAG_W] = fin_w[WRW-39 -: TAG_W];
        end
    endgenerate
endmodule
`default_nettype wire
