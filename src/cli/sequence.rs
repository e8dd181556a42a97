//! `filmsplat render --frames`: the command line's side of a frame sequence (its patterns
//! checked, each frame's arguments); the loop itself is the library's
//! ([`crate::pipeline::sequence`]).

use super::render_args::RenderArgs;
use super::render_one::{
    Fresh, Target, output_path, prepare_frame, ready_or_prepare, render_one, render_prepared,
};
use super::render_scene::scene_from_args;
use crate::image::video::VideoWriter;
use crate::pipeline::Prepared;
use crate::pipeline::camera_path::FrameCamera;
use crate::pipeline::sequence::{FrameJob, SequenceOptions, expand};
use crate::scene::SceneDesc;
use crate::{Error, Result};
use std::cell::RefCell;
use std::io::Write;
use std::path::PathBuf;

/// Renders the sequence `frames` of `render --frames`: checks the patterns, then runs the
/// library's loop over this command line's frames.
pub(super) fn render_sequence(a: &RenderArgs, frames: &[u64], out: &mut dyn Write) -> Result<()> {
    let output = a.output.as_ref().ok_or_else(|| {
        Error::invalid("--frames needs -o with a frame pattern, e.g. -o 'out/{:04}.png'")
    })?;
    let movie = super::movie::movie_of(a, output)?;
    let out_pattern = output.to_string_lossy().into_owned();
    let still = check_patterns(a, output, movie.is_some())?;
    // A mistake in the scene or flags is refused before any frame is read (the image size
    // against --max-memory's allowance too, set by `render::run`).
    let (first, first_base) = scene_from_args(&with_frame(a, frames[0]))?;
    first.resolve(&first_base).map_err(|e| first.locate(e))?;
    let opts = SequenceOptions {
        frames: frames.to_vec(),
        shard: a.shard,
        frame_all: a.frame_all,
        resume: a.resume,
        keep_going: a.keep_going,
        quiet: a.quiet,
    };
    // One copy of the arguments without the frame list: each frame's copy is then small
    // (copying the list for every frame made the checks quadratic in the frames).
    let mut base = a.clone();
    base.frames = None;
    base.frame_all = false;
    // With a shutter, every frame of this shard's velocities, before ffmpeg or a frame starts.
    if !a.keep_going {
        let mine = crate::pipeline::sequence::sharded(frames, a.shard);
        crate::pipeline::velocity_check::check_frames(&mine, |f| {
            scene_from_args(&with_frame(&base, f))
        })?;
    }
    let exr_pattern = a.exr.as_ref().map(|e| e.to_string_lossy().into_owned());
    let job = Frames {
        a: base,
        out_pattern: movie.is_none().then_some(out_pattern),
        exr_pattern,
        still,
        kept: RefCell::new(None),
        movie: None,
    };
    let Some(m) = movie else {
        return crate::pipeline::sequence::render_sequence(
            &job,
            &opts,
            out,
            &mut std::io::stderr(),
        );
    };
    // Into the movie: ffmpeg starts before the first frame; on an error the writer is dropped
    // unfinished, which removes the movie's temporary.
    let writer = m.start(&job.scene(frames[0])?)?;
    let mut job = job;
    job.movie = Some(RefCell::new(writer));
    crate::pipeline::sequence::render_sequence(&job, &opts, out, &mut std::io::stderr())?;
    let writer = job.movie.take().expect("set above").into_inner();
    m.finish(writer, opts.quiet, out)
}

/// `a` for frame `f` alone (its inputs' patterns expanded; outputs as given).
fn with_frame(a: &RenderArgs, f: u64) -> RenderArgs {
    RenderArgs {
        frame: Some(f),
        frames: None,
        ..a.clone()
    }
}

/// Checks the sequence's patterns: -o names images with a frame pattern or a movie; an input
/// has a frame pattern, or the camera moves (an orbit or keys) over one still cloud. Returns
/// whether it is such a turntable (one cloud, prepared once and re-aimed).
fn check_patterns(a: &RenderArgs, output: &std::path::Path, movie: bool) -> Result<bool> {
    let out_pattern = output.to_string_lossy();
    if !movie && expand(&out_pattern, 0)?.is_none() {
        crate::pipeline::check_extension(output).map_err(|_| {
            Error::invalid(format!(
                "{out_pattern}: -o must be images with a frame pattern ('out/{{:04}}.png' or \
                 .exr) or a movie (.mp4, .webm)"
            ))
        })?;
        return Err(Error::invalid(format!(
            "{out_pattern}: --frames needs a frame pattern ({{}} or {{:04}}) in -o, or a \
             movie (-o movie.mp4)"
        )));
    }
    let is_toml = a.scene_file()?.is_some();
    let (scene, _) = scene_from_args(a)?;
    let mut patterned = false;
    for i in scene.input.paths() {
        patterned |= expand(&i.to_string_lossy(), 0)?.is_some();
    }
    let still = !patterned && scene.input.sample.is_none();
    let orbit = scene.camera.orbit.is_some_and(|d| d != 0.0) || !scene.camera.key.is_empty();
    if !is_toml && !patterned && !orbit {
        return Err(Error::invalid(format!(
            "{}: --frames needs a frame pattern ({{}} or {{:04}}) in an input, or --orbit \
             DEG for a turntable of one cloud",
            a.first_input()
        )));
    }
    Ok(still && orbit)
}

/// The frames of one `render --frames` command line.
struct Frames {
    /// The command line's arguments without its frame list.
    a: RenderArgs,
    /// `-o`, with its frame pattern; `None` for a movie (its frames write no image).
    out_pattern: Option<String>,
    /// `--exr`, if given (a frame pattern in it or not).
    exr_pattern: Option<String>,
    /// A turntable: every frame draws the same cloud (no frame pattern, no generated sample)
    /// from a moving camera, so it is prepared once and re-aimed.
    still: bool,
    /// A turntable's prepared cloud, kept between frames.
    kept: RefCell<Option<Prepared>>,
    /// The movie the frames go into, if -o names one.
    movie: Option<RefCell<VideoWriter>>,
}

impl Frames {
    /// The arguments of frame `f`: its outputs and seed (the seed plus the frame number); each
    /// input's pattern is expanded for `frame` by [`scene_from_args`].
    fn args(&self, f: u64) -> Result<RenderArgs> {
        let mut one = self.a.clone();
        one.frame = Some(f);
        let [output, exr] = self.output_paths(f)?;
        (one.output, one.exr) = (output, exr);
        one.seed = Some(self.a.seed.unwrap_or(0).wrapping_add(f));
        Ok(one)
    }

    /// Frame `f`'s image and EXR paths, from the patterns alone (no copy of the arguments).
    fn output_paths(&self, f: u64) -> Result<[Option<PathBuf>; 2]> {
        let output = match &self.out_pattern {
            Some(o) => Some(expand(o, f)?.expect("checked")),
            None => None,
        };
        let exr = match &self.exr_pattern {
            Some(e) => Some(expand(e, f)?.unwrap_or_else(|| e.clone())),
            None => None,
        };
        Ok([output.map(PathBuf::from), exr.map(PathBuf::from)])
    }

    /// Renders frame `one` (its arguments, camera set): to its files, or into the movie; a
    /// turntable's frames draw the cloud prepared for the first one, re-aimed.
    fn write(&self, one: &RenderArgs, out: &mut dyn Write, ready: Option<Prepared>) -> Result<()> {
        if !self.still && self.movie.is_none() {
            return render_one(one, out, ready);
        }
        let mut one = one.clone();
        one.in_memory = self.movie.is_some();
        let (desc, base) = scene_from_args(&one)?;
        let mut kept = self.kept.borrow_mut();
        let (prepared, fresh) = match kept.take() {
            Some(p) => (p, Fresh::Reaimed),
            None => (ready_or_prepare(&one, &desc, ready)?, Fresh::Prepared),
        };
        // A turntable's frame: the prepared cloud seen from this frame's camera and light.
        let shot = if self.still {
            prepared.aimed(&desc).map_err(|e| desc.locate(e))?
        } else {
            prepared.shot.clone()
        };
        let output = output_path(&one, &desc, &base);
        let target = match &self.movie {
            Some(_) => Target::Pixels,
            None => {
                crate::atomic::prepare_output(&output)?;
                Target::File(&output)
            }
        };
        let done = render_prepared(&one, &prepared, shot, target, fresh, out);
        if self.still {
            *kept = Some(prepared);
        }
        match (done?, &self.movie) {
            (Some(px), Some(movie)) => movie.borrow_mut().push(px.width, px.height, &px.data),
            _ => Ok(()),
        }
    }
}

impl FrameJob for Frames {
    fn outputs(&self, f: u64) -> Result<Vec<PathBuf>> {
        Ok(self.output_paths(f)?.into_iter().flatten().collect())
    }

    fn inputs(&self, f: u64) -> Result<Vec<PathBuf>> {
        let (desc, base) = scene_from_args(&self.args(f)?)?;
        let paths = desc.input.paths();
        Ok(paths
            .into_iter()
            .filter(|p| p.as_os_str() != "-")
            .map(|p| base.join(p))
            .collect())
    }

    fn scene(&self, f: u64) -> Result<SceneDesc> {
        scene_from_args(&self.args(f)?).map(|(d, _)| d)
    }

    fn prepare(&self, f: u64) -> Result<Prepared> {
        prepare_frame(&self.args(f)?, crate::pipeline::Progress::Off)
    }

    fn render(
        &self,
        f: u64,
        camera: Option<&FrameCamera>,
        ready: Option<Prepared>,
        out: &mut dyn Write,
    ) -> Result<()> {
        let mut one = self.args(f)?;
        if let Some(FrameCamera {
            camera: c,
            exposure,
            turn_deg,
        }) = camera
        {
            one.turn_deg = *turn_deg;
            one.camera = c.position;
            one.look_at = c.look_at;
            (one.fov, one.aperture) = (c.fov.or(one.fov), c.aperture.or(one.aperture));
            one.focus_distance = c.focus_distance.or(one.focus_distance);
            one.exposure = exposure.or(one.exposure);
        }
        self.write(&one, out, ready)
    }
}
