// svo_walker: one octree walker with one ray context: the stack-based walk of
// rtl_model/src/units/walker.rs (Revelles et al. 2000, fixed point), cycle for cycle as the
// cycle model's walker pool times a context (rtl_model/src/cycle/walker_pool.rs, §2.3 of
// docs/cycle-model.md).
//
// Pipeline position: after svo_walker_root (the root slabs) and the dispatcher; its result
// goes to the record stage. It reads the SVO memory image (docs/svo-format.md) through one
// read port with valid/ready; every read returns mem_resp_valid with the data some cycles
// later (any latency, one read outstanding: the context waits for each).
//
// Timing (what the model counts, and so what walker.hex's cycles_* predict):
//   accept (cycle D)        the root descriptor is requested in D + 1 (a root miss leaves in
//                           D + 1 with no read);
//   an issue slot (cycle X) is a child examined or a stack pop: the slot's logic runs in
//                           X + 1 (COMP) from the top frame's registers, its result is held
//                           STEP_LATENCY - 2 more cycles, and its successor comes in
//                           X + STEP_LATENCY: the next slot, a read request, or the result;
//   a read's data (cycle C) a descriptor pushes the child's frame and issues its first slot
//                           in C; a far word requests the child's slot in C; a leaf slot
//                           requests the attribute record in C; the attribute record is the
//                           result, out_valid in C.
// The step's logic is evaluated in one cycle and then held: synthesis retimes it across the
// STEP_LATENCY - 1 registers of the hold.
//
// Arithmetic as the model: children by the midpoints tm = floor((t0 + t1)/2) (halves plus the
// carry of the low bits); zero axes take +inf / -inf from the origin's side of the node's
// centre plane -e + ((2m + 1)·2e) >> (level + 1) (m the mirrored coordinate); child order by
// Revelles' tables 1-3 (first child from the midpoints crossed before the entry, next child
// from the exit plane, ties x, y, z); a child is entered when max(t0) < min(t1) and
// min(t1) > 0. Negative axes are mirrored (label ^ a). Steps count children examined, fetches
// the root and each node descended into; a walk that examines more than MAX_STEPS children
// stops with outcome 2. A descent that would need more than STACK_DEPTH frames stops with
// outcome 3 (stack overflow; the model's stack never overflows at its default depth, so the
// vectors never expect it).
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
    output reg  [59:0]            visit_coords    // {z, y, x}
);
    localparam TI = T_W + 1;
    localparam signed [TI-1:0] NEG_INF = {1'b1, {(TI-1){1'b0}}};
    localparam signed [TI-1:0] POS_INF = {1'b0, {(TI-1){1'b1}}};
    localparam signed [TI-1:0] T_ZERO = {TI{1'b0}};
    localparam MW = POS_W + 24;                    // (2m + 1)·2e
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

    // The walk's constants.
    reg signed [POS_W:0]   w_o [0:2];
    reg signed [POS_W-1:0] w_half [0:2];
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

    // Frames below the top.
    reg [FW-1:0] stk [0:STACK_DEPTH-2];
    reg [SPW-1:0] sp;                              // frames in stk

    // The child being read.
    reg signed [TI-1:0] c_t0 [0:2];
    reg signed [TI-1:0] c_t1 [0:2];
    reg signed [TI-1:0] c_tm [0:2];
    reg [3:0]  c_first;
    reg [4:0]  c_level;
    reg [19:0] c_c [0:2];
    reg [31:0] c_addr;
    reg        c_leaf, c_root;
    reg [3:0]  c_slot;                             // popcount of the lower valid bits

    reg [31:0] req_addr;
    reg        req_attr;
    reg [31:0] steps, fetches;
    reg [63:0] attr_data;

    // ---- Combinational helpers ----------------------------------------------------------
    function automatic signed [TI-1:0] max3(input signed [TI-1:0] a, input signed [TI-1:0] b,
                                            input signed [TI-1:0] c);
        reg signed [TI-1:0] m;
        begin
            m = a;
            if (b > m) m = b;
            if (c > m) m = c;
            max3 = m;
        end
    endfunction
    function automatic signed [TI-1:0] min3(input signed [TI-1:0] a, input signed [TI-1:0] b,
                                            input signed [TI-1:0] c);
        reg signed [TI-1:0] m;
        begin
            m = a;
            if (b < m) m = b;
            if (c < m) m = c;
            min3 = m;
        end
    endfunction
    // Midpoint of one axis for the node at `level` with real coordinate `c`: `zero` the
    // axis's zero flag, `mir` its mirror bit, `half` and `o` its half extent and mirrored
    // origin.
    function automatic signed [TI-1:0] mid(input zero, input mir, input signed [POS_W-1:0] half,
                                           input signed [POS_W:0] o, input signed [TI-1:0] a,
                                           input signed [TI-1:0] b, input [4:0] level,
                                           input [19:0] c);
        reg [20:0] m;
        reg signed [MW-1:0] e, centre, ox;
        begin
            if (!zero) begin
                mid = (a >>> 1) + (b >>> 1) + $signed({{(TI-1){1'b0}}, a[0] & b[0]});
            end else begin
                if (mir) m = ((21'd1 << level) - 21'd1) - {1'b0, c};
                else m = {1'b0, c};
                e = {{(MW-POS_W){1'b0}}, half};
                centre = -e + (($signed({1'b0, m, 1'b1}) * (e <<< 1)) >>> (level + 5'd1));
                ox = {{(MW-POS_W-1){o[POS_W]}}, o};
                mid = (ox < centre) ? POS_INF : NEG_INF;
            end
        end
    endfunction
    wire taking = in_valid && in_ready;
    wire [2:0] in_a = {in_neg[0], in_neg[1], in_neg[2]};

    function automatic [3:0] first_child(input signed [TI-1:0] t0x, input signed [TI-1:0] t0y,
                                         input signed [TI-1:0] t0z, input signed [TI-1:0] tmx,
                                         input signed [TI-1:0] tmy, input signed [TI-1:0] tmz);
        reg signed [TI-1:0] en;
        begin
            en = max3(t0x, t0y, t0z);
            first_child = {1'b0, tmx < en, tmy < en, tmz < en};
        end
    endfunction

    // ---- The step (COMP): everything from the top frame --------------------------------
    wire [2:0]  cc = f_next[2:0];
    reg signed [TI-1:0] s_t0 [0:2];
    reg signed [TI-1:0] s_t1 [0:2];
    reg signed [TI-1:0] s_enter, s_exit;
    reg [3:0]  s_next;
    reg [2:0]  s_real;
    reg        s_valid, s_leaf, s_in;
    reg [3:0]  s_slot;
    reg [19:0] s_c [0:2];
    integer k;
    always @* begin
        for (k = 0; k < 3; k = k + 1) begin
            s_t0[k] = cc[2-k] ? f_tm[k] : f_t0[k];
            s_t1[k] = cc[2-k] ? f_t1[k] : f_tm[k];
        end
        if (s_t1[0] <= s_t1[1] && s_t1[0] <= s_t1[2])
            s_next = cc[2] ? 4'd8 : {1'b0, cc | 3'b100};
        else if (s_t1[1] <= s_t1[2])
            s_next = cc[1] ? 4'd8 : {1'b0, cc | 3'b010};
        else
            s_next = cc[0] ? 4'd8 : {1'b0, cc | 3'b001};
        s_enter = max3(s_t0[0], s_t0[1], s_t0[2]);
        s_exit = min3(s_t1[0], s_t1[1], s_t1[2]);
        s_in = s_enter < s_exit && s_exit > T_ZERO;
        s_real = cc ^ w_a;
        s_valid = f_desc[8 + s_real];
        s_leaf = f_desc[{2'b00, s_real}];
        s_slot = 4'd0;
        for (k = 0; k < 8; k = k + 1)
            if (k < s_real && f_desc[8 + k]) s_slot = s_slot + 4'd1;
        for (k = 0; k < 3; k = k + 1) s_c[k] = {f_c[k][18:0], s_real[2-k]};
    end

    // The entered child's midpoints and first child, and the root's (from the inputs, in
    // the accept cycle).
    reg signed [TI-1:0] s_tm [0:2];
    reg signed [TI-1:0] r_tm [0:2];
    reg [3:0] s_first, r_first;
    always @* begin
        for (k = 0; k < 3; k = k + 1) begin
            s_tm[k] = mid(w_zero[k], w_a[2-k], w_half[k], w_o[k], s_t0[k], s_t1[k],
                          f_level + 5'd1, s_c[k]);
            r_tm[k] = mid(in_zero[k], in_a[2-k], in_half[k*POS_W +: POS_W],
                          in_o[k*(POS_W+1) +: POS_W+1], in_t0[k*TI +: TI], in_t1[k*TI +: TI],
                          5'd0, 20'd0);
        end
        s_first = first_child(s_t0[0], s_t0[1], s_t0[2], s_tm[0], s_tm[1], s_tm[2]);
        r_first = first_child(in_t0[0 +: TI], in_t0[TI +: TI], in_t0[2*TI +: TI],
                              r_tm[0], r_tm[1], r_tm[2]);
    end

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
    wire [31:0] far_slot = f_addr + mem_resp_data[31:0] + {28'd0, c_slot};
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

    // ---- The sequencer -------------------------------------------------------------------
    integer j;
    always @(posedge clk) begin
        visit_valid <= 1'b0;
        if (rst) begin
            st <= S_IDLE;
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
                    end
                    f_addr <= c_addr;
                    f_desc <= mem_resp_data[31:0];
                    f_next <= c_first;
                    f_level <= c_level;
                    st <= S_COMP;
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
            S_ISSUE: st <= S_COMP;
            S_COMP: begin
                st <= S_HOLD;
                hold_left <= HOLD - 1;
                act <= A_ISSUE;
                if (f_next == 4'd8) begin
                    // A pop.
                    if (sp == {SPW{1'b0}}) begin
                        out_outcome <= 2'd0;
                        act <= A_OUT;
                    end else begin
                        {f_t0[0], f_t0[1], f_t0[2], f_t1[0], f_t1[1], f_t1[2], f_tm[0],
                         f_tm[1], f_tm[2], f_addr, f_desc, f_next, f_level, f_c[0], f_c[1],
                         f_c[2]} <= stk[sp_below];
                        sp <= sp - 1'b1;
                    end
                end else if (steps + 32'd1 > MAX_STEPS) begin
                    steps <= steps + 32'd1;
                    out_outcome <= 2'd2;
                    act <= A_OUT;
                end else begin
                    steps <= steps + 32'd1;
                    f_next <= s_next;
                    if (s_in && s_valid) begin
                        visit_valid <= 1'b1;
                        visit_level <= f_level + 5'd1;
                        visit_coords <= {s_c[2], s_c[1], s_c[0]};
                        for (j = 0; j < 3; j = j + 1) begin
                            c_t0[j] <= s_t0[j];
                            c_t1[j] <= s_t1[j];
                            c_tm[j] <= s_tm[j];
                            c_c[j] <= s_c[j];
                        end
                        c_first <= s_first;
                        c_level <= f_level + 5'd1;
                        c_leaf <= s_leaf;
                        c_root <= 1'b0;
                        c_slot <= s_slot;
                        req_attr <= 1'b0;
                        if (s_leaf) begin
                            out_outcome <= 2'd1;
                            out_t <= s_enter > T_ZERO ? s_enter[T_W-1:0] : {T_W{1'b0}};
                            out_voxel <= {s_c[2], s_c[1], s_c[0]};
                            out_level <= f_level + 5'd1;
                            out_entry_axis <= (s_t0[0] >= s_t0[1] && s_t0[0] >= s_t0[2]) ? 2'd0
                                            : (s_t0[1] >= s_t0[2]) ? 2'd1 : 2'd2;
                        end else begin
                            fetches <= fetches + 32'd1;
                        end
                        act <= A_REQ;
                        if (!s_leaf && {{(32-SPW){1'b0}}, sp} + 32'd1 >= STACK_DEPTH) begin
                            out_outcome <= 2'd3;
                            act <= A_OUT;
                        end else if (f_desc[16]) begin
                            pend <= P_FAR;
                            req_addr <= f_addr + {17'd0, f_desc[31:17]};
                        end else begin
                            pend <= s_leaf ? P_LEAF : P_DESC;
                            req_addr <= f_addr + {17'd0, f_desc[31:17]} + {28'd0, s_slot};
                            c_addr <= f_addr + {17'd0, f_desc[31:17]} + {28'd0, s_slot};
                        end
                    end
                end
            end
            S_HOLD: if (hold_left == 8'd0) begin
                st <= act == A_ISSUE ? S_ISSUE : act == A_REQ ? S_REQ : S_OUT;
            end else begin
                hold_left <= hold_left - 8'd1;
            end
            default: ;
            endcase
            // A new walk (possibly in the cycle the previous result leaves).
            if (taking) begin
                for (j = 0; j < 3; j = j + 1) begin
                    w_o[j] <= in_o[j*(POS_W+1) +: POS_W+1];
                    w_half[j] <= in_half[j*POS_W +: POS_W];
                    c_t0[j] <= in_t0[j*TI +: TI];
                    c_t1[j] <= in_t1[j*TI +: TI];
                    c_tm[j] <= r_tm[j];
                    c_c[j] <= 20'd0;
                end
                c_first <= r_first;
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
