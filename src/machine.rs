//! What the machine allows a run (read at the edge, by the command line and the Python
//! package: [`install_memory_limit`]): the memory it may
//! take. Linux's `/proc/meminfo` (`MemAvailable`: what can be allocated without swapping) and
//! `/proc/self/limits` ("Max address space": `ulimit -v`); the smaller of the two is the limit.
//! Elsewhere (no `/proc`) there is no limit. And how the allocator hands large arrays back
//! ([`map_large_arrays`], set by the command line for explicit runs).

/// The size from which an allocation is mapped on its own and returned to the system when
/// freed ([`map_large_arrays`]).
pub const MAPPED_FROM: usize = 1 << 20;

/// Makes glibc map every allocation of [`MAPPED_FROM`] bytes or more on its own and unmap it
/// when freed (`mallopt(M_MMAP_THRESHOLD)`, which also stops glibc raising that threshold as
/// large blocks are freed). Without it, the freed set-up arrays and each refactorised contact
/// layer stay in the heap, fragmented: the 69³ cube's explicit run with mod3 (200 steps, the face
/// lands and lifts off) peaks at 249.8 MiB without it, 227.5 MiB with it (issue 31;
/// `tests/lean_run.rs`). Called by the command line before an explicit run's set-up (an
/// edge: the Python package leaves its host's allocator alone). Not for the implicit schemes:
/// the 200² plate's Crank–Nicolson run took 1.03× the time with it (its set-up's arrays mapped
/// afresh). Returns whether the setting took (false off glibc).
pub fn map_large_arrays() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: mallopt only sets an allocator parameter, under glibc's arena lock (other
        // threads may allocate meanwhile).
        unsafe { libc::mallopt(libc::M_MMAP_THRESHOLD, MAPPED_FROM as libc::c_int) == 1 }
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        false
    }
}

/// The memory this process may allocate, in bytes, and where the limit comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryLimit {
    pub bytes: u64,
    pub source: &'static str,
}

/// The smaller of the available memory and the address-space limit (None if neither is known).
pub fn memory_limit() -> Option<MemoryLimit> {
    let available = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| mem_available(&t));
    let address_space = std::fs::read_to_string("/proc/self/limits").ok().and_then(|t| address_space(&t));
    match (available, address_space) {
        (Some(a), Some(v)) if v < a => Some(MemoryLimit { bytes: v, source: "ulimit -v" }),
        (Some(a), _) => Some(MemoryLimit { bytes: a, source: "MemAvailable" }),
        (None, Some(v)) => Some(MemoryLimit { bytes: v, source: "ulimit -v" }),
        (None, None) => None,
    }
}

/// Sets the solver's memory limit from the machine, for the command line and the Python
/// package: a factor may take what is left of 15/16 of [`memory_limit`] (1/16 for what follows
/// it: the solves' work vectors, the observers), measured by [`memory_in_use`] when it is
/// allocated (`crate::linalg::memory_left`). Returns the limit read, if any.
pub fn install_memory_limit() -> Option<MemoryLimit> {
    let limit = memory_limit()?;
    crate::linalg::set_memory_limit(limit.bytes / 16 * 15);
    crate::linalg::set_memory_in_use(memory_in_use(&limit));
    Some(limit)
}

/// What the process holds now, as `limit` counts it: its address space (`VmSize`) under
/// `ulimit -v`, its resident memory (`VmRSS`) against the available memory, read from
/// `/proc/self/status` (0 where it cannot be read). [`crate::linalg::set_memory_in_use`] takes
/// the function this returns.
pub fn memory_in_use(limit: &MemoryLimit) -> fn() -> u64 {
    fn field(name: &str) -> u64 {
        std::fs::read_to_string("/proc/self/status").ok().and_then(|t| status_kb(&t, name)).unwrap_or(0)
    }
    if limit.source == "ulimit -v" { || field("VmSize:") } else { || field("VmRSS:") }
}

/// The value of a `Name:   1234 kB` line of `/proc/self/status`, in bytes.
fn status_kb(status: &str, name: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with(name))?;
    let kb: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// `MemAvailable:   23558996 kB` in bytes.
fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// The soft limit of "Max address space" in bytes (None when unlimited).
fn address_space(limits: &str) -> Option<u64> {
    let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..].split_whitespace().next()?.parse().ok()
}

#[cfg(test)]
mod tests {
    #[test]
    fn reads_the_two_limits() {
        let meminfo = "MemTotal:       24000000 kB\nMemAvailable:   23558996 kB\n";
        assert_eq!(super::mem_available(meminfo), Some(23558996 * 1024));
        let unlimited = "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(super::address_space(unlimited), None);
        let limited = "Max address space         2048000000           unlimited            bytes\n";
        assert_eq!(super::address_space(limited), Some(2048000000));
        let status = "Name:\tmassredist\nVmPeak:\t  20000 kB\nVmSize:\t   12000 kB\nVmRSS:\t    3000 kB\n";
        assert_eq!(super::status_kb(status, "VmSize:"), Some(12000 * 1024));
        assert_eq!(super::status_kb(status, "VmRSS:"), Some(3000 * 1024));
    }
}
