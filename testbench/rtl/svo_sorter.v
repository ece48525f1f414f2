// svo_sorter: the candidate sorter of one ray: an N-lane sorting network (the model's for N:
// 19 comparators, depth 6 for 8 lanes; 60 and 10 for 16) on chunks of N keys, then two-way
// merge passes over the sorted runs when a ray has more than N candidates
// (rtl_model/src/units/sorter.rs `Sorter::sort`, docs/units/sorter.md). The network comes in
// as parameters N, D and PAIRS, which the vectors' package carries from the model.
//
// Pipeline position: after the sphere tests, before the hit-buffer check. Formats (parameters,
// from the vectors' package): a key is {id, t} with t the entry distance (KW = 32 bits,
// uQ10.22) in the low bits and the instance id (IW = 8 bits) above it; keys compare as the
// tuple (t, id), so equal entry distances go lower id first. A ray is in_count keys (up to
// MAX_KEYS, more are cut) in arrival order on in_keys, key k at [k*(KW+IW) +: KW+IW]; the result
// is the same keys in (t, id) order on out_keys, lanes at or above the count 0.
//
// Network: PAIRS by layers, one register per layer (D cycles, II = 1); lanes at or above the
// count carry an invalid bit above t that sorts them last. A ray of
// C = ceil(count / N) > 1 chunks issues chunk k on cycle k from a shift-register copy of the
// ray, writes the sorted chunks into run buffer A, then merges neighbouring runs
// (N, 2N, ...) from one buffer into the other, one key per cycle, until one run is left: each pass takes
// one setup cycle (MERGE_LATENCY) and count cycles; on equal keys the left run goes first,
// as the model's merge.
//
// Placed for 300 MHz (docs/cycle-model.md §1.5; Yosys does not retime): no stage reads a
// buffer through a multiplexer and compares in the same cycle. The merger keeps both run
// heads and their successors in registers, compares the heads, writes the winner and refills
// the winner's successor from a pointer register (a read straight into a register); the next
// pair's keys are read ahead, the next pass's first keys captured as they are written. The
// count's consequences (chunks, in_ready's hold) are a table over in_count, in_ready is a
// register, and every variable index is a multiplexer or a decoder on a register, never a
// product (no DSP48E2).
//
// Timing, the cycle model's (`units::sorter::pipe_cost` in a `UnitPipe` of latency D; the
// sorter's vector rows carry it per ray as `cycles` and `busy`):
//   latency: D for one chunk (a ray without keys too: an empty issue), else
//            (C - 1) + D + P * (count + 1) with P = ceil(log2 C) passes;
//   in_ready: high again 1 cycle after accepting a one-chunk ray (II = 1), and
//            C + P * (count + 1) cycles after a merged one: the next ray's network pass then
//            ends after this ray's merge, so one merger serves every ray and results leave in
//            order without a reorder buffer.
`timescale 1ns/1ps
`default_nettype none
// The model's BEST_8 network in PAIRS' encoding: the default, so the default width
// synthesises without the vectors (tb_sorter.sv checks it equals the package's NET_PAIRS).
`define SVO_SORTER_BEST_8 384'h000005060304010200000000030601040000000003050204060704050203000103070206010500040507040601030002
module svo_sorter #(
    parameter KW = 32,
    parameter IW = 8,
    parameter N = 8,                     // network lanes (the datapath's sorter.n), 2..255
    parameter D = 6,                     // network layers = latency
    parameter S = (N > 3) ? N / 2 : 1,   // comparator slots per layer of PAIRS
    // The network: layer l, slot p as {i[7:0], j[7:0]}, i < j < N, at [(l*S + p)*16 +: 16];
    // unused slots 0. The vectors' package writes the model's network for its N (NET_PAIRS,
    // rtl_model/src/vectors/stage/sorter.rs `NetworkPairs`), and the testbench passes it; the
    // default is the model's BEST_8 (checked against the package by tb_sorter.sv) so the
    // default width synthesises on its own. Any other N without PAIRS is refused below.
    /* verilator lint_off WIDTH */       // the default's 384 bits, zero-extended at other N
    parameter [D*S*16-1:0] PAIRS = (N == 8 && D == 6 && S == 4) ?
        `SVO_SORTER_BEST_8 : {(D*S*16){1'b0}},
    /* verilator lint_on WIDTH */
    parameter MAX_KEYS = 4 * N,          // a multiple of N, at most 15 chunks
    parameter CW = $clog2(MAX_KEYS + 1)  // bits of a count 0..MAX_KEYS
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
    // One network pass: a ray with at most N candidates; the testbench prints it (tb_*.sv: "rtl LATENCY"), tests/testbench_icarus.rs
    // compares it with the model's units.* latency and with the latency measured.
    /* verilator lint_off UNUSEDPARAM */
    localparam LATENCY = D;
    /* verilator lint_on UNUSEDPARAM */
    localparam KB = KW + IW;             // key bits in the ports
    localparam SKW = KB + 1;             // sort key {invalid, t, id}
    localparam PW = $clog2(MAX_KEYS + 3) + 1;  // pointer bits: 0..MAX_KEYS + 2, and sums
    localparam NCH = MAX_KEYS / N;       // chunks of a full ray
    localparam LW = $clog2(MAX_KEYS);    // lane index bits of the read multiplexers
    // The default network, read by tb_sorter.sv's check against the package.
    /* verilator lint_off UNUSEDPARAM */
    localparam [383:0] BEST_8_PAIRS = `SVO_SORTER_BEST_8;
    /* verilator lint_on UNUSEDPARAM */
    // The lane lane q meets in layer l (q itself when it has no comparator there).
    function integer partner(input integer l, input integer q);
        integer p, a, b;
        begin
            partner = q;
            for (p = 0; p < S; p = p + 1) begin
                a = {24'd0, PAIRS[(S*l + p)*16 + 8 +: 8]};
                b = {24'd0, PAIRS[(S*l + p)*16 +: 8]};
                if (a != b && a == q) partner = b;
                if (a != b && b == q) partner = a;
            end
        end
    endfunction
    // Whether PAIRS is a network of N lanes: some comparator, each used slot i < j < N, no
    // lane twice in a layer; and the ray's shape fits: MAX_KEYS a multiple of N, 1..15 chunks.
    function integer pairs_ok(input integer unused);
        integer l, p, a, b, used, any;
        reg [255:0] seen;
        begin
            pairs_ok = ((MAX_KEYS % N == 0) && (NCH >= 1) && (NCH <= 15) && (N >= 2) && (N <= 255)) ? 1 : 0;
            any = 0;
            for (l = 0; l < D; l = l + 1) begin
                seen = 256'd0;
                for (p = 0; p < S; p = p + 1) begin
                    a = {24'd0, PAIRS[(S*l + p)*16 + 8 +: 8]};
                    b = {24'd0, PAIRS[(S*l + p)*16 +: 8]};
                    used = ((a != 0) || (b != 0)) ? 1 : 0;
                    if (used != 0) begin
                        any = 1;
                        if (a >= b || b >= N || seen[a] || seen[b]) pairs_ok = 0;
                        seen[a] = 1'b1;
                        seen[b] = 1'b1;
                    end
                end
            end
            if (any == 0) pairs_ok = 0;
        end
    endfunction
    localparam PAIRS_OK = pairs_ok(0);
    // A width without the model's pairs (or pairs that are not a network of N lanes) stops
    // the elaboration here, in every tool: the module below does not exist.
    generate
        if (PAIRS_OK == 0) begin : refuse
            svo_sorter_has_no_valid_PAIRS_for_this_N_see_sorter_pkg_NET_PAIRS no_network ();
        end
    endgenerate

    // What a ray's count decides, a table over every in_count (constants: a small ROM
    // of LUTs, no arithmetic on the input): {in_ready's hold after the accept, occupancy - 1
    // (16 bits); the chunks C (4 bits, 1 for an empty ray)}, occupancy = 1 for C = 1, else
    // C + P*(count + 1) with P = ceil(log2 C) merge passes.
    localparam CT = 1 << CW;
    function [19:0] count_info(input integer c);
        integer cnt, ch, p, b;
        /* verilator lint_off UNUSEDSIGNAL */
        integer occ;                     // below 2^16: only its low 16 bits are read
        /* verilator lint_on UNUSEDSIGNAL */
        reg [15:0] occ16;
        begin
            cnt = (c > MAX_KEYS) ? MAX_KEYS : c;
            ch = (cnt + N - 1) / N;
            if (ch == 0) ch = 1;
            p = 0;
            for (b = 0; b < 8; b = b + 1)
                if ((1 << b) < ch) p = b + 1;
            occ = (ch <= 1) ? 1 : ch + p * (cnt + 1);
            occ16 = occ[15:0];
            count_info = {occ16 - 16'd1, ch[3:0]};
        end
    endfunction
    function [CT*32-1:0] info_table(input integer unused);
        integer c;
        begin
            info_table = {CT*32{1'b0}};
            for (c = 0; c < CT; c = c + 1)
                info_table[c*32 +: 32] = {12'd0, count_info(c)};
        end
    endfunction
    localparam [CT*32-1:0] INFO = info_table(0);
    wire [19:0]   info    = INFO[{in_count, 5'd0} +: 20];
    wire [15:0]   hold_in = info[19:4];
    wire [3:0]    nchunks_in = info[3:0];
    wire [CW-1:0] cnt_in  = (in_count > MAX_KEYS[CW-1:0]) ? MAX_KEYS[CW-1:0] : in_count;

    // Input: one ray per in_ready; in_ready falls for occupancy - 1 cycles after an accept
    // (a register: ready = (hold == 0) of the next cycle).
    reg  [15:0] hold;
    reg         ready_q;
    wire        accept = in_valid && ready_q;
    assign in_ready = ready_q;
    always @(posedge clk) begin
        if (rst) begin
            hold <= 16'd0;
            ready_q <= 1'b1;
        end else if (accept) begin
            hold <= hold_in;
            ready_q <= (hold_in == 16'd0);
        end else begin
            if (hold != 16'd0) hold <= hold - 16'd1;
            ready_q <= (hold <= 16'd1);
        end
    end

    // The ray as sort keys: {invalid, t, id}, lanes at or above the count invalid
    // (k < cnt_in is in_count > k for every lane k < MAX_KEYS).
    function [MAX_KEYS*SKW-1:0] to_sort(input [MAX_KEYS*KB-1:0] keys, input [CW-1:0] cnt);
        integer k;
        begin
            for (k = 0; k < MAX_KEYS; k = k + 1)
                to_sort[k*SKW +: SKW] = (k < {{(32 - CW){1'b0}}, cnt}) ?
                    {1'b0, keys[k*KB +: KW], keys[k*KB + KW +: IW]} : {1'b1, {KB{1'b0}}};
        end
    endfunction

    // Feeder: chunks 1..C-1 of a merged ray, one per cycle after the accept, from a shift
    // register (chunk 1 at the bottom); `feeding` is a register, so the network's input
    // multiplexer has no logic before it.
    reg [MAX_KEYS*SKW-1:0] f_keys;
    reg [CW-1:0]           f_count;
    reg [3:0]              f_next, f_chunks;
    reg                    feeding;
    wire [MAX_KEYS*SKW-1:0] in_sort = to_sort(in_keys, in_count);
    always @(posedge clk) begin
        if (rst) begin
            feeding <= 1'b0;
        end else if (accept) begin
            f_keys   <= in_sort >> (N*SKW);
            f_count  <= cnt_in;
            f_next   <= 4'd1;
            f_chunks <= nchunks_in;
            feeding  <= (nchunks_in > 4'd1);
        end else if (feeding) begin
            f_keys   <= f_keys >> (N*SKW);
            f_next   <= f_next + 4'd1;
            feeding  <= (f_next + 4'd1 < f_chunks);
        end
    end

    // Network input: chunk 0 at the accept, then the feeder's chunks (an accept never falls
    // in a feeding cycle: in_ready is low for C - 1 + P*(count + 1) cycles after it).
    wire          n_valid = accept || feeding;
    wire [N*SKW-1:0] n_keys  = feeding ? f_keys[0 +: N*SKW] : in_sort[0 +: N*SKW];
    wire [CW-1:0] n_count = feeding ? f_count : cnt_in;
    wire [3:0]    n_chunk = feeding ? f_next : 4'd0;
    wire [3:0]    n_nch   = feeding ? f_chunks : nchunks_in;

    // The network: layer l's compare-exchanges, then its register.
    genvar l, q;
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
            wire [N*SKW-1:0] k_ce;
            for (q = 0; q < N; q = q + 1) begin : ce
                localparam integer P = partner(l, q);
                localparam integer LO = (P < q) ? P : q;
                localparam integer HI = (P < q) ? q : P;
                if (P == q) begin : pass
                    assign k_ce[q*SKW +: SKW] = k_in[q*SKW +: SKW];
                end else begin : cmp
                    wire [SKW-1:0] a = k_in[LO*SKW +: SKW];
                    wire [SKW-1:0] b = k_in[HI*SKW +: SKW];
                    wire           swap = a > b;
                    assign k_ce[q*SKW +: SKW] = ((q == LO) == swap) ? b : a;
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

    // Run buffers and the merger. The merge never reads and compares in one cycle: the two
    // run heads (hi = src[i], hj = src[j]) and their successors (ni = src[i+1],
    // nj = src[j+1]) are registers; a step compares the heads, writes the winner at o, and
    // shifts the winner's run: its head takes the successor, the successor is read from src at
    // the index + 2 (a pointer register i2 / j2 straight into the register). The next pair's
    // heads and successors are read ahead into pf_* (from re and nxj, the next pair's indices;
    // a pair before the last of a pass is 2*run >= 2N steps, time enough for N >= 4); the next pass's are
    // captured while this pass writes them (c_*: indices 0, 1, sj, sj + 1), so its setup
    // cycle (MERGE_LATENCY) only copies registers. Pass 1's heads are chunks 0 and 1 as the
    // network delivers them (the previous ray's merge ended 2 cycles before chunk 0 arrives).
    /* verilator lint_off WIDTH */       // N below 2^(PW+2): MAX_KEYS >= N
    localparam [PW+2:0] N1 = N;
    /* verilator lint_on WIDTH */
    localparam [PW-1:0] TWO = 2;
    reg [MAX_KEYS*SKW-1:0] buf_a, buf_b;
    reg          merging, setup, src_b, m_done;
    reg [PW-1:0] i, j, le, re, o, run, i2, j2;
    reg [CW-1:0] m_count;
    reg          li, rj, pe, last, fin;  // i < le, j < re, o + 1 == re, re == count, final pass
    reg [SKW-1:0] hi, ni, hj, nj;
    reg [PW-1:0] nxj, nxre, pfa, pfb, pfc, pfd;
    reg [SKW-1:0] pf_hi, pf_ni, pf_hj, pf_nj;
    reg [PW-1:0] sj, sre;
    reg [SKW-1:0] c_hi, c_ni, c_hj, c_nj;
    wire [MAX_KEYS*SKW-1:0] src = src_b ? buf_b : buf_a;
    // One key of b at index x: a multiplexer tree on x's low LW bits (an index beyond the
    // keys reads some lane; the merge never uses such a read).
    function [SKW-1:0] pick(input [MAX_KEYS*SKW-1:0] b, input [PW-1:0] x);
        reg [(1 << LW)*SKW-1:0] t;
        integer s, k;
        begin
            t = {((1 << LW)*SKW){1'b0}};
            t[MAX_KEYS*SKW-1:0] = b;
            for (s = 0; s < LW; s = s + 1)
                for (k = 0; k < ((1 << LW) >> (s + 1)); k = k + 1)
                    t[k*SKW +: SKW] = x[s] ? t[(2*k + 1)*SKW +: SKW] : t[2*k*SKW +: SKW];
            pick = t[0 +: SKW];
        end
    endfunction
    function [PW-1:0] min_p(input [PW+2:0] x, input [PW-1:0] y);
        min_p = (x < {3'b000, y}) ? x[PW-1:0] : y;
    endfunction
    wire [PW-1:0]  cnt_p = {{(PW - CW){1'b0}}, m_count};
    wire [PW-1:0]  cnt_n = {{(PW - CW){1'b0}}, net_c};
    wire [PW+2:0]  run_w = {3'b000, run};
    wire [PW+2:0]  re_w  = {3'b000, re};
    wire [PW-1:0]  p1_j  = min_p(N1, cnt_n);         // pass 1: j = le
    wire [PW-1:0]  p1_re = min_p(N1 << 1, cnt_n);    // pass 1: re
    wire           take_left = li && (!rj || (hi <= hj));
    wire [SKW-1:0] k_out = take_left ? hi : hj;
    wire           pass_end = pe && last;
    integer c, w;
    always @(posedge clk) begin
        m_done <= 1'b0;
        // The next pair's indices and keys, read ahead (src does not change within a pass).
        nxj   <= min_p(re_w + run_w, cnt_p);
        nxre  <= min_p(re_w + (run_w << 1), cnt_p);
        pfa   <= re;
        pfb   <= re + 1'b1;
        pfc   <= nxj;
        pfd   <= nxj + 1'b1;
        pf_hi <= pick(src, pfa);
        pf_ni <= pick(src, pfb);
        pf_hj <= pick(src, pfc);
        pf_nj <= pick(src, pfd);
        // Sorted chunk k to run k of buffer A; chunks 0 and 1 are pass 1's first pair.
        for (c = 0; c < NCH; c = c + 1)
            if (net_run && net_ch == c[3:0]) buf_a[c*N*SKW +: N*SKW] <= net_k;
        if (net_run && net_ch == 4'd0) begin
            hi <= net_k[0 +: SKW];
            ni <= net_k[SKW +: SKW];
        end
        if (net_run && net_ch == 4'd1) begin
            hj <= net_k[0 +: SKW];
            nj <= net_k[SKW +: SKW];
        end
        if (rst) begin
            merging <= 1'b0;
            setup   <= 1'b0;
        end else if (net_last) begin     // setup of pass 1 (runs of N, A to B)
            merging <= 1'b1;
            src_b   <= 1'b0;
            m_count <= net_c;
            run     <= N1[PW-1:0];
            i       <= {PW{1'b0}};
            j       <= p1_j;
            le      <= p1_j;
            re      <= p1_re;
            o       <= {PW{1'b0}};
            i2      <= 2;
            j2      <= p1_j + TWO;
            li      <= 1'b1;
            rj      <= (p1_j < p1_re);
            pe      <= (p1_re == 1);
            last    <= (p1_re == cnt_n);
            sj      <= min_p(N1 << 1, cnt_n);
            sre     <= min_p(N1 << 2, cnt_n);
            fin     <= ((N1 << 1) >= {3'b000, cnt_n});
        end else if (setup) begin        // setup of the next pass: runs twice as long
            setup   <= 1'b0;
            merging <= 1'b1;
            src_b   <= !src_b;
            run     <= {run[PW-2:0], 1'b0};
            i       <= {PW{1'b0}};
            j       <= sj;
            le      <= sj;
            re      <= sre;
            o       <= {PW{1'b0}};
            i2      <= 2;
            j2      <= sj + TWO;
            li      <= 1'b1;
            rj      <= (sj < sre);
            pe      <= (sre == 1);
            last    <= (sre == cnt_p);
            hi      <= c_hi;
            ni      <= c_ni;
            hj      <= c_hj;
            nj      <= c_nj;
            sj      <= min_p(run_w << 2, cnt_p);
            sre     <= min_p(run_w << 3, cnt_p);
            fin     <= ((run_w << 2) >= {3'b000, cnt_p});
        end else if (merging) begin      // one key per cycle
            for (w = 0; w < MAX_KEYS; w = w + 1)
                if (o == w[PW-1:0]) begin
                    if (src_b) buf_a[w*SKW +: SKW] <= k_out;
                    else       buf_b[w*SKW +: SKW] <= k_out;
                end
            if (o == 0) c_hi <= k_out;
            if (o == 1) c_ni <= k_out;
            if (o == sj) c_hj <= k_out;
            if (o == sj + 1'b1) c_nj <= k_out;
            o <= o + 1'b1;
            if (pass_end) begin
                merging <= 1'b0;
                if (fin) begin           // one run left: the result
                    m_done <= 1'b1;
                    src_b  <= !src_b;
                end else begin
                    setup <= 1'b1;
                end
            end else if (pe) begin       // the next pair of runs
                i    <= re;
                j    <= nxj;
                le   <= nxj;
                re   <= nxre;
                i2   <= re + TWO;
                j2   <= nxj + TWO;
                hi   <= pf_hi;
                ni   <= pf_ni;
                hj   <= pf_hj;
                nj   <= pf_nj;
                li   <= (re < nxj);
                rj   <= (nxj < nxre);
                pe   <= (re + 1'b1 == nxre);
                last <= (nxre == cnt_p);
            end else begin
                if (take_left) begin
                    i  <= i + 1'b1;
                    i2 <= i2 + 1'b1;
                    hi <= ni;
                    ni <= pick(src, i2);
                    li <= (i + 1'b1 < le);
                end else begin
                    j  <= j + 1'b1;
                    j2 <= j2 + 1'b1;
                    hj <= nj;
                    nj <= pick(src, j2);
                    rj <= (j + 1'b1 < re);
                end
                pe <= (o + TWO == re);
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
