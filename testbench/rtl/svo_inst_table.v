// svo_inst_table: the instance table (issue 29) — NINST instances' registers in on-chip RAM,
// written by the host word by word, read by the sphere lanes and the walk section.
//
// Pipeline position: beside svo_core, on the host's side (svo_top). It replaces the eight
// instance register sets of the register block, so a frame can hold more instances than the
// core has sphere lanes: the lanes take ⌈n / LANES⌉ passes over it (svo_front.v).
//
// - Layout: instance k is a row of WORDS = 39 32-bit words, in the order of svo_core.rdl's
//   instance_rf (AXIS[9] sQ2.30; C_LO[3], C_HI[3], HALF_LO[3], HALF_HI[3] sQ8.32; REACH
//   LO/HI uQ8.32; THRESHOLD and INSIDE LO/HI uQ16.48; DELTA_T LO/HI sQ10.24; IMAGE; NMAT[9]
//   sQ2.16). Each word keeps only its field's bits (a _HI word of a 40-bit value its low 8);
//   a word index of 39 or more is not stored (writes dropped, reads 0).
// - Host port (`h_*`): one request a cycle, `h_wr` a write of `h_data` under the bit enables
//   `h_biten` to word `h_word` of instance `h_inst`, else a read; `h_rdata` is the word,
//   registered (valid the cycle after the request). A write of REACH recomputes the
//   instance's reach² (the sphere test's uQ16.64 constant, the model's host value) in the
//   next cycle, so it is ready before any frame can start.
// - Read ports, all asynchronous (the table is LUT RAM read by replicated ports; a frame's
//   reads see the row in the cycle they address it, as the instance registers were): LANES
//   sphere ports (lane l: instance `sp_base` + l), the transform's (`tr`), the walker root's
//   (`rt`), the walker's (`dp`: the image bases through the frame's image slots `img_*`,
//   word indices) and the normal unit's (`nm`), each WK times (one per walk-issue lane, lane
//   j at [j*8 +: 8]). An instance ≥ NINST reads as zeros.
// - `bad_image`: bit k set while instance k's IMAGE is IMAGES or more (svo_top refuses the
//   frame, STATUS.ERROR 4).
`timescale 1ns/1ps
`default_nettype none
module svo_inst_table #(
    parameter NINST  = 128,
    parameter LANES  = 8,
    parameter IMAGES = 8,
    parameter WK     = 1                          // walk-issue lanes: ports per walk reader
) (
    input  wire                    clk,
    // the host's port
    input  wire                    h_req,
    input  wire                    h_wr,
    input  wire [7:0]              h_inst,
    input  wire [5:0]              h_word,
    input  wire [31:0]             h_data,
    input  wire [31:0]             h_biten,
    output reg  [31:0]             h_rdata,
    output wire [NINST-1:0]        bad_image,
    // the sphere lanes
    input  wire [7:0]              sp_base,
    output reg  [LANES*120-1:0]    sp_c,
    output reg  [LANES*64-1:0]     sp_threshold,
    output reg  [LANES*64-1:0]     sp_inside,
    output reg  [LANES*34-1:0]     sp_delta_t,
    output reg  [LANES*40-1:0]     sp_reach,
    output reg  [LANES*80-1:0]     sp_reach2,
    // the walk section: WK ports per reader, lane j at [j*8 +: 8] and its fields' j-th slice
    input  wire [WK*8-1:0]         tr,
    output wire [WK*288-1:0]       tr_axes,
    output wire [WK*120-1:0]       tr_c,
    input  wire [WK*8-1:0]         rt,
    output wire [WK*120-1:0]       rt_half,
    input  wire [WK*8-1:0]         dp,
    input  wire [IMAGES*32-1:0]    img_node_base,
    input  wire [IMAGES*32-1:0]    img_attr_base,
    output wire [WK*32-1:0]        dp_node_base,
    output wire [WK*32-1:0]        dp_attr_base,
    input  wire [WK*8-1:0]         nm,
    output wire [WK*9*18-1:0]      nm_nmat
);
    localparam WORDS = 39;
    localparam ROW = WORDS * 32;
    localparam IW = IMAGES > 1 ? $clog2(IMAGES) : 1;
    localparam XW = NINST > 1 ? $clog2(NINST) : 1;   // row index bits
    localparam integer NINST_I = NINST;
    localparam integer IMAGES_I = IMAGES;
    localparam integer WORDS_I = WORDS;
    localparam [7:0] NINST8 = NINST_I[7:0];
    localparam [8:0] IMAGES9 = IMAGES_I[8:0];
    localparam [5:0] WORDS6 = WORDS_I[5:0];
    generate
        if (NINST < 1 || NINST > 255 || IMAGES < 1 || IMAGES > 256) begin : bad_params
            svo_inst_table_NINST_must_be_1_to_255 bad();
        end
    endgenerate

    reg [ROW-1:0] mem [0:NINST-1];
    reg [79:0]    reach2 [0:NINST-1];
    reg [NINST-1:0] img_bad;
    assign bad_image = img_bad;

    // The bits a word keeps.
    function automatic [31:0] keep(input [5:0] w);
        if ((w >= 6'd12 && w <= 6'd14) || (w >= 6'd18 && w <= 6'd20) || w == 6'd22 || w == 6'd29)
            keep = 32'h0000_00ff;
        else if (w == 6'd28) keep = 32'h0000_0003;
        else if (w >= 6'd30 && w <= 6'd38) keep = 32'h0003_ffff;
        else if (w < WORDS6) keep = 32'hffff_ffff;
        else keep = 32'd0;
    endfunction
    function automatic [31:0] word_of(input [ROW-1:0] r, input integer w);
        word_of = r[w*32 +: 32];
    endfunction
    function automatic [ROW-1:0] row(input [7:0] k);
        row = k < NINST8 ? mem[k[XW-1:0]] : {ROW{1'b0}};
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */
    function automatic [39:0] reach_of(input [ROW-1:0] rr);
        reach_of = {rr[22*32 +: 8], rr[21*32 +: 32]};
    endfunction
    /* verilator lint_on UNUSEDSIGNAL */

    // ---------------------------------------------------------------- host port
    wire h_ok = h_inst < NINST8 && h_word < WORDS6;
    wire [ROW-1:0] h_row = row(h_inst);
    wire [31:0] h_old = h_word < WORDS6 ? h_row[h_word * 32 +: 32] : 32'd0;
    wire [31:0] h_new = ((h_old & ~h_biten) | (h_data & h_biten)) & keep(h_word);
    reg       fix;                                // recompute reach² of fix_inst
    reg [XW-1:0] fix_inst;
    wire [39:0] fix_reach = reach_of(mem[fix_inst]);
    always @(posedge clk) begin
        h_rdata <= h_old;
        fix <= h_req && h_wr && h_ok && (h_word == 6'd21 || h_word == 6'd22);
        fix_inst <= h_inst[XW-1:0];
        if (h_req && h_wr && h_ok) begin
            mem[h_inst[XW-1:0]][h_word * 32 +: 32] <= h_new;
            if (h_word == 6'd29) img_bad[h_inst[XW-1:0]] <= {1'b0, h_new[7:0]} >= IMAGES9;
        end
        if (fix) reach2[fix_inst] <= {40'd0, fix_reach} * {40'd0, fix_reach};
    end
    initial img_bad = {NINST{1'b0}};

    // ---------------------------------------------------------------- sphere lanes
    integer l, j;
    /* verilator lint_off UNUSEDSIGNAL */
    reg [ROW-1:0] r;                              // the lanes read some of its fields
    /* verilator lint_on UNUSEDSIGNAL */
    reg [7:0] k;
    always @* begin
        for (l = 0; l < LANES; l = l + 1) begin
            k = sp_base + l[7:0];
            r = row(k);
            for (j = 0; j < 3; j = j + 1)
                sp_c[l*120 + j*40 +: 40] = {r[(12+j)*32 +: 8], r[(9+j)*32 +: 32]};
            sp_threshold[l*64 +: 64] = {word_of(r, 24), word_of(r, 23)};
            sp_inside[l*64 +: 64] = {word_of(r, 26), word_of(r, 25)};
            sp_delta_t[l*34 +: 34] = {r[28*32 +: 2], word_of(r, 27)};
            sp_reach[l*40 +: 40] = reach_of(r);
            sp_reach2[l*80 +: 80] = k < NINST8 ? reach2[k[XW-1:0]] : 80'd0;
        end
    end

    // ---------------------------------------------------------------- the walk section
    genvar g, p;
    generate
        for (p = 0; p < WK; p = p + 1) begin : walk_port
            /* verilator lint_off UNUSEDSIGNAL */
            wire [ROW-1:0] r_tr = row(tr[p*8 +: 8]), r_rt = row(rt[p*8 +: 8]),
                           r_dp = row(dp[p*8 +: 8]), r_nm = row(nm[p*8 +: 8]);   // each reader takes its fields
            /* verilator lint_on UNUSEDSIGNAL */
            for (g = 0; g < 3; g = g + 1) begin : xyz
                assign tr_axes[p*288 + g*96 +: 96] = r_tr[g*96 +: 96];
                assign tr_c[p*120 + g*40 +: 40] = {r_tr[(12+g)*32 +: 8], r_tr[(9+g)*32 +: 32]};
                assign rt_half[p*120 + g*40 +: 40] = {r_rt[(18+g)*32 +: 8], r_rt[(15+g)*32 +: 32]};
            end
            for (g = 0; g < 9; g = g + 1) begin : nmat
                assign nm_nmat[p*162 + g*18 +: 18] = r_nm[(30+g)*32 +: 18];
            end
            wire [IW-1:0] dp_img = r_dp[29*32 +: IW];
            assign dp_node_base[p*32 +: 32] = img_node_base[dp_img * 32 +: 32];
            assign dp_attr_base[p*32 +: 32] = img_attr_base[dp_img * 32 +: 32];
        end
    endgenerate
endmodule
`default_nettype wire
