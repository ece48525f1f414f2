// tb_frame: one whole frame through the RTL units, end to end, against frame_pixels.hex and
// the cycle model's frame cycles (`sim vectors`: frame_camera, frame_instances, frame_pixels,
// walker_nodes, walker_attrs, walker.json's image bases; docs/vectors.md §3).
//
// Pipeline position: all of it (docs/cycle-model.md §2.1). A testbench-level top over three
// RTL blocks that hold every unit and the control between them: svo_front (the pixel
// counter, svo_raygen, svo_sphere ×8 lanes with their square roots, svo_sorter, and the
// raygen_to_sphere, sphere_to_sorter and sorter_to_check FIFOs and elastic unit pipes),
// svo_hit_buffer (the check with svo_hit_check, the write FIFOs and ports) and svo_walk_wide (the
// ray slots, svo_transform with the loop-back first, svo_reciprocal ×3, svo_walker_root, one
// svo_walker of one context, the record's decision and svo_hit_pack, with their FIFOs and
// pipes): valid/ready with back-pressure at every joint, the cycle model's FIFO depths, unit
// pipes and stage rules, so that the frame takes the model's cycles (`sim --hw
// testbench/hw/frame_hw.ron`). The testbench is the host — the direction table, the
// instance registers, the images in a fixed-latency node memory, the record's normal — and
// the checker of every pixel; it drives no control.
//
// Clocking: the testbench observes cycle n at its falling edge (the writes, the rays whose
// record is decided, the rays the check takes) and gives the front end the direction of the
// pixel it issues next; the RTL moves at the rising edges. The front end starts in cycle 0
// (`run`), when the model's ray generation does.
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
// Hardware: the package svo_hw_pkg (`sim hardware --hw FILE --sv-package`; run.sh passes
// FRAME_HW_PKG, default testbench/hw/frame_hw_pkg.sv from testbench/hw/frame_hw.ron) gives
// the FIFO depths, the ray slots, the hit buffer's read latency and write paths and the
// sphere lanes; the model times the same file. What this top builds by structure (one
// walk-issue lane, one walker with one context, the units' own latencies) is checked against
// the package at start, and a package that differs stops the run naming the field.
//
// Plusargs: +vectors=DIR, +latency=L (node memory, default 3), +nb<i>=, +ab<i>= (node and
// attribute base of image i, from walker.json; run.sh passes them), +model_cycles=N (the
// cycle model's frame cycles, required: the RTL's must equal them, and without it the cycles
// row fails). Prints per-pixel failures (the first ten), then "frame: P/768 pixels equal,
// RTL N cycles, model M cycles" and the closing "N passed, N failed" (one row per pixel,
// plus one for the cycles). Pixel indices are PIXW (32) bits and ray-slot tags TAGW bits,
// sized from SLOTS.
`timescale 1ns/1ps
module tb_frame;
    import svo_hw_pkg::*;
    localparam int WRITE_PORTS = HIT_BUFFER_WRITE_PORTS;
    localparam int RECORD_WRITES = HIT_BUFFER_RECORD_WRITES;
    localparam int PB = frame_pixels_vectors_pkg::WORD_BITS;
    localparam int NPIX = frame_pixels_vectors_pkg::DEPTH;
    localparam int IB = frame_instances_vectors_pkg::WORD_BITS;
    localparam int NINST = frame_instances_vectors_pkg::DEPTH;
    localparam int CB = frame_camera_vectors_pkg::WORD_BITS;
    localparam int LANES = SPHERE_UNITS;
    localparam int TW = walker_vectors_pkg::T_WIDTH;       // walker t, sQ31.31
    localparam int TI = TW + 1;
    localparam int PW = walker_vectors_pkg::O_X_WIDTH;      // positions, sQ8.32
    localparam int NODE_WORDS = walker_vectors_pkg::NODE_WORDS;
    localparam int ATTR_RECORDS = walker_vectors_pkg::ATTR_RECORDS;
    localparam int SLOTS = RAY_SLOTS;                       // W·R + root_to_dispatch
    // A ray slot's tag through the walker root and the walker: wide enough for every slot
    // (the default machine's 48·16 + 64 = 832 slots take 10 bits).
    localparam int TAGW = SLOTS > 1 ? $clog2(SLOTS) : 1;
    // A pixel index: the raygen port's 32 bits (a 1280 × 768 frame needs 20).
    localparam int PIXW = 32;
    localparam int MAX_REPORTS = 10;
    // Cycle-model FIFO depths (docs/cycle-model.md §1.3), from the package.
    localparam int D_RG_SP = FIFOS_RAYGEN_TO_SPHERE, D_SP_SO = FIFOS_SPHERE_TO_SORTER,
                   D_SO_CK = FIFOS_SORTER_TO_CHECK, D_CK_TR = FIFOS_CHECK_TO_TRANSFORM,
                   D_TR_RC = FIFOS_TRANSFORM_TO_RECIPROCAL, D_RC_RT = FIFOS_RECIPROCAL_TO_ROOT,
                   D_RT_DP = FIFOS_ROOT_TO_DISPATCH, D_WK_RC = FIFOS_WALKER_TO_RECORD,
                   D_RC_WR = FIFOS_RECORD_TO_WRITE, D_LOOP = SLOTS;
    // The hit buffer's read (hit_buffer.read_latency_cycles) and the one register of
    // svo_hit_pack; the units' latencies are their own LATENCY (read from the instances
    // below), checked against the package's at start.
    localparam int HB_READ = HIT_BUFFER_READ_LATENCY_CYCLES, L_PK = 14;  // svo_normal 13 + svo_hit_pack 1 (svo_walk_wide)

    reg clk = 1'b0;
    always #5 clk = ~clk;
    reg rst = 1'b1;

    reg [PB-1:0] pix [0:NPIX-1];
    // At least one row per lane (the lanes beyond the frame's instances read zeros, and
    // their hits are masked by the core's n_inst).
    reg [IB-1:0] inst [0:(NINST > LANES ? NINST : LANES)-1];
    reg [CB-1:0] cam [0:0];
    reg [31:0]   nodes [0:NODE_WORDS-1];
    reg [63:0]   attrs [0:(ATTR_RECORDS > 0 ? ATTR_RECORDS : 1)-1];
    int nb [0:15], ab [0:15];
    int mem_latency = 3;
    // Random memory stalls (+mem_stall=PCT: the request's ready held low in PCT % of cycles;
    // +mem_jitter=J: each read 0..J cycles later; +seed=S): the frame must still write every
    // pixel once and right, in whatever cycles it takes.
    int mem_stall = 0, mem_jitter = 0;
    int unsigned mem_seed = 1, seed_state;
    bit stall_now = 0;
    longint n_stalled = 0, n_extra = 0;
    int extra_now = 0;
    longint model_cycles = -1;
    // +frames=2: a second frame of the same (still) scene after frame 0, with the hit buffer
    // kept: buffer_valid 1, the camera and instance dirty flags +f1_camera_dirty=0/1 and
    // +f1_instance_dirty=HEX (default 0: nothing moved), its cycles against +model_cycles1=N.
    int frames = 1, frame_no = 0, f1_camera_dirty = 0, f1_instance_dirty = 0;
    longint model_cycles1 = -1;
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
    // The RTL: svo_front, svo_hit_buffer, svo_walk_wide; the host registers they read.
    // =====================================================================================
    // raygen: svo_raygen quantises the pixel's direction and the camera position. The
    // host's f64 values are the table entries themselves (code / 2^frac, exact in f64), so
    // its codes are the table's (checked per pixel); the sphere lanes and the transform take
    // the direction from its output.
    function automatic [63:0] f64_of(input logic signed [63:0] code, input int frac);
        f64_of = $realtobits(real'(code) / (2.0 ** frac));
    endfunction
    // The front end: svo_front (ray generation, the sphere lanes, the sorter and the FIFOs
    // between them, in RTL). The host gives it the pixel's direction from the table (as an
    // f64, exact: code / 2^frac) and the instance registers.
    reg fr_run = 0;
    reg [3*64-1:0] fr_dir_f64 = '0;
    wire [PIXW-1:0] fr_dir_pixel;
    reg [3*32-1:0] ray_dir [0:NPIX-1];   // the direction each ray left the front end with
    function automatic [3*32-1:0] table_dir(input int p);
        table_dir = {pix[p][frame_pixels_vectors_pkg::DIR_Z_LSB +: 32],
                     pix[p][frame_pixels_vectors_pkg::DIR_Y_LSB +: 32],
                     pix[p][frame_pixels_vectors_pkg::DIR_X_LSB +: 32]};
    endfunction
    // The table's direction of pixel p as three binary64 (zero past the frame's last pixel).
    function automatic [3*64-1:0] dir_f64(input int p);
        reg [3*32-1:0] td;
        dir_f64 = '0;
        if (p < NPIX) begin
            td = table_dir(p);
            for (int a = 0; a < 3; a++) dir_f64[a*64 +: 64] = f64_of($signed(td[a*32 +: 32]), 30);
        end
    endfunction
    // The instance registers' read ports of the core (svo_top's instance table in a board):
    // the walk section's reads answered from the registers below in the same cycle. This
    // top has one instance per sphere lane (NINST <= LANES), so the lanes take one pass and
    // lane l tests instance l (the lanes beyond the frame's instances are masked by n_inst).
    localparam int IXW = LANES > 1 ? $clog2(LANES) : 1;
    wire [7:0] ird_tr, ird_rt, ird_dp, ird_nm;
    // The instance registers as svo_front's buses, set once the frame's rows are read (a
    // continuous assignment from array words does not always update in Icarus 12, as
    // svo_delay.v notes).
    reg [LANES*120-1:0] fr_c;
    reg [LANES*64-1:0] fr_threshold, fr_inside;
    reg [LANES*34-1:0] fr_delta_t;
    reg [LANES*40-1:0] fr_reach;
    reg [LANES*80-1:0] fr_reach2;
    task automatic load_lanes;
        for (int l = 0; l < LANES; l++) begin
            reg [39:0] reach = inst[l][frame_instances_vectors_pkg::REACH_LSB +: 40];
            fr_c[l*120 +: 120] = {inst[l][frame_instances_vectors_pkg::C_Z_LSB +: 40],
                                  inst[l][frame_instances_vectors_pkg::C_Y_LSB +: 40],
                                  inst[l][frame_instances_vectors_pkg::C_X_LSB +: 40]};
            fr_threshold[l*64 +: 64] = inst[l][frame_instances_vectors_pkg::THRESHOLD_LSB +: 64];
            fr_inside[l*64 +: 64] = inst[l][frame_instances_vectors_pkg::INSIDE_LSB +: 64];
            fr_delta_t[l*34 +: 34] = inst[l][frame_instances_vectors_pkg::DELTA_T_LSB +: 34];
            fr_reach[l*40 +: 40] = reach;
            fr_reach2[l*80 +: 80] = 80'(reach) * 80'(reach);   // the host squares the constant
            wk_axes[l*288 +: 288] = inst[l][0 +: 9 * 32];
            wk_half[l*120 +: 120] = {inst[l][frame_instances_vectors_pkg::HALF_Z_LSB +: 40],
                                     inst[l][frame_instances_vectors_pkg::HALF_Y_LSB +: 40],
                                     inst[l][frame_instances_vectors_pkg::HALF_X_LSB +: 40]};
            wk_nb[l*32 +: 32] = nb[inst[l][frame_instances_vectors_pkg::IMAGE_LSB +: 8]];
            wk_ab[l*32 +: 32] = ab[inst[l][frame_instances_vectors_pkg::IMAGE_LSB +: 8]];
            wk_nmat[l*162 +: 162] = inst[l][frame_instances_vectors_pkg::NMAT_XX_LSB +: 162];
        end
    endtask
    // The hit buffer's host registers. This frame is the first: the buffer holds no earlier
    // frame (buffer_valid 0), so nothing is reused; the dirty flags are the host's registers
    // as they stand before any frame (all dirty). testbench/cocotb/test_hit_buffer.py checks
    // reuse across frames.
    reg hb_buffer_valid = 1'b0, hb_camera_dirty = 1'b1;
    reg [LANES-1:0] hb_instance_dirty = '1;
    // The walk section's registers (with the normal matrices) and memory port.
    reg [LANES*288-1:0] wk_axes;
    reg [LANES*162-1:0] wk_nmat;
    reg [LANES*120-1:0] wk_half;
    reg [LANES*32-1:0] wk_nb, wk_ab;
    wire mem_req_valid, mem_req_attr, mem_resp_valid;
    wire [31:0] mem_req_addr;
    reg [63:0] mem_resp_data;
    int left = 0;
    // What the core gives: the pixel stream, the rays the check takes, each ray's results.
    wire hb_wr_valid, hb_wr_direct, hb_wr1_valid, hb_wr2_valid;
    wire [PIXW-1:0] hb_wr_pixel, hb_wr1_pixel, hb_wr2_pixel;
    wire [71:0] hb_wr_word, hb_wr1_word, hb_wr2_word;
    wire chk_valid;
    wire [PIXW-1:0] chk_pixel;
    wire [95:0] chk_dir;
    wire [5:0] chk_count;
    wire wk_done_valid, wk_done_hit, core_err_pipe, core_err_ov, core_err_pixel, core_ev_reused;
    int n_reused = 0, n_records = 0;      // this frame's reused words and walked rays
    wire [PIXW-1:0] wk_done_pixel;
    wire [15:0] wk_done_walks;
    wire [TW-1:0] wk_done_t;
    wire [59:0] wk_done_voxel;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_core #(.LANES(LANES), .NPIX(NPIX), .AW(NPIX > 1 ? $clog2(NPIX) : 1), .PIXW(PIXW),
        .SLOTS(SLOTS), .TAGW(TAGW), .PW(PW), .TW(TW),
        .POS_FRAC(walker_vectors_pkg::O_X_FRAC), .INV_W(walker_vectors_pkg::INV_X_WIDTH),
        .INV_FRAC(walker_vectors_pkg::INV_X_FRAC), .T_FRAC(walker_vectors_pkg::T_FRAC),
        .ROOT_PROD(walker_vectors_pkg::ROOT_LATENCY - 4),
        .STACK_DEPTH(walker_vectors_pkg::STACK_DEPTH), .MAX_STEPS(walker_vectors_pkg::MAX_STEPS),
        .STEP_LATENCY(walker_vectors_pkg::STEP_LATENCY),
        .RG_L(UNITS_RAYGEN_LATENCY_CYCLES),
        .SP_L(UNITS_SPHERE_LATENCY_CYCLES + UNITS_SQRT_LATENCY_CYCLES),
        .SO_N(sorter_vectors_pkg::NET_LANES), .SO_D(sorter_vectors_pkg::NET_DEPTH),
        .SO_S(sorter_vectors_pkg::NET_SLOTS), .SO_PAIRS(sorter_vectors_pkg::NET_PAIRS),
        .SO_MAX_KEYS(32), .TR_L(UNITS_TRANSFORM_LATENCY_CYCLES),
        .RC_L(UNITS_RECIPROCAL_LATENCY_CYCLES), .RT_L(UNITS_WALKER_ROOT_LATENCY_CYCLES),
        .HB_READ(HB_READ), .WRITE_PORTS(WRITE_PORTS), .RECORD_WRITES(RECORD_WRITES),
        .D_RG_SP(D_RG_SP), .D_SP_SO(D_SP_SO), .D_SO_CK(D_SO_CK), .D_CK_TR(D_CK_TR),
        .D_TR_RC(D_TR_RC), .D_RC_RT(D_RC_RT), .D_RT_DP(D_RT_DP), .D_WK_RC(D_WK_RC),
        .D_RC_WR(D_RC_WR))
    u_core (.clk(clk), .rst(rst), .run(fr_run), .npix(PIXW'(NPIX)), .dir_pixel(fr_dir_pixel),
        .dir_f64(fr_dir_f64), .dir_valid(1'b1), .dir_take(),
        .origin_f64({f64_of($signed(cam_o[80 +: 40]), 32), f64_of($signed(cam_o[40 +: 40]), 32),
                     f64_of($signed(cam_o[0 +: 40]), 32)}),
        .cam_o(cam_o), .inst_base(), .n_inst(8'(NINST)), .inst_c(fr_c),
        .inst_threshold(fr_threshold), .inst_inside(fr_inside),
        .inst_delta_t(fr_delta_t), .inst_reach(fr_reach), .inst_reach2(fr_reach2),
        .ird_tr(ird_tr), .inst_axes(wk_axes[ird_tr[IXW-1:0]*288 +: 288]),
        .inst_c_tr(fr_c[ird_tr[IXW-1:0]*120 +: 120]),
        .ird_rt(ird_rt), .inst_half(wk_half[ird_rt[IXW-1:0]*120 +: 120]),
        .ird_dp(ird_dp), .inst_node_base(wk_nb[ird_dp[IXW-1:0]*32 +: 32]),
        .inst_attr_base(wk_ab[ird_dp[IXW-1:0]*32 +: 32]), .buffer_valid(hb_buffer_valid),
        .camera_dirty(hb_camera_dirty), .instance_dirty(hb_instance_dirty),
        .miss_word(miss_word), .wr_hold(1'b0), .ird_nm(ird_nm),
        .inst_nmat(wk_nmat[ird_nm[IXW-1:0]*162 +: 162]),
        .mem_req_valid(mem_req_valid), .mem_req_ready(left <= 1 && !stall_now),
        .mem_req_attr(mem_req_attr),
        .mem_req_addr(mem_req_addr), .mem_resp_valid(mem_resp_valid),
        .mem_resp_data(mem_resp_data), .wr_valid(hb_wr_valid), .wr_pixel(hb_wr_pixel),
        .wr_word(hb_wr_word), .wr_direct(hb_wr_direct), .wr1_valid(hb_wr1_valid),
        .wr1_pixel(hb_wr1_pixel), .wr1_word(hb_wr1_word), .wr2_valid(hb_wr2_valid),
        .wr2_pixel(hb_wr2_pixel), .wr2_word(hb_wr2_word), .chk_valid(chk_valid),
        .chk_pixel(chk_pixel), .chk_dir(chk_dir), .chk_count(chk_count),
        .done_valid(wk_done_valid), .done_pixel(wk_done_pixel), .done_walks(wk_done_walks),
        .done_hit(wk_done_hit), .done_t(wk_done_t), .done_voxel(wk_done_voxel),
        .ev_reused(core_ev_reused),
        .ev_write_stall(), .ev_walk_stall(), .ev_bank_conflict(), .err_pipe(core_err_pipe),
        .err_overflow(core_err_ov), .err_pixel(core_err_pixel), .mem_req_ctx(),
        .mem_resp_ctx(1'b0), .ctx_resp_valid(1'b0), .ctx_resp_data(32'd0));
    /* verilator lint_on PINCONNECTEMPTY */
    // The node memory: a read requested in cycle c is valid in cycle c + L (tb_walker's).
    // With stalls: ready low in a random mem_stall % of cycles (drawn at the falling edge, for
    // the cycle that follows), each read's latency 0..mem_jitter more.
    always @(negedge clk) begin
        stall_now = mem_stall > 0 && ($urandom % 100) < mem_stall;
        if (stall_now && mem_req_valid && left <= 1) n_stalled++;
        extra_now = mem_jitter > 0 ? int'($urandom_range(mem_jitter, 0)) : 0;
    end
    always @(posedge clk) if (mem_req_valid && left <= 1 && !stall_now) n_extra += extra_now;
    `define TB_MEM_WHERE ""
    `define TB_MEM_EXTRA extra_now
    `include "tb_fixed_latency_mem.svh"

    // =====================================================================================
    // The host's side and the checks.
    // =====================================================================================
    int junk;
    // Per pixel: its candidate count (from the front end), and its walk results (from the
    // record stage), checked when the hit buffer writes it.
    int  n_cands [0:NPIX-1];
    int  pix_walks [0:NPIX-1];
    bit  pix_hit [0:NPIX-1];
    reg [TW-1:0] pix_t [0:NPIX-1];
    reg [59:0] pix_voxel [0:NPIX-1];
    int   written = 0;
    bit   pix_done [0:NPIX-1];
    // Every pixel is written once: a second write is a failure (and the frame ends when every
    // pixel has been written, so a repeat would otherwise hide a missing one).
    task automatic note_write(input int p);
        if (pix_done[p]) begin
            n_failed++;
            report($sformatf("pixel %0d: written twice (cycle %0d)", p, cyc));
        end else written++;
        pix_done[p] = 1;
    endtask
    longint cyc = 0;
    // +write_log: one line per hit-buffer write, "write <pixel> <cycle> <path>" (path 0: the
    // record FIFO's head, 1: the check's, 2: the second record), for a comparison with the
    // model's transaction log (the write stage's cycle of every pixel).
    bit write_log = 0;
    task automatic log_write(input int p, input int path);
        if (write_log) $display("write %0d %0d %0d", p, cyc, path);
    endtask

    // A package field this top cannot follow stops the run, naming it.
    task automatic hw_must_be(input string field, input int got, input int built);
        if (got != built)
            $fatal(1, "tb_frame: the hardware package has %s = %0d; this top builds %0d", field, got, built);
    endtask

    `include "tb_frame_host.svh"

    // One model cycle, observed at its falling edge: the hit buffer's writes, the rays whose
    // record is decided, the rays the check stage takes; then the host's direction of the
    // pixel the front end issues next.
    task automatic step;
        if (hb_wr1_valid) begin
            int p = int'(hb_wr1_pixel);
            pix_walks[p] = 0; pix_hit[p] = 0;
            // Frame 1 reuses frame 0's word without a walk: the word and the candidates are
            // what must match.
            if (frame_no > 0) check_word(p, hb_wr1_word);
            else check_pixel(p, hb_wr1_word, pix_walks[p], pix_hit[p], pix_t[p], pix_voxel[p]);
            log_write(p, 1);
            note_write(p);
        end
        if (hb_wr_valid) begin
            int p = int'(hb_wr_pixel);
            if (hb_wr_direct) begin
                pix_walks[p] = 0; pix_hit[p] = 0;
            end
            if (frame_no > 0 && hb_wr_direct) check_word(p, hb_wr_word);
            else check_pixel(p, hb_wr_word, pix_walks[p], pix_hit[p], pix_t[p], pix_voxel[p]);
            log_write(p, 0);
            note_write(p);
        end
        if (hb_wr2_valid) begin
            int p = int'(hb_wr2_pixel);
            check_pixel(p, hb_wr2_word, pix_walks[p], pix_hit[p], pix_t[p], pix_voxel[p]);
            log_write(p, 2);
            note_write(p);
        end
        n_reused += int'(core_ev_reused);
        if (wk_done_valid) begin
            int p = int'(wk_done_pixel);
            n_records++;
            pix_walks[p] = int'(wk_done_walks);
            pix_hit[p] = wk_done_hit;
            pix_t[p] = wk_done_t;
            pix_voxel[p] = wk_done_voxel;
        end
        if (chk_valid) begin
            int p = int'(chk_pixel);
            n_cands[p] = int'(chk_count);
            if (chk_dir !== table_dir(p))
                report($sformatf("pixel %0d: the front end's direction %h, the table's %h", p,
                                 chk_dir, table_dir(p)));
        end
        fr_run = 1;
        fr_dir_f64 = dir_f64(int'(fr_dir_pixel));
    endtask

    // One frame: model cycle n is evaluated at the falling edge inside it; then the cycles
    // row and the pixels never written.
    task automatic run_frame(input longint model_f);
        int passed0 = n_passed;
        while (written < NPIX && cyc < max_cycles) begin
            @(negedge clk);
            step();
            cyc++;
            if (cyc % 1000 == 0 && $test$plusargs("progress"))
                $display("cycle %0d: raygen %0d, written %0d", cyc, int'(fr_dir_pixel), written);
        end
        if (frame_no == 0)
            $display("frame: %0d/%0d pixels equal, RTL %0d cycles, model %0d cycles",
                     n_passed - passed0, NPIX, cyc, model_f);
        else
            $display("frame 1: %0d/%0d pixels equal, RTL %0d cycles, model %0d cycles; %0d words reused, %0d rays walked",
                     n_passed - passed0, NPIX, cyc, model_f, n_reused, n_records);
        // The cycles are part of what this testbench checks: without the model's figure the
        // frame fails rather than passing on its pixels alone. With random memory stalls the
        // model's figure (for the fixed-latency memory) is only a lower bound: the row passes
        // when the frame completed, and the stalls are counted.
        if (mem_stall > 0 || mem_jitter > 0) begin
            $display("frame: random stalls (seed %0d): %0d request cycles held, %0d read cycles added; RTL %0d cycles, %0d without stalls",
                     mem_seed, n_stalled, n_extra, cyc, model_f);
            if (written == NPIX && cyc < max_cycles) n_passed++;
            else begin
                n_failed++;
                $display("FAIL frame: with stalls, %0d of %0d pixels written in %0d cycles (a deadlock or a lost ray)", written, NPIX, cyc);
            end
        end else if (model_f < 0) begin
            n_failed++;
            $display("FAIL frame: no +model_cycles=N given (the cycle model's frame cycles, from `sim --model cycle` on the testbench's hardware; see testbench/README.md)");
        end else if (cyc == model_f) n_passed++;
        else begin
            n_failed++;
            $display("FAIL frame: %0d cycles, the cycle model's %0d", cyc, model_f);
        end
        begin
            bit first = 1;
            for (int p = 0; p < NPIX; p++) if (!pix_done[p]) begin
                n_failed++;
                if (first) $display("FAIL frame: pixel %0d (and %0d more) never written", p, NPIX - written - 1);
                first = 0;
            end
        end
    endtask

    initial begin
        string f;
        if (!$value$plusargs("vectors=%s", dir)) dir = "vectors";
        if ($value$plusargs("latency=%d", mem_latency)) junk = 0;
        if ($value$plusargs("model_cycles=%d", model_cycles)) junk = 0;
        if ($value$plusargs("max_cycles=%d", max_cycles)) junk = 0;
        if ($value$plusargs("mem_stall=%d", mem_stall)) junk = 0;
        if ($value$plusargs("frames=%d", frames)) junk = 0;
        if ($value$plusargs("model_cycles1=%d", model_cycles1)) junk = 0;
        if ($value$plusargs("f1_camera_dirty=%d", f1_camera_dirty)) junk = 0;
        if ($value$plusargs("f1_instance_dirty=%h", f1_instance_dirty)) junk = 0;
        if ($value$plusargs("mem_jitter=%d", mem_jitter)) junk = 0;
        if ($value$plusargs("seed=%d", mem_seed)) junk = 0;
        seed_state = mem_seed;                 // $urandom(seed) may update its argument
        junk = $urandom(seed_state);
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
        load_lanes();
        $readmemh({dir, "/walker_nodes.hex"}, nodes);
        $readmemh({dir, "/walker_attrs.hex"}, attrs);
        // The reciprocals' seed ROMs, from the same folder (as tb_reciprocal loads its own).
        $readmemh({dir, "/reciprocal_seed.hex"}, u_core.u_walk.recip_lane[0].recip[0].u_recip.rom);
        $readmemh({dir, "/reciprocal_seed.hex"}, u_core.u_walk.recip_lane[0].recip[1].u_recip.rom);
        $readmemh({dir, "/reciprocal_seed.hex"}, u_core.u_walk.recip_lane[0].recip[2].u_recip.rom);
        if (cam[0][frame_camera_vectors_pkg::INSTANCES_LSB +: 16] != NINST || NINST > LANES
            || NINST < 1)
            $fatal(1, "tb_frame: the frame has %0d instances; this top has %0d sphere lanes", NINST, LANES);
        // What this top builds by structure against the package (a field it cannot follow
        // stops the run, never ignored).
        hw_must_be("walker_pool.walkers", WALKER_POOL_WALKERS, 1);
        hw_must_be("walker_pool.contexts_per_walker", WALKER_POOL_CONTEXTS_PER_WALKER, 1);
        hw_must_be("transform_units", TRANSFORM_UNITS, 1);
        hw_must_be("reciprocal_units", RECIPROCAL_UNITS, 3);
        hw_must_be("walker_root_units", WALKER_ROOT_UNITS, 1);
        hw_must_be("sorter_lanes", SORTER_LANES, sorter_vectors_pkg::NET_LANES);
        hw_must_be("units.raygen.latency_cycles", UNITS_RAYGEN_LATENCY_CYCLES,
                   u_core.u_front.u_raygen.LATENCY);
        hw_must_be("units.sphere + units.sqrt latency_cycles",
                   UNITS_SPHERE_LATENCY_CYCLES + UNITS_SQRT_LATENCY_CYCLES,
                   u_core.u_front.lane[0].u_sphere.LATENCY);
        hw_must_be("units.sorter.latency_cycles", UNITS_SORTER_LATENCY_CYCLES,
                   sorter_vectors_pkg::NET_DEPTH);
        hw_must_be("units.transform.latency_cycles", UNITS_TRANSFORM_LATENCY_CYCLES,
                   u_core.u_walk.transform[0].u_transform.LATENCY);
        hw_must_be("units.reciprocal.latency_cycles", UNITS_RECIPROCAL_LATENCY_CYCLES,
                   u_core.u_walk.recip_lane[0].recip[0].u_recip.LATENCY);
        hw_must_be("units.walker_root.latency_cycles", UNITS_WALKER_ROOT_LATENCY_CYCLES,
                   u_core.u_walk.root[0].u_root.LATENCY);
        hw_must_be("units.hit_pack.latency_cycles", UNITS_HIT_PACK_LATENCY_CYCLES, L_PK);
        hw_must_be("units.hit_unpack.latency_cycles", UNITS_HIT_UNPACK_LATENCY_CYCLES, 1);
        hw_must_be("hit_buffer.present", int'(HIT_BUFFER_PRESENT), 1);
        repeat (64) @(posedge clk);   // longer than every unit's latency: no X valid bit left
        rst = 1'b0;
        @(posedge clk);
        run_frame(model_cycles);
        if (frames > 1) begin
            // Frame 1: the same scene again (the testbench's tables are frame 0's, so the
            // scene must be still). The pipeline is reset between frames, as the model
            // rebuilds it; the hit buffer keeps its words and the host sets the reuse flags.
            fr_run = 0;
            rst = 1'b1;
            repeat (64) @(posedge clk);
            hb_buffer_valid = 1'b1;
            hb_camera_dirty = 1'(f1_camera_dirty);
            hb_instance_dirty = LANES'(f1_instance_dirty);
            frame_no = 1;
            written = 0;
            n_reused = 0;
            n_records = 0;
            cyc = 0;
            for (int p = 0; p < NPIX; p++) pix_done[p] = 0;
            rst = 1'b0;
            @(posedge clk);
            run_frame(model_cycles1);
        end
        // svo_front's sticky flags: a broken pipe rule fails the frame; a datapath overflow
        // flag (saturation, which the model counts too) is reported.
        if (core_err_pipe || core_err_pixel) begin
            n_failed++;
            $display("FAIL frame: svo_core err_pipe %0d (a unit's result without its ray, the sorter busy, the loop-back FIFO full), err_pixel %0d",
                     core_err_pipe, core_err_pixel);
        end
        if (core_err_ov)
            $display("frame: svo_core saw an overflow flag (raygen, a used sphere lane, transform, reciprocal or pack)");
        $display("%0d passed, %0d failed", n_passed, n_failed);
        $finish;
    end
endmodule
