"""svo_elastic2 around a unit of latency L, against this file's own model of the rule.

Pipeline position: the record stage's packing lane (svo_normal + svo_hit_pack, latency 14 in
svo_walk_wide) handing on into record_to_write's two push ports (docs/cycle-model.md §2.1, the
record stage's `hand_on_lanes`). The top is tb_elastic2.sv (an svo_delay of L cycles as the
unit, carrying each item's number).

The rule, written here from svo_elastic2.v's header and rtl_model/src/cycle/unit_pipe.rs's
documentation (no code shared with the RTL or the Rust model), per cycle:
- the ready results, oldest first, are the waiting ones, then the unit's result of this cycle
  (an item accepted in cycle c is the unit's result in cycle c + L);
- the first ready result leaves when out_ready is high; the second leaves only with it, when
  out2_ready is high (the two push ports take a prefix);
- a ready result that does not leave waits; the pipe takes a new item while fewer than L are in
  flight or waiting, counting those that leave in this cycle.
Each cycle the bench offers the next item with probability SVO_IN percent and raises
out_ready / out2_ready with probability SVO_OUT each, all drawn from the seeded generator
whatever the state, so the model replays the same traffic. Checked: every item's accept cycle,
and its leaving cycle and port; the counts of cycles with two leaves and with the input
refused are printed (a run that never filled the pipe shows it).

Environment: SVO_SEED (default 29, printed), SVO_ITEMS (default 3000), SVO_IN (default 80),
SVO_OUT (default 45), SVO_CORRUPT_CYCLE=N adds one to item N's expected leaving cycle:
exactly one failure. Prints failures (first 20), then "elastic2: N passed, N failed".
"""
import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge, Timer


class Model:
    """The pipe of capacity L around a unit of latency L, one cycle at a time."""

    def __init__(self, lat):
        self.lat = lat
        self.waiting = []  # results that were ready and did not leave, oldest first
        self.flight = []   # (cycle the unit gives it, item)
        self.two_leaves = 0
        self.refused = 0

    def cycle(self, now, offered, ready1, ready2):
        """One cycle: returns (leaving items as (item, port), whether `offered` was taken)."""
        unit = [it for c, it in self.flight if c == now]
        self.flight = [(c, it) for c, it in self.flight if c != now]
        ready = self.waiting + unit
        leaves = []
        if ready and ready1:
            leaves.append((ready[0], 0))
            if len(ready) >= 2 and ready2:
                leaves.append((ready[1], 1))
        if len(leaves) == 2:
            self.two_leaves += 1
        inside = len(self.waiting) + len(self.flight) + len(unit)
        took = offered is not None and (inside < self.lat or bool(leaves))
        if offered is not None and not took:
            self.refused += 1
        self.waiting = ready[len(leaves):]
        if took:
            self.flight.append((now + self.lat, offered))
        return leaves, took


@cocotb.test()
async def elastic2_matches_the_rule(dut):
    lat, w = int(dut.L.value), int(dut.W.value)
    seed = int(os.environ.get("SVO_SEED", "29"))
    n_items = int(os.environ.get("SVO_ITEMS", "3000"))
    in_pct = int(os.environ.get("SVO_IN", "80"))
    out_pct = int(os.environ.get("SVO_OUT", "45"))
    corrupt = os.environ.get("SVO_CORRUPT_CYCLE", "")
    print(f"elastic2: seed {seed}, L {lat}, {n_items} items, in {in_pct} %, out {out_pct} %")
    rng = random.Random(seed)
    model = Model(lat)
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.rst.value = 1
    for s in ("in_valid", "out_ready", "out2_ready", "in_data"):
        getattr(dut, s).value = 0
    for _ in range(3):
        await RisingEdge(dut.clk)
    dut.rst.value = 0
    mask = (1 << w) - 1
    expect, got, failures = {}, {}, []
    nxt, now = 0, 0
    while len(expect) < n_items and now < 40 * n_items + 1000:
        await FallingEdge(dut.clk)
        offer = nxt if nxt < n_items and rng.randrange(100) < in_pct else None
        r1 = rng.randrange(100) < out_pct
        r2 = rng.randrange(100) < out_pct
        leaves, took = model.cycle(now, offer, r1, r2)
        for it, port in leaves:
            expect[it] = (now, port)
        dut.in_valid.value = int(offer is not None)
        dut.in_data.value = (offer or 0) & mask
        dut.out_ready.value = int(r1)
        dut.out2_ready.value = int(r2)
        await Timer(1, unit="ns")
        if offer is not None and bool(int(dut.in_ready.value)) != took:
            failures.append(f"FAIL item {offer}: in_ready {int(dut.in_ready.value)} in cycle {now}, the model {int(took)}")
        ports = [(dut.out_valid, dut.out_data, r1), (dut.out2_valid, dut.out2_data, r1 and r2)]
        for port, (valid, data, taken) in enumerate(ports):
            if taken and int(valid.value):
                it = int(data.value)
                if it in got:
                    failures.append(f"FAIL item {it}: left twice (cycles {got[it][0]} and {now})")
                got[it] = (now, port)
        if took:
            nxt += 1
        now += 1
    print(f"elastic2: {now} cycles; two leaves in {model.two_leaves}, input refused in {model.refused}")
    if corrupt:
        c = int(corrupt)
        e = expect.get(c, (0, 0))
        expect[c] = (e[0] + 1, e[1])
    passed = 0
    for it in range(n_items):
        e, g = expect.get(it), got.get(it)
        if e is not None and e == g:
            passed += 1
        else:
            failures.append(f"FAIL item {it}: RTL left (cycle, port) {g}, model {e}")
    for f in failures[:20]:
        print(f)
    print(f"elastic2: {passed} passed, {len(failures)} failed")
    assert not failures
