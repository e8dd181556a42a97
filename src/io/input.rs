//! Where an input's bytes come from: a regular file, standard input (`-`), or a pipe (a named
//! pipe, `<(cat f.ply)`). A pipe can be read only once, so its bytes are read into memory once,
//! with a bound, and its format is told from those bytes; devices (`/dev/zero`, also behind a
//! symlink) and sockets are refused. Opening a named pipe never blocks: with no writer the read
//! waits at most [`pipe_wait`] for one, then refuses.

use std::io::{self, Read};
use std::path::Path;
use std::time::{Duration, Instant};

use crate::budget;
use crate::error::{Error, Result};

/// Most bytes read from a pipe or standard input: 2 GiB (less if less memory is available).
pub const STREAM_LIMIT_BYTES: u64 = 2 << 30;

/// What a path names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `-`: standard input.
    Stdin,
    /// A named pipe (FIFO), also `/dev/fd/N` of a process substitution.
    Pipe,
    /// A regular file of this many bytes.
    File(u64),
    /// A directory.
    Dir,
}

/// True if `path` is `-` (standard input).
pub fn is_stdin(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// True if `path` is standard input or a pipe: content that can be read only once.
pub fn is_stream(path: &Path) -> bool {
    matches!(kind(path), Ok(Kind::Stdin | Kind::Pipe))
}

/// What `path` names (following symlinks).
///
/// # Errors
/// [`Error::Io`] if it cannot be inspected; [`Error::Format`] for a device or a socket.
pub(crate) fn kind(path: &Path) -> Result<Kind> {
    if is_stdin(path) {
        return Ok(Kind::Stdin);
    }
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    let t = meta.file_type();
    if t.is_file() {
        return Ok(Kind::File(meta.len()));
    }
    if t.is_dir() {
        return Ok(Kind::Dir);
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Ok(Kind::Pipe);
        }
        let what = if t.is_char_device() {
            "a character device (like /dev/zero)"
        } else if t.is_block_device() {
            "a block device"
        } else if t.is_socket() {
            "a socket"
        } else {
            "not a regular file"
        };
        Err(refused(path, what))
    }
    #[cfg(not(unix))]
    Err(refused(path, "not a regular file"))
}

fn refused(path: &Path, what: &str) -> Error {
    Error::Format {
        path: path.to_path_buf(),
        format: "input",
        message: format!("{what}, not a file or a pipe: refused"),
    }
}

/// How long reading a named pipe waits for a writer (or the first byte): 10 s, or
/// `FILMSPLAT_PIPE_WAIT` seconds.
pub fn pipe_wait() -> Duration {
    std::env::var("FILMSPLAT_PIPE_WAIT")
        .ok()
        .and_then(|s| s.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0)
        .map_or(Duration::from_secs(10), Duration::from_secs_f64)
}

/// The most bytes a stream may hold: [`STREAM_LIMIT_BYTES`] or half the memory allowance.
fn stream_limit() -> u64 {
    STREAM_LIMIT_BYTES.min(budget::allowance_bytes() / 2)
}

/// Reads all of a regular file, a pipe or standard input (`-`) into memory, once.
///
/// A regular file is read up to its size (refused if it exceeds the memory allowance); a
/// stream up to [`STREAM_LIMIT_BYTES`], and `head_ok` is asked about its first bytes (up to
/// 4 KiB) so a stream of the wrong content (`cat /dev/zero |`) is refused at once rather
/// than after the limit.
///
/// # Errors
/// [`Error::Io`] for read failures, a directory, or a terminal on standard input;
/// [`Error::Format`] naming the path for a device, an empty or too long stream, a named pipe
/// without a writer, or a head `head_ok` refuses.
pub(crate) fn read_all(
    path: &Path,
    head_ok: &dyn Fn(&[u8]) -> std::result::Result<(), String>,
) -> Result<Vec<u8>> {
    read_limited(path, None, head_ok)
}

/// Reads a small text input (a scene file) whole: a regular file or a pipe of at most
/// `max_bytes`, refusing devices and anything longer.
///
/// # Errors
/// As `read_all`; [`Error::Format`] if it holds more than `max_bytes`.
pub fn read_small(path: &Path, max_bytes: u64) -> Result<Vec<u8>> {
    if let Kind::File(len) = kind(path)?
        && len > max_bytes
    {
        return Err(Error::Format {
            path: path.to_path_buf(),
            format: "input",
            message: format!("{len} bytes, more than the {max_bytes} accepted for this input"),
        });
    }
    read_limited(path, Some(max_bytes), &|_| Ok(()))
}

fn read_limited(
    path: &Path,
    max_stream: Option<u64>,
    head_ok: &dyn Fn(&[u8]) -> std::result::Result<(), String>,
) -> Result<Vec<u8>> {
    let fail = |message: String| Error::Format {
        path: path.to_path_buf(),
        format: "input",
        message,
    };
    let limit = match kind(path)? {
        Kind::Dir => {
            let e = io::Error::new(io::ErrorKind::IsADirectory, "is a directory");
            return Err(Error::io(path, e));
        }
        Kind::File(len) => {
            budget::check(len, || format!("reading the {len}-byte file whole")).map_err(fail)?;
            let mut out = Vec::new();
            out.try_reserve_exact(len as usize)
                .map_err(|_| fail(format!("cannot allocate {len} bytes to read it")))?;
            // A file growing while it is read stops at the size it had.
            std::fs::File::open(path)
                .and_then(|f| f.take(len).read_to_end(&mut out))
                .map_err(|e| Error::io(path, e))?;
            return Ok(out);
        }
        Kind::Stdin | Kind::Pipe => max_stream.unwrap_or_else(stream_limit),
    };
    let bytes = if is_stdin(path) {
        use std::io::IsTerminal;
        let stdin = io::stdin();
        if stdin.is_terminal() {
            let e = io::Error::other("standard input is a terminal; pipe a file into it");
            return Err(Error::io("-", e));
        }
        read_bounded(&mut stdin.lock(), limit, head_ok, None)
    } else {
        open_pipe(path).and_then(|mut f| read_bounded(&mut f, limit, head_ok, Some(pipe_wait())))
    };
    let bytes = bytes.map_err(|e| match e {
        Fail::Io(e) => Error::io(path, e),
        Fail::Msg(m) => fail(m),
    })?;
    if bytes.is_empty() {
        return Err(fail(if is_stdin(path) {
            "standard input is empty".to_string()
        } else {
            format!(
                "the pipe stayed empty (no writer within {:.1} s)",
                pipe_wait().as_secs_f64()
            )
        }));
    }
    Ok(bytes)
}

enum Fail {
    Io(io::Error),
    Msg(String),
}

/// Opens a named pipe without blocking until a writer appears.
fn open_pipe(path: &Path) -> std::result::Result<std::fs::File, Fail> {
    let mut o = std::fs::OpenOptions::new();
    o.read(true);
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::OpenOptionsExt;
        o.custom_flags(0o4000); // O_NONBLOCK
    }
    #[cfg(all(unix, not(target_os = "linux")))]
    {
        use std::os::unix::fs::OpenOptionsExt;
        o.custom_flags(0x4); // O_NONBLOCK on the BSDs and macOS
    }
    o.open(path).map_err(Fail::Io)
}

/// Reads `r` to its end, refusing more than `limit` bytes. `wait`: the source is non-blocking
/// (a named pipe): an empty read before the first byte means "no writer yet" and is retried
/// until `wait` has passed; "would block" is retried after a millisecond.
fn read_bounded(
    r: &mut dyn Read,
    limit: u64,
    head_ok: &dyn Fn(&[u8]) -> std::result::Result<(), String>,
    wait: Option<Duration>,
) -> std::result::Result<Vec<u8>, Fail> {
    const HEAD: usize = 4096;
    let start = Instant::now();
    let mut out: Vec<u8> = Vec::new();
    let mut chunk = vec![0u8; 64 << 10];
    let mut head_checked = false;
    loop {
        match r.read(&mut chunk) {
            Ok(0) if out.is_empty() && wait.is_some_and(|w| start.elapsed() < w) => {
                std::thread::sleep(Duration::from_millis(5));
            }
            Ok(0) => break,
            Ok(n) => {
                if out.len() as u64 + n as u64 > limit {
                    return Err(Fail::Msg(format!(
                        "a pipe holding more than {} is refused (read it from a file)",
                        budget::human_bytes(limit)
                    )));
                }
                out.try_reserve(n).map_err(|_| {
                    Fail::Msg(format!("cannot allocate memory after {} bytes", out.len()))
                })?;
                out.extend_from_slice(&chunk[..n]);
                if !head_checked && out.len() >= HEAD {
                    head_ok(&out).map_err(Fail::Msg)?;
                    head_checked = true;
                }
            }
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) if e.kind() == io::ErrorKind::WouldBlock && wait.is_some() => {
                std::thread::sleep(Duration::from_millis(1));
            }
            Err(e) => return Err(Fail::Io(e)),
        }
    }
    if !head_checked && !out.is_empty() {
        head_ok(&out).map_err(Fail::Msg)?;
    }
    Ok(out)
}
