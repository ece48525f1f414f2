// svo_core: the accelerator as one piece of RTL, for K walk-issue lanes (1 or 2) and a walker pool of
// WALKERS × CONTEXTS (default one walker of one context): svo_front → svo_hit_buffer → svo_walk_wide → back into the hit buffer, every joint
// valid/ready with back-pressure, the cycle model's FIFOs and pipes between the units.
//
// Pipeline position: all of docs/cycle-model.md §2.1, raygen to the hit-buffer write. What it
// takes from outside (the host's side, as the register block and memories of a board would
// give it): the direction table (`dir_pixel` → `dir_f64`, read in the cycle, or a stream:
// `dir_valid` low holds ray generation, `dir_take` pops it), the camera, the instance table's
// read ports (the frame's `n_inst` instances of up to NINST, held by the host's side in
// on-chip RAM, svo_top's svo_inst_table: LANES ports for the sphere lanes, instance
// `inst_base` + l on lane l, and one each for the transform, the walker root, the walker's
// image bases and the record stage's svo_normal, `ird_*` → `inst_*`, all answered in the
// same cycle), the frame's reuse flags (a dirty bit per instance) and miss word, and the
// node memory behind one read port. What it gives: the hit-buffer writes, one per bank and cycle
// (`wr_*`: the record FIFO's head; `wr1_*`: the check's word; `wr2_*`: a second record), which
// are the frame's pixel stream; the rays the check stage takes and each ray's walk results
// (`chk_*`, `done_*`), for checking; sticky errors and overflow flags. `wr_hold` (a full pixel
// stream) stops the writes for a cycle; tied to 0 the write stage is the model's.
//
// Cycle-exact with the cycle model on the hardware of testbench/hw/frame_hw.ron (tb_frame.sv,
// tests/testbench_icarus.rs): the frame's cycles and every pixel's write cycle equal the
// model's, and on testbench/hw/pool_1x4.ron and pool_2x4.ron (the walker pool of WALKERS ×
// CONTEXTS, svo_walker_pool, through svo_top and the cocotb bench), and at K = 2 on
// pool_4x2_k2.ron (svo_walk_wide). The node memory of the
// default hardware (the banks' arbitration, cache, MSHRs, DRAM) is not here yet (issue 29):
// each walker has a read port; svo_top.sv wraps this core in its AXI interfaces.
`timescale 1ns/1ps
`default_nettype none
module svo_core #(
    parameter LANES    = 8,
    parameter NPIX     = 768,                     // the hit buffer's pixels
    parameter AW       = 10,                      // hit-buffer address bits
    parameter PIXW     = 32,
    parameter SLOTS    = 65,
    parameter TAGW     = 7,
    parameter PW       = 40,
    parameter TW       = 62,
    parameter POS_FRAC = 32,
    parameter INV_W    = 52,
    parameter INV_FRAC = 30,
    parameter T_FRAC   = 31,
    parameter ROOT_PROD = 4,
    parameter STACK_DEPTH  = 21,
    parameter MAX_STEPS    = 100000,
    parameter STEP_LATENCY = 3,
    parameter RG_L     = 4,
    parameter SP_L     = 48,
    parameter SO_N     = 8,
    parameter SO_D     = 6,
    parameter SO_S     = SO_N / 2,
    parameter [SO_D*SO_S*16-1:0] SO_PAIRS = {(SO_D*SO_S*16){1'b0}},
    parameter SO_MAX_KEYS = 2 * SO_N,
    parameter TR_L     = 9,
    parameter RC_L     = 26,
    parameter RT_L     = 8,
    parameter HB_READ  = 4,
    parameter WRITE_PORTS   = 2,
    parameter RECORD_WRITES = 2,
    parameter D_RG_SP  = 4,
    parameter D_SP_SO  = 4,
    parameter D_SO_CK  = 8,
    parameter D_CK_TR  = 1024,
    parameter D_TR_RC  = 4,
    parameter D_RC_RT  = 4,
    parameter D_RT_DP  = 64,
    parameter D_WK_RC  = 16,
    parameter D_RC_WR  = 8,
    parameter DIR_FIXED = 0,                      // dir_f64 holds sQ2.30 codes (svo_raygen)
    parameter RECIP_SEED_FILE = "",               // reciprocal seed ROM file ("": the bench loads it)
    parameter NINST    = LANES,                   // the instance table's entries (≤ 255)
    parameter KEYN     = LANES,                   // candidates a ray carries (≤ SO_MAX_KEYS)
    parameter CONTEXTS = 1,                       // walker_pool.contexts_per_walker
    parameter WALKERS  = 1,                       // walker_pool.walkers: a node-memory port each
    parameter CW       = WALKERS * CONTEXTS > 1 ? $clog2(WALKERS * CONTEXTS) : 1,
    parameter CTX_RESP = 0,                       // per-context response ports (svo_walker_pool): 1 node words, 2 all
    parameter ATTR_MERGE = 1,                     // svo_walker_pool's attribute-merge rule (0 behind a cache)
    parameter RESP_REG = 0,                       // svo_walker_pool's response / request register
    parameter REQ_REG = 0,                        //   (walker_pool.*_register_cycles, 0 or 1)
    parameter K        = 1,                       // walk-issue lanes (1 or 2, svo_walk_wide)
    parameter CRN      = CTX_RESP != 0 ? WALKERS * CONTEXTS : 1,  // their count (do not set)
    parameter CRW      = CTX_RESP == 2 ? 64 : 32                 // their width (do not set)
) (
    input  wire                    clk,
    input  wire                    rst,
    input  wire                    run,
    input  wire [PIXW-1:0]         npix,
    // host: direction table and camera
    output wire [PIXW-1:0]         dir_pixel,
    input  wire [3*64-1:0]         dir_f64,
    input  wire                    dir_valid,
    output wire                    dir_take,
    input  wire [3*64-1:0]         origin_f64,
    input  wire [3*PW-1:0]         cam_o,
    // host: the instance table's read ports (sphere lanes: instance inst_base + l on lane l)
    output wire [7:0]              inst_base,
    input  wire [7:0]              n_inst,
    input  wire [LANES*120-1:0]    inst_c,
    input  wire [LANES*64-1:0]     inst_threshold,
    input  wire [LANES*64-1:0]     inst_inside,
    input  wire [LANES*34-1:0]     inst_delta_t,
    input  wire [LANES*40-1:0]     inst_reach,
    input  wire [LANES*80-1:0]     inst_reach2,
    // (the walk section: transform, walker root, walker, normal unit; K ports each, lane j
    // at [j*8 +: 8] and the j-th slice of its fields)
    output wire [K*8-1:0]          ird_tr,
    input  wire [K*288-1:0]        inst_axes,
    input  wire [K*120-1:0]        inst_c_tr,
    output wire [K*8-1:0]          ird_rt,
    input  wire [K*120-1:0]        inst_half,
    output wire [K*8-1:0]          ird_dp,
    input  wire [K*32-1:0]         inst_node_base,
    input  wire [K*32-1:0]         inst_attr_base,
    output wire [K*8-1:0]          ird_nm,
    input  wire [K*9*18-1:0]       inst_nmat,       // the normal matrix, sQ2.16 row-major
    // host: the frame's reuse flags and the word of a ray without candidates
    input  wire                    buffer_valid,
    input  wire                    camera_dirty,
    input  wire [NINST-1:0]        instance_dirty,
    input  wire [71:0]             miss_word,
    input  wire                    wr_hold,
    // node memory: one read port per walker (svo_walk_wide)
    output wire [WALKERS-1:0]      mem_req_valid,
    input  wire [WALKERS-1:0]      mem_req_ready,
    output wire [WALKERS-1:0]      mem_req_attr,
    output wire [WALKERS*32-1:0]   mem_req_addr,
    input  wire [WALKERS-1:0]      mem_resp_valid,
    input  wire [WALKERS*64-1:0]   mem_resp_data,
    // the pixel stream: the hit buffer's writes
    output wire                    wr_valid,
    output wire [PIXW-1:0]         wr_pixel,
    output wire [71:0]             wr_word,
    output wire                    wr_direct,
    output wire                    wr1_valid,
    output wire [PIXW-1:0]         wr1_pixel,
    output wire [71:0]             wr1_word,
    output wire                    wr2_valid,
    output wire [PIXW-1:0]         wr2_pixel,
    output wire [71:0]             wr2_word,
    // for checking: the rays the check stage takes, and each ray's walk results
    output wire                    chk_valid,
    output wire [PIXW-1:0]         chk_pixel,
    output wire [95:0]             chk_dir,
    output wire [5:0]              chk_count,
    // (up to K rays a cycle, lane j the record's decision j)
    output wire [K-1:0]            done_valid,
    output wire [K*PIXW-1:0]       done_pixel,
    output wire [K*16-1:0]         done_walks,
    output wire [K-1:0]            done_hit,
    output wire [K*TW-1:0]         done_t,
    output wire [K*60-1:0]         done_voxel,
    // events and sticky flags
    output wire                    ev_reused,
    output wire                    ev_write_stall,
    output wire                    ev_walk_stall,
    output wire                    ev_bank_conflict,
    output wire                    err_pipe,
    output wire                    err_overflow,
    output wire                    err_pixel,
    // the node memory's context of a read: a response carries its read's (any order)
    output wire [WALKERS*CW-1:0]   mem_req_ctx,
    input  wire [WALKERS*CW-1:0]   mem_resp_ctx,
    // with CTX_RESP, a response port per context: its node word (1: svo_top's on-chip
    // store), or every response, records included (2: svo_top behind its node cache)
    input  wire [CRN-1:0]          ctx_resp_valid,
    input  wire [CRN*CRW-1:0]      ctx_resp_data
);
    localparam PAYW = 96 + 6 + KEYN * 40;
    localparam SO_CW = 6;

    // ---------------------------------------------------------------- front end
    wire fr_valid, hb_in_ready, fr_err_pipe, fr_err_ov;
    wire [PIXW-1:0] fr_pixel;
    wire [95:0] fr_dir;
    wire [SO_CW-1:0] fr_count;
    wire [KEYN*40-1:0] fr_keys;
    svo_front #(.LANES(LANES), .PIXW(PIXW), .RG_L(RG_L), .SP_L(SP_L), .SO_N(SO_N), .SO_D(SO_D),
        .SO_S(SO_S), .SO_PAIRS(SO_PAIRS), .SO_MAX_KEYS(SO_MAX_KEYS), .SO_CW(SO_CW),
        .D_RG_SP(D_RG_SP), .D_SP_SO(D_SP_SO), .D_SO_CK(D_SO_CK), .DIR_FIXED(DIR_FIXED),
        .NINST(NINST), .KEYN(KEYN))
        u_front (.clk(clk), .rst(rst), .run(run), .npix(npix), .dir_pixel(dir_pixel),
        .dir_f64(dir_f64), .dir_valid(dir_valid), .dir_take(dir_take),
        .origin_f64(origin_f64), .cam_o(cam_o), .inst_base(inst_base), .n_inst(n_inst),
        .inst_c(inst_c),
        .inst_threshold(inst_threshold), .inst_inside(inst_inside),
        .inst_delta_t(inst_delta_t), .inst_reach(inst_reach), .inst_reach2(inst_reach2),
        .out_valid(fr_valid), .out_ready(hb_in_ready),
        .out_pixel(fr_pixel), .out_dir(fr_dir), .out_count(fr_count), .out_keys(fr_keys),
        .err_pipe(fr_err_pipe), .err_overflow(fr_err_ov));
    assign chk_valid = fr_valid && hb_in_ready;
    assign chk_pixel = fr_pixel;
    assign chk_dir = fr_dir;
    assign chk_count = fr_count;

    // ---------------------------------------------------------------- hit buffer
    wire hb_walk_valid, hb_walk_ready, rec_valid, rec_ready;
    wire [PIXW-1:0] hb_walk_pixel, rec_pixel;
    wire [PAYW-1:0] hb_walk_payload;
    wire [71:0] rec_word;
    wire rec2_valid, rec2_ready;                   // the record stage's second push
    wire [PIXW-1:0] rec2_pixel;
    wire [71:0] rec2_word;
    svo_hit_buffer #(.NPIX(NPIX), .AW(AW), .PIXW(PIXW), .INSTANCES(NINST), .HB_READ(HB_READ),
        .PAYW(PAYW), .WR_DEPTH(D_RC_WR), .WRITE_PORTS(WRITE_PORTS),
        .RECORD_WRITES(RECORD_WRITES))
    u_hit_buffer (.clk(clk), .rst(rst), .buffer_valid(buffer_valid),
        .camera_dirty(camera_dirty), .instance_dirty(instance_dirty), .miss_word(miss_word),
        .wr_hold(wr_hold), .in_valid(fr_valid), .in_ready(hb_in_ready), .in_pixel(fr_pixel),
        .in_candidates({{(16-SO_CW){1'b0}}, fr_count}),
        .in_candidate(fr_count == 6'd1 ? {8'd0, fr_keys[39:32]} : 16'd0),
        .in_payload({fr_dir, fr_count, fr_keys}), .walk_valid(hb_walk_valid),
        .walk_ready(hb_walk_ready), .walk_pixel(hb_walk_pixel), .walk_payload(hb_walk_payload),
        .rec_valid(rec_valid), .rec_ready(rec_ready), .rec_pixel(rec_pixel),
        .rec_word(rec_word), .rec2_valid(rec2_valid), .rec2_ready(rec2_ready),
        .rec2_pixel(rec2_pixel), .rec2_word(rec2_word), .wr_valid(wr_valid), .wr_pixel(wr_pixel), .wr_word(wr_word),
        .wr_direct(wr_direct), .wr1_valid(wr1_valid), .wr1_pixel(wr1_pixel),
        .wr1_word(wr1_word), .wr2_valid(wr2_valid), .wr2_pixel(wr2_pixel), .wr2_word(wr2_word),
        .ev_reused(ev_reused), .ev_write_stall(ev_write_stall), .ev_walk_stall(ev_walk_stall),
        .ev_bank_conflict(ev_bank_conflict), .err_pixel(err_pixel));

    // ---------------------------------------------------------------- walk section
    // The walk-issue lanes: svo_walk_wide, K of them (K = 1: one lane, the same rules).
    wire wk_err_pipe, wk_err_ov;
    svo_walk_wide #(.K(K), .LANES(LANES), .PIXW(PIXW), .SLOTS(SLOTS), .TAGW(TAGW), .PW(PW), .TW(TW),
        .POS_FRAC(POS_FRAC), .INV_W(INV_W), .INV_FRAC(INV_FRAC), .T_FRAC(T_FRAC),
        .ROOT_PROD(ROOT_PROD), .STACK_DEPTH(STACK_DEPTH), .MAX_STEPS(MAX_STEPS),
        .STEP_LATENCY(STEP_LATENCY), .TR_L(TR_L), .RC_L(RC_L), .RT_L(RT_L),
        .D_CK_TR(D_CK_TR), .D_TR_RC(D_TR_RC), .D_RC_RT(D_RC_RT), .D_RT_DP(D_RT_DP),
        .D_WK_RC(D_WK_RC), .RECIP_SEED_FILE(RECIP_SEED_FILE), .KEYN(KEYN), .CONTEXTS(CONTEXTS),
        .WALKERS(WALKERS), .CW(CW), .CTX_RESP(CTX_RESP),
        .ATTR_MERGE(ATTR_MERGE), .RESP_REG(RESP_REG), .REQ_REG(REQ_REG))
    u_walk (.clk(clk), .rst(rst), .cam_o(cam_o), .ird_tr(ird_tr), .inst_axes(inst_axes),
        .inst_c(inst_c_tr), .ird_rt(ird_rt), .inst_half(inst_half), .ird_dp(ird_dp),
        .inst_node_base(inst_node_base), .inst_attr_base(inst_attr_base), .ird_nm(ird_nm),
        .in_valid(hb_walk_valid), .in_ready(hb_walk_ready),
        .in_pixel(hb_walk_pixel), .in_dir(hb_walk_payload[PAYW-1 -: 96]),
        .in_count(hb_walk_payload[KEYN*40 +: 6]), .in_keys(hb_walk_payload[KEYN*40-1:0]),
        .mem_req_valid(mem_req_valid), .mem_req_ready(mem_req_ready),
        .mem_req_attr(mem_req_attr), .mem_req_addr(mem_req_addr),
        .mem_resp_valid(mem_resp_valid), .mem_resp_data(mem_resp_data),
        .inst_nmat(inst_nmat), .rec_valid(rec_valid), .rec_ready(rec_ready),
        .rec_pixel(rec_pixel), .rec_word(rec_word), .rec2_valid(rec2_valid),
        .rec2_ready(rec2_ready), .rec2_pixel(rec2_pixel), .rec2_word(rec2_word),
        .done_valid(done_valid),
        .done_pixel(done_pixel), .done_walks(done_walks), .done_hit(done_hit), .done_t(done_t),
        .done_voxel(done_voxel), .err_pipe(wk_err_pipe), .err_overflow(wk_err_ov),
        .mem_req_ctx(mem_req_ctx), .mem_resp_ctx(mem_resp_ctx),
        .ctx_resp_valid(ctx_resp_valid), .ctx_resp_data(ctx_resp_data));

    assign err_pipe = fr_err_pipe || wk_err_pipe;
    assign err_overflow = fr_err_ov || wk_err_ov;
endmodule
`default_nettype wire
