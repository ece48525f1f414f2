// svo_onchip_store: the node memory's on-chip store (block RAM holding the top levels of the
// octree images) behind its crossbar: BANKS word-interleaved banks of PORTS read ports each,
// every request port (one per walker) able to reach every bank, a read that finds its bank's
// ports taken waiting for the next free one, and, with COMBINE, reads of a word already
// scheduled at its bank sharing that read. Cycle-exact with the on-chip part of the model's
// node memory (rtl_model/src/cycle/memory/onchip.rs and mod.rs "Timing semantics": a read
// arriving in cycle k is given its bank's next free port, or the scheduled read of the same
// word, and completes onchip.latency cycles after it is served), checked by
// tests/onchip_store_rtl.rs through testbench/tb/tb_onchip_store.sv.
//
// Pipeline position: between the walker pool (one request port per walker) and the walkers'
// read data, beside the cache (svo_node_cache.v), which takes the reads that are not on chip.
// Inside svo_top, which serves every node word from it (the attribute records go to its AXI4
// masters) and loads it with its DMA (m_axi_load, CTRL.LOAD).
//
// Cycle numbering: the first cycle after reset is the model's cycle 0.
//
// Request side (cycle k): req_valid[p], req_requester[p] (requester id = walker * contexts +
//   context), req_addr[p] (the word's store address: bank = addr mod BANKS, row = addr /
//   BANKS). Port p's requester ids must be below port p+1's (the pool's walker order), so port
//   order is the model's service order within a cycle (requester, then request id). No ready:
//   a read always joins its bank's schedule in the cycle it is made (the model's crossbar has
//   no cycle of its own). Each requester has at most one read outstanding (the pool's
//   property).
// Response side: rsp_done[r] is a one-cycle pulse in the model's cycle_done of requester r's
//   read (served + LATENCY); rsp_data[32r +: 32] holds the word from that cycle until the
//   requester's next completion.
// Loading: load_valid, load_addr, load_data write one word of the store a cycle (between
//   frames, as the model assumes: the store is read only during a frame; svo_top's load DMA
//   drives them, refusing a START while it runs).
//
// How a bank serves: each bank keeps its next free port as (delay from now, ports used then)
//   and a schedule of the reads it has accepted and not yet made: (delay, word), at most
//   QDEPTH of them. A read joins in the cycle it arrives; in port order, each either finds its
//   word in the schedule (COMBINE: served with it, no port) or takes the next free port,
//   moving the slot a cycle on when its PORTS are used. Every cycle the bank reads the words
//   whose delay is 0 (at most PORTS, by construction) through its RAM ports; the word leaves
//   the RAM a cycle later and passes LATENCY - 2 more registers, so it is in rsp_data in cycle
//   served + LATENCY. The schedule is what the model's per-bank queue of (served, word) is,
//   with delays instead of absolute cycles (every delay counts down at each edge; a read of
//   delay 0 is made and dropped).
//
// Counters (the model's NodeMemoryStats): cnt_reads (onchip_reads), cnt_combined
// (onchip_combined), cnt_port_wait (the on-chip share of port_wait: cycles reads waited for a
// port). err is set, and stays set, when a bank's schedule overflows QDEPTH (a protocol error:
// QDEPTH >= the requesters that can read one bank is enough).
`timescale 1ns/1ps
`default_nettype none
module svo_onchip_store #(
    parameter REQ_PORTS  = 2,    // walkers
    parameter REQUESTERS = 8,    // contexts in all (>= 2)
    parameter BANKS      = 16,   // onchip.banks, a power of two
    parameter PORTS      = 2,    // onchip.ports_per_bank (1 or 2: a block RAM's ports)
    parameter LATENCY    = 3,    // onchip.latency (>= 2: the RAM's output register and more)
    parameter COMBINE    = 1,    // onchip.combine
    parameter WORDS      = 4096, // store words, a multiple of BANKS
    parameter QDEPTH     = 8     // schedule entries per bank
) (
    input  wire                                    clk,
    input  wire                                    rst,
    input  wire                                    load_valid,
    input  wire [31:0]                             load_addr,
    input  wire [31:0]                             load_data,
    input  wire [REQ_PORTS-1:0]                    req_valid,
    input  wire [REQ_PORTS*$clog2(REQUESTERS)-1:0] req_requester,
    input  wire [REQ_PORTS*32-1:0]                 req_addr,
    output reg  [REQUESTERS-1:0]                   rsp_done,
    output reg  [REQUESTERS*32-1:0]                rsp_data,
    output reg  [31:0]                             cnt_reads,
    output reg  [31:0]                             cnt_combined,
    output reg  [31:0]                             cnt_port_wait,
    output reg                                     err
);
    localparam integer RQW = $clog2(REQUESTERS);
    localparam integer SH = $clog2(BANKS);              // bank bits of an address
    localparam integer BW = BANKS > 1 ? SH : 1;
    localparam integer ROWS = WORDS / BANKS;
    localparam integer RW = ROWS > 1 ? $clog2(ROWS) : 1;
    // A read waits at most for every other requester's read of its bank: delays below
    // REQUESTERS / PORTS + 1; the requester's count to its completion adds LATENCY.
    localparam integer DW = $clog2(REQUESTERS + 2);
    localparam integer CW = $clog2(REQUESTERS + LATENCY + 2);

    generate
        if (REQUESTERS < 2 || BANKS < 1 || (BANKS & (BANKS - 1)) != 0 || PORTS < 1 || PORTS > 2
            || LATENCY < 2 || WORDS % BANKS != 0 || QDEPTH < 1) begin : bad_params
            svo_onchip_store_parameters_out_of_range bad();
        end
    endgenerate

    // ---- State: per bank, the next free port and the schedule ------------------------------
    reg [BANKS-1:0]          slot_past;    // the slot is behind the current cycle (idle bank)
    reg [BANKS*DW-1:0]       slot_del;     // its delay from the current cycle
    reg [BANKS*2-1:0]        slot_used;    // ports taken in it
    reg [BANKS*QDEPTH-1:0]   q_valid;
    reg [BANKS*QDEPTH*DW-1:0] q_del;
    reg [BANKS*QDEPTH*32-1:0] q_word;
    // Per requester: cycles to its completion (0: none pending) and its word.
    reg [REQUESTERS*CW-1:0]  r_rem;
    reg [REQUESTERS*32-1:0]  r_word;

    // ---- This cycle's arrivals, in port order (the model's step 2 for on-chip reads) -------
    // Each bank's arbiter sees the ports in order and takes those of its bank: its slot and
    // schedule after them, and per port the delay to its service and whether it combined.
    wire [BANKS-1:0]           n_slot_past;
    wire [BANKS*DW-1:0]        n_slot_del;
    wire [BANKS*2-1:0]         n_slot_used;
    wire [BANKS*QDEPTH-1:0]    n_q_valid;
    wire [BANKS*QDEPTH*DW-1:0] n_q_del;
    wire [BANKS*QDEPTH*32-1:0] n_q_word;
    wire [BANKS*REQ_PORTS*DW-1:0] b_del;   // per bank, per port (0 for other banks' ports)
    wire [BANKS*REQ_PORTS-1:0]    b_comb;
    wire [BANKS-1:0]              b_err;
    genvar ga;
    generate
        for (ga = 0; ga < BANKS; ga = ga + 1) begin : arb
            reg             sp;
            reg [DW-1:0]    sd;
            reg [1:0]       su;
            reg [QDEPTH-1:0]    qv;
            reg [QDEPTH*DW-1:0] qd;
            reg [QDEPTH*32-1:0] qw;
            reg [REQ_PORTS*DW-1:0] pd;
            reg [REQ_PORTS-1:0]    pc;
            reg er, found, placed;
            reg [DW-1:0] d;
            reg [31:0] aw;
            integer p, e;
            always @(*) begin
                sp = slot_past[ga];
                sd = slot_del[ga*DW +: DW];
                su = slot_used[ga*2 +: 2];
                qv = q_valid[ga*QDEPTH +: QDEPTH];
                qd = q_del[ga*QDEPTH*DW +: QDEPTH*DW];
                qw = q_word[ga*QDEPTH*32 +: QDEPTH*32];
                pd = {REQ_PORTS*DW{1'b0}};
                pc = {REQ_PORTS{1'b0}};
                er = 1'b0;
                found = 1'b0;
                placed = 1'b0;
                d = {DW{1'b0}};
                aw = 32'd0;
                for (p = 0; p < REQ_PORTS; p = p + 1) begin
                    aw = req_addr[32*p +: 32];
                    if (req_valid[p] && (BANKS == 1 || aw[BW-1:0] == ga)) begin
                        found = 1'b0;
                        d = {DW{1'b0}};
                        if (COMBINE != 0)
                            for (e = 0; e < QDEPTH; e = e + 1)
                                if (!found && qv[e] && qw[32*e +: 32] == aw) begin
                                    found = 1'b1;
                                    d = qd[DW*e +: DW];
                                end
                        if (!found) begin
                            if (sp) begin
                                sp = 1'b0;
                                sd = {DW{1'b0}};
                                su = 2'd0;
                            end
                            d = sd;
                            if (su + 2'd1 == PORTS[1:0]) begin
                                sd = d + 1'b1;
                                su = 2'd0;
                            end else begin
                                su = su + 2'd1;
                            end
                            placed = 1'b0;
                            for (e = 0; e < QDEPTH; e = e + 1)
                                if (!placed && !qv[e]) begin
                                    placed = 1'b1;
                                    qv[e] = 1'b1;
                                    qd[DW*e +: DW] = d;
                                    qw[32*e +: 32] = aw;
                                end
                            if (!placed) er = 1'b1;
                        end
                        pd[DW*p +: DW] = d;
                        pc[p] = found;
                    end
                end
            end
            assign n_slot_past[ga] = sp;
            assign n_slot_del[ga*DW +: DW] = sd;
            assign n_slot_used[ga*2 +: 2] = su;
            assign n_q_valid[ga*QDEPTH +: QDEPTH] = qv;
            assign n_q_del[ga*QDEPTH*DW +: QDEPTH*DW] = qd;
            assign n_q_word[ga*QDEPTH*32 +: QDEPTH*32] = qw;
            assign b_del[ga*REQ_PORTS*DW +: REQ_PORTS*DW] = pd;
            assign b_comb[ga*REQ_PORTS +: REQ_PORTS] = pc;
            assign b_err[ga] = er;
        end
    endgenerate
    // Every port's delay and combining, from the bank it went to.
    reg [REQ_PORTS*DW-1:0] a_del;
    reg [REQ_PORTS-1:0]    a_comb;
    wire                   a_err = |b_err;
    integer b, e, p;
    always @(*) begin
        a_del = {REQ_PORTS*DW{1'b0}};
        a_comb = {REQ_PORTS{1'b0}};
        for (b = 0; b < BANKS; b = b + 1) begin
            a_del = a_del | b_del[b*REQ_PORTS*DW +: REQ_PORTS*DW];
            a_comb = a_comb | b_comb[b*REQ_PORTS +: REQ_PORTS];
        end
    end

    // ---- The reads made this cycle: per bank, the scheduled words of delay 0 ---------------
    // Lane j of a bank takes the j-th due entry (a priority pick over the schedule; every index
    // constant after unrolling, so each lane is a QDEPTH:1 multiplexer).
    reg [BANKS*PORTS-1:0]    rd_valid;
    reg [BANKS*PORTS*32-1:0] rd_word;
    reg [QDEPTH-1:0] due;
    reg taken;
    integer k;
    always @(*) begin
        rd_valid = {BANKS*PORTS{1'b0}};
        rd_word = {BANKS*PORTS*32{1'b0}};
        due = {QDEPTH{1'b0}};
        taken = 1'b0;
        for (b = 0; b < BANKS; b = b + 1) begin
            for (e = 0; e < QDEPTH; e = e + 1)
                due[e] = n_q_valid[b*QDEPTH + e] && n_q_del[(b*QDEPTH + e)*DW +: DW] == {DW{1'b0}};
            for (k = 0; k < PORTS; k = k + 1) begin
                taken = 1'b0;
                for (e = 0; e < QDEPTH; e = e + 1)
                    if (!taken && due[e]) begin
                        taken = 1'b1;
                        due[e] = 1'b0;
                        rd_valid[b*PORTS + k] = 1'b1;
                        rd_word[(b*PORTS + k)*32 +: 32] = n_q_word[(b*QDEPTH + e)*32 +: 32];
                    end
            end
        end
    end

    // ---- The banks' RAMs and their output pipelines ----------------------------------------
    // Stage j (1 .. LATENCY-1) holds, per bank and port, the read made j cycles ago: lane
    // (bank, port) of stage j at [(j*BP + bank*PORTS + port)] (valid) and the 32-bit words
    // (word address, data) at the same index times 32.
    localparam integer BP = BANKS * PORTS;
    wire [LATENCY*BP-1:0]    st_valid;
    wire [LATENCY*BP*32-1:0] st_word;
    wire [LATENCY*BP*32-1:0] st_data;
    assign st_valid[BP-1:0] = {BP{1'b0}};      // stage 0 is not used
    assign st_word[BP*32-1:0] = {BP*32{1'b0}};
    assign st_data[BP*32-1:0] = {BP*32{1'b0}};
    genvar gb, gp, gs;
    generate
        for (gb = 0; gb < BANKS; gb = gb + 1) begin : bank
            reg [31:0] mem [0:ROWS-1];
            /* verilator lint_off UNUSEDSIGNAL */
            wire [31:0] load_row = load_addr >> SH;     // rows above ROWS are not stored
            /* verilator lint_on UNUSEDSIGNAL */
            for (gp = 0; gp < PORTS; gp = gp + 1) begin : port
                reg [31:0] q;
                reg v;
                reg [31:0] w;
                /* verilator lint_off UNUSEDSIGNAL */
                wire [31:0] row = rd_word[(gb*PORTS + gp)*32 +: 32] >> SH;
                /* verilator lint_on UNUSEDSIGNAL */
                if (gp == 0) begin : rw
                    // Port 0 also loads the store (between frames).
                    always @(posedge clk) begin
                        if (load_valid && (BANKS == 1 || load_addr[BW-1:0] == gb))
                            mem[load_row[RW-1:0]] <= load_data;
                        q <= mem[row[RW-1:0]];
                    end
                end else begin : ro
                    always @(posedge clk) q <= mem[row[RW-1:0]];
                end
                always @(posedge clk) begin
                    v <= !rst && rd_valid[gb*PORTS + gp];
                    w <= rd_word[(gb*PORTS + gp)*32 +: 32];
                end
                assign st_valid[BP + gb*PORTS + gp] = v;
                assign st_word[(BP + gb*PORTS + gp)*32 +: 32] = w;
                assign st_data[(BP + gb*PORTS + gp)*32 +: 32] = q;
            end
        end
        for (gs = 2; gs < LATENCY; gs = gs + 1) begin : stage
            reg [BP-1:0]    v;
            reg [BP*32-1:0] w, q;
            always @(posedge clk) begin
                v <= rst ? {BP{1'b0}} : st_valid[(gs-1)*BP +: BP];
                w <= st_word[(gs-1)*BP*32 +: BP*32];
                q <= st_data[(gs-1)*BP*32 +: BP*32];
            end
            assign st_valid[gs*BP +: BP] = v;
            assign st_word[gs*BP*32 +: BP*32] = w;
            assign st_data[gs*BP*32 +: BP*32] = q;
        end
    endgenerate

    // ---- Completions: the requester's word from its bank's last stage ----------------------
    localparam integer LAST = (LATENCY - 1) * BP;
    localparam [CW-1:0] ONE = 1;
    localparam integer LM1 = LATENCY - 1;
    localparam [CW-1:0] TO_DONE = LM1[CW-1:0];
    reg [REQUESTERS*32-1:0] r_data;
    integer r, j;
    always @(*) begin
        r_data = {REQUESTERS*32{1'b0}};
        for (r = 0; r < REQUESTERS; r = r + 1)
            for (b = 0; b < BANKS; b = b + 1)
                if (BANKS == 1 || r_word[32*r +: BW] == b[BW-1:0])
                    for (j = 0; j < PORTS; j = j + 1)
                        if (st_valid[LAST + b*PORTS + j]
                            && st_word[(LAST + b*PORTS + j)*32 +: 32] == r_word[32*r +: 32])
                            r_data[32*r +: 32] = st_data[(LAST + b*PORTS + j)*32 +: 32];
    end

    // ---- The edge: schedules count down, arrivals are recorded, completions pulse ----------
    integer n, c;
    reg [31:0] waited;
    always @(*) begin
        waited = 32'd0;
        n = 0;
        c = 0;
        for (p = 0; p < REQ_PORTS; p = p + 1)
            if (req_valid[p]) begin
                waited = waited + {{(32-DW){1'b0}}, a_del[p*DW +: DW]};
                n = n + 1;
                c = c + (a_comb[p] ? 1 : 0);
            end
    end
    always @(posedge clk) begin
        if (rst) begin
            slot_past <= {BANKS{1'b1}};
            slot_del <= {BANKS*DW{1'b0}};
            slot_used <= {BANKS*2{1'b0}};
            q_valid <= {BANKS*QDEPTH{1'b0}};
            q_del <= {BANKS*QDEPTH*DW{1'b0}};
            q_word <= {BANKS*QDEPTH*32{1'b0}};
            r_rem <= {REQUESTERS*CW{1'b0}};
            r_word <= {REQUESTERS*32{1'b0}};
            rsp_done <= {REQUESTERS{1'b0}};
            rsp_data <= {REQUESTERS*32{1'b0}};
            cnt_reads <= 32'd0;
            cnt_combined <= 32'd0;
            cnt_port_wait <= 32'd0;
            err <= 1'b0;
        end else begin
            // The slot of delay 0 is this cycle's: next cycle it is behind.
            for (b = 0; b < BANKS; b = b + 1) begin
                if (n_slot_past[b] || n_slot_del[b*DW +: DW] == {DW{1'b0}}) begin
                    slot_past[b] <= 1'b1;
                    slot_del[b*DW +: DW] <= {DW{1'b0}};
                    slot_used[b*2 +: 2] <= 2'd0;
                end else begin
                    slot_past[b] <= 1'b0;
                    slot_del[b*DW +: DW] <= n_slot_del[b*DW +: DW] - 1'b1;
                    slot_used[b*2 +: 2] <= n_slot_used[b*2 +: 2];
                end
                for (e = 0; e < QDEPTH; e = e + 1) begin
                    // A read of delay 0 is made this cycle and leaves the schedule.
                    q_valid[b*QDEPTH + e] <= n_q_valid[b*QDEPTH + e]
                        && n_q_del[(b*QDEPTH + e)*DW +: DW] != {DW{1'b0}};
                    q_del[(b*QDEPTH + e)*DW +: DW] <= n_q_del[(b*QDEPTH + e)*DW +: DW] - 1'b1;
                    q_word[(b*QDEPTH + e)*32 +: 32] <= n_q_word[(b*QDEPTH + e)*32 +: 32];
                end
            end
            for (r = 0; r < REQUESTERS; r = r + 1) begin
                rsp_done[r] <= r_rem[r*CW +: CW] == ONE;
                if (r_rem[r*CW +: CW] == ONE) rsp_data[32*r +: 32] <= r_data[32*r +: 32];
                if (r_rem[r*CW +: CW] != {CW{1'b0}}) r_rem[r*CW +: CW] <= r_rem[r*CW +: CW] - 1'b1;
            end
            // Arrivals: done = served + LATENCY, i.e. LATENCY + delay cycles from now.
            for (r = 0; r < REQUESTERS; r = r + 1)
                for (p = 0; p < REQ_PORTS; p = p + 1)
                    if (req_valid[p] && req_requester[p*RQW +: RQW] == r[RQW-1:0]) begin
                        r_rem[r*CW +: CW] <= {{(CW-DW){1'b0}}, a_del[p*DW +: DW]} + TO_DONE;
                        r_word[32*r +: 32] <= req_addr[32*p +: 32];
                    end
            cnt_reads <= cnt_reads + n[31:0];
            cnt_combined <= cnt_combined + c[31:0];
            cnt_port_wait <= cnt_port_wait + waited;
            if (a_err) err <= 1'b1;
        end
    end
endmodule
`default_nettype wire
