// tb_reciprocal: svo_reciprocal against reciprocal.hex (`sim vectors`), its seed ROM loaded
// from the same folder's reciprocal_seed.hex; see tb_common.svh.
`timescale 1ns/1ps
module tb_reciprocal;
    import reciprocal_vectors_pkg::*;
    localparam UNIT = "reciprocal";
    `include "tb_common.svh"

    wire        got_valid, got_zero, got_negative, got_flushed, got_ov;
    wire [51:0] got_inv;
    svo_reciprocal dut (
        .clk(clk), .rst(rst), .in_valid(drive_valid),
        .in_d(drive_row[D_LSB +: 32]), .in_sign_negative(drive_row[SIGN_NEGATIVE_LSB]),
        .out_valid(got_valid), .out_inv(got_inv), .out_zero(got_zero),
        .out_negative(got_negative), .out_flushed(got_flushed), .out_ov(got_ov));

    string seed_path;
    initial begin
        require_width("d", 32, D_WIDTH);
        require_width("inv", 52, INV_WIDTH);
        if (!$value$plusargs("vectors=%s", seed_path)) seed_path = "vectors";
        seed_path = $sformatf("%0s/reciprocal_seed.hex", seed_path);
        $readmemh(seed_path, dut.rom);
    end

    always @(negedge clk) if (!rst && got_valid === 1'b1) begin
        check_row_begin();
        check_field("inv", got_inv, exp_row[INV_LSB +: 52]);
        check_field("zero", got_zero, exp_row[ZERO_LSB]);
        check_field("negative", got_negative, exp_row[NEGATIVE_LSB]);
        check_field("flushed", got_flushed, exp_row[FLUSHED_LSB]);
        check_field("ov", got_ov, exp_row[OV_LSB]);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_reciprocal %0d", dut.LATENCY);
endmodule
