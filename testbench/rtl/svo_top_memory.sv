// svo_top_memory: svo_top's node memory behind the walker pool's memory ports — the on-chip
// node store (svo_onchip_store) with its prefix test, and either one AXI4 attribute master per
// walker (m_axi_*) or the node cache (svo_node_cache_axi) with its fill masters
// (m_axi_node_*), by the package's node_memory.onchip.levels:
// - 21: the on-chip store alone (the model's banks: onchip.banks word-interleaved banks of
//   ports_per_bank ports, latency, combine), one request port per walker, a completion port
//   per context into the pool (svo_core CTX_RESP). The store address is the model's node
//   address: the read's word index (IMAGE.NODE_BASE / 4 + the image's word) minus the load's
//   store_base (LOAD_SRC / 4). The model places the scene's images one after the other from
//   word 0 (src/models/cycle/layout.rs), and a host that loads them that way from LOAD_SRC,
//   with NODE_BASE = LOAD_SRC + 4 · (the image's model base), gives every read the model's
//   address, so bank = address mod banks as in the model. A node read at or beyond the loaded
//   words is an error (st_err: STATUS.ERROR 7). Attribute records: one AXI4 master per walker.
// - 0: the node cache alone, node words and attribute records alike (attr_cached), below.
// - 1..8: both: each image's top levels (a prefix of its words, ONCHIP_WORDS) from the store,
//   every other node word and every record through the cache.
//
// Pipeline position: between svo_core's walker pool (mem_req_* / mem_resp_*, and st_done /
// st_data on the contexts' own completion ports) and the system's memory; svo_top's load DMA
// (svo_store_load.sv) writes the store between frames (load_*). Cycle-exact with the model's
// NodeMemory (rtl_model/src/cycle/memory/), checked through svo_top by the core bench.
`timescale 1ns/1ps
`default_nettype none
module svo_top_memory
    import svo_hw_pkg::*;
#(
    parameter int ADDR_W = 40,           // AXI byte addresses
    parameter int STORE_WORDS = 262144,  // the store's 32-bit words
    parameter int IMAGES = 8,            // image slots (the prefix test)
    parameter int CW = 1,                // context index bits
    parameter int REQS = 2,              // contexts in all, at least 2 (the store's requesters)
    parameter int NODE_PORTS = 1,        // the cache's fill ports (svo_top's)
    parameter int NODE_DW = 64,
    parameter int NODE_IDW = 1
) (
    input  wire                           clk,
    input  wire                           rst,
    input  wire                           core_rst,    // svo_top's pipeline reset (START)
    input  wire                           run,         // a frame runs (the cache's PREFILL)
    // The walker pool's memory ports (svo_core), walker w on bit / slice w
    input  wire  [WALKER_POOL_WALKERS-1:0]      mem_req_valid,
    input  wire  [WALKER_POOL_WALKERS-1:0]      mem_req_attr,
    input  wire  [WALKER_POOL_WALKERS*32-1:0]   mem_req_addr,
    input  wire  [WALKER_POOL_WALKERS*CW-1:0]   mem_req_ctx,
    output wire  [WALKER_POOL_WALKERS-1:0]      mem_req_ready,
    output logic [WALKER_POOL_WALKERS-1:0]      mem_resp_valid,
    output logic [WALKER_POOL_WALKERS*CW-1:0]   mem_resp_ctx,
    output logic [WALKER_POOL_WALKERS*64-1:0]   mem_resp_data,
    // The contexts' own ports (CTX_RESP): node words (the low half), and behind the cache the
    // attribute records as well; the reads' bookkeeping for svo_top's STALL_MEMORY and
    // NODE_READS, and its STATUS flags
    output wire  [REQS-1:0]               st_done,
    output wire  [REQS*64-1:0]            st_data,
    output wire  [REQS-1:0]               st_fin,      // a context's read completed
    output wire  [WALKER_POOL_WALKERS-1:0] st_req,     // a read to the store or the cache
    output wire  [WALKER_POOL_WALKERS-1:0] rd_out,     // an attribute master has reads out
    output wire                           st_overflow, // the store's schedule overflowed
    output logic                          st_err,      // a node read beyond the loaded words
    output logic                          rd_err,      // an attribute read answered an error
    output wire                           nc_err,      // the cache's fill answered an error
    output wire                           nr_aligned,  // the cache's cycle is the model's
    // The frame's image slots (the prefix test) and the store's load
    input  wire  [IMAGES*32-1:0]          img_node_base,
    input  wire  [IMAGES*32-1:0]          img_onchip_words,
    input  wire  [31:0]                   store_base,
    input  wire  [31:0]                   store_words,
    input  wire                           load_valid,
    input  wire  [31:0]                   load_addr,
    input  wire  [31:0]                   load_data,
    // AXI4 read masters of the attribute records (the store alone)
    output logic [WALKER_POOL_WALKERS-1:0]        m_axi_arvalid,
    input  wire  [WALKER_POOL_WALKERS-1:0]        m_axi_arready,
    output logic [WALKER_POOL_WALKERS*ADDR_W-1:0] m_axi_araddr,
    output logic [WALKER_POOL_WALKERS-1:0]        m_axi_arid,
    output logic [WALKER_POOL_WALKERS*8-1:0]      m_axi_arlen,
    output logic [WALKER_POOL_WALKERS*3-1:0]      m_axi_arsize,
    output logic [WALKER_POOL_WALKERS*2-1:0]      m_axi_arburst,
    output logic [WALKER_POOL_WALKERS*3-1:0]      m_axi_arprot,
    output logic [WALKER_POOL_WALKERS*4-1:0]      m_axi_arcache,
    input  wire  [WALKER_POOL_WALKERS-1:0]        m_axi_rvalid,
    output logic [WALKER_POOL_WALKERS-1:0]        m_axi_rready,
    input  wire  [WALKER_POOL_WALKERS*64-1:0]     m_axi_rdata,
    input  wire  [WALKER_POOL_WALKERS*2-1:0]      m_axi_rresp,
    input  wire  [WALKER_POOL_WALKERS-1:0]        m_axi_rlast,
    // AXI4 read masters of the node cache's fills
    output logic [NODE_PORTS-1:0]          m_axi_node_arvalid,
    input  wire  [NODE_PORTS-1:0]          m_axi_node_arready,
    output logic [NODE_PORTS*ADDR_W-1:0]   m_axi_node_araddr,
    output logic [NODE_PORTS*NODE_IDW-1:0] m_axi_node_arid,
    output logic [NODE_PORTS*8-1:0]        m_axi_node_arlen,
    output logic [NODE_PORTS*3-1:0]        m_axi_node_arsize,
    output logic [NODE_PORTS*2-1:0]        m_axi_node_arburst,
    output logic [NODE_PORTS*3-1:0]        m_axi_node_arprot,
    output logic [NODE_PORTS*4-1:0]        m_axi_node_arcache,
    input  wire  [NODE_PORTS-1:0]          m_axi_node_rvalid,
    output logic [NODE_PORTS-1:0]          m_axi_node_rready,
    input  wire  [NODE_PORTS*NODE_DW-1:0]  m_axi_node_rdata,
    input  wire  [NODE_PORTS*NODE_IDW-1:0] m_axi_node_rid,
    input  wire  [NODE_PORTS*2-1:0]        m_axi_node_rresp,
    input  wire  [NODE_PORTS-1:0]          m_axi_node_rlast
);
    localparam int NW = WALKER_POOL_WALKERS;
    localparam int CONTEXTS = WALKER_POOL_CONTEXTS_PER_WALKER;
    localparam bit HAS_STORE = NODE_MEMORY_ONCHIP_LEVELS != 0;  // svo_onchip_store
    localparam bit HAS_CACHE = NODE_MEMORY_ONCHIP_LEVELS != 21; // svo_node_cache_axi
    localparam bit SPLIT = HAS_STORE && HAS_CACHE;             // the prefix test per read
    wire [NW-1:0] rd_resp_err;                // an attribute master's response is an error
    genvar gm;
    wire [NW-1:0] s_req;                      // a read to the store (levels 21: every node read)
    wire [NW-1:0] s_top;                      // levels 1..8: the read is in its image's prefix
    wire [REQS-1:0] s_done;                   // the store's answers, per context
    wire [REQS*32-1:0] s_data;
    wire s_overflow;
    generate
        if (HAS_STORE) begin : onchip
            wire [NW-1:0] st_beyond;
            wire [NW*32-1:0] st_addr;
            /* verilator lint_off PINCONNECTEMPTY */
            svo_onchip_store #(.REQ_PORTS(NW), .REQUESTERS(REQS), .BANKS(NODE_MEMORY_ONCHIP_BANKS),
                .PORTS(NODE_MEMORY_ONCHIP_PORTS_PER_BANK), .LATENCY(NODE_MEMORY_ONCHIP_LATENCY),
                .COMBINE(NODE_MEMORY_ONCHIP_COMBINE ? 1 : 0), .WORDS(STORE_WORDS), .QDEPTH(REQS))
            u_store (.clk(clk), .rst(rst || core_rst), .load_valid(load_valid), .load_addr(load_addr),
                .load_data(load_data), .req_valid(s_req),
                .req_requester(mem_req_ctx), .req_addr(st_addr), .rsp_done(s_done),
                .rsp_data(s_data), .cnt_reads(), .cnt_combined(), .cnt_port_wait(),
                .err(s_overflow));
            /* verilator lint_on PINCONNECTEMPTY */
            always_ff @(posedge clk) st_err <= !(rst || core_rst) && |st_beyond;
            for (gm = 0; gm < NW; gm = gm + 1) begin : store_port
                wire [31:0] a = mem_req_addr[gm*32 +: 32];
                assign s_req[gm] = mem_req_valid[gm] && !mem_req_attr[gm] && (!SPLIT || s_top[gm]);
                assign st_addr[gm*32 +: 32] = a - store_base;
                assign st_beyond[gm] = s_req[gm] && a - store_base >= store_words;
            end
        end else begin : no_store
            assign s_req = '0;
            assign s_done = '0;
            assign s_data = '0;
            assign s_overflow = 1'b0;
            assign st_err = 1'b0;
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused_store = &{1'b0, store_base, store_words, load_valid, load_addr, load_data,
                                 s_top};
            /* verilator lint_on UNUSEDSIGNAL */
        end
        // The prefix test (levels 1..8): a node read is on chip iff its word index lies in
        // [IMAGE[i].NODE_BASE / 4, + ONCHIP_WORDS[i]) of some image slot i (8 compares a port;
        // the images do not overlap, so at most one matches). Attribute records never.
        if (SPLIT) begin : prefix
            for (gm = 0; gm < NW; gm = gm + 1) begin : port
                wire [31:0] a = mem_req_addr[gm*32 +: 32];
                logic hit;
                always_comb begin
                    hit = 1'b0;
                    for (int i = 0; i < IMAGES; i++)
                        if (a - img_node_base[i*32 +: 32] < img_onchip_words[i*32 +: 32]) hit = 1'b1;
                end
                assign s_top[gm] = hit;
            end
        end else begin : no_prefix
            assign s_top = '1;
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused_prefix = &{1'b0, img_onchip_words};
            /* verilator lint_on UNUSEDSIGNAL */
        end
        if (!HAS_CACHE) begin : attr_masters
            // Attribute records: one AXI4 read master per walker (its request port). Reads in
            // flight, in order (one AXI ID): each context has at most one read out, so per
            // master a FIFO of CONTEXTS entries names each response's context.
            localparam int RQ = CONTEXTS;
            localparam int RQW = RQ > 1 ? $clog2(RQ) : 1;
            localparam int RQC = $clog2(RQ + 1);
            for (gm = 0; gm < NW; gm = gm + 1) begin : node_port
                logic [CW-1:0] rq [RQ];
                logic [RQW-1:0] rq_wr, rq_rd;
                logic [RQC-1:0] rq_n;
                wire r_done = m_axi_rvalid[gm] && m_axi_rlast[gm];
                wire rd_free = rq_n != RQC'(RQ) || r_done;
                wire [31:0] a = mem_req_addr[gm*32 +: 32];
                assign st_req[gm] = s_req[gm];
                assign rd_out[gm] = rq_n != '0;
                assign rd_resp_err[gm] = m_axi_rvalid[gm] && m_axi_rresp[gm*2 + 1];
                assign m_axi_rready[gm] = 1'b1;      // the walker takes its read when it arrives
                assign m_axi_arvalid[gm] = mem_req_valid[gm] && mem_req_attr[gm] && rd_free;
                assign m_axi_araddr[gm*ADDR_W +: ADDR_W] = ADDR_W'({a, 3'b000});
                assign m_axi_arsize[gm*3 +: 3] = 3'd3;
                assign m_axi_arlen[gm*8 +: 8] = 8'd0;
                assign m_axi_arid[gm] = 1'b0;
                assign m_axi_arburst[gm*2 +: 2] = 2'b01;
                assign m_axi_arprot[gm*3 +: 3] = 3'b000;
                assign m_axi_arcache[gm*4 +: 4] = 4'b0011;
                assign mem_req_ready[gm] = !mem_req_attr[gm] || (m_axi_arready[gm] && rd_free);
                assign mem_resp_valid[gm] = m_axi_rvalid[gm];
                assign mem_resp_ctx[gm*CW +: CW] = rq[rq_rd];
                assign mem_resp_data[gm*64 +: 64] = m_axi_rdata[gm*64 +: 64];
                wire ar_take = m_axi_arvalid[gm] && m_axi_arready[gm];
                always_ff @(posedge clk) begin
                    if (ar_take) rq[rq_wr] <= mem_req_ctx[gm*CW +: CW];
                    if (rst || core_rst) begin
                        rq_n <= '0;
                        rq_wr <= '0;
                        rq_rd <= '0;
                    end else begin
                        if (ar_take) rq_wr <= rq_wr == RQW'(RQ - 1) ? '0 : rq_wr + 1'b1;
                        if (r_done) rq_rd <= rq_rd == RQW'(RQ - 1) ? '0 : rq_rd + 1'b1;
                        rq_n <= rq_n + RQC'(ar_take) - RQC'(r_done);
                    end
                end
            end
            always_ff @(posedge clk) rd_err <= !(rst || core_rst) && |rd_resp_err;
            // The cache's port: none.
            assign m_axi_node_arvalid = '0;
            assign m_axi_node_araddr = '0;
            assign m_axi_node_arid = '0;
            assign m_axi_node_arlen = '0;
            assign m_axi_node_arsize = '0;
            assign m_axi_node_arburst = '0;
            assign m_axi_node_arprot = '0;
            assign m_axi_node_arcache = '0;
            assign m_axi_node_rready = '1;
            assign nc_err = 1'b0;
            assign nr_aligned = 1'b1;
            assign st_fin = s_done;
            assign st_done = s_done;
            for (gm = 0; gm < REQS; gm = gm + 1) begin : ctx
                assign st_data[gm*64 +: 64] = {32'd0, s_data[gm*32 +: 32]};
            end
            assign st_overflow = s_overflow;
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused_onchip = &{1'b0, m_axi_node_arready, m_axi_node_rvalid, m_axi_node_rdata,
                                   m_axi_node_rid, m_axi_node_rresp, m_axi_node_rlast};
            /* verilator lint_on UNUSEDSIGNAL */
        end else begin : cached
            // The node cache (svo_node_cache_axi: banks, ports, tags, MSHRs, miss queue; its
            // fills on NODE_PORTS AXI4 read ports of one beat a line, ARID = MSHR), cycle-exact
            // with the model's NodeMemory without its on-chip store (memory/mod.rs, cache.rs,
            // dram.rs) behind a memory of the built-in DRAM's timing (tb_axi_dram.sv's contract:
            // dram.latency = the memory's AR-to-RLAST cycles + 3).
            // Requests: every read the pool sends, in the cycle it sends it, walker w on the
            // cache's port w (the pool's walker order is its context order, the model's service
            // order within a cycle), requester = the pool's context index, kind 2 for an
            // attribute record else 0 (the model times a far word as a node word), address the
            // core's: the word index IMAGE.NODE_BASE / 4 + i, the record index IMAGE.ATTR_BASE /
            // 8 + i. The cache takes every read (no ready). Its unified space (cache.rs: node
            // byte 4·word, attribute record j at 2^40 + 8j) is then the system's byte addresses
            // with bit 40 telling attributes: ARADDR = the cache's address without bit 40, i.e.
            // NODE_BASE + 4i or ATTR_BASE + 8i. The model's addresses start from 0 (layout.rs:
            // images one after the other); the same lines, sets and banks as the model's need
            // the host to place the node space and the attribute space each at a multiple of
            // SETS · LINE_BYTES bytes (the cache's size over its ways) with NODE_BASE = node
            // space + 4 · (the image's model base), ATTR_BASE likewise (8 bytes a record), as
            // the cocotb bench does; other bases read the right data at other set indices.
            // Responses: every read's on its context's own port (CTX_RESP 2) in its completion
            // cycle, a node word in the low half, a record whole: the cache answers per
            // context anyway, so the walker response ports stay idle and the pool decodes no
            // port (issue 29: records on walker ports, any context on any port, made the
            // pool's response side N x W). Any number of contexts complete in one cycle, as
            // in the model (the reads merged on one fill of a line holding several records).
            // The cache's cycle: svo_node_cache numbers cycles from reset (bank rotation
            // cycle mod BANKS); the model's cycle runs only in frames, continuing from one
            // frame to the next (the cache keeps its lines across frames; the pipeline's reset
            // at START leaves it alone). PREFILL therefore ends only when the cycles outside
            // RUN since reset are a multiple of cache.banks (up to banks − 1 more PREFILL
            // cycles, outside CYCLES).
            localparam int CSETS = NODE_MEMORY_CACHE_SIZE_BYTES
                / (NODE_MEMORY_CACHE_WAYS * NODE_MEMORY_CACHE_LINE_BYTES);
            localparam int CSLOTS = NODE_MEMORY_CACHE_MISS_QUEUE
                + NODE_MEMORY_CACHE_BANKS * NODE_MEMORY_CACHE_PORTS;
            localparam int CISSUE = NODE_MEMORY_DRAM_MSHRS < CSLOTS ? NODE_MEMORY_DRAM_MSHRS : CSLOTS;
            localparam int CMW = $clog2(NODE_MEMORY_DRAM_MSHRS);
            localparam int RQB = $clog2(REQS);
            localparam int NB = NODE_MEMORY_CACHE_BANKS;
            localparam int NBW = NB > 1 ? $clog2(NB) : 1;
            wire [NW-1:0] c_valid = mem_req_valid & ~s_req;   // the reads not on chip
            wire [REQS-1:0] c_done;
            wire [REQS*64-1:0] c_data;
            wire [NW*RQB-1:0] c_req;
            wire [NW*2-1:0] c_kind;
            wire [NODE_PORTS*41-1:0] c_araddr;
            wire [NODE_PORTS*CMW-1:0] c_arid;
            wire c_axi_error;
            logic c_axi_error_q;
            logic [REQS-1:0] c_attr;              // the context's read out is a record
            logic [NBW-1:0] nr;                   // cycles outside RUN since reset, mod banks
            for (gm = 0; gm < NW; gm = gm + 1) begin : req
                assign st_req[gm] = mem_req_valid[gm];
                assign c_req[gm*RQB +: RQB] = RQB'(mem_req_ctx[gm*CW +: CW]);
                assign c_kind[gm*2 +: 2] = {mem_req_attr[gm], 1'b0};
                assign mem_req_ready[gm] = 1'b1;
                assign rd_out[gm] = 1'b0;
                assign rd_resp_err[gm] = 1'b0;
            end
            /* verilator lint_off PINCONNECTEMPTY */
            svo_node_cache_axi #(.REQ_PORTS(NW), .REQUESTERS(REQS), .BANKS(NB),
                .PORTS(NODE_MEMORY_CACHE_PORTS), .SETS(CSETS), .WAYS(NODE_MEMORY_CACHE_WAYS),
                .LINE_BYTES(NODE_MEMORY_CACHE_LINE_BYTES),
                .HIT_LATENCY(NODE_MEMORY_CACHE_HIT_LATENCY), .MSHRS(NODE_MEMORY_DRAM_MSHRS),
                .MISS_QUEUE(NODE_MEMORY_CACHE_MISS_QUEUE), .ATTR_CACHED(1),
                .FILL_LANES(NODE_PORTS), .ISSUE_LANES(CISSUE))
            u_cache (.clk(clk), .rst(rst), .req_valid(c_valid), .req_requester(c_req),
                .req_kind(c_kind), .req_addr(mem_req_addr), .rsp_done(c_done), .rsp_data(c_data),
                .m_arvalid(m_axi_node_arvalid), .m_arready(m_axi_node_arready),
                .m_arid(c_arid), .m_araddr(c_araddr), .m_arlen(m_axi_node_arlen),
                .m_arsize(m_axi_node_arsize), .m_arburst(m_axi_node_arburst),
                .m_rvalid(m_axi_node_rvalid), .m_rready(m_axi_node_rready),
                .m_rid(m_axi_node_rid[NODE_PORTS*CMW-1:0]), .m_rdata(m_axi_node_rdata),
                .m_rresp(m_axi_node_rresp), .m_rlast(m_axi_node_rlast),
                .axi_error(c_axi_error), .cnt_hits(), .cnt_misses(), .cnt_merged(),
                .cnt_fills(), .cnt_uncached(), .cnt_replay_hits());
            /* verilator lint_on PINCONNECTEMPTY */
            for (gm = 0; gm < NODE_PORTS; gm = gm + 1) begin : axi
                assign m_axi_node_araddr[gm*ADDR_W +: ADDR_W] = ADDR_W'(c_araddr[gm*41 +: 40]);
                assign m_axi_node_arid[gm*NODE_IDW +: NODE_IDW] = NODE_IDW'(c_arid[gm*CMW +: CMW]);
                assign m_axi_node_arprot[gm*3 +: 3] = 3'b000;
                assign m_axi_node_arcache[gm*4 +: 4] = 4'b0011;
            end
            // Node words and records on the contexts' own ports, the store's and the cache's
            // together (a context has one read out: at most one of them answers it).
            assign st_done = s_done | c_done;
            for (gm = 0; gm < REQS; gm = gm + 1) begin : ctx
                assign st_data[gm*64 +: 64] = s_done[gm] ? {32'd0, s_data[gm*32 +: 32]}
                    : c_attr[gm] ? c_data[gm*64 +: 64] : {32'd0, c_data[gm*64 +: 32]};
            end
            assign mem_resp_valid = '0;
            assign mem_resp_ctx = '0;
            assign mem_resp_data = '0;
            assign st_fin = s_done | c_done;
            assign st_overflow = s_overflow;
            assign nc_err = c_axi_error && !c_axi_error_q;
            assign nr_aligned = NBW'(nr + 1'b1) == '0 || NB == 1;
            always_ff @(posedge clk) begin
                for (int w = 0; w < NW; w++)
                    if (c_valid[w]) c_attr[RQB'(mem_req_ctx[w*CW +: CW])] <= mem_req_attr[w];
                if (rst) begin
                    nr <= '0;
                    c_axi_error_q <= 1'b0;
                end else begin
                    if (!run) nr <= NBW'(nr + 1'b1);
                    c_axi_error_q <= c_axi_error;
                end
            end
            assign rd_err = 1'b0;
            assign m_axi_arvalid = '0;
            assign m_axi_araddr = '0;
            assign m_axi_arid = '0;
            assign m_axi_arlen = '0;
            assign m_axi_arsize = '0;
            assign m_axi_arburst = '0;
            assign m_axi_arprot = '0;
            assign m_axi_arcache = '0;
            assign m_axi_rready = '1;
            /* verilator lint_off UNUSEDSIGNAL */
            wire unused_cached = &{1'b0, m_axi_node_rid, c_araddr, m_axi_rvalid, rd_resp_err,
                                   m_axi_rdata, m_axi_rlast};
            /* verilator lint_on UNUSEDSIGNAL */
        end
    endgenerate
    /* verilator lint_off UNUSEDSIGNAL */
    // (each used by some of the three arrangements)
    wire unused = &{1'b0, m_axi_rresp, m_axi_rlast, m_axi_arready, m_axi_node_rid,
                    m_axi_node_rresp, run, core_rst, img_node_base};
    /* verilator lint_on UNUSEDSIGNAL */
endmodule
`default_nettype wire
