// svo_walker_pool: WALKERS octree walkers of CONTEXTS ray contexts each, their scheduler and
// the dispatcher, cycle for cycle as the cycle model's walker pool times them
// (rtl_model/src/cycle/walker_pool.rs, its module doc) with read_ports 1, step_cycles 1.
//
// Pipeline position: after root_to_dispatch (svo_walk), before walker_to_record; the node
// memory behind one request port per walker.
//
// What it is: per walker ONE step datapath, a barrel walker (svo_walker_barrel.v): the R
// contexts' state in RAMs indexed by context (LUT-RAM context words read at the issue and written
// back by the step; the stacks in one block-RAM array of R x (STACK_DEPTH - 1) frames), the
// design the model's cost estimate prices (rtl_model/src/cost: `walker_contexts`,
// `walker_stacks`). At R = 1 each walker is svo_walker, whose registers are its one context (the
// estimate's calibrated walker; it adds no context file at R = 1). One issue grant and one
// request port per walker, K take and K result ports (K walk-issue lanes, HwConfig::walk_lanes,
// 1 or 2: the dispatch and retire lanes). The contexts issue only when granted, one slot a
// walker and cycle.
//
// The scheduler is the model's, per cycle:
//   wake-up order  a context moves on to its next op in the model's wake-up order: first those
//                  whose step latency ended (ev_lat: at most one a walker, in walker order,
//                  the order their slots issued), then the walks dispatched in the cycle before
//                  (ev_disp: a root read, or a root miss; in dispatch order: disp_lane, the
//                  lane that took it), then the contexts whose read
//                  completed (ev_resp) by request age (the node memory's (done, id) order).
//                  That order decides where the context joins the queue its next op needs:
//   issue          each walker's ready contexts issue round robin in the order they became
//                  ready (a FIFO), one a cycle (step_cycles 1), a newly ready one in the same
//                  cycle if none waits before it;
//   request port   one read a walker and cycle; reads waiting for the port (the send queue)
//                  go first, oldest first, then this cycle's new ones in wake-up order; the
//                  sends of one cycle are the node memory's ids in the order: waiting ones by
//                  walker, then new ones in wake-up order (req_older keeps it);
//   retire         finished walks leave in the order they finished, up to K a cycle for the
//                  pool, while the record FIFO takes them (out_ready, a prefix); a context
//                  takes a new walk in the same cycle (the model retires before it
//                  dispatches): svo_walker_pool_retire.v;
//   dispatch       up to K walks a cycle, each to the walker with the most free contexts
//                  (this cycle's retires and the earlier lanes' takes counted), the lowest
//                  index on ties, so two can go to one walker: svo_walker_pool_dispatch.v.
// How it is built, so that it grows as W·R² plus O(N) for N = W·R contexts (never N²):
//   per walker     a context is in at most one queue at a time, and a walker's issue and send
//                  queues hold only its own contexts, so one R x R age order per walker
//                  (older[n][k]: n joined its queue before k, updated with each cycle's events
//                  ranked as above; req_older[n][k]: n's read went out before k's, which
//                  within a walker is the send order, one send a cycle) serves its issue
//                  queue, its send queue and its part of the retire queue.
//   pool-wide      contexts of different walkers are ordered by the model in one place only:
//                  the retire queue (finish order, one a cycle for the pool), where walks that
//                  finish in one cycle leave in that cycle's wake-up order — step latencies by
//                  walker, the dispatched walk, completions by request age (the node memory's
//                  id order). So each read gets an id {send stamp, rank}: the stamp counts the
//                  cycles that sent, the rank is its place among that cycle's sends (at most
//                  one a walker; waiting ones by walker, then new ones in wake-up order, a new
//                  one after a completion by its previous read's id): W x W rank compares.
//                  Each finished walk keeps a finish key {finish stamp, wake-up class, read
//                  id, dispatch lane}; the retire takes the oldest of the W walkers' oldest
//                  finished walks, at K = 2 then the next (svo_walker_pool_retire.v). Read ids
//                  compare modulo 2^ID_W: exact while no read stays out across 2^23 sending
//                  cycles (SEND_STAMP_W 24; svo_top's node memory answers in a fixed latency).
//   cost           per walker R² age bits (older, req_older) and R² compares; per context a
//                  read id (24 + clog2(W) bits) and a finish key (clog2(N) + 3 bits, at K = 2
//                  one more, the lane); W² rank compares of the ids; W - 1 key compares at
//                  retire (at K = 2 a second chain of W - 1). At K = 1, at 48 x 16: 24,576 age
//                  bits, 768 x (30 + 13) key bits, 2,256 id compares — against 589,824 bits of
//                  the N x N matrix it replaces. Verilator 5.006 --lint-only of 48 x 16 takes
//                  about a minute (testbench/README.md).
//   not scaled     with responses on the walker ports (CTX_RESP 0 or 1): every context matching
//                  each response port against its own and its fill's context (N x W compares)
//                  and selecting its word among the W ports; with the attribute-merge rule
//                  (below) each walker's read address against every context's fill address
//                  (W x N 32-bit compares). Behind a cache (svo_top: CTX_RESP 2, ATTR_MERGE 0)
//                  neither is built: every response comes on its context's own port.
//
// Attribute reads that merge (the model's MSHR rule for uncached attribute reads with
// cache.line_bytes 8, memory/dram.rs `miss`): a record read while a fill of the same record is
// in flight from any walker (sent, its response not yet back, and not arriving in this cycle)
// is not sent: it completes with that fill, in the same cycle, after it (request age). Two
// reads of one record sent in the same cycle both go out (the model merges the second, with
// the same completion cycle). With one context in all no read can merge, so any node memory
// works; with several, the hardware file must use uncached attributes with 8-byte lines
// (svo_top refuses other node memories), where this rule is the model's exactly. Behind a
// cache (svo_top with onchip.levels 0, attributes cached) the model merges in the cache
// instead: a read of a record in flight is looked up like any other (a hit completes at the
// hit latency, a miss joins the MSHR), so there ATTR_MERGE is 0 and every read goes out.
//
// The memory: per walker mem_req_* one read a cycle with its context (mem_req_ctx, the pool's
// context index n = walker·CONTEXTS + k); responses in any order, each with its context
// (mem_resp_ctx), on any port, several for one walker in a cycle included: node or leaf words
// (which chain a read in the cycle they arrive) of several contexts each make a request, the
// port takes the oldest and the others join the walker's send queue, as the model's (issue 29:
// svo_top's store and cache answer two contexts of one walker in one cycle, a fill completes
// the reads merged on it together; under random stalls on the cache's R this is common, and
// the barrel walker's old flag for it was a false FAULT, testbench/README.md "The store in
// front of the cache"); records of merged reads may complete several a cycle. Sticky
// err_resp: a response on a walker port that reaches no context (a context index beyond N),
// or with CTX_RESP 2 any response on a walker port.
// Registers (walker_pool.rs, "Registered response and request"; issue 29, for 300 MHz):
// RESPONSE_REGISTER_CYCLES 1 registers the responses (the contexts see the memory's cycle C in
// C + 1; the fills' state stays the memory's), REQUEST_REGISTER_CYCLES 1 each walker port's
// pick (the memory gets it in C + 1 and the merge is decided there, as the model's memory
// decides it). Both 1 cut response -> wake-up order -> pick -> merge -> send twice.
// With CTX_RESP 1 each context also has a port of its own (ctx_resp_valid[n], its node word in
// ctx_resp_data[32n +: 32]): svo_top's on-chip store answers there, several contexts a cycle,
// while the walker ports carry the attribute records. With CTX_RESP 2 the context ports carry
// every response, node words and records alike (ctx_resp_data[64n +: 64], a node word in the
// low half), and the walker response ports carry nothing (a response there is err_resp):
// svo_top behind its node cache, which answers each context on its own port anyway. That is
// what keeps the pool's response side O(N): with records on walker ports any context may be
// answered on any port, so every context decodes every port and selects its 64-bit word
// among W (N x W compares and N 64-bit W-to-1 selects, the pool's N^2 LUTs, issue 29). The
// merge rule needs the walker ports (a merged read completes with another walker's fill), so
// CTX_RESP 2 requires ATTR_MERGE 0. With CTX_RESP 0 those ports are one unused bit (the
// other benches leave them open).
`timescale 1ns/1ps
`default_nettype none
module svo_walker_pool #(
    parameter POS_W        = 40,
    parameter T_W          = 62,
    parameter STACK_DEPTH  = 21,
    parameter MAX_STEPS    = 100000,
    parameter STEP_LATENCY = 3,
    parameter TAG_W        = 1,
    parameter CONTEXTS     = 1,                 // contexts per walker
    parameter WALKERS      = 1,
    parameter K            = 1,                 // walk-issue lanes (HwConfig::walk_lanes): 1 or 2
    parameter CW           = WALKERS * CONTEXTS > 1 ? $clog2(WALKERS * CONTEXTS) : 1,  // context index bits
    parameter CTX_RESP     = 0,                 // per-context response ports: 1 node words, 2 all (below)
    parameter ATTR_MERGE   = 1,                 // 1: the attribute-merge rule below; 0: every read goes out
    // walker_pool.response_register_cycles / request_register_cycles (walker_pool.rs,
    // "Registered response and request"): 0 or 1 each (below, "Registers").
    parameter RESPONSE_REGISTER_CYCLES = 0,
    parameter REQUEST_REGISTER_CYCLES  = 0,
    parameter CRN          = CTX_RESP != 0 ? WALKERS * CONTEXTS : 1,  // their count (do not set)
    parameter CRW          = CTX_RESP == 2 ? 64 : 32                 // their width (do not set)
) (
    input  wire                   clk,
    input  wire                   rst,
    // K walk lanes, packed, lane j at [j*WIDTH +: WIDTH]: lane j is taken iff in_valid[j] &&
    // in_ready[j]; the source offers a prefix, the pool takes a prefix.
    input  wire [K-1:0]             in_valid,
    output wire [K-1:0]             in_ready,
    input  wire [K-1:0]             in_enter,
    input  wire [K*3*(T_W+1)-1:0]   in_t0,
    input  wire [K*3*(T_W+1)-1:0]   in_t1,
    input  wire [K*3*(POS_W+1)-1:0] in_o,
    input  wire [K*3*POS_W-1:0]     in_half,
    input  wire [K*3-1:0]           in_zero,
    input  wire [K*3-1:0]           in_neg,
    input  wire [K*32-1:0]          in_node_base,
    input  wire [K*32-1:0]          in_attr_base,
    input  wire [K*TAG_W-1:0]       in_tag,
    // One request port per walker (port w: walker w's reads), one response port per walker
    // (any context's response may come on any port).
    output wire [WALKERS-1:0]     mem_req_valid,
    input  wire [WALKERS-1:0]     mem_req_ready,
    output wire [WALKERS-1:0]     mem_req_attr,
    output wire [WALKERS*32-1:0]  mem_req_addr,
    output wire [WALKERS*CW-1:0]  mem_req_ctx,
    input  wire [WALKERS-1:0]     mem_resp_valid,
    input  wire [WALKERS*CW-1:0]  mem_resp_ctx,
    input  wire [WALKERS*64-1:0]  mem_resp_data,
    input  wire [CRN-1:0]         ctx_resp_valid,
    input  wire [CRN*CRW-1:0]     ctx_resp_data,
    // K retire lanes: lane j the j-th walk to retire in this cycle (finish order); valid is a
    // prefix; lane j retires iff out_valid[j] && out_ready[j] (the sink takes a prefix).
    output wire [K-1:0]           out_valid,
    input  wire [K-1:0]           out_ready,
    output wire [K*2-1:0]         out_outcome,
    output wire [K*T_W-1:0]       out_t,
    output wire [K*60-1:0]        out_voxel,
    output wire [K*64-1:0]        out_attr_data,
    output wire [K*TAG_W-1:0]     out_tag,
    output reg                    err_resp
);
    localparam R = CONTEXTS;
    localparam W = WALKERS;
    localparam N = W * R;                         // contexts in all; context n is walker n / R's
    localparam WI = W > 1 ? $clog2(W) : 1;
    localparam RI = R > 1 ? $clog2(R) : 1;        // a context's index within its walker

    generate
        if (R < 1 || R > 16 || W < 1 || W > 64) begin : bad_contexts
            svo_walker_pool_needs_1_to_64_walkers_of_1_to_16_contexts bad();
        end
        // Walk issue of width K (testbench/README.md): 1 or 2 lanes are built.
        if (K < 1 || K > 2) begin : unsupported_lanes
            svo_walker_pool_builds_1_or_2_walk_lanes bad();
        end
        // The registered response and request of the model (issue 29): one stage at most.
        if (RESPONSE_REGISTER_CYCLES > 1) begin : unsupported_response_register
            svo_walker_pool_builds_response_register_cycles_0_or_1 bad();
        end
        if (REQUEST_REGISTER_CYCLES > 1) begin : unsupported_request_register
            svo_walker_pool_builds_request_register_cycles_0_or_1 bad();
        end
        // Records on the context ports (CTX_RESP 2) leave the merge rule without its fills.
        if (CTX_RESP > 2 || (CTX_RESP == 2 && ATTR_MERGE != 0)) begin : unsupported_ctx_resp
            svo_walker_pool_ctx_resp_2_needs_attr_merge_0 bad();
        end
    endgenerate

    // Per context.
    wire [N-1:0] e_in_ready, e_issue_req, e_ev_lat, e_ev_disp, e_ev_resp, e_req_valid,
                 e_req_attr, e_out_valid;
    reg  [N-1:0] e_resp_valid;
    wire [N-1:0] e_take, e_out_ready;
    reg  [N-1:0] e_issue_grant, e_req_ready;
    wire [31:0]    e_req_addr  [0:N-1];
    reg  [63:0]    e_resp_data [0:N-1];
    // Per walker its K result ports (port j at [j*WIDTH +: WIDTH]): its oldest finished
    // context's result, and at K = 2 its second oldest's.
    wire [K*2-1:0]     w_outcome   [0:W-1];
    wire [K*T_W-1:0]   w_t         [0:W-1];
    wire [K*60-1:0]    w_voxel     [0:W-1];
    wire [K*64-1:0]    w_attr_data [0:W-1];
    wire [K*TAG_W-1:0] w_tag       [0:W-1];

    // ---------------------------------------------------------------- per walker: the age order
    // A context is in at most one queue at a time (issue, send, retire) and a walker's issue and
    // send queues hold only its own contexts, so one R x R order per walker serves them:
    // older[n][k] (context n joined its queue before context k of n's walker), updated with
    // each cycle's events ranked as the model wakes them (step latencies ended, then the
    // dispatched walk, then completions by request age: req_older[n][k], n's read out was sent
    // before k's; one send a walker and cycle, so within a walker that is the send order).
    wire [N-1:0] ev = e_ev_lat | e_ev_disp | e_ev_resp;
    reg  [N-1:0] disp_lane;                       // the context's walk came on lane 1 (K = 2)
    reg  [R-1:0] older     [0:N-1];
    reg  [R-1:0] req_older [0:N-1];
    reg  [R-1:0] older_eff [0:N-1];               // this cycle's order, events included
    integer w, i_e, k_e, w_o, k_o, i_r, p_r, w_q, k_q, i_q, w_s, v_s, k_s;
    always @* begin
        for (i_e = 0; i_e < N; i_e = i_e + 1)
            for (k_e = 0; k_e < R; k_e = k_e + 1) begin
                if ((i_e / R) * R + k_e == i_e) older_eff[i_e][k_e] = 1'b0;
                else if (ev[i_e] && ev[(i_e / R) * R + k_e])
                    older_eff[i_e][k_e] = (e_ev_lat[i_e] && !e_ev_lat[(i_e / R) * R + k_e])
                        || (e_ev_disp[i_e] && e_ev_resp[(i_e / R) * R + k_e])
                        // two walks dispatched in one cycle (K = 2): dispatch order
                        || (e_ev_disp[i_e] && e_ev_disp[(i_e / R) * R + k_e]
                            && !disp_lane[i_e] && disp_lane[(i_e / R) * R + k_e])
                        || (e_ev_resp[i_e] && e_ev_resp[(i_e / R) * R + k_e] && req_older[i_e][k_e]);
                else if (ev[(i_e / R) * R + k_e]) older_eff[i_e][k_e] = 1'b1;  // joins behind
                else if (ev[i_e]) older_eff[i_e][k_e] = 1'b0;
                else older_eff[i_e][k_e] = older[i_e][k_e];
            end
    end
    // The oldest member of a walker's queue.
    function automatic [R-1:0] oldest(input [R-1:0] member, input [R*R-1:0] ord);
        integer a, b;
        reg beaten;
        begin
            for (a = 0; a < R; a = a + 1) begin
                beaten = 1'b0;
                for (b = 0; b < R; b = b + 1)
                    if (member[b] && ord[b * R + a]) beaten = 1'b1;
                oldest[a] = member[a] && !beaten;
            end
        end
    endfunction
    reg [R*R-1:0] ord_w [0:W-1];
    reg [N-1:0] send_pick, fin_head, fin_head2;
    always @* begin
        for (w_o = 0; w_o < W; w_o = w_o + 1) begin
            for (k_o = 0; k_o < R; k_o = k_o + 1) ord_w[w_o][k_o * R +: R] = older_eff[w_o * R + k_o];
            e_issue_grant[w_o * R +: R] = oldest(e_issue_req[w_o * R +: R], ord_w[w_o]);
            send_pick[w_o * R +: R] = oldest(e_req_valid[w_o * R +: R], ord_w[w_o]);
            fin_head[w_o * R +: R] = oldest(e_out_valid[w_o * R +: R], ord_w[w_o]);
            // (K = 2: the walker's second oldest finished walk, lane 1's candidate)
            fin_head2[w_o * R +: R] = K < 2 || R < 2 ? {R{1'b0}}
                : oldest(e_out_valid[w_o * R +: R] & ~fin_head[w_o * R +: R], ord_w[w_o]);
        end
    end

    // ---------------------------------------------------------------- request ports
    reg  [N-1:0]  fill;                           // the read out is an attribute fill
    reg  [31:0]   fill_addr [0:N-1];
    reg  [N-1:0]  merged;                         // the read out rides on another's fill
    reg  [CW-1:0] merged_on [0:N-1];
    reg  [N-1:0]  responding;                     // the memory answers context n's read now
    // The response register (RESPONSE_REGISTER_CYCLES 1): the memory's cycle C is seen in
    // C + 1, in the wake-up's completion place, by request age. The fills' state is the
    // memory's: `responding` reads the ports, so a fill answered in C is not in flight in
    // C + 1. The contexts a response reaches (its own, the reads merged onto its fill) are
    // decoded before the register (a read never merges onto a fill answered in its cycle,
    // so C's merged reads are C + 1's): the wake-up starts from the one-hot's flip-flops.
    reg  [N-1:0]   d_valid, d_own;                // decoded in C: answered; on its own port
    reg  [WI-1:0]  d_port [0:N-1];                // the walker port that answers it
    wire [N-1:0]   r_valid_n, r_own;
    wire [WI-1:0]  r_port [0:N-1];
    wire [W-1:0]   r_valid;                       // the ports' valids (err_resp)
    wire [W*64-1:0] r_data;
    wire [CRN*CRW-1:0] r_cdata;
    always @* begin
        for (i_r = 0; i_r < N; i_r = i_r + 1) begin
            // The memory's view: a response for context n on some port in this cycle.
            responding[i_r] = CTX_RESP != 0 && ctx_resp_valid[i_r % CRN];
            d_own[i_r] = responding[i_r];
            d_valid[i_r] = d_own[i_r];
            d_port[i_r] = {WI{1'b0}};
            // (CTX_RESP 2: nothing on the walker ports; no port loop, no N x W decode)
            if (CTX_RESP != 2) for (p_r = 0; p_r < W; p_r = p_r + 1) begin
                if (mem_resp_valid[p_r] && mem_resp_ctx[p_r*CW +: CW] == i_r[CW-1:0])
                    responding[i_r] = 1'b1;
                // The contexts' view: the addressed context, and every read merged onto its
                // fill (no read merges onto a node read, which own ports carry).
                if (mem_resp_valid[p_r] && (mem_resp_ctx[p_r*CW +: CW] == i_r[CW-1:0]
                        || (merged[i_r] && mem_resp_ctx[p_r*CW +: CW] == merged_on[i_r]))) begin
                    d_valid[i_r] = 1'b1;
                    if (!d_own[i_r]) d_port[i_r] = p_r[WI-1:0];
                end
            end
        end
    end
    genvar g, gr, gq;
    generate
        if (RESPONSE_REGISTER_CYCLES != 0) begin : resp_reg
            reg [N-1:0]      q_valid_n, q_own;
            reg [WI-1:0]     q_port [0:N-1];
            reg [W-1:0]      q_valid;
            reg [W*64-1:0]   q_data;
            reg [CRN*CRW-1:0] q_cdata;
            always @(posedge clk) begin
                q_valid_n <= rst ? {N{1'b0}} : d_valid;
                q_valid <= rst ? {W{1'b0}} : mem_resp_valid;
                q_own <= d_own;
                q_data <= mem_resp_data;
                q_cdata <= ctx_resp_data;
            end
            for (gq = 0; gq < N; gq = gq + 1) begin : ctx
                always @(posedge clk) q_port[gq] <= d_port[gq];
                assign r_port[gq] = q_port[gq];
            end
            assign r_valid_n = q_valid_n;
            assign r_own = q_own;
            assign r_valid = q_valid;
            assign r_data = q_data;
            assign r_cdata = q_cdata;
        end else begin : resp_wire
            for (gq = 0; gq < N; gq = gq + 1) begin : ctx
                assign r_port[gq] = d_port[gq];
            end
            assign r_valid_n = d_valid;
            assign r_own = d_own;
            assign r_valid = mem_resp_valid;
            assign r_data = mem_resp_data;
            assign r_cdata = ctx_resp_data;
        end
    endgenerate
    reg [63:0] c_word;                            // a context port's word, widened
    always @* begin
        for (i_r = 0; i_r < N; i_r = i_r + 1) begin
            e_resp_valid[i_r] = r_valid_n[i_r];
            c_word = 64'd0;
            c_word[CRW-1:0] = r_cdata[(i_r % CRN)*CRW +: CRW];
            e_resp_data[i_r] = CTX_RESP == 2 || r_own[i_r] ? c_word : r_data[r_port[i_r]*64 +: 64];
        end
    end
    // Walker w's port: its oldest waiting read (send_pick, one-hot), an AND-OR of its R
    // contexts, no priority chain (this and the other one-hot picks as AND-OR forms took the
    // pool at 1 x 16 from 107.5 to 126.6 MHz by the clock rule, testbench/README.md).
    reg  [CW-1:0] pick      [0:W-1];              // walker w's port's context
    reg  [31:0]   p_addr    [0:W-1];
    reg  [W-1:0]  p_attr, want, merge, snd, go;
    reg  [CW-1:0] merge_to  [0:W-1];
    reg  [N-1:0]  sent;
    reg  [N-1:0]  m_hit, m_low;                   // the fills a walker's read matches; the lowest
    // The read at walker w's memory port (after the request register, if any).
    wire [W-1:0]  o_valid, o_attr;
    wire [N-1:0]  o_sel;
    wire [CW-1:0] o_ctx  [0:W-1];
    wire [31:0]   o_addr [0:W-1];
    /* verilator lint_off UNUSEDSIGNAL */
    integer n_q;                                  // a context index: its low CW bits matter
    /* verilator lint_on UNUSEDSIGNAL */
    always @* begin
        for (w_q = 0; w_q < W; w_q = w_q + 1) begin
            pick[w_q] = {CW{1'b0}};
            p_addr[w_q] = 32'd0;
            p_attr[w_q] = 1'b0;
            for (k_q = 0; k_q < R; k_q = k_q + 1) begin
                n_q = w_q * R + k_q;
                pick[w_q] = pick[w_q] | ({CW{send_pick[n_q]}} & n_q[CW-1:0]);
                p_addr[w_q] = p_addr[w_q] | ({32{send_pick[n_q]}} & e_req_addr[n_q]);
                p_attr[w_q] = p_attr[w_q] | (send_pick[n_q] & e_req_attr[n_q]);
            end
            want[w_q] = |send_pick[w_q * R +: R];
            // A read of a record whose fill is in flight (and not done in this cycle) merges:
            // its address against every context's fill (W x N compares, cross-walker), onto the
            // lowest such fill (two fills of one record are out when two walkers sent it in one
            // cycle): the matches' lowest bit (m & -m), OR-encoded. Decided where the read
            // meets the memory (after the request register), as the model's memory decides it
            // in the cycle the read arrives.
            for (i_q = 0; i_q < N; i_q = i_q + 1)
                m_hit[i_q] = fill[i_q] && fill_addr[i_q] == o_addr[w_q] && !responding[i_q];
            merge[w_q] = ATTR_MERGE != 0 && o_valid[w_q] && o_attr[w_q] && |m_hit;
            m_low = m_hit & (~m_hit + 1'b1);
            merge_to[w_q] = {CW{1'b0}};
            for (i_q = 0; i_q < N; i_q = i_q + 1)
                merge_to[w_q] = merge_to[w_q] | ({CW{m_low[i_q]}} & i_q[CW-1:0]);
        end
    end
    // The port's handshake, apart from the pick: a memory's ready may depend on the read's
    // kind (svo_top: a node read is always taken, an attribute read waits for AR).
    // go: the port's read leaves (to the memory, or merged); snd: the walker's pick is taken
    // (the context's read counts as sent: its request age, the walker's send order).
    integer w_k;
    always @* begin
        sent = {N{1'b0}};
        for (w_k = 0; w_k < W; w_k = w_k + 1) begin
            go[w_k] = o_valid[w_k] && (merge[w_k] || mem_req_ready[w_k]);
            // (with the register: the memory's ready, not the merge, frees it for a pick)
            snd[w_k] = REQUEST_REGISTER_CYCLES != 0
                ? want[w_k] && (!o_valid[w_k] || mem_req_ready[w_k]) : go[w_k];
            if (snd[w_k]) sent[w_k * R +: R] = send_pick[w_k * R +: R];
        end
        e_req_ready = sent;
    end
    // The request register (REQUEST_REGISTER_CYCLES 1): C's picks are at the memory port in
    // C + 1, in pick order (ids by pick). It holds a read the memory refuses (AR busy; never
    // on the memories timed as the model's, which take every read).
    generate
        for (g = 0; g < W; g = g + 1) begin : port
            if (REQUEST_REGISTER_CYCLES != 0) begin : req_reg
                reg          q_valid, q_attr;
                reg [R-1:0]  q_sel;
                reg [CW-1:0] q_ctx;
                reg [31:0]   q_addr;
                always @(posedge clk) begin
                    if (rst) q_valid <= 1'b0;
                    else if (snd[g] || go[g]) q_valid <= snd[g];
                    if (snd[g]) begin
                        q_attr <= p_attr[g];
                        q_sel <= send_pick[g*R +: R];
                        q_ctx <= pick[g];
                        q_addr <= p_addr[g];
                    end
                end
                assign o_valid[g] = q_valid;
                assign o_attr[g] = q_attr;
                assign o_sel[g*R +: R] = q_sel;
                assign o_ctx[g] = q_ctx;
                assign o_addr[g] = q_addr;
            end else begin : req_wire
                assign o_valid[g] = want[g];
                assign o_attr[g] = p_attr[g];
                assign o_sel[g*R +: R] = send_pick[g*R +: R];
                assign o_ctx[g] = pick[g];
                assign o_addr[g] = p_addr[g];
            end
            assign mem_req_valid[g] = o_valid[g] && !merge[g];
            assign mem_req_attr[g] = o_attr[g];
            assign mem_req_addr[g*32 +: 32] = o_addr[g];
            assign mem_req_ctx[g*CW +: CW] = o_ctx[g];
        end
    endgenerate

    // ---------------------------------------------------------------- request ages, pool-wide
    // Where the model orders contexts of different walkers: completions in one cycle by request
    // age (the node memory's id order) — observable only in the retire order (below). A read's
    // id is {send stamp, rank}: the stamp counts the cycles in which something was sent, the
    // rank is the read's place among that cycle's sends (at most one a walker): the reads that
    // waited for their port first, walkers ascending, then new ones in wake-up order (step
    // latencies by walker, the dispatched walk, completions by their previous read's id). W x W
    // rank compares, not N x N. Ids compare modulo 2^ID_W: exact while no read stays out across
    // 2^(SEND_STAMP_W-1) sending cycles (svo_top's node memory answers in a fixed latency).
    localparam SEND_STAMP_W = 24;
    localparam RK_W = W > 1 ? $clog2(W) : 1;
    localparam ID_W = SEND_STAMP_W + RK_W;
    function automatic id_before(input [ID_W-1:0] a, input [ID_W-1:0] b);
        reg [ID_W-1:0] d;
        begin
            d = a - b;
            id_before = d[ID_W-1];
        end
    endfunction
    reg [ID_W-1:0]         req_id [0:N-1];
    reg [SEND_STAMP_W-1:0] sstamp;
    reg [W-1:0]            s_new, s_lat, s_disp, s_resp, s_dl;
    reg [ID_W-1:0]         s_oid  [0:W-1];          // the sender's previous read's id
    reg [RK_W-1:0]         s_rank [0:W-1];
    reg                    s_before;
    always @* begin
        for (w_s = 0; w_s < W; w_s = w_s + 1) begin
            s_new[w_s] = 1'b0;
            s_lat[w_s] = 1'b0;
            s_disp[w_s] = 1'b0;
            s_resp[w_s] = 1'b0;
            s_dl[w_s] = 1'b0;
            s_oid[w_s] = {ID_W{1'b0}};
            // (send_pick is one-hot: AND-OR, no priority chain)
            for (k_s = 0; k_s < R; k_s = k_s + 1) begin
                s_new[w_s] = s_new[w_s] | (send_pick[w_s * R + k_s] & ev[w_s * R + k_s]);
                s_lat[w_s] = s_lat[w_s] | (send_pick[w_s * R + k_s] & e_ev_lat[w_s * R + k_s]);
                s_disp[w_s] = s_disp[w_s] | (send_pick[w_s * R + k_s] & e_ev_disp[w_s * R + k_s]);
                s_resp[w_s] = s_resp[w_s] | (send_pick[w_s * R + k_s] & e_ev_resp[w_s * R + k_s]);
                s_dl[w_s] = s_dl[w_s] | (send_pick[w_s * R + k_s] & disp_lane[w_s * R + k_s]);
                s_oid[w_s] = s_oid[w_s] | ({ID_W{send_pick[w_s * R + k_s]}} & req_id[w_s * R + k_s]);
            end
        end
        for (w_s = 0; w_s < W; w_s = w_s + 1) begin
            s_rank[w_s] = {RK_W{1'b0}};
            for (v_s = 0; v_s < W; v_s = v_s + 1) begin
                s_before = (!s_new[v_s] && s_new[w_s])
                    || (!s_new[v_s] && !s_new[w_s] && v_s < w_s)
                    || (s_new[v_s] && s_new[w_s]
                        && ((s_lat[v_s] && (!s_lat[w_s] || v_s < w_s))
                            || (s_disp[v_s] && s_resp[w_s])
                            || (s_disp[v_s] && s_disp[w_s] && !s_dl[v_s] && s_dl[w_s])
                            || (s_resp[v_s] && s_resp[w_s] && id_before(s_oid[v_s], s_oid[w_s]))));
                if (v_s != w_s && snd[v_s] && s_before) s_rank[w_s] = s_rank[w_s] + 1'b1;
            end
        end
    end

    // ---------------------------------------------------------------- dispatch and retire
    // (the header's retire and dispatch: svo_walker_pool_retire.v, svo_walker_pool_dispatch.v)
    wire [N-1:0]      busy;
    wire [N-1:0]      retiring;                   // e_out_ready: the retire lanes' picks
    wire [K*N-1:0]    take;                       // lane j's context: [j*N +: N]
    wire [K*WI-1:0]   lane_w;                     // retire lane j's walker
    wire [K-1:0]      lane_second;                // ... its second oldest (its result port 1)
    /* verilator lint_off UNUSEDSIGNAL */
    wire              have1;                      // (unused at K = 1)
    /* verilator lint_on UNUSEDSIGNAL */
    wire [N*ID_W-1:0] req_id_flat;
    wire [N-1:0] fin_ev = ev & e_out_valid;      // finished in this cycle (out_valid rises with an event)
    genvar gi;
    generate
        for (gi = 0; gi < N; gi = gi + 1) begin : ids
            assign req_id_flat[gi * ID_W +: ID_W] = req_id[gi];
        end
    endgenerate
    svo_walker_pool_retire #(.WALKERS(W), .CONTEXTS(R), .K(K), .ID_W(ID_W)) u_retire (
        .clk(clk), .rst(rst), .fin_head(fin_head), .fin_head2(fin_head2), .fin_ev(fin_ev),
        .ev_lat(e_ev_lat), .ev_disp(e_ev_disp), .disp_lane(disp_lane), .req_id(req_id_flat),
        .out_ready(out_ready), .have1(have1), .retiring(retiring), .lane_w(lane_w),
        .lane_second(lane_second));
    svo_walker_pool_dispatch #(.WALKERS(W), .CONTEXTS(R), .K(K)) u_dispatch (
        .clk(clk), .rst(rst), .in_valid(in_valid), .in_ready(in_ready), .retiring(retiring),
        .take(take), .busy(busy));
    assign e_out_ready = retiring;
    assign e_take = K > 1 ? take[0 +: N] | take[(K-1)*N +: N] : take[0 +: N];
    // The lane a context's walk came on (the wake-up order's ev_disp: dispatch order).
    wire [N-1:0] e_lane = K > 1 ? take[(K-1)*N +: N] : {N{1'b0}};
    always @(posedge clk)
        disp_lane <= rst ? {N{1'b0}} : (disp_lane & ~e_take) | e_lane;

    // Retire lane j's result: its walker's result port 0 (the walker's oldest finished
    // context), or port 1 (its second oldest: lane 1 when both lanes retire from one walker).
    genvar gl;
    assign out_valid[0] = |e_out_valid;
    generate
        if (K > 1) begin : out_lane1
            assign out_valid[1] = have1;
        end
        for (gl = 0; gl < K; gl = gl + 1) begin : out_lane
            wire [WI-1:0] lw_w = lane_w[gl * WI +: WI];
            wire          sec = lane_second[gl];
            assign out_outcome[gl*2 +: 2] = sec ? w_outcome[lw_w][(K-1)*2 +: 2] : w_outcome[lw_w][0 +: 2];
            assign out_t[gl*T_W +: T_W] = sec ? w_t[lw_w][(K-1)*T_W +: T_W] : w_t[lw_w][0 +: T_W];
            assign out_voxel[gl*60 +: 60] = sec ? w_voxel[lw_w][(K-1)*60 +: 60] : w_voxel[lw_w][0 +: 60];
            assign out_attr_data[gl*64 +: 64] = sec ? w_attr_data[lw_w][(K-1)*64 +: 64]
                                                    : w_attr_data[lw_w][0 +: 64];
            assign out_tag[gl*TAG_W +: TAG_W] = sec ? w_tag[lw_w][(K-1)*TAG_W +: TAG_W]
                                                    : w_tag[lw_w][0 +: TAG_W];
        end
    endgenerate

    // Per context state (a generate loop: Verilator does not unroll large loops of delayed
    // assignments to arrays).
    genvar gn;
    generate
        for (gn = 0; gn < N; gn = gn + 1) begin : ctx_state
            localparam GW = gn / R;               // its walker
            reg [R-1:0] req_older_nx;
            integer kk;
            always @* begin
                req_older_nx = req_older[gn];
                for (kk = 0; kk < R; kk = kk + 1)
                    if (sent[gn] || sent[GW * R + kk]) req_older_nx[kk] = GW * R + kk != gn && sent[GW * R + kk];
            end
            always @(posedge clk) begin
                older[gn] <= older_eff[gn];
                req_older[gn] <= req_older_nx;
                if (snd[GW] && send_pick[gn]) req_id[gn] <= {sstamp, s_rank[GW]};
                // The memory's state: set when the read leaves the port, a fill ended when
                // the memory answers it, a merged read when its context sees the answer.
                if (go[GW] && o_sel[gn]) begin
                    fill_addr[gn] <= o_addr[GW];
                    merged_on[gn] <= merge_to[GW];
                end
                if (rst) begin
                    fill[gn] <= 1'b0;
                    merged[gn] <= 1'b0;
                end else if (go[GW] && o_sel[gn]) begin
                    fill[gn] <= !merge[GW] && o_attr[GW];
                    merged[gn] <= merge[GW];
                end else begin
                    if (responding[gn]) fill[gn] <= 1'b0;
                    if (e_resp_valid[gn]) merged[gn] <= 1'b0;
                end
            end
        end
    endgenerate
    always @(posedge clk) begin
        if (rst) begin
            err_resp <= 1'b0;
            sstamp <= {SEND_STAMP_W{1'b0}};
        end else begin
            if (|snd) sstamp <= sstamp + 1'b1;
            for (w = 0; w < W; w = w + 1)
                // (CTX_RESP 2: the walker ports carry nothing, so any response there)
                if (r_valid[w] && (CTX_RESP == 2 || !(|e_resp_valid))) err_resp <= 1'b1;
`ifndef SYNTHESIS
            // The dispatcher's copy of the walkers' state (busy) must be theirs.
            if (e_in_ready != (~busy | retiring)) err_resp <= 1'b1;
`endif
        end
    end

    // ---------------------------------------------------------------- the walkers
    // R = 1: svo_walker, whose registers are the walker's one context (the estimate's
    // calibrated walker, rtl_model/src/cost/structures.rs `walker_contexts`: nothing added at
    // R = 1). R > 1: svo_walker_barrel, one step datapath and the R contexts' state in RAMs.
    generate
        if (R == 1) begin : single
            // The walks offered, one word per lane (lane 1 a copy of lane 0's at K = 1, never
            // taken), so that a walker at R = 1 selects its lane: its registers are its context.
            localparam LWW = 1 + 6*(T_W+1) + 3*(POS_W+1) + 3*POS_W + 3 + 3 + 32 + 32 + TAG_W;
            wire [LWW-1:0] lw [0:1];
            for (gl = 0; gl < 2; gl = gl + 1) begin : lane
                localparam L = gl < K ? gl : 0;
                assign lw[gl] = {in_enter[L], in_t0[L*3*(T_W+1) +: 3*(T_W+1)],
                    in_t1[L*3*(T_W+1) +: 3*(T_W+1)], in_o[L*3*(POS_W+1) +: 3*(POS_W+1)],
                    in_half[L*3*POS_W +: 3*POS_W], in_zero[L*3 +: 3], in_neg[L*3 +: 3],
                    in_node_base[L*32 +: 32], in_attr_base[L*32 +: 32], in_tag[L*TAG_W +: TAG_W]};
            end
            for (g = 0; g < N; g = g + 1) begin : ctx
                // Its lane's walk (the dispatcher's take of lane 1, else lane 0).
                wire [LWW-1:0] wd = lw[e_lane[g]];
                wire [1:0]     r_outcome;
                wire [T_W-1:0] r_t;
                wire [59:0]    r_voxel;
                wire [63:0]    r_attr_data;
                wire [TAG_W-1:0] r_tag;
                /* verilator lint_off PINCONNECTEMPTY */
                svo_walker #(.POS_W(POS_W), .T_W(T_W), .STACK_DEPTH(STACK_DEPTH),
                    .MAX_STEPS(MAX_STEPS), .STEP_LATENCY(STEP_LATENCY), .TAG_W(TAG_W)
                ) u_walker (.clk(clk), .rst(rst), .in_valid(e_take[g]), .in_ready(e_in_ready[g]),
                    .in_enter(wd[LWW-1]), .in_t0(wd[LWW-2 -: 3*(T_W+1)]),
                    .in_t1(wd[LWW-2-3*(T_W+1) -: 3*(T_W+1)]),
                    .in_o(wd[LWW-2-6*(T_W+1) -: 3*(POS_W+1)]),
                    .in_half(wd[70+TAG_W+3*POS_W-1 -: 3*POS_W]), .in_zero(wd[70+TAG_W-1 -: 3]),
                    .in_neg(wd[67+TAG_W-1 -: 3]), .in_node_base(wd[64+TAG_W-1 -: 32]),
                    .in_attr_base(wd[32+TAG_W-1 -: 32]), .in_tag(wd[TAG_W-1:0]),
                    .mem_req_valid(e_req_valid[g]), .mem_req_ready(e_req_ready[g]),
                    .mem_req_attr(e_req_attr[g]), .mem_req_addr(e_req_addr[g]),
                    .mem_resp_valid(e_resp_valid[g]), .mem_resp_data(e_resp_data[g]),
                    .out_valid(e_out_valid[g]), .out_ready(e_out_ready[g]),
                    .out_outcome(r_outcome), .out_t(r_t), .out_voxel(r_voxel),
                    .out_level(), .out_attr(), .out_entry_axis(), .out_steps(), .out_fetches(),
                    .out_attr_data(r_attr_data), .out_tag(r_tag), .visit_valid(),
                    .visit_level(), .visit_coords(), .issue_grant(e_issue_grant[g]),
                    .issue_req(e_issue_req[g]), .ev_lat(e_ev_lat[g]), .ev_disp(e_ev_disp[g]),
                    .ev_resp(e_ev_resp[g]));
                /* verilator lint_on PINCONNECTEMPTY */
                // One context: a walker's second oldest never exists (port 1 is port 0).
                assign w_outcome[g] = {K{r_outcome}};
                assign w_t[g] = {K{r_t}};
                assign w_voxel[g] = {K{r_voxel}};
                assign w_attr_data[g] = {K{r_attr_data}};
                assign w_tag[g] = {K{r_tag}};
            end
        end else begin : barrel
            for (g = 0; g < W; g = g + 1) begin : walker
                wire [R*32-1:0] req_addr;
                reg  [R*64-1:0] w_resp_data;
                wire [K*R-1:0]  w_take;           // lane j's take: [j*R +: R]
                reg  [K*RI-1:0] w_fin;            // result port j's context (its local index)
                integer q;
                always @* for (q = 0; q < R; q = q + 1) w_resp_data[q*64 +: 64] = e_resp_data[g*R + q];
                // The walker's oldest and second oldest finished contexts (one-hot: OR-encoded).
                always @* begin
                    w_fin = {K*RI{1'b0}};
                    for (q = 0; q < R; q = q + 1) begin
                        if (fin_head[g*R + q]) w_fin[0 +: RI] = w_fin[0 +: RI] | q[RI-1:0];
                        if (fin_head2[g*R + q]) w_fin[(K-1)*RI +: RI] = w_fin[(K-1)*RI +: RI] | q[RI-1:0];
                    end
                end
                for (gr = 0; gr < R; gr = gr + 1) begin : ctx
                    assign e_req_addr[g*R + gr] = req_addr[gr*32 +: 32];
                end
                for (gr = 0; gr < K; gr = gr + 1) begin : lane
                    assign w_take[gr*R +: R] = take[gr*N + g*R +: R];
                end
                svo_walker_barrel #(.POS_W(POS_W), .T_W(T_W), .STACK_DEPTH(STACK_DEPTH),
                    .MAX_STEPS(MAX_STEPS), .STEP_LATENCY(STEP_LATENCY), .TAG_W(TAG_W),
                    .CONTEXTS(R), .RI(RI), .K(K)
                ) u_walker (.clk(clk), .rst(rst), .in_take(w_take),
                    .in_ready(e_in_ready[g*R +: R]), .in_enter(in_enter), .in_t0(in_t0),
                    .in_t1(in_t1), .in_o(in_o), .in_half(in_half), .in_zero(in_zero),
                    .in_neg(in_neg), .in_node_base(in_node_base), .in_attr_base(in_attr_base),
                    .in_tag(in_tag), .mem_req_valid(e_req_valid[g*R +: R]),
                    .mem_req_ready(e_req_ready[g*R +: R]), .mem_req_attr(e_req_attr[g*R +: R]),
                    .mem_req_addr(req_addr), .mem_resp_valid(e_resp_valid[g*R +: R]),
                    .mem_resp_data(w_resp_data), .out_valid(e_out_valid[g*R +: R]),
                    .out_ready(e_out_ready[g*R +: R]), .issue_grant(e_issue_grant[g*R +: R]),
                    .issue_req(e_issue_req[g*R +: R]), .ev_lat(e_ev_lat[g*R +: R]),
                    .ev_disp(e_ev_disp[g*R +: R]), .ev_resp(e_ev_resp[g*R +: R]),
                    .fin(w_fin), .out_outcome(w_outcome[g]), .out_t(w_t[g]),
                    .out_voxel(w_voxel[g]), .out_attr_data(w_attr_data[g]), .out_tag(w_tag[g]));
            end
        end
    endgenerate
endmodule
`default_nettype wire
