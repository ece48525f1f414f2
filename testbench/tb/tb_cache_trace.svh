// tb_cache_trace.svh: the request-trace driver the node cache's two benches share
// (tb_node_cache.sv: the cache with its fill lanes timed by tb_dram_model.sv;
// tb_node_cache_axi.sv: the cache behind its AXI4 master and tb_axi_dram.sv), included inside
// the bench module. The module declares clk, rst, cyc, the request ports (req_valid,
// req_requester, req_kind, req_addr), rsp_done / rsp_data, dram_idle, REQUESTERS, RQW, CTX
// and MAX_CYCLES; this file declares the trace state and the task that runs it.
//
// Trace (+trace=FILE): lines "cycle requester kind addr" (decimal; kind 0 node, 1 far,
// 2 attribute), ordered by cycle then requester; requester r drives port r / CTX. Log
// (+log=FILE, opened by open_files): "D cycle_requested cycle_done requester data(hex, 64
// bits)" per completion, and "E ..." for a request of a requester whose read is still
// outstanding, two requests on one port in a cycle, a completion of a requester with nothing
// outstanding and a trace out of order; the bench writes its "C ..." and "END cycle errors"
// lines after run_trace.
// Exact (elastic = 0): every request in its recorded cycle (open loop). Elastic: the trace in
// order, each request in its recorded cycle or later, when its requester has nothing
// outstanding and its port is free (for runs whose cycles are the memory's, not the model's).
    reg [1023:0] trace_name, log_name;
    integer fd, fo, rc, port, r, errors;
    reg have, finished, blocked;
    reg [63:0] t_cyc;
    integer t_rq, t_kind;
    reg [31:0] t_addr;
    reg [REQUESTERS-1:0] outstanding;
    reg [63:0] req_cycle [0:REQUESTERS-1];

    task next_line;
        begin
            rc = $fscanf(fd, "%d %d %d %d\n", t_cyc, t_rq, t_kind, t_addr);
            have = rc == 4;
        end
    endtask

    // Opens the trace and the log named by the plusargs; stops the simulation if it cannot.
    task open_files;
        begin
            if (!$value$plusargs("trace=%s", trace_name)
                || !$value$plusargs("log=%s", log_name)) begin
                $display("E usage: +trace=FILE +log=FILE");
                $finish;
            end
            fd = $fopen(trace_name, "r");
            fo = $fopen(log_name, "w");
            if (fd == 0 || fo == 0) begin
                $display("E cannot open the trace or the log");
                $finish;
            end
        end
    endtask

    // Releases reset and drives the trace until it is done, nothing is outstanding and the
    // memory is idle (or MAX_CYCLES), logging every completion.
    task run_trace(input elastic);
        begin
            errors = 0;
            outstanding = 0;
            finished = 1'b0;
            next_line;
            repeat (3) @(posedge clk);
            @(negedge clk);
            rst = 1'b0;
            while (!finished) begin
                // Cycle cyc, between its edges: the completions of this cycle, then its requests.
                for (r = 0; r < REQUESTERS; r = r + 1)
                    if (rsp_done != 0 && rsp_done[r]) begin
                        if (!outstanding[r]) begin
                            $fdisplay(fo, "E cycle %0d: completion for requester %0d with no read outstanding", cyc, r);
                            errors = errors + 1;
                        end
                        $fdisplay(fo, "D %0d %0d %0d %h", req_cycle[r], cyc, r, rsp_data[64*r +: 64]);
                        outstanding[r] = 1'b0;
                    end
                req_valid = 0;
                blocked = 1'b0;
                while (have && !blocked && (elastic ? t_cyc <= cyc : t_cyc == cyc)) begin
                    port = t_rq / CTX;
                    if (elastic && (outstanding[t_rq] || req_valid[port])) blocked = 1'b1;
                    else begin
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
                        req_kind[2*port +: 2] = t_kind[1:0];
                        req_addr[32*port +: 32] = t_addr;
                        outstanding[t_rq] = 1'b1;
                        req_cycle[t_rq] = cyc;
                        next_line;
                    end
                end
                if (!elastic && have && t_cyc < cyc) begin
                    $fdisplay(fo, "E trace out of order at cycle %0d", t_cyc);
                    errors = errors + 1;
                    next_line;
                end
                if ((!have && outstanding == 0 && dram_idle) || cyc >= MAX_CYCLES) finished = 1'b1;
                else begin
                    @(negedge clk);
                    cyc = cyc + 1;
                end
            end
        end
    endtask
