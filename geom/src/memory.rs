//! How much memory this process may still take, so that a size read from a file or a scene can be
//! refused before it is allocated rather than abort the process when the allocation fails.

/// The bytes this process can still allocate, as far as Linux tells: the least of the memory
/// available (`MemAvailable` in `/proc/meminfo`), the control group's limit less its use, and the
/// address-space limit (`ulimit -v`). `None` where none of them can be read.
pub fn available_memory() -> Option<u64> {
    [meminfo(), cgroup(), address_space()]
        .into_iter()
        .flatten()
        .min()
}

/// The value of a `Key: N kB` line of a `/proc` file, in bytes.
fn kb_line(text: &str, key: &str) -> Option<u64> {
    let kb = text
        .lines()
        .find_map(|l| l.strip_prefix(key))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse::<u64>()
        .ok()?;
    Some(kb * 1024)
}

fn meminfo() -> Option<u64> {
    kb_line(
        &std::fs::read_to_string("/proc/meminfo").ok()?,
        "MemAvailable:",
    )
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
    let used = kb_line(&status, "VmSize:").unwrap_or(0);
    Some(soft.saturating_sub(used))
}

#[cfg(test)]
mod tests {
    #[test]
    fn some_memory_is_available_and_less_than_the_machine_has() {
        let a = super::available_memory().expect("Linux reports memory");
        let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap();
        let total = super::kb_line(&meminfo, "MemTotal:").unwrap();
        assert!(a > 0 && a <= total, "{a} of {total} bytes");
    }
}
