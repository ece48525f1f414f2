// svo_walker_pool: one octree walker of CONTEXTS ray contexts and its scheduler, cycle for
// cycle as the cycle model's walker pool times it (rtl_model/src/cycle/walker_pool.rs, its
// module doc) with walker_pool.walkers 1, read_ports 1, step_cycles 1.
//
// Pipeline position: after root_to_dispatch (svo_walk), before walker_to_record; the node
// memory behind one request port.
//
// What it is: CONTEXTS context engines, each a copy of the single-context walker
// (svo_walker.v, its stack and step registers), behind one issue grant, one request port and
// one result port. This is the acceptable first step of issue 29's milestone 1, NOT the design
// the model's cost estimate prices (rtl_model/src/cost: one step datapath per walker with R
// contexts' state in a small RAM, a true barrel): here the step datapath is replicated R
// times, so its area is about R times the estimate's walker datapath. The timing is the same:
// the engines issue only when granted, one slot a cycle.
//
// The scheduler is the model's, per cycle:
//   wake-up order  a context moves on to its next op in the model's wake-up order: first the
//                  one whose step latency ended (ev_lat: at most one, one slot issues a
//                  cycle), then the walk dispatched in the cycle before (ev_disp: its root
//                  read, or a root miss), then the contexts whose read completed (ev_resp) by
//                  request age (the node memory's (done, id) order). That order decides where
//                  the context joins the queue its next op needs:
//   issue          ready contexts issue round robin in the order they became ready (a FIFO),
//                  one a cycle (step_cycles 1), a newly ready one in the same cycle if none
//                  waits before it;
//   request port   one read a cycle; reads waiting for the port (the send queue) go first,
//                  oldest first, then this cycle's new ones in wake-up order;
//   retire         finished walks leave in the order they finished, one a cycle, when the
//                  record FIFO is ready (out_ready); the context takes a new walk in the same
//                  cycle (the model retires before it dispatches);
//   dispatch       a walk goes to the lowest free context (with one walker the model's rule,
//                  the walker with most free contexts, is this walker; which of its free
//                  contexts takes the walk does not change any cycle).
// The three queues are one age order: a context is in at most one queue at a time, so one
// matrix older[i][j] (i's event came first) serves all three, updated with each cycle's
// events; within a cycle the events are ranked as above (req_older orders the completions).
//
// Attribute reads that merge (the model's MSHR rule for uncached attribute reads with
// cache.line_bytes 8, memory/dram.rs `miss`): a record read while a fill of the same record is
// in flight (sent, its response not yet back, and not arriving in this cycle) is not sent: it
// completes with that fill, in the same cycle, after it (request age). With one context per
// walker no read can merge, so any node memory works; with several, the hardware file must
// use uncached attributes with 8-byte lines (svo_top refuses other node memories), where this
// rule is the model's exactly.
//
// The memory: mem_req_* one read a cycle with its context (mem_req_ctx); responses in any
// order, each with its context (mem_resp_ctx), one a cycle. Sticky err_resp: a response for a
// context that has no read out.
`timescale 1ns/1ps
`default_nettype none
module svo_walker_pool #(
    parameter POS_W        = 40,
    parameter T_W          = 62,
    parameter STACK_DEPTH  = 21,
    parameter MAX_STEPS    = 100000,
    parameter STEP_LATENCY = 3,
    parameter TAG_W        = 1,
    parameter CONTEXTS     = 1,
    parameter CW           = CONTEXTS > 1 ? $clog2(CONTEXTS) : 1   // context index bits
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
    output wire                   mem_req_valid,
    input  wire                   mem_req_ready,
    output wire                   mem_req_attr,
    output wire [31:0]            mem_req_addr,
    output wire [CW-1:0]          mem_req_ctx,
    input  wire                   mem_resp_valid,
    input  wire [CW-1:0]          mem_resp_ctx,
    input  wire [63:0]            mem_resp_data,
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

    generate
        if (R < 1 || R > 16) begin : bad_contexts
            svo_walker_pool_CONTEXTS_must_be_1_to_16 bad();
        end
    endgenerate

    // Per engine.
    wire [R-1:0] e_in_ready, e_issue_req, e_ev_lat, e_ev_disp, e_ev_resp, e_req_valid,
                 e_req_attr, e_out_valid, e_resp_valid;
    wire [R-1:0] e_take, e_issue_grant, e_req_ready, e_out_ready;
    wire [31:0]    e_req_addr  [0:R-1];
    wire [1:0]     e_outcome   [0:R-1];
    wire [T_W-1:0] e_t         [0:R-1];
    wire [59:0]    e_voxel     [0:R-1];
    wire [63:0]    e_attr_data [0:R-1];
    wire [TAG_W-1:0] e_tag     [0:R-1];

    // ---------------------------------------------------------------- the age orders
    reg  [R-1:0] older     [0:R-1];               // older[i][j]: i joined its queue before j
    reg  [R-1:0] req_older [0:R-1];               // i's read out was sent before j's
    wire [R-1:0] ev = e_ev_lat | e_ev_disp | e_ev_resp;
    reg  [R-1:0] older_eff [0:R-1];               // this cycle's order, events included
    integer i, j;
    always @* begin
        for (i = 0; i < R; i = i + 1)
            for (j = 0; j < R; j = j + 1) begin
                if (i == j) older_eff[i][j] = 1'b0;
                else if (ev[i] && ev[j])
                    // Both moved on in this cycle: the wake-up order.
                    older_eff[i][j] = e_ev_lat[i] || (e_ev_disp[i] && e_ev_resp[j])
                                   || (e_ev_resp[i] && e_ev_resp[j] && req_older[i][j]);
                else if (ev[j]) older_eff[i][j] = 1'b1;   // j joins behind everyone
                else if (ev[i]) older_eff[i][j] = 1'b0;
                else older_eff[i][j] = older[i][j];
            end
    end
    // The oldest member of each queue.
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
    reg [R*R-1:0] ord_flat;
    always @* for (i = 0; i < R; i = i + 1) ord_flat[i * R +: R] = older_eff[i];
    assign e_issue_grant = oldest(e_issue_req, ord_flat);
    wire [R-1:0] send_pick = oldest(e_req_valid, ord_flat);
    wire [R-1:0] fin_pick = oldest(e_out_valid, ord_flat);

    // ---------------------------------------------------------------- request port
    reg  [R-1:0]  fill;                           // the read out is an attribute fill
    reg  [31:0]   fill_addr [0:R-1];
    reg  [R-1:0]  merged;                         // the read out rides on another's fill
    reg  [CW-1:0] merged_on [0:R-1];
    reg  [CW-1:0] pick;                           // the port's context
    reg  [R-1:0]  same_fill;                      // fills of the picked record, not done now
    always @* begin
        pick = {CW{1'b0}};
        for (i = R - 1; i >= 0; i = i - 1) if (send_pick[i]) pick = i[CW-1:0];
        for (i = 0; i < R; i = i + 1)
            same_fill[i] = fill[i] && e_req_attr[pick] && fill_addr[i] == e_req_addr[pick]
                        && !(mem_resp_valid && mem_resp_ctx == i[CW-1:0]);
    end
    wire want = |send_pick;
    wire merge = want && |same_fill;
    reg [CW-1:0] merge_to;
    always @* begin
        merge_to = {CW{1'b0}};
        for (i = R - 1; i >= 0; i = i - 1) if (same_fill[i]) merge_to = i[CW-1:0];
    end
    assign mem_req_valid = want && !merge;
    assign mem_req_attr = e_req_attr[pick];
    assign mem_req_addr = e_req_addr[pick];
    assign mem_req_ctx = pick;
    wire sent = want && (merge || mem_req_ready);
    assign e_req_ready = sent ? send_pick : {R{1'b0}};
    // Responses: the addressed context, and every read merged onto its fill.
    genvar g;
    generate
        for (g = 0; g < R; g = g + 1) begin : resp
            assign e_resp_valid[g] = mem_resp_valid
                && (R == 1 || mem_resp_ctx == g[CW-1:0]
                    || (merged[g] && merged_on[g] == mem_resp_ctx));
        end
    endgenerate

    // ---------------------------------------------------------------- dispatch and retire
    reg [R-1:0] take_pick;                        // the lowest free context
    always @* begin
        take_pick = {R{1'b0}};
        for (i = R - 1; i >= 0; i = i - 1)
            if (e_in_ready[i]) take_pick = {{(R-1){1'b0}}, 1'b1} << i;
    end
    assign in_ready = |e_in_ready;
    assign e_take = in_valid ? take_pick : {R{1'b0}};
    assign e_out_ready = out_ready ? fin_pick : {R{1'b0}};
    assign out_valid = |e_out_valid;
    reg [CW-1:0] fin;
    always @* begin
        fin = {CW{1'b0}};
        for (i = R - 1; i >= 0; i = i - 1) if (fin_pick[i]) fin = i[CW-1:0];
    end
    assign out_outcome = e_outcome[fin];
    assign out_t = e_t[fin];
    assign out_voxel = e_voxel[fin];
    assign out_attr_data = e_attr_data[fin];
    assign out_tag = e_tag[fin];

    always @(posedge clk) begin
        for (i = 0; i < R; i = i + 1) begin
            older[i] <= older_eff[i];
            if (e_resp_valid[i]) begin
                fill[i] <= 1'b0;
                merged[i] <= 1'b0;
            end
            if (e_req_ready[i]) begin
                fill[i] <= !merge && e_req_attr[i];
                fill_addr[i] <= e_req_addr[i];
                merged[i] <= merge;
                merged_on[i] <= merge_to;
                // The read sent now is the youngest.
                for (j = 0; j < R; j = j + 1) begin
                    req_older[i][j] <= 1'b0;
                    req_older[j][i] <= j != i;
                end
            end
        end
        if (rst) begin
            fill <= {R{1'b0}};
            merged <= {R{1'b0}};
            err_resp <= 1'b0;
        end else if (mem_resp_valid && !(|e_resp_valid)) err_resp <= 1'b1;
    end

    // ---------------------------------------------------------------- the engines
    generate
        for (g = 0; g < R; g = g + 1) begin : ctx
            /* verilator lint_off PINCONNECTEMPTY */
            svo_walker #(.POS_W(POS_W), .T_W(T_W), .STACK_DEPTH(STACK_DEPTH),
                .MAX_STEPS(MAX_STEPS), .STEP_LATENCY(STEP_LATENCY), .TAG_W(TAG_W)
            ) u_walker (.clk(clk), .rst(rst), .in_valid(e_take[g]), .in_ready(e_in_ready[g]),
                .in_enter(in_enter), .in_t0(in_t0), .in_t1(in_t1), .in_o(in_o),
                .in_half(in_half), .in_zero(in_zero), .in_neg(in_neg),
                .in_node_base(in_node_base), .in_attr_base(in_attr_base), .in_tag(in_tag),
                .mem_req_valid(e_req_valid[g]), .mem_req_ready(e_req_ready[g]),
                .mem_req_attr(e_req_attr[g]), .mem_req_addr(e_req_addr[g]),
                .mem_resp_valid(e_resp_valid[g]), .mem_resp_data(mem_resp_data),
                .out_valid(e_out_valid[g]), .out_ready(e_out_ready[g]),
                .out_outcome(e_outcome[g]), .out_t(e_t[g]), .out_voxel(e_voxel[g]),
                .out_level(), .out_attr(), .out_entry_axis(), .out_steps(), .out_fetches(),
                .out_attr_data(e_attr_data[g]), .out_tag(e_tag[g]), .visit_valid(),
                .visit_level(), .visit_coords(), .issue_grant(e_issue_grant[g]),
                .issue_req(e_issue_req[g]), .ev_lat(e_ev_lat[g]), .ev_disp(e_ev_disp[g]),
                .ev_resp(e_ev_resp[g]));
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
endmodule
`default_nettype wire
