// svo_walk_pack: the record stage's K packing lanes of svo_walk_wide — per lane svo_normal
// (13) with the record's other fields beside it in an svo_delay, then svo_hit_pack (1), the
// model's units.hit_pack of 14 — and their hand-on into record_to_write.
//
// Pipeline position: the record stage (docs/cycle-model.md §2.1; src/models/cycle/stages/
// record.rs, `Record::pack`: UnitLanes of `walk_lanes` lanes), between the record's decisions
// and the hit buffer's record ports (`rec_*`, `rec2_*`: record_to_write's two push ports, a
// prefix). At K = 1 the lane is an svo_elastic2 (one unit, two ready records a
// cycle); at K = 2 svo_unit_lanes (each record into the lowest lane with room after this
// cycle's leaves, the ready records oldest first, ties in lane order, on the two ports).
// The decisions offer their packs as a prefix (`in_valid`, each pack's instance, best-hit
// attribute record and packed fields, the record's layout); `in_ready[p]`: p + 1 lanes can take
// one, what the record's decisions are gated on. Lane l reads its pack's instance's normal
// matrix through its own instance-table port (`ird_nm` lane l → `inst_nmat` lane l, in the
// cycle). `err_overflow`: a lane's svo_hit_pack flagged a saturated field this cycle.
`timescale 1ns/1ps
`default_nettype none
module svo_walk_pack #(
    parameter K    = 2,
    parameter PIXW = 32,
    parameter PKB  = 2 + 1 + 8 + 64 + 24 + PIXW,  // the fields that wait for the normal (do not set)
    parameter SW   = K > 1 ? $clog2(K) : 1        // (do not set)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire [K-1:0]      in_valid,            // a prefix
    output wire [K-1:0]      in_ready,
    input  wire [K*8-1:0]    in_inst,
    input  wire [K*64-1:0]   in_attr,
    input  wire [K*PKB-1:0]  in_fields,
    output wire [K*8-1:0]    ird_nm,
    input  wire [K*162-1:0]  inst_nmat,
    output wire              rec_valid,
    input  wire              rec_ready,
    output wire [PIXW-1:0]   rec_pixel,
    output wire [71:0]       rec_word,
    output wire              rec2_valid,
    input  wire              rec2_ready,
    output wire [PIXW-1:0]   rec2_pixel,
    output wire [71:0]       rec2_word,
    output wire              err_overflow
);
    localparam NL = 13;                           // svo_normal's LATENCY
    localparam RW = PIXW + 72;
    wire [K-1:0] take, u_valid, u_ov;
    wire [K*SW-1:0] src;
    wire [K*RW-1:0] u_data;
    genvar g;
    generate
        if (K == 1) begin : one
            // One lane's pipe: two out ports for record_to_write's two pushes at k = 1.
            svo_elastic2 #(.L(NL + 1), .W(RW)) pipe (.clk(clk), .rst(rst),
                .in_valid(in_valid[0]), .in_ready(in_ready[0]), .unit_valid(u_valid[0]),
                .unit_data(u_data), .out_valid(rec_valid), .out_ready(rec_ready),
                .out_data({rec_pixel, rec_word}), .out2_valid(rec2_valid),
                .out2_ready(rec2_ready), .out2_data({rec2_pixel, rec2_word}));
            assign take = in_valid & in_ready;
            assign src = {SW{1'b0}};
        end else begin : lanes                    // K = 2 (svo_walk_wide refuses more)
            wire [K-1:0] o_valid, o_ready;
            wire [K*RW-1:0] o_data;
            svo_unit_lanes #(.K(K), .L(NL + 1), .W(RW)) pipe (.clk(clk), .rst(rst),
                .in_valid(in_valid), .in_ready(in_ready), .lane_take(take), .lane_src(src),
                .unit_valid(u_valid), .unit_data(u_data), .out_valid(o_valid),
                .out_ready(o_ready), .out_data(o_data));
            // record_to_write's two push ports take the first two ready records.
            assign o_ready = {rec2_ready, rec_ready};
            assign rec_valid = o_valid[0];
            assign {rec_pixel, rec_word} = o_data[0 +: RW];
            assign rec2_valid = o_valid[1];
            assign {rec2_pixel, rec2_word} = o_data[RW +: RW];
        end
        for (g = 0; g < K; g = g + 1) begin : lane
            wire [SW-1:0] s = src[g*SW +: SW];
            wire [31:0] oct = in_attr[s*64 + 32 +: 32];   // the attribute's normal
            assign ird_nm[g*8 +: 8] = in_inst[s*8 +: 8];
            wire nm_valid;
            wire [15:0] nm_code;                  // {v, u}
            svo_normal #(.N_W(8)) u_normal (.clk(clk), .rst(rst), .in_valid(take[g]),
                .in_oct(oct), .in_mat(inst_nmat[g*162 +: 162]),
                .out_valid(nm_valid), .out_code(nm_code));
            wire [PKB-1:0] q;
            svo_delay #(.W(PKB), .D(NL)) side (.clk(clk), .rst(rst),
                .d(in_fields[s*PKB +: PKB]), .q(q));
            wire [1:0]  q_kind = q[PKB-1 -: 2];
            wire        q_best = q[PKB-3];
            wire [7:0]  q_inst = q[PKB-4 -: 8];
            wire [63:0] q_t    = q[PKB-12 -: 64];
            wire [7:0]  q_r    = q[PKB-76 -: 8];
            wire [7:0]  q_g    = q[PKB-84 -: 8];
            wire [7:0]  q_b    = q[PKB-92 -: 8];
            wire [71:0] word;
            svo_hit_pack u_pack (.clk(clk), .rst(rst), .in_valid(nm_valid), .in_kind(q_kind),
                .in_instance_valid(q_best), .in_instance(q_best ? {8'd0, q_inst} : 16'd0),
                .in_t(q_t),
                .in_normal_u(q_best ? {{24{nm_code[7]}}, nm_code[7:0]} : 32'd0),
                .in_normal_v(q_best ? {{24{nm_code[15]}}, nm_code[15:8]} : 32'd0),
                .in_colour_r(q_best ? q_r : 8'd0), .in_colour_g(q_best ? q_g : 8'd0),
                .in_colour_b(q_best ? q_b : 8'd0),
                .out_valid(u_valid[g]), .out_word(word), .out_ov(u_ov[g]));
            reg [PIXW-1:0] pixel;                 // the record leaving the pack
            always @(posedge clk) if (nm_valid) pixel <= q[PIXW-1:0];
            assign u_data[g*RW +: RW] = {pixel, word};
        end
    endgenerate
    assign err_overflow = |(u_valid & u_ov);
endmodule
`default_nettype wire
