// svo_hit_check: the hit-buffer check of one ray: unpacks the pixel's previous word and
// applies the reuse rule (rtl_model/src/units/hit_record.rs `unpack`,
// hit_record/reuse.rs `reuse`; docs/units/hit-record.md).
//
// Pipeline position: the check stage, after the sorter, on the word the hit buffer's read
// port returned. Word layout as svo_hit_pack.v: kind 2 | instance INST_W | t T_W | normal u,
// v N_W each | colour b, g, r 8 each. Outputs: the unpacked fields (kind 3 reads as 2; the
// all-ones instance is a miss: hit 0, instance 0), the decision `reuse` — the buffer is in use,
// the camera is still, the ray has exactly one candidate whose instance is still, and the
// word hit that instance or nothing — and the word written back when reused: the previous
// word with its kind refreshed to one sphere (this frame's count), else 0. Re-packing the
// unpacked fields is the identity on every other field, so no saturation is needed here.
//
// Latency 1 (units.hit_unpack, rtl_model cycle::hw_config): the none-code compare and the
// rule before one output register. II = 1.
`timescale 1ns/1ps
`default_nettype none
module svo_hit_check #(
    parameter INST_W = 8,
    parameter T_W    = 22,
    parameter N_W    = 8,
    parameter WB     = 2 + INST_W + T_W + 2 * N_W + 24
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              in_valid,
    input  wire [WB-1:0]     in_prev,
    input  wire              in_buffer,
    input  wire              in_camera_dirty,
    input  wire [15:0]       in_candidates,
    input  wire [15:0]       in_candidate,
    input  wire              in_instance_dirty,
    output reg               out_valid,
    output reg  [1:0]        out_kind,
    output reg               out_hit,
    output reg  [INST_W-1:0] out_instance,
    output reg  [T_W-1:0]    out_t,
    output reg  [N_W-1:0]    out_normal_u,
    output reg  [N_W-1:0]    out_normal_v,
    output reg  [7:0]        out_colour_r,
    output reg  [7:0]        out_colour_g,
    output reg  [7:0]        out_colour_b,
    output reg               out_reuse,
    output reg  [WB-1:0]     out_reused_word
);
    // The one output register of the always block below; the testbench prints it (tb_*.sv: "rtl LATENCY"), tests/testbench_icarus.rs
    // compares it with the model's units.* latency and with the latency measured.
    /* verilator lint_off UNUSEDPARAM */
    localparam LATENCY = 1;
    /* verilator lint_on UNUSEDPARAM */
    localparam I0 = 2;                   // field offsets
    localparam T0 = I0 + INST_W;
    localparam U0 = T0 + T_W;
    localparam V0 = U0 + N_W;
    localparam C0 = V0 + N_W;

    wire [1:0]        kind = in_prev[1:0];
    wire [INST_W-1:0] inst = in_prev[I0 +: INST_W];
    wire              miss = &inst;
    wire same = {{(16 - INST_W){1'b0}}, inst} == in_candidate;
    wire reuse = in_buffer && !in_camera_dirty && (in_candidates == 16'd1) &&
                 !in_instance_dirty && (miss || same);

    always @(posedge clk) begin
        out_valid       <= rst ? 1'b0 : in_valid;
        out_kind        <= (kind == 2'd3) ? 2'd2 : kind;
        out_hit         <= !miss;
        out_instance    <= miss ? {INST_W{1'b0}} : inst;
        out_t           <= in_prev[T0 +: T_W];
        out_normal_u    <= in_prev[U0 +: N_W];
        out_normal_v    <= in_prev[V0 +: N_W];
        out_colour_b    <= in_prev[C0 +: 8];
        out_colour_g    <= in_prev[C0 + 8 +: 8];
        out_colour_r    <= in_prev[C0 + 16 +: 8];
        out_reuse       <= reuse;
        out_reused_word <= reuse ? {in_prev[WB-1:2], 2'b01} : {WB{1'b0}};
    end
endmodule
`default_nettype wire
