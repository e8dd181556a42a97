//! How much memory the operating system lets this process use: Linux's `MemAvailable`
//! (`/proc/meminfo`: what can be allocated without swapping, counting reclaimable caches),
//! lowered to the room left under the tightest memory limit of the process's control group,
//! as Slurm, systemd and containers set them:
//!
//! - cgroup v2: `memory.max` minus `memory.current` in the process's cgroup (the `0::PATH`
//!   line of `/proc/self/cgroup`, under `/sys/fs/cgroup`) and in each of its ancestors (Slurm
//!   limits the job's cgroup, `job_N`, above the task's); `max` means no limit.
//! - cgroup v1: `memory.limit_in_bytes` minus `memory.usage_in_bytes` the same way, in the
//!   memory hierarchy (the `N:memory:PATH` line, under `/sys/fs/cgroup/memory`); a value of
//!   1 EiB or more (the kernel writes 9223372036854771712) means no limit.
//!
//! A cgroup path that is not visible (a container that mounts its own cgroup as the root) is
//! covered by the root's files, which are then the container's. Missing or unreadable files
//! are skipped; `None` where nothing is known (not Linux).

use std::path::{Path, PathBuf};

/// cgroup v1 limits at or above this, bytes (1 EiB), mean "no limit".
const UNLIMITED_V1: u64 = 1 << 60;

/// Where the cgroup v2 hierarchy is mounted.
const V2_ROOT: &str = "/sys/fs/cgroup";

/// Where the cgroup v1 memory hierarchy is mounted.
const V1_MEMORY_ROOT: &str = "/sys/fs/cgroup/memory";

/// A cgroup version's file names: (limit, usage).
const V2_FILES: (&str, &str) = ("memory.max", "memory.current");
/// See [`V2_FILES`].
const V1_FILES: (&str, &str) = ("memory.limit_in_bytes", "memory.usage_in_bytes");

/// The memory this process may allocate now, bytes (see the module docs), or `None` where the
/// system says nothing. Cost: reads a few small `/proc` and `/sys` files.
pub fn available_bytes() -> Option<u64> {
    available_with(&|p| std::fs::read_to_string(p).ok())
}

/// [`available_memory`](crate::budget::available_memory) with the files read by `read` (a
/// path's whole text, `None` if it cannot be read), so fixtures can stand in for `/proc` and
/// `/sys`.
pub fn available_with(read: &dyn Fn(&Path) -> Option<String>) -> Option<u64> {
    let meminfo = read(Path::new("/proc/meminfo")).and_then(|t| parse_meminfo(&t));
    let cgroup = read(Path::new("/proc/self/cgroup")).and_then(|t| cgroup_room(&t, read));
    match (meminfo, cgroup) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// `MemAvailable` of a `/proc/meminfo` text, bytes (the file gives kB, i.e. KiB).
pub fn parse_meminfo(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut words = line["MemAvailable:".len()..].split_whitespace();
    let value: u64 = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") => value.checked_mul(1024),
        None => Some(value),
        Some(_) => None,
    }
}

/// The process's cgroup paths in a `/proc/self/cgroup` text: (v2 path of the `0::PATH` line,
/// v1 path of the line whose controllers include `memory`).
pub fn cgroup_paths(text: &str) -> (Option<&str>, Option<&str>) {
    let (mut v2, mut v1) = (None, None);
    for line in text.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        if id == "0" && controllers.is_empty() {
            v2 = Some(path);
        } else if controllers.split(',').any(|c| c == "memory") {
            v1 = Some(path);
        }
    }
    (v2, v1)
}

/// A cgroup limit file's value, bytes: `None` for `max`, a v1 value meaning no limit (1 EiB or
/// more), or text that is not a number.
pub fn parse_limit(text: &str) -> Option<u64> {
    let t = text.trim();
    if t == "max" {
        return None;
    }
    t.parse::<u64>().ok().filter(|&v| v < UNLIMITED_V1)
}

/// The least room (limit minus usage, bytes) under the limits of the process's cgroups and
/// their ancestors, both versions; `None` if none is limited.
fn cgroup_room(proc_cgroup: &str, read: &dyn Fn(&Path) -> Option<String>) -> Option<u64> {
    let (v2, v1) = cgroup_paths(proc_cgroup);
    let levels = [(V2_ROOT, v2, V2_FILES), (V1_MEMORY_ROOT, v1, V1_FILES)];
    let mut room: Option<u64> = None;
    for (root, path, (limit_file, usage_file)) in levels {
        let Some(path) = path else { continue };
        for dir in ancestors(Path::new(root), path) {
            let Some(limit) = read(&dir.join(limit_file)).and_then(|t| parse_limit(&t)) else {
                continue;
            };
            let used = read(&dir.join(usage_file))
                .and_then(|t| t.trim().parse::<u64>().ok())
                .unwrap_or(0);
            let left = limit.saturating_sub(used);
            room = Some(room.map_or(left, |r| r.min(left)));
        }
    }
    room
}

/// `root/path` and each of its ancestors up to `root` itself.
fn ancestors(root: &Path, path: &str) -> Vec<PathBuf> {
    let parts: Vec<&str> = path.split('/').filter(|p| !p.is_empty()).collect();
    (0..=parts.len())
        .rev()
        .map(|k| parts[..k].iter().fold(root.to_path_buf(), |d, p| d.join(p)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// The files of a machine as fixture text.
    fn machine(files: &[(&str, &str)]) -> impl Fn(&Path) -> Option<String> + use<> {
        let map: HashMap<PathBuf, String> = files
            .iter()
            .map(|(p, t)| (PathBuf::from(p), t.to_string()))
            .collect();
        move |p: &Path| map.get(p).cloned()
    }

    const MEMINFO_16G: &str = "MemTotal: 32000000 kB\nMemAvailable:   16777216 kB\n";
    const SLURM_V2: &str = "0::/system.slice/slurmstepd.scope/job_42/step_0/user/task_0\n";
    const JOB_V2: &str = "/sys/fs/cgroup/system.slice/slurmstepd.scope/job_42";

    #[test]
    fn parsing() {
        assert_eq!(parse_meminfo(MEMINFO_16G), Some(16 << 30));
        assert_eq!(parse_meminfo("MemTotal: 5 kB\n"), None);
        assert_eq!(parse_meminfo("MemAvailable: lots\n"), None);
        assert_eq!(parse_meminfo("MemAvailable: 5 MB\n"), None);
        assert_eq!(parse_limit("max\n"), None);
        assert_eq!(parse_limit("4294967296\n"), Some(4 << 30));
        assert_eq!(parse_limit("9223372036854771712\n"), None);
        assert_eq!(parse_limit(""), None);
        let v1 = "12:pids:/user.slice\n4:memory:/slurm/uid_1000/job_7/step_0\n0::/\n";
        assert_eq!(
            cgroup_paths(v1),
            (Some("/"), Some("/slurm/uid_1000/job_7/step_0"))
        );
        let joined = "5:cpuacct,memory,cpu:/docker/abc\n";
        assert_eq!(cgroup_paths(joined), (None, Some("/docker/abc")));
        assert_eq!(
            cgroup_paths(SLURM_V2).0,
            Some(&SLURM_V2[3..SLURM_V2.len() - 1])
        );
        assert_eq!(cgroup_paths("garbage\n"), (None, None));
    }

    /// Slurm on cgroup v2 limits the job's cgroup; the task's own says `max`: the job's room
    /// (limit minus what the job uses) counts, below MemAvailable.
    #[test]
    fn slurm_v2_job_limit_counts_from_a_task() {
        let task = format!("{JOB_V2}/step_0/user/task_0");
        let read = machine(&[
            ("/proc/meminfo", MEMINFO_16G),
            ("/proc/self/cgroup", SLURM_V2),
            (&format!("{JOB_V2}/memory.max"), "4294967296\n"),
            (&format!("{JOB_V2}/memory.current"), "1073741824\n"),
            (&format!("{task}/memory.max"), "max\n"),
            (&format!("{task}/memory.current"), "1000\n"),
            ("/sys/fs/cgroup/memory.max", "max\n"),
        ]);
        assert_eq!(available_with(&read), Some(3 << 30));
    }

    /// cgroup v1 (Slurm's `task/cgroup` on older nodes): the job's limit; the step's huge
    /// value means no limit. A limit above MemAvailable leaves MemAvailable.
    #[test]
    fn v1_limits_and_unlimited_values() {
        let job = "/sys/fs/cgroup/memory/slurm/uid_1000/job_7";
        let files = |job_limit: &'static str| {
            machine(&[
                ("/proc/meminfo", MEMINFO_16G),
                (
                    "/proc/self/cgroup",
                    "4:memory:/slurm/uid_1000/job_7/step_0\n0::/\n",
                ),
                (&format!("{job}/memory.limit_in_bytes"), job_limit),
                (&format!("{job}/memory.usage_in_bytes"), "536870912\n"),
                (
                    &format!("{job}/step_0/memory.limit_in_bytes"),
                    "9223372036854771712\n",
                ),
            ])
        };
        assert_eq!(available_with(&files("2147483648\n")), Some(3 << 29));
        assert_eq!(available_with(&files("68719476736\n")), Some(16 << 30));
        assert_eq!(
            available_with(&files("9223372036854771712\n")),
            Some(16 << 30)
        );
    }

    /// A container that mounts its own cgroup as the root: the root's limit is the one.
    /// Missing files: MemAvailable alone, the cgroup alone, or nothing.
    #[test]
    fn root_limits_and_missing_files() {
        let read = machine(&[
            ("/proc/meminfo", MEMINFO_16G),
            ("/proc/self/cgroup", "0::/docker/abc\n"),
            ("/sys/fs/cgroup/memory.max", "1073741824\n"),
        ]);
        assert_eq!(available_with(&read), Some(1 << 30));
        let no_cgroup = machine(&[("/proc/meminfo", MEMINFO_16G)]);
        assert_eq!(available_with(&no_cgroup), Some(16 << 30));
        let no_meminfo = machine(&[
            ("/proc/self/cgroup", "0::/\n"),
            ("/sys/fs/cgroup/memory.max", "1073741824\n"),
            ("/sys/fs/cgroup/memory.current", "2147483648\n"),
        ]);
        assert_eq!(available_with(&no_meminfo), Some(0));
        assert_eq!(available_with(&machine(&[])), None);
    }
}
