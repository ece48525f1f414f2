// svo_node_cache_axi: the node cache (svo_node_cache.v) with its fill side on AXI4 read
// masters towards external memory. Pipeline position: between the walker pool and DRAM, as
// svo_node_cache; this file adds only the bus side. Checked cycle-exact against the model
// (rtl_model/src/cycle/memory, built-in DRAM bus of dram.rs) by tests/node_cache_axi_rtl.rs
// through testbench/tb/tb_node_cache_axi.sv and the slave testbench/tb/tb_axi_dram.sv.
//
// Bus: FILL_LANES AXI4 read ports (AR and R channels only; the cache never writes). Each fill is
// one INCR burst of one beat: ARLEN 0, ARSIZE log2(LINE_BYTES), data width LINE_BYTES * 8
// bits (so LINE_BYTES <= 128: AXI4's widest bus is 1024 bits; larger lines are refused by a
// generate error, see "Not done"), ARID = RID = the fill's MSHR index, ARADDR = the line's
// byte address in cache.rs's unified 41-bit space (node words from 0, attribute record i at
// 2^40 + 8i; mapping that space onto the system's address map is the integration's job).
// Why FILL_LANES ports of a whole line: one R channel carries one beat a cycle and the built-in
// bus moves bytes_per_cycle a cycle, so FILL_LANES = ceil(bytes_per_cycle / LINE_BYTES) ports of
// LINE_BYTES carry FILL_LANES * LINE_BYTES >= bytes_per_cycle a cycle (default: 2 x 512 bits =
// 128 B/cycle at 64-byte lines).
//
// Port of a fill: fill n (issue order, counted from reset) goes to port n mod FILL_LANES, AR and
// R. That keeps at most one completion per port per cycle on the built-in bus: fills are
// moved back to back in issue order, so end(n + FILL_LANES) >= end(n) + FILL_LANES * LINE_BYTES
// >= end(n) + bytes_per_cycle bytes, hence done(n + FILL_LANES) >= done(n) + 1 (done =
// ceil(end / bytes_per_cycle)).
//
// AR side: the fills the cache issues in cycle k (fill_req lanes, issue order) are written at
// the end of k into per-port queues (depth MSHRS: every queued fill holds an MSHR, so they
// cannot overflow); AR is driven from those registers, so the memory sees a fill in cycle k+1
// at the earliest. More fills may be issued in a cycle than there are ports; they queue and go
// out FILL_LANES a cycle (the ports together are a FIFO striped over the ports: with ARREADY
// high, fill n goes out in max(k_n + 1, ar(n - FILL_LANES) + 1), the same as one FIFO sending up
// to FILL_LANES a cycle).
// R side: RREADY is always high (the cache takes FILL_LANES lines a cycle). The R beats of a
// cycle (RLAST on each: one beat per burst) are registered and presented on the cache's fill
// lanes in the next cycle, in issue order (ports rotated from the port of the next fill to
// complete, compacted to lanes 0..); the cache writes them at the end of that cycle. So a
// fill whose RLAST is accepted in cycle t is seen by the cache (line in the tags, MSHR free,
// its reads' rsp_done) in cycle t + 2.
//
// Exactness with the model (the contract tb_axi_dram.sv implements): a fill issued in cycle k
// completes in the model in done = ceil(end / B), end = start + LINE_BYTES, start =
// max((k + latency) * B, end of the previous fill), B = bytes_per_cycle. If the slave takes
// the AR of a fill in cycle a, computes the same formula with k := a - 1 and returns RLAST in
// done - 2, the cache completes every read in the model's cycle, provided ARREADY is high
// whenever ARVALID is (the model's bus has no back-pressure): with k := a - 1 the start is
// unchanged although a queued fill's AR leaves later than k + 1. Proof by induction over n: if
// a_n = k_n + 1 the formulas agree; else a_n = a_{n-F} + 1 (F = FILL_LANES, the port was busy),
// and (a_n - 1 + latency) * B = (a_{n-F} - 1 + latency) * B + B <= start(n-F) + F * LINE_BYTES
// <= end(n-1) (fills n-F .. n-1 back to back), so both maxima are end(n-1). RLAST in done - 2
// is after the AR handshake (AXI) when latency >= 3. The fixed offsets (one cycle to the
// memory, two back) are thus inside the model's `latency`: an external memory with a fixed
// AR-to-RLAST latency of D cycles is modelled by latency = D + 3.
// With AR back-pressure (ARREADY low while ARVALID is high) the fills wait in their queues in
// issue order and the slave's start moves later: data and completion order stay right, cycles
// are those of the slave, no longer the model's (tests/node_cache_axi_rtl.rs's stall run). An
// R beat late by d cycles makes its reads complete d cycles late; a slave returning fills out
// of issue order is still correct in data, with the lanes' order (and so the LRU victims of
// fills of one set in one cycle) not the model's.
//
// Errors: a beat with RRESP != OKAY (SLVERR, DECERR) or without RLAST sets axi_error (sticky
// until reset; svo_top maps it to STATUS.ERROR). The fill is still delivered, so no read
// hangs; its data are whatever the slave returned.
//
// Not done: several beats per burst (lines above 128 bytes, or a narrower bus) would need a
// line buffer per ID (AXI4 may interleave the R beats of different IDs) and a rate argument per
// port (FILL_LANES * data width >= bytes_per_cycle); refused by the generate check instead.
`timescale 1ns/1ps
`default_nettype none
module svo_node_cache_axi #(
    parameter REQ_PORTS   = 2,
    parameter REQUESTERS  = 8,
    parameter BANKS       = 4,
    parameter PORTS       = 2,
    parameter SETS        = 16,
    parameter WAYS        = 4,
    parameter LINE_BYTES  = 64,    // 8 .. 128: one beat of LINE_BYTES * 8 bits per fill
    parameter HIT_LATENCY = 4,
    parameter MSHRS       = 8,
    parameter MISS_QUEUE  = 32,
    parameter ATTR_CACHED = 1,
    parameter FILL_LANES  = 2,     // AXI read ports: ceil(dram.bytes_per_cycle / LINE_BYTES)
    parameter ISSUE_LANES = 8      // >= min(MSHRS, MISS_QUEUE + BANKS * PORTS)
) (
    input  wire                                         clk,
    input  wire                                         rst,
    // Requests and responses: as svo_node_cache.
    input  wire [REQ_PORTS-1:0]                         req_valid,
    input  wire [REQ_PORTS*$clog2(REQUESTERS)-1:0]      req_requester,
    input  wire [REQ_PORTS*2-1:0]                       req_kind,
    input  wire [REQ_PORTS*32-1:0]                      req_addr,
    output wire [REQUESTERS-1:0]                        rsp_done,
    output wire [REQUESTERS*64-1:0]                     rsp_data,
    // AXI4 read ports (port p in bits [p*width +: width]).
    output wire [FILL_LANES-1:0]                        m_arvalid,
    input  wire [FILL_LANES-1:0]                        m_arready,
    output wire [FILL_LANES*$clog2(MSHRS)-1:0]          m_arid,
    output wire [FILL_LANES*41-1:0]                     m_araddr,
    output wire [FILL_LANES*8-1:0]                      m_arlen,
    output wire [FILL_LANES*3-1:0]                      m_arsize,
    output wire [FILL_LANES*2-1:0]                      m_arburst,
    input  wire [FILL_LANES-1:0]                        m_rvalid,
    output wire [FILL_LANES-1:0]                        m_rready,
    input  wire [FILL_LANES*$clog2(MSHRS)-1:0]          m_rid,
    input  wire [FILL_LANES*LINE_BYTES*8-1:0]           m_rdata,
    input  wire [FILL_LANES*2-1:0]                      m_rresp,
    input  wire [FILL_LANES-1:0]                        m_rlast,
    output reg                                          axi_error,
    output wire [31:0]                                  cnt_hits,
    output wire [31:0]                                  cnt_misses,
    output wire [31:0]                                  cnt_merged,
    output wire [31:0]                                  cnt_fills,
    output wire [31:0]                                  cnt_uncached,
    output wire [31:0]                                  cnt_replay_hits
);
    localparam integer MW = $clog2(MSHRS);
    localparam integer LB = $clog2(LINE_BYTES);
    localparam integer LINEW = 41 - LB;
    localparam integer LBITS = LINE_BYTES * 8;
    localparam integer F = FILL_LANES;
    localparam integer QD = MSHRS;                 // per-port AR queue depth
    localparam integer QW = $clog2(QD + 1);
    localparam integer PW = F > 1 ? $clog2(F) : 1;
    localparam [2:0] SIZE = LB[2:0];

    generate
        if (LINE_BYTES > 128 || F < 1) begin : bad_axi_params
            svo_node_cache_axi_line_wider_than_1024_bit_axi bad();
        end
    endgenerate

    wire [ISSUE_LANES-1:0]         iss_valid;
    wire [ISSUE_LANES*LINEW-1:0]   iss_line;
    wire [ISSUE_LANES*MW-1:0]      iss_mshr;
    reg  [F-1:0]                   fv_q;
    reg  [F*MW-1:0]                fm_q;
    reg  [F*LBITS-1:0]             fd_q;

    svo_node_cache #(
        .REQ_PORTS(REQ_PORTS), .REQUESTERS(REQUESTERS), .BANKS(BANKS), .PORTS(PORTS),
        .SETS(SETS), .WAYS(WAYS), .LINE_BYTES(LINE_BYTES), .HIT_LATENCY(HIT_LATENCY),
        .MSHRS(MSHRS), .MISS_QUEUE(MISS_QUEUE), .ATTR_CACHED(ATTR_CACHED),
        .FILL_LANES(F), .ISSUE_LANES(ISSUE_LANES)
    ) cache (
        .clk(clk), .rst(rst), .req_valid(req_valid), .req_requester(req_requester),
        .req_kind(req_kind), .req_addr(req_addr), .rsp_done(rsp_done), .rsp_data(rsp_data),
        .fill_req_valid(iss_valid), .fill_req_line(iss_line), .fill_req_mshr(iss_mshr),
        .fill_valid(fv_q), .fill_mshr(fm_q), .fill_data(fd_q),
        .cnt_hits(cnt_hits), .cnt_misses(cnt_misses), .cnt_merged(cnt_merged),
        .cnt_fills(cnt_fills), .cnt_uncached(cnt_uncached), .cnt_replay_hits(cnt_replay_hits)
    );

    // ---- AR: per-port queues, fill n on port n mod F ---------------------------------------
    localparam integer AW = $clog2(F * QD);        // queue storage address
    localparam integer QD_LAST_I = QD - 1;
    localparam [QW-1:0] QD_LAST = QD_LAST_I[QW-1:0];
    localparam integer F_LAST_I = F - 1;
    localparam [PW-1:0] F_LAST = F_LAST_I[PW-1:0];
    reg [LINEW-1:0] q_line [0:F*QD-1];
    reg [MW-1:0]    q_mshr [0:F*QD-1];
    reg [F*QW-1:0]  q_rd, q_wr, q_n;               // per port: read/write index, entries
    reg [PW-1:0]    ip_q;                          // port of the next fill issued

    // The port after port x (mod F).
    function [PW-1:0] next_port(input [PW-1:0] x);
        next_port = F == 1 || x == F_LAST ? {PW{1'b0}} : x + 1'b1;
    endfunction
    // Storage address of entry i of port x's queue.
    function [AW-1:0] q_addr(input [PW-1:0] x, input [QW-1:0] i);
        /* verilator lint_off UNUSEDSIGNAL */
        reg [31:0] t;
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            t = {{(32 - PW){1'b0}}, x} * QD + {{(32 - QW){1'b0}}, i};
            q_addr = t[AW-1:0];
        end
    endfunction

    genvar g;
    generate
        for (g = 0; g < F; g = g + 1) begin : ar_port
            localparam [PW-1:0] GP = g;
            wire [AW-1:0] head = q_addr(GP, q_rd[QW*g +: QW]);
            assign m_arvalid[g] = q_n[QW*g +: QW] != {QW{1'b0}};
            assign m_arid[MW*g +: MW] = q_mshr[head];
            assign m_araddr[41*g +: 41] = {q_line[head], {LB{1'b0}}};
            assign m_arlen[8*g +: 8] = 8'd0;
            assign m_arsize[3*g +: 3] = SIZE;
            assign m_arburst[2*g +: 2] = 2'b01;  // INCR
            assign m_rready[g] = 1'b1;
        end
    endgenerate

    // Next queue state: the ARs taken leave, the fills issued now enter, lane by lane.
    reg [F*QW-1:0]  n_rd, n_wr, n_n;
    reg [PW-1:0]    n_ip;
    reg [ISSUE_LANES*AW-1:0] w_addr;
    reg [QW-1:0]    wi;
    integer l, p;
    always @* begin
        n_rd = q_rd;
        n_wr = q_wr;
        n_n = q_n;
        n_ip = ip_q;
        w_addr = {ISSUE_LANES*AW{1'b0}};
        wi = {QW{1'b0}};
        for (p = 0; p < F; p = p + 1)
            if (m_arvalid[p] && m_arready[p]) begin
                n_rd[QW*p +: QW] = q_rd[QW*p +: QW] == QD_LAST ? {QW{1'b0}}
                                                              : q_rd[QW*p +: QW] + 1'b1;
                n_n[QW*p +: QW] = q_n[QW*p +: QW] - 1'b1;
            end
        for (l = 0; l < ISSUE_LANES; l = l + 1)
            if (iss_valid[l]) begin
                wi = n_wr[QW*n_ip +: QW];
                w_addr[AW*l +: AW] = q_addr(n_ip, wi);
                n_wr[QW*n_ip +: QW] = wi == QD_LAST ? {QW{1'b0}} : wi + 1'b1;
                n_n[QW*n_ip +: QW] = n_n[QW*n_ip +: QW] + 1'b1;
                n_ip = next_port(n_ip);
            end
    end

    integer wl;
    always @(posedge clk) begin
        for (wl = 0; wl < ISSUE_LANES; wl = wl + 1)
            if (iss_valid[wl]) begin
                q_line[w_addr[AW*wl +: AW]] <= iss_line[LINEW*wl +: LINEW];
                q_mshr[w_addr[AW*wl +: AW]] <= iss_mshr[MW*wl +: MW];
            end
        if (rst) begin
            q_rd <= {F*QW{1'b0}};
            q_wr <= {F*QW{1'b0}};
            q_n <= {F*QW{1'b0}};
            ip_q <= {PW{1'b0}};
        end else begin
            q_rd <= n_rd;
            q_wr <= n_wr;
            q_n <= n_n;
            ip_q <= n_ip;
        end
    end

    // ---- R: the beats of this cycle, registered onto the fill lanes in issue order ----------
    reg [PW-1:0]     cp_q;                         // port of the next fill to complete
    reg [PW-1:0]     n_cp, rp;
    reg [F-1:0]      n_fv;
    reg [F*MW-1:0]   n_fm;
    reg [F*LBITS-1:0] n_fd;
    reg              n_err;
    reg [PW-1:0]     nl;                           // lanes used (wraps after the last)
    integer k;
    always @* begin
        n_fv = {F{1'b0}};
        n_fm = fm_q;
        n_fd = fd_q;
        n_err = 1'b0;
        n_cp = cp_q;
        rp = cp_q;
        nl = {PW{1'b0}};
        for (k = 0; k < F; k = k + 1) begin
            if (m_rvalid[rp]) begin
                n_fv[nl] = 1'b1;
                n_fm[MW*nl +: MW] = m_rid[MW*rp +: MW];
                n_fd[LBITS*nl +: LBITS] = m_rdata[LBITS*rp +: LBITS];
                if (m_rresp[2*rp +: 2] != 2'b00 || !m_rlast[rp]) n_err = 1'b1;
                nl = nl + 1'b1;
                n_cp = next_port(n_cp);
            end
            rp = next_port(rp);
        end
    end

    always @(posedge clk) begin
        fm_q <= n_fm;
        fd_q <= n_fd;
        if (rst) begin
            fv_q <= {F{1'b0}};
            cp_q <= {PW{1'b0}};
            axi_error <= 1'b0;
        end else begin
            fv_q <= n_fv;
            cp_q <= n_cp;
            if (n_err) axi_error <= 1'b1;
        end
    end
endmodule
`default_nettype wire
