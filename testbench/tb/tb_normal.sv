// tb_normal: svo_normal against normal.hex (`sim vectors`): the attribute's octahedral code
// and the instance's normal matrix in, the record's (u, v) codes out; see tb_common.svh.
`timescale 1ns/1ps
module tb_normal;
    import normal_vectors_pkg::*;
    localparam UNIT = "normal";
    `include "tb_common.svh"

    localparam NW = U_WIDTH;
    wire          got_valid;
    wire [2*NW-1:0] got_code;       // {v, u}
    svo_normal #(.N_W(NW)) dut (
        .clk(clk), .rst(rst), .in_valid(drive_valid),
        .in_oct({drive_row[OCT_V_LSB +: 16], drive_row[OCT_U_LSB +: 16]}),
        .in_mat(drive_row[M_XX_LSB +: 9 * 18]),
        .out_valid(got_valid), .out_code(got_code));

    initial begin
        require_width("oct_u", 16, OCT_U_WIDTH);
        require_width("m_xx", 18, M_XX_WIDTH);
        require_width("m_zz", 18, M_ZZ_WIDTH);
        require_width("v", NW, V_WIDTH);
    end

    always @(negedge clk) if (!rst && got_valid === 1'b1) begin
        check_row_begin();
        check_field("u", got_code[NW-1:0], exp_row[U_LSB +: NW]);
        check_field("v", got_code[2*NW-1:NW], exp_row[V_LSB +: NW]);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_normal %0d", dut.LATENCY);
endmodule
