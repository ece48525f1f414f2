"""svo_walker_pool on its own at K = 2 walk lanes, against the functional model's walks and the
pool's dispatch and retire rules, checked at its ports and its walkers' own outputs.

Pipeline position: the walker pool between root_to_dispatch and walker_to_record
(rtl_model/src/cycle/walker_pool.rs; testbench/README.md, "Walk issue of width k"). The top is
tb_walker_pool.sv: one svo_walker_root on the rows of vectors/walker.hex, root_to_dispatch (an
svo_fifo_wide of K pop ports), the pool; this bench is the node memory (per walker port a read
in cycle c answered in c + L, vectors/walker_nodes.hex and walker_attrs.hex) and the record
FIFO.

Each cycle the bench offers a random prefix of root_to_dispatch's lanes and takes a random
prefix of the retire lanes (seeded). Checked, with nothing shared with the RTL or the Rust
model (the expectations are walker.hex's, written by the functional model):
- every row's walk retires exactly once, with the row's outcome and, a hit, its t, voxel and
  attribute record;
- the take lanes: in_ready[j] iff more than j contexts are free (a context is free when its
  walker's in_ready says so: idle, or retiring in this cycle); lane 1 taken only with lane 0;
  each taken walk goes to a free context of the walker with the most free contexts, the lowest
  index on ties, lane 1's counted after lane 0's (so both can go to one walker);
- the retire lanes: out_valid[j] iff more than j walks are finished (the walkers' out_valid);
  finished walks retire in the order they finished (by cycle; the order within a cycle, the
  model's wake-up order, is not checked here);
- err_resp and the bench top's root_to_dispatch overflow stay 0.
Not checked: the cycles (the model's, which the core bench checks at K = 1).

Environment: SVO_SEED (default 29, printed), SVO_MEM_LATENCY (default 3), SVO_OFFER and
SVO_TAKE (percent chance per lane and cycle that the source offers / the sink takes, default
70 and 60), SVO_CORRUPT=ROW adds one to row ROW's expected t (a hit's row): exactly one
failure. Prints the
failures (first 20), the counts of the cases covered, then "walker_pool: N passed, N failed".
"""
import json
import os
import random
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import FallingEdge, RisingEdge, Timer

VEC = Path(__file__).resolve().parents[2] / "vectors"


def read_hex(name):
    return [int(l, 16) for l in (VEC / name).read_text().split("\n") if l and not l.startswith("//")]


def fields(name):
    return {f["name"]: (f["offset"], f["width"]) for f in json.loads((VEC / name).read_text())["fields"]}


def get(word, f):
    off, width = f
    return (word >> off) & ((1 << width) - 1)


def bits(v, n):
    return [(v >> i) & 1 for i in range(n)]


@cocotb.test()
async def walker_pool_lanes_keep_the_rules(dut):
    k = int(dut.K.value)
    nw, nr = int(dut.WALKERS.value), int(dut.CONTEXTS.value)
    depth = int(dut.DEPTH.value)
    n = nw * nr
    seed = int(os.environ.get("SVO_SEED", "29"))
    lat = int(os.environ.get("SVO_MEM_LATENCY", "3"))
    offer_pct = int(os.environ.get("SVO_OFFER", "70"))
    take_pct = int(os.environ.get("SVO_TAKE", "60"))
    corrupt = os.environ.get("SVO_CORRUPT", "")
    rows = read_hex("walker.hex")
    nodes = read_hex("walker_nodes.hex")
    attrs = read_hex("walker_attrs.hex")
    fw = fields("walker.json")
    print(f"walker_pool: seed {seed}, K {k}, {nw} x {nr}, memory latency {lat}, "
          f"offer {offer_pct} %, take {take_pct} %, {len(rows)} rows")
    rng = random.Random(seed)
    expect = {}
    for i, r in enumerate(rows):
        outcome = get(r, fw["outcome"])        # 1: a hit
        rec = attrs[get(r, fw["attr_base"]) + get(r, fw["attr"])] if outcome == 1 else None
        voxel = get(r, fw["voxel_x"]) | get(r, fw["voxel_y"]) << 20 | get(r, fw["voxel_z"]) << 40
        expect[i] = (outcome, get(r, fw["t"]), voxel, rec)
    if corrupt:
        o, t, v, rec = expect[int(corrupt)]
        expect[int(corrupt)] = (o, (t + 1) & ((1 << fw["t"][1]) - 1), v, rec)
    t_w = fw["t"][1]
    cw = (n - 1).bit_length() if n > 1 else 1

    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.rst.value = 1
    dut.row_valid.value = 0
    dut.row.value = 0
    dut.row_tag.value = 0
    dut.offer.value = 0
    dut.out_ready.value = 0
    dut.mem_resp_valid.value = 0
    dut.mem_resp_ctx.value = 0
    dut.mem_resp_data.value = 0
    for _ in range(3):
        await RisingEdge(dut.clk)
    dut.rst.value = 0
    pool = dut.pool
    failures = []
    bad = set()                   # rows retired with a wrong result
    got = {}
    ctx_tag = [None] * n          # the walk a context holds
    finished_at = {}              # tag -> the cycle its walker first showed it finished
    last_retired_finish = -1
    sched = {}                    # cycle -> [(port, ctx, data)]
    pushed = taken = 0
    now = 0
    cover = dict(two_takes=0, two_takes_one_walker=0, two_retires=0,
                 two_retires_one_walker=0, dispatch_refused=0, retire_held=0, root_misses=0)

    def fail(msg):
        failures.append(f"FAIL cycle {now}: {msg}")

    while len(got) < len(rows) and now < 400 * len(rows):
        await FallingEdge(dut.clk)
        # The node memory's answers for this cycle.
        resp = sched.pop(now, [])
        rv = rc = rd = 0
        for port, ctx, data in resp:
            rv |= 1 << port
            rc |= ctx << (port * cw)
            rd |= data << (port * 64)
        dut.mem_resp_valid.value = rv
        dut.mem_resp_ctx.value = rc
        dut.mem_resp_data.value = rd
        # A row into the root while root_to_dispatch has room for everything in flight.
        push = pushed < len(rows) and pushed - taken < depth - 1 and rng.randrange(100) < 80
        dut.row_valid.value = int(push)
        dut.row.value = rows[pushed] if push else 0
        dut.row_tag.value = pushed if push else 0
        n_offer = 0
        while n_offer < k and rng.randrange(100) < offer_pct:
            n_offer += 1
        n_take = 0
        while n_take < k and rng.randrange(100) < take_pct:
            n_take += 1
        dut.offer.value = (1 << n_offer) - 1
        dut.out_ready.value = (1 << n_take) - 1
        await Timer(1, unit="ns")
        if push:
            pushed += 1

        free = bits(int(pool.e_in_ready.value), n)
        out_v = bits(int(pool.e_out_valid.value), n)
        in_v = bits(int(dut.in_valid.value), k)
        in_r = bits(int(dut.in_ready.value), k)
        take = int(pool.take.value)
        in_tag = int(pool.in_tag.value)
        # Finished walks, by the cycle their walker first shows them finished.
        for c in range(n):
            if out_v[c] and ctx_tag[c] is not None and ctx_tag[c] not in finished_at:
                finished_at[ctx_tag[c]] = now

        # Retire lanes: valid as a count of finished walks; finish order; the results.
        o_v = bits(int(dut.out_valid.value), k)
        n_fin = sum(out_v)
        for j in range(k):
            if o_v[j] != int(n_fin > j):
                fail(f"out_valid[{j}] = {o_v[j]} with {n_fin} finished walks")
        if o_v[0] and n_take == 0:
            cover["retire_held"] += 1
        outcome, t = int(dut.out_outcome.value), int(dut.out_t.value)
        voxel, adata = int(dut.out_voxel.value), int(dut.out_attr_data.value)
        tags = int(dut.out_tag.value)
        ret = []
        for j in range(min(n_take, k)):
            if not o_v[j]:
                break
            tag = (tags >> (16 * j)) & 0xFFFF
            res = ((outcome >> (2 * j)) & 3, (t >> (t_w * j)) & ((1 << t_w) - 1),
                   (voxel >> (60 * j)) & ((1 << 60) - 1), (adata >> (64 * j)) & ((1 << 64) - 1))
            ret.append(tag)
            if tag in got:
                fail(f"row {tag} retired twice (cycles {got[tag]} and {now})")
                continue
            got[tag] = now
            if tag not in expect:
                fail(f"row {tag} retired: no such row")
                continue
            e = expect[tag]
            # (t, voxel and the record mean something on a hit only: a barrel walker's
            # miss shows its context's stale t and voxel, which the record stage ignores)
            mine = res if e[0] == 1 else (res[0], e[1], e[2], None)
            if mine != e:
                bad.add(tag)
                fail(f"row {tag}: outcome, t, voxel, record {mine}, the functional model {e}")
            fa = finished_at.get(tag)
            if fa is None:
                fail(f"row {tag} retired before its walker showed it finished")
            elif fa < last_retired_finish:
                fail(f"row {tag} (finished in cycle {fa}) retired after a walk finished in cycle {last_retired_finish}")
            else:
                last_retired_finish = fa
        if len(ret) == 2:
            cover["two_retires"] += 1
            owners = [c // nr for c in range(n) if ctx_tag[c] in ret and out_v[c]]
            cover["two_retires_one_walker"] += len(owners) == 2 and owners[0] == owners[1]
        for c in range(n):
            if ctx_tag[c] in ret and out_v[c]:
                ctx_tag[c] = None
        # Take lanes: ready as a count of free contexts; the dispatch rule.
        nfree = [sum(free[w * nr:(w + 1) * nr]) for w in range(nw)]
        for j in range(k):
            if in_r[j] != int(sum(nfree) > j):
                fail(f"in_ready[{j}] = {in_r[j]} with {sum(nfree)} free contexts")
        lanes = [j for j in range(k) if in_v[j] and in_r[j]]
        if lanes and lanes != list(range(len(lanes))):
            fail(f"lanes {lanes} taken: not a prefix")
        if in_v[0] and not in_r[0]:
            cover["dispatch_refused"] += 1
        counts = list(nfree)
        walkers_taken = []
        for j in lanes:
            onehot = (take >> (j * n)) & ((1 << n) - 1)
            ctxs = [c for c in range(n) if (onehot >> c) & 1]
            best = max(range(nw), key=lambda w: (counts[w], -w))
            if len(ctxs) != 1:
                fail(f"lane {j} taken by contexts {ctxs}")
                continue
            c = ctxs[0]
            if c // nr != best or not free[c]:
                fail(f"lane {j} to context {c} (walker {c // nr}); free per walker {counts}: walker {best}")
            counts[c // nr] -= 1
            walkers_taken.append(c // nr)
            tag = (in_tag >> (16 * j)) & 0xFFFF
            cover["root_misses"] += tag < len(rows) and get(rows[tag], fw["steps"]) == 0
            ctx_tag[c] = tag
            taken += 1
        if len(lanes) == 2:
            cover["two_takes"] += 1
            cover["two_takes_one_walker"] += walkers_taken[0] == walkers_taken[1]

        # Reads: answered in cycle now + L on the same port.
        mv, ma = int(dut.mem_req_valid.value), int(dut.mem_req_attr.value)
        maddr, mctx = int(dut.mem_req_addr.value), int(dut.mem_req_ctx.value)
        for p in range(nw):
            if (mv >> p) & 1:
                addr = (maddr >> (32 * p)) & 0xFFFFFFFF
                ctx = (mctx >> (cw * p)) & ((1 << cw) - 1)
                if (ma >> p) & 1:
                    data = attrs[addr] if addr < len(attrs) else None
                else:
                    data = nodes[addr] if addr < len(nodes) else None
                if data is None:
                    fail(f"walker {p} read {addr} outside the memory")
                    data = 0
                sched.setdefault(now + lat, []).append((p, ctx, data))
        if int(dut.err_resp.value):
            fail("err_resp")
            break
        if int(dut.overflow.value):
            fail("root_to_dispatch overflowed (the bench's credit)")
            break
        now += 1

    missing = [i for i in range(len(rows)) if i not in got]
    for i in missing[:5]:
        failures.append(f"FAIL row {i}: never retired ({len(missing)} rows)")
    print(f"walker_pool: {now} cycles; " + ", ".join(f"{a} {b}" for a, b in cover.items()))
    # A run that never used the second lanes checked nothing of them.
    needed = ["two_takes", "two_retires"] + (["two_takes_one_walker", "two_retires_one_walker"] if nr > 1 else [])
    for name in needed:
        if cover[name] == 0:
            failures.append(f"FAIL coverage: no cycle with {name}")
    for f in failures[:20]:
        print(f)
    passed = sum(1 for i in got if i not in bad)
    print(f"walker_pool: {passed} passed, {len(failures)} failed")
    assert not failures
