//! What the machine allows a run (read at the edge, by the command line): the memory it may
//! take. Linux's `/proc/meminfo` (`MemAvailable`: what can be allocated without swapping) and
//! `/proc/self/limits` ("Max address space": `ulimit -v`); the smaller of the two is the limit.
//! Elsewhere (no `/proc`) there is no limit.

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
    }
}
