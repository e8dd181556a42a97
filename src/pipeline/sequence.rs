//! Frame sequences: path patterns (`frame_{:04}.ply`), frame ranges, shards for render farms,
//! one camera per sequence, output folders checked first, resume, keep-going.
//!
//! [`render_sequence`] runs the loop over a [`FrameJob`]: the caller's mapping from a frame
//! number to its scene, its files and its render (the CLI's `render --frames`). The camera is
//! decided once ([`super::framing::sequence_camera`]), from the frames alone, so sharded jobs
//! agree without talking.

use super::camera_path::{CameraMove, FrameCamera, path_toml};
use super::framing::{self, Framing};
use super::prepared::Prepared;
use crate::scene::{CameraDesc, SceneDesc};
use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The brace that opens a frame pattern's placeholder.
const OPEN: char = '\u{7b}';

/// Expands the first `{}` or `{:0N}` in `pattern` with `frame` (zero-padded to N digits).
/// Returns `None` if the pattern has no placeholder.
///
/// # Errors
/// [`Error::Invalid`] for an unclosed `{` or another placeholder.
pub fn expand(pattern: &str, frame: u64) -> Result<Option<String>> {
    let Some(open) = pattern.find(OPEN) else {
        return Ok(None);
    };
    let bad = || {
        Error::invalid(format!(
            "'{pattern}': frame pattern must be {{}} or {{:0N}}"
        ))
    };
    let close = pattern[open..]
        .find('\u{7d}')
        .map(|c| open + c)
        .ok_or_else(|| {
            Error::invalid(format!("'{pattern}': unclosed '{OPEN}' in frame pattern"))
        })?;
    let width = match &pattern[open + 1..close] {
        "" => 0,
        s if s.starts_with(":0") && s.len() > 2 => s[2..]
            .parse::<usize>()
            .ok()
            .filter(|w| *w <= 20)
            .ok_or_else(bad)?,
        _ => return Err(bad()),
    };
    let (head, tail) = (&pattern[..open], &pattern[close + 1..]);
    Ok(Some(format!("{head}{frame:0width$}{tail}")))
}

/// Parses a frame range `A..B` (B excluded) or `A..=B`, or a single frame `A`.
///
/// # Errors
/// A message for another text, an empty range or more than 10 000 000 frames.
pub fn frames(s: &str) -> std::result::Result<Vec<u64>, String> {
    let bad = || format!("frames '{s}' must be A..B, A..=B or A (whole numbers)");
    let num = |v: &str| v.trim().parse::<u64>().map_err(|_| bad());
    let (a, b) = if let Some((a, b)) = s.split_once("..=") {
        (num(a)?, num(b)?.checked_add(1).ok_or_else(bad)?)
    } else if let Some((a, b)) = s.split_once("..") {
        (num(a)?, num(b)?)
    } else {
        let a = num(s)?;
        (a, a.checked_add(1).ok_or_else(bad)?)
    };
    if b <= a {
        return Err(format!("frames '{s}' is empty"));
    }
    if b - a > 10_000_000 {
        return Err(format!("frames '{s}' has more than 10 000 000 frames"));
    }
    Ok((a..b).collect())
}

/// Parses a shard `K/N` (0 <= K < N).
///
/// # Errors
/// A message for another text.
pub fn shard(s: &str) -> std::result::Result<(u64, u64), String> {
    let bad = || format!("shard '{s}' must be K/N with 0 <= K < N");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n) = (
        k.trim().parse::<u64>().map_err(|_| bad())?,
        n.trim().parse::<u64>().map_err(|_| bad())?,
    );
    if n == 0 || k >= n {
        return Err(bad());
    }
    Ok((k, n))
}

/// The frames this shard renders: every N-th of `frames`, starting at the K-th.
pub fn sharded(frames: &[u64], shard: Option<(u64, u64)>) -> Vec<u64> {
    match shard {
        None => frames.to_vec(),
        Some((k, n)) => frames
            .iter()
            .copied()
            .skip(k as usize)
            .step_by(n as usize)
            .collect(),
    }
}

/// What a sequence renders, frame by frame.
pub trait FrameJob {
    /// The files frame `f` writes: its image first, then any others (an EXR). Called once per
    /// frame before the work, so it should cost little (not a copy of the whole frame list).
    fn outputs(&self, f: u64) -> Result<Vec<PathBuf>>;
    /// The files frame `f` reads, if known: those of the first frame to render are checked to
    /// exist before anything else (unless keep-going), so a missing input fails at once.
    fn inputs(&self, _f: u64) -> Result<Vec<PathBuf>> {
        Ok(Vec::new())
    }
    /// Frame `f`'s scene description (before the sequence's camera is applied).
    fn scene(&self, f: u64) -> Result<SceneDesc>;
    /// Frame `f` prepared (for measuring its framing), without a progress bar.
    fn prepare(&self, f: u64) -> Result<Prepared>;
    /// Renders frame `f` and writes its outputs: from `camera` when given (the sequence's one
    /// camera, or this frame's on an orbit or a camera path: position, look-at, field of view,
    /// lens and exposure); `ready` is the frame already prepared, if it was.
    fn render(
        &self,
        f: u64,
        camera: Option<&FrameCamera>,
        ready: Option<Prepared>,
        out: &mut dyn Write,
    ) -> Result<()>;
}

/// How a sequence is run.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SequenceOptions {
    /// The whole sequence's frames, in order (not empty).
    pub frames: Vec<u64>,
    /// Render only every N-th frame, starting at the K-th (`(K, N)`).
    pub shard: Option<(u64, u64)>,
    /// Frame the camera on the union of every frame's bounds (else on the first frame's).
    pub frame_all: bool,
    /// Skip frames whose outputs all exist; remove an interrupted run's temporary files.
    pub resume: bool,
    /// Report a failing frame and go on; fail at the end.
    pub keep_going: bool,
    /// No messages on `out`.
    pub quiet: bool,
}

/// Renders the sequence: checks every output name and folder of this shard first, decides the
/// one camera (`sequence_camera`) before the first frame it renders, then renders its
/// shard's frames, skipping finished ones (resume) and going on after failures (keep-going).
/// Progress goes to `out`, failures kept going past to `err`.
///
/// # Errors
/// The first frame's error, named by its frame (or with keep-going, one naming every failed
/// frame); [`Error::Invalid`] for a bad output name or an empty `frames`.
pub fn render_sequence(
    job: &dyn FrameJob,
    opts: &SequenceOptions,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<()> {
    if opts.frames.is_empty() {
        return Err(Error::invalid("a sequence needs at least one frame"));
    }
    let mine = sharded(&opts.frames, opts.shard);
    if let Some(&f) = mine.first().filter(|_| !opts.keep_going) {
        for p in job.inputs(f)? {
            std::fs::metadata(&p)
                .map_err(|e| Error::invalid(format!("frame {f}: {}", Error::io(&p, e))))?;
        }
    }
    // The camera's move, checked before anything renders.
    let desc = job.scene(opts.frames[0])?;
    let mv = CameraMove::of(&desc.camera).map_err(|e| desc.locate(e))?;
    check_outputs(&mine, |f| job.outputs(f))?;
    // Decided before the first frame this job renders (not at all if it renders none).
    let mut camera: Option<Option<CameraDesc>> = None;
    let mut failed = Vec::new();
    for (n, &f) in mine.iter().enumerate() {
        let outputs = job.outputs(f)?;
        let label = format!("frame {f}");
        if opts.resume && finished(&label, &outputs, opts.quiet, out)? {
            continue;
        }
        refuse_directories(&outputs)?;
        let mut first = None;
        if camera.is_none() {
            let decided = sequence_camera(job, opts, &desc, &mv, out)?;
            camera = Some(decided.camera);
            first = decided.first.filter(|(g, _)| *g == f).map(|(_, p)| p);
        }
        if !opts.quiet {
            let _ = writeln!(out, "frame {f} ({}/{}):", n + 1, mine.len());
        }
        let start = camera.as_ref().and_then(Option::as_ref);
        let this = start.map(|s| mv.at(s, &opts.frames, f)).transpose()?;
        match job.render(f, this.as_ref(), first, out) {
            Ok(()) => {}
            Err(e) if opts.keep_going => {
                let _ = writeln!(err, "filmsplat: error: frame {f}: {e}");
                failed.push(f);
            }
            Err(e) => return Err(Error::invalid(format!("frame {f}: {e}"))),
        }
    }
    if !failed.is_empty() {
        return Err(Error::invalid(format!(
            "{} of {} frames failed: {:?}",
            failed.len(),
            mine.len(),
            failed
        )));
    }
    Ok(())
}

/// Fails before the work: every output of `frames` (`outputs(f)`) is a .png or .exr and not a
/// directory, no two frames in a row write the same file (an output without a frame pattern),
/// and every folder they are written in exists (created) and takes files (the first output of
/// each folder is checked whole, see [`crate::atomic::prepare_output`]). Cost: linear in the
/// frames (one `outputs` call and one `stat` an output, a set of the folders).
///
/// # Errors
/// [`Error::Invalid`] naming the output and the frames.
pub fn check_outputs(frames: &[u64], outputs: impl Fn(u64) -> Result<Vec<PathBuf>>) -> Result<()> {
    let mut ready = std::collections::BTreeSet::new();
    let mut previous: Option<(u64, Vec<PathBuf>)> = None;
    for &f in frames {
        let these = outputs(f)?;
        if let Some((g, before)) = &previous
            && let Some(p) = these.iter().find(|p| before.contains(p))
        {
            return Err(Error::invalid(format!(
                "{}: frames {g} and {f} would both write this file (put a frame pattern such \
                 as {{:04}} in its name)",
                p.display()
            )));
        }
        refuse_directories(&these)?;
        for p in &these {
            super::output::check_extension(p)?;
            if ready.insert(p.parent().map(Path::to_path_buf)) {
                crate::atomic::prepare_output(p)?;
            }
        }
        previous = Some((f, these));
    }
    Ok(())
}

/// Refuses outputs that are directories (a rename cannot replace them), naming the first.
///
/// # Errors
/// [`Error::Invalid`] naming the directory.
pub fn refuse_directories(outputs: &[PathBuf]) -> Result<()> {
    match outputs.iter().find(|p| p.is_dir()) {
        Some(p) => Err(Error::invalid(format!(
            "{}: is a directory, not an image (remove it or choose another output)",
            p.display()
        ))),
        None => Ok(()),
    }
}

/// For a resumed run: removes the hidden temporaries (`.NAME.tmp-…`) that writers no longer
/// running left for `outputs` (a live writer's, e.g. a concurrent job's, are kept), and says
/// whether the work `label` (`frame 12`, a glob's input) is finished: every output is a
/// non-empty regular file (outputs are renamed into place only when complete).
///
/// # Errors
/// [`Error::Invalid`] if an output is a directory or another non-file; [`Error::Io`] if a
/// folder cannot be listed.
pub fn finished(
    label: &str,
    outputs: &[PathBuf],
    quiet: bool,
    out: &mut dyn Write,
) -> Result<bool> {
    let mut removed = 0;
    for t in outputs {
        removed += crate::atomic::remove_stale_temps(t)?;
    }
    if removed > 0 && !quiet {
        let _ = writeln!(
            out,
            "{label}: removed {removed} unfinished temporary file(s) of an interrupted run"
        );
    }
    refuse_directories(outputs)?;
    let mut done = true;
    for p in outputs {
        match std::fs::metadata(p) {
            Ok(m) if m.is_file() => done &= m.len() > 0,
            Ok(_) => {
                return Err(Error::invalid(format!(
                    "{}: exists but is not a regular file (remove it or choose another output)",
                    p.display()
                )));
            }
            Err(_) => done = false,
        }
    }
    if done
        && !quiet
        && let Some(target) = outputs.first()
    {
        let _ = writeln!(out, "{label}: {} exists, skipped", target.display());
    }
    Ok(done)
}

/// What [`sequence_camera`] decided.
struct SequenceCamera {
    /// The camera every frame is rendered from; `None` if the scene names one.
    camera: Option<CameraDesc>,
    /// The first frame's number and its prepared scene, if it was prepared whole.
    first: Option<(u64, Prepared)>,
}

/// The camera a sequence starts from (every frame's, unless `mv` moves it): `None` if the
/// scene names a camera position and the camera stays (it wins); the scene's camera if it
/// names one and `mv` turns it; else auto-framed once, on the first frame of the whole
/// sequence, or with `frame_all` on the union of every frame's bounds, so every job of a farm
/// picks the same camera. Prints it as `[camera]` lines, or the path `mv` takes from it
/// (unless quiet). Also returns the first frame's prepared scene when it was prepared whole
/// (not with `frame_all`), for the caller to render instead of preparing it again.
fn sequence_camera(
    job: &dyn FrameJob,
    opts: &SequenceOptions,
    desc: &SceneDesc,
    mv: &CameraMove,
    out: &mut dyn Write,
) -> Result<SequenceCamera> {
    let frames = &opts.frames;
    let first = frames[0];
    let keyed_all = matches!(mv, CameraMove::Keys(_)) && !mv.needs_framing();
    if desc.camera.position.is_some() || keyed_all {
        let camera = (*mv != CameraMove::Fixed).then(|| desc.camera.clone());
        if let Some(c) = camera.as_ref().filter(|_| !opts.quiet) {
            let _ = writeln!(
                out,
                "camera path (paste into a scene file to keep it):\n{}",
                path_toml(c, mv).trim_end()
            );
        }
        return Ok(SequenceCamera {
            camera,
            first: None,
        });
    }
    let measured: &[u64] = if opts.frame_all { frames } else { &frames[..1] };
    let mut framings = Vec::with_capacity(measured.len());
    let mut aspect = 1.0;
    let mut kept = None;
    for &f in measured {
        let p = job.prepare(f).map_err(|e| {
            Error::invalid(format!(
                "frame {f} (the sequence's camera is framed on it): {e}"
            ))
        })?;
        framings.push(p.framing);
        aspect = p.aspect;
        if !opts.frame_all {
            kept = Some((f, p));
        }
    }
    let framing = Framing::union_all(&framings).expect("at least one frame");
    let camera = framing::sequence_camera(desc, &framing, aspect)?;
    if let Some(c) = &camera
        && !opts.quiet
    {
        let (what, lines) = match mv {
            CameraMove::Fixed => ("camera for every frame", framing::camera_toml(c)),
            _ => ("camera path", path_toml(c, mv)),
        };
        let on = if opts.frame_all {
            format!(
                "the bounds of all {} frames ({}..={}, --frame-all)",
                frames.len(),
                first,
                frames[frames.len() - 1]
            )
        } else {
            format!("frame {first}, the first of the sequence")
        };
        let _ = writeln!(
            out,
            "{what}, auto-framed on {on} (paste into a scene file to keep it):\n{}",
            lines.trim_end()
        );
    }
    Ok(SequenceCamera {
        camera,
        first: kept,
    })
}

/// Frame `frame` of a sequence's scene: the first frame pattern (`{}`, `{:04}`) in each input
/// path expanded, and a generated sample's time moved on by `frame / fps` seconds.
///
/// # Errors
/// As [`expand`] for a bad pattern.
pub fn at_frame(desc: &mut SceneDesc, frame: u64, fps: f32) -> Result<()> {
    let expand_path = |p: &mut PathBuf| -> Result<()> {
        if let Some(e) = expand(&p.to_string_lossy(), frame)? {
            *p = PathBuf::from(e);
        }
        Ok(())
    };
    let input = &mut desc.input;
    input.cloud.iter_mut().try_for_each(expand_path)?;
    input
        .clouds
        .iter_mut()
        .flatten()
        .try_for_each(expand_path)?;
    if input.sample.is_some() {
        input.time = Some(input.time.unwrap_or(0.0) + frame as f32 / fps);
    }
    Ok(())
}
