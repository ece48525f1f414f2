"""svo_unit_lanes between two svo_fifo_wide joints, against this file's own model of the rule.

Pipeline position: the k-wide walk section's glue (docs/cycle-model.md §2.1, "Walk issue of
width k"): transform_to_reciprocal → K units side by side → reciprocal_to_root. The top is
tb_unit_lanes.sv (K svo_delay units of latency L carrying each item's number).

The rule, written here from docs/cycle-model.md and rtl_model/src/cycle/{fifo,unit_lanes,
unit_pipe}.rs's documentation (no code shared with the RTL or the Rust model):
- a K-wide FIFO takes up to K pushes a cycle while its occupancy at the start of the cycle plus
  the pushes before is below its depth, and gives up to K pops a cycle of the items inside at
  the start of the cycle; pushes show after the edge;
- each cycle the lanes first hand their ready results to the back FIFO, oldest ready first
  (a result is ready L cycles after it entered; ties in lane order), while it takes pushes;
  then they take items from the front FIFO, each into the lowest lane that has not taken one
  this cycle and holds fewer than L items (in flight or waiting).
Each cycle the bench offers a random number of new items (0..K) and pops a random number
(0..K) from the back FIFO, both drawn from the seeded generator whatever the state, so the
model replays the same traffic. Checked: every item leaves once, in the model's cycle, and
the cycles in which the model's lanes were full or its back FIFO refused (printed, so a run
that never back-pressured shows it).

Environment: SVO_SEED (default 29, printed), SVO_ITEMS (default 2000), SVO_POP (percent
chance per pop port and cycle, default 60), SVO_CORRUPT_CYCLE=N adds one to item N's
expected cycle: exactly one failure. Prints failures (first 20), then
"unit_lanes: N passed, N failed".
"""
import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge, Timer


class Model:
    """The front FIFO, the K lanes and the back FIFO, one cycle at a time."""

    def __init__(self, k, lat, d_in, d_out):
        self.k, self.lat, self.d_in, self.d_out = k, lat, d_in, d_out
        self.front, self.back = [], []
        self.lanes = [[] for _ in range(k)]  # per lane: [(ready_cycle, item)], in order
        self.full_lane_cycles = 0
        self.back_refused = 0

    def cycle(self, now, offered, pops):
        """One cycle: `pops` pops of the back FIFO (returned), then the lanes, then
        `offered` (a list of items) into the front FIFO. Returns the popped items and the
        offered items the front FIFO took."""
        front0, back0 = len(self.front), len(self.back)
        popped = self.back[: min(pops, back0)]
        del self.back[: len(popped)]
        # Hand on: oldest ready head first, ties lowest lane, while the back FIFO takes.
        pushed = []
        while len(pushed) < self.k and back0 + len(pushed) < self.d_out:
            heads = [(ln[0][0], i) for i, ln in enumerate(self.lanes) if ln and ln[0][0] <= now]
            if not heads:
                break
            _, i = min(heads)
            pushed.append(self.lanes[i].pop(0)[1])
        if len(pushed) < self.k and back0 + len(pushed) >= self.d_out:
            if any(ln and ln[0][0] <= now for ln in self.lanes):
                self.back_refused += 1
        # Take from the front FIFO's items of the start of the cycle, one a lane.
        took, used = 0, set()
        while took < self.k and took < front0:
            free = [i for i in range(self.k) if i not in used and len(self.lanes[i]) < self.lat]
            if not free:
                self.full_lane_cycles += 1
                break
            i = free[0]
            used.add(i)
            self.lanes[i].append((now + self.lat, self.front.pop(0)))
            took += 1
        # The producer's pushes against the registered occupancy.
        accepted = []
        for it in offered:
            if len(accepted) < self.k and front0 + len(accepted) < self.d_in:
                accepted.append(it)
            else:
                break
        self.front.extend(accepted)
        self.back.extend(pushed)
        return popped, accepted


@cocotb.test()
async def unit_lanes_match_the_rule(dut):
    k, lat = int(dut.K.value), int(dut.L.value)
    d_in, d_out, w = int(dut.D_IN.value), int(dut.D_OUT.value), int(dut.W.value)
    seed = int(os.environ.get("SVO_SEED", "29"))
    n_items = int(os.environ.get("SVO_ITEMS", "2000"))
    pop_pct = int(os.environ.get("SVO_POP", "60"))
    corrupt = os.environ.get("SVO_CORRUPT_CYCLE", "")
    print(f"unit_lanes: seed {seed}, K {k}, L {lat}, depths {d_in}/{d_out}, {n_items} items, pop {pop_pct} %")
    rng = random.Random(seed)
    model = Model(k, lat, d_in, d_out)
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.rst.value = 1
    dut.push_valid.value = 0
    dut.pop_ready.value = 0
    dut.push_data.value = 0
    for _ in range(3):
        await RisingEdge(dut.clk)
    dut.rst.value = 0
    mask = (1 << w) - 1
    expect, got = {}, {}
    nxt, now, failures = 0, 0, []
    push_mismatch = 0
    while (nxt < n_items or len(expect) < n_items) and now < 50 * n_items + 1000:
        await FallingEdge(dut.clk)
        offer_n = rng.randint(0, k) if nxt < n_items else 0
        offered = list(range(nxt, min(nxt + offer_n, n_items)))
        pops = sum(rng.randrange(100) < pop_pct for _ in range(k))
        popped, accepted = model.cycle(now, offered, pops)
        for it in popped:
            expect[it] = now
        # Drive the same traffic: the offered prefix, the pop prefix; read the RTL's
        # handshakes once its logic has settled (they are decided before the rising edge).
        dut.push_valid.value = (1 << len(offered)) - 1
        data = 0
        for j, it in enumerate(offered):
            data |= (it & mask) << (j * w)
        dut.push_data.value = data
        dut.pop_ready.value = (1 << pops) - 1
        await Timer(1, unit="ns")
        pv, pr = int(dut.pop_valid.value), int(dut.push_ready.value)
        pd = int(dut.pop_data.value)
        for j in range(pops):
            if not (pv >> j) & 1:
                break
            it = (pd >> (j * w)) & mask
            if it in got:
                failures.append(f"FAIL item {it}: popped twice (cycles {got[it]} and {now})")
            got[it] = now
        n_push = 0
        while n_push < len(offered) and (pr >> n_push) & 1:
            n_push += 1
        if n_push != len(accepted) and push_mismatch < 20:
            push_mismatch += 1
            failures.append(f"FAIL cycle {now}: the front FIFO took {n_push} pushes, the model {len(accepted)}")
        nxt += len(accepted)
        now += 1
    print(f"unit_lanes: {now} cycles; model lanes full in {model.full_lane_cycles}, back FIFO refused a ready result in {model.back_refused}")
    if corrupt:
        expect[int(corrupt)] = expect.get(int(corrupt), 0) + 1
    passed = 0
    for it in range(n_items):
        e, g = expect.get(it), got.get(it)
        if e is not None and e == g:
            passed += 1
        else:
            failures.append(f"FAIL item {it}: RTL popped in cycle {g}, model {e}")
    for f in failures[:20]:
        print(f)
    print(f"unit_lanes: {passed} passed, {len(failures)} failed")
    assert not failures
