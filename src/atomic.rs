//! All-or-nothing file output: write a temporary file beside the target, fsync, rename.

use std::fs::{self, File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::{Error, Result};

/// Distinguishes concurrent writes from the same process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `path` atomically: `f` writes into a temporary file `.NAME.tmp-PID-N` in the same
/// directory, which is then flushed, fsynced and renamed over `path`.
///
/// Readers therefore see either the old file or the complete new one. On any error (from `f`,
/// flushing, syncing or renaming) the temporary file is removed and the target is left untouched.
/// I/O errors name the path concerned. Cost: one extra fsync per file.
///
/// Temporaries of `path` that processes no longer running left behind (killed mid-write) are
/// removed first ([`remove_dead_temps`]).
pub fn write_atomic(path: &Path, f: impl FnOnce(&mut BufWriter<File>) -> Result<()>) -> Result<()> {
    remove_dead_temps(path);
    let tmp = temp_path(path)?;
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(|e| Error::io(path, e))?;
    let result = write_and_sync(path, file, f)
        .and_then(|()| fs::rename(&tmp, path).map_err(|e| Error::io(path, e)));
    match result {
        Ok(()) => {
            sync_parent(path);
            Ok(())
        }
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

fn write_and_sync(
    path: &Path,
    file: File,
    f: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let mut w = BufWriter::new(file);
    f(&mut w)?;
    w.flush().map_err(|e| Error::io(path, e))?;
    let file = w
        .into_inner()
        .map_err(|e| Error::io(path, e.into_error()))?;
    file.sync_all().map_err(|e| Error::io(path, e))
}

/// `dir/.name.tmp-PID-N` for target `dir/name`.
fn temp_path(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::invalid(format!("{}: not a file name", path.display())))?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp_name = format!(".{}.tmp-{}-{n}", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(tmp_name))
}

/// Removes the temporary files that interrupted [`write_atomic`]s of `path` left behind (a
/// process killed between creating and renaming its `.NAME.tmp-PID-N`), except this process's
/// own. Returns how many were removed. Call it only when no other process is writing `path`.
///
/// # Errors
/// [`Error::Io`] if the directory cannot be listed or a temporary file cannot be removed.
pub fn remove_stale_temps(path: &Path) -> Result<usize> {
    let Some(name) = path.file_name() else {
        return Ok(0);
    };
    let prefix = format!(".{}.tmp-", name.to_string_lossy());
    let own = format!("{prefix}{}-", std::process::id());
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let entries = match fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(Error::io(dir, e)),
    };
    let mut removed = 0;
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let file = entry.file_name().to_string_lossy().into_owned();
        if file.starts_with(&prefix) && !file.starts_with(&own) {
            fs::remove_file(entry.path()).map_err(|e| Error::io(entry.path(), e))?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// Makes sure `path` can be written before any work is done for it: creates the folder it is
/// to be written in (and its parents), then creates and removes a temporary file there (named
/// as [`write_atomic`]'s, so a killed run leaves nothing [`remove_stale_temps`] would not
/// clean). Cost: a few system calls.
///
/// # Errors
/// [`Error::Invalid`] naming `path` and the folder if the folder cannot be created (a part of
/// it is a file, no permission) or no file can be created in it.
pub fn prepare_output(path: &Path) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let refuse = |what: &str, e: std::io::Error| {
        Error::invalid(format!("{}: {what} {}: {e}", path.display(), dir.display()))
    };
    fs::create_dir_all(dir).map_err(|e| refuse("cannot create the output folder", e))?;
    let probe = temp_path(path)?;
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| refuse("cannot write in the output folder", e))?;
    let _ = fs::remove_file(&probe);
    Ok(())
}

/// Removes the temporaries `.NAME.tmp-PID-N` of `path` whose process `PID` is no longer running
/// (Linux: no `/proc/PID`), best effort; a live process's temporary is never touched. Where
/// liveness cannot be told (no `/proc`), nothing is removed. Returns how many were removed.
pub fn remove_dead_temps(path: &Path) -> usize {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return 0;
    }
    let Some(name) = path.file_name() else {
        return 0;
    };
    let prefix = format!(".{}.tmp-", name.to_string_lossy());
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Ok(entries) = fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let Some(pid) = file
            .strip_prefix(&prefix)
            .and_then(|rest| rest.split('-').next())
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if !proc.join(pid.to_string()).exists() && fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Makes the rename durable by syncing the directory (best effort; not possible on all systems).
fn sync_parent(path: &Path) {
    #[cfg(unix)]
    {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    #[cfg(not(unix))]
    let _ = path;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plain_write_removes_dead_processes_temporaries_only() {
        let d = scratch("dead");
        let target = d.join("a.png");
        // PID 4194304 is above Linux's largest (pid_max ≤ 2^22): never running.
        fs::write(d.join(".a.png.tmp-4194304-0"), b"half").unwrap();
        let live = format!(".a.png.tmp-{}-99", std::process::id());
        fs::write(d.join(&live), b"mine").unwrap();
        fs::write(d.join(".b.png.tmp-4194304-0"), b"other target").unwrap();
        write_atomic(&target, |w| {
            w.write_all(b"new").map_err(|e| Error::io(&target, e))
        })
        .unwrap();
        if Path::new("/proc/self").exists() {
            assert_eq!(
                entries(&d),
                vec![
                    live,
                    ".b.png.tmp-4194304-0".to_string(),
                    "a.png".to_string()
                ]
            );
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("filmsplat-atomic-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_and_replaces() {
        let d = scratch("ok");
        let p = d.join("out.txt");
        write_atomic(&p, |w| w.write_all(b"one").map_err(|e| Error::io(&p, e))).unwrap();
        write_atomic(&p, |w| w.write_all(b"two").map_err(|e| Error::io(&p, e))).unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two");
        assert_eq!(entries(&d), vec!["out.txt"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn failure_leaves_no_temp_and_keeps_old_file() {
        let d = scratch("fail");
        let p = d.join("out.txt");
        fs::write(&p, b"old").unwrap();
        let err = write_atomic(&p, |w| {
            w.write_all(&[7u8; 100_000]).unwrap(); // more than the buffer: reaches the temp file
            Err(Error::invalid("encoder failed"))
        })
        .unwrap_err();
        assert!(err.to_string().contains("encoder failed"));
        assert_eq!(fs::read(&p).unwrap(), b"old");
        assert_eq!(entries(&d), vec!["out.txt"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn missing_directory_is_an_error_naming_the_path() {
        let d = scratch("nodir");
        let p = d.join("no/such/dir/out.txt");
        let err = write_atomic(&p, |_| Ok(())).unwrap_err();
        assert!(err.to_string().contains("no/such/dir/out.txt"), "{err}");
        assert!(entries(&d).is_empty());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn stale_temps_of_other_processes_are_removed() {
        let d = scratch("stale");
        let p = d.join("f.png");
        let own = format!(".f.png.tmp-{}-3", std::process::id());
        for name in [
            ".f.png.tmp-4000000-0",
            ".f.png.tmp-1-7",
            own.as_str(),
            ".g.png.tmp-1-0",
        ] {
            fs::write(d.join(name), b"partial").unwrap();
        }
        assert_eq!(remove_stale_temps(&p).unwrap(), 2);
        let mut left = vec![".g.png.tmp-1-0".to_string(), own];
        left.sort();
        assert_eq!(entries(&d), left);
        assert_eq!(remove_stale_temps(&d.join("none/f.png")).unwrap(), 0);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn rename_failure_cleans_up() {
        // Renaming a file over a non-empty directory fails.
        let d = scratch("rename");
        let p = d.join("target");
        fs::create_dir(&p).unwrap();
        fs::write(p.join("inner"), b"x").unwrap();
        let err = write_atomic(&p, |w| w.write_all(b"data").map_err(|e| Error::io(&p, e)));
        assert!(err.is_err());
        assert_eq!(entries(&d), vec!["target"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn outputs_are_prepared_or_refused_before_the_work() {
        let d = scratch("prepare");
        let deep = d.join("a/b/c/out.png");
        prepare_output(&deep).unwrap();
        assert!(d.join("a/b/c").is_dir());
        assert!(entries(&d.join("a/b/c")).is_empty(), "the probe is removed");
        fs::write(d.join("file"), b"x").unwrap();
        let e = prepare_output(&d.join("file/out.png"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("file/out.png") && e.contains("cannot create the output folder"),
            "{e}"
        );
        prepare_output(Path::new("relative.png")).unwrap();
    }
}
