// tb_sphere: svo_sphere (square root included) against sphere.hex (`sim vectors`); see
// tb_common.svh.
`timescale 1ns/1ps
module tb_sphere;
    import sphere_vectors_pkg::*;
    localparam UNIT = "sphere";
    `include "tb_common.svh"

    wire        got_valid, got_hit, got_ov_reach, got_ov_t_enter;
    wire [31:0] got_t_enter;
    // reach^2 is a host constant like T (svo_sphere.v): the testbench is the host here.
    wire [79:0] reach2 = drive_row[REACH_LSB +: 40] * drive_row[REACH_LSB +: 40];
    svo_sphere dut (
        .clk(clk), .rst(rst), .in_valid(drive_valid),
        .in_o(drive_row[O_X_LSB +: 120]), .in_d(drive_row[D_X_LSB +: 96]),
        .in_c(drive_row[C_X_LSB +: 120]),
        .in_threshold(drive_row[THRESHOLD_LSB +: 64]), .in_inside(drive_row[INSIDE_LSB +: 64]),
        .in_delta_t(drive_row[DELTA_T_LSB +: 34]), .in_reach(drive_row[REACH_LSB +: 40]),
        .in_reach2(reach2),
        .out_valid(got_valid), .out_hit(got_hit), .out_t_enter(got_t_enter),
        .out_ov_reach(got_ov_reach), .out_ov_t_enter(got_ov_t_enter));

    initial begin
        require_width("o_x", 40, O_X_WIDTH);
        require_width("d_x", 32, D_X_WIDTH);
        require_width("c_x", 40, C_X_WIDTH);
        require_width("threshold", 64, THRESHOLD_WIDTH);
        require_width("inside", 64, INSIDE_WIDTH);
        require_width("delta_t", 34, DELTA_T_WIDTH);
        require_width("reach", 40, REACH_WIDTH);
        require_width("t_enter", 32, T_ENTER_WIDTH);
    end

    always @(negedge clk) if (!rst && got_valid === 1'b1) begin
        check_row_begin();
        check_field("hit", got_hit, exp_row[HIT_LSB]);
        check_field("t_enter", got_t_enter, exp_row[T_ENTER_LSB +: 32]);
        check_field("ov_reach", got_ov_reach, exp_row[OV_REACH_LSB]);
        check_field("ov_t_enter", got_ov_t_enter, exp_row[OV_T_ENTER_LSB]);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_sphere %0d", dut.LATENCY);
endmodule
