// tb_axi_dram: an AXI4 read slave (PORTS read ports, AR and R) whose timing is the built-in
// DRAM bus of rtl_model/src/cycle/memory/dram.rs seen through svo_node_cache_axi.v's registers,
// for testbenches only. The contract (svo_node_cache_axi.v header): the AR of a fill taken in
// cycle a counts as issued by the cache in cycle a - 1; the fill transfers on one bus after the
// fills taken before it (dram.rs: start = max((issue + LATENCY) * B, end of the previous fill),
// end = start + LINE_BYTES, done = ceil(end / B), B = BYTES_PER_CYCLE); its single beat (RLAST)
// is on R in cycle done - 2 on the port its AR came on, so the cache sees the line in done.
//
// The arithmetic is tb_dram_model.sv's, instantiated, not copied: tb_dram_model presents a fill
// on its lanes one cycle before its done, so run on a cycle count one ahead (cycle + 1) and with
// latency LATENCY - 2 it takes a fill in cycle a as issued in (a + 1) + (LATENCY - 2) - LATENCY
// = a - 1 and presents it in done - 2: those lanes are the R beats (needs LATENCY >= 3, which
// is also AXI's minimum: R follows the AR handshake by a cycle at least).
//
// Order: fills are taken in the master's issue order, which svo_node_cache_axi stripes over the
// ports (fill n on port n mod PORTS): the slave takes ARs in rotating port order from the port
// of the next fill, stopping at the first port with no AR (or paused), so its bus order is the
// issue order even with pauses.
//
// Pauses (seeded, for the stall run): each cycle and port, ARREADY is low with probability
// pause_ar % and a due R beat is held with probability pause_r %; held beats queue per port
// (in order). Then data and order stay exact, cycles do not. slverr_fill: the fill with that
// index (taken order, from 0) answers RRESP = SLVERR (all ones: none). Counters: ar_stalls
// (port-cycles with ARVALID high and ARREADY low), r_stalls (port-cycles a beat was held).
// Errors ("E ..."): an
// AR that is not one INCR beat of LINE_BYTES at an aligned address, two due beats on one port
// in a cycle, queue overflow, and tb_dram_model's own (a fill that missed its lane).
`timescale 1ns/1ps
module tb_axi_dram #(
    parameter LINE_BYTES      = 64,
    parameter LATENCY         = 60,       // dram.latency (>= 3)
    parameter BYTES_PER_CYCLE = 128,
    parameter PORTS           = 2,
    parameter MW              = 3,        // ARID / RID bits
    parameter RQ              = 256,      // held beats per port
    parameter ORDQ            = 8192      // fills in flight
) (
    input  wire                        clk,
    input  wire                        rst,
    input  wire [63:0]                 cycle,          // the cycle ending at this edge
    input  wire [31:0]                 pause_ar,       // percent
    input  wire [31:0]                 pause_r,        // percent
    input  wire [31:0]                 seed,
    input  wire [31:0]                 slverr_fill,
    input  wire [PORTS-1:0]            s_arvalid,
    output reg  [PORTS-1:0]            s_arready,
    input  wire [PORTS*MW-1:0]         s_arid,
    input  wire [PORTS*41-1:0]         s_araddr,
    input  wire [PORTS*8-1:0]          s_arlen,
    input  wire [PORTS*3-1:0]          s_arsize,
    input  wire [PORTS*2-1:0]          s_arburst,
    output reg  [PORTS-1:0]            s_rvalid,
    input  wire [PORTS-1:0]            s_rready,
    output reg  [PORTS*MW-1:0]         s_rid,
    output reg  [PORTS*LINE_BYTES*8-1:0] s_rdata,
    output reg  [PORTS*2-1:0]          s_rresp,
    output wire [PORTS-1:0]            s_rlast,
    output wire                        idle,
    output wire [31:0]                 errors,
    output reg  [31:0]                 ar_stalls,
    output reg  [31:0]                 r_stalls
);
    localparam integer LB = $clog2(LINE_BYTES);
    localparam integer LINEW = 41 - LB;
    localparam integer LBITS = LINE_BYTES * 8;
    localparam integer PB = PORTS > 1 ? $clog2(PORTS) : 1;

    // ---- AR: taken in rotating port order; the bus (tb_dram_model) sees them in that order ---
    reg  [PORTS-1:0]       d_valid;
    reg  [PORTS*LINEW-1:0] d_line;
    reg  [PORTS*MW-1:0]    d_mshr;
    reg  [PORTS-1:0]       par_q, pr_q;            // this cycle's pauses
    integer sp_q;                                  // port of the next fill to take
    integer i, p, n_take;
    reg stop;
    always @* begin
        s_arready = 0;
        d_valid = 0;
        d_line = 0;
        d_mshr = 0;
        n_take = 0;
        stop = 1'b0;
        for (i = 0; i < PORTS; i = i + 1) begin
            p = (sp_q + i) % PORTS;
            if (!stop && s_arvalid[p] && !par_q[p]) begin
                s_arready[p] = 1'b1;
                d_valid[n_take] = 1'b1;
                d_line[LINEW*n_take +: LINEW] = s_araddr[41*p + LB +: LINEW];
                d_mshr[MW*n_take +: MW] = s_arid[MW*p +: MW];
                n_take = n_take + 1;
            end else stop = 1'b1;
        end
    end

    wire [PORTS-1:0]         l_valid;
    wire [PORTS*MW-1:0]      l_mshr;
    wire [PORTS*LBITS-1:0]   l_data;
    wire                     bus_idle;
    wire [31:0]              bus_errors;
    tb_dram_model #(
        .LINE_BYTES(LINE_BYTES), .LATENCY(LATENCY - 2), .BYTES_PER_CYCLE(BYTES_PER_CYCLE),
        .ISSUE_LANES(PORTS), .FILL_LANES(PORTS), .MW(MW), .DEPTH(ORDQ)
    ) bus (
        .clk(clk), .rst(rst), .cycle(cycle + 64'd1), .req_valid(d_valid), .req_line(d_line),
        .req_mshr(d_mshr), .fill_valid(l_valid), .fill_mshr(l_mshr), .fill_data(l_data),
        .idle(bus_idle), .errors(bus_errors)
    );

    // The port and index of each fill taken, in bus order (its lanes come out in that order).
    reg [PB-1:0] ord_port [0:ORDQ-1];
    reg [31:0]   ord_idx  [0:ORDQ-1];
    integer oh_q, ot_q, nfill_q;

    // ---- R: the due beats (bus lanes) to their ports, held per port when paused -------------
    reg [MW-1:0]    rq_id   [0:PORTS*RQ-1];
    reg [LBITS-1:0] rq_data [0:PORTS*RQ-1];
    reg             rq_err  [0:PORTS*RQ-1];
    integer rq_h [0:PORTS-1];
    integer rq_n [0:PORTS-1];
    reg [PORTS-1:0]       in_v, in_err;
    reg [PORTS*MW-1:0]    in_id;
    reg [PORTS*LBITS-1:0] in_data;
    integer e_in;                                  // two due beats on one port (an error)
    integer k, q;
    always @* begin
        in_v = 0;
        in_err = 0;
        in_id = 0;
        in_data = 0;
        e_in = 0;
        for (k = 0; k < PORTS; k = k + 1)
            if (l_valid[k]) begin
                q = ord_port[(oh_q + k) % ORDQ];
                if (in_v[q]) e_in = e_in + 1;
                in_v[q] = 1'b1;
                in_err[q] = ord_idx[(oh_q + k) % ORDQ] == slverr_fill;
                in_id[MW*q +: MW] = l_mshr[MW*k +: MW];
                in_data[LBITS*q +: LBITS] = l_data[LBITS*k +: LBITS];
            end
        for (k = 0; k < PORTS; k = k + 1) begin
            if (rq_n[k] != 0) begin
                s_rvalid[k] = !pr_q[k];
                s_rid[MW*k +: MW] = rq_id[k*RQ + rq_h[k]];
                s_rdata[LBITS*k +: LBITS] = rq_data[k*RQ + rq_h[k]];
                s_rresp[2*k +: 2] = rq_err[k*RQ + rq_h[k]] ? 2'b10 : 2'b00;
            end else begin
                s_rvalid[k] = in_v[k] && !pr_q[k];
                s_rid[MW*k +: MW] = in_id[MW*k +: MW];
                s_rdata[LBITS*k +: LBITS] = in_data[LBITS*k +: LBITS];
                s_rresp[2*k +: 2] = in_err[k] ? 2'b10 : 2'b00;
            end
        end
    end
    assign s_rlast = {PORTS{1'b1}};

    integer my_errors, held, t, sd;
    reg [31:0] rnd;
    reg seeded;
    reg all_empty;
    always @* begin
        all_empty = 1'b1;
        for (t = 0; t < PORTS; t = t + 1) if (rq_n[t] != 0) all_empty = 1'b0;
    end
    assign idle = bus_idle && l_valid == 0 && all_empty;
    assign errors = my_errors + bus_errors;

    initial begin
        if (LATENCY < 3) begin
            $display("E tb_axi_dram: LATENCY %0d < 3 (R must follow the AR handshake)", LATENCY);
            $finish;
        end
        sp_q = 0;
        oh_q = 0;
        ot_q = 0;
        nfill_q = 0;
        my_errors = 0;
        ar_stalls = 0;
        r_stalls = 0;
        par_q = 0;
        pr_q = 0;
        seeded = 1'b0;
        for (t = 0; t < PORTS; t = t + 1) begin
            rq_h[t] = 0;
            rq_n[t] = 0;
        end
    end

    // Nonblocking state updates: tb_dram_model samples d_* (combinational from this state) at
    // the same edge.
    integer pn, tk, ot, ix;
    always @(posedge clk) begin
        if (!seeded) begin
            sd = seed;
            seeded = 1'b1;
        end
        if (!rst) begin
            // ARs taken now: check them and remember their ports in bus order.
            tk = 0;
            ot = ot_q;
            ix = nfill_q;
            for (t = 0; t < PORTS; t = t + 1) begin
                pn = (sp_q + t) % PORTS;
                if (s_arvalid[pn] && s_arready[pn]) begin
                    if (s_arlen[8*pn +: 8] != 0 || s_arsize[3*pn +: 3] != LB
                        || s_arburst[2*pn +: 2] != 2'b01 || s_araddr[41*pn +: LB] != 0) begin
                        $display("E tb_axi_dram cycle %0d port %0d: AR not one INCR beat of %0d bytes at an aligned address (len %0d size %0d burst %0d addr %h)",
                                 cycle, pn, LINE_BYTES, s_arlen[8*pn +: 8], s_arsize[3*pn +: 3],
                                 s_arburst[2*pn +: 2], s_araddr[41*pn +: 41]);
                        my_errors = my_errors + 1;
                    end
                    ord_port[ot % ORDQ] <= pn[PB-1:0];
                    ord_idx[ot % ORDQ] <= ix;
                    ot = ot + 1;
                    ix = ix + 1;
                    tk = tk + 1;
                end
                if (s_arvalid[pn] && !s_arready[pn]) ar_stalls <= ar_stalls + 1;
            end
            ot_q <= ot;
            nfill_q <= ix;
            sp_q <= (sp_q + tk) % PORTS;
            if (ot - oh_q > ORDQ) begin
                $display("E tb_axi_dram: more than %0d fills in flight", ORDQ);
                my_errors = my_errors + 1;
            end
            // The due beats leave their lanes; the ones not sent now are held.
            held = 0;
            for (t = 0; t < PORTS; t = t + 1) if (l_valid[t]) held = held + 1;
            oh_q <= oh_q + held;
            if (e_in != 0) begin
                $display("E tb_axi_dram cycle %0d: two beats due on one port", cycle);
                my_errors = my_errors + 1;
            end
            for (t = 0; t < PORTS; t = t + 1) begin
                if ((rq_n[t] != 0 || in_v[t]) && pr_q[t]) r_stalls <= r_stalls + 1;
                pn = rq_n[t];
                ix = rq_h[t];
                if (rq_n[t] != 0 && s_rvalid[t] && s_rready[t]) begin
                    ix = (ix + 1) % RQ;
                    pn = pn - 1;
                end
                if (in_v[t] && !(rq_n[t] == 0 && s_rvalid[t] && s_rready[t])) begin
                    if (rq_n[t] >= RQ) begin
                        $display("E tb_axi_dram: more than %0d beats held on port %0d", RQ, t);
                        my_errors = my_errors + 1;
                    end
                    ot = t * RQ + (rq_h[t] + rq_n[t]) % RQ;
                    rq_id[ot] <= in_id[MW*t +: MW];
                    rq_data[ot] <= in_data[LBITS*t +: LBITS];
                    rq_err[ot] <= in_err[t];
                    pn = pn + 1;
                end
                rq_h[t] <= ix;
                rq_n[t] <= pn;
            end
            // The next cycle's pauses.
            for (t = 0; t < PORTS; t = t + 1) begin
                rnd = $random(sd);
                par_q[t] <= rnd % 100 < pause_ar;
                rnd = $random(sd);
                pr_q[t] <= rnd % 100 < pause_r;
            end
        end
    end
endmodule
