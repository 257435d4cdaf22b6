//! How much memory this process may still use: the least of what the machine has available,
//! what its memory cgroup leaves (every level of the hierarchy, v2 or v1), and what its
//! address-space and data-segment limits (`ulimit -v`, `ulimit -d`) leave. A run planned
//! within the least of them is refused before it starts instead of aborting in an allocation.

use std::path::{Path, PathBuf};

/// Address space each worker thread reserves beyond what the process has mapped when it is
/// asked: its stack (2 MiB) and a malloc arena (glibc reserves 64 MiB of address space per
/// arena). Counted against `ulimit -v`, which counts reservations, not use.
const ADDRESS_SPACE_PER_THREAD: u64 = 66 << 20;

/// The tightest limit for a process of `threads` worker threads and what it is, in words (`the
/// memory cgroup leaves`, `the address-space limit (ulimit -v) leaves`, …); `None` where none
/// can be read.
pub fn tightest(threads: u64) -> Option<(u64, &'static str)> {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let limits = [
        (meminfo_available(), "available"),
        (cgroup_headroom(), "the memory cgroup leaves"),
        (
            rlimit_headroom(Rlimit::AddressSpace, &status, "VmSize:", threads),
            "the address-space limit (ulimit -v) leaves",
        ),
        (
            rlimit_headroom(Rlimit::Data, &status, "VmData:", threads),
            "the data-segment limit (ulimit -d) leaves",
        ),
    ];
    limits
        .into_iter()
        .filter_map(|(bytes, what)| bytes.map(|b| (b, what)))
        .min_by_key(|&(b, _)| b)
}

/// Linux's `MemAvailable`.
fn meminfo_available() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/meminfo").ok()?;
    status_kib(&s, "MemAvailable:").map(|kib| kib.saturating_mul(1024))
}

/// A `Key:   1234 kB` line of `/proc/meminfo` or `/proc/self/status`, in KiB.
fn status_kib(text: &str, key: &str) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
}

/// What the memory cgroups of this process leave: at every level from its own cgroup up to
/// the root, the limit minus the usage; the least of them.
fn cgroup_headroom() -> Option<u64> {
    let own = std::fs::read_to_string("/proc/self/cgroup").unwrap_or_default();
    cgroup_dirs(&own, Path::new("/sys/fs/cgroup"))
        .into_iter()
        .filter_map(|(dir, files)| {
            let read = |f: &str| -> Option<u64> {
                std::fs::read_to_string(dir.join(f))
                    .ok()
                    .and_then(|s| s.trim().parse::<u64>().ok())
            };
            // "max" (v2) parses as no limit; v1 reports none as a huge number, harmless.
            Some(read(files.0)?.saturating_sub(read(files.1)?))
        })
        .min()
}

/// The directories holding this process's memory-cgroup limits, from its own cgroup up to the
/// root of the hierarchy under `root`, with the files of the limit and the usage. `own` is
/// `/proc/self/cgroup`: `0::/path` for cgroup v2, `N:…memory…:/path` for v1.
pub(super) fn cgroup_dirs(own: &str, root: &Path) -> Vec<(PathBuf, (&'static str, &'static str))> {
    const V2: (&str, &str) = ("memory.max", "memory.current");
    const V1: (&str, &str) = ("memory.limit_in_bytes", "memory.usage_in_bytes");
    let mut out = Vec::new();
    let mut climb = |base: PathBuf, rel: &str, files| {
        let mut dir = base.join(rel.trim_start_matches('/'));
        loop {
            out.push((dir.clone(), files));
            if dir == base || !dir.pop() {
                break;
            }
        }
    };
    for line in own.lines() {
        let mut parts = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(rel)) = (parts.next(), parts.next(), parts.next())
        else {
            continue;
        };
        if id == "0" && controllers.is_empty() {
            climb(root.to_path_buf(), rel, V2);
        } else if controllers.split(',').any(|c| c == "memory") {
            climb(root.join("memory"), rel, V1);
        }
    }
    if out.is_empty() {
        // No /proc/self/cgroup (or no memory line): the root's files, where a container
        // shows its own limits.
        out.push((root.to_path_buf(), V2));
        out.push((root.join("memory"), V1));
    }
    out
}

/// The resource limits that count memory.
#[derive(Clone, Copy)]
enum Rlimit {
    AddressSpace,
    Data,
}

/// What the soft limit `which` leaves beyond the process's current size (`key` of
/// `/proc/self/status`) and the reservations of `threads` worker threads; `None` without a
/// limit.
fn rlimit_headroom(which: Rlimit, status: &str, key: &str, threads: u64) -> Option<u64> {
    let limit = soft_limit(which)?;
    let used = status_kib(status, key).unwrap_or(0).saturating_mul(1024);
    Some(
        limit
            .saturating_sub(used)
            .saturating_sub(threads.saturating_mul(ADDRESS_SPACE_PER_THREAD)),
    )
}

#[cfg(unix)]
fn soft_limit(which: Rlimit) -> Option<u64> {
    let resource = match which {
        Rlimit::AddressSpace => libc::RLIMIT_AS,
        Rlimit::Data => libc::RLIMIT_DATA,
    };
    let mut r = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes one rlimit to the valid, exclusively borrowed `r`.
    if unsafe { libc::getrlimit(resource, &mut r) } != 0 || r.rlim_cur == libc::RLIM_INFINITY {
        return None;
    }
    #[allow(clippy::unnecessary_cast)] // rlim_t differs between platforms
    Some(r.rlim_cur as u64)
}

#[cfg(not(unix))]
fn soft_limit(_which: Rlimit) -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cgroup_limits_are_read_at_every_level_of_the_process_hierarchy() {
        let root = Path::new("/cg");
        let v2 = cgroup_dirs("0::/user.slice/run-1.scope\n", root);
        let dirs: Vec<_> = v2.iter().map(|(d, _)| d.to_str().unwrap()).collect();
        assert_eq!(
            dirs,
            ["/cg/user.slice/run-1.scope", "/cg/user.slice", "/cg"]
        );
        assert!(v2.iter().all(|(_, f)| f.0 == "memory.max"));
        let v1 = cgroup_dirs("4:cpu,cpuacct:/x\n9:memory:/docker/abc\n", root);
        let dirs: Vec<_> = v1.iter().map(|(d, _)| d.to_str().unwrap()).collect();
        assert_eq!(
            dirs,
            ["/cg/memory/docker/abc", "/cg/memory/docker", "/cg/memory"]
        );
        assert!(v1.iter().all(|(_, f)| f.0 == "memory.limit_in_bytes"));
        assert_eq!(cgroup_dirs("0::/\n", root).len(), 1);
        assert_eq!(cgroup_dirs("", root).len(), 2);
    }

    #[test]
    fn status_lines_read_in_kib() {
        let s = "Name:\tsph\nVmSize:\t  123456 kB\nVmData:\t 42 kB\n";
        assert_eq!(status_kib(s, "VmSize:"), Some(123456));
        assert_eq!(status_kib(s, "VmData:"), Some(42));
        assert_eq!(status_kib(s, "VmRSS:"), None);
    }
}
