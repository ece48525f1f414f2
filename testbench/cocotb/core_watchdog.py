"""The core bench's watchdog (test_core.py): a frame that has not finished (every pixel
streamed and STATUS.DONE read) within a bound of simulated cycles after its START ends the
bench with the state that explains a hang, instead of running forever.

Pipeline position: none; a helper of the core bench (testbench/cocotb/test_core.py), which
runs each frame's wait under `frame_within` and, when it fires, prints `hang_report` and fails.

The bound: SVO_WATCHDOG=N cycles if given, else 50 x the model's frame cycles + 10,000 (20 %
pauses cost the stall runs of testbench/README.md about 1 %, e.g. 15,405 cycles against the
model's 15,272; the constant covers the bench's own polling of STATUS after the last pixel). Why the state below: a hang is a read or a pixel that is
waited for and never comes, so the report names who waits (the pool's busy contexts and the
contexts with a node-memory read out), what the node memory holds (the cache's MSHRs, the
contexts waiting on a fill, its miss and bank queues, the AXI fill queue; the store's schedule)
and each AXI channel's valid/ready at the cycle it fired. Internal state is read through
Verilator's public handles (the cocotb runner builds with --public-flat-rw); a handle the
hardware does not have (no cache, no store) prints as "-".
"""
import os

from cocotb.triggers import SimTimeoutError, with_timeout
from cocotb.utils import get_sim_time

CLOCK_NS = 10  # test_core.py's clock period


def bound(model_cycles):
    """The frame's bound in cycles: SVO_WATCHDOG, else 50 x the model's cycles + 10,000."""
    given = os.environ.get("SVO_WATCHDOG")
    if given:
        return int(given)
    return 50 * max(model_cycles, 0) + 10_000


def cycle():
    """The simulated cycle (clock edges since time 0)."""
    return int(get_sim_time("ns")) // CLOCK_NS


async def frame_within(wait, limit):
    """Runs the coroutine `wait` for at most `limit` cycles: True if it finished, False if the
    watchdog fired (the coroutine is then killed)."""
    try:
        await with_timeout(wait, limit * CLOCK_NS, "ns")
        return True
    except SimTimeoutError:
        return False


def _peek(dut, path):
    """The integer value of dut.<path>, or None where the hardware has no such handle."""
    h = dut
    for part in path.split("."):
        try:
            h = getattr(h, part)
        except AttributeError:
            return None
    try:
        return int(h.value)
    except (ValueError, TypeError, AttributeError):
        return None


def _ones(v):
    return "-" if v is None else "[" + ",".join(str(i) for i in range(v.bit_length()) if v >> i & 1) + "]"


def _hex(v):
    return "-" if v is None else f"{v:#x}"


def _count(v):
    return "-" if v is None else str(bin(v).count("1"))


def hang_report(dut, started, limit):
    """The lines that explain a hang: the cycle, who waits, what the node memory holds, the
    AXI channels' handshakes. `started`: the frame's START cycle."""
    now = cycle()
    # svo_core's walk section (svo_walk_wide at K = 1 and 2; the generate scopes of the
    # builds before svo_walk's removal, for an older build folder).
    walk = next((p for p in ("u_core.u_walk", "u_core.walk_one.u_walk", "u_core.walk_wide.u_walk")
                 if _peek(dut, p + ".err_pipe") is not None), "u_core.u_walk")
    pool = walk + ".u_walker"
    cache = "u_memory.cached.u_cache"
    lines = [
        f"watchdog: the frame started in cycle {started} has not finished in {now - started} "
        f"cycles (bound {limit}); simulated cycle {now}",
        f"watchdog: pool: busy contexts {_ones(_peek(dut, pool + '.busy'))}, node-memory reads "
        f"out {_ones(_peek(dut, 'st_pend'))}, pipe error {_peek(dut, walk + '.err_pipe')}, "
        f"svo_top run {_peek(dut, 'run')}",
        f"watchdog: cache: MSHRs in use {_ones(_peek(dut, cache + '.cache.mv_q'))}, contexts "
        f"waiting on a fill {_ones(_peek(dut, cache + '.cache.wait_q'))}, miss queue entries "
        f"{_peek(dut, cache + '.cache.mn_q')}, bank queue counts "
        f"{_hex(_peek(dut, cache + '.cache.bn_q'))}, AXI fill queue counts "
        f"{_hex(_peek(dut, cache + '.q_n'))}, fills held {_ones(_peek(dut, cache + '.fv_q'))}",
        f"watchdog: store: schedule entries {_count(_peek(dut, 'u_memory.onchip.u_store.q_valid'))} "
        f"({_hex(_peek(dut, 'u_memory.onchip.u_store.q_valid'))}), overflow {_peek(dut, 'u_memory.onchip.u_store.err')}",
    ]
    chans = []
    for bus, hs in (("m_axi_node_ar", "valid ready"), ("m_axi_node_r", "valid ready"),
                    ("m_axi_ar", "valid ready"), ("m_axi_r", "valid ready"),
                    ("m_axi_dir_ar", "valid ready"), ("m_axi_dir_r", "valid ready"),
                    ("m_axi_load_ar", "valid ready"), ("m_axi_load_r", "valid ready"),
                    ("m_axis_t", "valid ready")):
        v, r = (_peek(dut, bus + s) for s in hs.split())
        chans.append(f"{bus} {_hex(v)}/{_hex(r)}")
    lines.append("watchdog: AXI valid/ready: " + ", ".join(chans))
    return "\n".join(lines)
