//! Peak resident memory of this process.

/// Peak resident set size of this process in MiB (1 MiB = 1024 KiB), from the `VmHWM` line of
/// `/proc/self/status` (given there in kB, which Linux means as KiB).
///
/// Returns 0.0 where that file or line is unavailable (non-Linux systems, restricted `/proc`).
pub fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|status| parse_vm_hwm_kib(&status))
        .map_or(0.0, |kib| kib as f64 / 1024.0)
}

/// The `VmHWM` value in KiB from the text of a `/proc/<pid>/status` file.
fn parse_vm_hwm_kib(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let mut words = line["VmHWM:".len()..].split_whitespace();
    let value = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") | None => Some(value),
        Some(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::parse_vm_hwm_kib;

    #[test]
    fn parses_the_vm_hwm_line() {
        let status = "Name:\tcleave\nVmPeak:\t  20000 kB\nVmHWM:\t    5120 kB\nVmRSS:\t 4000 kB\n";
        assert_eq!(parse_vm_hwm_kib(status), Some(5120));
        assert_eq!(parse_vm_hwm_kib("Name:\tx\n"), None);
        assert_eq!(parse_vm_hwm_kib("VmHWM:\t12 MB\n"), None);
    }
}
