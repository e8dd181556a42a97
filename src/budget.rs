//! The memory one run may allocate: every allocation whose size comes from a file header, a
//! flag or a scene key is checked here first, so a run refuses (exit 2, naming what asked for
//! the memory) instead of aborting with "memory allocation failed" or meeting the OOM killer.
//!
//! The allowance is the memory available now, [`available_memory`]: Linux's `MemAvailable`
//! (`/proc/meminfo`), lowered to the room under the memory limits of the process's cgroups (v2
//! `memory.max`, v1 `memory.limit_in_bytes`, as Slurm and containers set them), or 16 GiB where
//! nothing is known. The same answer is `render --max-memory`'s default. `FILMSPLAT_MEMORY_LIMIT` (a size such as `512M` or `8G`)
//! replaces it (tests use this; so can a shared machine), and [`set_allowance`] (the CLI's
//! `--max-memory`) replaces both.

mod system;

pub use system::{available_with, cgroup_paths, parse_limit, parse_meminfo};

/// The memory the operating system lets this process allocate now, bytes: `MemAvailable`
/// lowered to the room under its cgroups' memory limits (v1 and v2, the process's cgroup and
/// its ancestors); `None` where the system says nothing (not Linux). Cost: reads a few small
/// `/proc` and `/sys` files.
pub fn available_memory() -> Option<u64> {
    system::available_bytes()
}

/// Allowance where the operating system says nothing: 16 GiB.
const UNKNOWN_BYTES: u64 = 16 << 30;

/// An allowance set by the program (e.g. `render --max-memory`), 0 for none.
static SET_BYTES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Sets this process's allowance to `bytes` (a user's explicit limit, such as
/// `--max-memory`), replacing what the system says and `FILMSPLAT_MEMORY_LIMIT`.
pub fn set_allowance(bytes: u64) {
    SET_BYTES.store(bytes, std::sync::atomic::Ordering::Relaxed);
}

/// The memory this run may allocate, bytes (see the module docs). Cost: reads a few small
/// `/proc` and `/sys` files.
pub fn allowance_bytes() -> u64 {
    let set = SET_BYTES.load(std::sync::atomic::Ordering::Relaxed);
    if set > 0 {
        return set;
    }
    if let Ok(s) = std::env::var("FILMSPLAT_MEMORY_LIMIT")
        && let Ok(b) = parse_size(&s)
    {
        return b;
    }
    system::available_bytes().unwrap_or(UNKNOWN_BYTES)
}

/// Refuses `bytes` for `what` if they exceed the allowance: `Err` says how much `what` needs
/// and how much is available, e.g. "a 100000x100000 map needs 149.0 GiB, 7.1 GiB available".
pub fn check(bytes: u64, what: impl FnOnce() -> String) -> Result<(), String> {
    let allowed = allowance_bytes();
    if bytes > allowed {
        return Err(format!(
            "{} needs {}, more than the {} of memory available",
            what(),
            human_bytes(bytes),
            human_bytes(allowed)
        ));
    }
    Ok(())
}

/// `count` elements of `T` as a `Vec`, allocated without aborting: refused by [`check`] or by
/// the allocator (`try_reserve_exact`) with a message naming `what`.
pub fn vec_with_capacity<T>(count: usize, what: impl Fn() -> String) -> Result<Vec<T>, String> {
    let bytes = (count as u64).saturating_mul(std::mem::size_of::<T>() as u64);
    check(bytes, &what)?;
    let mut v = Vec::new();
    v.try_reserve_exact(count)
        .map_err(|_| format!("{}: allocating {} failed", what(), human_bytes(bytes)))?;
    Ok(v)
}

/// Bytes as `1.5 GiB`, `12.0 MiB`, `800 B`.
pub fn human_bytes(b: u64) -> String {
    const UNITS: [&str; 5] = ["KiB", "MiB", "GiB", "TiB", "PiB"];
    if b < 1024 {
        return format!("{b} B");
    }
    let mut v = b as f64 / 1024.0;
    let mut unit = 0;
    while v >= 1024.0 && unit + 1 < UNITS.len() {
        v /= 1024.0;
        unit += 1;
    }
    format!("{v:.1} {}", UNITS[unit])
}

/// Parses a memory size: a number with an optional binary suffix K, M, G or T (also KB, KiB,
/// ...; case-insensitive), e.g. `8G`, `512M`, `1.5G`, `1000000` (bytes).
///
/// # Errors
/// A message if the text is not a positive size.
pub fn parse_size(s: &str) -> std::result::Result<u64, String> {
    let t = s.trim();
    let bad = || format!("memory size '{s}' must be a number with K, M, G or T, e.g. 8G or 512M");
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: f64 = num.parse().map_err(|_| bad())?;
    let shift = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kb" | "kib" => 10,
        "m" | "mb" | "mib" => 20,
        "g" | "gb" | "gib" => 30,
        "t" | "tb" | "tib" => 40,
        _ => return Err(bad()),
    };
    let bytes = value * (1u64 << shift) as f64;
    if !(bytes.is_finite() && bytes >= 1.0 && bytes < u64::MAX as f64) {
        return Err(bad());
    }
    Ok(bytes as u64)
}
