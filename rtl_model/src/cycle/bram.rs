//! Block RAM with a fixed number of ports per cycle and documented read-during-write
//! behaviour: the model of the hit buffer's storage (and of other on-chip tables).
//!
//! Pipeline position: the hit buffer (paper §4.3) is read by the reuse check and written by
//! the record write-back; both go through this model, which counts every access and refuses
//! what the ports cannot do in one cycle.
//!
//! Read during write: READ_FIRST, the mode of UltraScale+ block RAM and UltraRAM that is well
//! defined with a common clock: a read in cycle c returns the contents at the start of c, and
//! every write of cycle c lands at the clock edge that ends it. Reads therefore never depend on
//! the order in which ports are driven within a cycle, which the two-phase discipline of
//! [`super::clocked`] requires. A read and a write of the same address in one cycle (the old
//! value is read) is legal but counted as a collision, since in the hit buffer it would mean a
//! pixel's record is read while its own update is in flight. Two writes of one address in one
//! cycle are refused.

use super::clocked::Commit;
use serde::Serialize;
use thiserror::Error;

/// Why an access was refused (nothing panics).
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
pub enum BramError {
    /// Every port is already used this cycle.
    #[error("all {ports} ports are busy in cycle {cycle}")]
    PortsBusy {
        /// Ports per cycle.
        ports: u8,
        /// The cycle.
        cycle: u64,
    },
    /// The address is outside the memory.
    #[error("address {addr} is outside a {depth}-word memory")]
    Address {
        /// The address.
        addr: usize,
        /// Words.
        depth: usize,
    },
    /// A second write to the same address in one cycle.
    #[error("address {addr} is written twice in cycle {cycle}")]
    WriteCollision {
        /// The address.
        addr: usize,
        /// The cycle.
        cycle: u64,
    },
    /// A memory with no ports or no words cannot be built.
    #[error("a block RAM needs at least one port and one word")]
    Shape,
}

/// Access counters.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct BramStats {
    /// Cycles seen.
    pub cycles: u64,
    /// Reads served.
    pub reads: u64,
    /// Writes accepted.
    pub writes: u64,
    /// Accesses refused because every port was busy.
    pub port_conflicts: u64,
    /// Cycles in which an address was both read and written (the read saw the old value).
    pub read_write_collisions: u64,
    /// Refused double writes and out-of-range addresses.
    pub errors: u64,
    /// Cycles with every port in use.
    pub full_cycles: u64,
}

/// A `depth`-word block RAM with `ports` accesses per cycle.
#[derive(Clone, Debug)]
pub struct Bram<T> {
    data: Vec<T>,
    ports: u8,
    used: u8,
    now: u64,
    writes: Vec<(usize, T)>,
    reads: Vec<usize>,
    stats: BramStats,
}

impl<T> Bram<T> {
    /// Takes `k` cycles without an access at once (idle-cycle skipping), as `k` edges with
    /// no access would: only the cycle counters move. Call between edges.
    pub fn skip_idle(&mut self, k: u64) {
        self.now = self.now.saturating_add(k);
        self.stats.cycles = self.stats.cycles.saturating_add(k);
    }
}

impl<T: Clone> Bram<T> {
    /// A memory of `depth` words, each `init`, with `ports` accesses per cycle (2 for a
    /// true dual-port block RAM).
    pub fn new(depth: usize, ports: u8, init: T) -> Result<Self, BramError> {
        if depth == 0 || ports == 0 {
            return Err(BramError::Shape);
        }
        Ok(Self {
            data: vec![init; depth],
            ports,
            used: 0,
            now: 0,
            writes: Vec::with_capacity(usize::from(ports)),
            reads: Vec::with_capacity(usize::from(ports)),
            stats: BramStats::default(),
        })
    }

    /// Words.
    pub fn depth(&self) -> usize {
        self.data.len()
    }

    /// Counters so far.
    pub fn stats(&self) -> &BramStats {
        &self.stats
    }

    /// Ports still free this cycle.
    pub fn free_ports(&self) -> u8 {
        self.ports - self.used
    }

    fn take_port(&mut self) -> Result<(), BramError> {
        if self.used >= self.ports {
            self.stats.port_conflicts += 1;
            return Err(BramError::PortsBusy {
                ports: self.ports,
                cycle: self.now,
            });
        }
        self.used += 1;
        Ok(())
    }

    fn check_addr(&mut self, addr: usize) -> Result<(), BramError> {
        if addr >= self.data.len() {
            self.stats.errors += 1;
            return Err(BramError::Address {
                addr,
                depth: self.data.len(),
            });
        }
        Ok(())
    }

    /// Reads `addr` on a free port: the contents at the start of this cycle (READ_FIRST).
    pub fn read(&mut self, addr: usize) -> Result<T, BramError> {
        self.check_addr(addr)?;
        self.take_port()?;
        self.stats.reads += 1;
        self.reads.push(addr);
        Ok(self.data[addr].clone())
    }

    /// Writes `value` to `addr` on a free port; it lands at the edge ending this cycle.
    pub fn write(&mut self, addr: usize, value: T) -> Result<(), BramError> {
        self.check_addr(addr)?;
        if self.writes.iter().any(|&(a, _)| a == addr) {
            self.stats.errors += 1;
            return Err(BramError::WriteCollision {
                addr,
                cycle: self.now,
            });
        }
        self.take_port()?;
        self.stats.writes += 1;
        self.writes.push((addr, value));
        Ok(())
    }

    /// The contents at the start of this cycle, without using a port (for checks and dumps).
    pub fn peek(&self, addr: usize) -> Option<&T> {
        self.data.get(addr)
    }

    /// Sets `addr` at once, without a port or a cycle: functional warming between the timed
    /// parts of a sampled frame (docs/cycle-model.md §3.5), never in a timed cycle.
    pub fn poke(&mut self, addr: usize, value: T) -> Result<(), BramError> {
        self.check_addr(addr)?;
        self.data[addr] = value;
        Ok(())
    }
}

impl<T: Clone> Commit for Bram<T> {
    fn cycle(&self) -> u64 {
        self.now
    }

    fn commit(&mut self) {
        if self
            .reads
            .iter()
            .any(|r| self.writes.iter().any(|(w, _)| w == r))
        {
            self.stats.read_write_collisions += 1;
        }
        if self.used == self.ports {
            self.stats.full_cycles += 1;
        }
        for (addr, value) in self.writes.drain(..) {
            self.data[addr] = value;
        }
        self.reads.clear();
        self.used = 0;
        self.now += 1;
        self.stats.cycles += 1;
    }
}

/// The dirty-flag registers of the hit buffer: written by the host for the next frame, read
/// by the reuse check; the new flags take effect at the edge, like any register.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DirtyRegisters {
    current: (bool, Vec<bool>),
    next: Option<(bool, Vec<bool>)>,
    now: u64,
}

impl DirtyRegisters {
    /// Flags for `instances` instances, all dirty (the first frame traces everything).
    pub fn new(instances: usize) -> Self {
        Self {
            current: (true, vec![true; instances]),
            next: None,
            now: 0,
        }
    }

    /// The camera flag in force this cycle.
    pub fn camera(&self) -> bool {
        self.current.0
    }

    /// Instance `i`'s flag in force this cycle (an unknown instance reads as dirty, the safe
    /// answer for reuse).
    pub fn instance(&self, i: usize) -> bool {
        self.current.1.get(i).copied().unwrap_or(true)
    }

    /// Loads new flags; they take effect at the next edge.
    pub fn load(&mut self, camera: bool, instances: Vec<bool>) {
        self.next = Some((camera, instances));
    }
}

impl Commit for DirtyRegisters {
    fn cycle(&self) -> u64 {
        self.now
    }

    fn commit(&mut self) {
        if let Some(n) = self.next.take() {
            self.current = n;
        }
        self.now += 1;
    }
}
