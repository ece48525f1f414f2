// svo_hit_buffer: the hit buffer with its check stage and write port — reuse across frames
// with the host's dirty flags, valid/ready with back-pressure on every side.
//
// Pipeline position: after the sorter, before the transform (rays to walk) and after the
// record stage (docs/cycle-model.md §2.1: sorter_to_check → check → check_to_transform or
// record_to_write → write). Cycle-exact with the cycle model's check and write stages
// (src/models/cycle/stages/check.rs, write.rs) and the record stage's claim of the write
// FIFO (record.rs):
// - check: an elastic pipe of capacity L = HB_READ + 1 (the hit buffer's read latency plus
//   svo_hit_check's register, units.hit_unpack). A ray accepted in cycle n reads the buffer
//   at the edge ending n (READ_FIRST: a write of the same edge is not seen) and is decided in
//   cycle n + L: reused (svo_hit_check's rule with this frame's dirty flags), or without
//   candidates (the host's miss word), both straight to the write FIFO; else out to walk.
//   The pipe is svo_elastic: `in_ready` is high while fewer than L rays are inside, counting
//   the one that leaves this cycle (so it depends combinationally on walk_ready and the write
//   FIFO's room, as the model's pipe frees its slot before it accepts).
// - the write FIFO (record_to_write, WR_DEPTH deep, registered occupancy): the record stage
//   (`rec_*`) has the port first; the check's word enters only in a cycle the record did not
//   push. The head is written to the buffer every cycle (the write port is always ready) and
//   shown on `wr_*` in that cycle.
// WRITE_PORTS = 2 builds the cycle model's two write paths (hit_buffer.write_ports: 2, the
// default hardware; src/models/cycle/stages/write.rs): the buffer is two banks on pixel
// parity, one write port each, and the check's words have a FIFO of their own
// (check_to_write, WR_DEPTH deep, on wr1_*). Each cycle the check FIFO's head is written
// first; the record FIFO's head is written too unless it falls in the same bank (it waits:
// ev_bank_conflict); with RECORD_WRITES = 2 (hit_buffer.record_writes) the record behind the
// head is written as well (on wr2_*) when the check wrote nothing and it falls in the other
// bank. The record FIFO then passes up to two a cycle, as the model's two-port
// record_to_write; it also takes up to two a cycle, as the model's FIFO has
// max(k, record_writes) = 2 push ports at k = 1: the record stage's second ready record enters
// on rec2_* in the cycle its first does when the FIFO has room for both (registered occupancy
// + 1 < WR_DEPTH; records a, b waiting behind a full FIFO that wrote two enter together).
// Both write-path designs are checked cycle by cycle against the model
// (tb_frame.sv, testbench/cocotb/test_hit_buffer.py).
//
// The buffer holds one word per pixel (NPIX words of WB bits, word layout as
// svo_hit_pack.v) and keeps them across frames: frame f's check reads what frame f − 1 wrote.
// Host inputs, constant during a frame: buffer_valid (the buffer holds a frame of this size
// and camera), camera_dirty, instance_dirty (bit i: instance i moved; an instance id of
// INSTANCES or more reads as dirty), miss_word. A pixel index of NPIX or more sets the sticky
// err_pixel (its address wraps; never a silent overflow).
// Events for the performance counters, one pulse per cycle: ev_reused (a reused word entered
// the write FIFO), ev_write_stall (a decided word waited for the write port), ev_walk_stall (a
// ray to walk waited for walk_ready).
// wr_hold (the pixel stream behind the writes is full, svo_top): no word is written this
// cycle; the write FIFOs keep theirs and fill, and back-pressure does the rest. Tied to 0 the
// write stage is the model's (its write port is always ready).
`timescale 1ns/1ps
`default_nettype none
module svo_hit_buffer #(
    parameter NPIX        = 768,
    parameter AW          = 10,     // address bits: 2^AW >= NPIX
    parameter PIXW        = 32,
    parameter INST_W      = 8,
    parameter T_W         = 22,
    parameter N_W         = 8,
    parameter WB          = 2 + INST_W + T_W + 2 * N_W + 24,
    parameter INSTANCES   = 8,
    parameter HB_READ     = 4,      // hit_buffer read latency, cycles (>= 1)
    parameter PAYW        = 1,      // side band carried with a ray to walk
    parameter WR_DEPTH    = 8,      // record_to_write FIFO depth
    parameter WRITE_PORTS = 1,      // 1: one shared write port; 2: two banks, the check's first
    parameter RECORD_WRITES = 1     // 2: a second record a cycle (WRITE_PORTS = 2 only)
) (
    input  wire                 clk,
    input  wire                 rst,
    // host, constant during a frame
    input  wire                 buffer_valid,
    input  wire                 camera_dirty,
    input  wire [INSTANCES-1:0] instance_dirty,
    input  wire [WB-1:0]        miss_word,
    input  wire                 wr_hold,          // no write this cycle (stream full)
    // rays from the sorter
    input  wire                 in_valid,
    output wire                 in_ready,
    input  wire [PIXW-1:0]      in_pixel,
    input  wire [15:0]          in_candidates,
    input  wire [15:0]          in_candidate,     // the instance of candidate 0
    input  wire [PAYW-1:0]      in_payload,
    // rays to walk
    output wire                 walk_valid,
    input  wire                 walk_ready,
    output wire [PIXW-1:0]      walk_pixel,
    output wire [PAYW-1:0]      walk_payload,
    // records from the record stage
    input  wire                 rec_valid,
    output wire                 rec_ready,
    input  wire [PIXW-1:0]      rec_pixel,
    input  wire [WB-1:0]        rec_word,
    // a second record behind rec_* (RECORD_WRITES = 2), taken only with rec_*'s
    input  wire                 rec2_valid,
    output wire                 rec2_ready,
    input  wire [PIXW-1:0]      rec2_pixel,
    input  wire [WB-1:0]        rec2_word,
    // the buffer's writes (wr: the record FIFO's head, and the check's words when
    // WRITE_PORTS = 1; wr1: the check's FIFO; wr2: the record behind the head)
    output wire                 wr_valid,
    output wire [PIXW-1:0]      wr_pixel,
    output wire [WB-1:0]        wr_word,
    output wire                 wr_direct,        // from the check (reused or no candidate)
    output wire                 wr1_valid,        // port 1 (WRITE_PORTS = 2): the check's words
    output wire [PIXW-1:0]      wr1_pixel,
    output wire [WB-1:0]        wr1_word,
    output wire                 wr2_valid,        // RECORD_WRITES = 2: a second record
    output wire [PIXW-1:0]      wr2_pixel,
    output wire [WB-1:0]        wr2_word,
    output wire                 ev_reused,
    output wire                 ev_write_stall,
    output wire                 ev_walk_stall,
    output wire                 ev_bank_conflict, // the record head waited for its bank
    output reg                  err_pixel
);
    localparam CAP = HB_READ + 1;                  // the check pipe's capacity = its latency
    localparam FW = $clog2(WR_DEPTH + 1);
    localparam WW = WR_DEPTH > 1 ? $clog2(WR_DEPTH) : 1;
    localparam SB = PIXW + 1 + PAYW;               // side band: pixel, no candidate, payload
    localparam QB = PIXW + 1 + 1 + WB + PAYW;      // queue: pixel, direct, reuse, word, payload
    localparam integer F_LAST_I = WR_DEPTH - 1;
    localparam [WW-1:0] F_LAST = F_LAST_I[WW-1:0];
    localparam integer DEPTH_I = WR_DEPTH;
    localparam integer NPIX_I = NPIX;
    localparam integer INSTANCES_I = INSTANCES;
    localparam [FW-1:0] DEPTH_C = DEPTH_I[FW-1:0];
    localparam [AW:0] NPIX_C = NPIX_I[AW:0];
    localparam IXW = INSTANCES > 1 ? $clog2(INSTANCES) : 1;
    localparam [16:0] INSTANCES_C = INSTANCES_I[16:0];

    // Elaboration checks: a parameter outside what this file implements is refused.
    generate
        if (WRITE_PORTS < 1 || WRITE_PORTS > 2) begin : bad_write_ports
            svo_hit_buffer_WRITE_PORTS_must_be_1_or_2 bad();
        end
        if (RECORD_WRITES < 1 || RECORD_WRITES > WRITE_PORTS) begin : bad_record_writes
            svo_hit_buffer_RECORD_WRITES_must_be_1_or_2_and_at_most_WRITE_PORTS bad();
        end
        if (WR_DEPTH < 2 && RECORD_WRITES == 2) begin : bad_depth
            svo_hit_buffer_WR_DEPTH_must_be_2_or_more_for_two_record_writes bad();
        end
        if (HB_READ < 1) begin : bad_read
            svo_hit_buffer_HB_READ_must_be_at_least_1 bad();
        end
        if ((1 << AW) < NPIX || AW >= PIXW || INSTANCES > 65536 || (WRITE_PORTS == 2 && AW < 2))
        begin : bad_aw
            svo_hit_buffer_AW_must_fit_NPIX_and_be_below_PIXW bad();
        end
    endgenerate

    // ---------------------------------------------------------------- the buffer
    // One word per pixel: one memory (WRITE_PORTS = 1), or two banks on pixel parity with a
    // write port each (WRITE_PORTS = 2). The read is registered in the memory (READ_FIRST:
    // a write of the same edge is not seen); with two banks both are read and the pixel's
    // parity picks the word after the registers, so each bank is a plain simple dual-port
    // block RAM.
    // Each bank layout reads only the write paths it has (one bank: w0 alone).
    /* verilator lint_off UNUSEDSIGNAL */
    wire          w0_en, w1_en, w2_en;
    wire [AW-1:0] w0_addr, w1_addr, w2_addr;
    wire [WB-1:0] w0_data, w1_data, w2_data;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [WB-1:0] rd_word;                         // the accepted ray's word, a cycle on

    // ---------------------------------------------------------------- check pipe
    wire accept = in_valid && in_ready;
    wire in_dirty = ({1'b0, in_candidate} >= INSTANCES_C) ? 1'b1
                  : instance_dirty[in_candidate[IXW-1:0]];
    // Stages 1..HB_READ: the read word (stage 1 is the memory's own register) and what the
    // check needs; the side band runs one stage further, beside svo_hit_check's register.
    localparam HB_HI = HB_READ > 1 ? HB_READ : 2;
    reg [HB_READ:1]   s_valid;
    reg [WB-1:0]      s_word  [2:HB_HI];
    reg [15:0]        s_cands [1:HB_READ];
    reg [15:0]        s_cand  [1:HB_READ];
    reg [HB_READ:1]   s_dirty;
    reg [SB-1:0]      s_side  [1:HB_READ + 1];
    integer k;
    always @(posedge clk) begin
        s_valid[1] <= rst ? 1'b0 : accept;
        s_cands[1] <= in_candidates;
        s_cand[1]  <= in_candidate;
        s_dirty[1] <= in_dirty;
        s_side[1]  <= {in_pixel, in_candidates == 16'd0, in_payload};
        for (k = 2; k <= HB_READ; k = k + 1) begin
            s_valid[k] <= rst ? 1'b0 : s_valid[k - 1];
            s_word[k]  <= k == 2 ? rd_word : s_word[k - 1];
            s_cands[k] <= s_cands[k - 1];
            s_cand[k]  <= s_cand[k - 1];
            s_dirty[k] <= s_dirty[k - 1];
        end
        for (k = 2; k <= HB_READ + 1; k = k + 1) s_side[k] <= s_side[k - 1];
    end
    wire [WB-1:0] ck_word = HB_READ == 1 ? rd_word : s_word[HB_HI];

    generate
        if (WRITE_PORTS == 1) begin : one_bank
            reg [WB-1:0] mem [0:NPIX-1];
            reg [WB-1:0] rd_q;
            always @(posedge clk) begin
                rd_q <= mem[in_pixel[AW-1:0]];
                if (w0_en) mem[w0_addr] <= w0_data;
            end
            assign rd_word = rd_q;
        end else begin : two_banks
            // Bank b holds the pixels p with p mod 2 = b at p / 2. The model's rule puts at
            // most one write in each bank a cycle (check first, then the records by bank).
            localparam HALF = (NPIX + 1) / 2;
            reg [WB-1:0] bank0 [0:HALF-1];
            reg [WB-1:0] bank1 [0:HALF-1];
            reg [WB-1:0] rd0_q, rd1_q;
            reg          par_q;
            wire b0_w1 = w1_en && !w1_addr[0], b1_w1 = w1_en && w1_addr[0];
            wire b0_w0 = w0_en && !w0_addr[0], b1_w0 = w0_en && w0_addr[0];
            wire b0_w2 = w2_en && !w2_addr[0], b1_w2 = w2_en && w2_addr[0];
            wire [AW-2:0] b0_addr = b0_w1 ? w1_addr[AW-1:1] : b0_w0 ? w0_addr[AW-1:1]
                                  : w2_addr[AW-1:1];
            wire [AW-2:0] b1_addr = b1_w1 ? w1_addr[AW-1:1] : b1_w0 ? w0_addr[AW-1:1]
                                  : w2_addr[AW-1:1];
            wire [WB-1:0] b0_data = b0_w1 ? w1_data : b0_w0 ? w0_data : w2_data;
            wire [WB-1:0] b1_data = b1_w1 ? w1_data : b1_w0 ? w0_data : w2_data;
            always @(posedge clk) begin
                rd0_q <= bank0[in_pixel[AW-1:1]];
                rd1_q <= bank1[in_pixel[AW-1:1]];
                par_q <= in_pixel[0];
                if (b0_w1 || b0_w0 || b0_w2) bank0[b0_addr] <= b0_data;
                if (b1_w1 || b1_w0 || b1_w2) bank1[b1_addr] <= b1_data;
            end
            assign rd_word = par_q ? rd1_q : rd0_q;
        end
    endgenerate

    wire          p_valid, p_reuse;
    wire [WB-1:0] p_reused;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_hit_check #(.INST_W(INST_W), .T_W(T_W), .N_W(N_W), .WB(WB)) u_check (
        .clk(clk), .rst(rst), .in_valid(s_valid[HB_READ]), .in_prev(ck_word),
        .in_buffer(buffer_valid), .in_camera_dirty(camera_dirty),
        .in_candidates(s_cands[HB_READ]), .in_candidate(s_cand[HB_READ]),
        .in_instance_dirty(s_dirty[HB_READ]),
        .out_valid(p_valid), .out_kind(), .out_hit(), .out_instance(), .out_t(),
        .out_normal_u(), .out_normal_v(), .out_colour_r(), .out_colour_g(), .out_colour_b(),
        .out_reuse(p_reuse), .out_reused_word(p_reused));
    /* verilator lint_on PINCONNECTEMPTY */
    wire [PIXW-1:0] p_pixel;
    wire            p_nocand;
    wire [PAYW-1:0] p_payload;
    assign {p_pixel, p_nocand, p_payload} = s_side[HB_READ + 1];
    wire          p_direct = p_reuse || p_nocand;
    wire [WB-1:0] p_dword = p_reuse ? p_reused : miss_word;

    // The check pipe's back-pressure: svo_elastic of capacity CAP around the read and
    // svo_hit_check. The decided rays that could not leave yet wait in order; the head is the
    // oldest of these, else svo_hit_check's output of this cycle. A direct word leaves when
    // the write FIFO has room, a ray to walk when walk_ready is high.
    wire            h_valid, h_ready;
    wire [QB-1:0]   h;
    svo_elastic #(.L(CAP), .W(QB)) check_pipe (.clk(clk), .rst(rst), .in_valid(in_valid),
        .in_ready(in_ready), .unit_valid(p_valid),
        .unit_data({p_pixel, p_direct, p_reuse, p_dword, p_payload}), .out_valid(h_valid),
        .out_ready(h_ready), .out_data(h));
    wire [PIXW-1:0] h_pixel;
    wire            h_direct, h_reuse;
    wire [WB-1:0]   h_word;
    wire [PAYW-1:0] h_payload;
    assign {h_pixel, h_direct, h_reuse, h_word, h_payload} = h;

    // ---------------------------------------------------------------- write FIFOs
    reg [PIXW + WB:0] f0 [0:WR_DEPTH-1];            // {direct, pixel, word}
    reg [WW-1:0] f0_rd, f0_wr;
    reg [FW-1:0] f0_n;
    wire rec_push = rec_valid && rec_ready;
    assign rec_ready = f0_n < DEPTH_C;
    // The second push port: room for two by the registered occupancy, taken with the first.
    localparam [FW:0] DEPTH_W = DEPTH_I[FW:0];
    assign rec2_ready = (RECORD_WRITES == 2) && {1'b0, f0_n} + 1'b1 < DEPTH_W;
    wire rec2_push = rec_push && rec2_valid && rec2_ready;
    wire [WW-1:0] f0_wr1 = (f0_wr == F_LAST) ? {WW{1'b0}} : f0_wr + 1'b1;
    wire f1_free;                                   // the check's FIFO has room
    wire ck_room = (WRITE_PORTS == 1) ? (!rec_push && f0_n < DEPTH_C) : f1_free;
    wire ck_push = h_valid && h_direct && ck_room;
    assign walk_valid = h_valid && !h_direct;
    assign walk_pixel = h_pixel;
    assign walk_payload = h_payload;
    wire f0_push_ck = (WRITE_PORTS == 1) && ck_push;
    wire f0_push = rec_push || f0_push_ck;
    // The record FIFO's head, and the record behind it (RECORD_WRITES = 2).
    wire [WW-1:0] f0_rd1 = (f0_rd == F_LAST) ? {WW{1'b0}} : f0_rd + 1'b1;
    localparam [FW:0] TWO = 2;
    wire          f0_two = {1'b0, f0_n} >= TWO;
    assign {wr_direct, wr_pixel, wr_word} = f0[f0_rd];
    /* verilator lint_off UNUSEDSIGNAL */
    wire          s_direct_unused;                 // wr2 is always a record
    /* verilator lint_on UNUSEDSIGNAL */
    assign {s_direct_unused, wr2_pixel, wr2_word} = f0[f0_rd1];
    // Two banks: the check's word goes first; the record head waits if it shares the bank.
    wire conflict = (WRITE_PORTS == 2) && wr1_valid && f0_n != {FW{1'b0}}
                 && wr1_pixel[0] == wr_pixel[0];
    assign wr_valid = f0_n != {FW{1'b0}} && !conflict && !wr_hold;
    assign wr2_valid = (RECORD_WRITES == 2) && wr_valid && !wr1_valid && f0_two
                    && wr2_pixel[0] != wr_pixel[0];
    // One bit wider than the occupancy so that WR_DEPTH = 1 needs no special case; the top
    // bit is never set (the occupancy stays within 0..WR_DEPTH).
    /* verilator lint_off UNUSEDSIGNAL */
    wire [FW:0] f0_next = {1'b0, f0_n} + {{FW{1'b0}}, f0_push} + {{FW{1'b0}}, rec2_push}
                        - {{FW{1'b0}}, wr_valid} - {{FW{1'b0}}, wr2_valid};
    /* verilator lint_on UNUSEDSIGNAL */
    assign w0_en = wr_valid;
    assign w0_addr = wr_pixel[AW-1:0];
    assign w0_data = wr_word;
    assign w2_en = wr2_valid;
    assign w2_addr = wr2_pixel[AW-1:0];
    assign w2_data = wr2_word;

    assign h_ready = h_direct ? ck_room : walk_ready;

    function out_of_range(input [PIXW-1:0] p);
        out_of_range = (|p[PIXW-1:AW]) || {1'b0, p[AW-1:0]} >= NPIX_C;
    endfunction

    always @(posedge clk) begin
        if (rst) begin
            f0_rd <= {WW{1'b0}};
            f0_wr <= {WW{1'b0}};
            f0_n <= {FW{1'b0}};
            err_pixel <= 1'b0;
        end else begin
            if (f0_push) begin
                f0[f0_wr] <= rec_push ? {1'b0, rec_pixel, rec_word} : {1'b1, h_pixel, h_word};
                f0_wr <= f0_wr1;
            end
            if (rec2_push) begin
                f0[f0_wr1] <= {1'b0, rec2_pixel, rec2_word};
                f0_wr <= (f0_wr1 == F_LAST) ? {WW{1'b0}} : f0_wr1 + 1'b1;
            end
            if (wr2_valid) f0_rd <= (f0_rd1 == F_LAST) ? {WW{1'b0}} : f0_rd1 + 1'b1;
            else if (wr_valid) f0_rd <= f0_rd1;
            f0_n <= f0_next[FW-1:0];
            if ((accept && out_of_range(in_pixel)) || (rec_push && out_of_range(rec_pixel))
                || (rec2_push && out_of_range(rec2_pixel)))
                err_pixel <= 1'b1;
        end
    end

    // The check's own FIFO and write port (WRITE_PORTS = 2), else nothing.
    generate
        if (WRITE_PORTS == 2) begin : port1
            reg [PIXW + WB - 1:0] f1 [0:WR_DEPTH-1];
            reg [WW-1:0] f1_rd, f1_wr;
            reg [FW-1:0] f1_n;
            assign f1_free = f1_n < DEPTH_C;
            assign wr1_valid = f1_n != {FW{1'b0}} && !wr_hold;
            assign {wr1_pixel, wr1_word} = f1[f1_rd];
            always @(posedge clk) begin
                if (rst) begin
                    f1_rd <= {WW{1'b0}};
                    f1_wr <= {WW{1'b0}};
                    f1_n <= {FW{1'b0}};
                end else begin
                    if (ck_push) begin
                        f1[f1_wr] <= {h_pixel, h_word};
                        f1_wr <= (f1_wr == F_LAST) ? {WW{1'b0}} : f1_wr + 1'b1;
                    end
                    if (wr1_valid) f1_rd <= (f1_rd == F_LAST) ? {WW{1'b0}} : f1_rd + 1'b1;
                    f1_n <= f1_n + {{(FW - 1){1'b0}}, ck_push} - {{(FW - 1){1'b0}}, wr1_valid};
                end
            end
        end else begin : port1_none
            assign f1_free = 1'b0;
            assign wr1_valid = 1'b0;
            assign wr1_pixel = {PIXW{1'b0}};
            assign wr1_word = {WB{1'b0}};
        end
    endgenerate
    assign w1_en = wr1_valid;
    assign w1_addr = wr1_pixel[AW-1:0];
    assign w1_data = wr1_word;

    assign ev_reused = ck_push && h_reuse;
    assign ev_write_stall = h_valid && h_direct && !ck_room;
    assign ev_walk_stall = walk_valid && !walk_ready;
    assign ev_bank_conflict = conflict;
endmodule
`default_nettype wire
