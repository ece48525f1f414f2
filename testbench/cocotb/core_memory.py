"""The memories behind svo_top's AXI4 read masters in the core bench (test_core.py): the
fixed-latency slaves, the several walkers' node lanes, the node store's load master and the
node cache's DRAM, each driven once a cycle by every_cycle, with optional seeded random pauses.

Pipeline position: outside the accelerator, the system's memory as the host lays it out
(test_core.py puts the direction table, node images and attribute records into `mem`). The
timing each one gives is the model's memory timing it stands for (its class says which), so a
frame's cycles can be compared with the cycle model's.
"""
from cocotb.triggers import FallingEdge, ReadOnly


class FixedLatencyRead:
    """An AXI4 read slave whose every read is there L cycles after its AR handshake (the
    model's fixed-latency node memory), a burst's beats on consecutive cycles, arready
    always high. Each cycle: drive R at the falling edge, then sample AR once settled."""

    def __init__(self, dut, prefix, mem, latency, nbytes):
        self.dut, self.p, self.mem, self.lat, self.nbytes = dut, prefix, mem, latency, nbytes
        self.beats = []             # (due cycle, address, last), in order
        self.cycle = 0
        self.fail_next = False      # the next beat answers SLVERR (STATUS.ERROR 5 / 6)
        self.sig("arready").value = 1
        self.sig("rvalid").value = 0
        self.sig("rid").value = 0
        self.sig("rresp").value = 0
        self.sig("rlast").value = 0
        self.sig("rdata").value = 0

    def sig(self, name):
        return getattr(self.dut, f"{self.p}_{name}")

    def drive(self):
        """The falling edge of a cycle: R for this cycle."""
        self.cycle += 1
        if self.beats and self.beats[0][0] <= self.cycle:
            _, addr, last = self.beats.pop(0)
            base = addr - addr % self.nbytes
            self.sig("rdata").value = int.from_bytes(self.mem[base:base + self.nbytes], "little")
            self.sig("rlast").value = int(last)
            self.sig("rvalid").value = 1
            self.sig("rresp").value = 2 if self.fail_next else 0
            self.fail_next = False
        else:
            self.sig("rvalid").value = 0
            self.sig("rresp").value = 0

    def sample(self):
        """Once the cycle has settled: an AR handshake at its closing edge."""
        if self.sig("arvalid").value == 1:
            addr = int(self.sig("araddr").value)
            n = int(self.sig("arlen").value) + 1
            size = 1 << int(self.sig("arsize").value)
            for k in range(n):
                self.beats.append((self.cycle + self.lat + k, addr + k * size, k == n - 1))


class RandomPauses:
    """The random pauses of the stalling slaves below: with pct > 0 a point of the protocol
    (key: "node ar", "load r", ...) pauses in a random pct % of the cycles it is asked about
    (rng, seeded by the bench), counted in stalls[key]."""

    def paused(self, key):
        if self.pct and self.rng.randrange(100) < self.pct:
            self.stalls[key] += 1
            return True
        return False


class NodeLanesRead(RandomPauses):
    """svo_top's node memory with several walkers: one AXI4 read slave per walker's master
    (lane w = bits [w] of the m_axi_* vectors, its address and data the w-th slices), each as
    FixedLatencyRead: single beats, in order, a read there L cycles after its AR handshake.
    With pct > 0 each lane's arready and each due R beat pause in a random pct % of cycles
    (rng), counted in stalls["node ar"] / ["node r"]; a paused beat and those behind it wait."""

    ADDR_W = 40

    def __init__(self, dut, mem, latency, lanes, rng=None, pct=0, stalls=None):
        self.dut, self.mem, self.lat, self.lanes = dut, mem, latency, lanes
        self.rng, self.pct, self.stalls = rng, pct, stalls
        self.q = [[] for _ in range(lanes)]       # (due cycle, address), in order
        self.cycle = 0
        self.fail_next = False                    # the next beat answers SLVERR (STATUS.ERROR 5)
        self.ar = (1 << lanes) - 1
        dut.m_axi_arready.value = self.ar
        for name in ("rvalid", "rid", "rresp", "rlast", "rdata"):
            getattr(dut, f"m_axi_{name}").value = 0

    def drive(self):
        """The falling edge of a cycle: each lane's R and arready for this cycle."""
        self.cycle += 1
        rvalid, rdata, ar, rresp = 0, 0, 0, 0
        for w in range(self.lanes):
            q = self.q[w]
            if q and q[0][0] <= self.cycle and not self.paused("node r"):
                _, addr = q.pop(0)
                base = addr - addr % 8
                rvalid |= 1 << w
                if self.fail_next:
                    rresp |= 2 << (2 * w)
                    self.fail_next = False
                rdata |= int.from_bytes(self.mem[base:base + 8], "little") << (64 * w)
            if not self.paused("node ar"):
                ar |= 1 << w
        self.ar = ar
        self.dut.m_axi_arready.value = ar
        self.dut.m_axi_rvalid.value = rvalid
        self.dut.m_axi_rresp.value = rresp
        self.dut.m_axi_rlast.value = rvalid
        self.dut.m_axi_rdata.value = rdata

    def sample(self):
        """Once the cycle has settled: each lane's AR handshake at its closing edge."""
        arvalid = int(self.dut.m_axi_arvalid.value) & self.ar
        if not arvalid:
            return
        araddr = int(self.dut.m_axi_araddr.value)
        arlen = int(self.dut.m_axi_arlen.value)
        for w in range(self.lanes):
            if arvalid >> w & 1:
                assert (arlen >> (8 * w)) & 0xFF == 0, "node reads are single beats"
                addr = (araddr >> (self.ADDR_W * w)) & ((1 << self.ADDR_W) - 1)
                self.q[w].append((self.cycle + self.lat, addr))


class LoadRead(RandomPauses):
    """svo_top's load master (m_axi_load_*, 8-byte beats, INCR bursts): a burst's beats from
    L cycles after its AR handshake, one a cycle as rready takes them (the DMA takes one every
    other cycle), rvalid held until taken. With pct > 0 arready and each beat not yet shown
    pause in a random pct % of cycles (rng), counted in stalls["load ar"] / ["load r"].
    fail_at = k: the load's beat k answers SLVERR (STATUS.ERROR 9). Checks that no burst
    crosses a 4 KiB page."""

    def __init__(self, dut, mem, latency, rng=None, pct=0, stalls=None):
        self.dut, self.mem, self.lat = dut, mem, latency
        self.rng, self.pct, self.stalls = rng, pct, stalls
        self.bursts = []            # [due cycle, address, beats left]
        self.cycle = 0
        self.shown = False          # a beat is on R, not yet taken
        self.beats = 0              # beats taken since the last reset_count()
        self.fail_at = None
        self.errors = []            # protocol errors seen (bursts crossing a page)
        self.ar = 1
        dut.m_axi_load_arready.value = 1
        for name in ("rvalid", "rid", "rresp", "rlast", "rdata"):
            getattr(dut, f"m_axi_load_{name}").value = 0

    def drive(self):
        self.cycle += 1
        d = self.dut
        if not self.shown and self.bursts and self.bursts[0][0] <= self.cycle and not self.paused("load r"):
            _, addr, left = self.bursts[0]
            d.m_axi_load_rdata.value = int.from_bytes(self.mem[addr:addr + 8], "little")
            d.m_axi_load_rlast.value = int(left == 1)
            d.m_axi_load_rresp.value = 2 if self.fail_at == self.beats else 0
            d.m_axi_load_rvalid.value = 1
            self.shown = True
        elif not self.shown:
            d.m_axi_load_rvalid.value = 0
            d.m_axi_load_rresp.value = 0
        self.ar = 0 if self.paused("load ar") else 1
        d.m_axi_load_arready.value = self.ar

    def sample(self):
        d = self.dut
        if self.shown and d.m_axi_load_rready.value == 1:
            self.shown = False
            self.beats += 1
            b = self.bursts[0]
            b[1] += 8
            b[2] -= 1
            if b[2] == 0:
                self.bursts.pop(0)
        if self.ar and d.m_axi_load_arvalid.value == 1:
            addr = int(d.m_axi_load_araddr.value)
            n = int(d.m_axi_load_arlen.value) + 1
            if int(d.m_axi_load_arsize.value) != 3 or addr % 8:
                self.errors.append(f"a load burst at {addr:#x} of size {1 << int(d.m_axi_load_arsize.value)}")
            if addr // 4096 != (addr + 8 * n - 1) // 4096:
                self.errors.append(f"a load burst of {n} beats at {addr:#x} crosses a 4 KiB page")
            self.bursts.append([self.cycle + self.lat, addr, n])


class NodeCacheDram(RandomPauses):
    """svo_top's node-cache master (m_axi_node_*, hardware with node_memory.onchip.levels 0):
    an AXI4 read slave whose timing is the model's built-in DRAM bus (rtl_model memory/dram.rs)
    as svo_node_cache_axi.v's contract states it and testbench/tb/tb_axi_dram.sv implements it
    (written again here, not shared, because the data must be the node image and the attribute
    records in `mem`, where tb_dram_model returns a hash of the address): the AR of a fill
    taken in cycle a counts as issued in a - 1; the fill starts on the one bus at
    max((a - 1 + LATENCY) * B, the previous fill's end), ends LINE_BYTES later, is done in
    ceil(end / B), and its one beat (RLAST) is on R in done - 2 on the port its AR came on.
    ARs are taken in rotating port order from the port of the next fill (the master stripes
    fill n on port n mod ports), stopping at the first port without one, so the bus order is
    the issue order; ARREADY is high only on the ports taken. (Issue 29, two ports under
    pauses: a READY on a port behind a paused one completed a handshake the bench did not
    take, the master's ports being independent queues, and two ARs taken in one cycle read
    one port twice, the rotation moving inside its own loop: lost fills, frames that never
    ended.) With pct > 0, each port's ARREADY and each due beat pause in a random pct % of
    cycles (rng), counted in stalls["cache ar"] / ["cache r"]; held beats wait in order.
    fail_next: the next beat answers SLVERR (STATUS.ERROR 10)."""

    ADDR_W = 40

    def __init__(self, dut, mem, latency, bpc, line, rng=None, pct=0, stalls=None):
        self.dut, self.mem, self.lat, self.bpc, self.line = dut, mem, latency, bpc, line
        self.rng, self.pct, self.stalls = rng, pct, stalls
        self.ports = len(dut.m_axi_node_arvalid)
        self.idw = len(dut.m_axi_node_arid) // self.ports
        self.q = [[] for _ in range(self.ports)]  # (due cycle, address, id), in order
        self.cycle = 0
        self.bus_end = 0                          # the last fill's end (byte slots)
        self.next_port = 0                        # the port of the next fill
        self.fills = 0
        self.fail_next = False
        self.errors = []
        self.ar = (1 << self.ports) - 1
        dut.m_axi_node_arready.value = self.ar
        for name in ("rvalid", "rid", "rresp", "rlast", "rdata"):
            getattr(dut, f"m_axi_node_{name}").value = 0

    def drive(self):
        """The falling edge of a cycle: each port's R and ARREADY for this cycle."""
        self.cycle += 1
        rvalid, rdata, rresp, rid, ar, free = 0, 0, 0, 0, 0, 0
        for p in range(self.ports):
            q = self.q[p]
            if q and q[0][0] <= self.cycle and not self.paused("cache r"):
                _, addr, i = q.pop(0)
                rvalid |= 1 << p
                rid |= i << (self.idw * p)
                if self.fail_next:
                    rresp |= 2 << (2 * p)
                    self.fail_next = False
                rdata |= int.from_bytes(self.mem[addr:addr + self.line], "little") << (8 * self.line * p)
            if not self.paused("cache ar"):
                free |= 1 << p
        # READY on the ports sample() takes: in rotation from the next fill's, each with ARVALID
        # (the master's queue registers: settled at this edge) and not paused, to the first not.
        arvalid = int(self.dut.m_axi_node_arvalid.value)
        for j in range(self.ports):
            p = (self.next_port + j) % self.ports
            if not (free & arvalid) >> p & 1:
                break
            ar |= 1 << p
        self.ar = ar
        d = self.dut
        d.m_axi_node_arready.value = ar
        d.m_axi_node_rvalid.value = rvalid
        d.m_axi_node_rresp.value = rresp
        d.m_axi_node_rlast.value = rvalid
        d.m_axi_node_rid.value = rid
        d.m_axi_node_rdata.value = rdata

    def sample(self):
        """Once the cycle has settled: the AR handshakes at its closing edge, in fill order."""
        arvalid = int(self.dut.m_axi_node_arvalid.value)
        if not arvalid & self.ar:
            return
        araddr = int(self.dut.m_axi_node_araddr.value)
        arid = int(self.dut.m_axi_node_arid.value)
        arlen = int(self.dut.m_axi_node_arlen.value)
        arsize = int(self.dut.m_axi_node_arsize.value)
        first = self.next_port                    # (next_port moves with each AR taken)
        for j in range(self.ports):
            p = (first + j) % self.ports
            if not (arvalid & self.ar) >> p & 1:
                break                             # the fills behind it wait, in order
            addr = (araddr >> (self.ADDR_W * p)) & ((1 << self.ADDR_W) - 1)
            if (arlen >> (8 * p)) & 0xFF or 1 << ((arsize >> (3 * p)) & 7) != self.line or addr % self.line:
                self.errors.append(f"a fill at {addr:#x} that is not one aligned beat of {self.line} bytes")
            start = max((self.cycle - 1 + self.lat) * self.bpc, self.bus_end)
            self.bus_end = start + self.line
            done = -(-self.bus_end // self.bpc)
            self.q[p].append((done - 2, addr, (arid >> (self.idw * p)) & ((1 << self.idw) - 1)))
            self.next_port = (p + 1) % self.ports
            self.fills += 1


async def every_cycle(dut, slaves):
    """One coroutine for both fixed-latency slaves (fewer simulator callbacks): at the falling
    edge their R, then, settled, their AR handshakes."""
    if not slaves:
        return
    while True:
        await FallingEdge(dut.clk)
        for s in slaves:
            s.drive()
        await ReadOnly()
        for s in slaves:
            s.sample()


def stall_gen(rng, pct, counter, key):
    while True:
        s = rng.randrange(100) < pct
        if s:
            counter[key] += 1
        yield s
