// tb_dram_model: the built-in DRAM timing of rtl_model/src/cycle/memory/dram.rs (struct Bus)
// behind svo_node_cache's fill side, for testbenches only. A fill issued in cycle k may start
// to transfer at byte slot (k + LATENCY) * BYTES_PER_CYCLE, transfers after the fills issued
// before it (one bus, issue order), occupies LINE_BYTES slots, and completes in cycle
// ceil(end / BYTES_PER_CYCLE); it is presented on a fill lane one cycle before that (the
// cache's convention, svo_node_cache.v header). The line's data is a fixed function of the
// byte address (word at byte A: A[31:0] * 0x9E3779B1 ^ A[40:32] * 0x85EBCA77, mod 2^32), so
// the bench's reader can check every word returned.
`timescale 1ns/1ps
module tb_dram_model #(
    parameter LINE_BYTES      = 64,
    parameter LATENCY         = 60,
    parameter BYTES_PER_CYCLE = 128,
    parameter ISSUE_LANES     = 8,
    parameter FILL_LANES      = 2,
    parameter MW              = 3,
    parameter DEPTH           = 8192
) (
    input  wire                                       clk,
    input  wire                                       rst,
    input  wire [63:0]                                cycle,     // the cycle ending at this edge
    input  wire [ISSUE_LANES-1:0]                     req_valid,
    input  wire [ISSUE_LANES*(41-$clog2(LINE_BYTES))-1:0] req_line,
    input  wire [ISSUE_LANES*MW-1:0]                  req_mshr,
    output reg  [FILL_LANES-1:0]                      fill_valid,
    output reg  [FILL_LANES*MW-1:0]                   fill_mshr,
    output reg  [FILL_LANES*LINE_BYTES*8-1:0]         fill_data,
    output wire                                       idle,
    output reg  [31:0]                                errors
);
    localparam integer LB = $clog2(LINE_BYTES);
    localparam integer LINEW = 41 - LB;
    reg [LINEW-1:0] q_line [0:DEPTH-1];
    reg [MW-1:0]    q_mshr [0:DEPTH-1];
    reg [63:0]      q_done [0:DEPTH-1];
    integer head, tail, l, n, i;
    reg [63:0] bus_next, earliest, start, fin;
    reg [40:0] a;

    function [31:0] word_at(input [40:0] byte_addr);
        word_at = (byte_addr[31:0] * 32'h9E3779B1) ^ ({23'd0, byte_addr[40:32]} * 32'h85EBCA77);
    endfunction

    assign idle = head == tail;
    initial begin
        head = 0;
        tail = 0;
        bus_next = 0;
        errors = 0;
        fill_valid = 0;
        fill_mshr = 0;
        fill_data = 0;
    end
    always @(posedge clk) begin
        if (!rst) begin
            for (l = 0; l < ISSUE_LANES; l = l + 1) begin
                if (req_valid[l]) begin
                    earliest = (cycle + LATENCY) * BYTES_PER_CYCLE;
                    start = earliest > bus_next ? earliest : bus_next;
                    fin = start + LINE_BYTES;
                    bus_next = fin;
                    q_line[tail % DEPTH] = req_line[LINEW*l +: LINEW];
                    q_mshr[tail % DEPTH] = req_mshr[MW*l +: MW];
                    q_done[tail % DEPTH] = (fin + BYTES_PER_CYCLE - 1) / BYTES_PER_CYCLE;
                    tail = tail + 1;
                    if (tail - head > DEPTH) begin
                        $display("E dram model: more than %0d fills in flight", DEPTH);
                        errors = errors + 1;
                    end
                end
            end
            // The lanes of the next cycle: the fills that complete in the cycle after it.
            fill_valid <= {FILL_LANES{1'b0}};
            n = 0;
            while (head != tail && q_done[head % DEPTH] <= cycle + 2) begin
                if (q_done[head % DEPTH] < cycle + 2 || n >= FILL_LANES) begin
                    $display("E dram model: fill of line %0h (done %0d) missed its lane at cycle %0d",
                             q_line[head % DEPTH], q_done[head % DEPTH], cycle);
                    errors = errors + 1;
                end else begin
                    fill_valid[n] <= 1'b1;
                    fill_mshr[MW*n +: MW] <= q_mshr[head % DEPTH];
                    for (i = 0; i < LINE_BYTES / 4; i = i + 1) begin
                        a = {q_line[head % DEPTH], {LB{1'b0}}} + 4 * i;
                        fill_data[(LINE_BYTES*8)*n + 32*i +: 32] <= word_at(a);
                    end
                end
                n = n + 1;
                head = head + 1;
            end
        end
    end
endmodule
