// svo_walk_wide: the walk section at K walk-issue lanes (K 1 or 2), from check_to_transform to
// the record stage's word: the ray slots, K transforms (the loop-back before new rays), K lanes
// of three reciprocals, K walker roots, the walker pool with its dispatcher, the record stage's
// K decisions (early termination, the best hit) and K packing lanes (svo_walk_pack: svo_normal
// and svo_hit_pack).
//
// Pipeline position: docs/cycle-model.md §2.1 and testbench/README.md, "Walk issue of width
// k": check_to_transform → transform → transform_to_reciprocal → reciprocal →
// reciprocal_to_root → root → root_to_dispatch → walker → walker_to_record → record →
// loop_back (the next candidate) or the hit buffer's record ports. Cycle-exact with the
// model's stages (src/models/cycle/stages/{transform,passthrough,walkers,record}.rs) on
// hardware of K lanes (transform_units K, reciprocal_units 3K, walker_root_units K) and any
// walker pool svo_walker_pool builds: every joint an svo_fifo_wide of the model's depth and K
// ports a side, every fixed-latency unit kind behind one svo_unit_lanes (its slot tags in a
// FIFO of L + 1 per lane). svo_core builds it at K = 1 and 2 (until issue 29's K = 1 had its
// own module, svo_walk, with the same rules at one port a side; this module at K = 1 replaced
// it, bit- and cycle-exact on every bench). K above 2 is refused: record_to_write has
// max(K, record_writes) push ports in the model and svo_hit_buffer takes two.
//
// A ray arrives from the check stage with its direction and its sorted candidates (count and
// keys {instance 8, t_enter uQ10.22}) and takes the lowest free ray slot (SLOTS = walkers x
// contexts + root_to_dispatch); the slot holds it until its record leaves for packing. Each
// walk of the ray is one candidate, front to back: the record stage sends the next one back
// through loop_back unless the best hit so far ends the ray (FramePlan::stops: best t <= the
// next candidate's entry). The instance table gives the transform's axes and centre, the
// root's half extents, the walker's image bases and the normal matrix through K read ports
// per reader (`ird_*`: the instance read, lane j at [j*8 +: 8], `inst_*` its registers in the
// same cycle; the table answers asynchronously, one replicated port per reader, so the timing
// is that of the instance registers they replace). The record's normal is computed in the
// packing lane: the best hit's attribute normal and its instance's normal matrix (`inst_nmat`,
// 9 sQ2.16 elements row-major) through svo_normal (latency 13) beside an svo_delay of the other
// fields, then svo_hit_pack (1): the model's units.hit_pack of 14.
//
// Per cycle, consumers first:
// - record: walker_to_record's heads are decided in port order while a packing lane can take
//   one (svo_unit_lanes' in_ready after this cycle's leaves; a loop-back decision is gated
//   too but takes no lane); each either pushes the next candidate into loop_back (its ports in
//   decision order) or goes to the next packing lane, freeing its slot for this very cycle.
// - transform: one sequence of up to K walks, first loop_back's heads, then new rays from
//   check_to_transform while a slot is free (the record's releases counted); new ray m takes
//   the m-th lowest free slot. A cycle can take one loop-back walk and one new ray.
// - each unit stage: its ready results leave into the FIFO behind (up to K), then up to K
//   walks enter, each into the lowest lane with room (svo_unit_lanes).
// - walker pool: up to K retires into walker_to_record, up to K dispatches from
//   root_to_dispatch (svo_walker_pool's K ports, lane j at [j*W +: W], prefixes both ways):
//   WALKERS walkers of CONTEXTS contexts (per walker one step datapath, its contexts' state in
//   RAMs, behind one issue grant and one request port; see its header).
// A slot is read by K readers per stage (its walks are one at a time, so no two lanes touch
// one slot in a cycle) and written by up to K units a cycle.
// Sticky `err_pipe`: a unit result without its slot tag, loop_back refusing a walk (never
// expected: it has one entry per slot), or the pool's `err_resp` (a node read's response for
// a context with no read out); `err_overflow`: a transform, reciprocal or pack overflow flag
// (the datapath saturated, which the model counts: reported). Reciprocal seed ROMs:
// recip_lane[j].recip[a].u_recip.rom, loaded by the host as for svo_reciprocal.
`timescale 1ns/1ps
`default_nettype none
module svo_walk_wide #(
    parameter K         = 2,          // walk-issue lanes
    parameter LANES     = 8,
    parameter PIXW      = 32,
    parameter SLOTS     = 65,
    parameter TAGW      = 7,
    parameter PW        = 40,
    parameter TW        = 62,
    parameter POS_FRAC  = 32,
    parameter INV_W     = 52,
    parameter INV_FRAC  = 30,
    parameter T_FRAC    = 31,
    parameter ROOT_PROD = 4,
    parameter STACK_DEPTH  = 21,
    parameter MAX_STEPS    = 100000,
    parameter STEP_LATENCY = 3,
    parameter TR_L      = 9,
    parameter RC_L      = 26,
    parameter RT_L      = 8,
    parameter D_CK_TR   = 1024,
    parameter D_TR_RC   = 4,
    parameter D_RC_RT   = 4,
    parameter D_RT_DP   = 64,
    parameter D_WK_RC   = 16,
    parameter RECIP_SEED_FILE = "",
    parameter KEYN      = LANES,
    parameter CONTEXTS  = 1,
    parameter WALKERS   = 1,
    parameter CW        = WALKERS * CONTEXTS > 1 ? $clog2(WALKERS * CONTEXTS) : 1,
    parameter CTX_RESP  = 0,
    parameter ATTR_MERGE = 1,
    parameter RESP_REG = 0,
    parameter REQ_REG  = 0,
    parameter CRN       = CTX_RESP != 0 ? WALKERS * CONTEXTS : 1,  // (do not set)
    parameter CRW       = CTX_RESP == 2 ? 64 : 32                 // (do not set)
) (
    input  wire                    clk,
    input  wire                    rst,
    input  wire [3*PW-1:0]         cam_o,
    // the instance table's read ports, K per reader (lane j at [j*8 +: 8])
    output wire [K*8-1:0]          ird_tr,
    input  wire [K*288-1:0]        inst_axes,
    input  wire [K*120-1:0]        inst_c,
    output wire [K*8-1:0]          ird_rt,
    input  wire [K*120-1:0]        inst_half,
    output wire [K*8-1:0]          ird_dp,
    input  wire [K*32-1:0]         inst_node_base,
    input  wire [K*32-1:0]         inst_attr_base,
    output wire [K*8-1:0]          ird_nm,
    input  wire [K*162-1:0]        inst_nmat,
    // rays to walk (check_to_transform's first push port; the hit buffer offers one a cycle)
    input  wire                    in_valid,
    output wire                    in_ready,
    input  wire [PIXW-1:0]         in_pixel,
    input  wire [95:0]             in_dir,
    input  wire [5:0]              in_count,
    input  wire [KEYN*40-1:0]      in_keys,
    // the node memory: one read port per walker
    output wire [WALKERS-1:0]      mem_req_valid,
    input  wire [WALKERS-1:0]      mem_req_ready,
    output wire [WALKERS-1:0]      mem_req_attr,
    output wire [WALKERS*32-1:0]   mem_req_addr,
    input  wire [WALKERS-1:0]      mem_resp_valid,
    input  wire [WALKERS*64-1:0]   mem_resp_data,
    // records to the hit buffer: record_to_write's two push ports (a prefix)
    output wire                    rec_valid,
    input  wire                    rec_ready,
    output wire [PIXW-1:0]         rec_pixel,
    output wire [71:0]             rec_word,
    output wire                    rec2_valid,
    input  wire                    rec2_ready,
    output wire [PIXW-1:0]         rec2_pixel,
    output wire [71:0]             rec2_word,
    // the rays whose record is decided this cycle, decision j on lane j
    output wire [K-1:0]            done_valid,
    output wire [K*PIXW-1:0]       done_pixel,
    output wire [K*16-1:0]         done_walks,
    output wire [K-1:0]            done_hit,
    output wire [K*TW-1:0]         done_t,
    output wire [K*60-1:0]         done_voxel,
    output reg                     err_pipe,
    output reg                     err_overflow,
    output wire [WALKERS*CW-1:0]   mem_req_ctx,
    input  wire [WALKERS*CW-1:0]   mem_resp_ctx,
    input  wire [CRN-1:0]          ctx_resp_valid,
    input  wire [CRN*CRW-1:0]      ctx_resp_data
);
    localparam TI = TW + 1;
    localparam KEYS = KEYN * 40;
    localparam RAY = PIXW + 96 + 6 + KEYS;
    localparam RTB = 1 + 2 * 3 * TI + 3 * (PW + 1) + 3 * PW + 3 + 3 + TAGW;   // root bundle
    localparam SW = K > 1 ? $clog2(K) : 1;        // a lane's source index

    generate
        if ((1 << TAGW) < SLOTS || SLOTS < 2) begin : bad_slots
            svo_walk_wide_TAGW_must_address_SLOTS bad();
        end
        if (K < 1 || K > 2) begin : bad_lanes
            svo_walk_wide_K_1_to_2_record_to_write_has_two_push_ports bad();
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
    wire [SLOTS-1:0] one = {{(SLOTS-1){1'b0}}, 1'b1};
    // svo_walk's multiplexers over the keys (no variable part-select: see there).
    function automatic [7:0] cand_inst(input [KEYS-1:0] keys, input [5:0] c);
        integer q;
        begin
            cand_inst = 8'd0;
            for (q = 0; q < KEYS / 40; q = q + 1)
                if ({26'd0, c} == q) cand_inst = keys[q * 40 + 32 +: 8];
        end
    endfunction
    function automatic [31:0] cand_key(input [KEYS-1:0] keys, input [5:0] c);
        integer q;
        begin
            cand_key = 32'd0;
            for (q = 0; q < KEYS / 40; q = q + 1)
                if ({26'd0, c} == q) cand_key = keys[q * 40 +: 32];
        end
    endfunction
    function automatic [INV_W-1:0] abs_inv(input [INV_W-1:0] v);
        abs_inv = v[INV_W-1] ? -v : v;
    endfunction
    genvar g;

    // ---------------------------------------------------------------- record (first)
    wire [K-1:0] wr_valid;                        // walker_to_record's heads
    wire [K*TAGW-1:0] wr_slot;
    wire [K-1:0] r_more;                          // head j's ray needs its next candidate
    wire [K*6-1:0] r_next;
    generate
        for (g = 0; g < K; g = g + 1) begin : decide
            wire [TAGW-1:0] sl = wr_slot[g*TAGW +: TAGW];
            wire [5:0] nx = s_cand[sl] + 6'd1;
            wire [31:0] nk = cand_key(s_keys[sl], nx);
            // FramePlan::stops: best t (sQ31.31) <= the next key (uQ10.22).
            wire signed [TW+1:0] ta = $signed({{2{s_t[sl][TW-1]}}, s_t[sl]});
            wire signed [TW+1:0] tb = $signed({{(TW+2-32-9){1'b0}}, nk, 9'd0});
            assign r_more[g] = nx < s_count[sl] && !(s_best[sl] && ta <= tb);
            assign r_next[g*6 +: 6] = nx;
            assign done_pixel[g*PIXW +: PIXW] = s_pixel[sl];
            assign done_walks[g*16 +: 16] = s_walks[sl] + 16'd1;
            assign done_hit[g] = s_best[sl];
            assign done_t[g*TW +: TW] = s_t[sl];
            assign done_voxel[g*60 +: 60] = s_voxel[sl];
        end
    endgenerate
    wire [K-1:0] pk_in_ready;                     // port j: j + 1 packing lanes can take one
    // pk_valid is gated by pk_in_ready, which svo_unit_lanes computes in the always block that
    // also reads its in_valid (for lane_take): a loop for Verilator's ordering only, as its
    // in_ready depends on the lanes' counts and this cycle's leaves, never on in_valid.
    /* verilator lint_off UNOPTFLAT */
    reg [K-1:0] dec, r_loop, r_pack, pk_valid, lp_push;
    /* verilator lint_on UNOPTFLAT */
    reg [K*TAGW-1:0] pk_slot, lp_push_slot;
    reg [SLOTS-1:0] released;
    reg dec_on;
    integer j, np, nl;
    always @* begin
        dec_on = 1'b1;
        np = 0;
        nl = 0;
        released = {SLOTS{1'b0}};
        pk_valid = {K{1'b0}};
        pk_slot = {(K*TAGW){1'b0}};
        lp_push = {K{1'b0}};
        lp_push_slot = {(K*TAGW){1'b0}};
        for (j = 0; j < K; j = j + 1) begin
            dec[j] = dec_on && wr_valid[j] && pk_in_ready[np];
            r_pack[j] = dec[j] && !r_more[j];
            r_loop[j] = dec[j] && r_more[j];
            if (r_pack[j]) begin
                pk_valid[np] = 1'b1;
                pk_slot[np*TAGW +: TAGW] = wr_slot[j*TAGW +: TAGW];
                released = released | (one << wr_slot[j*TAGW +: TAGW]);
                np = np + 1;
            end
            if (r_loop[j]) begin
                lp_push[nl] = 1'b1;
                lp_push_slot[nl*TAGW +: TAGW] = wr_slot[j*TAGW +: TAGW];
                nl = nl + 1;
            end
            dec_on = dec[j];
        end
    end
    assign done_valid = r_pack;

    // The packing lanes: each pack's slot fields into svo_normal + svo_hit_pack.
    wire [K*8-1:0] pk_inst;
    wire [K*64-1:0] pk_attr;
    wire [K*(2+1+8+64+24+PIXW)-1:0] pk_fields;
    wire pk_ov;
    generate
        for (g = 0; g < K; g = g + 1) begin : pack_fields
            wire [TAGW-1:0] sl = pk_slot[g*TAGW +: TAGW];
            // sQ31.31 → uQ8.14, truncated; no hit: RecordT::far.
            wire signed [63:0] th = $signed({{(64-TW){s_t[sl][TW-1]}}, s_t[sl]}) >>> 17;
            wire [63:0] tp = s_best[sl] ? th : 64'h3fffff;
            assign pk_inst[g*8 +: 8] = s_inst[sl];
            assign pk_attr[g*64 +: 64] = s_attr[sl];
            assign pk_fields[g*(2+1+8+64+24+PIXW) +: 2+1+8+64+24+PIXW] = {
                s_count[sl] == 6'd1 ? 2'd1 : 2'd2, s_best[sl], s_inst[sl], tp,
                s_attr[sl][7:0], s_attr[sl][15:8], s_attr[sl][23:16], s_pixel[sl]};
        end
    endgenerate
    svo_walk_pack #(.K(K), .PIXW(PIXW)) u_pack (.clk(clk), .rst(rst), .in_valid(pk_valid),
        .in_ready(pk_in_ready), .in_inst(pk_inst), .in_attr(pk_attr), .in_fields(pk_fields),
        .ird_nm(ird_nm), .inst_nmat(inst_nmat),
        .rec_valid(rec_valid), .rec_ready(rec_ready), .rec_pixel(rec_pixel),
        .rec_word(rec_word), .rec2_valid(rec2_valid), .rec2_ready(rec2_ready),
        .rec2_pixel(rec2_pixel), .rec2_word(rec2_word), .err_overflow(pk_ov));

    // ---------------------------------------------------------------- walker
    wire [K-1:0] dp_valid, dp_ready;              // root_to_dispatch's heads
    wire [K*RTB-1:0] dp_data;
    wire [K-1:0] wk_out_valid, wk_out_ready;
    wire [K*2-1:0] wk_outcome;
    wire [K*TW-1:0] wk_t;
    wire [K*60-1:0] wk_voxel;
    wire [K*64-1:0] wk_attr_data;
    wire [K*TAGW-1:0] wk_tag;
    wire [K-1:0] p_enter;
    wire [K*3*TI-1:0] p_t0, p_t1;
    wire [K*3*(PW+1)-1:0] p_o;
    wire [K*3*PW-1:0] p_half;
    wire [K*3-1:0] p_zero, p_neg;
    wire [K*TAGW-1:0] p_tag;
    generate
        for (g = 0; g < K; g = g + 1) begin : dispatch
            wire [RTB-1:0] d = dp_data[g*RTB +: RTB];
            assign p_enter[g] = d[RTB-1];
            assign p_t0[g*3*TI +: 3*TI] = d[RTB-2 -: 3*TI];
            assign p_t1[g*3*TI +: 3*TI] = d[RTB-2-3*TI -: 3*TI];
            assign p_o[g*3*(PW+1) +: 3*(PW+1)] = d[3*PW+TAGW+6+3*(PW+1)-1 -: 3*(PW+1)];
            assign p_half[g*3*PW +: 3*PW] = d[3*PW+TAGW+6-1 -: 3*PW];
            assign p_zero[g*3 +: 3] = d[TAGW+5 -: 3];
            assign p_neg[g*3 +: 3] = d[TAGW+2 -: 3];
            assign p_tag[g*TAGW +: TAGW] = d[TAGW-1:0];
            assign ird_dp[g*8 +: 8] = cand_inst(s_keys[d[TAGW-1:0]], s_cand[d[TAGW-1:0]]);
        end
    endgenerate
    wire wk_err_resp;
    svo_walker_pool #(.POS_W(PW), .T_W(TW), .STACK_DEPTH(STACK_DEPTH), .MAX_STEPS(MAX_STEPS),
        .STEP_LATENCY(STEP_LATENCY), .TAG_W(TAGW), .CONTEXTS(CONTEXTS), .WALKERS(WALKERS),
        .CW(CW), .CTX_RESP(CTX_RESP), .ATTR_MERGE(ATTR_MERGE),
        .RESPONSE_REGISTER_CYCLES(RESP_REG), .REQUEST_REGISTER_CYCLES(REQ_REG), .K(K)
    ) u_walker (.clk(clk), .rst(rst), .in_valid(dp_valid), .in_ready(dp_ready),
        .in_enter(p_enter), .in_t0(p_t0), .in_t1(p_t1), .in_o(p_o), .in_half(p_half),
        .in_zero(p_zero), .in_neg(p_neg), .in_node_base(inst_node_base),
        .in_attr_base(inst_attr_base), .in_tag(p_tag),
        .mem_req_valid(mem_req_valid), .mem_req_ready(mem_req_ready), .mem_req_attr(mem_req_attr),
        .mem_req_addr(mem_req_addr), .mem_req_ctx(mem_req_ctx), .mem_resp_valid(mem_resp_valid),
        .mem_resp_ctx(mem_resp_ctx), .mem_resp_data(mem_resp_data),
        .ctx_resp_valid(ctx_resp_valid), .ctx_resp_data(ctx_resp_data), .out_valid(wk_out_valid),
        .out_ready(wk_out_ready), .out_outcome(wk_outcome), .out_t(wk_t), .out_voxel(wk_voxel),
        .out_attr_data(wk_attr_data), .out_tag(wk_tag), .err_resp(wk_err_resp));
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo_wide #(.K(K), .DEPTH(D_WK_RC), .W(TAGW)) walker_to_record (.clk(clk), .rst(rst),
        .in_valid(wk_out_valid), .in_ready(wk_out_ready), .in_data(wk_tag),
        .out_valid(wr_valid), .out_ready(dec), .out_data(wr_slot), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // A retiring walk's hit, if it is its ray's best so far.
    wire [K-1:0] wk_better;
    wire [K*8-1:0] wk_inst;
    generate
        for (g = 0; g < K; g = g + 1) begin : retire
            wire [TAGW-1:0] sl = wk_tag[g*TAGW +: TAGW];
            assign wk_better[g] = wk_out_valid[g] && wk_out_ready[g]
                && wk_outcome[g*2 +: 2] == 2'd1
                && (!s_best[sl] || $signed(wk_t[g*TW +: TW]) < $signed(s_t[sl]));
            assign wk_inst[g*8 +: 8] = cand_inst(s_keys[sl], s_cand[sl]);
        end
    endgenerate

    // ---------------------------------------------------------------- root
    wire [K-1:0] rt_in_valid, rt_in_ready;       // reciprocal_to_root's heads
    wire [K*TAGW-1:0] rr_slot;
    wire [K-1:0] rt_take, rt_u_valid;
    wire [K*SW-1:0] rt_src;
    wire [K*RTB-1:0] rt_u_data;
    generate
        for (g = 0; g < K; g = g + 1) begin : root
            wire [TAGW-1:0] sl = rr_slot[rt_src[g*SW +: SW]*TAGW +: TAGW];
            assign ird_rt[g*8 +: 8] = cand_inst(s_keys[sl], s_cand[sl]);
            wire u_enter;
            wire [3*TI-1:0] u_t0, u_t1;
            wire [3*(PW+1)-1:0] u_o;
            wire [3*PW-1:0] u_half;
            wire [2:0] u_zero, u_neg;
            wire [TAGW-1:0] u_tag;
            svo_walker_root #(.POS_W(PW), .POS_FRAC(POS_FRAC), .INV_W(INV_W),
                .INV_FRAC(INV_FRAC), .T_W(TW), .T_FRAC(T_FRAC), .PROD(ROOT_PROD), .TAG_W(TAGW)
            ) u_root (.clk(clk), .rst(rst), .in_valid(rt_take[g]), .in_o(s_o[sl]),
                .in_inv(s_inv[sl]), .in_half(inst_half[g*120 +: 120]), .in_zero(s_zero[sl]),
                .in_neg(s_neg[sl]), .in_tag(sl), .out_valid(rt_u_valid[g]),
                .out_enter(u_enter), .out_t0(u_t0), .out_t1(u_t1), .out_o(u_o),
                .out_half(u_half), .out_zero(u_zero), .out_neg(u_neg), .out_tag(u_tag));
            assign rt_u_data[g*RTB +: RTB] = {u_enter, u_t0, u_t1, u_o, u_half, u_zero, u_neg,
                                             u_tag};
        end
    endgenerate
    wire [K-1:0] rt_valid, rt_ready;
    wire [K*RTB-1:0] rt_data;
    svo_unit_lanes #(.K(K), .L(RT_L), .W(RTB)) rt_lanes (.clk(clk), .rst(rst),
        .in_valid(rt_in_valid), .in_ready(rt_in_ready), .lane_take(rt_take),
        .lane_src(rt_src), .unit_valid(rt_u_valid), .unit_data(rt_u_data),
        .out_valid(rt_valid), .out_ready(rt_ready), .out_data(rt_data));
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo_wide #(.K(K), .DEPTH(D_RT_DP), .W(RTB)) root_to_dispatch (.clk(clk), .rst(rst),
        .in_valid(rt_valid), .in_ready(rt_ready), .in_data(rt_data), .out_valid(dp_valid),
        .out_ready(dp_ready), .out_data(dp_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- reciprocals
    wire [K-1:0] rc_in_valid, rc_in_ready;       // transform_to_reciprocal's heads
    wire [K*TAGW-1:0] tr_head;
    wire [K-1:0] rc_take, rc_u_valid, rc_tag_valid, rc_ovf;
    wire [K*SW-1:0] rc_src;
    wire [K*TAGW-1:0] rc_tag;
    wire [K*3*INV_W-1:0] rc_inv;                  // |1/d| per axis
    wire [K*3-1:0] rc_zero, rc_neg;
    generate
        for (g = 0; g < K; g = g + 1) begin : recip_lane
            wire [TAGW-1:0] sl = tr_head[rc_src[g*SW +: SW]*TAGW +: TAGW];
            // The three units take the same walks: unit 0's valid stands for all; a flushed
            // result is the walk's (svo_walk).
            /* verilator lint_off UNUSEDSIGNAL */
            wire [2:0] uv, fl;
            /* verilator lint_on UNUSEDSIGNAL */
            wire [2:0] ov;
            genvar a;
            for (a = 0; a < 3; a = a + 1) begin : recip
                wire [INV_W-1:0] inv;
                svo_reciprocal #(.SEED_FILE(RECIP_SEED_FILE)) u_recip (.clk(clk), .rst(rst),
                    .in_valid(rc_take[g]), .in_d(s_d[sl][a*32 +: 32]),
                    .in_sign_negative(s_sign[sl][a]), .out_valid(uv[a]), .out_inv(inv),
                    .out_zero(rc_zero[g*3 + a]), .out_negative(rc_neg[g*3 + a]),
                    .out_flushed(fl[a]), .out_ov(ov[a]));
                assign rc_inv[(g*3 + a)*INV_W +: INV_W] = abs_inv(inv);
            end
            assign rc_u_valid[g] = uv[0];
            assign rc_ovf[g] = |ov;
            /* verilator lint_off PINCONNECTEMPTY */
            svo_fifo #(.DEPTH(RC_L + 1), .W(TAGW)) tags (.clk(clk), .rst(rst),
                .in_valid(rc_take[g]), .in_ready(), .in_data(sl),
                .out_valid(rc_tag_valid[g]), .out_ready(uv[0]),
                .out_data(rc_tag[g*TAGW +: TAGW]), .occupancy());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire [K-1:0] rc_valid, rc_ready;
    wire [K*TAGW-1:0] rc_data;
    svo_unit_lanes #(.K(K), .L(RC_L), .W(TAGW)) rc_lanes (.clk(clk), .rst(rst),
        .in_valid(rc_in_valid), .in_ready(rc_in_ready), .lane_take(rc_take),
        .lane_src(rc_src), .unit_valid(rc_u_valid), .unit_data(rc_tag),
        .out_valid(rc_valid), .out_ready(rc_ready), .out_data(rc_data));
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo_wide #(.K(K), .DEPTH(D_RC_RT), .W(TAGW)) reciprocal_to_root (.clk(clk),
        .rst(rst), .in_valid(rc_valid), .in_ready(rc_ready), .in_data(rc_data),
        .out_valid(rt_in_valid), .out_ready(rt_in_ready), .out_data(rr_slot), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- transform
    wire [K-1:0] lp_valid;                        // loop_back's heads
    wire [K*TAGW-1:0] lp_slot;
    wire [K-1:0] ck_valid;                        // check_to_transform's heads
    wire [K*RAY-1:0] ck_data;
    wire [K-1:0] tr_in_ready;
    // The sequence of this cycle's walks: loop_back's heads, then new rays while slots are
    // free; new ray m takes pick[m], the m-th lowest free slot (this cycle's releases too).
    wire [SLOTS-1:0] free_now = free | released;
    reg [K*TAGW-1:0] pick, it_slot;
    reg [K-1:0] pick_ok, tr_in_valid, it_loop, lp_take, ck_take, it_new_taken;
    reg [K*SW-1:0] it_m;                          // item i, a new ray: its port on check_to_transform
    reg [SLOTS-1:0] mask, taken_mask;
    reg tr_on;
    integer m, i, si, nlp;
    /* verilator lint_off UNUSEDSIGNAL */
    integer im;                                   // its low SW bits are the port
    integer pj;
    /* verilator lint_on UNUSEDSIGNAL */
    always @* begin
        mask = free_now;
        pick = {(K*TAGW){1'b0}};
        pick_ok = {K{1'b0}};
        for (m = 0; m < K; m = m + 1) begin
            pick_ok[m] = |mask;
            for (si = SLOTS - 1; si >= 0; si = si - 1)
                if (mask[si]) pick[m*TAGW +: TAGW] = si[TAGW-1:0];
            if (pick_ok[m]) mask = mask & ~(one << pick[m*TAGW +: TAGW]);
        end
        nlp = 0;
        for (i = 0; i < K; i = i + 1)
            if (lp_valid[i]) nlp = nlp + 1;
        tr_on = 1'b1;
        im = 0;
        it_slot = {(K*TAGW){1'b0}};
        it_m = {(K*SW){1'b0}};
        for (i = 0; i < K; i = i + 1) begin
            it_loop[i] = i < nlp;
            if (i < nlp) begin
                tr_in_valid[i] = tr_on;
                it_slot[i*TAGW +: TAGW] = lp_slot[i*TAGW +: TAGW];
            end else begin
                im = i - nlp;
                tr_in_valid[i] = tr_on && ck_valid[im] && pick_ok[im];
                // A multiplexer over the picks (an index product im * TAGW became a
                // DSP48E2 in Yosys at K = 1).
                for (pj = 0; pj < K; pj = pj + 1)
                    if (pj == im) it_slot[i*TAGW +: TAGW] = pick[pj*TAGW +: TAGW];
                it_m[i*SW +: SW] = im[SW-1:0];
            end
            tr_on = tr_in_valid[i];
        end
    end
    // What the transform's lanes take of the sequence (a prefix): the FIFOs' pops, the slots.
    integer t;
    always @* begin
        lp_take = {K{1'b0}};
        ck_take = {K{1'b0}};
        it_new_taken = {K{1'b0}};
        taken_mask = {SLOTS{1'b0}};
        for (t = 0; t < K; t = t + 1)
            if (tr_in_valid[t] && tr_in_ready[t]) begin
                if (it_loop[t]) lp_take[t] = 1'b1;
                else begin
                    ck_take[it_m[t*SW +: SW]] = 1'b1;
                    it_new_taken[t] = 1'b1;
                    taken_mask = taken_mask | (one << it_slot[t*TAGW +: TAGW]);
                end
            end
    end
    wire [K-1:0] tr_take, tr_u_valid, tr_tag_valid, tr_ovf;
    wire [K*SW-1:0] tr_src;
    wire [K*TAGW-1:0] tr_tag;
    wire [K*3*PW-1:0] tr_u_o;
    wire [K*96-1:0] tr_u_d;
    wire [K*3-1:0] tr_u_sign;
    generate
        for (g = 0; g < K; g = g + 1) begin : transform
            wire [SW-1:0] src = tr_src[g*SW +: SW];
            wire [TAGW-1:0] sl = it_slot[src*TAGW +: TAGW];
            wire [RAY-1:0] ray = ck_data[it_m[src*SW +: SW]*RAY +: RAY];
            /* verilator lint_off UNUSEDSIGNAL */
            wire [PIXW-1:0] r_pixel;
            wire [5:0] r_count;
            /* verilator lint_on UNUSEDSIGNAL */
            wire [95:0] r_dir;
            wire [KEYS-1:0] r_keys;
            assign {r_pixel, r_dir, r_count, r_keys} = ray;
            wire lp = it_loop[src];
            assign ird_tr[g*8 +: 8] = lp ? cand_inst(s_keys[sl], s_cand[sl])
                                         : cand_inst(r_keys, 6'd0);
            wire ov_o, ov_d;
            svo_transform u_transform (.clk(clk), .rst(rst), .in_valid(tr_take[g]),
                .in_o(cam_o), .in_d(lp ? s_dir[sl] : r_dir),
                .in_axes(inst_axes[g*288 +: 288]), .in_c(inst_c[g*120 +: 120]),
                .out_valid(tr_u_valid[g]), .out_o(tr_u_o[g*3*PW +: 3*PW]),
                .out_d(tr_u_d[g*96 +: 96]), .out_sign(tr_u_sign[g*3 +: 3]),
                .out_ov_origin(ov_o), .out_ov_dir(ov_d));
            assign tr_ovf[g] = ov_o || ov_d;
            /* verilator lint_off PINCONNECTEMPTY */
            svo_fifo #(.DEPTH(TR_L + 1), .W(TAGW)) tags (.clk(clk), .rst(rst),
                .in_valid(tr_take[g]), .in_ready(), .in_data(sl),
                .out_valid(tr_tag_valid[g]), .out_ready(tr_u_valid[g]),
                .out_data(tr_tag[g*TAGW +: TAGW]), .occupancy());
            /* verilator lint_on PINCONNECTEMPTY */
        end
    endgenerate
    wire [K-1:0] tr_valid, tr_ready;
    wire [K*TAGW-1:0] tr_data;
    svo_unit_lanes #(.K(K), .L(TR_L), .W(TAGW)) tr_lanes (.clk(clk), .rst(rst),
        .in_valid(tr_in_valid), .in_ready(tr_in_ready), .lane_take(tr_take),
        .lane_src(tr_src), .unit_valid(tr_u_valid), .unit_data(tr_tag),
        .out_valid(tr_valid), .out_ready(tr_ready), .out_data(tr_data));
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo_wide #(.K(K), .DEPTH(D_TR_RC), .W(TAGW)) transform_to_reciprocal (.clk(clk),
        .rst(rst), .in_valid(tr_valid), .in_ready(tr_ready), .in_data(tr_data),
        .out_valid(rc_in_valid), .out_ready(rc_in_ready), .out_data(tr_head), .occupancy());
    wire [K-1:0] lp_in_ready;
    svo_fifo_wide #(.K(K), .DEPTH(SLOTS), .W(TAGW)) loop_back (.clk(clk), .rst(rst),
        .in_valid(lp_push), .in_ready(lp_in_ready), .in_data(lp_push_slot),
        .out_valid(lp_valid), .out_ready(lp_take), .out_data(lp_slot), .occupancy());
    /* verilator lint_off UNUSEDSIGNAL */
    wire [K-1:0] ck_in_ready;                     // (one push port used: one ray a cycle)
    /* verilator lint_on UNUSEDSIGNAL */
    localparam [K-1:0] PORT0 = 1;
    svo_fifo_wide #(.K(K), .DEPTH(D_CK_TR), .W(RAY)) check_to_transform (.clk(clk),
        .rst(rst), .in_valid({K{in_valid}} & PORT0), .in_ready(ck_in_ready),
        .in_data({K{in_pixel, in_dir, in_count, in_keys}}),
        .out_valid(ck_valid), .out_ready(ck_take), .out_data(ck_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    assign in_ready = ck_in_ready[0];

    // ---------------------------------------------------------------- slot state
    integer l;
    always @(posedge clk) begin
        // New rays take their slots.
        for (l = 0; l < K; l = l + 1)
            if (it_new_taken[l]) begin
                {s_pixel[it_slot[l*TAGW +: TAGW]], s_dir[it_slot[l*TAGW +: TAGW]],
                 s_count[it_slot[l*TAGW +: TAGW]], s_keys[it_slot[l*TAGW +: TAGW]]}
                    <= ck_data[it_m[l*SW +: SW]*RAY +: RAY];
                s_cand[it_slot[l*TAGW +: TAGW]] <= 6'd0;
                s_walks[it_slot[l*TAGW +: TAGW]] <= 16'd0;
                s_best[it_slot[l*TAGW +: TAGW]] <= 1'b0;
            end
        // Unit results into their rays' slots.
        for (l = 0; l < K; l = l + 1) begin
            if (tr_u_valid[l]) begin
                s_o[tr_tag[l*TAGW +: TAGW]] <= tr_u_o[l*3*PW +: 3*PW];
                s_d[tr_tag[l*TAGW +: TAGW]] <= tr_u_d[l*96 +: 96];
                s_sign[tr_tag[l*TAGW +: TAGW]] <= tr_u_sign[l*3 +: 3];
            end
            if (rc_u_valid[l]) begin
                s_inv[rc_tag[l*TAGW +: TAGW]] <= rc_inv[l*3*INV_W +: 3*INV_W];
                s_zero[rc_tag[l*TAGW +: TAGW]] <= rc_zero[l*3 +: 3];
                s_neg[rc_tag[l*TAGW +: TAGW]] <= rc_neg[l*3 +: 3];
            end
        end
        // The walks' hits, each if it is its ray's best so far.
        for (l = 0; l < K; l = l + 1)
            if (wk_better[l]) begin
                s_best[wk_tag[l*TAGW +: TAGW]] <= 1'b1;
                s_t[wk_tag[l*TAGW +: TAGW]] <= wk_t[l*TW +: TW];
                s_attr[wk_tag[l*TAGW +: TAGW]] <= wk_attr_data[l*64 +: 64];
                s_voxel[wk_tag[l*TAGW +: TAGW]] <= wk_voxel[l*60 +: 60];
                s_inst[wk_tag[l*TAGW +: TAGW]] <= wk_inst[l*8 +: 8];
            end
        // The record's decisions: the next candidate (a packed ray's slot may be taken by a
        // new ray in this very cycle, so nothing is written to it).
        for (l = 0; l < K; l = l + 1)
            if (r_loop[l]) begin
                s_walks[wr_slot[l*TAGW +: TAGW]] <= s_walks[wr_slot[l*TAGW +: TAGW]] + 16'd1;
                s_cand[wr_slot[l*TAGW +: TAGW]] <= r_next[l*6 +: 6];
            end
        if (rst) begin
            free <= {SLOTS{1'b1}};
            err_pipe <= 1'b0;
            err_overflow <= 1'b0;
        end else begin
            free <= free_now & ~taken_mask;
            if (|(tr_u_valid & ~tr_tag_valid) || |(rc_u_valid & ~rc_tag_valid)
                || |(lp_push & ~lp_in_ready) || wk_err_resp)
                err_pipe <= 1'b1;
            if (|(tr_u_valid & tr_ovf) || |(rc_u_valid & rc_ovf) || pk_ov)
                err_overflow <= 1'b1;
        end
    end
endmodule
`default_nettype wire
