// svo_node_cache: the node memory's cache in front of DRAM (the model's NodeMemory without its
// on-chip store): line-interleaved banks with in-order request queues and PORTS lookups a
// cycle, set-associative tags with true LRU, MSHRs that merge any number of reads, the miss
// queue (hit under miss) and the fill side towards DRAM. Cycle-exact with
// rtl_model/src/cycle/memory (mod.rs "Timing semantics"; cache.rs, dram.rs) with the built-in
// DRAM timing, checked by tests/node_cache_rtl.rs through testbench/tb/tb_node_cache.sv.
//
// Pipeline position: between the walker pool (one request port per walker) and external
// memory. Not yet inside svo_top (its node reads still go to fixed-latency AXI masters).
//
// Cycle numbering: the first cycle after reset is the model's cycle 0. Everything the model's
// step(k) does is done by the combinational block in cycle k and registered at the edge that
// ends it; the model's step(k+1) part 1 (fills that complete in k+1 install their line and free
// their MSHR) is done at the end of cycle k as well, from the fill lanes presented in cycle k.
//
// Request side (cycle k):
//   req_valid[p], req_requester[p] (requester id = walker * contexts + context), req_kind[p]
//   (0 node word, 1 far word, 2 attribute record), req_addr[p] (node word address or
//   attribute record index). Port p's requester ids must all be below port p+1's (the pool's
//   walker order), so port order is requester order, the model's service order within a
//   cycle. No ready: a request always enters its bank's queue (line mod BANKS) in the cycle it
//   is made (the model's crossbar) and is looked up in that cycle if a port is free. Each
//   requester has at most one read outstanding (the pool's property; each bank queue holds
//   REQUESTERS entries for that reason); a request of a requester with one outstanding is a
//   protocol error (the testbench flags it).
// Response side: rsp_done[r] is a one-cycle pulse in the model's cycle_done of requester r's
//   read; rsp_data[64r +: 64] (a per-requester register, valid from that cycle until the
//   requester's next completion) holds the node word in bits 31:0 (63:32 zero) or the 8-byte
//   attribute record (the word at the lower address in 31:0).
// Fill side (DRAM):
//   fill_req_valid[l], fill_req_line[l], fill_req_mshr[l], l < ISSUE_LANES: the fills issued in
//   cycle k (combinational, in issue order: lane 0 first; the lanes used are 0 .. n-1). Line
//   numbers are byte address / LINE_BYTES in the unified 41-bit byte space of cache.rs (node
//   words from byte 0, attribute record i at 2^40 + 8i). No back-pressure: the memory takes
//   every fill (the model's bus queue is unbounded; MSHRS bounds what is in flight).
//   fill_valid[l], fill_mshr[l], fill_data[l] (a whole line, byte 0 in bits 7:0), l <
//   FILL_LANES: the fills whose model completion cycle (dram.rs Fill::done) is k + 1, presented
//   in cycle k in issue order. The line is written at the end of cycle k, so in cycle k+1 it is
//   in the tags (a lookup hits), its MSHR is free and its reads' rsp_done pulse. Several fills
//   complete in one cycle when bytes_per_cycle > LINE_BYTES: FILL_LANES = ceil(bytes_per_cycle
//   / LINE_BYTES) covers the built-in bus (ends of consecutive fills are LINE_BYTES apart).
//   The memory times the fills; testbench/tb/tb_dram_model.sv is the built-in bus of dram.rs.
//   Mapping onto AXI4: svo_node_cache_axi.v (this cache with its fills as one-beat INCR bursts
//   of LINE_BYTES on FILL_LANES read ports, ARID = MSHR index; the AR registered, so the
//   memory sees a fill one cycle after its issue; RLAST's line registered onto the fill lanes,
//   i.e. presented one cycle before the model's completion cycle, as above), exact against
//   testbench/tb/tb_axi_dram.sv (tests/node_cache_axi_rtl.rs).
// Counters: the model's NodeMemoryStats cache_hits (replayed hits included), cache_misses,
//   cache_merged, dram_fills, uncached_reads; and cnt_replay_hits, the part of cnt_hits made by
//   the miss queue's head on its tag re-check (the model counts those among its hits only).
//
// Structure: the tag, LRU-age, MSHR and queue state are registers and one combinational block
// runs the model's cycle in its order (miss queue head first, then the banks in the rotating
// order starting at bank k mod BANKS, PORTS lookups each, then the fills). It is a reference
// structure, exact by construction and small enough to synthesise at test sizes; it is not
// pipelined for 300 MHz (a lookup, its MSHR search and the next lookup of the same cycle are in
// series), which integration at the default geometry will need (tag arrays in RAM, the LRU
// update and MSHR CAM in their own stages).
`timescale 1ns/1ps
`default_nettype none
module svo_node_cache #(
    parameter REQ_PORTS   = 2,     // walkers
    parameter REQUESTERS  = 8,     // contexts in all (>= 2)
    parameter BANKS       = 4,     // cache.banks, a power of two <= SETS
    parameter PORTS       = 2,     // cache.ports
    parameter SETS        = 16,    // cache.size_bytes / (ways * line_bytes), a power of two >= 2
    parameter WAYS        = 4,     // cache.ways
    parameter LINE_BYTES  = 64,    // cache.line_bytes (8 .. 4096)
    parameter HIT_LATENCY = 4,     // cache.hit_latency (>= 1)
    parameter MSHRS       = 8,     // dram.mshrs (>= 2)
    parameter MISS_QUEUE  = 32,    // cache.miss_queue (0 allowed)
    parameter ATTR_CACHED = 1,     // cache.attr_cached
    parameter FILL_LANES  = 2,     // ceil(dram.bytes_per_cycle / LINE_BYTES)
    parameter ISSUE_LANES = 8      // >= min(MSHRS, MISS_QUEUE + BANKS * PORTS)
) (
    input  wire                                         clk,
    input  wire                                         rst,
    input  wire [REQ_PORTS-1:0]                         req_valid,
    input  wire [REQ_PORTS*$clog2(REQUESTERS)-1:0]      req_requester,
    input  wire [REQ_PORTS*2-1:0]                       req_kind,
    input  wire [REQ_PORTS*32-1:0]                      req_addr,
    output reg  [REQUESTERS-1:0]                        rsp_done,
    output wire [REQUESTERS*64-1:0]                     rsp_data,
    output reg  [ISSUE_LANES-1:0]                       fill_req_valid,
    output reg  [ISSUE_LANES*(41-$clog2(LINE_BYTES))-1:0] fill_req_line,
    output reg  [ISSUE_LANES*$clog2(MSHRS)-1:0]         fill_req_mshr,
    input  wire [FILL_LANES-1:0]                        fill_valid,
    input  wire [FILL_LANES*$clog2(MSHRS)-1:0]          fill_mshr,
    input  wire [FILL_LANES*LINE_BYTES*8-1:0]           fill_data,
    output reg  [31:0]                                  cnt_hits,
    output reg  [31:0]                                  cnt_misses,
    output reg  [31:0]                                  cnt_merged,
    output reg  [31:0]                                  cnt_fills,
    output reg  [31:0]                                  cnt_uncached,
    output reg  [31:0]                                  cnt_replay_hits
);
    localparam integer RQW = $clog2(REQUESTERS);
    localparam integer MW = $clog2(MSHRS);
    localparam integer LB = $clog2(LINE_BYTES);
    localparam integer SB = $clog2(SETS);
    localparam integer LINEW = 41 - LB;            // line number
    localparam integer TAGW = LINEW - SB;          // line number above the set bits
    localparam integer WB = LB - 2;                // word index within a line
    localparam integer LBITS = LINE_BYTES * 8;
    localparam integer SW = SETS * WAYS;           // tag entries
    localparam integer SLW = SW > 1 ? $clog2(SW) : 1;
    localparam integer AGW = WAYS > 1 ? $clog2(WAYS) : 1;
    localparam integer BQ = REQUESTERS;            // entries per bank queue
    localparam integer CW = $clog2(BQ + 1);
    localparam integer MQD = MISS_QUEUE > 0 ? MISS_QUEUE : 1;
    localparam integer MQW = $clog2(MQD + 1);
    localparam integer EW = RQW + 34;              // queue entry: {requester, kind, addr}
    localparam integer SLOTS = MISS_QUEUE + BANKS * PORTS;
    localparam integer NEED_ISSUE = MSHRS < SLOTS ? MSHRS : SLOTS;
    localparam [1:0] KIND_ATTR = 2'd2;
    localparam integer MQ_I = MISS_QUEUE;
    localparam [MQW-1:0] MQ_SIZE = MQ_I[MQW-1:0];
    localparam integer LRU_I = WAYS - 1;
    localparam [AGW-1:0] LRU_AGE = LRU_I[AGW-1:0];
    localparam integer HCW = HIT_LATENCY > 1 ? $clog2(HIT_LATENCY) : 1;  // hit countdown
    localparam integer HIT_LAST_I = HIT_LATENCY - 1;
    localparam [HCW-1:0] HIT_LAST = HIT_LAST_I[HCW-1:0];
    localparam [HCW-1:0] HIT_ONE = 1;

    generate
        if (REQUESTERS < 2 || MSHRS < 2 || SETS < 2 || BANKS > SETS || (BANKS & (BANKS - 1)) != 0
            || (SETS & (SETS - 1)) != 0 || LINE_BYTES < 8 || (LINE_BYTES & (LINE_BYTES - 1)) != 0
            || HIT_LATENCY < 1 || WAYS < 1 || PORTS < 1 || FILL_LANES < 1
            || ISSUE_LANES < NEED_ISSUE) begin : bad_params
            svo_node_cache_parameters_out_of_range bad();
        end
    endgenerate

    // The line of a read (cache.rs line_of): the byte address in the unified 41-bit space
    // over the line size (the byte within the line is not needed here).
    function [LINEW-1:0] line_of(input [1:0] kind, input [31:0] addr);
        /* verilator lint_off UNUSEDSIGNAL */
        reg [40:0] byte_addr;
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            if (kind == KIND_ATTR) byte_addr = {1'b1, 5'd0, addr, 3'd0};
            else byte_addr = {7'd0, addr, 2'd0};
            line_of = byte_addr[40:LB];
        end
    endfunction

    // ---- State (packed vectors: whole-state copies and queue shifts are one operation) -----
    reg [SW*TAGW-1:0]   tag_q;
    reg [SW-1:0]        val_q;
    reg [SW*AGW-1:0]    age_q;                     // 0 = most recently used; a permutation per set
    reg [MSHRS-1:0]     mv_q;                      // MSHR in use
    reg [MSHRS-1:0]     mi_q;                      // install the line when it arrives
    reg [MSHRS*LINEW-1:0] ml_q;
    reg [BANKS*BQ*EW-1:0] bq_q;                    // bank queues, head at entry 0 of each
    reg [BANKS*CW-1:0]  bn_q;
    reg [MQD*EW-1:0]    mq_q;                      // miss queue, head at entry 0
    reg [MQW-1:0]       mn_q;
    reg [31:0]          rot_q;                     // cycle mod BANKS: first bank for MSHRs
    reg [LBITS-1:0]     data_mem [0:SW-1];
    reg [REQUESTERS-1:0] wait_q;                   // waiting for the fill of MSHR wm_q
    reg [REQUESTERS*MW-1:0] wm_q;
    reg [REQUESTERS-1:0] attr_q;
    reg [REQUESTERS*WB-1:0] word_q;
    reg [REQUESTERS*HCW-1:0] hcnt_q;               // hit latency countdown
    reg [REQUESTERS*64-1:0] data_q;
    assign rsp_data = data_q;

    // ---- The model's cycle, combinationally -------------------------------------------------
    reg [SW*TAGW-1:0]   n_tag;
    reg [SW-1:0]        n_val;
    reg [SW*AGW-1:0]    n_age;
    reg [MSHRS-1:0]     n_mv, n_mi;
    reg [MSHRS*LINEW-1:0] n_ml;
    reg [BANKS*BQ*EW-1:0] n_bq;
    reg [BANKS*CW-1:0]  n_bn;
    reg [MQD*EW-1:0]    n_mq;
    reg [MQW-1:0]       n_mn;
    reg [REQUESTERS-1:0] ev_hit, ev_wait, ev_attr;
    reg [REQUESTERS*SLW-1:0] ev_slot;
    reg [REQUESTERS*MW-1:0] ev_m;
    reg [REQUESTERS*WB-1:0] ev_word;
    reg [FILL_LANES-1:0] inst_v;
    reg [FILL_LANES*SLW-1:0] inst_slot;
    reg [31:0]          inc_hit, inc_miss, inc_merge, inc_fill, inc_unc, inc_replay;
    reg [BANKS*32-1:0]  rp;                        // per bank: lookup ports the replays took
    reg [BANKS*32-1:0]  bpos;                      // per j (rotation order): entries popped
    reg [BANKS-1:0]     bstop;                     // per j: stalled (miss queue full)
    reg [BQ*EW-1:0]     bqt;                       // one bank's queue, being shifted

    integer s, i, w, m, j, p, b, set_i, base, hw, fm, lane, mpops, cnt;
    reg go, is_mq, mstop, hit, cached, ok;
    reg [EW-1:0]    e;
    reg [RQW-1:0]   e_rq;
    reg [1:0]       e_kind;
    reg [31:0]      e_addr;
    reg [LINEW-1:0] line;
    reg [TAGW-1:0]  tag;
    reg [AGW-1:0]   a;
    reg [MW-1:0]    mi;
    /* verilator lint_off UNUSEDSIGNAL */
    reg [32:0]      w33;                           // (the word index of an attribute record)
    /* verilator lint_on UNUSEDSIGNAL */

    always @* begin
        n_tag = tag_q;
        n_age = age_q;
        n_val = val_q;
        n_mv = mv_q;
        n_mi = mi_q;
        n_ml = ml_q;
        n_bq = bq_q;
        n_bn = bn_q;
        n_mq = mq_q;
        n_mn = mn_q;
        rp = {BANKS*32{1'b0}};
        bpos = {BANKS*32{1'b0}};
        bstop = {BANKS{1'b0}};
        bqt = {BQ*EW{1'b0}};
        ev_hit = {REQUESTERS{1'b0}};
        ev_wait = {REQUESTERS{1'b0}};
        ev_attr = {REQUESTERS{1'b0}};
        ev_slot = {REQUESTERS*SLW{1'b0}};
        ev_m = {REQUESTERS*MW{1'b0}};
        ev_word = {REQUESTERS*WB{1'b0}};
        fill_req_valid = {ISSUE_LANES{1'b0}};
        fill_req_line = {ISSUE_LANES*LINEW{1'b0}};
        fill_req_mshr = {ISSUE_LANES*MW{1'b0}};
        lane = 0;
        inc_hit = 0;
        inc_miss = 0;
        inc_merge = 0;
        inc_fill = 0;
        inc_unc = 0;
        inc_replay = 0;
        inst_v = {FILL_LANES{1'b0}};
        inst_slot = {FILL_LANES*SLW{1'b0}};
        mstop = 1'b0;
        mpops = 0;
        go = 1'b0;
        is_mq = 1'b0;
        hit = 1'b0;
        cached = 1'b0;
        ok = 1'b0;
        e = {EW{1'b0}};
        e_rq = {RQW{1'b0}};
        e_kind = 2'd0;
        e_addr = 32'd0;
        line = {LINEW{1'b0}};
        tag = {TAGW{1'b0}};
        a = {AGW{1'b0}};
        mi = {MW{1'b0}};
        w33 = 33'd0;
        set_i = 0;
        base = 0;
        hw = 0;
        fm = 0;
        cnt = 0;
        j = 0;
        p = 0;
        b = 0;
        s = 0;  // (loop variables, assigned on every path: no latch)
        w = 0;
        m = 0;

        // The crossbar: this cycle's requests join their bank's queue in port order.
        for (i = 0; i < REQ_PORTS; i = i + 1) begin
            if (req_valid[i]) begin
                line = line_of(req_kind[2*i +: 2], req_addr[32*i +: 32]);
                b = {{(32 - SB){1'b0}}, line[SB-1:0]} % BANKS;
                cnt = {{(32 - CW){1'b0}}, n_bn[CW*b +: CW]};
                if (cnt < BQ) begin
                    n_bq[EW*(b * BQ + cnt) +: EW] =
                        {req_requester[RQW*i +: RQW], req_kind[2*i +: 2], req_addr[32*i +: 32]};
                    n_bn[CW*b +: CW] = n_bn[CW*b +: CW] + 1'b1;
                end
            end
        end

        // Slots 0 .. MISS_QUEUE-1: the miss queue's head, in order; then each bank (rotating,
        // from bank cycle mod BANKS) with PORTS lookups less the ports its replays took.
        // (Skipped when both queues are empty: the same result, a faster simulation.)
        if (mn_q != 0 || n_bn != 0)
        for (s = 0; s < SLOTS; s = s + 1) begin
            go = 1'b0;
            is_mq = s < MISS_QUEUE;
            if (is_mq) begin
                if (!mstop && s < {{(32 - MQW){1'b0}}, mn_q}) begin
                    e = n_mq[EW*(s % MQD) +: EW];
                    go = 1'b1;
                end
            end else begin
                if (s == MISS_QUEUE && mpops != 0) begin
                    // The miss queue's pops leave; misses of the lookups join behind.
                    n_mq = n_mq >> (EW * mpops);
                    n_mn = n_mn - mpops[MQW-1:0];
                end
                j = (s - MISS_QUEUE) / PORTS;
                p = (s - MISS_QUEUE) % PORTS;
                b = (j + rot_q) % BANKS;
                if (!bstop[j] && p + rp[32*b +: 32] < PORTS
                    && bpos[32*j +: 32] < {{(32 - CW){1'b0}}, n_bn[CW*b +: CW]}) begin
                    e = n_bq[EW*(b * BQ + bpos[32*j +: 32]) +: EW];
                    go = 1'b1;
                end
            end
            if (go) begin
                e_rq = e[EW-1 -: RQW];
                e_kind = e[33:32];
                e_addr = e[31:0];
                line = line_of(e_kind, e_addr);
                set_i = {{(32 - SB){1'b0}}, line[SB-1:0]};
                tag = line[LINEW-1:SB];
                base = set_i * WAYS;
                if (is_mq) b = set_i % BANKS;
                cached = e_kind != KIND_ATTR || ATTR_CACHED != 0;
                hit = 1'b0;
                hw = 0;
                if (cached)
                    for (w = 0; w < WAYS; w = w + 1)
                        if (n_val[base + w] && n_tag[TAGW*(base + w) +: TAGW] == tag) begin
                            hit = 1'b1;
                            hw = w;
                        end
                ev_attr[e_rq] = e_kind == KIND_ATTR;
                w33 = {e_addr, 1'b0};
                ev_word[WB*e_rq +: WB] = e_kind == KIND_ATTR ? w33[WB-1:0] : e_addr[WB-1:0];
                if (hit && is_mq && rp[32*b +: 32] >= PORTS) begin
                    // A replay hit with no port left in its bank: waits, in order.
                    mstop = 1'b1;
                end else if (hit) begin
                    a = n_age[AGW*(base + hw) +: AGW];
                    for (w = 0; w < WAYS; w = w + 1)
                        if (n_age[AGW*(base + w) +: AGW] < a)
                            n_age[AGW*(base + w) +: AGW] = n_age[AGW*(base + w) +: AGW] + 1'b1;
                    n_age[AGW*(base + hw) +: AGW] = {AGW{1'b0}};
                    ev_hit[e_rq] = 1'b1;
                    ev_slot[SLW*e_rq +: SLW] = base[SLW-1:0] + hw[SLW-1:0];
                    inc_hit = inc_hit + 1;
                    if (is_mq) begin
                        rp[32*b +: 32] = rp[32*b +: 32] + 1;
                        mpops = mpops + 1;
                        inc_replay = inc_replay + 1;
                    end else begin
                        bpos[32*j +: 32] = bpos[32*j +: 32] + 1;
                    end
                end else begin
                    // To DRAM: merge into the fill of the line in flight, or take a free MSHR.
                    ok = 1'b0;
                    fm = -1;
                    for (m = MSHRS - 1; m >= 0; m = m - 1)
                        if (n_mv[m] && n_ml[LINEW*m +: LINEW] == line) fm = m;
                    if (fm >= 0) begin
                        mi = fm[MW-1:0];
                        n_mi[mi] = n_mi[mi] | cached;
                        ok = 1'b1;
                        if (cached) inc_merge = inc_merge + 1;
                    end else begin
                        for (m = MSHRS - 1; m >= 0; m = m - 1)
                            if (!n_mv[m]) fm = m;
                        if (fm >= 0) begin
                            mi = fm[MW-1:0];
                            n_mv[mi] = 1'b1;
                            n_mi[mi] = cached;
                            n_ml[LINEW*fm +: LINEW] = line;
                            fill_req_valid[lane] = 1'b1;
                            fill_req_line[LINEW*lane +: LINEW] = line;
                            fill_req_mshr[MW*lane +: MW] = mi;
                            lane = lane + 1;
                            ok = 1'b1;
                            inc_fill = inc_fill + 1;
                            if (cached) inc_miss = inc_miss + 1;
                        end
                    end
                    if (ok) begin
                        if (!cached) inc_unc = inc_unc + 1;
                        ev_wait[e_rq] = 1'b1;
                        ev_m[MW*e_rq +: MW] = mi;
                        if (is_mq) mpops = mpops + 1;
                        else bpos[32*j +: 32] = bpos[32*j +: 32] + 1;
                    end else if (is_mq) begin
                        mstop = 1'b1;
                    end else if (n_mn != MQ_SIZE) begin  // (never above MISS_QUEUE)
                        // Hit under miss: the miss leaves its bank's pipeline.
                        n_mq[EW*n_mn +: EW] = e;
                        n_mn = n_mn + 1'b1;
                        bpos[32*j +: 32] = bpos[32*j +: 32] + 1;
                    end else begin
                        // Miss queue full: the bank stalls until a fill completes.
                        bstop[j] = 1'b1;
                    end
                end
            end
        end

        // The lookups taken leave their bank queues.
        for (j = 0; j < BANKS; j = j + 1) begin
            if (bpos[32*j +: 32] != 0) begin
                b = (j + rot_q) % BANKS;
                bqt = n_bq[BQ*EW*b +: BQ*EW] >> (EW * bpos[32*j +: 32]);
                n_bq[BQ*EW*b +: BQ*EW] = bqt;
                n_bn[CW*b +: CW] = n_bn[CW*b +: CW] - bpos[32*j +: CW];
            end
        end

        // The fills presented now complete at the start of the next cycle: install (as most
        // recently used, over the least recently used way) and free the MSHR, in issue order.
        for (i = 0; i < FILL_LANES; i = i + 1) begin
            if (fill_valid[i]) begin
                mi = fill_mshr[MW*i +: MW];
                if (n_mi[mi]) begin
                    line = n_ml[LINEW*mi +: LINEW];
                    set_i = {{(32 - SB){1'b0}}, line[SB-1:0]};
                    base = set_i * WAYS;
                    hw = 0;
                    for (w = 0; w < WAYS; w = w + 1)
                        if (n_age[AGW*(base + w) +: AGW] == LRU_AGE) hw = w;
                    n_tag[TAGW*(base + hw) +: TAGW] = line[LINEW-1:SB];
                    n_val[base + hw] = 1'b1;
                    a = n_age[AGW*(base + hw) +: AGW];
                    for (w = 0; w < WAYS; w = w + 1)
                        if (n_age[AGW*(base + w) +: AGW] < a)
                            n_age[AGW*(base + w) +: AGW] = n_age[AGW*(base + w) +: AGW] + 1'b1;
                    n_age[AGW*(base + hw) +: AGW] = {AGW{1'b0}};
                    inst_v[i] = 1'b1;
                    inst_slot[SLW*i +: SLW] = base[SLW-1:0] + hw[SLW-1:0];
                end
                n_mv[mi] = 1'b0;
                n_mi[mi] = 1'b0;
            end
        end
    end

    // The read's 64 bits out of a line.
    function [63:0] pick(input [LBITS-1:0] ln, input is_attr, input [WB-1:0] word);
        begin
            if (is_attr) pick = ln[32 * word +: 64];
            else pick = {32'd0, ln[32 * word +: 32]};
        end
    endfunction

    // ---- Responses: per requester, the hit countdown and the fill it waits for -----------
    integer r, l;
    reg [REQUESTERS-1:0] rs_done, rs_load, rs_wait, rs_attr;
    reg [REQUESTERS*64-1:0] rs_data;
    reg [REQUESTERS*HCW-1:0] rs_hcnt;
    reg [REQUESTERS*MW-1:0] rs_m;
    reg [REQUESTERS*WB-1:0] rs_word;
    always @* begin
        r = 0;  // (loop variables, assigned on every path: no latch)
        l = 0;
        rs_done = {REQUESTERS{1'b0}};
        rs_load = {REQUESTERS{1'b0}};
        rs_data = {REQUESTERS*64{1'b0}};
        rs_hcnt = hcnt_q;
        rs_wait = ev_wait | wait_q;
        rs_attr = attr_q;
        rs_m = wm_q;
        rs_word = word_q;
        // (Skipped when nothing completes or counts down: the same result, a faster simulation.)
        if (ev_hit != 0 || ev_wait != 0 || hcnt_q != 0 || fill_valid != 0)
        for (r = 0; r < REQUESTERS; r = r + 1) begin
            if (ev_hit[r]) begin
                rs_load[r] = 1'b1;
                rs_data[64*r +: 64] = pick(data_mem[ev_slot[SLW*r +: SLW]], ev_attr[r],
                                           ev_word[WB*r +: WB]);
                if (HIT_LATENCY == 1) rs_done[r] = 1'b1;
                else rs_hcnt[HCW*r +: HCW] = HIT_LAST;
            end else if (hcnt_q[HCW*r +: HCW] != {HCW{1'b0}}) begin
                rs_hcnt[HCW*r +: HCW] = hcnt_q[HCW*r +: HCW] - 1'b1;
                if (hcnt_q[HCW*r +: HCW] == HIT_ONE) rs_done[r] = 1'b1;
            end
            if (ev_wait[r]) begin
                rs_m[MW*r +: MW] = ev_m[MW*r +: MW];
                rs_attr[r] = ev_attr[r];
                rs_word[WB*r +: WB] = ev_word[WB*r +: WB];
            end
            if (rs_wait[r])
                for (l = 0; l < FILL_LANES; l = l + 1)
                    if (fill_valid[l] && fill_mshr[MW*l +: MW] == rs_m[MW*r +: MW]) begin
                        rs_done[r] = 1'b1;
                        rs_load[r] = 1'b1;
                        rs_data[64*r +: 64] = pick(fill_data[LBITS*l +: LBITS], rs_attr[r],
                                                   rs_word[WB*r +: WB]);
                        rs_wait[r] = 1'b0;
                    end
        end
    end

    // ---- Registers ------------------------------------------------------------------------
    integer q;
    always @(posedge clk) begin
        for (q = 0; q < FILL_LANES; q = q + 1)
            if (inst_v[q]) data_mem[inst_slot[SLW*q +: SLW]] <= fill_data[LBITS*q +: LBITS];
        for (q = 0; q < REQUESTERS; q = q + 1)
            if (rs_load[q]) data_q[64*q +: 64] <= rs_data[64*q +: 64];
        if (rst) begin
            val_q <= {SW{1'b0}};
            tag_q <= {SW*TAGW{1'b0}};
            for (q = 0; q < SW; q = q + 1) age_q[AGW*q +: AGW] <= q[AGW-1:0];
            mv_q <= {MSHRS{1'b0}};
            mi_q <= {MSHRS{1'b0}};
            bn_q <= {BANKS*CW{1'b0}};
            mn_q <= {MQW{1'b0}};
            rot_q <= 32'd0;
            wait_q <= {REQUESTERS{1'b0}};
            rsp_done <= {REQUESTERS{1'b0}};
            hcnt_q <= {REQUESTERS*HCW{1'b0}};
            cnt_hits <= 32'd0;
            cnt_misses <= 32'd0;
            cnt_merged <= 32'd0;
            cnt_fills <= 32'd0;
            cnt_uncached <= 32'd0;
            cnt_replay_hits <= 32'd0;
        end else begin
            tag_q <= n_tag;
            age_q <= n_age;
            val_q <= n_val;
            mv_q <= n_mv;
            mi_q <= n_mi;
            ml_q <= n_ml;
            bq_q <= n_bq;
            bn_q <= n_bn;
            mq_q <= n_mq;
            mn_q <= n_mn;
            rot_q <= (rot_q + 32'd1) % BANKS;
            cnt_hits <= cnt_hits + inc_hit;
            cnt_misses <= cnt_misses + inc_miss;
            cnt_merged <= cnt_merged + inc_merge;
            cnt_fills <= cnt_fills + inc_fill;
            cnt_uncached <= cnt_uncached + inc_unc;
            cnt_replay_hits <= cnt_replay_hits + inc_replay;
            rsp_done <= rs_done;
            wait_q <= rs_wait;
            attr_q <= rs_attr;
            hcnt_q <= rs_hcnt;
            wm_q <= rs_m;
            word_q <= rs_word;
        end
    end
endmodule
`default_nettype wire
