// svo_front: the front end of the pipeline, pixel counter to sorter_to_check: ray generation,
// the sphere lanes and the candidate sorter, joined by the cycle model's FIFOs, with
// back-pressure from the check stage.
//
// Pipeline position: the first stages of docs/cycle-model.md §2.1 (raygen → raygen_to_sphere
// → sphere → sphere_to_sorter → sorter → sorter_to_check); its output feeds svo_hit_buffer's
// check. Cycle-exact with the model's stages (src/models/cycle/stages/raygen.rs, sphere.rs,
// sorter.rs): each unit sits in an svo_elastic pipe whose capacity is its latency, each joint
// is an svo_fifo of the model's depth (registered occupancy, no fall-through), and a stage hands
// its head result on before it takes the next input (the model evaluates consumers first).
//
// - raygen: while `run` is high, pixel `next` (0, 1, ... `npix` − 1) enters svo_raygen with the
//   host's direction for it (`dir_pixel` → `dir_f64`, read in the same cycle: the direction
//   table) and the camera position; the quantised direction travels with the ray. `dir_valid`
//   low holds ray generation (a table streamed from memory that has not arrived); `dir_take`
//   is high in the cycle the direction is taken. DIR_FIXED = 1: `dir_f64` carries sQ2.30 codes
//   {z, y, x} in its low 96 bits (svo_raygen's DIR_FIXED).
// - sphere: LANES svo_sphere lanes test the ray against the frame's `n_inst` instances in
//   P = ⌈n_inst / LANES⌉ passes, one a cycle (the model's flat passes, sphere.rs): in pass p
//   lane l tests instance LANES·p + l, whose registers the instance table gives on `inst_*`
//   in the same cycle (`inst_base` = LANES·p: an asynchronous read port per lane); an
//   instance ≥ n_inst never hits. The input stays closed for the ray's P cycles and the ray
//   leaves when its last pass does (accept + SP_L + P − 1). The hits leave compacted in
//   instance order as sorter keys {instance 8, t_enter uQ10.22 32}, at most KEYN of them,
//   with their count.
// - sorter: svo_sorter (network SO_N lanes, SO_D layers) sorts them by (t, id); a ray of more
//   than SO_N keys takes its merge passes, with the sorter's own `in_ready` closing the input
//   as the model's `units::sorter::pipe_cost` does. The pipe's capacity is SO_D.
// `err_overflow` (sticky) is set when raygen or a used sphere lane raises an overflow flag
//   (the datapath's saturation, counted by the model), or a ray has more than KEYN candidates
//   (the rest are dropped): reported, never silent.
// A side band (pixel and direction) rides beside each unit in a tag FIFO: pushed when a ray
// enters the unit, popped when its result comes out (in order). It holds L + 1: in the cycle
// a ray leaves a full unit of latency L the next enters, and the FIFO's registered not-full
// does not count the leaving one.
// Unit latencies are parameters (RG_L, SP_L, SO_D) and must equal the units' own LATENCY
// (the testbench checks them against the hardware package).
`timescale 1ns/1ps
`default_nettype none
module svo_front #(
    parameter LANES    = 8,
    parameter PIXW     = 32,
    parameter RG_L     = 4,                       // svo_raygen's LATENCY
    parameter SP_L     = 48,                      // svo_sphere's LATENCY (with the root)
    parameter SO_N     = 8,                       // the sorter's network (the datapath's)
    parameter SO_D     = 6,
    parameter SO_S     = SO_N / 2,
    // The network's pairs (sorter_pkg NET_PAIRS); all zero: svo_sorter's own default (8 lanes).
    parameter [SO_D*SO_S*16-1:0] SO_PAIRS = {(SO_D*SO_S*16){1'b0}},
    parameter SO_MAX_KEYS = 2 * SO_N,             // the sorter's key bus (a multiple of SO_N)
    parameter SO_CW    = $clog2(SO_MAX_KEYS + 1),
    parameter D_RG_SP  = 4,                       // fifos.raygen_to_sphere
    parameter D_SP_SO  = 4,                       // fifos.sphere_to_sorter
    parameter D_SO_CK  = 8,                       // fifos.sorter_to_check
    parameter DIR_FIXED = 0,                      // dir_f64 holds sQ2.30 codes
    parameter NINST    = LANES,                   // the instance table's entries (≤ 255)
    parameter KEYN     = LANES                    // keys a ray carries (≤ SO_MAX_KEYS, ≤ 63)
) (
    input  wire                     clk,
    input  wire                     rst,
    input  wire                     run,
    input  wire [PIXW-1:0]          npix,
    // the direction table: the host's direction of pixel dir_pixel, this cycle
    output wire [PIXW-1:0]          dir_pixel,
    input  wire [3*64-1:0]          dir_f64,      // {z, y, x}, binary64
    input  wire                     dir_valid,    // dir_f64 is there (else raygen waits)
    output wire                     dir_take,     // the direction is taken this cycle
    input  wire [3*64-1:0]          origin_f64,   // the camera, binary64
    input  wire [3*40-1:0]          cam_o,        // the camera register, sQ8.32
    // the instance table's lane read ports: lane l's instance, inst_base + l, this cycle
    output wire [7:0]               inst_base,
    input  wire [7:0]               n_inst,       // instances this frame (constant in a frame)
    input  wire [LANES*120-1:0]     inst_c,
    input  wire [LANES*64-1:0]      inst_threshold,
    input  wire [LANES*64-1:0]      inst_inside,
    input  wire [LANES*34-1:0]      inst_delta_t,
    input  wire [LANES*40-1:0]      inst_reach,
    input  wire [LANES*80-1:0]      inst_reach2,
    // rays to the check stage (sorter_to_check's head)
    output wire                     out_valid,
    input  wire                     out_ready,
    output wire [PIXW-1:0]          out_pixel,
    output wire [3*32-1:0]          out_dir,
    output wire [SO_CW-1:0]         out_count,
    output wire [KEYN*40-1:0]       out_keys,     // sorted, the first out_count valid
    output reg                      err_pipe,      // a pipe rule broken (sticky)
    output reg                      err_overflow  // raygen or sphere overflow flags (sticky)
);
    localparam TAG = PIXW + 96;                   // pixel, direction
    localparam KEYS = KEYN * 40;
    localparam KC = $clog2(KEYN + 1);

    generate
        if (LANES > SO_N || LANES < 1 || SO_MAX_KEYS < SO_N || KEYN < LANES
            || KEYN > SO_MAX_KEYS || KEYN > 63 || NINST < LANES || NINST > 255) begin : bad_lanes
            svo_front_LANES_1_to_SO_N_KEYN_LANES_to_SO_MAX_KEYS_NINST_to_255 bad();
        end
    endgenerate

    // ---------------------------------------------------------------- raygen
    reg  [PIXW-1:0] next;
    assign dir_pixel = next;
    wire rg_in_ready, rg_u_valid, rg_ov_d, rg_ov_o;
    wire rg_in = run && next < npix && dir_valid;
    wire rg_accept = rg_in && rg_in_ready;
    assign dir_take = rg_accept;
    wire [31:0] rg_u_pixel;
    wire [95:0] rg_u_dir;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_raygen #(.DIR_FIXED(DIR_FIXED)) u_raygen (.clk(clk), .rst(rst), .in_valid(rg_accept), .in_pixel(next[31:0]),
        .in_dir(dir_f64), .in_origin(origin_f64), .out_valid(rg_u_valid),
        .out_pixel(rg_u_pixel), .out_dir(rg_u_dir), .out_origin(), .out_ov_dir(rg_ov_d),
        .out_ov_origin(rg_ov_o));
    /* verilator lint_on PINCONNECTEMPTY */
    wire rg_valid, rg_ready;
    wire [TAG-1:0] rg_data;
    svo_elastic #(.L(RG_L), .W(TAG)) rg_pipe (.clk(clk), .rst(rst), .in_valid(rg_in),
        .in_ready(rg_in_ready), .unit_valid(rg_u_valid),
        .unit_data({rg_u_pixel[PIXW-1:0], rg_u_dir}), .out_valid(rg_valid),
        .out_ready(rg_ready), .out_data(rg_data));
    always @(posedge clk)
        if (rst) next <= {PIXW{1'b0}};
        else if (rg_accept) next <= next + 1'b1;

    wire f1_valid, f1_ready;
    wire [TAG-1:0] f1_data;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_RG_SP), .W(TAG)) raygen_to_sphere (.clk(clk), .rst(rst),
        .in_valid(rg_valid), .in_ready(rg_ready), .in_data(rg_data), .out_valid(f1_valid),
        .out_ready(f1_ready), .out_data(f1_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- sphere lanes
    // Passes: P = ⌈n_inst / LANES⌉ (at least 1), a frame constant; `pc` is the pass a held
    // ray is in (0: none held, the input is open), `sp_hold` that ray's direction.
    localparam PCW = 8;
    localparam integer LANES_I = LANES;
    localparam integer LANES_M1 = LANES - 1;
    localparam integer KEYN_I = KEYN;
    localparam [8:0] L9 = LANES_I[8:0];
    localparam [8:0] LM9 = LANES_M1[8:0];
    localparam [7:0] L8 = LANES_I[7:0];
    localparam [KC-1:0] KEYN_C = KEYN_I[KC-1:0];
    wire [8:0] n_up = {1'b0, n_inst} + LM9;
    wire [8:0] n_pass = n_up / L9;
    wire [PCW-1:0] sp_p_now = n_pass == 9'd0 ? 8'd1 : n_pass[PCW-1:0];
    reg  [PCW-1:0] pc;
    reg  [95:0]    sp_hold;                                  // the held ray's direction
    wire sp_in_ready, sp_pipe_ready;
    assign sp_in_ready = sp_pipe_ready && pc == {PCW{1'b0}};
    wire sp_accept = f1_valid && sp_in_ready;
    assign f1_ready = sp_in_ready;
    wire sp_go = sp_accept || pc != {PCW{1'b0}};             // a pass enters the lanes
    wire [95:0] sp_dir = pc != {PCW{1'b0}} ? sp_hold : f1_data[95:0];
    assign inst_base = pc * L8;
    always @(posedge clk)
        if (rst) pc <= {PCW{1'b0}};
        else if (sp_accept && sp_p_now != 8'd1) pc <= 8'd1;
        else if (pc != {PCW{1'b0}}) pc <= (pc == sp_p_now - 8'd1) ? {PCW{1'b0}} : pc + 1'b1;
    always @(posedge clk)
        if (sp_accept) sp_hold <= f1_data[95:0];
    // Every lane's valid is the same bit (they take the same passes): lane 0's is used.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [LANES-1:0] sp_u_valid;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [LANES-1:0] sp_u_hit, sp_ov_r, sp_ov_t;
    wire [LANES*32-1:0] sp_u_t;
    genvar gl;
    generate
        for (gl = 0; gl < LANES; gl = gl + 1) begin : lane
            svo_sphere u_sphere (.clk(clk), .rst(rst), .in_valid(sp_go), .in_o(cam_o),
                .in_d(sp_dir), .in_c(inst_c[gl*120 +: 120]),
                .in_threshold(inst_threshold[gl*64 +: 64]),
                .in_inside(inst_inside[gl*64 +: 64]), .in_delta_t(inst_delta_t[gl*34 +: 34]),
                .in_reach(inst_reach[gl*40 +: 40]), .in_reach2(inst_reach2[gl*80 +: 80]),
                .out_valid(sp_u_valid[gl]), .out_hit(sp_u_hit[gl]),
                .out_t_enter(sp_u_t[gl*32 +: 32]), .out_ov_reach(sp_ov_r[gl]),
                .out_ov_t_enter(sp_ov_t[gl]));
        end
    endgenerate
    // The ray's side band and pass count while its spheres are tested. `oc` counts the
    // passes of the ray leaving the lanes; they leave on consecutive cycles, as they entered.
    wire [PCW+TAG-1:0] sp_tag;
    wire sp_tag_valid;
    reg  [PCW-1:0] oc;
    wire [PCW-1:0] sp_tag_p = sp_tag[TAG +: PCW];
    wire sp_last = sp_u_valid[0] && oc == sp_tag_p - 8'd1;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(SP_L + 1), .W(PCW + TAG)) sp_tags (.clk(clk), .rst(rst),
        .in_valid(sp_accept), .in_ready(), .in_data({sp_p_now, f1_data}),
        .out_valid(sp_tag_valid), .out_ready(sp_last), .out_data(sp_tag), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    // Instance of lane l in the pass leaving: LANES·oc + l; an instance ≥ n_inst never hits.
    wire [LANES-1:0] sp_used;
    generate
        for (gl = 0; gl < LANES; gl = gl + 1) begin : used
            localparam integer GL_I = gl;
            localparam [7:0] GL8 = GL_I[7:0];
            wire [15:0] id = {8'd0, oc} * {8'd0, L8} + {8'd0, GL8};
            assign sp_used[gl] = id < {8'd0, n_inst};
        end
    endgenerate
    // Compaction: this pass's hits appended in lane order to the ray's keys so far, as
    // {instance, t}; more than KEYN are dropped (err_overflow). Built as a decoder per key
    // slot, not as a running index (a multiplexer per key bit over every lane that could land
    // there, and a DSP48E2 per `index * 40`; issue 29): a hit lane's rank is the keys before
    // it, the ray's so far plus the earlier lanes' hits of this pass (a prefix count), and key
    // slot s takes the hit lane of rank s (at most one: the ranks of hits differ), else keeps
    // its key. A rank ≥ KEYN lands nowhere: dropped.
    localparam RW = $clog2(KEYN + LANES + 1);     // a rank: up to KEYN + LANES
    reg  [KEYS-1:0]     acc_keys;                 // the ray's keys after its previous pass
    reg  [KC-1:0]       acc_n;
    wire [LANES-1:0]    sp_take = sp_u_hit & sp_used;
    wire [KEYS-1:0]     sp_base = oc == {PCW{1'b0}} ? {KEYS{1'b0}} : acc_keys;
    wire [KC-1:0]       sp_base_n = oc == {PCW{1'b0}} ? {KC{1'b0}} : acc_n;
    wire [7:0]          sp_id0 = oc * L8;         // lane 0's instance this pass
    // sp_rank: lane l's rank (the prefix count, unrolled: RW-bit adds of one bit per lane);
    // sp_total: the ray's keys after this pass, uncapped.
    reg  [LANES*RW-1:0] sp_rank;
    reg  [RW-1:0]       sp_total;
    integer l;
    always @* begin
        sp_total = {{(RW-KC){1'b0}}, sp_base_n};
        for (l = 0; l < LANES; l = l + 1) begin
            sp_rank[l*RW +: RW] = sp_total;
            sp_total = sp_total + {{(RW-1){1'b0}}, sp_take[l]};
        end
    end
    wire [LANES*40-1:0] sp_key;                   // lane l's key
    generate
        for (gl = 0; gl < LANES; gl = gl + 1) begin : key
            localparam integer GL_I = gl;
            localparam [7:0] GL8 = GL_I[7:0];
            assign sp_key[gl*40 +: 40] = {sp_id0 + GL8, sp_u_t[gl*32 +: 32]};
        end
    endgenerate
    localparam integer KEYN_R = KEYN;
    localparam [RW-1:0] KEYN_W = KEYN_R[RW-1:0];
    wire          sp_drop = sp_total > KEYN_W;
    wire [KC-1:0] sp_n = sp_drop ? KEYN_C : sp_total[KC-1:0];
    wire [KEYS-1:0] sp_keys;
    genvar gs;
    generate
        for (gs = 0; gs < KEYN; gs = gs + 1) begin : slot
            localparam integer GS_I = gs;
            localparam [RW-1:0] GSW = GS_I[RW-1:0];
            // sel[l]: lane l lands in this slot; one-hot or none.
            wire [LANES-1:0] sel;
            reg  [39:0]      from_lanes;
            integer j;
            for (gl = 0; gl < LANES; gl = gl + 1) begin : dec
                assign sel[gl] = sp_take[gl] && sp_rank[gl*RW +: RW] == GSW;
            end
            always @* begin
                from_lanes = 40'd0;
                for (j = 0; j < LANES; j = j + 1)
                    from_lanes = from_lanes | (sp_key[j*40 +: 40] & {40{sel[j]}});
            end
            assign sp_keys[gs*40 +: 40] = sel == {LANES{1'b0}} ? sp_base[gs*40 +: 40]
                : from_lanes;
        end
    endgenerate
    always @(posedge clk)
        if (rst) begin
            oc <= {PCW{1'b0}};
            acc_n <= {KC{1'b0}};
        end else if (sp_u_valid[0]) begin
            oc <= sp_last ? {PCW{1'b0}} : oc + 1'b1;
            acc_keys <= sp_keys;
            acc_n <= sp_n;
        end
    wire sp_valid, sp_ready;
    wire [TAG+KC+KEYS-1:0] sp_data;
    svo_elastic #(.L(SP_L), .W(TAG + KC + KEYS)) sp_pipe (.clk(clk), .rst(rst),
        .in_valid(f1_valid && pc == {PCW{1'b0}}), .in_ready(sp_pipe_ready),
        .unit_valid(sp_last), .unit_data({sp_tag[TAG-1:0], sp_n, sp_keys}),
        .out_valid(sp_valid), .out_ready(sp_ready), .out_data(sp_data));

    wire f2_valid, f2_ready;
    wire [TAG+KC+KEYS-1:0] f2_data;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_SP_SO), .W(TAG + KC + KEYS)) sphere_to_sorter (.clk(clk), .rst(rst),
        .in_valid(sp_valid), .in_ready(sp_ready), .in_data(sp_data), .out_valid(f2_valid),
        .out_ready(f2_ready), .out_data(f2_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- sorter
    wire so_in_ready, so_pipe_ready, so_u_valid;
    // The sorter's own ready closes the input while a merged ray's passes run.
    wire so_accept = f2_valid && so_pipe_ready && so_in_ready;
    assign f2_ready = so_pipe_ready && so_in_ready;
    wire [SO_CW-1:0] so_u_count;
    // Keys beyond KEYN are the zero padding of the input: a ray has at most KEYN keys.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [SO_MAX_KEYS*40-1:0] so_u_keys;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [SO_CW-1:0] so_count_in = {{(SO_CW-KC){1'b0}}, f2_data[KEYS +: KC]};
    wire [SO_MAX_KEYS*40-1:0] so_keys_in = {{(SO_MAX_KEYS*40-KEYS){1'b0}}, f2_data[KEYS-1:0]};
    generate
        if (SO_PAIRS == {(SO_D*SO_S*16){1'b0}}) begin : sorter_default
            svo_sorter #(.N(SO_N), .D(SO_D), .S(SO_S), .MAX_KEYS(SO_MAX_KEYS), .CW(SO_CW))
                u_sorter (.clk(clk), .rst(rst), .in_valid(so_accept), .in_ready(so_in_ready),
                .in_count(so_count_in), .in_keys(so_keys_in), .out_valid(so_u_valid),
                .out_count(so_u_count), .out_keys(so_u_keys));
        end else begin : sorter_pairs
            svo_sorter #(.N(SO_N), .D(SO_D), .S(SO_S), .PAIRS(SO_PAIRS),
                         .MAX_KEYS(SO_MAX_KEYS), .CW(SO_CW))
                u_sorter (.clk(clk), .rst(rst), .in_valid(so_accept), .in_ready(so_in_ready),
                .in_count(so_count_in), .in_keys(so_keys_in), .out_valid(so_u_valid),
                .out_count(so_u_count), .out_keys(so_u_keys));
        end
    endgenerate
    wire [TAG-1:0] so_tag;
    wire so_tag_valid;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(SO_D + 1), .W(TAG)) so_tags (.clk(clk), .rst(rst), .in_valid(so_accept),
        .in_ready(), .in_data(f2_data[KC+KEYS +: TAG]), .out_valid(so_tag_valid),
        .out_ready(so_u_valid), .out_data(so_tag), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    wire so_valid, so_ready;
    wire [TAG+SO_CW+KEYS-1:0] so_data;
    svo_elastic #(.L(SO_D), .W(TAG + SO_CW + KEYS)) so_pipe (.clk(clk), .rst(rst),
        .in_valid(f2_valid && so_in_ready), .in_ready(so_pipe_ready), .unit_valid(so_u_valid),
        .unit_data({so_tag, so_u_count, so_u_keys[KEYS-1:0]}), .out_valid(so_valid),
        .out_ready(so_ready), .out_data(so_data));

    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_SO_CK), .W(TAG + SO_CW + KEYS)) sorter_to_check (.clk(clk),
        .rst(rst), .in_valid(so_valid), .in_ready(so_ready), .in_data(so_data),
        .out_valid(out_valid), .out_ready(out_ready),
        .out_data({out_pixel, out_dir, out_count, out_keys}), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- errors (sticky)
    always @(posedge clk) begin
        if (rst) begin
            err_pipe <= 1'b0;
            err_overflow <= 1'b0;
        end else begin
            if ((rg_u_valid && (rg_ov_d || rg_ov_o))
                || (sp_u_valid[0] && (|((sp_ov_r | sp_ov_t) & sp_used) || sp_drop)))
                err_overflow <= 1'b1;
            // A result with no side band waiting would be a broken pipe: never expected.
            if ((sp_u_valid[0] && !sp_tag_valid) || (so_u_valid && !so_tag_valid))
                err_pipe <= 1'b1;
        end
    end
endmodule
`default_nettype wire
