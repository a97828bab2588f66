//! How much memory a process may still allocate, so that an application can refuse an image
//! too large for it with a message instead of being aborted by a failed allocation.
//!
//! Linux only (read from `/proc` and `/sys`); elsewhere nothing is known and [`available`]
//! gives `None`.

use std::path::Path;

/// Bytes the process can still allocate, as far as the system says: the least of the free
/// memory (`MemAvailable` plus free swap), the room under the address-space and data-size
/// limits (`ulimit -v`, `ulimit -d`, less what the process already maps), and the room under
/// its control group's memory limit. `None` when none of these can be read.
#[must_use]
pub fn available() -> Option<u64> {
    [free_memory(), rlimit_room(), cgroup_room()]
        .into_iter()
        .flatten()
        .min()
}

/// Fixed room kept beside an image for everything else (encoder rows and blocks, thread
/// stacks, the window system's copy).
pub const SLACK_BYTES: u64 = 64 << 20;

/// Bytes an image of `width` x `height` at `bytes_per_pixel` needs, with [`SLACK_BYTES`].
#[must_use]
pub fn image_bytes(width: u32, height: u32, bytes_per_pixel: u64) -> u64 {
    u64::from(width) * u64::from(height) * bytes_per_pixel + SLACK_BYTES
}

/// Refuses, before it is allocated, an image of `width` x `height` at `bytes_per_pixel` that
/// would not fit in the memory left ([`available`]): `FIELD: WxH needs N GB of memory, M GB
/// available`, where `field` names what set the size. Where nothing is known of the memory
/// left, nothing is refused.
///
/// # Errors
/// The message above.
pub fn check_image(
    field: &str,
    (width, height): (u32, u32),
    bytes_per_pixel: u64,
) -> Result<(), String> {
    let need = image_bytes(width, height, bytes_per_pixel);
    match available() {
        Some(left) if left < need => Err(format!(
            "{field}: {width}x{height} needs {} of memory, {} available",
            human(need),
            human(left)
        )),
        _ => Ok(()),
    }
}

/// A byte count as people read it: `6.4 GB`, `512 MB`, `900 kB` (powers of 1000).
#[must_use]
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.0} MB", b / 1e6)
    } else {
        format!("{:.0} kB", (b / 1e3).ceil())
    }
}

fn read(path: impl AsRef<Path>) -> Option<String> {
    std::fs::read_to_string(path).ok()
}

/// The value in kB of `key:` in a `/proc` file of `key: value kB` lines, in bytes.
fn kb_field(text: &str, key: &str) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(':'))
        .and_then(|v| v.split_whitespace().next()?.parse::<u64>().ok())
        .map(|kb| kb * 1024)
}

fn free_memory() -> Option<u64> {
    let info = read("/proc/meminfo")?;
    let available = kb_field(&info, "MemAvailable")?;
    Some(available + kb_field(&info, "SwapFree").unwrap_or(0))
}

/// The soft limit of `name` in `/proc/self/limits`, if not unlimited.
fn soft_limit(limits: &str, name: &str) -> Option<u64> {
    let line = limits.lines().find(|l| l.starts_with(name))?;
    line[name.len()..].split_whitespace().next()?.parse().ok()
}

fn rlimit_room() -> Option<u64> {
    let limits = read("/proc/self/limits")?;
    let status = read("/proc/self/status")?;
    let room = |limit: &str, used: &str| {
        let limit = soft_limit(&limits, limit)?;
        Some(limit.saturating_sub(kb_field(&status, used).unwrap_or(0)))
    };
    [
        room("Max address space", "VmSize"),
        room("Max data size", "VmData"),
    ]
    .into_iter()
    .flatten()
    .min()
}

/// Room under the control group's limit (cgroup v2, else v1); reclaimable file cache counts
/// as room.
fn cgroup_room() -> Option<u64> {
    let cgroups = read("/proc/self/cgroup")?;
    let v2 = cgroups.lines().find_map(|l| l.strip_prefix("0::"));
    if let Some(dir) = v2 {
        let base = Path::new("/sys/fs/cgroup").join(dir.trim_start_matches('/'));
        for dir in [base.as_path(), Path::new("/sys/fs/cgroup")] {
            let limit = read(dir.join("memory.max")).and_then(|t| t.trim().parse::<u64>().ok());
            let used = read(dir.join("memory.current")).and_then(|t| t.trim().parse::<u64>().ok());
            if let (Some(limit), Some(used)) = (limit, used) {
                let cache = stat_field(&read(dir.join("memory.stat"))?, "inactive_file");
                return Some(limit.saturating_sub(used.saturating_sub(cache)));
            }
        }
    }
    let dir = Path::new("/sys/fs/cgroup/memory");
    let limit: u64 = read(dir.join("memory.limit_in_bytes"))?
        .trim()
        .parse()
        .ok()?;
    if limit >= 1 << 60 {
        return None; // v1's "no limit"
    }
    let used: u64 = read(dir.join("memory.usage_in_bytes"))?
        .trim()
        .parse()
        .ok()?;
    let cache = stat_field(&read(dir.join("memory.stat"))?, "total_inactive_file");
    Some(limit.saturating_sub(used.saturating_sub(cache)))
}

/// The value of `key` in a cgroup `memory.stat` (`key value` lines), 0 if absent.
fn stat_field(stat: &str, key: &str) -> u64 {
    stat.lines()
        .find_map(|l| {
            let (k, v) = l.split_once(' ')?;
            (k == key).then(|| v.trim().parse().ok())?
        })
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proc_fields_are_read_in_bytes() {
        let info = "MemTotal:       24683656 kB\nMemAvailable:   1000 kB\nSwapFree: 0 kB\n";
        assert_eq!(kb_field(info, "MemAvailable"), Some(1_024_000));
        assert_eq!(kb_field(info, "MemTotal"), Some(24_683_656 * 1024));
        assert_eq!(kb_field(info, "Missing"), None);
        let limits = "Limit  Soft Limit  Hard Limit  Units\nMax data size             unlimited            unlimited            bytes\nMax address space         3000000000           unlimited            bytes\n";
        assert_eq!(soft_limit(limits, "Max address space"), Some(3_000_000_000));
        assert_eq!(soft_limit(limits, "Max data size"), None);
        assert_eq!(stat_field("cache 5\ninactive_file 7\n", "inactive_file"), 7);
    }

    #[test]
    fn a_16k_framebuffer_needs_more_than_4_gb() {
        let need = image_bytes(16_384, 16_384, 16);
        assert!(need > 4 << 30, "{need}");
        assert_eq!(human(need), "4.4 GB");
        assert!(check_image("--size", (4, 4), 16).is_ok());
    }

    #[test]
    fn byte_counts_read_as_people_write_them() {
        assert_eq!(human(6_442_450_944), "6.4 GB");
        assert_eq!(human(512_000_000), "512 MB");
        assert_eq!(human(1), "1 kB");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn this_machine_reports_some_memory() {
        assert!(available().is_some_and(|b| b > 0));
    }
}
