// The testbenches' node memory, shared by tb_walker.sv and tb_frame.sv: one read port of
// fixed latency, a read requested in cycle c is valid in cycle c + L (L = mem_latency).
// Included inside a module (textually, so both simulators take it) that declares
// mem_req_valid, mem_req_attr, mem_req_addr, mem_resp_valid (a wire), mem_resp_data, the
// countdown `int left`, `int mem_latency`, the images nodes[]/attrs[] with NODE_WORDS and
// ATTR_RECORDS entries and the task report(msg); and defines TB_MEM_WHERE, the message
// prefix naming what made an out-of-range read (undefined here again at the end). An includer
// may define TB_MEM_EXTRA, an expression of cycles added to each read's latency (random
// stalls; default 0), and must then hold the request's ready low while it wants to stall.
`ifndef TB_MEM_EXTRA
`define TB_MEM_EXTRA 0
`endif
always @(posedge clk) begin
    if (mem_req_valid && left <= 1) begin
        left <= mem_latency + `TB_MEM_EXTRA;
        if (mem_req_attr ? mem_req_addr >= ATTR_RECORDS : mem_req_addr >= NODE_WORDS) begin
            report($sformatf("%sread of %s %0d outside the memory", `TB_MEM_WHERE,
                             mem_req_attr ? "attribute" : "node word", mem_req_addr));
            mem_resp_data <= 'x;
        end else begin
            mem_resp_data <= mem_req_attr ? attrs[mem_req_addr] : {32'd0, nodes[mem_req_addr]};
        end
    end else if (left > 0) begin
        left <= left - 1;
    end
end
assign mem_resp_valid = left == 1;   // (an always @* would not run at time 0: x)
`undef TB_MEM_WHERE
`undef TB_MEM_EXTRA
