// tb_node_cache: svo_node_cache against a recorded request trace, open loop, with the built-in
// DRAM timing (tb_dram_model.sv). Driven by tests/node_cache_rtl.rs, which records the trace
// from the model's NodeMemory (closed loop) and compares this bench's log with the model's
// completions and counters.
//
// +trace=FILE, +log=FILE: the trace, its exact (open-loop) run and the log's "D" and "E" lines
// are tb_cache_trace.svh's (shared with tb_node_cache_axi.sv); after them the log has
// "C hits misses merged fills uncached replay_hits" and "END cycle errors".
`timescale 1ns/1ps
module tb_node_cache;
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
    localparam integer LINEW = 41 - $clog2(LINE_BYTES);
    localparam integer FILL_LANES = (BYTES_PER_CYCLE + LINE_BYTES - 1) / LINE_BYTES;
    localparam integer SLOTS = MISS_QUEUE + BANKS * PORTS;
    localparam integer ISSUE_LANES = MSHRS < SLOTS ? MSHRS : SLOTS;

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
    wire [ISSUE_LANES-1:0]   iss_valid;
    wire [ISSUE_LANES*LINEW-1:0] iss_line;
    wire [ISSUE_LANES*MW-1:0] iss_mshr;
    wire [FILL_LANES-1:0]    fill_valid;
    wire [FILL_LANES*MW-1:0] fill_mshr;
    wire [FILL_LANES*LINE_BYTES*8-1:0] fill_data;
    wire [31:0] c_hits, c_misses, c_merged, c_fills, c_unc, c_replay, dram_errors;
    wire dram_idle;

    svo_node_cache #(
        .REQ_PORTS(REQ_PORTS), .REQUESTERS(REQUESTERS), .BANKS(BANKS), .PORTS(PORTS),
        .SETS(SETS), .WAYS(WAYS), .LINE_BYTES(LINE_BYTES), .HIT_LATENCY(HIT_LATENCY),
        .MSHRS(MSHRS), .MISS_QUEUE(MISS_QUEUE), .ATTR_CACHED(ATTR_CACHED),
        .FILL_LANES(FILL_LANES), .ISSUE_LANES(ISSUE_LANES)
    ) dut (
        .clk(clk), .rst(rst), .req_valid(req_valid), .req_requester(req_requester),
        .req_kind(req_kind), .req_addr(req_addr), .rsp_done(rsp_done), .rsp_data(rsp_data),
        .fill_req_valid(iss_valid), .fill_req_line(iss_line), .fill_req_mshr(iss_mshr),
        .fill_valid(fill_valid), .fill_mshr(fill_mshr), .fill_data(fill_data),
        .cnt_hits(c_hits), .cnt_misses(c_misses), .cnt_merged(c_merged), .cnt_fills(c_fills),
        .cnt_uncached(c_unc), .cnt_replay_hits(c_replay)
    );

    tb_dram_model #(
        .LINE_BYTES(LINE_BYTES), .LATENCY(DRAM_LATENCY), .BYTES_PER_CYCLE(BYTES_PER_CYCLE),
        .ISSUE_LANES(ISSUE_LANES), .FILL_LANES(FILL_LANES), .MW(MW)
    ) dram (
        .clk(clk), .rst(rst), .cycle(cyc), .req_valid(iss_valid), .req_line(iss_line),
        .req_mshr(iss_mshr), .fill_valid(fill_valid), .fill_mshr(fill_mshr),
        .fill_data(fill_data), .idle(dram_idle), .errors(dram_errors)
    );

    `include "tb_cache_trace.svh"

    initial begin
        open_files;
        run_trace(1'b0);
        $fdisplay(fo, "C %0d %0d %0d %0d %0d %0d", c_hits, c_misses, c_merged, c_fills, c_unc, c_replay);
        $fdisplay(fo, "END %0d %0d", cyc, errors + dram_errors);
        $fclose(fo);
        $finish;
    end
endmodule
