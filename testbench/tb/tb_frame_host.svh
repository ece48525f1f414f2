// tb_frame_host.svh: the parts of tb_frame.sv that are the host's and the checker's, not the
// pipeline's (included inside module tb_frame, after its declarations): the early-termination
// compare of the record stage (FramePlan::stops), and the check of one pixel's results against
// frame_pixels.hex. (The record's normal is svo_normal's, inside svo_walk.)
    // Early termination (FramePlan::stops): best walker t (sQ31.31) <= next key (uQ10.22).
    function automatic bit stops(input [TW-1:0] best_t, input [31:0] key);
        logic signed [TW+1:0] a, b;
        a = $signed({{2{best_t[TW-1]}}, best_t});
        b = $signed({{(TW+2-32-9){1'b0}}, key, 9'd0});
        stops = a <= b;
    endfunction

    // The check of one pixel's result against frame_pixels.hex.
    task automatic check_pixel(input int p, input reg [71:0] word, input int walks,
                               input bit hit, input [TW-1:0] t, input [59:0] voxel);
        reg [PB-1:0] e;
        bit ok;
        e = pix[p];
        ok = 1;
        if (word !== e[frame_pixels_vectors_pkg::WORD_LSB +: 72]) begin
            ok = 0;
            report($sformatf("pixel %0d: word %018h, expected %018h", p, word,
                             e[frame_pixels_vectors_pkg::WORD_LSB +: 72]));
        end
        if (n_cands[p] != e[frame_pixels_vectors_pkg::CANDIDATES_LSB +: 16]) begin
            ok = 0;
            report($sformatf("pixel %0d: %0d candidates, expected %0d", p, n_cands[p],
                             e[frame_pixels_vectors_pkg::CANDIDATES_LSB +: 16]));
        end
        if (walks != e[frame_pixels_vectors_pkg::WALKS_LSB +: 16]
            || hit !== e[frame_pixels_vectors_pkg::HIT_LSB]
            || (hit && (t !== e[frame_pixels_vectors_pkg::T_LSB +: TW]
                        || voxel !== {e[frame_pixels_vectors_pkg::VOXEL_Z_LSB +: 20],
                                      e[frame_pixels_vectors_pkg::VOXEL_Y_LSB +: 20],
                                      e[frame_pixels_vectors_pkg::VOXEL_X_LSB +: 20]}))) begin
            ok = 0;
            report($sformatf("pixel %0d: walks %0d hit %0d t %0h, expected walks %0d hit %0d t %0h",
                             p, walks, hit, t, e[frame_pixels_vectors_pkg::WALKS_LSB +: 16],
                             e[frame_pixels_vectors_pkg::HIT_LSB], e[frame_pixels_vectors_pkg::T_LSB +: TW]));
        end
        if (ok) n_passed++; else n_failed++;
    endtask

    // The check of a word written without a walk in a later frame (reused, or the miss word):
    // the word and the candidate count against frame_pixels.hex.
    task automatic check_word(input int p, input reg [71:0] word);
        reg [PB-1:0] e;
        bit ok;
        e = pix[p];
        ok = word === e[frame_pixels_vectors_pkg::WORD_LSB +: 72]
          && n_cands[p] == e[frame_pixels_vectors_pkg::CANDIDATES_LSB +: 16];
        if (!ok)
            report($sformatf("frame 1 pixel %0d: word %018h (%0d candidates), expected %018h (%0d)",
                             p, word, n_cands[p], e[frame_pixels_vectors_pkg::WORD_LSB +: 72],
                             e[frame_pixels_vectors_pkg::CANDIDATES_LSB +: 16]));
        if (ok) n_passed++; else n_failed++;
    endtask
