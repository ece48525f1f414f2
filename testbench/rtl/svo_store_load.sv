// svo_store_load: the node store's load DMA of svo_top (CTRL.LOAD), on its AXI4 read master
// m_axi_load_* (64-bit data).
//
// Pipeline position: outside the frame. Between frames the host loads the images' node words
// into svo_onchip_store (svo_top's node memory, svo_top_memory.sv) from memory; svo_top refuses
// a START while it runs and until a load has completed (STATUS.ERROR 7, 8; testbench/README.md,
// "The host register block"). The model assumes the store loaded (its load has no timing).
//
// CTRL.LOAD (`cmd`, taken when `idle`: svo_top in IDLE with no START): `words` words from byte
// address `src` into store words 0 .. words - 1: INCR bursts of up to LOAD_BURST 8-byte beats,
// cut at 4 KiB pages, at most two bursts' beats asked ahead. A beat carries two words (low
// first) and the store takes one a cycle (its load port is a bank's write port), so R is taken
// every other cycle: 4 bytes a cycle, the store's write rate. Refused (`error`, one cycle): 7
// `src` off 8 bytes or beyond the 32-bit word range, `words` 0 or over STORE_WORDS, or no store
// (HAS_STORE 0); 8 a LOAD while a frame (not `idle`) or a load runs. A beat answering an error
// ends the load with 9 and the store without a load (`store_ok` 0 until the next complete
// load). `cycles` counts the load's cycles (LOAD_CYCLES); svo_top's CYCLES only the frame's.
// store_base (src / 4: the word index of store word 0) and store_words (the load's words) are
// what svo_top's node reads are checked and addressed against.
`timescale 1ns/1ps
`default_nettype none
module svo_store_load #(
    parameter int ADDR_W = 40,           // AXI byte addresses
    parameter int STORE_WORDS = 262144,  // the store's 32-bit words
    parameter int LOAD_BURST = 32,       // beats (8 bytes) per burst (1 .. 256)
    parameter bit HAS_STORE = 1'b1       // 0: every LOAD refused (7)
) (
    input  wire              clk,
    input  wire              rst,
    input  wire              cmd,        // CTRL.LOAD
    input  wire              idle,       // svo_top in IDLE and no START this cycle
    input  wire [63:0]       src_r,      // LOAD_SRC
    input  wire [31:0]       words_r,    // LOAD_WORDS
    output logic             m_axi_load_arvalid,
    input  wire              m_axi_load_arready,
    output logic [ADDR_W-1:0] m_axi_load_araddr,
    output logic [0:0]       m_axi_load_arid,
    output logic [7:0]       m_axi_load_arlen,
    output logic [2:0]       m_axi_load_arsize,
    output logic [1:0]       m_axi_load_arburst,
    output logic [2:0]       m_axi_load_arprot,
    output logic [3:0]       m_axi_load_arcache,
    input  wire              m_axi_load_rvalid,
    output logic             m_axi_load_rready,
    input  wire [63:0]       m_axi_load_rdata,
    input  wire [1:0]        m_axi_load_rresp,
    output logic             ld_busy,    // STATUS.LOADING
    output logic [3:0]       ld_error,   // a refused LOAD or a failed load (one cycle)
    output logic [63:0]      ld_cycles,  // LOAD_CYCLES
    output logic             store_ok,   // the store holds a complete load
    output logic [31:0]      store_base, // the word index of store word 0 (LOAD_SRC / 4)
    output logic [31:0]      store_words,// words of the last complete load
    output wire              wr_valid,   // the store's load port: one word a cycle
    output wire [31:0]       wr_addr,
    output wire [31:0]       wr_data
);
    wire ld_refused = !HAS_STORE || src_r[2:0] != 3'd0 || |src_r[63:34]
        || (ADDR_W < 64 && |(src_r >> ADDR_W))
        || words_r == 32'd0 || words_r > 32'(STORE_WORDS);
    logic [ADDR_W-1:0] ld_src;                // the load's source (byte address of word 0)
    logic [31:0] ld_words, ld_beats;          // its words and beats (⌈words / 2⌉)
    logic [31:0] ld_asked, ld_got;            // beats asked (AR) and received (R)
    logic [31:0] ld_wr;                       // the next store word written
    logic ld_hold;                            // the beat's high word is written this cycle
    logic [31:0] ld_hi;
    logic ld_bad;                             // a beat of this load answered an error
    wire ld_beat = m_axi_load_rvalid && m_axi_load_rready;
    wire ld_write = ld_beat || ld_hold;
    wire ld_last = ld_write && ld_wr + 32'd1 == ld_words;
    wire [ADDR_W-1:0] ld_addr = ld_src + ADDR_W'({ld_asked, 3'b000});
    wire [31:0] ld_left = ld_beats - ld_asked;
    /* verilator lint_off UNUSEDSIGNAL */
    wire [12:0] ld_room = 13'h1000 - 13'(ld_addr[11:0]);          // bytes to the 4 KiB page
    /* verilator lint_on UNUSEDSIGNAL */
    wire [9:0] ld_page = ld_room[12:3];                             // beats (the source is 8-aligned)
    wire [31:0] ld_len0 = ld_left < 32'(LOAD_BURST) ? ld_left : 32'(LOAD_BURST);
    wire [31:0] ld_len = ld_len0 < 32'(ld_page) ? ld_len0 : 32'(ld_page);
    wire ld_ask = ld_busy && !m_axi_load_arvalid && ld_left != 32'd0
        && ld_asked - ld_got <= 32'(LOAD_BURST);
    assign m_axi_load_arid = '0;
    assign m_axi_load_arsize = 3'd3;          // 8 bytes
    assign m_axi_load_arburst = 2'b01;        // INCR
    assign m_axi_load_arprot = 3'b000;
    assign m_axi_load_arcache = 4'b0011;
    assign m_axi_load_rready = ld_busy && !ld_hold;
    always_ff @(posedge clk) begin
        if (rst) begin
            ld_busy <= 1'b0;
            ld_hold <= 1'b0;
            ld_error <= 4'd0;
            store_ok <= 1'b0;
            m_axi_load_arvalid <= 1'b0;
            ld_cycles <= '0;
        end else begin
            ld_error <= 4'd0;
            if (cmd && !ld_busy && idle) begin
                if (ld_refused) ld_error <= 4'd7;
                else begin
                    ld_busy <= 1'b1;
                    ld_src <= ADDR_W'(src_r);
                    ld_words <= words_r;
                    ld_beats <= (words_r + 32'd1) >> 1;
                    ld_asked <= '0;
                    ld_got <= '0;
                    ld_wr <= '0;
                    ld_bad <= 1'b0;
                    ld_cycles <= '0;
                    store_base <= 32'(src_r >> 2);
                    store_words <= words_r;
                end
                store_ok <= 1'b0;
            end else if (cmd) ld_error <= 4'd8;
            if (ld_busy) ld_cycles <= ld_cycles + 1'b1;
            if (m_axi_load_arvalid && m_axi_load_arready) m_axi_load_arvalid <= 1'b0;
            else if (ld_ask) begin
                m_axi_load_arvalid <= 1'b1;
                m_axi_load_araddr <= ld_addr;
                m_axi_load_arlen <= 8'(ld_len - 32'd1);
                ld_asked <= ld_asked + ld_len;
            end
            if (ld_beat) begin
                ld_got <= ld_got + 32'd1;
                ld_hi <= m_axi_load_rdata[63:32];
                if (m_axi_load_rresp[1]) ld_bad <= 1'b1;
            end
            ld_hold <= ld_beat && !ld_last;
            if (ld_write) ld_wr <= ld_wr + 32'd1;
            if (ld_last) begin
                ld_busy <= 1'b0;
                store_ok <= !(ld_bad || (ld_beat && m_axi_load_rresp[1]));
                if (ld_bad || (ld_beat && m_axi_load_rresp[1])) ld_error <= 4'd9;
            end
        end
    end
    /* verilator lint_off UNUSEDSIGNAL */
    wire unused = &{1'b0, m_axi_load_rresp[0]};  // OKAY / EXOKAY alike
    /* verilator lint_on UNUSEDSIGNAL */
    assign wr_valid = ld_write;
    assign wr_addr = ld_wr;
    assign wr_data = ld_hold ? ld_hi : m_axi_load_rdata[31:0];
endmodule
`default_nettype wire
