// svo_fifo: the bounded FIFO between two pipeline stages, as the cycle model has it
// (rtl_model/src/cycle/fifo.rs): registered occupancy, no fall-through.
//
// Pipeline position: every joint of docs/cycle-model.md §2.1 (raygen_to_sphere,
// sphere_to_sorter, sorter_to_check, ...). `in_ready` is the registered not-full flag and
// `out_valid` the registered not-empty flag: a pop in a cycle does not make room for a push in
// the same cycle, and an item pushed in cycle c leaves in c + 1 at the earliest, so neither
// side's handshake depends combinationally on the other's (the long path a FIFO is there to
// cut). A depth-1 FIFO passes an item every other cycle; depth 2 sustains one a cycle.
// `occupancy` is the registered count (the model's FIFO statistics and back-pressure).
`timescale 1ns/1ps
`default_nettype none
module svo_fifo #(
    parameter DEPTH = 4,                          // 1 .. 65536, the model's MAX_DEPTH
    parameter W     = 32
) (
    input  wire                         clk,
    input  wire                         rst,
    input  wire                         in_valid,
    output wire                         in_ready,
    input  wire [W-1:0]                 in_data,
    output wire                         out_valid,
    input  wire                         out_ready,
    output wire [W-1:0]                 out_data,
    output reg  [$clog2(DEPTH + 1)-1:0] occupancy
);
    localparam NW = $clog2(DEPTH + 1);
    localparam AW = DEPTH > 1 ? $clog2(DEPTH) : 1;
    localparam integer LAST_I = DEPTH - 1;
    localparam integer DEPTH_I = DEPTH;
    localparam [AW-1:0] LAST = LAST_I[AW-1:0];
    localparam [NW-1:0] FULL = DEPTH_I[NW-1:0];

    generate
        if (DEPTH < 1 || DEPTH > 65536) begin : bad_depth
            svo_fifo_DEPTH_must_be_1_to_65536 bad();
        end
    endgenerate

    reg [W-1:0]  mem [0:DEPTH-1];
    reg [AW-1:0] rd, wr;
    assign in_ready = occupancy != FULL;
    assign out_valid = occupancy != {NW{1'b0}};
    assign out_data = mem[rd];
    wire push = in_valid && in_ready;
    wire pop = out_valid && out_ready;
    always @(posedge clk) begin
        if (push) mem[wr] <= in_data;
        if (rst) begin
            rd <= {AW{1'b0}};
            wr <= {AW{1'b0}};
            occupancy <= {NW{1'b0}};
        end else begin
            if (push) wr <= (wr == LAST) ? {AW{1'b0}} : wr + 1'b1;
            if (pop) rd <= (rd == LAST) ? {AW{1'b0}} : rd + 1'b1;
            if (push && !pop) occupancy <= occupancy + 1'b1;
            else if (pop && !push) occupancy <= occupancy - 1'b1;
        end
    end
endmodule
`default_nettype wire
