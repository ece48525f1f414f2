// tb_transform: svo_transform against transform.hex (`sim vectors`); see tb_common.svh.
// UNITS transforms side by side (the package's UNITS: one per walk-issue lane, `sim vectors
// --walk-lanes`), row i in unit i mod UNITS, all units fed in the same cycle.
`timescale 1ns/1ps
module tb_transform;
    import transform_vectors_pkg::*;
    localparam UNIT = "transform";
    `define TB_UNITS UNITS
    `include "tb_common.svh"

    wire [UNITS-1:0]      got_valid;
    wire [UNITS*120-1:0]  got_o;
    wire [UNITS*96-1:0]   got_d;
    wire [UNITS*3-1:0]    got_sign;
    wire [UNITS-1:0]      got_ov_origin, got_ov_dir;
    // Fields of one vector are contiguous x, y, z (axis k component j at 3k + j), so whole
    // vectors slice out at once.
    genvar g;
    generate for (g = 0; g < UNITS; g = g + 1) begin : lane
        svo_transform dut (
            .clk(clk), .rst(rst), .in_valid(drive_valid_u[g]),
            .in_o(drive_rows_all[g*WORD_BITS + O_X_LSB +: 120]),
            .in_d(drive_rows_all[g*WORD_BITS + D_X_LSB +: 96]),
            .in_axes(drive_rows_all[g*WORD_BITS + AXIS0_X_LSB +: 288]),
            .in_c(drive_rows_all[g*WORD_BITS + C_X_LSB +: 120]),
            .out_valid(got_valid[g]), .out_o(got_o[g*120 +: 120]), .out_d(got_d[g*96 +: 96]),
            .out_sign(got_sign[g*3 +: 3]), .out_ov_origin(got_ov_origin[g]),
            .out_ov_dir(got_ov_dir[g]));
    end endgenerate

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

    // Units in unit order: the rows of one cycle are checked in row order.
    int u;
    always @(negedge clk) if (!rst) for (u = 0; u < UNITS; u = u + 1) if (got_valid[u] === 1'b1) begin
        check_row_begin();
        check_field("local_o_x", got_o[u*120 + 0 +: 40], exp_row[LOCAL_O_X_LSB +: 40]);
        check_field("local_o_y", got_o[u*120 + 40 +: 40], exp_row[LOCAL_O_Y_LSB +: 40]);
        check_field("local_o_z", got_o[u*120 + 80 +: 40], exp_row[LOCAL_O_Z_LSB +: 40]);
        check_field("local_d_x", got_d[u*96 + 0 +: 32], exp_row[LOCAL_D_X_LSB +: 32]);
        check_field("local_d_y", got_d[u*96 + 32 +: 32], exp_row[LOCAL_D_Y_LSB +: 32]);
        check_field("local_d_z", got_d[u*96 + 64 +: 32], exp_row[LOCAL_D_Z_LSB +: 32]);
        check_field("sign_x", got_sign[u*3 + 0], exp_row[SIGN_X_LSB]);
        check_field("sign_y", got_sign[u*3 + 1], exp_row[SIGN_Y_LSB]);
        check_field("sign_z", got_sign[u*3 + 2], exp_row[SIGN_Z_LSB]);
        check_field("ov_origin", got_ov_origin[u], exp_row[OV_ORIGIN_LSB]);
        check_field("ov_dir", got_ov_dir[u], exp_row[OV_DIR_LSB]);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_transform %0d", lane[0].dut.LATENCY);
endmodule
