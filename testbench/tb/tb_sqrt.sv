// tb_sqrt: svo_sqrt against sqrt.hex (`sim vectors`); see tb_common.svh.
`timescale 1ns/1ps
module tb_sqrt;
    import sqrt_vectors_pkg::*;
    localparam UNIT = "sqrt";
    `include "tb_common.svh"

    wire        got_valid;
    wire [31:0] got_root;
    svo_sqrt #(.N(64)) dut (
        .clk(clk), .rst(rst), .in_valid(drive_valid), .in_x(drive_row[X_LSB +: 64]),
        .out_valid(got_valid), .out_root(got_root));

    initial begin
        require_width("x", 64, X_WIDTH);
        require_width("root", 32, ROOT_WIDTH);
    end

    always @(negedge clk) if (!rst && got_valid === 1'b1) begin
        check_row_begin();
        check_field("root", got_root, exp_row[ROOT_LSB +: 32]);
        check_field("ov", 1'b0, exp_row[OV_LSB]);   // a 64-bit radicand's root always fits
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_sqrt %0d", dut.LATENCY);
endmodule
