//! How much memory this process may still take, so that a size read from a file or a scene can be
//! refused before it is allocated rather than abort the process when the allocation fails.

/// The bytes this process can still allocate, as far as Linux tells: the least of the memory
/// available (`MemAvailable` in `/proc/meminfo`), the control group's limit less its use, and the
/// address-space limit (`ulimit -v`). `None` where none of them can be read.
pub fn available() -> Option<u64> {
    [meminfo(), cgroup(), address_space()]
        .into_iter()
        .flatten()
        .min()
}

fn meminfo() -> Option<u64> {
    let m = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kb = m
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse::<u64>()
        .ok()?;
    Some(kb * 1024)
}

fn cgroup() -> Option<u64> {
    let read = |f: &str| -> Option<u64> {
        std::fs::read_to_string(format!("/sys/fs/cgroup/{f}"))
            .ok()?
            .trim()
            .parse()
            .ok()
    };
    // `max` (no limit) does not parse: then there is nothing to say.
    let limit = read("memory.max")?;
    Some(limit.saturating_sub(read("memory.current").unwrap_or(0)))
}

/// The soft address-space limit less the address space in use (`VmSize`): a process over it
/// gets no more memory, whatever the machine has.
fn address_space() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let soft = limits
        .lines()
        .find_map(|l| l.strip_prefix("Max address space"))?
        .split_whitespace()
        .next()?
        .parse::<u64>()
        .ok()?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let used_kb = status
        .lines()
        .find_map(|l| l.strip_prefix("VmSize:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .unwrap_or(0);
    Some(soft.saturating_sub(used_kb * 1024))
}

#[cfg(test)]
mod tests {
    #[test]
    fn some_memory_is_available_and_less_than_the_machine_has() {
        let a = super::available().expect("Linux reports memory");
        let total_kb: u64 = std::fs::read_to_string("/proc/meminfo")
            .unwrap()
            .lines()
            .find_map(|l| l.strip_prefix("MemTotal:"))
            .unwrap()
            .trim()
            .trim_end_matches("kB")
            .trim()
            .parse()
            .unwrap();
        assert!(a > 0 && a <= total_kb * 1024, "{a} of {total_kb} kB");
    }
}
