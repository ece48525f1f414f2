// tb_walker_root: svo_walker_root against walker_root.hex (`sim vectors`); see tb_common.svh.
// UNITS roots side by side (the package's UNITS: one per walk-issue lane, `sim vectors
// --walk-lanes`), row i in unit i mod UNITS, all units fed in the same cycle. Besides the
// row's outputs (enter, t0, t1, the mirrored origin o'), each unit's side-band is checked
// against the row's inputs: half extents, zero and negative flags, and a one-bit tag (the
// row's parity) that travels beside the walk.
// tb_walker.sv runs the same RTL in front of each walker and checks it through the walks.
`timescale 1ns/1ps
module tb_walker_root;
    import walker_root_vectors_pkg::*;
    localparam UNIT = "walker_root";
    `define TB_UNITS UNITS
    `include "tb_common.svh"

    localparam int PW = O_X_WIDTH;        // pos
    localparam int IW = INV_X_WIDTH;      // 1/|d|
    localparam int TI = T0_X_WIDTH;       // t, one bit wider for the sentinels
    localparam int OW = OM_X_WIDTH;       // o', one bit wider than pos

    wire [UNITS-1:0]      got_valid, got_enter, got_tag;
    wire [UNITS*3*TI-1:0] got_t0, got_t1;
    wire [UNITS*3*OW-1:0] got_o;
    wire [UNITS*3*PW-1:0] got_half;
    wire [UNITS*3-1:0]    got_zero, got_neg;
    // Fields of one vector are contiguous x, y, z (checked below), so whole vectors slice out
    // at once, {z, y, x} as the ports take them.
    genvar g;
    generate for (g = 0; g < UNITS; g = g + 1) begin : lane
        wire [WORD_BITS-1:0] r = drive_rows_all[g*WORD_BITS +: WORD_BITS];
        svo_walker_root #(
            .POS_W(PW), .POS_FRAC(O_X_FRAC), .INV_W(IW), .INV_FRAC(INV_X_FRAC),
            .T_W(TI - 1), .T_FRAC(T0_X_FRAC), .PROD(LATENCY - 4), .TAG_W(1)
        ) dut (
            .clk(clk), .rst(rst), .in_valid(drive_valid_u[g]),
            .in_o(r[O_X_LSB +: 3*PW]), .in_inv(r[INV_X_LSB +: 3*IW]),
            .in_zero(r[ZERO_X_LSB +: 3]), .in_neg(r[NEGATIVE_X_LSB +: 3]),
            .in_half(r[HALF_X_LSB +: 3*PW]), .in_tag(^r),
            .out_valid(got_valid[g]), .out_enter(got_enter[g]),
            .out_t0(got_t0[g*3*TI +: 3*TI]), .out_t1(got_t1[g*3*TI +: 3*TI]),
            .out_o(got_o[g*3*OW +: 3*OW]), .out_half(got_half[g*3*PW +: 3*PW]),
            .out_zero(got_zero[g*3 +: 3]), .out_neg(got_neg[g*3 +: 3]),
            .out_tag(got_tag[g]));
    end endgenerate

    initial begin
        require_width("om_x", PW + 1, OW);
        require_width("inv_y", IW, INV_Y_WIDTH);
        require_width("o contiguous", O_X_LSB + 2*PW, O_Z_LSB);
        require_width("inv contiguous", INV_X_LSB + 2*IW, INV_Z_LSB);
        require_width("zero contiguous", ZERO_X_LSB + 2, ZERO_Z_LSB);
        require_width("negative contiguous", NEGATIVE_X_LSB + 2, NEGATIVE_Z_LSB);
        require_width("half contiguous", HALF_X_LSB + 2*PW, HALF_Z_LSB);
    end

    // Units in unit order: the rows of one cycle are checked in row order.
    int u;
    always @(negedge clk) if (!rst) for (u = 0; u < UNITS; u = u + 1) if (got_valid[u] === 1'b1) begin
        check_row_begin();
        check_field("enter", got_enter[u], exp_row[ENTER_LSB]);
        check_field("t0_x", got_t0[u*3*TI + 0*TI +: TI], exp_row[T0_X_LSB +: TI]);
        check_field("t0_y", got_t0[u*3*TI + 1*TI +: TI], exp_row[T0_Y_LSB +: TI]);
        check_field("t0_z", got_t0[u*3*TI + 2*TI +: TI], exp_row[T0_Z_LSB +: TI]);
        check_field("t1_x", got_t1[u*3*TI + 0*TI +: TI], exp_row[T1_X_LSB +: TI]);
        check_field("t1_y", got_t1[u*3*TI + 1*TI +: TI], exp_row[T1_Y_LSB +: TI]);
        check_field("t1_z", got_t1[u*3*TI + 2*TI +: TI], exp_row[T1_Z_LSB +: TI]);
        check_field("om_x", got_o[u*3*OW + 0*OW +: OW], exp_row[OM_X_LSB +: OW]);
        check_field("om_y", got_o[u*3*OW + 1*OW +: OW], exp_row[OM_Y_LSB +: OW]);
        check_field("om_z", got_o[u*3*OW + 2*OW +: OW], exp_row[OM_Z_LSB +: OW]);
        // The side-band, against the row's own inputs.
        check_field("half", got_half[u*3*PW +: 3*PW], exp_row[HALF_X_LSB +: 3*PW]);
        check_field("zero", got_zero[u*3 +: 3], exp_row[ZERO_X_LSB +: 3]);
        check_field("negative", got_neg[u*3 +: 3], exp_row[NEGATIVE_X_LSB +: 3]);
        check_field("tag", got_tag[u], ^exp_row);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_walker_root %0d", lane[0].dut.LATENCY);
endmodule
