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
// request port per walker; one result port for the pool. The contexts issue only when granted,
// one slot a walker and cycle.
//
// The scheduler is the model's, per cycle:
//   wake-up order  a context moves on to its next op in the model's wake-up order: first those
//                  whose step latency ended (ev_lat: at most one a walker, in walker order,
//                  the order their slots issued), then the walk dispatched in the cycle before
//                  (ev_disp: its root read, or a root miss), then the contexts whose read
//                  completed (ev_resp) by request age (the node memory's (done, id) order).
//                  That order decides where the context joins the queue its next op needs:
//   issue          each walker's ready contexts issue round robin in the order they became
//                  ready (a FIFO), one a cycle (step_cycles 1), a newly ready one in the same
//                  cycle if none waits before it;
//   request port   one read a walker and cycle; reads waiting for the port (the send queue)
//                  go first, oldest first, then this cycle's new ones in wake-up order; the
//                  sends of one cycle are the node memory's ids in the order: waiting ones by
//                  walker, then new ones in wake-up order (req_older keeps it);
//   retire         finished walks leave in the order they finished, one a cycle for the pool,
//                  when the record FIFO is ready (out_ready); the context takes a new walk in
//                  the same cycle (the model retires before it dispatches);
//   dispatch       one walk a cycle, to the walker with the most free contexts (a context
//                  retiring in this cycle counts), the lowest index on ties, and there to its
//                  lowest free context (which free context takes it changes no cycle).
// The queues are one age order: a context is in at most one queue at a time, so one matrix
// older[i][j] (i's event came first) serves them all, updated with each cycle's events;
// within a cycle the events are ranked as above.
//
// Attribute reads that merge (the model's MSHR rule for uncached attribute reads with
// cache.line_bytes 8, memory/dram.rs `miss`): a record read while a fill of the same record is
// in flight from any walker (sent, its response not yet back, and not arriving in this cycle)
// is not sent: it completes with that fill, in the same cycle, after it (request age). Two
// reads of one record sent in the same cycle both go out (the model merges the second, with
// the same completion cycle). With one context in all no read can merge, so any node memory
// works; with several, the hardware file must use uncached attributes with 8-byte lines
// (svo_top refuses other node memories), where this rule is the model's exactly.
//
// The memory: per walker mem_req_* one read a cycle with its context (mem_req_ctx, the pool's
// context index n = walker·CONTEXTS + k); responses in any order, each with its context
// (mem_resp_ctx), on any port, but at most one node or leaf word (the words that chain a read in
// the cycle they arrive) for one walker in a cycle — svo_top returns walker w's reads on its own
// master; records of merged reads may complete several a cycle. Sticky err_resp: a response for
// a context that has no read out, or two chaining words for one walker in a cycle.
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
    parameter CW           = WALKERS * CONTEXTS > 1 ? $clog2(WALKERS * CONTEXTS) : 1  // context index bits
) (
    input  wire                   clk,
    input  wire                   rst,
    input  wire                   in_valid,
    output wire                   in_ready,
    input  wire                   in_enter,
    input  wire [3*(T_W+1)-1:0]   in_t0,
    input  wire [3*(T_W+1)-1:0]   in_t1,
    input  wire [3*(POS_W+1)-1:0] in_o,
    input  wire [3*POS_W-1:0]     in_half,
    input  wire [2:0]             in_zero,
    input  wire [2:0]             in_neg,
    input  wire [31:0]            in_node_base,
    input  wire [31:0]            in_attr_base,
    input  wire [TAG_W-1:0]       in_tag,
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
    output wire                   out_valid,
    input  wire                   out_ready,
    output wire [1:0]             out_outcome,
    output wire [T_W-1:0]         out_t,
    output wire [59:0]            out_voxel,
    output wire [63:0]            out_attr_data,
    output wire [TAG_W-1:0]       out_tag,
    output reg                    err_resp
);
    localparam R = CONTEXTS;
    localparam W = WALKERS;
    localparam N = W * R;                         // contexts in all; context n is walker n / R's
    localparam WI = W > 1 ? $clog2(W) : 1;
    localparam RI = R > 1 ? $clog2(R) : 1;        // a context's index within its walker

    generate
        if (R < 1 || R > 16 || W < 1 || W > 16 || N > 64) begin : bad_contexts
            svo_walker_pool_needs_1_to_16_walkers_of_1_to_16_contexts bad();
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
    // Per walker: the result of the context being retired.
    wire [1:0]     w_outcome   [0:W-1];
    wire [T_W-1:0] w_t         [0:W-1];
    wire [59:0]    w_voxel     [0:W-1];
    wire [63:0]    w_attr_data [0:W-1];
    wire [TAG_W-1:0] w_tag     [0:W-1];
    wire [W-1:0]   w_err;
    function automatic [WI-1:0] walker_of(input integer n);
        /* verilator lint_off UNUSEDSIGNAL */
        integer q;                                // below W: only its low WI bits matter
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            q = n / R;
            walker_of = q[WI-1:0];
        end
    endfunction

    function automatic [RI-1:0] local_of(input integer n);
        /* verilator lint_off UNUSEDSIGNAL */
        integer q;                                // below R: only its low RI bits matter
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            q = n % R;
            local_of = q[RI-1:0];
        end
    endfunction

    // ---------------------------------------------------------------- the age orders
    reg  [N-1:0] older     [0:N-1];               // older[i][j]: i joined its queue before j
    reg  [N-1:0] req_older [0:N-1];               // i's read out was sent before j's
    wire [N-1:0] ev = e_ev_lat | e_ev_disp | e_ev_resp;
    reg  [N-1:0] older_eff [0:N-1];               // this cycle's order, events included
    integer i, j, w, p;
    integer i_o, w_g, i_r, p_r, i_q, w_q, i_d, w_d, i_f;
    always @* begin
        for (i = 0; i < N; i = i + 1)
            for (j = 0; j < N; j = j + 1) begin
                if (i == j) older_eff[i][j] = 1'b0;
                else if (ev[i] && ev[j])
                    // Both moved on in this cycle: the wake-up order (step latencies ended
                    // in the order the slots issued, walkers ascending; then the dispatched
                    // walk; then completions by request age).
                    older_eff[i][j] = (e_ev_lat[i] && (!e_ev_lat[j] || walker_of(i) < walker_of(j)))
                                   || (e_ev_disp[i] && e_ev_resp[j])
                                   || (e_ev_resp[i] && e_ev_resp[j] && req_older[i][j]);
                else if (ev[j]) older_eff[i][j] = 1'b1;   // j joins behind everyone
                else if (ev[i]) older_eff[i][j] = 1'b0;
                else older_eff[i][j] = older[i][j];
            end
    end
    // The oldest member of each queue.
    function automatic [N-1:0] oldest(input [N-1:0] member, input [N*N-1:0] ord);
        integer a, b;
        reg beaten;
        begin
            for (a = 0; a < N; a = a + 1) begin
                beaten = 1'b0;
                for (b = 0; b < N; b = b + 1)
                    if (member[b] && ord[b * N + a]) beaten = 1'b1;
                oldest[a] = member[a] && !beaten;
            end
        end
    endfunction
    reg [N*N-1:0] ord_flat;
    always @* for (i_o = 0; i_o < N; i_o = i_o + 1) ord_flat[i_o * N +: N] = older_eff[i_o];
    // Each walker's issue slot and request port, among its own contexts.
    // Walker w's contexts (constant: continuous assignments, since an always @* with no input
    // never runs in an event-driven simulator such as Icarus).
    wire [N-1:0] wmask [0:W-1];
    genvar gw;
    generate
        for (gw = 0; gw < W; gw = gw + 1) begin : walker_mask
            assign wmask[gw] = ({N{1'b1}} >> (N - R)) << (gw * R);
        end
    endgenerate
    reg [N-1:0] send_pick;
    always @* begin
        e_issue_grant = {N{1'b0}};
        send_pick = {N{1'b0}};
        for (w_g = 0; w_g < W; w_g = w_g + 1) begin
            e_issue_grant = e_issue_grant | oldest(e_issue_req & wmask[w_g], ord_flat);
            send_pick = send_pick | oldest(e_req_valid & wmask[w_g], ord_flat);
        end
    end
    wire [N-1:0] fin_pick = oldest(e_out_valid, ord_flat);

    // ---------------------------------------------------------------- request ports
    reg  [N-1:0]  fill;                           // the read out is an attribute fill
    reg  [31:0]   fill_addr [0:N-1];
    reg  [N-1:0]  merged;                         // the read out rides on another's fill
    reg  [CW-1:0] merged_on [0:N-1];
    reg  [N-1:0]  responding;                     // a response for context n on some port
    reg  [63:0]   resp_data [0:N-1];
    reg  [CW-1:0] pick      [0:W-1];              // walker w's port's context
    reg  [W-1:0]  want, merge;
    reg  [CW-1:0] merge_to  [0:W-1];
    reg  [N-1:0]  sent;
    always @* begin
        for (i_r = 0; i_r < N; i_r = i_r + 1) begin
            responding[i_r] = 1'b0;
            resp_data[i_r] = mem_resp_data[63:0];
            for (p_r = 0; p_r < W; p_r = p_r + 1)
                if (mem_resp_valid[p_r] && mem_resp_ctx[p_r*CW +: CW] == i_r[CW-1:0]) begin
                    responding[i_r] = 1'b1;
                    resp_data[i_r] = mem_resp_data[p_r*64 +: 64];
                end
        end
        // Responses: the addressed context, and every read merged onto its fill.
        for (i_r = 0; i_r < N; i_r = i_r + 1) begin
            e_resp_valid[i_r] = responding[i_r];
            e_resp_data[i_r] = resp_data[i_r];
            if (merged[i_r] && responding[merged_on[i_r]]) begin
                e_resp_valid[i_r] = 1'b1;
                e_resp_data[i_r] = resp_data[merged_on[i_r]];
            end
        end
    end
    always @* begin
        sent = {N{1'b0}};
        for (w_q = 0; w_q < W; w_q = w_q + 1) begin
            pick[w_q] = {CW{1'b0}};
            for (i_q = N - 1; i_q >= 0; i_q = i_q - 1)
                if (send_pick[i_q] && wmask[w_q][i_q]) pick[w_q] = i_q[CW-1:0];
            want[w_q] = |(send_pick & wmask[w_q]);
            // A read of a record whose fill is in flight (and not done in this cycle) merges.
            merge[w_q] = 1'b0;
            merge_to[w_q] = {CW{1'b0}};
            for (i_q = N - 1; i_q >= 0; i_q = i_q - 1)
                if (want[w_q] && fill[i_q] && e_req_attr[pick[w_q]] && fill_addr[i_q] == e_req_addr[pick[w_q]]
                    && !responding[i_q]) begin
                    merge[w_q] = 1'b1;
                    merge_to[w_q] = i_q[CW-1:0];
                end
            if (want[w_q] && (merge[w_q] || mem_req_ready[w_q])) sent = sent | (send_pick & wmask[w_q]);
        end
        e_req_ready = sent;
    end
    genvar g, gr;
    generate
        for (g = 0; g < W; g = g + 1) begin : port
            assign mem_req_valid[g] = want[g] && !merge[g];
            assign mem_req_attr[g] = e_req_attr[pick[g]];
            assign mem_req_addr[g*32 +: 32] = e_req_addr[pick[g]];
            assign mem_req_ctx[g*CW +: CW] = pick[g];
        end
    endgenerate
    // The order of this cycle's sends (the node memory's request ids): the reads that
    // waited for their port first, walkers ascending, then new ones in wake-up order.
    function automatic sent_before(input integer a, input integer b);
        sent_before = (!ev[a] && ev[b]) || (!ev[a] && !ev[b] && walker_of(a) < walker_of(b))
                   || (ev[a] && ev[b] && older_eff[a][b]);
    endfunction

    // ---------------------------------------------------------------- dispatch and retire
    // The walker with the most free contexts (a context retiring now counts), the lowest
    // index on ties; its lowest free context.
    reg [N-1:0] take_pick;
    reg [5:0] nfree, best_n;
    reg [WI-1:0] best;
    always @* begin
        best = {WI{1'b0}};
        best_n = 6'd0;
        for (w_d = 0; w_d < W; w_d = w_d + 1) begin
            nfree = 6'd0;
            for (i_d = 0; i_d < N; i_d = i_d + 1)
                if (wmask[w_d][i_d] && e_in_ready[i_d]) nfree = nfree + 6'd1;
            if (nfree > best_n) begin
                best_n = nfree;
                best = w_d[WI-1:0];
            end
        end
        take_pick = {N{1'b0}};
        for (i_d = N - 1; i_d >= 0; i_d = i_d - 1)
            if (e_in_ready[i_d] && walker_of(i_d) == best) take_pick = {{(N-1){1'b0}}, 1'b1} << i_d;
    end
    assign in_ready = |e_in_ready;
    assign e_take = in_valid ? take_pick : {N{1'b0}};
    assign e_out_ready = out_ready ? fin_pick : {N{1'b0}};
    assign out_valid = |e_out_valid;
    reg [CW-1:0] fin;
    always @* begin
        fin = {CW{1'b0}};
        for (i_f = N - 1; i_f >= 0; i_f = i_f - 1) if (fin_pick[i_f]) fin = i_f[CW-1:0];
    end
    // The result of context fin: its walker's result port (each walker reads its context's
    // state at fin's index within the walker).
    wire [31:0] fin32 = {{(32-CW){1'b0}}, fin};
    wire [WI-1:0] fin_w = walker_of(fin32);
    /* verilator lint_off UNUSEDSIGNAL */
    wire [RI-1:0] fin_local = local_of(fin32);   // (unused at R = 1)
    /* verilator lint_on UNUSEDSIGNAL */
    assign out_outcome = w_outcome[fin_w];
    assign out_t = w_t[fin_w];
    assign out_voxel = w_voxel[fin_w];
    assign out_attr_data = w_attr_data[fin_w];
    assign out_tag = w_tag[fin_w];

    always @(posedge clk) begin
        for (i = 0; i < N; i = i + 1) begin
            older[i] <= older_eff[i];
            for (j = 0; j < N; j = j + 1)
                if (sent[i] || sent[j])
                    req_older[i][j] <= sent[i] && sent[j] ? i != j && sent_before(i, j)
                                                          : sent[j];
            if (e_resp_valid[i]) begin
                fill[i] <= 1'b0;
                merged[i] <= 1'b0;
            end
        end
        for (w = 0; w < W; w = w + 1)
            if (want[w] && (merge[w] || mem_req_ready[w])) begin
                fill[pick[w]] <= !merge[w] && e_req_attr[pick[w]];
                fill_addr[pick[w]] <= e_req_addr[pick[w]];
                merged[pick[w]] <= merge[w];
                merged_on[pick[w]] <= merge_to[w];
            end
        if (rst) begin
            fill <= {N{1'b0}};
            merged <= {N{1'b0}};
            err_resp <= 1'b0;
        end else
            for (p = 0; p < W; p = p + 1)
                if ((mem_resp_valid[p] && !(|e_resp_valid)) || |w_err) err_resp <= 1'b1;
    end

    // ---------------------------------------------------------------- the walkers
    // R = 1: svo_walker, whose registers are the walker's one context (the estimate's
    // calibrated walker, rtl_model/src/cost/structures.rs `walker_contexts`: nothing added at
    // R = 1). R > 1: svo_walker_barrel, one step datapath and the R contexts' state in RAMs.
    generate
        if (R == 1) begin : single
            for (g = 0; g < N; g = g + 1) begin : ctx
                /* verilator lint_off PINCONNECTEMPTY */
                svo_walker #(.POS_W(POS_W), .T_W(T_W), .STACK_DEPTH(STACK_DEPTH),
                    .MAX_STEPS(MAX_STEPS), .STEP_LATENCY(STEP_LATENCY), .TAG_W(TAG_W)
                ) u_walker (.clk(clk), .rst(rst), .in_valid(e_take[g]), .in_ready(e_in_ready[g]),
                    .in_enter(in_enter), .in_t0(in_t0), .in_t1(in_t1), .in_o(in_o),
                    .in_half(in_half), .in_zero(in_zero), .in_neg(in_neg),
                    .in_node_base(in_node_base), .in_attr_base(in_attr_base), .in_tag(in_tag),
                    .mem_req_valid(e_req_valid[g]), .mem_req_ready(e_req_ready[g]),
                    .mem_req_attr(e_req_attr[g]), .mem_req_addr(e_req_addr[g]),
                    .mem_resp_valid(e_resp_valid[g]), .mem_resp_data(e_resp_data[g]),
                    .out_valid(e_out_valid[g]), .out_ready(e_out_ready[g]),
                    .out_outcome(w_outcome[g]), .out_t(w_t[g]), .out_voxel(w_voxel[g]),
                    .out_level(), .out_attr(), .out_entry_axis(), .out_steps(), .out_fetches(),
                    .out_attr_data(w_attr_data[g]), .out_tag(w_tag[g]), .visit_valid(),
                    .visit_level(), .visit_coords(), .issue_grant(e_issue_grant[g]),
                    .issue_req(e_issue_req[g]), .ev_lat(e_ev_lat[g]), .ev_disp(e_ev_disp[g]),
                    .ev_resp(e_ev_resp[g]));
                /* verilator lint_on PINCONNECTEMPTY */
                assign w_err[g] = 1'b0;
            end
        end else begin : barrel
            for (g = 0; g < W; g = g + 1) begin : walker
                wire [R*32-1:0] req_addr;
                reg  [R*64-1:0] w_resp_data;
                integer q;
                always @* for (q = 0; q < R; q = q + 1) w_resp_data[q*64 +: 64] = e_resp_data[g*R + q];
                for (gr = 0; gr < R; gr = gr + 1) begin : ctx
                    assign e_req_addr[g*R + gr] = req_addr[gr*32 +: 32];
                end
                svo_walker_barrel #(.POS_W(POS_W), .T_W(T_W), .STACK_DEPTH(STACK_DEPTH),
                    .MAX_STEPS(MAX_STEPS), .STEP_LATENCY(STEP_LATENCY), .TAG_W(TAG_W),
                    .CONTEXTS(R), .RI(RI)
                ) u_walker (.clk(clk), .rst(rst), .in_take(e_take[g*R +: R]),
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
                    .fin(fin_local), .out_outcome(w_outcome[g]), .out_t(w_t[g]),
                    .out_voxel(w_voxel[g]), .out_attr_data(w_attr_data[g]), .out_tag(w_tag[g]),
                    .err_resp(w_err[g]));
            end
        end
    endgenerate
endmodule
`default_nettype wire
