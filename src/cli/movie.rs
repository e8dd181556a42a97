//! `filmsplat render --frames … -o movie.mp4`: a sequence straight into a movie. Everything
//! that can be refused is refused before the first frame renders (ffmpeg on PATH, the
//! container, the frame rate and quality, an odd size, flags that need image files); the frames
//! are then rendered as a sequence ([`crate::pipeline::sequence`], one camera) and piped to
//! ffmpeg ([`crate::image::video`]), never written to disk.

use super::render_args::RenderArgs;
use crate::image::video::{self, Container, VideoSettings, VideoWriter};
use crate::pipeline::sequence::expand;
use crate::scene::SceneDesc;
use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// A movie a sequence is rendered into, checked.
pub(super) struct Movie {
    /// The movie file.
    path: PathBuf,
    /// Its container.
    container: Container,
    /// The `ffmpeg` found on PATH.
    ffmpeg: PathBuf,
    /// Frame rate and quality.
    settings: VideoSettings,
}

/// The movie `-o` names (.mp4, .webm), checked, or `None` for images. Refuses, before any
/// work: a movie name with a frame pattern, flags that need image files (`--shard`,
/// `--resume`, `--keep-going`, `--exr`; with the fix: images, then `filmsplat encode`), a
/// missing ffmpeg, a bad quality; and `--crf` for images.
///
/// # Errors
/// [`Error::Invalid`], one line naming the problem and the fix.
pub(super) fn movie_of(a: &RenderArgs, output: &Path) -> Result<Option<Movie>> {
    let Some(container) = Container::of(output) else {
        if a.crf.is_some() {
            return Err(Error::invalid(format!(
                "--crf sets a movie's quality; {} is not a movie (.mp4, .webm)",
                output.display()
            )));
        }
        return Ok(None);
    };
    let name = output.display();
    if expand(&output.to_string_lossy(), 0)?.is_some() {
        return Err(Error::invalid(format!(
            "{name}: a movie is one file: drop the frame pattern from its name"
        )));
    }
    let image_only = [
        (a.shard.is_some(), "--shard"),
        (a.resume, "--resume"),
        (a.keep_going, "--keep-going"),
        (a.exr.is_some(), "--exr"),
    ];
    if let Some((_, flag)) = image_only.iter().find(|(given, _)| *given) {
        return Err(Error::invalid(format!(
            "{flag} needs image files, and a movie is written in one run: render images \
             (-o 'out/{{:04}}.png' ... {flag}), then join them with `filmsplat encode \
             'out/{{:04}}.png' -o {name}`"
        )));
    }
    let settings = VideoSettings {
        fps: a.fps.unwrap_or(video::DEFAULT_FPS),
        crf: a.crf.unwrap_or(container.default_crf()),
    };
    settings.check(container)?;
    let ffmpeg = video::find_ffmpeg()?;
    check_movie_output(output)?;
    Ok(Some(Movie {
        path: output.to_path_buf(),
        container,
        ffmpeg,
        settings,
    }))
}

/// Refuses a movie output that is a directory, and makes sure its folder exists and takes
/// files (see [`crate::atomic::prepare_output`]).
///
/// # Errors
/// [`Error::Invalid`] naming the output.
pub(super) fn check_movie_output(output: &Path) -> Result<()> {
    if output.as_os_str() == "-" {
        return Err(Error::invalid(
            "-: a movie is written to a file, not to standard output (MP4's +faststart \
             rewrites the file's start when it is finished); give -o movie.mp4",
        ));
    }
    crate::pipeline::sequence::refuse_directories(&[output.to_path_buf()])?;
    crate::atomic::prepare_output(output)
}

impl Movie {
    /// Starts ffmpeg for the frames of `desc` (the sequence's first frame's scene: its image
    /// size, refused if odd). The sequence then pushes each frame into the writer; dropping it
    /// unfinished removes the movie's temporary and stops ffmpeg.
    ///
    /// # Errors
    /// [`Error::Invalid`] for an odd size; the writer's ([`VideoWriter::create`]).
    pub(super) fn start(&self, desc: &SceneDesc) -> Result<VideoWriter> {
        let size = crate::pipeline::config::image_size(desc);
        video::check_video_size(size.0, size.1)?;
        VideoWriter::create(&self.ffmpeg, &self.path, size, &self.settings)
    }

    /// Closes the movie (renamed into place) and says what was written on `out`.
    ///
    /// # Errors
    /// The writer's ([`VideoWriter::finish`]).
    pub(super) fn finish(
        &self,
        writer: VideoWriter,
        quiet: bool,
        out: &mut dyn Write,
    ) -> Result<()> {
        let size = writer.size();
        let frames = writer.finish()?;
        if !quiet {
            let _ = writeln!(out, "{}", self.summary(frames, size));
        }
        Ok(())
    }

    /// "wrote N frames (W×H, FPS fps, codec, CRF) to PATH".
    fn summary(&self, frames: u64, (w, h): (usize, usize)) -> String {
        let codec = match self.container {
            Container::Mp4 => "H.264",
            Container::Webm => "VP9",
        };
        format!(
            "wrote {frames} frames ({w}x{h}, {} fps, {codec} yuv420p, crf {}) to {}",
            self.settings.fps,
            self.settings.crf,
            self.path.display()
        )
    }
}
