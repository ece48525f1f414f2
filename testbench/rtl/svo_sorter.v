// svo_sorter: the candidate sorter of one ray: the 8-lane sorting network (19 comparators,
// depth 6) on chunks of 8 keys, then two-way merge passes over the sorted runs when a ray has
// more than 8 candidates (rtl_model/src/units/sorter.rs `Sorter::sort`, docs/units/sorter.md).
//
// Pipeline position: after the sphere tests, before the hit-buffer check. Formats (parameters,
// from the vectors' package): a key is {id, t} with t the entry distance (KW = 32 bits,
// uQ10.22) in the low bits and the instance id (IW = 8 bits) above it; keys compare as the
// tuple (t, id), so equal entry distances go lower id first. A ray is in_count keys (up to
// MAX_KEYS, more are cut) in arrival order on in_keys, key k at [k*(KW+IW) +: KW+IW]; the result
// is the same keys in (t, id) order on out_keys, lanes at or above the count 0.
//
// Network: the model's BEST_8 network by layers, one register per layer (6 cycles, II = 1);
// lanes at or above the count carry an invalid bit above t that sorts them last. A ray of
// C = ceil(count / 8) > 1 chunks issues chunk k on cycle k from a register copy of the ray,
// writes the sorted chunks into run buffer A, then merges neighbouring runs (8, 16, ...)
// from one buffer into the other, one key per cycle, until one run is left: each pass takes
// one setup cycle (the head compare's register, MERGE_LATENCY) and count cycles; on equal
// keys the left run goes first, as the model's merge.
//
// Timing, the cycle model's (`units::sorter::pipe_cost` in a `UnitPipe` of latency 6; the
// sorter's vector rows carry it per ray as `cycles` and `busy`):
//   latency: 6 for one chunk (a ray without keys too: an empty issue), else
//            (C - 1) + 6 + P * (count + 1) with P = ceil(log2 C) passes;
//   in_ready: high again 1 cycle after accepting a one-chunk ray (II = 1), and
//            C + P * (count + 1) cycles after a merged one: the next ray's network pass then
//            ends after this ray's merge, so one merger serves every ray and results leave in
//            order without a reorder buffer.
`timescale 1ns/1ps
`default_nettype none
module svo_sorter #(
    parameter KW = 32,
    parameter IW = 8,
    parameter MAX_KEYS = 32,             // a multiple of 8, at most 64
    parameter CW = 6                     // bits of a count 0..MAX_KEYS
) (
    input  wire                       clk,
    input  wire                       rst,
    input  wire                       in_valid,
    output wire                       in_ready,
    input  wire [CW-1:0]              in_count,
    input  wire [MAX_KEYS*(KW+IW)-1:0] in_keys,
    output wire                       out_valid,
    output wire [CW-1:0]              out_count,
    output wire [MAX_KEYS*(KW+IW)-1:0] out_keys
);
    localparam N = 8;                    // network lanes
    localparam D = 6;                    // network layers = latency
    localparam KB = KW + IW;             // key bits in the ports
    localparam SKW = KB + 1;             // sort key {invalid, t, id}
    localparam PW = 7;                   // pointer bits: 0..MAX_KEYS and one beyond
    // The model's BEST_8 network: layer l, comparator p as {i, j} at [(4l + p)*6 +: 6];
    // unused slots are (0, 0), a compare of a lane with itself, which never swaps.
    localparam [6*4*6-1:0] PAIRS = {
        6'o12, 6'o34, 6'o56, 6'o00,      // layer 5: (1,2) (3,4) (5,6)
        6'o14, 6'o36, 6'o00, 6'o00,      // layer 4: (1,4) (3,6)
        6'o24, 6'o35, 6'o00, 6'o00,      // layer 3: (2,4) (3,5)
        6'o01, 6'o23, 6'o45, 6'o67,      // layer 2
        6'o04, 6'o15, 6'o26, 6'o37,      // layer 1
        6'o02, 6'o13, 6'o46, 6'o57       // layer 0
    };

    // Counts: chunks C (an empty ray is one empty issue) and merge passes P.
    wire [CW-1:0] cnt_in = (in_count > MAX_KEYS[CW-1:0]) ? MAX_KEYS[CW-1:0] : in_count;
    wire [CW-1:0] chunks_in = (cnt_in + N[CW-1:0] - 1'b1) / N[CW-1:0];
    function [3:0] clog2c(input [CW-1:0] c);   // ceil(log2 c), 0 for c <= 1
        integer b;
        begin
            clog2c = 4'd0;
            for (b = 0; b < CW; b = b + 1)
                if ((c - 1'b1) >> b != 0) clog2c = b[3:0] + 4'd1;
            if (c <= 1) clog2c = 4'd0;
        end
    endfunction
    wire [3:0]  passes_in = clog2c(chunks_in);
    wire [15:0] occupancy = (chunks_in <= 1) ? 16'd1 :
                            {{(16 - CW){1'b0}}, chunks_in} + {12'd0, passes_in} * ({10'd0, cnt_in} + 16'd1);

    // Input: one ray per in_ready; in_ready falls for occupancy - 1 cycles after an accept.
    reg  [15:0] hold;
    wire        accept = in_valid && in_ready;
    assign in_ready = (hold == 16'd0);
    always @(posedge clk) begin
        if (rst) hold <= 16'd0;
        else if (accept) hold <= occupancy - 16'd1;
        else if (hold != 16'd0) hold <= hold - 16'd1;
    end

    // The ray as sort keys: {invalid, t, id}, lanes at or above the count invalid.
    function [MAX_KEYS*SKW-1:0] to_sort(input [MAX_KEYS*KB-1:0] keys, input [CW-1:0] cnt);
        integer k;
        begin
            for (k = 0; k < MAX_KEYS; k = k + 1)
                to_sort[k*SKW +: SKW] = (k < cnt) ?
                    {1'b0, keys[k*KB +: KW], keys[k*KB + KW +: IW]} : {1'b1, {KB{1'b0}}};
        end
    endfunction

    // Feeder: chunks 1..C-1 of a merged ray, one per cycle after the accept.
    reg [MAX_KEYS*SKW-1:0] f_keys;
    reg [CW-1:0]           f_count;
    reg [3:0]              f_next, f_chunks;
    wire [MAX_KEYS*SKW-1:0] in_sort = to_sort(in_keys, cnt_in);
    wire feeding = (f_next < f_chunks);
    always @(posedge clk) begin
        if (rst) begin
            f_next <= 4'd0;
            f_chunks <= 4'd0;
        end else if (accept) begin
            f_keys   <= in_sort;
            f_count  <= cnt_in;
            f_next   <= 4'd1;
            f_chunks <= (chunks_in == 0) ? 4'd1 : chunks_in[3:0];
        end else if (feeding) begin
            f_next <= f_next + 4'd1;
        end
    end

    // Network input: chunk 0 at the accept, then the feeder's chunks.
    wire          n_valid = accept || feeding;
    wire [N*SKW-1:0] n_keys  = accept ? in_sort[0 +: N*SKW] : f_keys[f_next*N*SKW +: N*SKW];
    wire [CW-1:0] n_count = accept ? cnt_in : f_count;
    wire [3:0]    n_chunk = accept ? 4'd0 : f_next;
    wire [3:0]    n_nch   = accept ? ((chunks_in == 0) ? 4'd1 : chunks_in[3:0]) : f_chunks;

    // The network: layer l's compare-exchanges, then its register.
    genvar l;
    generate
        for (l = 0; l < D; l = l + 1) begin : layer
            wire [N*SKW-1:0] k_in;
            wire             v_in;
            wire [CW-1:0]    c_in;
            wire [3:0]       ch_in, nch_in;
            if (l == 0) begin : first
                assign k_in = n_keys;  assign v_in = n_valid;  assign c_in = n_count;
                assign ch_in = n_chunk;  assign nch_in = n_nch;
            end else begin : next
                assign k_in = layer[l-1].k_q;  assign v_in = layer[l-1].v_q;
                assign c_in = layer[l-1].c_q;  assign ch_in = layer[l-1].ch_q;
                assign nch_in = layer[l-1].nch_q;
            end
            reg [N*SKW-1:0] k_ce;
            reg [SKW-1:0]   a, b;
            reg [5:0]       pair;
            integer p;
            always @* begin
                k_ce = k_in;
                for (p = 0; p < 4; p = p + 1) begin
                    pair = PAIRS[(4*l + p)*6 +: 6];
                    a = k_ce[pair[5:3]*SKW +: SKW];
                    b = k_ce[pair[2:0]*SKW +: SKW];
                    if (a > b) begin
                        k_ce[pair[5:3]*SKW +: SKW] = b;
                        k_ce[pair[2:0]*SKW +: SKW] = a;
                    end
                end
            end
            reg [N*SKW-1:0] k_q;
            reg             v_q;
            reg [CW-1:0]    c_q;
            reg [3:0]       ch_q, nch_q;
            always @(posedge clk) begin
                v_q   <= rst ? 1'b0 : v_in;
                k_q   <= k_ce;
                c_q   <= c_in;
                ch_q  <= ch_in;
                nch_q <= nch_in;
            end
        end
    endgenerate
    wire             net_v   = layer[D-1].v_q;
    wire [N*SKW-1:0] net_k   = layer[D-1].k_q;
    wire [CW-1:0]    net_c   = layer[D-1].c_q;
    wire [3:0]       net_ch  = layer[D-1].ch_q;
    wire [3:0]       net_nch = layer[D-1].nch_q;
    wire             net_single = net_v && (net_nch == 4'd1);
    wire             net_run    = net_v && (net_nch != 4'd1);
    wire             net_last   = net_run && (net_ch == net_nch - 4'd1);

    // Run buffers and the merger.
    localparam [PW:0] N1 = N;
    reg [MAX_KEYS*SKW-1:0] buf_a, buf_b;
    reg          merging, setup, src_b, m_done;
    reg [PW-1:0] i, j, le, re, o, run;
    reg [CW-1:0] m_count;
    wire [MAX_KEYS*SKW-1:0] src = src_b ? buf_b : buf_a;
    wire [PW-1:0] i_rd = (i < MAX_KEYS) ? i : {PW{1'b0}};
    wire [PW-1:0] j_rd = (j < MAX_KEYS) ? j : {PW{1'b0}};
    wire [SKW-1:0] ki = src[i_rd*SKW +: SKW];
    wire [SKW-1:0] kj = src[j_rd*SKW +: SKW];
    wire take_left = (i < le) && ((j >= re) || (ki <= kj));
    wire [SKW-1:0] k_out = take_left ? ki : kj;
    wire [PW-1:0] cnt_p = {{(PW - CW){1'b0}}, m_count};
    wire [PW-1:0] cnt_n = {{(PW - CW){1'b0}}, net_c};
    wire [PW:0]   run2 = {run, 1'b0};
    wire [PW:0]   run4 = {run, 1'b0} << 1;
    wire [PW:0]   re_r  = {1'b0, re} + {1'b0, run};
    wire [PW:0]   re_2r = {1'b0, re} + run2;
    wire          pair_end = (o + 1'b1 == re);
    wire          pass_end = pair_end && (re == cnt_p);
    function [PW-1:0] min_p(input [PW:0] x, input [PW-1:0] y);
        min_p = (x < {1'b0, y}) ? x[PW-1:0] : y;
    endfunction
    always @(posedge clk) begin
        m_done <= 1'b0;
        if (net_run)                     // sorted chunk k to run k of buffer A
            buf_a[net_ch*N*SKW +: N*SKW] <= net_k;
        if (rst) begin
            merging <= 1'b0;
            setup   <= 1'b0;
        end else if (net_last) begin     // setup of pass 1 (runs of N, A to B)
            merging <= 1'b1;
            src_b   <= 1'b0;
            m_count <= net_c;
            run     <= N1[PW-1:0];
            i       <= {PW{1'b0}};
            j       <= min_p(N1, cnt_n);
            le      <= min_p(N1, cnt_n);
            re      <= min_p(N1 << 1, cnt_n);
            o       <= {PW{1'b0}};
        end else if (setup) begin        // setup of the next pass: runs twice as long
            setup   <= 1'b0;
            merging <= 1'b1;
            src_b   <= !src_b;
            run     <= run2[PW-1:0];
            i       <= {PW{1'b0}};
            j       <= min_p(run2, cnt_p);
            le      <= min_p(run2, cnt_p);
            re      <= min_p(run4, cnt_p);
            o       <= {PW{1'b0}};
        end else if (merging) begin      // one key per cycle
            if (src_b) buf_a[o*SKW +: SKW] <= k_out;
            else       buf_b[o*SKW +: SKW] <= k_out;
            if (take_left) i <= i + 1'b1; else j <= j + 1'b1;
            o <= o + 1'b1;
            if (pass_end) begin
                merging <= 1'b0;
                if (run2 >= {1'b0, cnt_p}) begin   // one run left: the result
                    m_done <= 1'b1;
                    src_b  <= !src_b;
                end else begin
                    setup <= 1'b1;
                end
            end else if (pair_end) begin          // the next pair of runs
                i  <= re;
                j  <= min_p(re_r, cnt_p);
                le <= min_p(re_r, cnt_p);
                re <= min_p(re_2r, cnt_p);
            end
        end
    end

    // Output: a one-chunk ray from the network's last register, a merged one from the
    // buffer its last pass wrote; never both in one cycle (in_ready's hold).
    wire [MAX_KEYS*SKW-1:0] res = src_b ? buf_b : buf_a;
    assign out_valid = net_single || m_done;
    assign out_count = m_done ? m_count : net_c;
    genvar k;
    generate
        for (k = 0; k < MAX_KEYS; k = k + 1) begin : lane
            wire [SKW-1:0] sk = m_done ? res[k*SKW +: SKW] :
                                (k < N) ? net_k[(k % N)*SKW +: SKW] : {SKW{1'b1}};
            // Lanes below the count are valid keys; the invalid bit is a second guard.
            wire live = (k < out_count) && !sk[KB];
            // Port order {id, t} from the sort order {invalid, t, id}.
            assign out_keys[k*KB +: KB] = live ? {sk[IW-1:0], sk[IW +: KW]} : {KB{1'b0}};
        end
    endgenerate
endmodule
`default_nettype wire
