// tb_raygen: svo_raygen against raygen.hex (`sim vectors`): every direction and position code,
// both flags and the pixel carried beside them; see tb_common.svh.
`timescale 1ns/1ps
module tb_raygen;
    import raygen_vectors_pkg::*;
    localparam UNIT = "raygen";
    `include "tb_common.svh"

    localparam DW = DIR_X_WIDTH, PW = ORIGIN_X_WIDTH;
    wire            got_valid, got_ov_dir, got_ov_origin;
    wire [31:0]     got_pixel;
    wire [3*DW-1:0] got_dir;
    wire [3*PW-1:0] got_origin;
    // Fields of one vector are contiguous x, y, z, so whole vectors slice out at once.
    svo_raygen #(.DW(DW), .DF(DIR_X_FRAC), .PW(PW), .PF(ORIGIN_X_FRAC)) dut (
        .clk(clk), .rst(rst), .in_valid(drive_valid),
        .in_pixel(drive_row[PIXEL_X_LSB +: 32]),
        .in_dir(drive_row[DIR_F64_X_LSB +: 192]), .in_origin(drive_row[ORIGIN_F64_X_LSB +: 192]),
        .out_valid(got_valid), .out_pixel(got_pixel), .out_dir(got_dir), .out_origin(got_origin),
        .out_ov_dir(got_ov_dir), .out_ov_origin(got_ov_origin));

    initial begin
        require_width("pixel x, y contiguous", PIXEL_X_LSB + 16, PIXEL_Y_LSB);
        require_width("pixel_x", 16, PIXEL_X_WIDTH);
        require_width("dir_f64 contiguous", DIR_F64_X_LSB + 128, DIR_F64_Z_LSB);
        require_width("origin_f64 contiguous", ORIGIN_F64_X_LSB + 128, ORIGIN_F64_Z_LSB);
        require_width("dir_x signed", 1, DIR_X_SIGNED);
        require_width("origin_x signed", 1, ORIGIN_X_SIGNED);
        require_width("dir_y", DW, DIR_Y_WIDTH);
        require_width("origin_y", PW, ORIGIN_Y_WIDTH);
    end

    always @(negedge clk) if (!rst && got_valid === 1'b1) begin
        check_row_begin();
        check_field("pixel", got_pixel, exp_row[PIXEL_X_LSB +: 32]);
        check_field("dir_x", got_dir[0 +: DW], exp_row[DIR_X_LSB +: DW]);
        check_field("dir_y", got_dir[DW +: DW], exp_row[DIR_Y_LSB +: DW]);
        check_field("dir_z", got_dir[2*DW +: DW], exp_row[DIR_Z_LSB +: DW]);
        check_field("origin_x", got_origin[0 +: PW], exp_row[ORIGIN_X_LSB +: PW]);
        check_field("origin_y", got_origin[PW +: PW], exp_row[ORIGIN_Y_LSB +: PW]);
        check_field("origin_z", got_origin[2*PW +: PW], exp_row[ORIGIN_Z_LSB +: PW]);
        check_field("ov_dir", got_ov_dir, exp_row[OV_DIR_LSB]);
        check_field("ov_origin", got_ov_origin, exp_row[OV_ORIGIN_LSB]);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_raygen %0d", dut.LATENCY);
endmodule
