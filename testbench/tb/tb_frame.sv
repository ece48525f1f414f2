// tb_frame: one whole frame through the RTL units, end to end, against frame_pixels.hex and
// the cycle model's frame cycles (`sim vectors`: frame_camera, frame_instances, frame_pixels,
// walker_nodes, walker_attrs, walker.json's image bases; docs/vectors.md §3).
//
// Pipeline position: all of it (docs/cycle-model.md §2.1). A testbench-level top: the RTL
// units do every datapath operation — svo_raygen, svo_sphere ×8 lanes (square roots inside), svo_sorter,
// svo_hit_buffer (the hit buffer, svo_hit_check inside, its write FIFO and port), svo_transform, svo_reciprocal ×3, svo_walker_root,
// one svo_walker (one context) on a fixed-latency node memory, svo_hit_pack — while the
// testbench is the host (direction table, instance registers, the images in memory) and the
// control between the units: valid/ready FIFOs of the cycle model's depths, its stage rules
// (elastic unit pipes, loop-back priority, ray slots, early termination, the record's claim
// of the write FIFO) and its evaluation order, so that the frame takes the cycle model's
// cycles (`sim --hw` with one walker, one context, every node read MEM_LATENCY cycles).
//
// Clocking: the control runs at the falling edge of cycle n, evaluating the model's cycle n
// consumers first; a FIFO's valid/ready are its occupancy at the start of the cycle, as the
// model's registered FIFOs. A unit input driven in cycle n is sampled at the rising edge that
// ends it, so a unit of latency L hands its result to the control in cycle n + L, the model's
// ready cycle. Ray generation is svo_raygen fed with the host's direction (the table entry
// as an f64); the hit-buffer read is HB_READ cycles (svo_delay) before svo_hit_check. The
// control's pipe capacities are the units' own LATENCY (hierarchical references).
//
// The frame may have fewer instances than the 8 sphere lanes (the unused lanes' hits are
// masked). A pixel without candidates is written with the frame's miss word
// (frame_camera.hex `miss_word`, the model's record of a ray that pierced no sphere): the
// check stage writes it without a walk, as the model's check stage does.
//
// The record's normal is the one field the model computes in f64 on the host path
// (`FramePlan::finish`: R·diag(1/scale)·n, normalised, octahedral, 8 bits); the testbench
// computes it with `real` from the programmed axes and half extents (tb_frame_host.svh).
//
// Parameters: WRITE_PORTS and RECORD_WRITES, the hit buffer's write paths (the model's
// hit_buffer.write_ports and record_writes; default 2 and 2, the default hardware's two banks
// with the check's word first; run.sh sets them from FRAME_PARAMS, e.g.
// "WRITE_PORTS=1 RECORD_WRITES=1"). The model's frame cycles must be for the same values.
//
// Plusargs: +vectors=DIR, +latency=L (node memory, default 3), +nb<i>=, +ab<i>= (node and
// attribute base of image i, from walker.json; run.sh passes them), +model_cycles=N (the
// cycle model's frame cycles, required: the RTL's must equal them, and without it the cycles
// row fails). Prints per-pixel failures (the first ten), then "frame: P/768 pixels equal,
// RTL N cycles, model M cycles" and the closing "N passed, N failed" (one row per pixel,
// plus one for the cycles). Pixel indices are PIXW (32) bits and ray-slot tags TAGW bits,
// sized from SLOTS.
`timescale 1ns/1ps
module tb_frame #(
    parameter int WRITE_PORTS = 2,
    parameter int RECORD_WRITES = 2
);
    localparam int PB = frame_pixels_vectors_pkg::WORD_BITS;
    localparam int NPIX = frame_pixels_vectors_pkg::DEPTH;
    localparam int IB = frame_instances_vectors_pkg::WORD_BITS;
    localparam int NINST = frame_instances_vectors_pkg::DEPTH;
    localparam int CB = frame_camera_vectors_pkg::WORD_BITS;
    localparam int LANES = 8;
    localparam int TW = walker_vectors_pkg::T_WIDTH;       // walker t, sQ31.31
    localparam int TI = TW + 1;
    localparam int PW = walker_vectors_pkg::O_X_WIDTH;      // positions, sQ8.32
    localparam int NODE_WORDS = walker_vectors_pkg::NODE_WORDS;
    localparam int ATTR_RECORDS = walker_vectors_pkg::ATTR_RECORDS;
    localparam int SLOTS = 1 * 1 + 64;                      // W·R + root_to_dispatch
    // A ray slot's tag through the walker root and the walker: wide enough for every slot
    // (the default machine's 32·8 + 64 = 320 slots take 9 bits).
    localparam int TAGW = SLOTS > 1 ? $clog2(SLOTS) : 1;
    // A pixel index: the raygen port's 32 bits (a 1280 × 768 frame needs 20).
    localparam int PIXW = 32;
    localparam int MAX_REPORTS = 10;
    // Cycle-model FIFO depths (docs/cycle-model.md §1.3) and unit latencies.
    localparam int D_RG_SP = 4, D_SP_SO = 4, D_SO_CK = 8, D_CK_TR = 1024, D_TR_RC = 4,
                   D_RC_RT = 4, D_RT_DP = 64, D_WK_RC = 16, D_RC_WR = 8, D_LOOP = SLOTS;
    // The hit buffer's read (hit_buffer.read_latency_cycles, 4 by default) and the one
    // register of svo_hit_check and of svo_hit_pack; the other units' latencies are their
    // own LATENCY (read from the instances below, so a retimed unit needs no edit here).
    localparam int HB_READ = 4, L_PK = 1;

    reg clk = 1'b0;
    always #5 clk = ~clk;
    reg rst = 1'b1;

    reg [PB-1:0] pix [0:NPIX-1];
    // At least one row per lane (the lanes beyond the frame's instances read zeros, and
    // their hits are masked by lane_used).
    reg [IB-1:0] inst [0:(NINST > LANES ? NINST : LANES)-1];
    reg [CB-1:0] cam [0:0];
    reg [31:0]   nodes [0:NODE_WORDS-1];
    reg [63:0]   attrs [0:(ATTR_RECORDS > 0 ? ATTR_RECORDS : 1)-1];
    int nb [0:15], ab [0:15];
    int mem_latency = 3;
    longint model_cycles = -1;
    longint max_cycles = 1000000;
    string dir;

    int n_reports = 0, n_passed = 0, n_failed = 0;
    task automatic report(input string what);
        if (n_reports < MAX_REPORTS) $display("FAIL frame %s", what);
        n_reports = n_reports + 1;
    endtask

    // The word a pixel without candidates gets: the check stage writes it without a walk.
    wire [71:0] miss_word = cam[0][frame_camera_vectors_pkg::MISS_WORD_LSB +: 72];
    wire [3*40-1:0] cam_o = {cam[0][frame_camera_vectors_pkg::O_Z_LSB +: 40],
                             cam[0][frame_camera_vectors_pkg::O_Y_LSB +: 40],
                             cam[0][frame_camera_vectors_pkg::O_X_LSB +: 40]};


    // =====================================================================================
    // Unit instances; their inputs are driven by the control at the falling edge.
    // =====================================================================================
    // raygen: svo_raygen quantises the pixel's direction and the camera position. The
    // host's f64 values are the table entries themselves (code / 2^frac, exact in f64), so
    // its codes are the table's (checked per pixel); the sphere lanes and the transform take
    // the direction from its output.
    function automatic [63:0] f64_of(input logic signed [63:0] code, input int frac);
        f64_of = $realtobits(real'(code) / (2.0 ** frac));
    endfunction
    reg rg_in_valid = 0;
    reg [PIXW-1:0] rg_in_pixel;
    reg [3*64-1:0] rg_in_dir;
    wire rg_out_valid, rg_ov_d, rg_ov_o;
    wire [31:0] rg_out_pixel;
    wire [3*32-1:0] rg_out_dir;
    wire [3*40-1:0] rg_out_origin;
    svo_raygen u_raygen (.clk(clk), .rst(rst), .in_valid(rg_in_valid),
        .in_pixel(rg_in_pixel), .in_dir(rg_in_dir),
        .in_origin({f64_of($signed(cam_o[80 +: 40]), 32), f64_of($signed(cam_o[40 +: 40]), 32),
                    f64_of($signed(cam_o[0 +: 40]), 32)}),
        .out_valid(rg_out_valid), .out_pixel(rg_out_pixel), .out_dir(rg_out_dir),
        .out_origin(rg_out_origin), .out_ov_dir(rg_ov_d), .out_ov_origin(rg_ov_o));
    reg [3*32-1:0] ray_dir [0:NPIX-1];   // raygen's direction per pixel
    reg [3*32-1:0] rg_td;
    function automatic [3*32-1:0] table_dir(input int p);
        table_dir = {pix[p][frame_pixels_vectors_pkg::DIR_Z_LSB +: 32],
                     pix[p][frame_pixels_vectors_pkg::DIR_Y_LSB +: 32],
                     pix[p][frame_pixels_vectors_pkg::DIR_X_LSB +: 32]};
    endfunction

    // sphere lanes.
    reg sp_in_valid = 0;
    reg [PIXW-1:0] sp_in_pixel;
    wire [3*32-1:0] sp_d = ray_dir[sp_in_pixel];
    wire [LANES-1:0] sp_out_valid, sp_hit;
    // Lanes with an instance: a frame of fewer instances than lanes leaves the rest unused.
    wire [LANES-1:0] lane_used = LANES'((64'd1 << NINST) - 64'd1);
    wire [31:0] sp_t [0:LANES-1];
    genvar gl;
    generate
        for (gl = 0; gl < LANES; gl = gl + 1) begin : lane
            wire [39:0] reach = inst[gl][frame_instances_vectors_pkg::REACH_LSB +: 40];
            wire [79:0] reach2 = reach * reach;
            wire ov_r, ov_t;
            svo_sphere u_sphere (.clk(clk), .rst(rst), .in_valid(sp_in_valid), .in_o(cam_o),
                .in_d(sp_d),
                .in_c({inst[gl][frame_instances_vectors_pkg::C_Z_LSB +: 40],
                       inst[gl][frame_instances_vectors_pkg::C_Y_LSB +: 40],
                       inst[gl][frame_instances_vectors_pkg::C_X_LSB +: 40]}),
                .in_threshold(inst[gl][frame_instances_vectors_pkg::THRESHOLD_LSB +: 64]),
                .in_inside(inst[gl][frame_instances_vectors_pkg::INSIDE_LSB +: 64]),
                .in_delta_t(inst[gl][frame_instances_vectors_pkg::DELTA_T_LSB +: 34]),
                .in_reach(reach), .in_reach2(reach2),
                .out_valid(sp_out_valid[gl]), .out_hit(sp_hit[gl]), .out_t_enter(sp_t[gl]),
                .out_ov_reach(ov_r), .out_ov_t_enter(ov_t));
        end
    endgenerate

    // sorter.
    reg so_in_valid = 0;
    reg [5:0] so_in_count;
    reg [32*40-1:0] so_in_keys;
    wire so_in_ready, so_out_valid;
    wire [5:0] so_out_count;
    wire [32*40-1:0] so_out_keys;
    // The datapath's network (the sorter package's NET_*, the model's), rays of up to 32 keys.
    svo_sorter #(.N(sorter_vectors_pkg::NET_LANES), .D(sorter_vectors_pkg::NET_DEPTH),
                 .S(sorter_vectors_pkg::NET_SLOTS), .PAIRS(sorter_vectors_pkg::NET_PAIRS),
                 .MAX_KEYS(32), .CW(6))
        u_sorter (.clk(clk), .rst(rst), .in_valid(so_in_valid), .in_ready(so_in_ready),
        .in_count(so_in_count), .in_keys(so_in_keys), .out_valid(so_out_valid),
        .out_count(so_out_count), .out_keys(so_out_keys));

    // check and write: svo_hit_buffer (the hit buffer with its HB_READ-cycle read,
    // svo_hit_check, the decision, record_to_write and the write port). This frame is the
    // first: the buffer holds no earlier frame (buffer_valid 0), so nothing is reused; the
    // dirty flags are the host's registers as they stand before any frame (all dirty).
    // testbench/cocotb/test_hit_buffer.py checks reuse across frames.
    reg hb_buffer_valid = 1'b0, hb_camera_dirty = 1'b1;
    reg [LANES-1:0] hb_instance_dirty = '1;
    reg hb_in_valid = 0, hb_rec_valid = 0, hb_walk_ready = 0;
    reg [PIXW-1:0] hb_in_pixel, hb_rec_pixel;
    reg [15:0] hb_in_cands, hb_in_cand;
    reg [71:0] hb_rec_word;
    wire hb_in_ready, hb_walk_valid, hb_rec_ready, hb_wr_valid, hb_wr_direct;
    wire [PIXW-1:0] hb_walk_pixel, hb_wr_pixel;
    wire [71:0] hb_wr_word;
    wire hb_wr1_valid, hb_wr2_valid;                 // the check's path, the second record
    wire [PIXW-1:0] hb_wr1_pixel, hb_wr2_pixel;
    wire [71:0] hb_wr1_word, hb_wr2_word;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_hit_buffer #(.NPIX(NPIX), .AW(NPIX > 1 ? $clog2(NPIX) : 1), .PIXW(PIXW),
        .INSTANCES(LANES), .HB_READ(HB_READ), .PAYW(1), .WR_DEPTH(D_RC_WR), .WRITE_PORTS(WRITE_PORTS),
        .RECORD_WRITES(RECORD_WRITES))
    u_hit_buffer (.clk(clk), .rst(rst), .buffer_valid(hb_buffer_valid),
        .camera_dirty(hb_camera_dirty), .instance_dirty(hb_instance_dirty),
        .miss_word(miss_word), .in_valid(hb_in_valid), .in_ready(hb_in_ready),
        .in_pixel(hb_in_pixel), .in_candidates(hb_in_cands), .in_candidate(hb_in_cand),
        .in_payload(1'b0), .walk_valid(hb_walk_valid), .walk_ready(hb_walk_ready),
        .walk_pixel(hb_walk_pixel), .walk_payload(), .rec_valid(hb_rec_valid),
        .rec_ready(hb_rec_ready), .rec_pixel(hb_rec_pixel), .rec_word(hb_rec_word),
        .wr_valid(hb_wr_valid), .wr_pixel(hb_wr_pixel), .wr_word(hb_wr_word),
        .wr_direct(hb_wr_direct), .wr1_valid(hb_wr1_valid), .wr1_pixel(hb_wr1_pixel),
        .wr1_word(hb_wr1_word), .wr2_valid(hb_wr2_valid), .wr2_pixel(hb_wr2_pixel),
        .wr2_word(hb_wr2_word), .ev_reused(), .ev_write_stall(), .ev_walk_stall(),
        .ev_bank_conflict(), .err_pixel());
    /* verilator lint_on PINCONNECTEMPTY */

    // transform.
    reg tr_in_valid = 0;
    reg [PIXW-1:0] tr_in_pixel;
    reg [7:0] tr_in_inst;
    wire tr_out_valid, tr_ov_o, tr_ov_d;
    wire [3*40-1:0] tr_o;
    wire [3*32-1:0] tr_d;
    wire [2:0] tr_sign;
    svo_transform u_transform (.clk(clk), .rst(rst), .in_valid(tr_in_valid), .in_o(cam_o),
        .in_d(ray_dir[tr_in_pixel]),
        .in_axes(inst[tr_in_inst][0 +: 9 * 32]),
        .in_c({inst[tr_in_inst][frame_instances_vectors_pkg::C_Z_LSB +: 40],
               inst[tr_in_inst][frame_instances_vectors_pkg::C_Y_LSB +: 40],
               inst[tr_in_inst][frame_instances_vectors_pkg::C_X_LSB +: 40]}),
        .out_valid(tr_out_valid), .out_o(tr_o), .out_d(tr_d), .out_sign(tr_sign),
        .out_ov_origin(tr_ov_o), .out_ov_dir(tr_ov_d));

    // reciprocals, one per axis.
    reg rc_in_valid = 0;
    reg [3*32-1:0] rc_in_d;
    reg [2:0] rc_in_sign;
    wire [2:0] rc_out_valid, rc_zero, rc_neg, rc_fl, rc_ov;
    wire [51:0] rc_inv [0:2];
    genvar ga;
    generate
        for (ga = 0; ga < 3; ga = ga + 1) begin : recip
            svo_reciprocal u_recip (.clk(clk), .rst(rst), .in_valid(rc_in_valid),
                .in_d(rc_in_d[ga*32 +: 32]), .in_sign_negative(rc_in_sign[ga]),
                .out_valid(rc_out_valid[ga]), .out_inv(rc_inv[ga]), .out_zero(rc_zero[ga]),
                .out_negative(rc_neg[ga]), .out_flushed(rc_fl[ga]), .out_ov(rc_ov[ga]));
        end
    endgenerate

    // walker root.
    reg rt_in_valid = 0;
    reg [3*PW-1:0] rt_in_o, rt_in_half;
    reg [3*52-1:0] rt_in_inv;
    reg [2:0] rt_in_zero, rt_in_neg;
    reg [TAGW-1:0] rt_in_tag;
    wire rt_out_valid, rt_enter;
    wire [3*TI-1:0] rt_t0, rt_t1;
    wire [3*(PW+1)-1:0] rt_o;
    wire [3*PW-1:0] rt_half;
    wire [2:0] rt_zero, rt_neg;
    wire [TAGW-1:0] rt_tag;
    svo_walker_root #(.POS_W(PW), .POS_FRAC(walker_vectors_pkg::O_X_FRAC),
        .INV_W(walker_vectors_pkg::INV_X_WIDTH), .INV_FRAC(walker_vectors_pkg::INV_X_FRAC),
        .T_W(TW), .T_FRAC(walker_vectors_pkg::T_FRAC), .PROD(walker_vectors_pkg::ROOT_LATENCY - 4), .TAG_W(TAGW)
    ) u_root (.clk(clk), .rst(rst), .in_valid(rt_in_valid), .in_o(rt_in_o), .in_inv(rt_in_inv),
        .in_half(rt_in_half), .in_zero(rt_in_zero), .in_neg(rt_in_neg), .in_tag(rt_in_tag),
        .out_valid(rt_out_valid), .out_enter(rt_enter), .out_t0(rt_t0), .out_t1(rt_t1),
        .out_o(rt_o), .out_half(rt_half), .out_zero(rt_zero), .out_neg(rt_neg), .out_tag(rt_tag));

    // the walker (one context) and its memory.
    localparam int RTB = 1 + 2 * 3 * TI + 3 * (PW + 1) + 3 * PW + 3 + 3 + TAGW;   // root bundle
    reg wk_in_valid = 0, wk_out_ready = 0;
    reg [RTB-1:0] wk_in;
    reg [31:0] wk_nb, wk_ab;
    wire wk_in_ready, mem_req_valid, mem_req_attr, wk_out_valid, visit_valid;
    wire [31:0] mem_req_addr, wk_attr, wk_steps, wk_fetches;
    wire mem_resp_valid;
    reg [63:0] mem_resp_data;
    wire [1:0] wk_outcome, wk_axis;
    wire [TW-1:0] wk_t;
    wire [59:0] wk_voxel, visit_coords;
    wire [4:0] wk_level, visit_level;
    wire [63:0] wk_attr_data;
    wire [TAGW-1:0] wk_tag;
    int left = 0;
    svo_walker #(.POS_W(PW), .T_W(TW), .STACK_DEPTH(walker_vectors_pkg::STACK_DEPTH),
        .MAX_STEPS(walker_vectors_pkg::MAX_STEPS), .STEP_LATENCY(walker_vectors_pkg::STEP_LATENCY),
        .TAG_W(TAGW)
    ) u_walker (.clk(clk), .rst(rst), .in_valid(wk_in_valid), .in_ready(wk_in_ready),
        .in_enter(wk_in[RTB-1]), .in_t0(wk_in[RTB-2 -: 3*TI]), .in_t1(wk_in[RTB-2-3*TI -: 3*TI]),
        .in_o(wk_in[3*PW+TAGW+6+3*(PW+1)-1 -: 3*(PW+1)]), .in_half(wk_in[3*PW+TAGW+6-1 -: 3*PW]),
        .in_zero(wk_in[TAGW+5 -: 3]), .in_neg(wk_in[TAGW+2 -: 3]), .in_node_base(wk_nb),
        .in_attr_base(wk_ab), .in_tag(wk_in[TAGW-1:0]),
        .mem_req_valid(mem_req_valid), .mem_req_ready(left <= 1), .mem_req_attr(mem_req_attr),
        .mem_req_addr(mem_req_addr), .mem_resp_valid(mem_resp_valid),
        .mem_resp_data(mem_resp_data), .out_valid(wk_out_valid), .out_ready(wk_out_ready),
        .out_outcome(wk_outcome), .out_t(wk_t), .out_voxel(wk_voxel), .out_level(wk_level),
        .out_attr(wk_attr), .out_entry_axis(wk_axis), .out_steps(wk_steps),
        .out_fetches(wk_fetches), .out_attr_data(wk_attr_data), .out_tag(wk_tag),
        .visit_valid(visit_valid), .visit_level(visit_level), .visit_coords(visit_coords));
    // The node memory: a read requested in cycle c is valid in cycle c + L (tb_walker's).
    `define TB_MEM_WHERE ""
    `include "tb_fixed_latency_mem.svh"

    // record: svo_hit_pack.
    reg pk_in_valid = 0, pk_inst_valid;
    reg [1:0] pk_kind;
    reg [15:0] pk_inst;
    reg [63:0] pk_t;
    reg [31:0] pk_nu, pk_nv;
    reg [7:0] pk_r, pk_g, pk_b;
    wire pk_out_valid, pk_ov;
    wire [71:0] pk_word;
    svo_hit_pack u_pack (.clk(clk), .rst(rst), .in_valid(pk_in_valid), .in_kind(pk_kind),
        .in_instance_valid(pk_inst_valid), .in_instance(pk_inst), .in_t(pk_t),
        .in_normal_u(pk_nu), .in_normal_v(pk_nv), .in_colour_r(pk_r), .in_colour_g(pk_g),
        .in_colour_b(pk_b), .out_valid(pk_out_valid), .out_word(pk_word), .out_ov(pk_ov));

    // =====================================================================================
    // Control: FIFOs, unit bookkeeping, ray slots.
    // =====================================================================================
    int   q_rg_sp[$], q_sp_so[$], q_so_ck[$], q_ck_tr[$], q_loop[$], q_tr_rc[$], q_rc_rt[$],
          q_wk_rc[$];
    int junk;
    reg [RTB-1:0] q_rt_dp[$];
    // Unit pipes: tags in flight (inside the RTL) and results waiting (model's elastic pipe).
    int rg_fly[$], rg_res[$];
    int sp_fly[$], sp_res[$];
    reg [LANES-1:0] sp_res_hit[$];
    reg [LANES*32-1:0] sp_res_t[$];
    int so_fly[$], so_res[$];
    reg [32*40-1:0] so_res_keys[$];
    int tr_fly[$], tr_res[$];
    int rc_fly[$], rc_res[$];
    int rt_res[$];
    int rt_n = 0;                 // root items (in flight + waiting)
    int pk_fly[$], pk_res[$];
    reg [71:0] pk_res_word[$];
    // Per pixel: its sorted candidates; per slot: the ray's walk state.
    int   n_cands [0:NPIX-1];
    reg [39:0] cands [0:NPIX-1][0:7];
    int   slot_pixel [0:SLOTS-1], slot_cand [0:SLOTS-1], slot_walks [0:SLOTS-1];
    bit   slot_best [0:SLOTS-1], slot_free [0:SLOTS-1];
    reg [TW-1:0] slot_t [0:SLOTS-1];
    reg [63:0] slot_attr [0:SLOTS-1];
    reg [59:0] slot_voxel [0:SLOTS-1];
    int   slot_inst [0:SLOTS-1];
    reg [3*40-1:0] slot_o [0:SLOTS-1];
    reg [3*32-1:0] slot_d [0:SLOTS-1];
    reg [2:0] slot_sign [0:SLOTS-1];
    int   n_free = SLOTS;
    int   next_pixel = 0, written = 0;
    longint cyc = 0;
    // +write_log: one line per hit-buffer write, "write <pixel> <cycle> <path>" (path 0: the
    // record FIFO's head, 1: the check's, 2: the second record), for a comparison with the
    // model's transaction log (the write stage's cycle of every pixel).
    bit write_log = 0;
    task automatic log_write(input int p, input int path);
        if (write_log) $display("write %0d %0d %0d", p, cyc, path);
    endtask
    bit   done = 0;

    reg [3*52-1:0] rt_in_inv_slot [0:SLOTS-1];
    reg [2:0] rt_in_zero_slot [0:SLOTS-1], rt_in_neg_slot [0:SLOTS-1];
    reg [RTB-1:0] rt_bundle[$];
    reg [RTB-1:0] q_rt_dp_wait[$];
    reg [32*40-1:0] sorter_in [0:NPIX-1];
    int  pix_walks [0:NPIX-1];
    bit  pix_hit [0:NPIX-1];
    reg [TW-1:0] pix_t [0:NPIX-1];
    reg [59:0] pix_voxel [0:NPIX-1];

    function automatic int take_slot();
        for (int s = 0; s < SLOTS; s++) if (slot_free[s]) begin
            slot_free[s] = 0;
            n_free--;
            return s;
        end
        return -1;
    endfunction

    // Start-of-cycle occupancies (the registered valid/ready).
    int o_rg_sp, o_sp_so, o_so_ck, o_ck_tr, o_loop, o_tr_rc, o_rc_rt, o_rt_dp, o_wk_rc;

    // Collect unit results (valid in this cycle) into their pipes' result queues.
    task automatic collect;
        if (rg_out_valid) begin
            int p = rg_fly.pop_front();
            ray_dir[p] = rg_out_dir;
            if (rg_out_pixel != 32'(p) || rg_out_dir !== table_dir(p) || rg_out_origin !== cam_o
                || rg_ov_d || rg_ov_o)
                report($sformatf("pixel %0d: raygen gave direction %h, expected %h", p,
                                 rg_out_dir, table_dir(p)));
            rg_res.push_back(p);
        end
        if (sp_out_valid[0]) begin
            reg [LANES*32-1:0] tt;
            for (int l = 0; l < LANES; l++) tt[l*32 +: 32] = sp_t[l];
            sp_res.push_back(sp_fly.pop_front());
            sp_res_hit.push_back(sp_hit & lane_used);   // lanes beyond the instances hold none
            sp_res_t.push_back(tt);
        end
        if (so_out_valid) begin
            so_res.push_back(so_fly.pop_front());
            so_res_keys.push_back(so_out_keys);
        end
        if (tr_out_valid) begin
            int s = tr_fly.pop_front();
            slot_o[s] = tr_o; slot_d[s] = tr_d; slot_sign[s] = tr_sign;
            tr_res.push_back(s);
        end
        if (rc_out_valid[0]) begin
            int s = rc_fly.pop_front();
            rc_res.push_back(s);
            // The walker root's inputs (WalkerInput::set_axis): |inv|, zero, negative.
            for (int a = 0; a < 3; a++) begin
                logic signed [51:0] iv = $signed(rc_inv[a]);
                rt_in_inv_slot[s][a*52 +: 52] = iv < 0 ? -iv : iv;
            end
            rt_in_zero_slot[s] = rc_zero;
            rt_in_neg_slot[s] = rc_neg;
        end
        if (rt_out_valid)
            rt_bundle.push_back({rt_enter, rt_t0, rt_t1, rt_o, rt_half, rt_zero, rt_neg, rt_tag});
        if (pk_out_valid) begin
            pk_res.push_back(pk_fly.pop_front());
            pk_res_word.push_back(pk_word);
        end
    endtask


    `include "tb_frame_host.svh"
    // One model cycle, consumers first (write, record, walkers, root, reciprocal, transform,
    // check, sorter, sphere, raygen), FIFO valid/ready from the start-of-cycle occupancies.
    task automatic step;
        bit free_after;
        o_rg_sp = q_rg_sp.size(); o_sp_so = q_sp_so.size(); o_so_ck = q_so_ck.size();
        o_ck_tr = q_ck_tr.size(); o_loop = q_loop.size(); o_tr_rc = q_tr_rc.size();
        o_rc_rt = q_rc_rt.size(); o_rt_dp = q_rt_dp.size(); o_wk_rc = q_wk_rc.size();
        rg_in_valid = 0; sp_in_valid = 0; so_in_valid = 0; hb_in_valid = 0; tr_in_valid = 0;
        hb_rec_valid = 0; hb_walk_ready = 0;
        rc_in_valid = 0; rt_in_valid = 0; wk_in_valid = 0; pk_in_valid = 0;
        collect();
        while (rt_bundle.size() > 0) begin
            rt_res.push_back(0);
            q_rt_dp_wait.push_back(rt_bundle.pop_front());
        end
        // write: svo_hit_buffer writes this cycle its record FIFO's head (wr), with two
        // write paths the check's word first (wr1) and a second record (wr2). A word from the
        // check stage, reused or the miss word, had no walk.
        if (hb_wr1_valid) begin
            int p = int'(hb_wr1_pixel);
            pix_walks[p] = 0; pix_hit[p] = 0;
            check_pixel(p, hb_wr1_word, pix_walks[p], pix_hit[p], pix_t[p], pix_voxel[p]);
            log_write(p, 1);
            written++;
        end
        if (hb_wr_valid) begin
            int p = int'(hb_wr_pixel);
            if (hb_wr_direct) begin
                pix_walks[p] = 0; pix_hit[p] = 0;
            end
            check_pixel(p, hb_wr_word, pix_walks[p], pix_hit[p], pix_t[p], pix_voxel[p]);
            log_write(p, 0);
            written++;
        end
        if (hb_wr2_valid) begin
            int p = int'(hb_wr2_pixel);
            check_pixel(p, hb_wr2_word, pix_walks[p], pix_hit[p], pix_t[p], pix_voxel[p]);
            log_write(p, 2);
            written++;
        end
        // record: the pack's result out, then the next walk result's decision.
        if (pk_res.size() > 0) begin
            hb_rec_valid = 1;
            hb_rec_pixel = PIXW'(pk_res[0]);
            hb_rec_word = pk_res_word[0];
            if (hb_rec_ready) begin                        // the FIFO's registered occupancy
                junk = pk_res.pop_front();
                pk_res_word.delete(0);
            end
        end
        if (o_wk_rc > 0 && pk_fly.size() + pk_res.size() < L_PK) begin
            int s = q_wk_rc.pop_front();
            int p = slot_pixel[s];
            int c = slot_cand[s];
            slot_walks[s]++;
            if (c + 1 < n_cands[p]
                && !(slot_best[s] && stops(slot_t[s], cands[p][c + 1][31:0]))) begin
                slot_cand[s] = c + 1;
                q_loop.push_back(s);
            end else begin
                int k = slot_inst[s];
                pix_walks[p] = slot_walks[s];
                pix_hit[p] = slot_best[s];
                pix_t[p] = slot_t[s];
                pix_voxel[p] = slot_voxel[s];
                pk_kind = n_cands[p] == 1 ? 2'd1 : 2'd2;
                if (slot_best[s]) begin
                    reg [15:0] nrm;
                    nrm = host_normal(k, slot_attr[s][63:32]);
                    pk_inst_valid = 1; pk_inst = 16'(k);
                    pk_t = 64'($signed(slot_t[s]) >>> 17);   // sQ31.31 → uQ8.14, truncated
                    pk_nu = {{24{nrm[7]}}, nrm[7:0]};
                    pk_nv = {{24{nrm[15]}}, nrm[15:8]};
                    pk_r = slot_attr[s][7:0]; pk_g = slot_attr[s][15:8]; pk_b = slot_attr[s][23:16];
                end else begin
                    pk_inst_valid = 0; pk_inst = 0; pk_t = 64'h3fffff;   // RecordT::far
                    pk_nu = 0; pk_nv = 0; pk_r = 0; pk_g = 0; pk_b = 0;
                end
                pk_in_valid = 1;
                pk_fly.push_back(p);
                slot_free[s] = 1;
                n_free++;
            end
        end
        // walkers: the result leaves when walker_to_record is ready; a walk enters when the
        // context is free (the RTL walker's in_ready is high in the cycle its result leaves).
        wk_out_ready = o_wk_rc < D_WK_RC;
        #1;
        if (wk_out_valid && wk_out_ready) begin
            int s = wk_tag;
            q_wk_rc.push_back(s);
            if (wk_outcome == 2'd1 && (!slot_best[s] || $signed(wk_t) < $signed(slot_t[s]))) begin
                slot_best[s] = 1;
                slot_t[s] = wk_t;
                slot_attr[s] = wk_attr_data;
                slot_voxel[s] = wk_voxel;
                slot_inst[s] = cands[slot_pixel[s]][slot_cand[s]][39:32];
            end
        end
        if (o_rt_dp > 0 && wk_in_ready) begin
            int k;
            wk_in = q_rt_dp.pop_front();
            k = cands[slot_pixel[wk_in[TAGW-1:0]]][slot_cand[wk_in[TAGW-1:0]]][39:32];
            wk_nb = nb[inst[k][frame_instances_vectors_pkg::IMAGE_LSB +: 8]];
            wk_ab = ab[inst[k][frame_instances_vectors_pkg::IMAGE_LSB +: 8]];
            wk_in_valid = 1;
        end
        // root: results into root_to_dispatch; walks in from reciprocal_to_root.
        if (rt_res.size() > 0 && o_rt_dp < D_RT_DP) begin
            junk = rt_res.pop_front();
            q_rt_dp.push_back(q_rt_dp_wait.pop_front());
            rt_n--;
        end
        if (o_rc_rt > 0 && rt_n < u_root.LATENCY) begin
            int s = q_rc_rt.pop_front();
            int k = cands[slot_pixel[s]][slot_cand[s]][39:32];
            rt_in_o = slot_o[s];
            rt_in_inv = rt_in_inv_slot[s];
            rt_in_zero = rt_in_zero_slot[s];
            rt_in_neg = rt_in_neg_slot[s];
            rt_in_half = {inst[k][frame_instances_vectors_pkg::HALF_Z_LSB +: 40],
                          inst[k][frame_instances_vectors_pkg::HALF_Y_LSB +: 40],
                          inst[k][frame_instances_vectors_pkg::HALF_X_LSB +: 40]};
            rt_in_tag = TAGW'(s);
            rt_in_valid = 1;
            rt_n++;
        end
        // reciprocal.
        if (rc_res.size() > 0 && o_rc_rt < D_RC_RT) q_rc_rt.push_back(rc_res.pop_front());
        if (o_tr_rc > 0 && rc_fly.size() + rc_res.size() < recip[0].u_recip.LATENCY) begin
            int s = q_tr_rc.pop_front();
            rc_in_d = slot_d[s];
            rc_in_sign = slot_sign[s];
            rc_in_valid = 1;
            rc_fly.push_back(s);
        end
        // transform: loop-back first, else a new ray takes a slot.
        if (tr_res.size() > 0 && o_tr_rc < D_TR_RC) q_tr_rc.push_back(tr_res.pop_front());
        if (tr_fly.size() + tr_res.size() < u_transform.LATENCY) begin
            int s = -1;
            if (o_loop > 0) s = q_loop.pop_front();
            else if (o_ck_tr > 0 && n_free > 0) begin
                int p = q_ck_tr.pop_front();
                s = take_slot();
                slot_pixel[s] = p; slot_cand[s] = 0; slot_walks[s] = 0; slot_best[s] = 0;
            end
            if (s >= 0) begin
                tr_in_pixel = PIXW'(slot_pixel[s]);
                tr_in_inst = cands[slot_pixel[s]][slot_cand[s]][39:32];
                tr_in_valid = 1;
                tr_fly.push_back(s);
            end
        end
        // check: svo_hit_buffer decides its head ray (reused word or no candidate: into its
        // write FIFO unless the record pushed this cycle; else out to check_to_transform) and
        // takes the next ray from sorter_to_check while fewer than its capacity are inside,
        // counting the one leaving. Its in_ready depends on rec_valid and walk_ready through
        // that departure: #1 lets them settle before it is read (the edge is at +5).
        hb_walk_ready = o_ck_tr < D_CK_TR;
        if (o_so_ck > 0) begin
            int p = q_so_ck[0];
            hb_in_valid = 1;
            hb_in_pixel = PIXW'(p);
            hb_in_cands = 16'(n_cands[p]);
            hb_in_cand = n_cands[p] == 1 ? 16'(cands[p][0][39:32]) : 16'd0;
        end
        #1;
        if (hb_walk_valid && hb_walk_ready) q_ck_tr.push_back(int'(hb_walk_pixel));
        if (hb_in_valid && hb_in_ready) junk = q_so_ck.pop_front();
        // sorter.
        if (so_res.size() > 0 && o_so_ck < D_SO_CK) begin
            int p = so_res.pop_front();
            reg [32*40-1:0] keys = so_res_keys.pop_front();
            for (int c = 0; c < 8; c++) cands[p][c] = keys[c*40 +: 40];
            q_so_ck.push_back(p);
        end
        if (o_sp_so > 0 && so_fly.size() + so_res.size() < u_sorter.D) begin
            int p = q_sp_so.pop_front();
            if (so_in_ready !== 1'b1) report($sformatf("pixel %0d: sorter not ready", p));
            so_in_count = 6'(n_cands[p]);
            so_in_keys = sorter_in[p];
            so_in_valid = 1;
            so_fly.push_back(p);
        end
        // sphere.
        if (sp_res.size() > 0 && o_sp_so < D_SP_SO) begin
            int p = sp_res.pop_front();
            reg [LANES-1:0] h = sp_res_hit.pop_front();
            reg [LANES*32-1:0] tt = sp_res_t.pop_front();
            int n = 0;
            sorter_in[p] = '0;
            for (int l = 0; l < LANES; l++) if (h[l]) begin
                sorter_in[p][n*40 +: 40] = {8'(l), tt[l*32 +: 32]};
                n++;
            end
            n_cands[p] = n;
            q_sp_so.push_back(p);
        end
        if (o_rg_sp > 0 && sp_fly.size() + sp_res.size() < lane[0].u_sphere.LATENCY) begin
            int p = q_rg_sp.pop_front();
            sp_in_pixel = PIXW'(p);
            sp_in_valid = 1;
            sp_fly.push_back(p);
        end
        // raygen.
        if (rg_res.size() > 0 && o_rg_sp < D_RG_SP) q_rg_sp.push_back(rg_res.pop_front());
        if (next_pixel < NPIX && rg_fly.size() + rg_res.size() < u_raygen.LATENCY) begin
            rg_in_pixel = PIXW'(next_pixel);
            rg_td = table_dir(next_pixel);
            for (int a = 0; a < 3; a++) rg_in_dir[a*64 +: 64] = f64_of($signed(rg_td[a*32 +: 32]), 30);
            rg_in_valid = 1;
            rg_fly.push_back(next_pixel);
            next_pixel++;
        end
    endtask

    initial begin
        string f;
        if (!$value$plusargs("vectors=%s", dir)) dir = "vectors";
        if ($value$plusargs("latency=%d", mem_latency)) junk = 0;
        if ($value$plusargs("model_cycles=%d", model_cycles)) junk = 0;
        if ($value$plusargs("max_cycles=%d", max_cycles)) junk = 0;
        write_log = $test$plusargs("write_log");
        for (int i = 0; i < 16; i++) begin
            nb[i] = 0; ab[i] = 0;
            if ($value$plusargs($sformatf("nb%0d=%%d", i), junk)) nb[i] = junk;
            if ($value$plusargs($sformatf("ab%0d=%%d", i), junk)) ab[i] = junk;
        end
        $readmemh({dir, "/frame_pixels.hex"}, pix);
        for (int k = 0; k < LANES; k++) inst[k] = '0;
        $readmemh({dir, "/frame_instances.hex"}, inst, 0, NINST - 1);
        $readmemh({dir, "/frame_camera.hex"}, cam);
        $readmemh({dir, "/walker_nodes.hex"}, nodes);
        $readmemh({dir, "/walker_attrs.hex"}, attrs);
        // The reciprocals' seed ROMs, from the same folder (as tb_reciprocal loads its own).
        $readmemh({dir, "/reciprocal_seed.hex"}, recip[0].u_recip.rom);
        $readmemh({dir, "/reciprocal_seed.hex"}, recip[1].u_recip.rom);
        $readmemh({dir, "/reciprocal_seed.hex"}, recip[2].u_recip.rom);
        for (int s = 0; s < SLOTS; s++) slot_free[s] = 1;
        if (cam[0][frame_camera_vectors_pkg::INSTANCES_LSB +: 16] != NINST || NINST > LANES
            || NINST < 1)
            $fatal(1, "tb_frame: the frame has %0d instances; this top has %0d sphere lanes", NINST, LANES);
        repeat (64) @(posedge clk);   // longer than every unit's latency: no X valid bit left
        rst = 1'b0;
        @(posedge clk);
        // Model cycle n is evaluated at the falling edge inside it.
        while (written < NPIX && cyc < max_cycles) begin
            @(negedge clk);
            step();
            cyc++;
            if (cyc % 1000 == 0 && $test$plusargs("progress"))
                $display("cycle %0d: raygen %0d, written %0d, ck_tr %0d, rt_dp %0d, free %0d", cyc, next_pixel, written, q_ck_tr.size(), q_rt_dp.size(), n_free);
        end
        $display("frame: %0d/%0d pixels equal, RTL %0d cycles, model %0d cycles", n_passed, NPIX,
                 cyc, model_cycles);
        // The cycles are part of what this testbench checks: without the model's figure the
        // frame fails rather than passing on its pixels alone.
        if (model_cycles < 0) begin
            n_failed++;
            $display("FAIL frame: no +model_cycles=N given (the cycle model's frame cycles, from `sim --model cycle` on the testbench's hardware; see testbench/README.md)");
        end else if (cyc == model_cycles) n_passed++;
        else begin
            n_failed++;
            $display("FAIL frame: %0d cycles, the cycle model's %0d", cyc, model_cycles);
        end
        if (written < NPIX) n_failed += NPIX - written;
        $display("%0d passed, %0d failed", n_passed, n_failed);
        $finish;
    end
endmodule
