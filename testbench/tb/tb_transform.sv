// tb_transform: svo_transform against transform.hex (`sim vectors`); see tb_common.svh.
`timescale 1ns/1ps
module tb_transform;
    import transform_vectors_pkg::*;
    localparam UNIT = "transform";
    `include "tb_common.svh"

    wire          got_valid;
    wire [119:0]  got_o;
    wire [95:0]   got_d;
    wire [2:0]    got_sign;
    wire          got_ov_origin, got_ov_dir;
    // Fields of one vector are contiguous x, y, z (axis k component j at 3k + j), so whole
    // vectors slice out at once.
    svo_transform dut (
        .clk(clk), .rst(rst), .in_valid(drive_valid),
        .in_o(drive_row[O_X_LSB +: 120]), .in_d(drive_row[D_X_LSB +: 96]),
        .in_axes(drive_row[AXIS0_X_LSB +: 288]), .in_c(drive_row[C_X_LSB +: 120]),
        .out_valid(got_valid), .out_o(got_o), .out_d(got_d), .out_sign(got_sign),
        .out_ov_origin(got_ov_origin), .out_ov_dir(got_ov_dir));

    initial begin
        require_width("o_x", 40, O_X_WIDTH);
        require_width("d_x", 32, D_X_WIDTH);
        require_width("axis0_x", 32, AXIS0_X_WIDTH);
        require_width("c_x", 40, C_X_WIDTH);
        require_width("local_o_x", 40, LOCAL_O_X_WIDTH);
        require_width("local_d_x", 32, LOCAL_D_X_WIDTH);
        require_width("o contiguous", O_X_LSB + 80, O_Z_LSB);
        require_width("axes contiguous", AXIS0_X_LSB + 256, AXIS2_Z_LSB);
    end

    always @(negedge clk) if (!rst && got_valid === 1'b1) begin
        check_row_begin();
        check_field("local_o_x", got_o[0 +: 40], exp_row[LOCAL_O_X_LSB +: 40]);
        check_field("local_o_y", got_o[40 +: 40], exp_row[LOCAL_O_Y_LSB +: 40]);
        check_field("local_o_z", got_o[80 +: 40], exp_row[LOCAL_O_Z_LSB +: 40]);
        check_field("local_d_x", got_d[0 +: 32], exp_row[LOCAL_D_X_LSB +: 32]);
        check_field("local_d_y", got_d[32 +: 32], exp_row[LOCAL_D_Y_LSB +: 32]);
        check_field("local_d_z", got_d[64 +: 32], exp_row[LOCAL_D_Z_LSB +: 32]);
        check_field("sign_x", got_sign[0], exp_row[SIGN_X_LSB]);
        check_field("sign_y", got_sign[1], exp_row[SIGN_Y_LSB]);
        check_field("sign_z", got_sign[2], exp_row[SIGN_Z_LSB]);
        check_field("ov_origin", got_ov_origin, exp_row[OV_ORIGIN_LSB]);
        check_field("ov_dir", got_ov_dir, exp_row[OV_DIR_LSB]);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_transform %0d", dut.LATENCY);
endmodule
