//! The DRAMsim3 backend of the DRAM behind the MSHRs: a line fill becomes one or more
//! DRAMsim3 read transactions, DRAMsim3 is clocked at the device's own rate against the
//! pipeline clock (an exact integer ratio, no floating point), and each transaction's
//! completion is mapped back to its fill and to a pipeline cycle.
//!
//! Pipeline position: inside [`super::dram::Dram`] when the hardware file selects
//! [`DramBackend::DramSim3`](super::config::DramBackend::DramSim3); step 1 of every simulated
//! cycle advances DRAMsim3 through the DRAM clocks that start in that cycle, step 4 queues the
//! cycle's new fills.
//!
//! # Clocks
//!
//! The pipeline runs at `f_c` = `clock_mhz` MHz, the device at `f_d` = half its data rate
//! (DDR4-2400: 1200 MHz), both held as integers in kHz. DRAM clock `j` starts at `j / f_d`,
//! pipeline cycle `k` at `k / f_c`. Simulating cycle `k` runs every DRAM clock that starts before
//! the end of cycle `k`: clocks up to `⌈(k + 1) · f_d / f_c⌉` (exclusive). A fill issued in
//! cycle `k` enters DRAMsim3's transaction queue at the end of cycle `k`, before the first DRAM
//! clock starting at or after `(k + 1) / f_c`. DRAMsim3 reports a read done at the start of
//! its clock `j` (`j / f_d`); the data is in the pipeline's clock domain at the first cycle
//! boundary at or after that, `⌈j · f_c / f_d⌉`, and the fill completes
//! `controller_latency` cycles later. All of this is integer arithmetic on u128, so a run
//! gives the same cycles on every machine. The device's `tCK` in its file is DRAMsim3's
//! rounded value (0.83 ns for 2400) and is used by DRAMsim3 only for its energy figures.
//!
//! # Transactions and addresses
//!
//! One DRAMsim3 transaction moves one burst: `bus_width / 8 · BL` bytes (64 for the bundled
//! DDR4 devices, x64 channel and BL8). A fill of a `line_bytes` line is
//! `⌈line_bytes / 64⌉` transactions at consecutive burst addresses and completes with the
//! last of them; a line shorter than a burst still moves a whole burst. The model's address
//! space (node words from byte 0, attribute records from `ATTR_REGION_BASE`) is folded onto
//! the device: node lines in the lower half of its capacity, attribute lines in the upper
//! half (each modulo the half), so the two arrays never share a row.
//!
//! # Statistics
//!
//! The binding exposes no counters, so the row-buffer figures are read from the epoch
//! statistics DRAMsim3 writes (`dramsim3epoch.json`): the epoch is set to
//! [`EPOCH_DRAM_CLOCKS`], and after each epoch the new records are parsed and added to the
//! window. A window's row-buffer figures therefore cover the epochs that ended in it
//! (up to 65 536 DRAM clocks, about 16 000 pipeline cycles, late at its end). Bytes are counted
//! by this model when each transaction completes. DRAMsim3's files go to a fresh directory
//! under the system's temporary directory, removed when the model is dropped.

use super::config::ConfigError;
use super::stats::DramDeviceStats;
use std::collections::{BTreeMap, VecDeque};
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

/// DRAM clocks per DRAMsim3 statistics epoch.
pub const EPOCH_DRAM_CLOCKS: u64 = 1 << 16;

/// A bundled DRAMsim3 device.
#[derive(Clone, Copy, Debug)]
pub(super) struct Device {
    pub(super) name: &'static str,
    /// Data rate, MT/s (the name's last number); the DRAM clock is half of it.
    pub(super) data_rate_mts: u64,
    ini: &'static str,
}

macro_rules! devices {
    ($($name:literal => $rate:literal),* $(,)?) => {
        /// The bundled DRAMsim3 device files (from the `dramsim3` crate's DRAMsim3, MIT licence,
        /// copied into `rtl_model/dram_configs/`).
        const DEVICES: &[Device] = &[$(Device {
            name: $name,
            data_rate_mts: $rate,
            ini: include_str!(concat!("../../../dram_configs/", $name, ".ini")),
        }),*];
        /// Names accepted by `DramSim3(config: ..)`.
        pub const CONFIG_NAMES: &[&str] = &[$($name),*];
    };
}

devices! {
    "DDR4_8Gb_x16_1866" => 1866,
    "DDR4_8Gb_x16_2133" => 2133,
    "DDR4_8Gb_x16_2400" => 2400,
    "DDR4_8Gb_x16_2666" => 2666,
    "DDR4_8Gb_x16_2933" => 2933,
    "DDR4_8Gb_x16_3200" => 3200,
    "DDR4_8Gb_x8_2400" => 2400,
    "DDR4_8Gb_x4_2400" => 2400,
    "DDR4_4Gb_x16_2400" => 2400,
    "DDR4_4Gb_x8_2400" => 2400,
}

/// The bundled device of that name.
pub(super) fn device(name: &str) -> Option<Device> {
    DEVICES.iter().copied().find(|d| d.name == name)
}

/// Bytes of one burst (one transaction) of every bundled device: a 64-bit channel, BL8.
pub const BURST_BYTES: u64 = 64;

/// Peak bytes per pipeline cycle of `channels` channels of `device` at `clock_mhz`: 16 bytes
/// per DRAM clock (8-byte bus, two transfers) per channel, rounded to the nearest byte.
pub(super) fn peak_bytes_per_cycle(device: &Device, channels: u32, clock_mhz: u32) -> u64 {
    let num = 16 * u64::from(channels) * dram_khz(device);
    let den = 1000 * u64::from(clock_mhz.max(1));
    (num + den / 2) / den
}

fn dram_khz(device: &Device) -> u64 {
    device.data_rate_mts * 500
}

/// A scratch directory under the system's temporary directory, removed on drop.
struct ScratchDir(PathBuf);

impl ScratchDir {
    fn new() -> Result<Self, String> {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let base = std::env::temp_dir();
        for _ in 0..1000 {
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let dir = base.join(format!("svo_sim_dramsim3_{}_{n}", std::process::id()));
            match std::fs::create_dir(&dir) {
                Ok(()) => return Ok(Self(dir)),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(format!("cannot create {}: {e}", dir.display())),
            }
        }
        Err(format!("no free scratch directory in {}", base.display()))
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        // Best effort: a left-over directory in the temporary directory harms nothing.
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The device file with this run's channel count and statistics epoch.
fn ini_text(device: &Device, channels: u32) -> String {
    let mut out = String::with_capacity(device.ini.len() + 64);
    for line in device.ini.lines() {
        let key = line.split('=').next().unwrap_or("").trim();
        match key {
            "channels" => out.push_str(&format!("channels = {channels}")),
            "epoch_period" => out.push_str(&format!("epoch_period = {EPOCH_DRAM_CLOCKS}")),
            "output_level" => out.push_str("output_level = 1"),
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    out
}

/// A fill in DRAMsim3: its transactions not yet done, and the latest completion so far.
#[derive(Clone, Copy, Debug)]
struct Fill {
    left: u32,
    done: u64,
}

/// DRAMsim3 behind the MSHRs.
pub(super) struct DramSim3 {
    // Declared first so that it is dropped (and closes its files) before the directory goes.
    sys: dramsim3::MemorySystem,
    _dir: ScratchDir,
    name: &'static str,
    /// Pipeline and DRAM clocks, kHz.
    f_core: u128,
    f_dram: u128,
    /// DRAM clocks run so far (DRAMsim3's `clk_`).
    clocks: u64,
    controller_latency: u64,
    line_bytes: u64,
    /// Bytes of half the device's capacity (each of the two regions' span).
    half_capacity: u64,
    /// Transactions not yet accepted by DRAMsim3's queues, in issue order.
    queued: VecDeque<u64>,
    /// Fills in DRAMsim3 by line, and the line of each transaction address.
    fills: BTreeMap<u64, Fill>,
    line_of_addr: BTreeMap<u64, u64>,
    /// Bytes completed during the last [`Self::advance`].
    bytes_last: u64,
    /// The epoch file and how much of it was read.
    epoch_file: PathBuf,
    epoch_read: usize,
    /// Counters of the current window.
    window: DramDeviceStats,
}

impl std::fmt::Debug for DramSim3 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DramSim3")
            .field("device", &self.name)
            .field("clocks", &self.clocks)
            .field("fills", &self.fills.len())
            .finish()
    }
}

impl DramSim3 {
    /// DRAMsim3 with `channels` channels of the device `name` (validated), behind a pipeline
    /// at `clock_mhz`.
    pub(super) fn new(
        name: &str,
        channels: u32,
        controller_latency: u32,
        line_bytes: u32,
        clock_mhz: u32,
    ) -> Result<Self, ConfigError> {
        let device = device(name).ok_or_else(|| ConfigError::DramDevice {
            name: name.to_string(),
            known: CONFIG_NAMES.join(", "),
        })?;
        let dir = ScratchDir::new().map_err(ConfigError::DramSim3Start)?;
        let ini = dir.0.join(format!("{name}.ini"));
        std::fs::write(&ini, ini_text(&device, channels)).map_err(|e| {
            ConfigError::DramSim3Start(format!("cannot write {}: {e}", ini.display()))
        })?;
        // DRAMsim3 appends its file names to the directory without a separator.
        let mut out = dir.0.clone().into_os_string();
        out.push(std::path::MAIN_SEPARATOR_STR);
        let sys = dramsim3::MemorySystem::new(&ini, &out)
            .map_err(|e| ConfigError::DramSim3Start(format!("{e:?}")))?;
        let channel_mib: u64 = device
            .ini
            .lines()
            .find_map(|l| {
                let (k, v) = l.split_once('=')?;
                (k.trim() == "channel_size").then(|| v.trim().parse().ok())?
            })
            .unwrap_or(4096);
        let epoch_file = dir.0.join("dramsim3epoch.json");
        Ok(Self {
            sys,
            _dir: dir,
            name: device.name,
            f_core: 1000 * u128::from(clock_mhz.max(1)),
            f_dram: u128::from(dram_khz(&device)),
            clocks: 0,
            controller_latency: u64::from(controller_latency),
            line_bytes: u64::from(line_bytes),
            half_capacity: (channel_mib * u64::from(channels)) << 19,
            queued: VecDeque::new(),
            fills: BTreeMap::new(),
            line_of_addr: BTreeMap::new(),
            bytes_last: 0,
            epoch_file,
            epoch_read: 0,
            window: DramDeviceStats::default(),
        })
    }

    /// Cycles added to every fill for the controller.
    pub(super) fn controller_latency(&self) -> u64 {
        self.controller_latency
    }

    /// Whether a fill is in DRAMsim3 (its completion cycle not known yet).
    pub(super) fn busy(&self) -> bool {
        !self.fills.is_empty()
    }

    /// DRAM clocks that start before pipeline cycle `k` starts: `⌈k · f_d / f_c⌉`.
    fn clocks_before(&self, k: u64) -> u64 {
        let n = u128::from(k) * self.f_dram;
        u64::try_from(n.div_ceil(self.f_core)).unwrap_or(u64::MAX)
    }

    /// The first pipeline cycle starting at or after the start of DRAM clock `j`.
    fn cycle_at_clock(&self, j: u64) -> u64 {
        let n = u128::from(j) * self.f_core;
        u64::try_from(n.div_ceil(self.f_dram)).unwrap_or(u64::MAX)
    }

    /// Queues the fill of `line`, issued in cycle `k` (its transactions enter DRAMsim3 at the
    /// end of the cycle).
    pub(super) fn issue(&mut self, line: u64) {
        let first = self.device_addr(line);
        let n = self.line_bytes.div_ceil(BURST_BYTES).max(1);
        for i in 0..n {
            let addr = first + i * BURST_BYTES;
            self.line_of_addr.insert(addr, line);
            self.queued.push_back(addr);
        }
        self.fills.insert(
            line,
            Fill {
                left: n as u32,
                done: 0,
            },
        );
        self.window.fills += 1;
        self.window.transactions += n;
    }

    /// The device byte address of a line's first burst (module documentation).
    fn device_addr(&self, line: u64) -> u64 {
        let byte = line * self.line_bytes;
        let base = super::cache::ATTR_REGION_BASE;
        let (region, offset) = if byte >= base {
            (self.half_capacity, byte - base)
        } else {
            (0, byte)
        };
        let aligned = offset / BURST_BYTES * BURST_BYTES;
        region + aligned % self.half_capacity
    }

    /// Runs every DRAM clock that starts before the end of cycle `k`, and appends to `done`
    /// each fill that completed in them, with its completion cycle.
    pub(super) fn advance(&mut self, k: u64, done: &mut Vec<(u64, u64)>) {
        let until = self.clocks_before(k.saturating_add(1));
        self.bytes_last = 0;
        let mut returned: Vec<u64> = Vec::new();
        while self.clocks < until {
            while let Some(&addr) = self.queued.front() {
                if !self.sys.can_add(addr, false) {
                    self.window.queue_full_clocks += 1;
                    break;
                }
                self.sys.add(addr, false);
                self.queued.pop_front();
            }
            returned.clear();
            self.sys.tick(|addr, _| returned.push(addr));
            let j = self.clocks;
            self.clocks += 1;
            for &addr in &returned {
                self.complete(addr, j, done);
            }
            if self.clocks % EPOCH_DRAM_CLOCKS == 0 {
                self.read_epochs();
            }
        }
    }

    fn complete(&mut self, addr: u64, j: u64, done: &mut Vec<(u64, u64)>) {
        let Some(line) = self.line_of_addr.remove(&addr) else {
            return;
        };
        self.bytes_last += BURST_BYTES;
        self.window.bytes += BURST_BYTES;
        let at = self.cycle_at_clock(j) + self.controller_latency;
        if let Some(f) = self.fills.get_mut(&line) {
            f.left -= 1;
            f.done = f.done.max(at);
            if f.left == 0 {
                let d = f.done;
                self.fills.remove(&line);
                done.push((line, d));
            }
        }
    }

    /// Bytes whose transactions completed during the last [`Self::advance`].
    pub(super) fn bytes_last(&self) -> u64 {
        self.bytes_last
    }

    /// Parses the epoch records DRAMsim3 appended since the last call.
    fn read_epochs(&mut self) {
        let Ok(text) = std::fs::read_to_string(&self.epoch_file) else {
            return;
        };
        let Some(new) = text.get(self.epoch_read..) else {
            return;
        };
        let mut consumed = 0;
        let mut rest = new;
        loop {
            let trimmed = rest.trim_start_matches(['[', ',', '\n', ' ', ']']);
            let skipped = rest.len() - trimmed.len();
            if trimmed.is_empty() {
                consumed += skipped;
                break;
            }
            let mut it =
                serde_json::Deserializer::from_str(trimmed).into_iter::<serde_json::Value>();
            match it.next() {
                Some(Ok(v)) => {
                    self.window.add_epoch(&v);
                    let used = it.byte_offset();
                    consumed += skipped + used;
                    rest = &trimmed[used..];
                }
                // An incomplete record (still being written): read it next time.
                _ => break,
            }
        }
        self.epoch_read += consumed;
    }

    /// The current window's counters.
    pub(super) fn stats(&self) -> DramDeviceStats {
        let mut s = self.window.clone();
        s.device = self.name.to_string();
        s
    }

    /// Starts a new window.
    pub(super) fn reset_stats(&mut self) {
        self.window = DramDeviceStats::default();
    }

    /// The directory DRAMsim3 writes to (for tests).
    #[cfg(test)]
    pub(super) fn dir(&self) -> &std::path::Path {
        &self._dir.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dramsim3_writes_only_into_its_scratch_directory_which_goes_with_it() {
        let cwd_before: Vec<_> = std::fs::read_dir(".")
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        let mut d = DramSim3::new("DDR4_8Gb_x16_2400", 2, 1, 64, 300).unwrap();
        let dir = d.dir().to_path_buf();
        assert!(dir.starts_with(std::env::temp_dir()), "{}", dir.display());
        d.issue(5);
        let mut done = Vec::new();
        // Past one statistics epoch, so DRAMsim3 writes its file.
        d.advance(EPOCH_DRAM_CLOCKS / 4 + 10, &mut done);
        assert_eq!(done.len(), 1);
        assert!(dir.join("dramsim3epoch.json").exists());
        assert_eq!(d.stats().epochs, 2, "one record per channel");
        drop(d);
        assert!(!dir.exists(), "{} left behind", dir.display());
        let cwd_after: Vec<_> = std::fs::read_dir(".")
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(cwd_before, cwd_after);
    }
}
