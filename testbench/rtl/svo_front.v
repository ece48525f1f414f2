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
// - sphere: LANES svo_sphere lanes test the ray against the instance registers (`inst_*`,
//   lane l = instance l; lanes not in `lane_used` never hit). The hits leave compacted in
//   lane order as sorter keys {lane 8, t_enter uQ10.22 32}, with their count.
// - sorter: svo_sorter (network SO_N lanes, SO_D layers) sorts them by (t, id). The pipe's
//   capacity is SO_D, the network's latency: a ray of at most SO_N keys never waits for the
//   merge passes (LANES <= SO_N is required), so `err_pipe` (sticky) never rises unless that
//   is broken.
// `err_overflow` (sticky) is set when raygen or a used sphere lane raises an overflow flag
// (the datapath's saturation, counted by the model; reported, never silent).
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
    parameter DIR_FIXED = 0                       // dir_f64 holds sQ2.30 codes
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
    // instance registers, lane l in bits l·W +: W
    input  wire [LANES*120-1:0]     inst_c,
    input  wire [LANES*64-1:0]      inst_threshold,
    input  wire [LANES*64-1:0]      inst_inside,
    input  wire [LANES*34-1:0]      inst_delta_t,
    input  wire [LANES*40-1:0]      inst_reach,
    input  wire [LANES*80-1:0]      inst_reach2,
    input  wire [LANES-1:0]         lane_used,
    // rays to the check stage (sorter_to_check's head)
    output wire                     out_valid,
    input  wire                     out_ready,
    output wire [PIXW-1:0]          out_pixel,
    output wire [3*32-1:0]          out_dir,
    output wire [SO_CW-1:0]         out_count,
    output wire [LANES*40-1:0]      out_keys,     // sorted, the first out_count valid
    output reg                      err_pipe,      // a pipe rule broken (sticky)
    output reg                      err_overflow  // raygen or sphere overflow flags (sticky)
);
    localparam TAG = PIXW + 96;                   // pixel, direction
    localparam KEYS = LANES * 40;
    localparam KC = $clog2(LANES + 1);

    generate
        if (LANES > SO_N || LANES < 1 || SO_MAX_KEYS < SO_N) begin : bad_lanes
            svo_front_LANES_must_be_1_to_SO_N bad();
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
    wire sp_in_ready;
    wire sp_accept = f1_valid && sp_in_ready;
    assign f1_ready = sp_in_ready;
    // Every lane's valid is the same bit (they take the same rays): lane 0's is used.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [LANES-1:0] sp_u_valid;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [LANES-1:0] sp_u_hit, sp_ov_r, sp_ov_t;
    wire [LANES*32-1:0] sp_u_t;
    genvar gl;
    generate
        for (gl = 0; gl < LANES; gl = gl + 1) begin : lane
            svo_sphere u_sphere (.clk(clk), .rst(rst), .in_valid(sp_accept), .in_o(cam_o),
                .in_d(f1_data[95:0]), .in_c(inst_c[gl*120 +: 120]),
                .in_threshold(inst_threshold[gl*64 +: 64]),
                .in_inside(inst_inside[gl*64 +: 64]), .in_delta_t(inst_delta_t[gl*34 +: 34]),
                .in_reach(inst_reach[gl*40 +: 40]), .in_reach2(inst_reach2[gl*80 +: 80]),
                .out_valid(sp_u_valid[gl]), .out_hit(sp_u_hit[gl]),
                .out_t_enter(sp_u_t[gl*32 +: 32]), .out_ov_reach(sp_ov_r[gl]),
                .out_ov_t_enter(sp_ov_t[gl]));
        end
    endgenerate
    // The ray's side band while its spheres are tested.
    wire [TAG-1:0] sp_tag;
    wire sp_tag_valid;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(SP_L + 1), .W(TAG)) sp_tags (.clk(clk), .rst(rst), .in_valid(sp_accept),
        .in_ready(), .in_data(f1_data), .out_valid(sp_tag_valid), .out_ready(sp_u_valid[0]),
        .out_data(sp_tag), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */
    // Compaction: the hits in lane order as keys {lane, t}, and their count.
    reg [KEYS-1:0] sp_keys;
    reg [KC-1:0]   sp_n;
    integer l;
    always @* begin
        sp_keys = {KEYS{1'b0}};
        sp_n = {KC{1'b0}};
        for (l = 0; l < LANES; l = l + 1)
            if (sp_u_hit[l] && lane_used[l]) begin
                sp_keys[sp_n * 40 +: 40] = {l[7:0], sp_u_t[l*32 +: 32]};
                sp_n = sp_n + 1'b1;
            end
    end
    wire sp_valid, sp_ready;
    wire [TAG+KC+KEYS-1:0] sp_data;
    svo_elastic #(.L(SP_L), .W(TAG + KC + KEYS)) sp_pipe (.clk(clk), .rst(rst),
        .in_valid(f1_valid), .in_ready(sp_in_ready), .unit_valid(sp_u_valid[0]),
        .unit_data({sp_tag, sp_n, sp_keys}), .out_valid(sp_valid), .out_ready(sp_ready),
        .out_data(sp_data));

    wire f2_valid, f2_ready;
    wire [TAG+KC+KEYS-1:0] f2_data;
    /* verilator lint_off PINCONNECTEMPTY */
    svo_fifo #(.DEPTH(D_SP_SO), .W(TAG + KC + KEYS)) sphere_to_sorter (.clk(clk), .rst(rst),
        .in_valid(sp_valid), .in_ready(sp_ready), .in_data(sp_data), .out_valid(f2_valid),
        .out_ready(f2_ready), .out_data(f2_data), .occupancy());
    /* verilator lint_on PINCONNECTEMPTY */

    // ---------------------------------------------------------------- sorter
    wire so_in_ready, so_pipe_ready, so_u_valid;
    wire so_accept = f2_valid && so_pipe_ready;
    assign f2_ready = so_pipe_ready;
    wire [SO_CW-1:0] so_u_count;
    // Keys beyond LANES are the zero padding of the input: a ray has at most LANES keys.
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
        .in_valid(f2_valid), .in_ready(so_pipe_ready), .unit_valid(so_u_valid),
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
            if (so_accept && !so_in_ready) err_pipe <= 1'b1;
            if ((rg_u_valid && (rg_ov_d || rg_ov_o))
                || (sp_u_valid[0] && |((sp_ov_r | sp_ov_t) & lane_used)))
                err_overflow <= 1'b1;
            // A result with no side band waiting would be a broken pipe: never expected.
            if ((sp_u_valid[0] && !sp_tag_valid) || (so_u_valid && !so_tag_valid))
                err_pipe <= 1'b1;
        end
    end
endmodule
`default_nettype wire
