// tb_walker_pool: svo_walker_pool on its own at K walk lanes, for test_walker_pool.py — one
// svo_walker_root in front (the rows of vectors/walker.hex, their memory bases carried in its
// tag), root_to_dispatch as an svo_fifo_wide of K pop ports, the pool, and its K retire lanes
// out to the bench; the bench is the node memory (one request port per walker, always ready)
// and the record FIFO (out_ready, a prefix).
//
// Pipeline position: none (a bench top); the chain is walker_root → root_to_dispatch → walker
// pool → walker_to_record as a K-wide walk section builds it.
`timescale 1ns/1ps
`default_nettype none
module tb_walker_pool
    import walker_vectors_pkg::*;
#(
    parameter K = 2,
    parameter WALKERS = 2,
    parameter CONTEXTS = 2,
    parameter DEPTH = 8,                            // root_to_dispatch
    parameter POOL_STEP_LATENCY = 4,
    parameter CW = WALKERS * CONTEXTS > 1 ? $clog2(WALKERS * CONTEXTS) : 1
) (
    input  wire                      clk,
    input  wire                      rst,
    // A row into the root unit (the bench keeps root_to_dispatch from overflowing).
    input  wire                      row_valid,
    input  wire [WORD_BITS-1:0]      row,
    input  wire [15:0]               row_tag,
    input  wire [K-1:0]              offer,         // the lanes root_to_dispatch may offer (a prefix)
    output wire [K-1:0]              in_valid,      // the pool's take lanes
    output wire [K-1:0]              in_ready,
    output wire                      overflow,      // sticky: the root's result found no room
    output wire [WALKERS-1:0]        mem_req_valid,
    output wire [WALKERS-1:0]        mem_req_attr,
    output wire [WALKERS*32-1:0]     mem_req_addr,
    output wire [WALKERS*CW-1:0]     mem_req_ctx,
    input  wire [WALKERS-1:0]        mem_resp_valid,
    input  wire [WALKERS*CW-1:0]     mem_resp_ctx,
    input  wire [WALKERS*64-1:0]     mem_resp_data,
    output wire [K-1:0]              out_valid,
    input  wire [K-1:0]              out_ready,
    output wire [K*2-1:0]            out_outcome,
    output wire [K*T_WIDTH-1:0]      out_t,
    output wire [K*60-1:0]           out_voxel,
    output wire [K*64-1:0]           out_attr_data,
    output wire [K*16-1:0]           out_tag,
    output wire                      err_resp
);
    localparam TI = T_WIDTH + 1;
    localparam PW = O_X_WIDTH;
    localparam TAGW = 16 + 64;                      // {attr_base, node_base, row}
    localparam DW = 1 + 6*TI + 3*(PW+1) + 3*PW + 6 + TAGW;

    wire            r_valid, r_enter;
    wire [3*TI-1:0] r_t0, r_t1;
    wire [3*(PW+1)-1:0] r_o;
    wire [3*PW-1:0] r_half;
    wire [2:0]      r_zero, r_neg;
    wire [TAGW-1:0] r_tag;
    svo_walker_root #(
        .POS_W(PW), .POS_FRAC(O_X_FRAC), .INV_W(INV_X_WIDTH), .INV_FRAC(INV_X_FRAC),
        .T_W(T_WIDTH), .T_FRAC(T_FRAC), .PROD(ROOT_LATENCY - 4), .TAG_W(TAGW)
    ) root (
        .clk(clk), .rst(rst), .in_valid(row_valid),
        .in_o({row[O_Z_LSB +: PW], row[O_Y_LSB +: PW], row[O_X_LSB +: PW]}),
        .in_inv({row[INV_Z_LSB +: INV_X_WIDTH], row[INV_Y_LSB +: INV_X_WIDTH],
                 row[INV_X_LSB +: INV_X_WIDTH]}),
        .in_zero({row[ZERO_Z_LSB], row[ZERO_Y_LSB], row[ZERO_X_LSB]}),
        .in_neg({row[NEGATIVE_Z_LSB], row[NEGATIVE_Y_LSB], row[NEGATIVE_X_LSB]}),
        .in_half({row[HALF_Z_LSB +: PW], row[HALF_Y_LSB +: PW], row[HALF_X_LSB +: PW]}),
        .in_tag({row[ATTR_BASE_LSB +: 32], row[NODE_BASE_LSB +: 32], row_tag}),
        .out_valid(r_valid), .out_enter(r_enter), .out_t0(r_t0), .out_t1(r_t1), .out_o(r_o),
        .out_half(r_half), .out_zero(r_zero), .out_neg(r_neg), .out_tag(r_tag));

    // root_to_dispatch: one push port used (one root unit), K pop ports into the pool.
    wire [K-1:0]   f_in_ready, f_valid;
    wire [K*DW-1:0] f_data;
    wire [DW-1:0]  r_word = {r_enter, r_t0, r_t1, r_o, r_half, r_zero, r_neg, r_tag};
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo_wide #(.K(K), .DEPTH(DEPTH), .W(DW)) root_to_dispatch (.clk(clk), .rst(rst),
        .in_valid({{(K-1){1'b0}}, r_valid}), .in_ready(f_in_ready),
        .in_data({{((K-1)*DW){1'b0}}, r_word}), .out_valid(f_valid),
        .out_ready(in_valid & in_ready), .out_data(f_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    reg ovf;
    always @(posedge clk) ovf <= rst ? 1'b0 : ovf | (r_valid & !f_in_ready[0]);
    assign overflow = ovf;
    assign in_valid = f_valid & offer;

    // The pool's lanes, field by field.
    wire [K-1:0]          p_enter;
    wire [K*3*TI-1:0]     p_t0, p_t1;
    wire [K*3*(PW+1)-1:0] p_o;
    wire [K*3*PW-1:0]     p_half;
    wire [K*3-1:0]        p_zero, p_neg;
    wire [K*32-1:0]       p_node_base, p_attr_base;
    wire [K*16-1:0]       p_tag;
    genvar j;
    generate
        for (j = 0; j < K; j = j + 1) begin : lane
            wire [DW-1:0] d = f_data[j*DW +: DW];
            assign {p_enter[j], p_t0[j*3*TI +: 3*TI], p_t1[j*3*TI +: 3*TI],
                    p_o[j*3*(PW+1) +: 3*(PW+1)], p_half[j*3*PW +: 3*PW], p_zero[j*3 +: 3],
                    p_neg[j*3 +: 3], p_attr_base[j*32 +: 32], p_node_base[j*32 +: 32],
                    p_tag[j*16 +: 16]} = d;
        end
    endgenerate
    svo_walker_pool #(
        .POS_W(PW), .T_W(T_WIDTH), .STACK_DEPTH(STACK_DEPTH), .MAX_STEPS(MAX_STEPS),
        .STEP_LATENCY(POOL_STEP_LATENCY), .TAG_W(16), .CONTEXTS(CONTEXTS), .WALKERS(WALKERS),
        .K(K), .CW(CW)
    ) pool (
        .clk(clk), .rst(rst), .in_valid(in_valid), .in_ready(in_ready), .in_enter(p_enter),
        .in_t0(p_t0), .in_t1(p_t1), .in_o(p_o), .in_half(p_half), .in_zero(p_zero),
        .in_neg(p_neg), .in_node_base(p_node_base), .in_attr_base(p_attr_base), .in_tag(p_tag),
        .mem_req_valid(mem_req_valid), .mem_req_ready({WALKERS{1'b1}}),
        .mem_req_attr(mem_req_attr), .mem_req_addr(mem_req_addr), .mem_req_ctx(mem_req_ctx),
        .mem_resp_valid(mem_resp_valid), .mem_resp_ctx(mem_resp_ctx),
        .mem_resp_data(mem_resp_data), .ctx_resp_valid(1'b0), .ctx_resp_data(32'd0),
        .out_valid(out_valid), .out_ready(out_ready), .out_outcome(out_outcome), .out_t(out_t),
        .out_voxel(out_voxel), .out_attr_data(out_attr_data), .out_tag(out_tag),
        .err_resp(err_resp));
endmodule
`default_nettype wire
