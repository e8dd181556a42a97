//! How many worker threads the command line uses: `--threads N`, else `FILMSPLAT_THREADS`,
//! else the CPUs this job was given. Rayon's global pool is set up once, before any work.

use crate::{Error, Result};

/// The environment variable that sets the thread count when `--threads` is not given.
pub const THREADS_ENV: &str = "FILMSPLAT_THREADS";

/// Most threads a user may ask for.
const MAX_THREADS: usize = 4096;

/// The CPUs this job may use: the process's CPU affinity and cgroup CPU quota (what
/// [`std::thread::available_parallelism`] reads on Linux), and no more than Slurm's
/// `SLURM_CPUS_PER_TASK` when it is set (Slurm does not always pin a job's threads).
pub fn job_cpus(slurm_cpus_per_task: Option<&str>) -> usize {
    let machine = std::thread::available_parallelism().map_or(1, |n| n.get());
    let slurm = slurm_cpus_per_task
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n > 0);
    slurm.map_or(machine, |s| s.min(machine))
}

/// Parses a thread count (`--threads` or the environment variable `source`): 1..=4096.
///
/// # Errors
/// [`Error::Invalid`] naming `source` for anything else.
pub fn parse_threads(s: &str, source: &str) -> Result<usize> {
    match s.trim().parse::<usize>() {
        Ok(n) if (1..=MAX_THREADS).contains(&n) => Ok(n),
        _ => Err(Error::invalid(format!(
            "{source}: '{s}' is not a thread count (1..={MAX_THREADS})"
        ))),
    }
}

/// The thread count to use: `flag` (from `--threads`), else `env` (the value of
/// [`THREADS_ENV`]), else [`job_cpus`] of `slurm`.
///
/// # Errors
/// As [`parse_threads`], for a bad environment value.
pub fn choose(flag: Option<usize>, env: Option<&str>, slurm: Option<&str>) -> Result<usize> {
    if let Some(n) = flag {
        return Ok(n);
    }
    match env.filter(|s| !s.trim().is_empty()) {
        Some(s) => parse_threads(s, THREADS_ENV),
        None => Ok(job_cpus(slurm)),
    }
}

/// Sets rayon's global pool to `flag`, the environment's or the job's thread count (see
/// [`choose`]). The pool is built once per process: a second call (the Python package runs
/// the CLI many times in one process) keeps the first pool.
///
/// # Errors
/// As [`choose`].
pub fn configure(flag: Option<usize>) -> Result<usize> {
    let env = std::env::var(THREADS_ENV).ok();
    let slurm = std::env::var("SLURM_CPUS_PER_TASK").ok();
    let n = choose(flag, env.as_deref(), slurm.as_deref())?;
    // Err only when the pool already exists (started by an earlier call): that one stays.
    let _ = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global();
    Ok(rayon::current_num_threads())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flag_wins_then_the_environment_then_the_job() {
        let machine = job_cpus(None);
        assert!(machine >= 1);
        assert_eq!(choose(Some(3), Some("5"), Some("2")).unwrap(), 3);
        assert_eq!(choose(None, Some("5"), Some("2")).unwrap(), 5);
        assert_eq!(choose(None, None, None).unwrap(), machine);
        assert_eq!(choose(None, Some(" "), None).unwrap(), machine);
        // Slurm's share caps the machine's, never raises it; nonsense is ignored.
        assert_eq!(choose(None, None, Some("1")).unwrap(), 1);
        assert_eq!(choose(None, None, Some("100000")).unwrap(), machine);
        assert_eq!(choose(None, None, Some("zero")).unwrap(), machine);
        assert_eq!(choose(None, None, Some("0")).unwrap(), machine);
    }

    #[test]
    fn a_bad_count_is_refused_naming_where_it_came_from() {
        for bad in ["0", "-1", "two", "5000", ""] {
            let e = parse_threads(bad, THREADS_ENV).unwrap_err().to_string();
            assert!(e.contains(THREADS_ENV), "{e}");
        }
        assert_eq!(parse_threads("8", "--threads").unwrap(), 8);
    }
}
