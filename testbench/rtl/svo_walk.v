// svo_walk: the walk section for one walk-issue lane and the walker pool, from
// check_to_transform to the record stage's word: the ray slots, the transform with the
// loop-back before new rays, the three reciprocals, the walker root, the walker and its memory
// port, the record stage's decision (early termination, the best hit) and svo_hit_pack.
//
// Pipeline position: docs/cycle-model.md §2.1, check_to_transform → transform →
// transform_to_reciprocal → reciprocal → reciprocal_to_root → root → root_to_dispatch →
// walker → walker_to_record → record → loop_back (the next candidate) or the hit buffer's
// record port. Cycle-exact with the model's stages (src/models/cycle/stages/transform.rs,
// passthrough.rs, walkers.rs, record.rs) on hardware of one lane (transform_units 1,
// reciprocal_units 3, walker_root_units 1) and any walker pool svo_walker_pool builds: every
// joint an svo_fifo of the model's depth, every fixed-latency unit in an svo_elastic pipe of
// its latency, and within a cycle the consumers decide first (the record frees a slot the
// transform can take in the same cycle; the loop-back FIFO and every other joint pass an item
// a cycle later).
//
// A ray arrives from the check stage with its direction and its sorted candidates (count and
// keys {instance 8, t_enter uQ10.22}) and takes the lowest free ray slot (SLOTS = walkers x
// contexts + root_to_dispatch); the slot holds it until its record leaves for packing. Each
// walk of the ray is one candidate, front to back: the record stage sends the next one back
// through loop_back unless the best hit so far ends the ray (FramePlan::stops: best t <= the
// next candidate's entry). The instance table gives the transform's axes and centre, the
// root's half extents, the walker's image bases and the normal matrix through four read
// ports (`ird_*`: the instance read, `inst_*` its registers in the same cycle; the table
// answers asynchronously, one replicated port per reader, so the timing is that of the
// instance registers they replace).
//
// The record's normal is computed here: a packed ray's best-hit attribute normal and its
// instance's normal matrix (`inst_nmat` for `ird_nm`, 9 sQ2.16 elements row-major, programmed by
// the host with the frame) go through svo_normal (latency 13) while the other fields wait
// beside it in an svo_delay, then svo_hit_pack (1): the pack pipe is 14 long, the model's
// units.hit_pack (units::hit_record::PACK_LATENCY_CYCLES). The pack pipe is svo_elastic2: two ready records
// leave in a cycle on rec_* and rec2_* when record_to_write has room for both (its two push
// ports at k = 1 in the model). `done_*` shows each ray's walk results when its record is decided (for checking).
// Sticky `err_pipe`: a unit result without its slot, the loop-back FIFO refusing a walk
// (never expected: it has one entry per slot), or a node read's response for a context with
// no read out.
//
// The walkers are svo_walker_pool: WALKERS walkers of CONTEXTS contexts (per walker one step
// datapath, its contexts' state in RAMs, behind one issue grant and one request port; see its
// header), the model's
// walker pool with its dispatcher. Sticky `err_overflow`: a transform, reciprocal
// or pack overflow flag (the datapath saturated, which the model counts: reported). Reciprocal seed ROMs: recip[k].u_recip.rom,
// loaded by the host as for svo_reciprocal.
`timescale 1ns/1ps
`default_nettype none
module svo_walk #(
    parameter LANES     = 8,          // sphere lanes (KEYN's default)
    parameter PIXW      = 32,
    parameter SLOTS     = 65,
    parameter TAGW      = 7,          // ray-slot tag bits: 2^TAGW >= SLOTS
    parameter PW        = 40,         // positions sQ8.32
    parameter TW        = 62,         // walker t sQ31.31
    parameter POS_FRAC  = 32,
    parameter INV_W     = 52,
    parameter INV_FRAC  = 30,
    parameter T_FRAC    = 31,
    parameter ROOT_PROD = 4,
    parameter STACK_DEPTH  = 21,
    parameter MAX_STEPS    = 100000,
    parameter STEP_LATENCY = 3,
    parameter TR_L      = 9,          // svo_transform's LATENCY
    parameter RC_L      = 26,         // svo_reciprocal's
    parameter RT_L      = 8,          // svo_walker_root's
    parameter D_CK_TR   = 1024,       // fifos.check_to_transform
    parameter D_TR_RC   = 4,
    parameter D_RC_RT   = 4,
    parameter D_RT_DP   = 64,
    parameter D_WK_RC   = 16,
    parameter RECIP_SEED_FILE = "",            // the reciprocal seed ROM (reciprocal_seed.hex); "": loaded by the testbench
    parameter KEYN      = LANES,      // keys a ray carries (svo_front's KEYN)
    parameter CONTEXTS  = 1,          // walker_pool.contexts_per_walker
    parameter WALKERS   = 1,          // walker_pool.walkers: one node-memory port each
    parameter CW        = WALKERS * CONTEXTS > 1 ? $clog2(WALKERS * CONTEXTS) : 1,
    parameter CTX_RESP  = 0,          // per-context response ports (svo_walker_pool)
    parameter ATTR_MERGE = 1,         // svo_walker_pool's attribute-merge rule (0 behind a cache)
    parameter RESP_REG = 0,           // svo_walker_pool's response / request register (0 or 1)
    parameter REQ_REG  = 0,
    parameter CRN       = CTX_RESP != 0 ? WALKERS * CONTEXTS : 1  // their count (do not set)
) (
    input  wire                    clk,
    input  wire                    rst,
    input  wire [3*PW-1:0]         cam_o,
    // the instance table's read ports: the instance read (`ird_*`), its registers back
    output wire [7:0]              ird_tr,       // the transform's
    input  wire [287:0]            inst_axes,
    input  wire [119:0]            inst_c,
    output wire [7:0]              ird_rt,       // the walker root's
    input  wire [119:0]            inst_half,
    output wire [7:0]              ird_dp,       // the walker's (dispatch)
    input  wire [31:0]             inst_node_base,
    input  wire [31:0]             inst_attr_base,
    output wire [7:0]              ird_nm,       // the record's normal unit
    input  wire [9*18-1:0]         inst_nmat,
    // rays to walk, from the check stage
    input  wire                    in_valid,
    output wire                    in_ready,
    input  wire [PIXW-1:0]         in_pixel,
    input  wire [95:0]             in_dir,
    input  wire [5:0]              in_count,
    input  wire [KEYN*40-1:0]      in_keys,
    // the node memory
    // the node memory: one read port per walker (port w: walker w's reads; one read a cycle
    // each, their responses in any order, each on any port, with its context)
    output wire [WALKERS-1:0]      mem_req_valid,
    input  wire [WALKERS-1:0]      mem_req_ready,
    output wire [WALKERS-1:0]      mem_req_attr,
    output wire [WALKERS*32-1:0]   mem_req_addr,
    input  wire [WALKERS-1:0]      mem_resp_valid,
    input  wire [WALKERS*64-1:0]   mem_resp_data,
    // records to the hit buffer
    output wire                    rec_valid,
    input  wire                    rec_ready,
    output wire [PIXW-1:0]         rec_pixel,
    output wire [71:0]             rec_word,
    // a second ready record behind rec_*, taken with it (the model's second push into
    // record_to_write: svo_elastic2)
    output wire                    rec2_valid,
    input  wire                    rec2_ready,
    output wire [PIXW-1:0]         rec2_pixel,
    output wire [71:0]             rec2_word,
    // a ray's walk results, when its record is decided
    output wire                    done_valid,
    output wire [PIXW-1:0]         done_pixel,
    output wire [15:0]             done_walks,
    output wire                    done_hit,
    output wire [TW-1:0]           done_t,
    output wire [59:0]             done_voxel,
    output reg                     err_pipe,
    output reg                     err_overflow, // a transform, reciprocal or pack flag (sticky)
    // the node memory's context of a read (svo_walker_pool: responses may come in any order)
    output wire [WALKERS*CW-1:0]   mem_req_ctx,
    input  wire [WALKERS*CW-1:0]   mem_resp_ctx,
    // with CTX_RESP, a response port per context (svo_walker_pool; svo_top's on-chip store)
    input  wire [CRN-1:0]          ctx_resp_valid,
    input  wire [CRN*32-1:0]       ctx_resp_data
);
    localparam TI = TW + 1;
    localparam KEYS = KEYN * 40;
    localparam RAY = PIXW + 96 + 6 + KEYS;
    localparam RTB = 1 + 2 * 3 * TI + 3 * (PW + 1) + 3 * PW + 3 + 3 + TAGW;   // root bundle

    generate
        if ((1 << TAGW) < SLOTS || SLOTS < 2) begin : bad_slots
            svo_walk_TAGW_must_address_SLOTS bad();
        end
    endgenerate

    // ---------------------------------------------------------------- the ray slots
    reg [PIXW-1:0]  s_pixel [0:SLOTS-1];
    reg [95:0]      s_dir   [0:SLOTS-1];
    reg [5:0]       s_count [0:SLOTS-1];
    reg [KEYS-1:0]  s_keys  [0:SLOTS-1];
    reg [5:0]       s_cand  [0:SLOTS-1];
    reg [15:0]      s_walks [0:SLOTS-1];
    reg             s_best  [0:SLOTS-1];
    reg [TW-1:0]    s_t     [0:SLOTS-1];
    reg [63:0]      s_attr  [0:SLOTS-1];
    reg [59:0]      s_voxel [0:SLOTS-1];
    reg [7:0]       s_inst  [0:SLOTS-1];
    reg [3*PW-1:0]  s_o     [0:SLOTS-1];
    reg [95:0]      s_d     [0:SLOTS-1];
    reg [2:0]       s_sign  [0:SLOTS-1];
    reg [3*INV_W-1:0] s_inv [0:SLOTS-1];
    reg [2:0]       s_zero  [0:SLOTS-1];
    reg [2:0]       s_neg   [0:SLOTS-1];
    reg [SLOTS-1:0] free;
    // The instance of slot s's current candidate.
    // A multiplexer over the KEYS/40 keys, not keys[c * 40 ...]: Yosys maps a part-select
    // at a variable times a constant to DSP48E2 multipliers (5 of them in the whole core).
    function automatic [7:0] cand_inst(input [KEYS-1:0] keys, input [5:0] c);
        integer k;
        begin
            cand_inst = 8'd0;
            for (k = 0; k < KEYS / 40; k = k + 1)
                if ({26'd0, c} == k) cand_inst = keys[k * 40 + 32 +: 8];
        end
    endfunction
    // The key (t_enter) of candidate c, by the same multiplexer.
    function automatic [31:0] cand_key(input [KEYS-1:0] keys, input [5:0] c);
        integer k;
        begin
            cand_key = 32'd0;
            for (k = 0; k < KEYS / 40; k = k + 1)
                if ({26'd0, c} == k) cand_key = keys[k * 40 +: 32];
        end
    endfunction

    // ---------------------------------------------------------------- record (first)
    wire wr_valid;                                // walker_to_record's head
    wire [TAGW-1:0] wr_slot;
    wire pk_in_ready;
    wire rc_take = wr_valid && pk_in_ready;       // the record decides on the head
    wire [SLOTS-1:0] one = {{(SLOTS-1){1'b0}}, 1'b1};
    wire [5:0] r_cand = s_cand[wr_slot];
    wire [5:0] r_next = r_cand + 6'd1;
    wire [31:0] r_next_key = cand_key(s_keys[wr_slot], r_next);
    // FramePlan::stops: best t (sQ31.31) <= the next key (uQ10.22 → 9 more fraction bits).
    wire signed [TW+1:0] r_a = $signed({{2{s_t[wr_slot][TW-1]}}, s_t[wr_slot]});
    wire signed [TW+1:0] r_b = $signed({{(TW+2-32-9){1'b0}}, r_next_key, 9'd0});
    wire r_more = r_next < s_count[wr_slot] && !(s_best[wr_slot] && r_a <= r_b);
    wire r_loop = rc_take && r_more;
    wire r_pack = rc_take && !r_more;
    wire [SLOTS-1:0] released = r_pack ? (one << wr_slot) : {SLOTS{1'b0}};
    assign done_valid = r_pack;
    assign done_pixel = s_pixel[wr_slot];
    assign done_walks = s_walks[wr_slot] + 16'd1;
    assign done_hit = s_best[wr_slot];
    assign done_t = s_t[wr_slot];
    assign done_voxel = s_voxel[wr_slot];

    // svo_normal then svo_hit_pack in one pipe (capacity NL + 1), the other fields and the
    // pixel beside the normal unit.
    localparam NL = 13;                           // svo_normal's LATENCY
    localparam PKB = 2 + 1 + 8 + 64 + 24 + PIXW;  // the fields that wait for the normal
    wire pk_u_valid, pk_ov, nm_valid;
    wire [15:0] nm_code;                          // {v, u}
    wire [71:0] pk_word;
    // sQ31.31 → uQ8.14, truncated (an arithmetic shift); no hit: RecordT::far.
    wire signed [63:0] pk_t_hit = $signed({{(64-TW){s_t[wr_slot][TW-1]}}, s_t[wr_slot]}) >>> 17;
    wire [63:0] pk_t = s_best[wr_slot] ? pk_t_hit : 64'h3fffff;
    svo_normal #(.N_W(8)) u_normal (.clk(clk), .rst(rst), .in_valid(r_pack),
        .in_oct(s_attr[wr_slot][63:32]),
        .in_mat(inst_nmat),
        .out_valid(nm_valid), .out_code(nm_code));
    wire [PKB-1:0] pk_d = {s_count[wr_slot] == 6'd1 ? 2'd1 : 2'd2, s_best[wr_slot],
        s_inst[wr_slot], pk_t, s_attr[wr_slot][7:0], s_attr[wr_slot][15:8],
        s_attr[wr_slot][23:16], s_pixel[wr_slot]};
    wire [PKB-1:0] pk_q;
    svo_delay #(.W(PKB), .D(NL)) pk_side (.clk(clk), .rst(rst), .d(pk_d), .q(pk_q));
    wire [1:0]  pq_kind  = pk_q[PKB-1 -: 2];
    wire        pq_best  = pk_q[PKB-3];
    wire [7:0]  pq_inst  = pk_q[PKB-4 -: 8];
    wire [63:0] pq_t     = pk_q[PKB-12 -: 64];
    wire [7:0]  pq_r     = pk_q[PKB-76 -: 8];
    wire [7:0]  pq_g     = pk_q[PKB-84 -: 8];
    wire [7:0]  pq_b     = pk_q[PKB-92 -: 8];
    wire [PIXW-1:0] pq_pixel = pk_q[PIXW-1:0];
    svo_hit_pack u_pack (.clk(clk), .rst(rst), .in_valid(nm_valid),
        .in_kind(pq_kind),
        .in_instance_valid(pq_best),
        .in_instance(pq_best ? {8'd0, pq_inst} : 16'd0), .in_t(pq_t),
        .in_normal_u(pq_best ? {{24{nm_code[7]}}, nm_code[7:0]} : 32'd0),
        .in_normal_v(pq_best ? {{24{nm_code[15]}}, nm_code[15:8]} : 32'd0),
        .in_colour_r(pq_best ? pq_r : 8'd0),
        .in_colour_g(pq_best ? pq_g : 8'd0),
        .in_colour_b(pq_best ? pq_b : 8'd0),
        .out_valid(pk_u_valid), .out_word(pk_word), .out_ov(pk_ov));
    reg [PIXW-1:0] pk_pixel;                      // the ray leaving the pack (its last register)
    always @(posedge clk) if (nm_valid) pk_pixel <= pq_pixel;
    // The pipe's gate applies to every decision (a loop-back too), as the model's record
    // stage takes a walk only while its pack lanes can accept.
    // Two out ports: record_to_write has two push ports at k = 1 (max(k, record_writes) in the
    // model), so two waiting records enter it in a cycle when it has room for both.
    svo_elastic2 #(.L(NL + 1), .W(PIXW + 72)) pk_pipe (.clk(clk), .rst(rst), .in_valid(r_pack),
        .in_ready(pk_in_ready), .unit_valid(pk_u_valid), .unit_data({pk_pixel, pk_word}),
        .out_valid(rec_valid), .out_ready(rec_ready), .out_data({rec_pixel, rec_word}),
        .out2_valid(rec2_valid), .out2_ready(rec2_ready), .out2_data({rec2_pixel, rec2_word}));

    // ---------------------------------------------------------------- walker
    wire dp_valid;                                // root_to_dispatch's head
    wire [RTB-1:0] dp_data;
    wire wk_in_ready, wk_out_valid, wk_out_ready;
    wire [1:0] wk_outcome;
    wire [TW-1:0] wk_t;
    wire [59:0] wk_voxel;
    wire [63:0] wk_attr_data;
    wire [TAGW-1:0] wk_tag;
    wire [TAGW-1:0] dp_slot = dp_data[TAGW-1:0];
    /* verilator lint_off UNUSEDSIGNAL */
    wire [7:0] dp_inst = cand_inst(s_keys[dp_slot], s_cand[dp_slot]);
    /* verilator lint_on UNUSEDSIGNAL */
    wire wk_err_resp;
    svo_walker_pool #(.POS_W(PW), .T_W(TW), .STACK_DEPTH(STACK_DEPTH), .MAX_STEPS(MAX_STEPS),
        .STEP_LATENCY(STEP_LATENCY), .TAG_W(TAGW), .CONTEXTS(CONTEXTS), .WALKERS(WALKERS),
        .CW(CW), .CTX_RESP(CTX_RESP), .ATTR_MERGE(ATTR_MERGE),
        .RESPONSE_REGISTER_CYCLES(RESP_REG), .REQUEST_REGISTER_CYCLES(REQ_REG)
    ) u_walker (.clk(clk), .rst(rst), .in_valid(dp_valid), .in_ready(wk_in_ready),
        .in_enter(dp_data[RTB-1]), .in_t0(dp_data[RTB-2 -: 3*TI]),
        .in_t1(dp_data[RTB-2-3*TI -: 3*TI]),
        .in_o(dp_data[3*PW+TAGW+6+3*(PW+1)-1 -: 3*(PW+1)]),
        .in_half(dp_data[3*PW+TAGW+6-1 -: 3*PW]), .in_zero(dp_data[TAGW+5 -: 3]),
        .in_neg(dp_data[TAGW+2 -: 3]), .in_node_base(inst_node_base),
        .in_attr_base(inst_attr_base), .in_tag(dp_slot),
        .mem_req_valid(mem_req_valid), .mem_req_ready(mem_req_ready), .mem_req_attr(mem_req_attr),
        .mem_req_addr(mem_req_addr), .mem_req_ctx(mem_req_ctx), .mem_resp_valid(mem_resp_valid),
        .mem_resp_ctx(mem_resp_ctx), .mem_resp_data(mem_resp_data),
        .ctx_resp_valid(ctx_resp_valid), .ctx_resp_data(ctx_resp_data), .out_valid(wk_out_valid),
        .out_ready(wk_out_ready), .out_outcome(wk_outcome), .out_t(wk_t), .out_voxel(wk_voxel),
        .out_attr_data(wk_attr_data), .out_tag(wk_tag), .err_resp(wk_err_resp));
    wire wk_leave = wk_out_valid && wk_out_ready;
    wire wk_better = wk_outcome == 2'd1
                  && (!s_best[wk_tag] || $signed(wk_t) < $signed(s_t[wk_tag]));
    wire wr_in_ready;
    assign wk_out_ready = wr_in_ready;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_WK_RC), .W(TAGW)) walker_to_record (.clk(clk), .rst(rst),
        .in_valid(wk_out_valid), .in_ready(wr_in_ready), .in_data(wk_tag),
        .out_valid(wr_valid), .out_ready(rc_take), .out_data(wr_slot), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- root
    wire rt_in_valid, rt_in_ready, rt_u_valid;
    wire [TAGW-1:0] rr_slot;                      // reciprocal_to_root's head
    /* verilator lint_off UNUSEDSIGNAL */
    wire [7:0] rr_inst = cand_inst(s_keys[rr_slot], s_cand[rr_slot]);
    /* verilator lint_on UNUSEDSIGNAL */
    wire rt_accept = rt_in_valid && rt_in_ready;
    wire rt_u_enter;
    wire [3*TI-1:0] rt_u_t0, rt_u_t1;
    wire [3*(PW+1)-1:0] rt_u_o;
    wire [3*PW-1:0] rt_u_half;
    wire [2:0] rt_u_zero, rt_u_neg;
    wire [TAGW-1:0] rt_u_tag;
    svo_walker_root #(.POS_W(PW), .POS_FRAC(POS_FRAC), .INV_W(INV_W), .INV_FRAC(INV_FRAC),
        .T_W(TW), .T_FRAC(T_FRAC), .PROD(ROOT_PROD), .TAG_W(TAGW)
    ) u_root (.clk(clk), .rst(rst), .in_valid(rt_accept), .in_o(s_o[rr_slot]),
        .in_inv(s_inv[rr_slot]), .in_half(inst_half),
        .in_zero(s_zero[rr_slot]), .in_neg(s_neg[rr_slot]), .in_tag(rr_slot),
        .out_valid(rt_u_valid), .out_enter(rt_u_enter), .out_t0(rt_u_t0), .out_t1(rt_u_t1),
        .out_o(rt_u_o), .out_half(rt_u_half), .out_zero(rt_u_zero), .out_neg(rt_u_neg),
        .out_tag(rt_u_tag));
    wire rt_valid, rt_ready;
    wire [RTB-1:0] rt_data;
    svo_elastic #(.L(RT_L), .W(RTB)) rt_pipe (.clk(clk), .rst(rst), .in_valid(rt_in_valid),
        .in_ready(rt_in_ready), .unit_valid(rt_u_valid),
        .unit_data({rt_u_enter, rt_u_t0, rt_u_t1, rt_u_o, rt_u_half, rt_u_zero, rt_u_neg,
                    rt_u_tag}),
        .out_valid(rt_valid), .out_ready(rt_ready), .out_data(rt_data));
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_RT_DP), .W(RTB)) root_to_dispatch (.clk(clk), .rst(rst),
        .in_valid(rt_valid), .in_ready(rt_ready), .in_data(rt_data), .out_valid(dp_valid),
        .out_ready(wk_in_ready), .out_data(dp_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- reciprocals
    wire rc_in_valid, rc_in_ready;
    wire [TAGW-1:0] tr_slot_head;                 // transform_to_reciprocal's head
    wire rc_accept = rc_in_valid && rc_in_ready;
    // The three units take the same walks: unit 0's valid stands for all. A flushed result
    // (|1/d| beyond the format: the zero-axis path) is the walk's, not an error.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [2:0] rc_u_valid, rc_fl;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [2:0] rc_u_zero, rc_u_neg, rc_ov;
    wire [INV_W-1:0] rc_u_inv [0:2];
    genvar ga;
    generate
        for (ga = 0; ga < 3; ga = ga + 1) begin : recip
            svo_reciprocal #(.SEED_FILE(RECIP_SEED_FILE)) u_recip (.clk(clk), .rst(rst), .in_valid(rc_accept),
                .in_d(s_d[tr_slot_head][ga*32 +: 32]),
                .in_sign_negative(s_sign[tr_slot_head][ga]), .out_valid(rc_u_valid[ga]),
                .out_inv(rc_u_inv[ga]), .out_zero(rc_u_zero[ga]), .out_negative(rc_u_neg[ga]),
                .out_flushed(rc_fl[ga]), .out_ov(rc_ov[ga]));
        end
    endgenerate
    wire [TAGW-1:0] rc_tag;
    wire rc_tag_valid;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(RC_L + 1), .W(TAGW)) rc_tags (.clk(clk), .rst(rst),
        .in_valid(rc_accept), .in_ready(), .in_data(tr_slot_head), .out_valid(rc_tag_valid),
        .out_ready(rc_u_valid[0]), .out_data(rc_tag), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    wire rc_valid, rc_ready;
    wire [TAGW-1:0] rc_data;
    svo_elastic #(.L(RC_L), .W(TAGW)) rc_pipe (.clk(clk), .rst(rst), .in_valid(rc_in_valid),
        .in_ready(rc_in_ready), .unit_valid(rc_u_valid[0]), .unit_data(rc_tag),
        .out_valid(rc_valid), .out_ready(rc_ready), .out_data(rc_data));
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_RC_RT), .W(TAGW)) reciprocal_to_root (.clk(clk), .rst(rst),
        .in_valid(rc_valid), .in_ready(rc_ready), .in_data(rc_data), .out_valid(rt_in_valid),
        .out_ready(rt_in_ready), .out_data(rr_slot), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    // |1/d| for the root (WalkerInput::set_axis), per axis.
    function automatic [INV_W-1:0] abs_inv(input [INV_W-1:0] v);
        abs_inv = v[INV_W-1] ? -v : v;
    endfunction

    // ---------------------------------------------------------------- transform
    wire lp_valid;                                // loop_back's head
    wire [TAGW-1:0] lp_slot;
    wire ck_valid;                                // check_to_transform's head
    wire [RAY-1:0] ck_data;
    wire [PIXW-1:0] ck_pixel;
    wire [95:0] ck_dir;
    wire [5:0] ck_count;
    wire [KEYS-1:0] ck_keys;
    assign {ck_pixel, ck_dir, ck_count, ck_keys} = ck_data;
    // The lowest free slot, counting the one the record frees in this cycle.
    wire [SLOTS-1:0] free_now = free | released;
    reg [TAGW-1:0] lowest;
    integer si;
    always @* begin
        lowest = {TAGW{1'b0}};
        for (si = SLOTS - 1; si >= 0; si = si - 1)
            if (free_now[si]) lowest = si[TAGW-1:0];
    end
    wire tr_in_ready, tr_u_valid, tr_ov_o, tr_ov_d;
    wire take_loop = lp_valid;
    wire take_new = !lp_valid && ck_valid && |free_now;
    wire tr_in_valid = take_loop || take_new;
    wire tr_accept = tr_in_valid && tr_in_ready;
    wire [TAGW-1:0] tr_slot = take_loop ? lp_slot : lowest;
    wire [95:0] tr_dir = take_loop ? s_dir[lp_slot] : ck_dir;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [7:0] tr_inst = take_loop ? cand_inst(s_keys[lp_slot], s_cand[lp_slot])
                                   : cand_inst(ck_keys, 6'd0);
    /* verilator lint_on UNUSEDSIGNAL */
    wire [3*PW-1:0] tr_u_o;
    wire [95:0] tr_u_d;
    wire [2:0] tr_u_sign;
    svo_transform u_transform (.clk(clk), .rst(rst), .in_valid(tr_accept), .in_o(cam_o),
        .in_d(tr_dir), .in_axes(inst_axes),
        .in_c(inst_c), .out_valid(tr_u_valid), .out_o(tr_u_o),
        .out_d(tr_u_d), .out_sign(tr_u_sign), .out_ov_origin(tr_ov_o), .out_ov_dir(tr_ov_d));
    wire [TAGW-1:0] tr_tag;
    wire tr_tag_valid;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(TR_L + 1), .W(TAGW)) tr_tags (.clk(clk), .rst(rst),
        .in_valid(tr_accept), .in_ready(), .in_data(tr_slot), .out_valid(tr_tag_valid),
        .out_ready(tr_u_valid), .out_data(tr_tag), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    wire tr_valid, tr_ready;
    wire [TAGW-1:0] tr_data;
    svo_elastic #(.L(TR_L), .W(TAGW)) tr_pipe (.clk(clk), .rst(rst), .in_valid(tr_in_valid),
        .in_ready(tr_in_ready), .unit_valid(tr_u_valid), .unit_data(tr_tag),
        .out_valid(tr_valid), .out_ready(tr_ready), .out_data(tr_data));
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_TR_RC), .W(TAGW)) transform_to_reciprocal (.clk(clk), .rst(rst),
        .in_valid(tr_valid), .in_ready(tr_ready), .in_data(tr_data), .out_valid(rc_in_valid),
        .out_ready(rc_in_ready), .out_data(tr_slot_head), .occupancy());
    wire lp_in_ready;
    svo_fifo #(.DEPTH(SLOTS), .W(TAGW)) loop_back (.clk(clk), .rst(rst), .in_valid(r_loop),
        .in_ready(lp_in_ready), .in_data(wr_slot), .out_valid(lp_valid),
        .out_ready(tr_accept && take_loop), .out_data(lp_slot), .occupancy());
    svo_fifo #(.DEPTH(D_CK_TR), .W(RAY)) check_to_transform (.clk(clk), .rst(rst),
        .in_valid(in_valid), .in_ready(in_ready), .in_data({in_pixel, in_dir, in_count, in_keys}),
        .out_valid(ck_valid), .out_ready(tr_accept && take_new), .out_data(ck_data),
        .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- slot state
    integer a;
    always @(posedge clk) begin
        // A new ray takes its slot.
        if (tr_accept && take_new) begin
            s_pixel[lowest] <= ck_pixel;
            s_dir[lowest] <= ck_dir;
            s_count[lowest] <= ck_count;
            s_keys[lowest] <= ck_keys;
            s_cand[lowest] <= 6'd0;
            s_walks[lowest] <= 16'd0;
            s_best[lowest] <= 1'b0;
        end
        // Unit results into their ray's slot.
        if (tr_u_valid) begin
            s_o[tr_tag] <= tr_u_o;
            s_d[tr_tag] <= tr_u_d;
            s_sign[tr_tag] <= tr_u_sign;
        end
        if (rc_u_valid[0]) begin
            for (a = 0; a < 3; a = a + 1) s_inv[rc_tag][a*INV_W +: INV_W] <= abs_inv(rc_u_inv[a]);
            s_zero[rc_tag] <= rc_u_zero;
            s_neg[rc_tag] <= rc_u_neg;
        end
        // The walk's hit, if it is the ray's best so far.
        if (wk_leave && wk_better) begin
            s_best[wk_tag] <= 1'b1;
            s_t[wk_tag] <= wk_t;
            s_attr[wk_tag] <= wk_attr_data;
            s_voxel[wk_tag] <= wk_voxel;
            s_inst[wk_tag] <= cand_inst(s_keys[wk_tag], s_cand[wk_tag]);
        end
        // The record's decision: the next candidate (a packed ray's slot may be taken by a
        // new ray in this very cycle, so nothing is written to it; done_walks counts the
        // last walk).
        if (r_loop) begin
            s_walks[wr_slot] <= s_walks[wr_slot] + 16'd1;
            s_cand[wr_slot] <= r_next;
        end
        if (rst) begin
            free <= {SLOTS{1'b1}};
            err_pipe <= 1'b0;
            err_overflow <= 1'b0;
        end else begin
            free <= (free | released) & ~((tr_accept && take_new) ? (one << lowest)
                                                                  : {SLOTS{1'b0}});
            if ((tr_u_valid && !tr_tag_valid) || (rc_u_valid[0] && !rc_tag_valid)
                || (r_loop && !lp_in_ready) || wk_err_resp)
                err_pipe <= 1'b1;
            if ((tr_u_valid && (tr_ov_o || tr_ov_d)) || (rc_u_valid[0] && |rc_ov)
                || (pk_u_valid && pk_ov))
                err_overflow <= 1'b1;
        end
    end
    // ---------------------------------------------------------------- instance table reads
    assign ird_tr = tr_inst;
    assign ird_rt = rr_inst;
    assign ird_dp = dp_inst;
    assign ird_nm = s_inst[wr_slot];
endmodule
`default_nettype wire
