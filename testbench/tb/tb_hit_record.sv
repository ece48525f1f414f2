// tb_hit_record: svo_hit_pack and svo_hit_check against hit_record.hex (`sim vectors`): each
// row drives both (the record into the packer, the previous word and the frame's reuse inputs
// into the check) and every output of both is compared; see tb_common.svh. The package's
// LATENCY is units.hit_pack; the check's latency (units.hit_unpack) is the same 1 cycle in
// the default configuration, and both must leave together.
`timescale 1ns/1ps
module tb_hit_record;
    import hit_record_vectors_pkg::*;
    localparam UNIT = "hit_record";
    `include "tb_common.svh"

    localparam IW = PREV_INSTANCE_WIDTH, TW = PREV_T_WIDTH, NW = PREV_NORMAL_U_WIDTH;
    localparam WB = WORD_WIDTH;
    wire          pack_valid, got_ov;
    wire [WB-1:0] got_word;
    svo_hit_pack #(.INST_W(IW), .T_W(TW), .N_W(NW)) pack (
        .clk(clk), .rst(rst), .in_valid(drive_valid),
        .in_kind(drive_row[KIND_LSB +: 2]), .in_instance_valid(drive_row[INSTANCE_VALID_LSB]),
        .in_instance(drive_row[INSTANCE_LSB +: 16]), .in_t(drive_row[T_LSB +: 64]),
        .in_normal_u(drive_row[NORMAL_U_LSB +: 32]), .in_normal_v(drive_row[NORMAL_V_LSB +: 32]),
        .in_colour_r(drive_row[COLOUR_R_LSB +: 8]), .in_colour_g(drive_row[COLOUR_G_LSB +: 8]),
        .in_colour_b(drive_row[COLOUR_B_LSB +: 8]),
        .out_valid(pack_valid), .out_word(got_word), .out_ov(got_ov));

    wire          check_valid, got_hit, got_reuse;
    wire [1:0]    got_kind;
    wire [IW-1:0] got_instance;
    wire [TW-1:0] got_t;
    wire [NW-1:0] got_nu, got_nv;
    wire [7:0]    got_r, got_g, got_b;
    wire [WB-1:0] got_reused;
    svo_hit_check #(.INST_W(IW), .T_W(TW), .N_W(NW)) check (
        .clk(clk), .rst(rst), .in_valid(drive_valid),
        .in_prev(drive_row[PREV_LSB +: WB]), .in_buffer(drive_row[BUFFER_LSB]),
        .in_camera_dirty(drive_row[CAMERA_DIRTY_LSB]),
        .in_candidates(drive_row[CANDIDATES_LSB +: 16]),
        .in_candidate(drive_row[CANDIDATE_LSB +: 16]),
        .in_instance_dirty(drive_row[INSTANCE_DIRTY_LSB]),
        .out_valid(check_valid), .out_kind(got_kind), .out_hit(got_hit),
        .out_instance(got_instance), .out_t(got_t), .out_normal_u(got_nu), .out_normal_v(got_nv),
        .out_colour_r(got_r), .out_colour_g(got_g), .out_colour_b(got_b),
        .out_reuse(got_reuse), .out_reused_word(got_reused));

    initial begin
        require_width("word", WB, REUSED_WORD_WIDTH);
        require_width("prev", WB, PREV_WIDTH);
        require_width("word bits", 2 + IW + TW + 2 * NW + 24, WB);
        require_width("prev_t signed", 0, PREV_T_SIGNED);
        require_width("colour (RGB888)", 8, PREV_COLOUR_G_WIDTH);
        require_width("candidates", 16, CANDIDATES_WIDTH);
        require_width("instance", 16, INSTANCE_WIDTH);
        require_width("t", 64, T_WIDTH);
    end

    always @(negedge clk) if (!rst && (pack_valid === 1'b1 || check_valid === 1'b1)) begin
        check_row_begin();
        check_field("valid together", {pack_valid, check_valid}, 2'b11);
        check_field("word", got_word, exp_row[WORD_LSB +: WB]);
        check_field("ov", got_ov, exp_row[OV_LSB]);
        check_field("prev_kind", got_kind, exp_row[PREV_KIND_LSB +: 2]);
        check_field("prev_hit", got_hit, exp_row[PREV_HIT_LSB]);
        check_field("prev_instance", got_instance, exp_row[PREV_INSTANCE_LSB +: IW]);
        check_field("prev_t", got_t, exp_row[PREV_T_LSB +: TW]);
        check_field("prev_normal_u", got_nu, exp_row[PREV_NORMAL_U_LSB +: NW]);
        check_field("prev_normal_v", got_nv, exp_row[PREV_NORMAL_V_LSB +: NW]);
        check_field("prev_colour_r", got_r, exp_row[PREV_COLOUR_R_LSB +: 8]);
        check_field("prev_colour_g", got_g, exp_row[PREV_COLOUR_G_LSB +: 8]);
        check_field("prev_colour_b", got_b, exp_row[PREV_COLOUR_B_LSB +: 8]);
        check_field("reuse", got_reuse, exp_row[REUSE_LSB]);
        check_field("reused_word", got_reused, exp_row[REUSED_WORD_LSB +: WB]);
        check_row_end();
    end
    // The RTL's own latencies, read back for the comparison with the model's
    // (tests/testbench_icarus.rs): the packer's is units.hit_pack, the check's units.hit_unpack.
    initial $display("rtl LATENCY svo_hit_pack %0d", pack.LATENCY);
    initial $display("rtl LATENCY svo_hit_check %0d", check.LATENCY);
endmodule
