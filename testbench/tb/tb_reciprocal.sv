// tb_reciprocal: svo_reciprocal against reciprocal.hex (`sim vectors`), its seed ROM loaded
// from the same folder's reciprocal_seed.hex; see tb_common.svh. UNITS reciprocals side by
// side (the package's UNITS: three per walk-issue lane, `sim vectors --walk-lanes`), row i
// in unit i mod UNITS, all units fed in the same cycle.
`timescale 1ns/1ps
module tb_reciprocal;
    import reciprocal_vectors_pkg::*;
    localparam UNIT = "reciprocal";
    `define TB_UNITS UNITS
    `include "tb_common.svh"

    wire [UNITS-1:0]    got_valid, got_zero, got_negative, got_flushed, got_ov;
    wire [UNITS*52-1:0] got_inv;
    string seed_path;
    genvar g;
    generate for (g = 0; g < UNITS; g = g + 1) begin : lane
        svo_reciprocal dut (
            .clk(clk), .rst(rst), .in_valid(drive_valid_u[g]),
            .in_d(drive_rows_all[g*WORD_BITS + D_LSB +: 32]),
            .in_sign_negative(drive_rows_all[g*WORD_BITS + SIGN_NEGATIVE_LSB]),
            .out_valid(got_valid[g]), .out_inv(got_inv[g*52 +: 52]), .out_zero(got_zero[g]),
            .out_negative(got_negative[g]), .out_flushed(got_flushed[g]), .out_ov(got_ov[g]));
        // After the path is set (time 0), well before reset ends.
        initial begin
            #1;
            $readmemh(seed_path, dut.rom);
        end
    end endgenerate

    initial begin
        require_width("d", 32, D_WIDTH);
        require_width("inv", 52, INV_WIDTH);
        if (!$value$plusargs("vectors=%s", seed_path)) seed_path = "vectors";
        seed_path = $sformatf("%0s/reciprocal_seed.hex", seed_path);
    end

    // Units in unit order: the rows of one cycle are checked in row order.
    int u;
    always @(negedge clk) if (!rst) for (u = 0; u < UNITS; u = u + 1) if (got_valid[u] === 1'b1) begin
        check_row_begin();
        check_field("inv", got_inv[u*52 +: 52], exp_row[INV_LSB +: 52]);
        check_field("zero", got_zero[u], exp_row[ZERO_LSB]);
        check_field("negative", got_negative[u], exp_row[NEGATIVE_LSB]);
        check_field("flushed", got_flushed[u], exp_row[FLUSHED_LSB]);
        check_field("ov", got_ov[u], exp_row[OV_LSB]);
        check_row_end();
    end
    // The RTL's own latency, read back for the comparison with the model's (tests/testbench_icarus.rs).
    initial $display("rtl LATENCY svo_reciprocal %0d", lane[0].dut.LATENCY);
endmodule
