// svo_walker: one octree walker with one ray context: the stack-based walk of
// rtl_model/src/units/walker.rs (Revelles et al. 2000, fixed point), cycle for cycle as the
// cycle model's walker pool times a context (rtl_model/src/cycle/walker_pool.rs, §2.3 of
// docs/cycle-model.md).
//
// Pipeline position: after svo_walker_root (the root slabs) and the dispatcher; its result
// goes to the record stage. It reads the SVO memory image (docs/svo-format.md) through one
// read port with valid/ready; every read returns mem_resp_valid with the data some cycles
// later (any latency of at least one cycle, one read outstanding: the context waits for each).
//
// Timing (what the model counts, and so what walker.hex's cycles_* predict):
//   accept (cycle D)        the root descriptor is requested in D + 1 (a root miss leaves in
//                           D + 1 with no read);
//   an issue slot (cycle X) is a child examined or a stack pop; its successor comes in
//                           X + STEP_LATENCY: the next slot, a read request, or the result;
//   a read's data (cycle C) a descriptor pushes the child's frame and issues its first slot
//                           in C; a far word requests the child's slot in C; a leaf slot
//                           requests the attribute record in C; the attribute record is the
//                           result, out_valid in C.
// Where the registers are (Yosys does not retime, so the RTL places them; each stage fits
// 300 MHz by docs/cycle-model.md §1.5's rule):
//   X + 1 (S_COMP, stage A) from the top frame's registers f_* only: the child's t0/t1 (the
//       cc-multiplexers), registered into c_t0/c_t1 with its coordinates, level and zero-axis
//       centre c_g; every wide comparison in parallel, registered as bits (a_*): the 9 pairs
//       t0_a < t1_b (max t0 < min t1 holds iff all do), t1_b > 0 (min t1 > 0 iff all are),
//       the 3 pairs of t1 (next child, table 3), the 3 pairs of t0 (entry axis) and t0_k > 0;
//       the child's valid/leaf bits, its slot (selected from f_pc, the frame's counts of valid
//       children below each label, registered from the descriptor as it arrives and then
//       every cycle from f_desc), the group base address, the step limit and the
//       stack-overflow tests. A pop (f_next = 8) is decided here and loads the parent from the
//       stack in this cycle (its g and d updated beside it).
//   X + 2 (the first S_HOLD cycle, stage B, b_dec set): those bits make the decision — the
//       next child, steps, the visit, the request (address = base + slot), pend, the
//       outcome fields (max(entry, 0) is the t0 selected by the entry-axis bits) — and what
//       follows the hold; the remaining STEP_LATENCY - 3 hold cycles only wait.
//   The child's midpoints and first child are not in the step: c_tm is registered every
//       cycle from c_t0/c_t1 (or, on a zero axis, from c_g) and c_first every cycle from
//       c_t0/c_tm: c_tm at the end of X + 2, c_first at the end of X + 3, so both are there
//       when the descriptor can first arrive (request in X + STEP_LATENCY >= X + 3, data at
//       least one cycle later); the root's c_tm is registered in the accept cycle D from the
//       inputs and its c_first in D + 1, before its descriptor (request D + 1, data
//       >= D + 2). The descriptor's arrival copies c_* into f_*.
//
// Arithmetic as the model: children by the midpoints tm = floor((t0 + t1)/2) (halves plus the
// carry of the low bits); zero axes take +inf / -inf from the origin's side of the node's
// centre plane: +inf iff ox < floor(-e + (2m + 1)·e / 2^level) (m the mirrored coordinate).
// The walker keeps that centre exactly, without a product: g = centre - (ox + 1), in
// F = STACK_DEPTH fraction bits (a frame's level is at most STACK_DEPTH - 1, its children's
// centres need level + 1 fraction bits), so +inf iff g >= 0 (ox + 1 <= centre iff
// ox < floor(centre), ox an integer). The root's centre is 0 (g = ~ox); a child's is its
// parent's ± e / 2^(level + 1), + when the child's mirrored bit (= cc's bit) is 1; the top
// frame keeps d = e / 2^(level + 1) (f_d, halved on a descent, doubled on a pop) and a pop
// takes g back by ∓ 2d from the popped child's bit. Child order by Revelles' tables 1-3
// (first child from the midpoints crossed before the entry, next child from the exit plane,
// ties x, y, z); a child is entered when max(t0) < min(t1) and min(t1) > 0. Negative axes are
// mirrored (label ^ a). Steps count children examined, fetches the root and each node
// descended into; a walk that examines more than MAX_STEPS children stops with outcome 2. A
// descent that would need more than STACK_DEPTH frames stops with outcome 3 (stack overflow;
// the model's stack never overflows at its default depth, so the vectors never expect it).
//
// Widths from walker_pkg.sv: POS_W (walker.pos, the origin after mirroring is POS_W + 1 bits),
// T_W (walker.t; t values carry one more bit for the +-inf sentinels). The memory word is 64
// bits: a node word in the low 32 bits, an attribute record whole.
`timescale 1ns/1ps
`default_nettype none
module svo_walker #(
    parameter POS_W        = 40,
    parameter T_W          = 62,
    parameter STACK_DEPTH  = 21,
    parameter MAX_STEPS    = 100000,
    parameter STEP_LATENCY = 3,
    parameter TAG_W        = 1
) (
    input  wire                   clk,
    input  wire                   rst,
    // A walk from svo_walker_root (plus the image's memory bases).
    input  wire                   in_valid,
    output wire                   in_ready,
    input  wire                   in_enter,
    input  wire [3*(T_W+1)-1:0]   in_t0,
    input  wire [3*(T_W+1)-1:0]   in_t1,
    input  wire [3*(POS_W+1)-1:0] in_o,
    input  wire [3*POS_W-1:0]     in_half,
    input  wire [2:0]             in_zero,
    input  wire [2:0]             in_neg,
    input  wire [31:0]            in_node_base,
    input  wire [31:0]            in_attr_base,
    input  wire [TAG_W-1:0]       in_tag,
    // Memory read port.
    output wire                   mem_req_valid,
    input  wire                   mem_req_ready,
    output wire                   mem_req_attr,   // 1: attribute record, 0: node word
    output wire [31:0]            mem_req_addr,
    input  wire                   mem_resp_valid,
    input  wire [63:0]            mem_resp_data,
    // The walk's result.
    output wire                   out_valid,
    input  wire                   out_ready,
    output reg  [1:0]             out_outcome,    // 0 miss, 1 hit, 2 step limit, 3 stack overflow
    output reg  [T_W-1:0]         out_t,          // max(entry, 0) of the hit leaf
    output reg  [59:0]            out_voxel,      // {z, y, x}, 20 bits each
    output reg  [4:0]             out_level,
    output reg  [31:0]            out_attr,
    output reg  [1:0]             out_entry_axis,
    output reg  [31:0]            out_steps,
    output reg  [31:0]            out_fetches,
    output wire [63:0]            out_attr_data,  // the hit leaf's attribute record
    output reg  [TAG_W-1:0]       out_tag,
    // Each node entered (for node-by-node checks).
    output reg                    visit_valid,
    output reg  [4:0]             visit_level,
    output reg  [59:0]            visit_coords,   // {z, y, x}
    // The pool's scheduler (svo_walker_pool, whose walker this is at one context a walker;
    // svo_walker_barrel is the walker of several, the same step with its contexts' state in
    // RAMs): an issue slot is taken only in a cycle with issue_grant (tie to 1 for a walker of
    // its own); issue_req asks for one.
    // ev_* mark the cycle the context moves on to its next op, as the model's wake-up:
    // ev_lat (its step latency ended), ev_disp (the cycle after its walk was accepted),
    // ev_resp (its read completed).
    input  wire                   issue_grant,
    output wire                   issue_req,
    output reg                    ev_lat,
    output reg                    ev_disp,
    output wire                   ev_resp
);
    localparam TI = T_W + 1;
    localparam signed [TI-1:0] NEG_INF = {1'b1, {(TI-1){1'b0}}};
    localparam signed [TI-1:0] POS_INF = {1'b0, {(TI-1){1'b1}}};
    localparam signed [TI-1:0] T_ZERO = {TI{1'b0}};
    localparam F = STACK_DEPTH;                    // fraction bits of a zero axis's centre
    localparam GW = POS_W + 2 + F;                 // g = centre - (ox + 1) and d, signed
    localparam FW = 9*TI + 32 + 32 + 4 + 5 + 60;   // a stack frame
    localparam HOLD = STEP_LATENCY - 2;
    localparam SPW = $clog2(STACK_DEPTH) + 1;     // stack pointer bits (0 .. STACK_DEPTH - 1)
    localparam IW = $clog2(STACK_DEPTH - 1) > 0 ? $clog2(STACK_DEPTH - 1) : 1;  // index of stk

    localparam [2:0] S_IDLE = 3'd0, S_REQ = 3'd1, S_MEMW = 3'd2, S_ISSUE = 3'd3,
                     S_COMP = 3'd4, S_HOLD = 3'd5, S_OUT = 3'd6;
    localparam [1:0] P_DESC = 2'd0, P_FAR = 2'd1, P_LEAF = 2'd2, P_ATTR = 2'd3;
    localparam [1:0] A_ISSUE = 2'd0, A_REQ = 2'd1, A_OUT = 2'd2;

    reg [2:0] st;
    reg [1:0] pend;
    reg [1:0] act;                                 // what follows the hold
    reg [7:0] hold_left;
    reg       b_dec;                               // stage B decides in this S_HOLD cycle

    // The walk's constants.
    reg [2:0]  w_zero;
    reg [2:0]  w_a;                                // mirror mask: bit 2 - k for axis k
    reg [31:0] w_attr_base;

    // The top frame.
    reg signed [TI-1:0] f_t0 [0:2];
    reg signed [TI-1:0] f_t1 [0:2];
    reg signed [TI-1:0] f_tm [0:2];
    reg [31:0] f_addr, f_desc;
    reg [3:0]  f_next;
    reg [4:0]  f_level;
    reg [19:0] f_c [0:2];
    reg signed [GW-1:0] f_g [0:2];                 // zero axes: centre - (ox + 1)
    reg signed [GW-1:0] f_d [0:2];                 // zero axes: e / 2^(level + 1)
    reg [2:0]  f_pc [0:7];                         // f_pc[r]: valid children below label r

    // Frames below the top.
    reg [FW-1:0] stk [0:STACK_DEPTH-2];
    reg [SPW-1:0] sp;                              // frames in stk

    // The child being examined (stage A) and then read.
    reg signed [TI-1:0] c_t0 [0:2];
    reg signed [TI-1:0] c_t1 [0:2];
    reg signed [TI-1:0] c_tm [0:2];
    reg signed [GW-1:0] c_g [0:2];
    reg [3:0]  c_first;
    reg [4:0]  c_level;
    reg [19:0] c_c [0:2];
    reg [31:0] c_addr;
    reg [31:0] c_fa;                               // parent address + slot (far escape)
    reg        c_leaf, c_root;

    // Stage A's results.
    reg [8:0]  a_lt;                               // bit 3a + b: t0_a < t1_b
    reg [2:0]  a_pos;                              // t1_b > 0
    reg        a_n01, a_n02, a_n12;                // t1_0 <= t1_1, t1_0 <= t1_2, t1_1 <= t1_2
    reg        a_e01, a_e02, a_e12;                // t0_0 >= t0_1, t0_0 >= t0_2, t0_1 >= t0_2
    reg [2:0]  a_t0pos;                            // t0_k > 0
    reg        a_valid, a_leaf, a_far, a_lim, a_ovf;
    reg [3:0]  a_slot;                             // popcount of the lower valid bits
    reg [31:0] a_base;                             // parent address + child pointer

    reg [31:0] req_addr;
    reg        req_attr;
    reg [31:0] steps, fetches;
    reg [63:0] attr_data;

    // ---- Combinational helpers ----------------------------------------------------------
    // floor((a + b)/2) of two t codes: the halves plus the carry of the low bits.
    function automatic signed [TI-1:0] mid_t(input signed [TI-1:0] a, input signed [TI-1:0] b);
        mid_t = (a >>> 1) + (b >>> 1) + $signed({{(TI-1){1'b0}}, a[0] & b[0]});
    endfunction
    // Valid children with a label below r, for every r (a child's slot in its group): from
    // the descriptor's valid mask. Full adders in logic, so each count is a LUT function of
    // at most 7 bits and no carry chain.
    function automatic [2:0] popcount7(input [6:0] v);
        reg s1, c1, s2, c2, c3;
        begin
            s1 = v[0] ^ v[1] ^ v[2];
            c1 = (v[0] & v[1]) | (v[0] & v[2]) | (v[1] & v[2]);
            s2 = v[3] ^ v[4] ^ v[5];
            c2 = (v[3] & v[4]) | (v[3] & v[5]) | (v[4] & v[5]);
            popcount7[0] = s1 ^ s2 ^ v[6];
            c3 = (s1 & s2) | (s1 & v[6]) | (s2 & v[6]);
            popcount7[1] = c1 ^ c2 ^ c3;
            popcount7[2] = (c1 & c2) | (c1 & c3) | (c2 & c3);
        end
    endfunction
    function automatic [23:0] prefix_counts(input [6:0] valid);   // labels 0..6
        integer r;
        begin
            for (r = 0; r < 8; r = r + 1)
                prefix_counts[3*r +: 3] = popcount7(valid & ~(7'h7f << r));
        end
    endfunction
    wire taking = in_valid && in_ready;
    wire [2:0] in_a = {in_neg[0], in_neg[1], in_neg[2]};

    // ---- Stage A (S_COMP): everything from the top frame --------------------------------
    wire [2:0]  cc = f_next[2:0];
    wire        popping = f_next[3];               // f_next = 8
    reg signed [TI-1:0] s_t0 [0:2];
    reg signed [TI-1:0] s_t1 [0:2];
    reg signed [GW-1:0] s_g [0:2];                 // the child's g (a step) or the parent's (a pop)
    reg signed [GW-1:0] s_y;
    reg        s_neg;
    reg [2:0]  s_real;
    reg [19:0] s_c [0:2];
    reg [8:0]  s_lt;
    integer k, b;
    always @* begin
        for (k = 0; k < 3; k = k + 1) begin
            s_t0[k] = cc[2-k] ? f_tm[k] : f_t0[k];
            s_t1[k] = cc[2-k] ? f_t1[k] : f_tm[k];
        end
        for (k = 0; k < 3; k = k + 1)
            for (b = 0; b < 3; b = b + 1)
                s_lt[3*k + b] = s_t0[k] < s_t1[b];
        s_real = cc ^ w_a;
        for (k = 0; k < 3; k = k + 1) s_c[k] = {f_c[k][18:0], s_real[2-k]};
        // A step: g ± d (+ when cc's bit is 1). A pop: the popped child's bit b (its
        // coordinate's low bit, unmirrored) gives the parent's g = g ∓ 2d.
        for (k = 0; k < 3; k = k + 1) begin
            s_y = popping ? f_d[k] <<< 1 : f_d[k];
            s_neg = popping ? f_c[k][0] ^ w_a[2-k] : !cc[2-k];
            s_g[k] = f_g[k] + (s_y ^ {GW{s_neg}}) + {{(GW-1){1'b0}}, s_neg};
        end
    end

    // ---- Stage B (the first S_HOLD cycle): the decision from stage A's bits -------------
    wire        b_in = &a_lt && &a_pos;
    wire        b_enter = b_in && a_valid;
    wire [2:0]  b_bit = a_n01 && a_n02 ? 3'b100 : a_n12 ? 3'b010 : 3'b001;
    wire [3:0]  b_next = (cc & b_bit) != 3'b000 ? 4'd8 : {1'b0, cc | b_bit};
    wire [1:0]  b_axis = a_e01 && a_e02 ? 2'd0 : a_e12 ? 2'd1 : 2'd2;
    wire [1:0]  b_act = a_lim ? A_OUT : !b_enter ? A_ISSUE
                      : (!a_leaf && a_ovf) ? A_OUT : A_REQ;
    wire [1:0]  act_now = b_dec ? b_act : act;
    wire [31:0] b_slot_addr = a_base + {28'd0, a_slot};

    // A configuration this RTL cannot time as the model: elaboration fails on the missing
    // module.
    generate
        if (STEP_LATENCY < 3 || STEP_LATENCY > 200 || STACK_DEPTH < 2 || STACK_DEPTH > 64)
        begin : bad_parameters
            svo_walker_unsupported_parameters fail ();
        end
    endgenerate

    wire [IW-1:0]  sp_below = sp[IW-1:0] - 1'b1;   // used only when sp > 0

    // ---- Ports ----------------------------------------------------------------------------
    wire resp = st == S_MEMW && mem_resp_valid;
    wire [31:0] far_slot = c_fa + mem_resp_data[31:0];
    // A far word's child slot and a leaf's attribute record are requested in the cycle the
    // word arrives.
    wire chain = resp && (pend == P_FAR || pend == P_LEAF);
    assign mem_req_valid = st == S_REQ || chain;
    assign mem_req_attr = chain ? pend == P_LEAF : req_attr;
    assign mem_req_addr = !chain ? req_addr
                        : pend == P_FAR ? far_slot : w_attr_base + mem_resp_data[31:0];
    assign out_valid = st == S_OUT || (resp && pend == P_ATTR);
    assign out_attr_data = st == S_OUT ? attr_data : mem_resp_data;
    assign in_ready = st == S_IDLE || (out_valid && out_ready);
    // An issue slot: a waiting slot, or a descriptor's first slot in the cycle it arrives.
    assign issue_req = st == S_ISSUE || (resp && pend == P_DESC);
    assign ev_resp = resp;

    wire [23:0] pc_next = prefix_counts(resp && pend == P_DESC ? mem_resp_data[14:8]
                                                               : f_desc[14:8]);

    // ---- The sequencer -------------------------------------------------------------------
    integer j;
    always @(posedge clk) begin
        visit_valid <= 1'b0;
        ev_lat <= !rst && st == S_HOLD && hold_left == 8'd0;
        ev_disp <= !rst && taking;
        // The child's midpoints and first child, every cycle from the child's registers
        // (a zero axis from the sign of its g; the root's midpoints come from the inputs).
        for (j = 0; j < 3; j = j + 1)
            c_tm[j] <= !w_zero[j] ? mid_t(c_t0[j], c_t1[j])
                     : c_g[j][GW-1] ? NEG_INF : POS_INF;
        for (j = 0; j < 3; j = j + 1)
            c_first[2-j] <= c_tm[j] < c_t0[0] || c_tm[j] < c_t0[1] || c_tm[j] < c_t0[2];
        c_first[3] <= 1'b0;
        // The top frame's prefix counts, every cycle from f_desc (a pop's parent has them
        // before its next slot, three cycles on) and from the descriptor as it arrives.
        for (j = 0; j < 8; j = j + 1) f_pc[j] <= pc_next[3*j +: 3];
        if (rst) begin
            st <= S_IDLE;
            b_dec <= 1'b0;
        end else begin
            // The result leaves.
            if (out_valid && out_ready) begin
                st <= S_IDLE;
            end else if (resp && pend == P_ATTR) begin
                attr_data <= mem_resp_data;
                st <= S_OUT;
            end
            case (st)
            S_REQ: if (mem_req_ready) st <= S_MEMW;
            S_MEMW: if (mem_resp_valid) begin
                case (pend)
                P_DESC: begin
                    // Push the parent (not for the root) and make the child the top; its
                    // first slot issues now.
                    if (!c_root) begin
                        stk[sp[IW-1:0]] <= {f_t0[0], f_t0[1], f_t0[2], f_t1[0], f_t1[1], f_t1[2],
                                    f_tm[0], f_tm[1], f_tm[2], f_addr, f_desc, f_next, f_level,
                                    f_c[0], f_c[1], f_c[2]};
                        sp <= sp + 1'b1;
                    end
                    for (j = 0; j < 3; j = j + 1) begin
                        f_t0[j] <= c_t0[j];
                        f_t1[j] <= c_t1[j];
                        f_tm[j] <= c_tm[j];
                        f_c[j] <= c_c[j];
                        f_g[j] <= c_g[j];
                        f_d[j] <= f_d[j] >>> 1;
                    end
                    f_addr <= c_addr;
                    f_desc <= mem_resp_data[31:0];
                    f_next <= c_first;
                    f_level <= c_level;
                    st <= issue_grant ? S_COMP : S_ISSUE;
                end
                P_FAR: begin
                    pend <= c_leaf ? P_LEAF : P_DESC;
                    c_addr <= far_slot;
                    req_addr <= far_slot;
                    req_attr <= 1'b0;
                    st <= mem_req_ready ? S_MEMW : S_REQ;
                end
                P_LEAF: begin
                    out_attr <= mem_resp_data[31:0];
                    pend <= P_ATTR;
                    req_addr <= w_attr_base + mem_resp_data[31:0];
                    req_attr <= 1'b1;
                    st <= mem_req_ready ? S_MEMW : S_REQ;
                end
                default: ;  // P_ATTR: handled above
                endcase
            end
            S_ISSUE: if (issue_grant) st <= S_COMP;
            S_COMP: begin
                // Stage A.
                st <= S_HOLD;
                hold_left <= HOLD - 1;
                if (popping) begin
                    b_dec <= 1'b0;
                    if (sp == {SPW{1'b0}}) begin
                        out_outcome <= 2'd0;
                        act <= A_OUT;
                    end else begin
                        act <= A_ISSUE;
                        {f_t0[0], f_t0[1], f_t0[2], f_t1[0], f_t1[1], f_t1[2], f_tm[0],
                         f_tm[1], f_tm[2], f_addr, f_desc, f_next, f_level, f_c[0], f_c[1],
                         f_c[2]} <= stk[sp_below];
                        sp <= sp - 1'b1;
                        for (j = 0; j < 3; j = j + 1) begin
                            f_g[j] <= s_g[j];
                            f_d[j] <= f_d[j] <<< 1;
                        end
                    end
                end else begin
                    b_dec <= 1'b1;
                    for (j = 0; j < 3; j = j + 1) begin
                        c_t0[j] <= s_t0[j];
                        c_t1[j] <= s_t1[j];
                        c_c[j] <= s_c[j];
                        c_g[j] <= s_g[j];
                        a_pos[j] <= s_t1[j] > T_ZERO;
                        a_t0pos[j] <= s_t0[j] > T_ZERO;
                    end
                    c_level <= f_level + 5'd1;
                    c_leaf <= f_desc[{2'b00, s_real}];
                    c_root <= 1'b0;
                    a_lt <= s_lt;
                    a_n01 <= s_t1[0] <= s_t1[1];
                    a_n02 <= s_t1[0] <= s_t1[2];
                    a_n12 <= s_t1[1] <= s_t1[2];
                    a_e01 <= s_t0[0] >= s_t0[1];
                    a_e02 <= s_t0[0] >= s_t0[2];
                    a_e12 <= s_t0[1] >= s_t0[2];
                    a_valid <= f_desc[8 + s_real];
                    a_leaf <= f_desc[{2'b00, s_real}];
                    a_far <= f_desc[16];
                    a_slot <= {1'b0, f_pc[s_real]};
                    a_base <= f_addr + {17'd0, f_desc[31:17]};
                    a_lim <= steps + 32'd1 > MAX_STEPS;
                    a_ovf <= {{(32-SPW){1'b0}}, sp} + 32'd1 >= STACK_DEPTH;
                end
            end
            S_HOLD: begin
                if (b_dec) begin
                    // Stage B.
                    b_dec <= 1'b0;
                    steps <= steps + 32'd1;
                    if (a_lim) begin
                        out_outcome <= 2'd2;
                    end else begin
                        f_next <= b_next;
                        if (b_enter) begin
                            visit_valid <= 1'b1;
                            visit_level <= c_level;
                            visit_coords <= {c_c[2], c_c[1], c_c[0]};
                            c_fa <= f_addr + {28'd0, a_slot};
                            req_attr <= 1'b0;
                            if (a_leaf) begin
                                out_outcome <= 2'd1;
                                out_t <= a_t0pos[b_axis] ? c_t0[b_axis][T_W-1:0] : {T_W{1'b0}};
                                out_voxel <= {c_c[2], c_c[1], c_c[0]};
                                out_level <= c_level;
                                out_entry_axis <= b_axis;
                            end else begin
                                fetches <= fetches + 32'd1;
                            end
                            if (!a_leaf && a_ovf) begin
                                out_outcome <= 2'd3;
                            end else if (a_far) begin
                                pend <= P_FAR;
                                req_addr <= a_base;
                            end else begin
                                pend <= a_leaf ? P_LEAF : P_DESC;
                                req_addr <= b_slot_addr;
                                c_addr <= b_slot_addr;
                            end
                        end
                    end
                end
                act <= act_now;
                if (hold_left == 8'd0) begin
                    st <= act_now == A_ISSUE ? S_ISSUE : act_now == A_REQ ? S_REQ : S_OUT;
                end else begin
                    hold_left <= hold_left - 8'd1;
                end
            end
            default: ;
            endcase
            // A new walk (possibly in the cycle the previous result leaves).
            if (taking) begin
                for (j = 0; j < 3; j = j + 1) begin
                    c_t0[j] <= in_t0[j*TI +: TI];
                    c_t1[j] <= in_t1[j*TI +: TI];
                    // The root's centre is 0: +inf iff ox < 0; g = -(ox + 1) = ~ox, and the
                    // d of a level above the root, e, halved when the root becomes the top.
                    c_tm[j] <= !in_zero[j] ? mid_t(in_t0[j*TI +: TI], in_t1[j*TI +: TI])
                             : in_o[j*(POS_W+1) + POS_W] ? POS_INF : NEG_INF;
                    c_g[j] <= {~{{(GW-F-POS_W-1){in_o[j*(POS_W+1) + POS_W]}},
                                 in_o[j*(POS_W+1) +: POS_W+1]}, {F{1'b0}}};
                    f_d[j] <= {{(GW-F-POS_W){in_half[j*POS_W + POS_W-1]}},
                               in_half[j*POS_W +: POS_W], {F{1'b0}}};
                    c_c[j] <= 20'd0;
                end
                w_zero <= in_zero;
                w_a <= in_a;
                w_attr_base <= in_attr_base;
                out_tag <= in_tag;
                c_level <= 5'd0;
                c_root <= 1'b1;
                c_leaf <= 1'b0;
                c_addr <= in_node_base;
                req_addr <= in_node_base;
                req_attr <= 1'b0;
                pend <= P_DESC;
                sp <= {SPW{1'b0}};
                steps <= 32'd0;
                fetches <= in_enter ? 32'd1 : 32'd0;
                out_outcome <= 2'd0;
                out_t <= {T_W{1'b0}};
                out_voxel <= 60'd0;
                out_level <= 5'd0;
                out_attr <= 32'd0;
                out_entry_axis <= 2'd0;
                st <= in_enter ? S_REQ : S_OUT;
            end
        end
    end

    always @* begin
        out_steps = steps;
        out_fetches = fetches;
    end
endmodule
`default_nettype wire
