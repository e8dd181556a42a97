//! Movies: 8-bit sRGB frames (exactly the bytes a PNG of the frame holds) piped as raw RGB to
//! the system's `ffmpeg` program, which encodes H.264 in MP4 (yuv420p, `+faststart`, plays in
//! browsers and slide software) or VP9 in WebM.
//!
//! The movie is written to a hidden temporary beside its name (`.NAME.tmp-PID-START-N`, as
//! [`crate::atomic::write_atomic`] does) and renamed only when ffmpeg has finished it: a failed
//! frame, an ffmpeg that dies, or a killed run leaves no movie under the name (a killed run's
//! temporary is removed by the next write of that name). Cost besides the render: ffmpeg's
//! encode, in another process (measured in docs/benchmarks.md).

use crate::{Error, Result};
use std::collections::VecDeque;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// Frames per second when none is given.
pub const DEFAULT_FPS: f64 = 24.0;
/// Highest frame rate taken, frames per second.
pub const MAX_FPS: f64 = 1000.0;
/// Lines of ffmpeg's messages kept for an error.
const KEPT_LINES: usize = 8;

/// A movie container and its codec, chosen by the output's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Container {
    /// `.mp4`: H.264 (libx264), yuv420p, `+faststart`.
    Mp4,
    /// `.webm`: VP9 (libvpx-vp9), yuv420p, constant quality.
    Webm,
}

impl Container {
    /// The container of `path` by its extension (case-insensitive), `None` for another.
    pub fn of(path: &Path) -> Option<Container> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "mp4" => Some(Container::Mp4),
            "webm" => Some(Container::Webm),
            _ => None,
        }
    }

    /// The quality when none is given: CRF 18 for H.264 (visually lossless), 31 for VP9
    /// (its documented start for HD).
    pub fn default_crf(self) -> u32 {
        match self {
            Container::Mp4 => 18,
            Container::Webm => 31,
        }
    }

    /// Highest CRF the codec takes (51 for H.264, 63 for VP9).
    pub fn max_crf(self) -> u32 {
        match self {
            Container::Mp4 => 51,
            Container::Webm => 63,
        }
    }

    /// ffmpeg's output arguments after the input: codec, quality, pixel format, container.
    fn codec_args(self, crf: u32) -> Vec<String> {
        let crf = crf.to_string();
        let args: Vec<&str> = match self {
            Container::Mp4 => vec![
                "-c:v",
                "libx264",
                "-preset",
                "medium",
                "-crf",
                &crf,
                "-movflags",
                "+faststart",
                "-f",
                "mp4",
            ],
            Container::Webm => vec![
                "-c:v",
                "libvpx-vp9",
                "-crf",
                &crf,
                "-b:v",
                "0",
                "-row-mt",
                "1",
                "-f",
                "webm",
            ],
        };
        args.into_iter().map(String::from).collect()
    }
}

/// How a movie is encoded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VideoSettings {
    /// Frames per second of the movie, in (0, [`MAX_FPS`]].
    pub fps: f64,
    /// Constant rate factor: lower is better and larger (0..=51 for H.264, 0..=63 for VP9).
    pub crf: u32,
}

impl VideoSettings {
    /// Checks the settings for `container`.
    ///
    /// # Errors
    /// [`Error::Invalid`] for a frame rate that is not a number in (0, 1000] or a CRF above
    /// the codec's.
    pub fn check(&self, container: Container) -> Result<()> {
        check_fps(self.fps)?;
        if self.crf > container.max_crf() {
            return Err(Error::invalid(format!(
                "--crf {} is above {}, the highest this codec takes",
                self.crf,
                container.max_crf()
            )));
        }
        Ok(())
    }
}

/// Refuses a frame rate that is not a number in (0, [`MAX_FPS`]] frames per second.
///
/// # Errors
/// [`Error::Invalid`] naming the value.
pub fn check_fps(fps: f64) -> Result<()> {
    if fps > 0.0 && fps <= MAX_FPS {
        Ok(())
    } else {
        Err(Error::invalid(format!(
            "--fps {fps}: frames per second must be a number in (0, {MAX_FPS}]"
        )))
    }
}

/// Refuses a size H.264 and yuv420p cannot take (odd width or height), with the fix.
///
/// # Errors
/// [`Error::Invalid`] naming the size and the nearest even sizes.
pub fn check_video_size(width: usize, height: usize) -> Result<()> {
    if width.is_multiple_of(2) && height.is_multiple_of(2) {
        return Ok(());
    }
    let even = |v: usize| v + v % 2;
    Err(Error::invalid(format!(
        "size {width}x{height}: a movie needs an even width and height (yuv420p halves the \
         colour resolution); render at --size {}x{}",
        even(width),
        even(height)
    )))
}

/// The `ffmpeg` program on `PATH`.
///
/// # Errors
/// [`Error::Invalid`]: one line naming the program and how to install it.
pub fn find_ffmpeg() -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|d| d.join("ffmpeg"))
        .find(|p| is_executable(p))
        .ok_or_else(|| {
            Error::invalid(
                "ffmpeg: not found on PATH; writing a movie needs it (Debian/Ubuntu: \
                 apt-get install ffmpeg), or write images with -o 'out/{:04}.png'",
            )
        })
}

/// True for a regular file with an execute bit.
fn is_executable(p: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    }
    #[cfg(not(unix))]
    {
        p.is_file()
    }
}

/// A movie being written: ffmpeg running, fed one frame at a time.
pub struct VideoWriter {
    /// The ffmpeg process.
    child: Child,
    /// Its standard input (raw RGB frames); `None` once closed.
    stdin: Option<ChildStdin>,
    /// The last lines ffmpeg said on its standard error.
    said: Arc<Mutex<VecDeque<String>>>,
    /// The thread reading them.
    reader: Option<JoinHandle<()>>,
    /// The hidden temporary ffmpeg writes.
    tmp: PathBuf,
    /// The movie's name.
    path: PathBuf,
    /// Frame size, pixels.
    size: (usize, usize),
    /// Frames written so far.
    frames: u64,
    /// Renamed into place (nothing to clean up).
    done: bool,
}

impl VideoWriter {
    /// Starts `ffmpeg` writing `path` (its container by extension) from `width`×`height`
    /// frames. Removes temporaries of `path` that killed runs left.
    ///
    /// # Errors
    /// [`Error::Invalid`] for an unknown container, bad settings or an odd size;
    /// [`Error::Io`] if ffmpeg cannot be started.
    pub fn create(
        ffmpeg: &Path,
        path: &Path,
        size: (usize, usize),
        settings: &VideoSettings,
    ) -> Result<VideoWriter> {
        let container = Container::of(path).ok_or_else(|| unknown_container(path))?;
        settings.check(container)?;
        check_video_size(size.0, size.1)?;
        crate::atomic::remove_dead_temps(path);
        let tmp = crate::atomic::temp_path(path)?;
        let mut child = Command::new(ffmpeg)
            .args(["-hide_banner", "-nostats", "-loglevel", "error", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgb24"])
            .args(["-s", &format!("{}x{}", size.0, size.1)])
            .args(["-r", &format!("{}", settings.fps), "-i", "-"])
            // sRGB pixels into BT.709 studio-range YUV, tagged so players convert back.
            .args(["-vf", "scale=out_color_matrix=bt709:out_range=tv"])
            .args(["-pix_fmt", "yuv420p", "-colorspace", "bt709"])
            .args(["-color_primaries", "bt709", "-color_trc", "iec61966-2-1"])
            .args(["-color_range", "tv"])
            .args(container.codec_args(settings.crf))
            .arg(&tmp)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| Error::io(ffmpeg, e))?;
        let said = Arc::new(Mutex::new(VecDeque::new()));
        let reader = child.stderr.take().map(|e| {
            let said = said.clone();
            std::thread::spawn(move || keep_last_lines(e, &said))
        });
        Ok(VideoWriter {
            stdin: child.stdin.take(),
            child,
            said,
            reader,
            tmp,
            path: path.to_path_buf(),
            size,
            frames: 0,
            done: false,
        })
    }

    /// Frames written so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The frames' size, (width, height) pixels.
    pub fn size(&self) -> (usize, usize) {
        self.size
    }

    /// Appends one frame: `width`×`height` packed sRGB RGB8 pixels, top row first (the bytes
    /// of its PNG).
    ///
    /// # Errors
    /// [`Error::Invalid`] for another size, or if ffmpeg stopped (with its last lines).
    pub fn push(&mut self, width: usize, height: usize, rgb8: &[u8]) -> Result<()> {
        if (width, height) != self.size || rgb8.len() != width * height * 3 {
            return Err(Error::invalid(format!(
                "{}: frame {} is {width}x{height}, the movie's frames are {}x{}",
                self.path.display(),
                self.frames + 1,
                self.size.0,
                self.size.1
            )));
        }
        let stdin = self.stdin.as_mut().expect("open until finish");
        if stdin.write_all(rgb8).is_err() {
            return Err(self.failure());
        }
        self.frames += 1;
        Ok(())
    }

    /// Closes the movie: waits for ffmpeg, then renames the finished file into place.
    /// Returns the frames written.
    ///
    /// # Errors
    /// [`Error::Invalid`] if no frame was written or ffmpeg failed (with its last lines);
    /// [`Error::Io`] if the rename fails. No movie is left under the name then.
    pub fn finish(mut self) -> Result<u64> {
        if self.frames == 0 {
            return Err(Error::invalid(format!(
                "{}: no frames to write",
                self.path.display()
            )));
        }
        drop(self.stdin.take());
        let status = self.child.wait().map_err(|e| Error::io(&self.path, e))?;
        if let Some(r) = self.reader.take() {
            let _ = r.join();
        }
        if !status.success() {
            return Err(self.failure());
        }
        if let Ok(f) = std::fs::File::open(&self.tmp) {
            let _ = f.sync_all();
        }
        std::fs::rename(&self.tmp, &self.path).map_err(|e| Error::io(&self.path, e))?;
        crate::atomic::sync_parent(&self.path);
        self.done = true;
        Ok(self.frames)
    }

    /// The error of an ffmpeg that stopped: its exit status and last lines, on one line.
    fn failure(&mut self) -> Error {
        drop(self.stdin.take());
        let status = self.child.wait().ok();
        if let Some(r) = self.reader.take() {
            let _ = r.join();
        }
        let lines: Vec<String> = self
            .said
            .lock()
            .map(|l| l.clone().into())
            .unwrap_or_default();
        let said = if lines.is_empty() {
            "it said nothing".to_string()
        } else {
            format!("it said: {}", lines.join(" | "))
        };
        let status = status.map_or("did not run".into(), |s| s.to_string());
        Error::invalid(format!(
            "{}: ffmpeg failed ({status}); {said}",
            self.path.display()
        ))
    }
}

impl Drop for VideoWriter {
    /// An unfinished movie (a frame failed, or an error above) is abandoned: ffmpeg is
    /// stopped and its temporary removed, so no movie is left under the name.
    fn drop(&mut self) {
        if self.done {
            return;
        }
        drop(self.stdin.take());
        let _ = self.child.kill();
        let _ = self.child.wait();
        if let Some(r) = self.reader.take() {
            let _ = r.join();
        }
        let _ = std::fs::remove_file(&self.tmp);
    }
}

/// Reads `from` to its end, keeping its last [`KEPT_LINES`] non-empty lines in `said`.
fn keep_last_lines(from: impl std::io::Read, said: &Mutex<VecDeque<String>>) {
    for line in BufReader::new(from).lines() {
        let Ok(line) = line else { break };
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        if let Ok(mut l) = said.lock() {
            if l.len() == KEPT_LINES {
                l.pop_front();
            }
            l.push_back(line.chars().take(300).collect());
        }
    }
}

/// The error for a movie name of another extension.
pub fn unknown_container(path: &Path) -> Error {
    Error::invalid(format!(
        "{}: a movie must end in .mp4 (H.264) or .webm (VP9)",
        path.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn containers_by_extension() {
        assert_eq!(Container::of(Path::new("a/m.MP4")), Some(Container::Mp4));
        assert_eq!(Container::of(Path::new("m.webm")), Some(Container::Webm));
        assert_eq!(Container::of(Path::new("m.avi")), None);
        assert_eq!(Container::of(Path::new("m")), None);
    }

    #[test]
    fn bad_fps_and_sizes_are_refused() {
        for fps in [0.0, -1.0, f64::NAN, f64::INFINITY, 1001.0] {
            assert!(check_fps(fps).is_err(), "{fps}");
        }
        assert!(check_fps(23.976).is_ok());
        assert!(check_video_size(64, 48).is_ok());
        let e = check_video_size(65, 48).unwrap_err().to_string();
        assert!(e.contains("--size 66x48"), "{e}");
        let s = VideoSettings { fps: 24.0, crf: 52 };
        assert!(s.check(Container::Mp4).is_err());
        assert!(s.check(Container::Webm).is_ok());
    }
}
