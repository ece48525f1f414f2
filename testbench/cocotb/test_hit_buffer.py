"""svo_hit_buffer across frames, against the Rust model's hit-record vectors.

Pipeline position: the check stage and the write port (testbench/rtl/svo_hit_buffer.v).
Each row of `hit_record.hex` (`sim vectors`, the model's own decisions: previous word,
buffer/camera/instance flags, candidate count and instance → reuse and the reused word) is a
pixel. Rows are grouped so that each group's flags can be one frame's host registers (the
buffer and camera flags equal, an instance's dirty bit the same in every row of the group).
Per group, two frames: frame A writes every row's previous word through the record port (as
the record stage of the previous frame would), frame B sends the rows' rays with the group's
dirty flags. Expected per ray, from the row alone: reused → its reused word written, marked
direct; no candidate → the frame's miss word written; else the ray leaves to walk.

Three passes, each over all groups:
- clean: walk_ready always high, no other traffic. Also checks timing: a ray leaves to walk L
  = HB_READ + 1 cycles after it was accepted, a direct word is written L + 1 cycles after
  (through the registered write FIFO). With RECORD_WRITES = 2 frame A offers two records a
  cycle (rec_* and rec2_*), and every record's push and write cycle is checked against this
  file's own model of the record FIFO (below; frame A of the stall pass too: it has no rays);
  with one record port a record is written 1 cycle after its push.
- stalls: walk_ready low in a random half of the cycles and random records (other pixels)
  competing for the write port (with RECORD_WRITES = 2 a second one on rec2_* in a random
  half of the cycles); everything must come out, once, in order.

The record FIFO's rule (record_to_write, written here from svo_hit_buffer.v's header and
docs/cycle-model.md §2.1; no code shared with the RTL or the Rust model), per cycle with the
FIFO's contents as the cycle starts: the head is written; with RECORD_WRITES = 2 the record
behind it too, when no check word is written and the two pixels differ in parity (two banks);
the first offered record is taken while the occupancy is below WR_DEPTH, the second only with
the first and while the occupancy plus one is below WR_DEPTH; taken records are written from
the next cycle on, in order.
- the stall pass counts the cycles in which back-pressure reached each side (printed), so a
  pass that never stalled shows it.

Rows whose single candidate's id is 255 or more (no instance register holds a dirty bit for
it; the RTL reads such an id as dirty) are left out, and counted in the output.
Environment: SVO_VECTORS (default the committed vectors/), SVO_SEED (default 29, printed),
SVO_CORRUPT=N flips bit 0 of row N's expected word (or pixel, for a ray to walk) in the clean
pass, SVO_CORRUPT_CYCLE=N adds one to row N's expected cycle there, SVO_CORRUPT_RECORD=N adds
one to the expected write cycle of the clean pass's first frame A's record N (its N-th push):
each exactly one failure. Prints failures (first 20), then "hit_buffer: N passed, N failed".
"""
import os
import random
import re
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge, Timer

REPO = Path(__file__).resolve().parents[2]


def read_rows(folder):
    pkg = (folder / "hit_record_pkg.sv").read_text()
    f = {m.group(1): int(m.group(2)) for m in re.finditer(r"localparam int (\w+) = (\d+);", pkg)}
    rows = []
    for line in (folder / "hit_record.hex").read_text().splitlines():
        line = line.split("//")[0].strip()
        if line:
            rows.append(int(line, 16))

    def field(r, name):
        return (r >> f[f"{name}_LSB"]) & ((1 << f[f"{name}_WIDTH"]) - 1)

    out = []
    for i, r in enumerate(rows):
        out.append(
            dict(
                row=i,
                prev=field(r, "PREV"),
                buffer=field(r, "BUFFER"),
                camera_dirty=field(r, "CAMERA_DIRTY"),
                candidates=field(r, "CANDIDATES"),
                candidate=field(r, "CANDIDATE"),
                instance_dirty=field(r, "INSTANCE_DIRTY"),
                reuse=field(r, "REUSE"),
                reused_word=field(r, "REUSED_WORD"),
            )
        )
    return out


def group_rows(rows, instances):
    """Rows into frames whose host registers can satisfy every row's flags."""
    groups = []  # (buffer, camera_dirty, {instance: dirty}, [rows])
    for r in rows:
        need = {}
        if r["candidates"] == 1:
            need[r["candidate"]] = r["instance_dirty"]
        for g in groups:
            if (g[0], g[1]) == (r["buffer"], r["camera_dirty"]) and all(
                g[2].get(k, v) == v for k, v in need.items()
            ):
                g[2].update(need)
                g[3].append(r)
                break
        else:
            groups.append((r["buffer"], r["camera_dirty"], dict(need), [r]))
    return groups


class Bench:
    def __init__(self, dut):
        self.dut = dut
        self.cycle = 0
        self.lat = int(dut.HB_READ.value) + 1
        self.passed = 0
        self.failures = []
        self.record_writes = int(dut.RECORD_WRITES.value)
        self.wr_depth = int(dut.WR_DEPTH.value)
        self.stalls = {"write port": 0, "walk": 0, "input": 0, "bank conflict": 0,
                       "second record pushed": 0, "record FIFO full": 0, "second record written": 0}

    def check(self, ok, what):
        if ok:
            self.passed += 1
        else:
            self.failures.append(what)

    async def frame(self, rays, records, flags, walk_p, extra_p, rng, timing, corrupt_row):
        """One frame: `records` (pixel, word) through the record port (two a cycle on rec_*
        and rec2_* with RECORD_WRITES = 2: always in the clean pass, in a random half of the
        cycles in the stall pass), `rays` (row dicts) through the check. Returns when
        everything came out (or a cycle limit); `self.offers` then holds the records offered
        per cycle, (cycle, count)."""
        d = self.dut
        buffer_valid, camera_dirty, idirty = flags
        d.buffer_valid.value = buffer_valid
        d.camera_dirty.value = camera_dirty
        d.instance_dirty.value = idirty
        rays = list(rays)
        records = list(records)
        n_rec, n_ray = len(records), len(rays)
        accepted = []  # (row, cycle)
        pushed = []  # (pixel, word, cycle)
        walked, written = [], []
        self.offers = []
        limit = self.cycle + 50 * (n_ray + n_rec) + 200
        while (len(walked) + len(written) < n_ray + n_rec or records or rays) and self.cycle < limit:
            await FallingEdge(d.clk)
            ready = rng.random() >= walk_p
            d.walk_ready.value = int(ready)
            rec = rec2 = None
            if records and (timing or rng.random() >= extra_p or not rays):
                rec = records[0]
                if self.record_writes == 2 and len(records) >= 2 and (timing or rng.random() < 0.5):
                    rec2 = records[1]
            d.rec_valid.value = int(rec is not None)
            if rec is not None:
                d.rec_pixel.value = rec[0]
                d.rec_word.value = rec[1]
            d.rec2_valid.value = int(rec2 is not None)
            if rec2 is not None:
                d.rec2_pixel.value = rec2[0]
                d.rec2_word.value = rec2[1]
            self.offers.append((self.cycle, (rec is not None) + (rec2 is not None)))
            ray = rays[0] if rays else None
            d.in_valid.value = int(ray is not None)
            if ray is not None:
                d.in_pixel.value = ray["pixel"]
                d.in_candidates.value = ray["candidates"]
                d.in_candidate.value = ray["candidate"] if ray["candidates"] == 1 else 0
                d.in_payload.value = ray["row"]
            await Timer(1, unit="ns")
            c = self.cycle
            if int(d.wr_valid.value):
                written.append((int(d.wr_pixel.value), int(d.wr_word.value), int(d.wr_direct.value), c))
            if int(d.wr1_valid.value):
                written.append((int(d.wr1_pixel.value), int(d.wr1_word.value), 1, c))
            if int(d.wr2_valid.value):
                written.append((int(d.wr2_pixel.value), int(d.wr2_word.value), 0, c))
                self.stalls["second record written"] += 1
            if int(d.walk_valid.value) and ready:
                walked.append((int(d.walk_pixel.value), int(d.walk_payload.value), c))
            self.stalls["write port"] += int(d.ev_write_stall.value)
            self.stalls["walk"] += int(d.ev_walk_stall.value)
            self.stalls["bank conflict"] += int(d.ev_bank_conflict.value)
            self.stalls["input"] += int(ray is not None and not int(d.in_ready.value))
            if rec is not None and int(d.rec_ready.value):
                pushed.append((rec[0], rec[1], c))
                records.pop(0)
                if rec2 is not None and int(d.rec2_ready.value):
                    pushed.append((rec2[0], rec2[1], c))
                    records.pop(0)
                    self.stalls["second record pushed"] += 1
            elif rec is not None:
                self.stalls["record FIFO full"] += 1
            if ray is not None and int(d.in_ready.value):
                accepted.append((ray, c))
                rays.pop(0)
            await RisingEdge(d.clk)
            self.cycle += 1
        return accepted, pushed, walked, written

    def record_fifo(self, records):
        """The record FIFO's rule (module doc) over `self.offers` of a frame without rays:
        per record, in offer order, the cycle it is pushed and the cycle it is written."""
        fifo, nxt, push_at, write_at = [], 0, {}, {}
        for c, n_off in self.offers:
            start = list(fifo)
            out = start[:1]
            if self.record_writes == 2 and len(start) >= 2 and (records[start[0]][0] ^ records[start[1]][0]) & 1:
                out = start[:2]
            for i in out:
                write_at[i] = c
            fifo = start[len(out):]
            take = 0
            if n_off >= 1 and len(start) < self.wr_depth:
                take = 1
                if n_off >= 2 and len(start) + 1 < self.wr_depth:
                    take = 2
            for i in range(nxt, nxt + take):
                push_at[i] = c
                fifo.append(i)
            nxt += take
        return push_at, write_at

    def expect_records(self, records, pushed, written, tag, corrupt_record=None):
        """Frame A of the clean pass with RECORD_WRITES = 2: every record's push and write
        cycle as the record FIFO's rule (`record_fifo`) gives them."""
        push_at, write_at = self.record_fifo(records)
        if corrupt_record is not None:
            write_at[corrupt_record] = write_at.get(corrupt_record, 0) + 1
        at = {p: cy for p, _, _, cy in written}
        for i, (p, _, c) in enumerate(pushed):
            self.check(records[i][0] == p and push_at.get(i) == c,
                       f"{tag}: record {i} (pixel {records[i][0]}): pushed pixel {p} in cycle {c}, the FIFO rule {push_at.get(i)}")
            self.check(at.get(p) == write_at.get(i),
                       f"{tag}: record {i} (pixel {p}): written in cycle {at.get(p)}, the FIFO rule {write_at.get(i)}")

    def expect_frame(self, accepted, pushed, walked, written, miss_word, timing, corrupt_row, tag,
                     corrupt_cycle=None, record_rule=False):
        """Compares one frame's outputs with the rows' expectations (a record's cycle only
        when `record_rule` is off: `expect_records` checks it)."""
        lat = self.lat
        by_pixel = {}
        for w in written:
            by_pixel.setdefault(w[0], []).append(w)
        walk_iter = iter(walked)
        rec_pixels = {p for p, _, _ in pushed}
        # Records: each written once, with its word, in push order (1 cycle after in clean).
        for p, word, c in pushed:
            got = by_pixel.get(p, [])
            ok = len(got) == 1 and got[0][1] == word and got[0][2] == 0
            when = ""
            if ok and timing and not record_rule:
                ok = got[0][3] == c + 1
                when = f" at cycle {c + 1}"
            self.check(ok, f"{tag}: record pixel {p}: written {got}, expected word {word:#x} once{when}")
        order_direct = []
        for ray, c in accepted:
            r = ray
            if corrupt_cycle is not None and r["row"] == corrupt_cycle:
                c += 1
            if r["reuse"]:
                want = ("write", r["reused_word"])
            elif r["candidates"] == 0:
                want = ("write", miss_word)
            else:
                want = ("walk", r["pixel"])
            if corrupt_row is not None and r["row"] == corrupt_row:
                want = (want[0], want[1] ^ 1)
            if want[0] == "write":
                got = by_pixel.get(r["pixel"], [])
                ok = len(got) == 1 and got[0][1] == want[1] and got[0][2] == 1
                msg = f"{tag}: row {r['row']} (pixel {r['pixel']}): written {[(hex(w), dd, cy) for _, w, dd, cy in got]}, expected {want[1]:#x} (direct)"
                if ok and timing:
                    ok = got[0][3] == c + lat + 1
                    msg += f" at cycle {c + lat + 1}"
                order_direct.append(got[0][3] if got else -1)
                self.check(ok, msg)
            else:
                w = next(walk_iter, None)
                ok = w is not None and w[0] == want[1] and w[1] == r["row"]
                msg = f"{tag}: row {r['row']}: walked {w}, expected pixel {want[1]} (payload {r['row']})"
                if ok and timing:
                    ok = w[2] == c + lat
                    msg += f" at cycle {c + lat}"
                self.check(ok, msg)
                self.check(r["pixel"] not in by_pixel, f"{tag}: row {r['row']}: walked but also written")
        self.check(next(walk_iter, None) is None, f"{tag}: more rays walked than sent")
        self.check(order_direct == sorted(order_direct), f"{tag}: direct words written out of order")
        extra = [w for w in written if w[0] not in rec_pixels and w[2] == 0]
        self.check(not extra, f"{tag}: unexpected record writes {extra[:3]}")


@cocotb.test()
async def reuse_across_frames_against_the_model_rows(dut):
    seed = int(os.environ.get("SVO_SEED", "29"))
    corrupt = os.environ.get("SVO_CORRUPT", "")
    corrupt_row = int(corrupt) if corrupt else None
    corrupt_cycle_env = os.environ.get("SVO_CORRUPT_CYCLE", "")
    corrupt_cycle = int(corrupt_cycle_env) if corrupt_cycle_env else None
    corrupt_record_env = os.environ.get("SVO_CORRUPT_RECORD", "")
    corrupt_record = int(corrupt_record_env) if corrupt_record_env else None
    folder = Path(os.environ.get("SVO_VECTORS", REPO / "vectors"))
    npix = int(dut.NPIX.value)
    instances = int(dut.INSTANCES.value)
    ports = int(dut.WRITE_PORTS.value)
    record_writes = int(dut.RECORD_WRITES.value)
    print(f"hit_buffer: seed {seed}, vectors {folder}, WRITE_PORTS {ports}, RECORD_WRITES {record_writes}, HB_READ {int(dut.HB_READ.value)}"
          + (f", corrupted row {corrupt_row}" if corrupt else "")
          + (f", corrupted cycle of row {corrupt_cycle}" if corrupt_cycle is not None else "")
          + (f", corrupted write cycle of record {corrupt_record}" if corrupt_record is not None else ""))
    rng = random.Random(seed)
    rows = read_rows(folder)
    usable = [r for r in rows if not (r["candidates"] == 1 and r["candidate"] >= min(instances, 255))]
    for i, r in enumerate(usable):
        r["pixel"] = i
    groups = group_rows(usable, instances)
    assert len(usable) <= npix // 2, "NPIX too small for the rows"
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    for s in ("in_valid", "rec_valid", "rec2_valid", "walk_ready", "buffer_valid", "camera_dirty"):
        getattr(dut, s).value = 0
    dut.instance_dirty.value = 0
    dut.miss_word.value = 0
    dut.rst.value = 1
    b = Bench(dut)
    for _ in range(4):
        await RisingEdge(dut.clk)
    dut.rst.value = 0
    for pass_name, walk_p, extra_p, timing in (("clean", 0.0, 1.0, True), ("stalls", 0.5, 0.3, False)):
        for gi, (buf, cam, need, grows) in enumerate(groups):
            tag = f"{pass_name} group {gi}"
            miss_word = rng.getrandbits(72)
            dut.miss_word.value = miss_word
            # Frame A: the previous frame's words.
            prev = [(r["pixel"], r["prev"]) for r in grows]
            acc, pushed, walked, written = await b.frame(
                [], prev, (0, 1, (1 << instances) - 1), walk_p, 0.0, rng, True, None)
            # Frame A has no rays, so the record FIFO's rule gives every cycle in both passes.
            rule = record_writes == 2
            b.expect_frame(acc, pushed, walked, written, miss_word, timing, None, tag + " frame A",
                           record_rule=rule)
            if rule:
                b.expect_records(prev, pushed, written, tag + " frame A",
                                 corrupt_record if (timing and gi == 0) else None)
            # Frame B: the rays, with the group's flags; in the stall pass records of other
            # pixels compete for the write port.
            idirty = (1 << instances) - 1
            for k, v in need.items():
                if not v:
                    idirty &= ~(1 << k)
            others = []
            if not timing:
                others = [(npix // 2 + rng.randrange(npix // 2), rng.getrandbits(72)) for _ in range(len(grows))]
                # one record per pixel in a frame, as the pipeline writes
                seen = set()
                others = [o for o in others if not (o[0] in seen or seen.add(o[0]))]
            acc, pushed, walked, written = await b.frame(
                grows, others, (buf, cam, idirty), walk_p, extra_p, rng, timing,
                corrupt_row if pass_name == "clean" else None)
            b.expect_frame(acc, pushed, walked, written, miss_word, timing,
                           corrupt_row if pass_name == "clean" else None, tag + " frame B",
                           corrupt_cycle if pass_name == "clean" else None)
            b.check(int(dut.err_pixel.value) == 0, f"{tag}: err_pixel set")
    for line in b.failures[:20]:
        print("FAIL " + line)
    print(f"hit_buffer: {len(usable)} of {len(rows)} rows ({len(rows) - len(usable)} with a candidate id of 255 or more left out), "
          f"{len(groups)} frames pairs per pass, {b.cycle} cycles")
    print("hit_buffer: stalled cycles: " + ", ".join(f"{k} {v}" for k, v in b.stalls.items()))
    print(f"hit_buffer: {b.passed} passed, {len(b.failures)} failed")
    assert not b.failures, f"{len(b.failures)} checks failed"
