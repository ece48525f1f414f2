// tb_onchip_store: svo_onchip_store against a recorded request trace, open loop. Driven by
// tests/onchip_store_rtl.rs, which records the trace from the model's NodeMemory (every node
// word on chip, closed loop) and compares this bench's log with the model's completions and
// counters.
//
// The store is loaded first (one word a cycle, during reset's hold: the frame's cycle 0 is
// the first after it) with word a = store_word(a), the function the Rust side computes again.
// +trace=FILE: lines "cycle requester addr" (decimal), ordered by cycle then requester.
// Requester r drives port r / CTX. The bench flags (line "E ...") a request of a requester
// whose read is still outstanding, two requests on one port in a cycle, a completion of a
// requester with nothing outstanding and the store's schedule overflow.
// +log=FILE: one line "D cycle_requested cycle_done requester data(hex)" per completion, then
// "C reads combined port_wait" and "END cycle errors".
`timescale 1ns/1ps
module tb_onchip_store;
    parameter REQ_PORTS = 2;
    parameter CTX = 4;
    parameter BANKS = 16;
    parameter PORTS = 2;
    parameter LATENCY = 3;
    parameter COMBINE = 1;
    parameter WORDS = 4096;
    parameter MAX_CYCLES = 1000000;
    localparam integer REQUESTERS = REQ_PORTS * CTX;
    localparam integer RQW = $clog2(REQUESTERS);

    reg clk = 1'b0;
    reg rst = 1'b1;
    always #5 clk = ~clk;
    reg [63:0] cyc = 64'd0;

    function [31:0] store_word(input [31:0] a);
        store_word = (a * 32'h9E37_79B1) ^ 32'h5A5A_0F0F;
    endfunction

    reg                      load_valid = 1'b0;
    reg  [31:0]              load_addr = 0, load_data = 0;
    reg  [REQ_PORTS-1:0]     req_valid = 0;
    reg  [REQ_PORTS*RQW-1:0] req_requester = 0;
    reg  [REQ_PORTS*32-1:0]  req_addr = 0;
    wire [REQUESTERS-1:0]    rsp_done;
    wire [REQUESTERS*32-1:0] rsp_data;
    wire [31:0] c_reads, c_combined, c_wait;
    wire overflow;

    svo_onchip_store #(
        .REQ_PORTS(REQ_PORTS), .REQUESTERS(REQUESTERS), .BANKS(BANKS), .PORTS(PORTS),
        .LATENCY(LATENCY), .COMBINE(COMBINE), .WORDS(WORDS), .QDEPTH(REQUESTERS)
    ) dut (
        .clk(clk), .rst(rst), .load_valid(load_valid), .load_addr(load_addr),
        .load_data(load_data), .req_valid(req_valid), .req_requester(req_requester),
        .req_addr(req_addr), .rsp_done(rsp_done), .rsp_data(rsp_data), .cnt_reads(c_reads),
        .cnt_combined(c_combined), .cnt_port_wait(c_wait), .err(overflow)
    );

    reg [1023:0] trace_name, log_name;
    integer fd, fo, rc, port, r, errors, a;
    reg have, finished;
    reg [63:0] t_cyc;
    integer t_rq;
    reg [31:0] t_addr;
    reg [REQUESTERS-1:0] outstanding;
    reg [63:0] req_cycle [0:REQUESTERS-1];

    task next_line;
        begin
            rc = $fscanf(fd, "%d %d %d\n", t_cyc, t_rq, t_addr);
            have = rc == 3;
        end
    endtask

    initial begin
        if (!$value$plusargs("trace=%s", trace_name) || !$value$plusargs("log=%s", log_name)) begin
            $display("E usage: +trace=FILE +log=FILE");
            $finish;
        end
        fd = $fopen(trace_name, "r");
        fo = $fopen(log_name, "w");
        if (fd == 0 || fo == 0) begin
            $display("E cannot open the trace or the log");
            $finish;
        end
        errors = 0;
        outstanding = 0;
        finished = 1'b0;
        next_line;
        // Load the store while the schedule is held in reset.
        for (a = 0; a < WORDS; a = a + 1) begin
            @(negedge clk);
            load_valid = 1'b1;
            load_addr = a;
            load_data = store_word(a);
        end
        @(negedge clk);
        load_valid = 1'b0;
        rst = 1'b0;
        while (!finished) begin
            // Cycle cyc, between its edges: the completions of this cycle, then its requests.
            for (r = 0; r < REQUESTERS; r = r + 1)
                if (rsp_done[r]) begin
                    if (!outstanding[r]) begin
                        $fdisplay(fo, "E cycle %0d: completion for requester %0d with no read outstanding", cyc, r);
                        errors = errors + 1;
                    end
                    $fdisplay(fo, "D %0d %0d %0d %h", req_cycle[r], cyc, r, rsp_data[32*r +: 32]);
                    outstanding[r] = 1'b0;
                end
            req_valid = 0;
            while (have && t_cyc == cyc) begin
                port = t_rq / CTX;
                if (req_valid[port]) begin
                    $fdisplay(fo, "E cycle %0d: two requests on port %0d", cyc, port);
                    errors = errors + 1;
                end
                if (outstanding[t_rq]) begin
                    $fdisplay(fo, "E cycle %0d: request of requester %0d, whose read of cycle %0d is outstanding", cyc, t_rq, req_cycle[t_rq]);
                    errors = errors + 1;
                end
                req_valid[port] = 1'b1;
                req_requester[RQW*port +: RQW] = t_rq[RQW-1:0];
                req_addr[32*port +: 32] = t_addr;
                outstanding[t_rq] = 1'b1;
                req_cycle[t_rq] = cyc;
                next_line;
            end
            if (have && t_cyc < cyc) begin
                $fdisplay(fo, "E trace out of order at cycle %0d", t_cyc);
                errors = errors + 1;
                next_line;
            end
            if (overflow) begin
                $fdisplay(fo, "E cycle %0d: a bank's schedule overflowed", cyc);
                errors = errors + 1;
                finished = 1'b1;
            end else if ((!have && outstanding == 0) || cyc >= MAX_CYCLES) finished = 1'b1;
            else begin
                @(negedge clk);
                cyc = cyc + 1;
            end
        end
        $fdisplay(fo, "C %0d %0d %0d", c_reads, c_combined, c_wait);
        $fdisplay(fo, "END %0d %0d", cyc, errors);
        $fclose(fo);
        $finish;
    end
endmodule
