// tb_node_cache_axi: svo_node_cache_axi (the node cache on AXI4 read ports) against a recorded
// request trace, with tb_axi_dram.sv as the memory (the built-in DRAM bus of dram.rs on AXI).
// Driven by tests/node_cache_axi_rtl.rs, which records the trace from the model's NodeMemory
// and compares this bench's log with the model's completions and counters. The log and trace
// formats are tb_node_cache.sv's (tests/common/mem_bench.rs reads both).
//
// +trace=FILE, +log=FILE: the trace, its run (exact or elastic) and the log's "D" and "E"
// lines are tb_cache_trace.svh's (shared with tb_node_cache.sv); then
//   "C hits misses merged fills uncached replay_hits ar_queued ar_stalls r_stalls axi_error"
//   and "END cycle errors". ar_queued: fills whose AR was taken later than the cycle after
//   their issue (coverage of the AR queues); ar_stalls / r_stalls: the slave's pauses.
// Exact mode (default): requests at their recorded cycles; "E ..." also for fill lanes out of
//   issue order. +elastic: the elastic run (for the stall run, whose cycles are the slave's).
//   +pause_ar=PCT +pause_r=PCT +seed=N: the slave's pauses. +slverr=N: the
//   N-th fill (from 0) answers SLVERR.
`timescale 1ns/1ps
module tb_node_cache_axi;
    parameter REQ_PORTS = 2;
    parameter CTX = 4;
    parameter BANKS = 4;
    parameter PORTS = 2;
    parameter SETS = 16;
    parameter WAYS = 4;
    parameter LINE_BYTES = 64;
    parameter HIT_LATENCY = 4;
    parameter MSHRS = 8;
    parameter MISS_QUEUE = 32;
    parameter ATTR_CACHED = 1;
    parameter DRAM_LATENCY = 60;
    parameter BYTES_PER_CYCLE = 128;
    parameter MAX_CYCLES = 1000000;
    localparam integer REQUESTERS = REQ_PORTS * CTX;
    localparam integer RQW = $clog2(REQUESTERS);
    localparam integer MW = $clog2(MSHRS);
    localparam integer F = (BYTES_PER_CYCLE + LINE_BYTES - 1) / LINE_BYTES;
    localparam integer SLOTS = MISS_QUEUE + BANKS * PORTS;
    localparam integer ISSUE_LANES = MSHRS < SLOTS ? MSHRS : SLOTS;
    localparam integer LBITS = LINE_BYTES * 8;

    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;
    reg [63:0] cyc = 64'd0;

    reg  [REQ_PORTS-1:0]     req_valid = 0;
    reg  [REQ_PORTS*RQW-1:0] req_requester = 0;
    reg  [REQ_PORTS*2-1:0]   req_kind = 0;
    reg  [REQ_PORTS*32-1:0]  req_addr = 0;
    wire [REQUESTERS-1:0]    rsp_done;
    wire [REQUESTERS*64-1:0] rsp_data;
    wire [F-1:0] arvalid, arready, rvalid, rready, rlast;
    wire [F*MW-1:0] arid, rid;
    wire [F*41-1:0] araddr;
    wire [F*8-1:0] arlen;
    wire [F*3-1:0] arsize;
    wire [F*2-1:0] arburst, rresp;
    wire [F*LBITS-1:0] rdata;
    wire axi_error;
    wire [31:0] c_hits, c_misses, c_merged, c_fills, c_unc, c_replay, dram_errors;
    wire [31:0] ar_stalls, r_stalls;
    wire dram_idle;
    reg [31:0] pause_ar = 0, pause_r = 0, seed = 1, slverr = 32'hFFFF_FFFF;

    svo_node_cache_axi #(
        .REQ_PORTS(REQ_PORTS), .REQUESTERS(REQUESTERS), .BANKS(BANKS), .PORTS(PORTS),
        .SETS(SETS), .WAYS(WAYS), .LINE_BYTES(LINE_BYTES), .HIT_LATENCY(HIT_LATENCY),
        .MSHRS(MSHRS), .MISS_QUEUE(MISS_QUEUE), .ATTR_CACHED(ATTR_CACHED),
        .FILL_LANES(F), .ISSUE_LANES(ISSUE_LANES)
    ) dut (
        .clk(clk), .rst(rst), .req_valid(req_valid), .req_requester(req_requester),
        .req_kind(req_kind), .req_addr(req_addr), .rsp_done(rsp_done), .rsp_data(rsp_data),
        .m_arvalid(arvalid), .m_arready(arready), .m_arid(arid), .m_araddr(araddr),
        .m_arlen(arlen), .m_arsize(arsize), .m_arburst(arburst), .m_rvalid(rvalid),
        .m_rready(rready), .m_rid(rid), .m_rdata(rdata), .m_rresp(rresp), .m_rlast(rlast),
        .axi_error(axi_error),
        .cnt_hits(c_hits), .cnt_misses(c_misses), .cnt_merged(c_merged), .cnt_fills(c_fills),
        .cnt_uncached(c_unc), .cnt_replay_hits(c_replay)
    );

    tb_axi_dram #(
        .LINE_BYTES(LINE_BYTES), .LATENCY(DRAM_LATENCY), .BYTES_PER_CYCLE(BYTES_PER_CYCLE),
        .PORTS(F), .MW(MW)
    ) dram (
        .clk(clk), .rst(rst), .cycle(cyc), .pause_ar(pause_ar), .pause_r(pause_r),
        .seed(seed), .slverr_fill(slverr),
        .s_arvalid(arvalid), .s_arready(arready), .s_arid(arid), .s_araddr(araddr),
        .s_arlen(arlen), .s_arsize(arsize), .s_arburst(arburst), .s_rvalid(rvalid),
        .s_rready(rready), .s_rid(rid), .s_rdata(rdata), .s_rresp(rresp), .s_rlast(rlast),
        .idle(dram_idle), .errors(dram_errors), .ar_stalls(ar_stalls), .r_stalls(r_stalls)
    );

    // Coverage: fills whose AR was taken later than the cycle after their issue (queued behind
    // other fills or paused), matched in issue order. Check (exact mode): the fill lanes the
    // cache sees carry the fills in issue order (the slave keeps it, so the wrapper must: the
    // order decides the LRU victims of two fills of one set in one cycle); "E ..." when not.
    // Not in the stall run: pauses per R port reorder the fills across ports (AXI allows it
    // across IDs), which the wrapper must survive with the right data. Sampled before the
    // edge's updates.
    reg [63:0]   iss_cyc [0:65535];
    reg [MW-1:0] iss_m   [0:65535];
    integer ih = 0, fh = 0, it = 0, ar_queued = 0, order_errors = 0, x;
    always @(posedge clk) begin
        if (!rst) begin
            for (x = 0; x < F; x = x + 1)
                if (arvalid[x] && arready[x]) begin
                    if (cyc > iss_cyc[ih % 65536] + 1) ar_queued = ar_queued + 1;
                    ih = ih + 1;
                end
            for (x = 0; x < F; x = x + 1)
                if (dut.fv_q[x]) begin
                    if (!elastic && dut.fm_q[MW*x +: MW] != iss_m[fh % 65536]) begin
                        $fdisplay(fo, "E cycle %0d: fill lane %0d carries MSHR %0d, the next fill in issue order has MSHR %0d",
                                  cyc, x, dut.fm_q[MW*x +: MW], iss_m[fh % 65536]);
                        order_errors = order_errors + 1;
                    end
                    fh = fh + 1;
                end
            for (x = 0; x < ISSUE_LANES; x = x + 1)
                if (dut.iss_valid[x]) begin
                    iss_cyc[it % 65536] = cyc;
                    iss_m[it % 65536] = dut.iss_mshr[MW*x +: MW];
                    it = it + 1;
                end
        end
    end

    reg elastic;
    `include "tb_cache_trace.svh"

    initial begin
        elastic = $test$plusargs("elastic");
        if ($value$plusargs("pause_ar=%d", pause_ar)) ;
        if ($value$plusargs("pause_r=%d", pause_r)) ;
        if ($value$plusargs("seed=%d", seed)) ;
        if ($value$plusargs("slverr=%d", slverr)) ;
        open_files;
        run_trace(elastic);
        $fdisplay(fo, "C %0d %0d %0d %0d %0d %0d %0d %0d %0d %0d", c_hits, c_misses, c_merged,
                  c_fills, c_unc, c_replay, ar_queued, ar_stalls, r_stalls, axi_error);
        $fdisplay(fo, "END %0d %0d", cyc, errors + order_errors + dram_errors);
        $fclose(fo);
        $finish;
    end
endmodule
