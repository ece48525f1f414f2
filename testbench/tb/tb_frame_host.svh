// tb_frame_host.svh: the parts of tb_frame.sv that are the host's and the checker's, not the
// pipeline's (included inside module tb_frame, after its declarations): the record's normal,
// which the model computes in f64 on the host path (FramePlan::finish), the early-termination
// compare of the record stage (FramePlan::stops), and the check of one pixel's results against
// frame_pixels.hex.
    // ---- the host's f64 normal path (FramePlan::finish) ----
    function automatic real sgn1(input real x);
        sgn1 = (x >= 0.0) ? 1.0 : -1.0;
    endfunction
    function automatic real absr(input real x);
        absr = (x < 0.0) ? -x : x;
    endfunction
    function automatic int round_away(input real x);   // f64::round: ties away from zero
        round_away = (x >= 0.0) ? int'($floor(x + 0.5)) : -int'($floor(-x + 0.5));
    endfunction
    function automatic real fix(input logic signed [63:0] code, input int frac);
        fix = real'(code) / (2.0 ** frac);
    endfunction
    function automatic real ax(input int k, input int c, input int j);  // axis c, component j
        ax = fix($signed(inst[k][(3 * c + j) * 32 +: 32]), 30);
    endfunction
    function automatic real hx(input int k, input int c);
        hx = fix($signed(inst[k][frame_instances_vectors_pkg::HALF_X_LSB + 40 * c +: 40]), 32);
    endfunction
    function automatic [15:0] host_normal(input int k, input [31:0] oct);
        real u, v, x, y, z, len, n0, n1, n2, w0, w1, w2, l1, a, b, nz, s;
        int cu, cv;
        u = real'($signed(oct[15:0])) / 32767.0;
        v = real'($signed(oct[31:16])) / 32767.0;
        z = 1.0 - absr(u) - absr(v);
        if (z < 0.0) begin
            x = (1.0 - absr(v)) * sgn1(u);
            y = (1.0 - absr(u)) * sgn1(v);
        end else begin
            x = u;
            y = v;
        end
        len = $sqrt(x * x + y * y + z * z);
        // n_local / scale (half extents: the scale up to a common factor), then R·n
        n0 = (x / len) / hx(k, 0); n1 = (y / len) / hx(k, 1); n2 = (z / len) / hx(k, 2);
        w0 = ax(k, 0, 0) * n0 + ax(k, 1, 0) * n1 + ax(k, 2, 0) * n2;
        w1 = ax(k, 0, 1) * n0 + ax(k, 1, 1) * n1 + ax(k, 2, 1) * n2;
        w2 = ax(k, 0, 2) * n0 + ax(k, 1, 2) * n1 + ax(k, 2, 2) * n2;
        len = $sqrt(w0 * w0 + w1 * w1 + w2 * w2);
        if (len > 0.0) begin
            w0 = w0 / len; w1 = w1 / len; w2 = w2 / len;
        end
        l1 = absr(w0) + absr(w1) + absr(w2);
        if (!(l1 > 0.0)) return 16'd0;
        a = w0 / l1; b = w1 / l1; nz = w2 / l1;
        if (nz < 0.0) begin
            u = (1.0 - absr(b)) * sgn1(a);
            v = (1.0 - absr(a)) * sgn1(b);
        end else begin
            u = a;
            v = b;
        end
        s = 127.0;
        if (u > 1.0) u = 1.0; if (u < -1.0) u = -1.0;
        if (v > 1.0) v = 1.0; if (v < -1.0) v = -1.0;
        cu = round_away(u * s);
        cv = round_away(v * s);
        host_normal = {cv[7:0], cu[7:0]};
    endfunction

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
