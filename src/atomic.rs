//! All-or-nothing file output: write a temporary file beside the target, fsync, rename.

use std::fs::{self, File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::{Error, Result};

/// Distinguishes concurrent writes from the same process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Longest file name most file systems take (ext4, XFS, btrfs, tmpfs), bytes.
pub const MAX_NAME_BYTES: usize = 255;

/// Longest target name kept whole in its temporary's name: `.` + name + the longest
/// `.tmp-PID-START-N` (5 + 7 + 1 + 20 + 1 + 20 bytes) stays within [`MAX_NAME_BYTES`].
const MAX_KEPT_NAME: usize = MAX_NAME_BYTES - 55;

/// Writes `path` atomically: `f` writes into a temporary file `.NAME.tmp-PID-START-N` in the
/// same directory (START: the process's start time, so a later process that reuses the PID
/// is not taken for the writer; a NAME too long to fit is shortened and hashed, see
/// [`temp_prefix`]), which is then flushed, fsynced and renamed over `path`.
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

/// The start of every temporary's name for target file name `name`: `.NAME.tmp-`, or, for a
/// name longer than `MAX_KEPT_NAME` bytes, `.HEAD~HASH.tmp-` (HEAD: the name's first 180
/// bytes or fewer, cut at a character; HASH: 16 hex digits of the whole name's FNV-1a hash),
/// so the temporary of any legal name is a legal name too.
pub fn temp_prefix(name: &str) -> String {
    if name.len() <= MAX_KEPT_NAME {
        return format!(".{name}.tmp-");
    }
    let mut cut = 180;
    while !name.is_char_boundary(cut) {
        cut -= 1;
    }
    let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    });
    format!(".{}~{hash:016x}.tmp-", &name[..cut])
}

/// `dir/.name.tmp-PID-START-N` for target `dir/name` (see [`temp_prefix`]).
pub(crate) fn temp_path(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::invalid(format!("{}: not a file name", path.display())))?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let prefix = temp_prefix(&name.to_string_lossy());
    let (pid, start) = (
        std::process::id(),
        start_time(std::process::id()).unwrap_or(0),
    );
    Ok(path.with_file_name(format!("{prefix}{pid}-{start}-{n}")))
}

/// When process `pid` started, in clock ticks since boot (field 22 of `/proc/PID/stat`);
/// `None` if it is not running (or there is no `/proc`).
fn start_time(pid: u32) -> Option<u64> {
    let stat = fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count after it.
    let after = &stat[stat.rfind(')')? + 1..];
    after.split_whitespace().nth(19)?.parse().ok()
}

/// True if the writer of a temporary named `…tmp-REST` (REST: `PID-START-N`, or `PID-N` from
/// older versions) is certainly gone: its PID is not running, or a process with a different
/// start time now holds the PID. Unknown formats and systems without `/proc` count as alive.
fn writer_is_dead(rest: &str) -> bool {
    if !Path::new("/proc/self").exists() {
        return false;
    }
    let fields: Vec<&str> = rest.split('-').collect();
    let Some(Ok(pid)) = fields.first().map(|p| p.parse::<u32>()) else {
        return false;
    };
    match (start_time(pid), fields.len()) {
        (None, _) => !Path::new(&format!("/proc/{pid}")).exists(),
        (Some(now), 3) => fields[1].parse::<u64>().is_ok_and(|then| then != now),
        (Some(_), _) => false,
    }
}

/// For a resumed run: removes the temporary files that interrupted [`write_atomic`]s of `path`
/// left behind, those of writers that are gone only (see [`remove_dead_temps`]): a process
/// still writing `path`, such as a concurrent `--resume` job, keeps its temporary. Returns how
/// many were removed.
///
/// # Errors
/// [`Error::Io`] if the directory exists but cannot be listed.
pub fn remove_stale_temps(path: &Path) -> Result<usize> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match fs::read_dir(dir) {
        Ok(_) => Ok(remove_dead_temps(path)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(0),
        Err(e) => Err(Error::io(dir, e)),
    }
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
    if let Some(name) = path.file_name()
        && name.len() > MAX_NAME_BYTES
    {
        return Err(Error::invalid(format!(
            "{}: the file name is {} bytes long, more than the {MAX_NAME_BYTES} a file system \
             takes",
            path.display(),
            name.len()
        )));
    }
    if path.is_dir() {
        return Err(Error::invalid(format!(
            "{}: is a directory, not a file (remove it or choose another output)",
            path.display()
        )));
    }
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

/// Removes the temporaries `.NAME.tmp-PID-START-N` of `path` whose writer is gone (Linux: no
/// `/proc/PID`, or the PID now belongs to a process started at another time), best effort; a
/// live process's temporary is never touched. Where liveness cannot be told (no `/proc`),
/// nothing is removed. Returns how many were removed.
pub fn remove_dead_temps(path: &Path) -> usize {
    let Some(name) = path.file_name() else {
        return 0;
    };
    let prefix = temp_prefix(&name.to_string_lossy());
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
        let dead = file.strip_prefix(&prefix).is_some_and(writer_is_dead);
        if dead && fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Makes the rename durable by syncing the directory (best effort; not possible on all systems).
pub(crate) fn sync_parent(path: &Path) {
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
        fs::remove_dir_all(&d).unwrap();
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
    fn stale_temps_of_dead_writers_only_are_removed() {
        if !Path::new("/proc/self").exists() {
            return;
        }
        let d = scratch("stale");
        let p = d.join("f.png");
        let (pid, start) = (std::process::id(), start_time(std::process::id()).unwrap());
        // Ours (running), PID 1's (running, old format), a gone PID's, and one whose PID is
        // ours but whose start time is not: the PID was reused, its writer is gone.
        let own = format!(".f.png.tmp-{pid}-{start}-3");
        let reused = format!(".f.png.tmp-{pid}-{}-0", start + 1);
        for name in [
            ".f.png.tmp-4000000-0",
            ".f.png.tmp-4000000-5-0",
            ".f.png.tmp-1-7",
            own.as_str(),
            reused.as_str(),
            ".g.png.tmp-4000000-0",
        ] {
            fs::write(d.join(name), b"partial").unwrap();
        }
        assert_eq!(remove_stale_temps(&p).unwrap(), 3);
        let mut left = vec![
            ".f.png.tmp-1-7".to_string(),
            ".g.png.tmp-4000000-0".to_string(),
            own,
        ];
        left.sort();
        assert_eq!(entries(&d), left);
        assert_eq!(remove_stale_temps(&d.join("none/f.png")).unwrap(), 0);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_legal_long_name_is_written_through_a_short_temporary() {
        let d = scratch("long");
        // 254 bytes, multi-byte characters at the cut included.
        let name = format!("{}{}.png", "é".repeat(100), "a".repeat(50));
        assert_eq!(name.len(), 254);
        let p = d.join(&name);
        prepare_output(&p).unwrap();
        write_atomic(&p, |w| w.write_all(b"x").map_err(|e| Error::io(&p, e))).unwrap();
        assert_eq!(entries(&d), vec![name.clone()]);
        let prefix = temp_prefix(&name);
        // The longest `PID-START-N` after it: 7 + 1 + 20 + 1 + 20 bytes.
        assert!(prefix.len() + 49 <= MAX_NAME_BYTES, "{}", prefix.len());
        assert_ne!(
            prefix,
            temp_prefix(&format!("{}{}.pnh", "é".repeat(100), "a".repeat(50)))
        );
        // A dead writer's temporary of that name is found and removed.
        fs::write(d.join(format!("{prefix}4000000-1-0")), b"half").unwrap();
        assert_eq!(remove_stale_temps(&p).unwrap(), 1);
        // A name longer than any file system takes is refused for what it is.
        let e = prepare_output(&d.join("b".repeat(256)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("256 bytes"), "{e}");
        let e = prepare_output(&d).unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
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
        fs::remove_dir_all(&d).unwrap();
    }
}
