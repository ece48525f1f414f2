//! The memory a run needs, estimated before its per-pixel buffers are allocated, against the
//! memory the machine has: a run that cannot fit is refused with both figures instead of
//! aborting in an allocation (a 16384×4096 reference run on a 4 GB machine used to abort with
//! an allocation backtrace at 3.7 GB).
//!
//! Pipeline position: in `run::frames::run`, before the assets are built and again after
//! (when the memory they took is no longer available), and always before the first output is
//! created. The estimate is a fixed part (program, tables, one frame's worker state) plus
//! bytes per pixel per model, measured as the slope of peak RSS against pixels (`/usr/bin/time
//! -f %M`, the embedded car, 2 frames, 2 threads; docs/cycle-model.md "Memory of a run") and
//! rounded up: every buffer of a run is per pixel (hit buffers, the frame's records, the
//! images and their PNG encoding, the cycle model's BRAM and row traces); the hit dump and the
//! report are written frame by frame.
//!
//! The available figure is the smallest of what the machine and the process's own limits
//! leave: `MemAvailable` of `/proc/meminfo`; the cgroup's `memory.max` less its
//! `memory.current` (a container's limit, which `MemAvailable` does not see); and the soft
//! address-space limit (`ulimit -v`, "Max address space" in `/proc/self/limits`) less the
//! process's `VmSize` — the limit under which an allocation fails first. A source that is
//! missing or unlimited is passed over; with none the check is skipped. The environment
//! variable `SVO_SIM_MEM_AVAILABLE_MIB` replaces them all (tests use it to make the refusal
//! deterministic).

use super::Model;
use thiserror::Error;

/// The fixed part of the estimate: the program, its tables and the worker threads' state
/// (peak RSS of a 128×128 run is 71 MiB).
pub const BASE_BYTES: u64 = 128 << 20;

/// Environment variable that overrides the available memory, in MiB.
pub const AVAILABLE_ENV: &str = "SVO_SIM_MEM_AVAILABLE_MIB";

/// Bytes per pixel of a run with `model` (measured slopes: reference 100, fixed 201, cycle
/// 422 bytes per pixel; rounded up).
pub fn bytes_per_pixel(model: Model) -> u64 {
    match model {
        Model::Reference => 112,
        Model::Fixed => 224,
        Model::Cycle => 480,
    }
}

/// The estimate of a `width`×`height` run with `model`, bytes.
pub fn estimate_bytes(model: Model, width: u32, height: u32) -> u64 {
    let pixels = u64::from(width) * u64::from(height);
    BASE_BYTES.saturating_add(pixels.saturating_mul(bytes_per_pixel(model)))
}

/// A run that does not fit.
#[derive(Debug, Error)]
#[error(
    "a {width}×{height} run of the {model} model needs about {} (estimate: {} fixed, plus \
     {per_pixel} bytes per pixel) but only {} is available ({source_name}); choose a smaller \
     resolution",
    mib(*needed),
    mib(BASE_BYTES),
    mib(*available)
)]
pub struct MemoryError {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The model's name.
    pub model: &'static str,
    /// Bytes per pixel of the estimate.
    pub per_pixel: u64,
    /// The estimate, bytes.
    pub needed: u64,
    /// The available memory, bytes.
    pub available: u64,
    /// Where the available figure comes from.
    pub source_name: String,
}

fn mib(bytes: u64) -> String {
    format!("{} MiB", bytes.div_ceil(1 << 20))
}

/// Bad value of [`AVAILABLE_ENV`].
#[derive(Debug, Error)]
#[error("{AVAILABLE_ENV}={0:?} is not a whole number of MiB")]
pub struct AvailableEnvError(String);

/// The available memory in bytes and where the figure comes from: [`AVAILABLE_ENV`] if set,
/// else the smallest of [`machine_sources`], else `None` (the check is skipped).
pub fn available_bytes() -> Result<Option<(u64, String)>, AvailableEnvError> {
    if let Ok(v) = std::env::var(AVAILABLE_ENV) {
        let mib: u64 = v.trim().parse().map_err(|_| AvailableEnvError(v.clone()))?;
        return Ok(Some((
            mib.saturating_mul(1 << 20),
            format!("{AVAILABLE_ENV}={mib}"),
        )));
    }
    Ok(machine_sources().into_iter().min_by_key(|(b, _)| *b))
}

/// What each limit this process runs under leaves, bytes, with the limit's name: the
/// machine's `MemAvailable`, the cgroup (v2) limit less its use, and the address-space limit
/// less the process's virtual size. Missing or unlimited sources are left out.
pub fn machine_sources() -> Vec<(u64, String)> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let mut out = Vec::new();
    if let Some(b) = read("/proc/meminfo").and_then(|t| mem_available(&t)) {
        out.push((b, "MemAvailable in /proc/meminfo".to_string()));
    }
    if let (Some(max), Some(cur)) = (
        read("/sys/fs/cgroup/memory.max"),
        read("/sys/fs/cgroup/memory.current"),
    ) {
        if let Some(b) = cgroup_left(&max, &cur) {
            out.push((b, "the cgroup's memory.max less memory.current".to_string()));
        }
    }
    if let (Some(limits), Some(status)) = (read("/proc/self/limits"), read("/proc/self/status")) {
        if let Some(b) = address_space_left(&limits, &status) {
            out.push((
                b,
                "the address-space limit (ulimit -v) less this process's VmSize".to_string(),
            ));
        }
    }
    out
}

/// `MemAvailable` of a `/proc/meminfo` text, bytes.
pub fn mem_available(meminfo: &str) -> Option<u64> {
    kb_field(meminfo, "MemAvailable:")
}

/// A `NAME: N kB` field of a `/proc` text, bytes.
fn kb_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find_map(|l| l.strip_prefix(name))?;
    let kb: u64 = line.trim().strip_suffix("kB")?.trim().parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// What a cgroup v2 limit leaves: `memory.max` (a byte count, or `max` for none) less
/// `memory.current`; `None` when unlimited or unreadable.
pub fn cgroup_left(max: &str, current: &str) -> Option<u64> {
    let max: u64 = max.trim().parse().ok()?;
    let current: u64 = current.trim().parse().ok()?;
    Some(max.saturating_sub(current))
}

/// What the soft address-space limit leaves: the "Max address space" line of
/// `/proc/self/limits` (bytes, or `unlimited`) less `VmSize` of `/proc/self/status`; `None`
/// when unlimited or unreadable.
pub fn address_space_left(limits: &str, status: &str) -> Option<u64> {
    let soft = limits
        .lines()
        .find_map(|l| l.strip_prefix("Max address space"))?
        .split_whitespace()
        .next()?;
    let soft: u64 = soft.parse().ok()?;
    let size = kb_field(status, "VmSize:")?;
    Some(soft.saturating_sub(size))
}

/// Refuses a run whose estimate exceeds `available` (bytes, with its source's name).
pub fn check_with(
    model: Model,
    width: u32,
    height: u32,
    available: Option<(u64, String)>,
) -> Result<(), MemoryError> {
    let Some((available, source_name)) = available else {
        return Ok(());
    };
    let needed = estimate_bytes(model, width, height);
    if needed <= available {
        return Ok(());
    }
    Err(MemoryError {
        width,
        height,
        model: match model {
            Model::Reference => "reference",
            Model::Fixed => "fixed",
            Model::Cycle => "cycle",
        },
        per_pixel: bytes_per_pixel(model),
        needed,
        available,
        source_name,
    })
}

/// [`check_with`] the machine's available memory ([`available_bytes`]).
pub fn check(model: Model, width: u32, height: u32) -> anyhow::Result<()> {
    Ok(check_with(model, width, height, available_bytes()?)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_available_is_read_from_meminfo() {
        let text = "MemTotal:       24684084 kB\nMemFree: 1 kB\nMemAvailable:   23241464 kB\n";
        assert_eq!(mem_available(text), Some(23_241_464 * 1024));
        assert_eq!(mem_available("MemTotal: 5 kB\n"), None);
    }

    #[test]
    fn cgroup_and_address_space_limits_are_read() {
        assert_eq!(cgroup_left("4294967296\n", "1073741824\n"), Some(3 << 30));
        assert_eq!(cgroup_left("max\n", "1073741824\n"), None);
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \n\
                      Max address space         4096000000           unlimited            bytes     \n";
        let status = "Name:\tsim\nVmPeak:\t  200000 kB\nVmSize:\t  100000 kB\n";
        assert_eq!(
            address_space_left(limits, status),
            Some(4_096_000_000 - 102_400_000)
        );
        let unlimited =
            "Max address space         unlimited            unlimited            bytes     \n";
        assert_eq!(address_space_left(unlimited, status), None);
    }

    #[test]
    fn a_run_above_the_available_memory_is_refused_with_both_figures() {
        let e = check_with(
            Model::Reference,
            16384,
            4096,
            Some((4 << 30, "test".into())),
        )
        .expect_err("7.3 GiB against 4 GiB");
        assert_eq!(
            e.to_string(),
            "a 16384×4096 run of the reference model needs about 7296 MiB (estimate: 128 MiB \
             fixed, plus 112 bytes per pixel) but only 4096 MiB is available (test); choose a \
             smaller resolution"
        );
        assert!(check_with(Model::Reference, 640, 384, Some((4 << 30, "t".into()))).is_ok());
        assert!(check_with(Model::Cycle, 16384, 16384, None).is_ok());
    }
}
