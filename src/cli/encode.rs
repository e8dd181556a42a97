//! `filmsplat encode 'out/{:04}.png' -o movie.mp4`: joins a rendered image sequence (a
//! sharded or resumed render's) into a movie with the system's ffmpeg
//! ([`crate::image::video`]). Frames are found by the frame pattern as `render --frames`
//! expands it; a missing frame in the range is an error naming it, never skipped.

use super::parse::FrameList;
use crate::image::Srgb8Image;
use crate::image::video::{self, Container, VideoSettings, VideoWriter};
use crate::pipeline::sequence::expand;
use crate::{Error, Result};
use clap::Args;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Arguments of `filmsplat encode`.
#[derive(Debug, Args)]
pub struct EncodeArgs {
    /// The frames: PNG images named by a frame pattern, {} or {:04} (zero-padded), e.g.
    /// 'out/{:04}.png', as `render --frames` writes them. Without --frames, the frames are the
    /// files of the pattern's folder whose names it gives, and every number from the lowest to
    /// the highest must be there.
    input: PathBuf,
    /// The movie: .mp4 (H.264, yuv420p, +faststart) or .webm (VP9). Written to a temporary
    /// beside it and renamed when complete.
    #[arg(short, long)]
    output: PathBuf,
    /// Frames per second of the movie (default 24).
    #[arg(long, value_parser = super::render_args::fps_arg, allow_hyphen_values = true)]
    fps: Option<f64>,
    /// Quality, the codec's constant rate factor: lower is better and larger (H.264 0..=51,
    /// default 18, visually lossless; VP9 0..=63, default 31).
    #[arg(long, value_parser = super::parse::int_in::<u32>(0, 63))]
    crf: Option<u32>,
    /// Frame numbers to join, A..B (B excluded) or A..=B; each must exist.
    #[arg(long, value_parser = super::parse::frame_list)]
    frames: Option<FrameList>,
    /// No messages.
    #[arg(short, long)]
    quiet: bool,
}

/// Runs `filmsplat encode`: checks everything (pattern, container, quality, ffmpeg, output
/// folder, every frame's file, the first frame's size), then pipes the frames to ffmpeg.
pub fn run(a: &EncodeArgs, out: &mut dyn Write) -> Result<()> {
    let pattern = a.input.to_string_lossy().into_owned();
    if expand(&pattern, 0)?.is_none() {
        return Err(Error::invalid(format!(
            "{pattern}: encode needs a frame pattern ({{}} or {{:04}}), e.g. 'out/{{:04}}.png'"
        )));
    }
    super::movie::check_movie_output(&a.output)?;
    let container = Container::of(&a.output).ok_or_else(|| video::unknown_container(&a.output))?;
    let settings = VideoSettings {
        fps: a.fps.unwrap_or(video::DEFAULT_FPS),
        crf: a.crf.unwrap_or(container.default_crf()),
    };
    settings.check(container)?;
    let ffmpeg = video::find_ffmpeg()?;
    let frames = match &a.frames {
        Some(list) => list.0.clone(),
        None => found_frames(&pattern)?,
    };
    let paths: Vec<PathBuf> = frames
        .iter()
        .map(|&f| Ok(PathBuf::from(expand(&pattern, f)?.expect("checked"))))
        .collect::<Result<_>>()?;
    for (f, p) in frames.iter().zip(&paths) {
        if !p.is_file() {
            return Err(Error::invalid(format!(
                "{}: frame {f} is missing (frames {}..={} of {pattern}); render it, or give \
                 --frames without it",
                p.display(),
                frames[0],
                frames[frames.len() - 1]
            )));
        }
    }
    let first = read_frame(&paths[0], out, a.quiet)?;
    let size = (first.width, first.height);
    video::check_video_size(size.0, size.1)
        .map_err(|e| Error::invalid(format!("{}: {e} (or crop the images)", paths[0].display())))?;
    if !a.quiet {
        let _ = writeln!(
            out,
            "encoding {} frames ({}x{}) of {pattern} at {} fps",
            paths.len(),
            size.0,
            size.1,
            settings.fps
        );
    }
    let mut writer = VideoWriter::create(&ffmpeg, &a.output, size, &settings)?;
    writer.push(first.width, first.height, &first.data)?;
    for p in &paths[1..] {
        let px = read_frame(p, out, a.quiet)?;
        if (px.width, px.height) != size {
            return Err(Error::invalid(format!(
                "{}: is {}x{}, the first frame {} is {}x{}; frames of a movie must agree",
                p.display(),
                px.width,
                px.height,
                paths[0].display(),
                size.0,
                size.1
            )));
        }
        writer.push(px.width, px.height, &px.data)?;
    }
    let n = writer.finish()?;
    if !a.quiet {
        let _ = writeln!(out, "wrote {n} frames to {}", a.output.display());
    }
    Ok(())
}

/// Reads frame `p` as 8-bit sRGB; says so on `out` if its alpha is dropped.
fn read_frame(p: &Path, out: &mut dyn Write, quiet: bool) -> Result<Srgb8Image> {
    let (px, alpha) = crate::image::read_png_srgb8(p)?;
    if alpha && !quiet {
        let _ = writeln!(
            out,
            "{}: its alpha channel is dropped (a movie is opaque)",
            p.display()
        );
    }
    Ok(px)
}

/// The frame numbers of the files `pattern` names in its folder (the pattern in the file
/// name), from the lowest to the highest: every number between must have its file.
///
/// # Errors
/// [`Error::Invalid`] if the pattern is not in the file name, no file matches, a frame in the
/// range is missing (named), or the folder cannot be listed.
fn found_frames(pattern: &str) -> Result<Vec<u64>> {
    let path = Path::new(pattern);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let open = name
        .find('{')
        .filter(|_| expand(&name, 0).ok().flatten().is_some());
    let Some(open) = open else {
        return Err(Error::invalid(format!(
            "{pattern}: the frame pattern is not in the file name; give --frames A..B"
        )));
    };
    let close = open + name[open..].find('}').expect("expanded");
    let (head, tail) = (&name[..open], &name[close + 1..]);
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut found = Vec::new();
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let Some(digits) = file
            .strip_prefix(head)
            .and_then(|r| r.strip_suffix(tail))
            .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
        else {
            continue;
        };
        // Only the names the pattern gives (`{:04}`: 0007, not 7 or 00007).
        if let Ok(f) = digits.parse::<u64>()
            && expand(&name, f)?.as_deref() == Some(file.as_str())
        {
            found.push(f);
        }
    }
    found.sort_unstable();
    let (Some(&lo), Some(&hi)) = (found.first(), found.last()) else {
        return Err(Error::invalid(format!("{pattern}: no file matches")));
    };
    if hi - lo >= 10_000_000 {
        return Err(Error::invalid(format!(
            "{pattern}: frames {lo}..={hi} are more than 10 000 000; give --frames"
        )));
    }
    Ok((lo..=hi).collect())
}
