//! `filmsplat render --frames`: the command line's side of a frame sequence (its patterns
//! checked, each frame's arguments); the loop itself is the library's
//! ([`crate::pipeline::sequence`]).

use super::render_args::RenderArgs;
use super::render_one::{Fresh, prepare_frame, ready_or_prepare, render_one, render_prepared};
use super::render_scene::scene_from_args;
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
    let out_pattern = output.to_string_lossy().into_owned();
    let is_toml = a.scene_file()?.is_some();
    let (scene, _) = scene_from_args(a)?;
    let mut patterned = false;
    for i in scene.input.paths() {
        patterned |= expand(&i.to_string_lossy(), 0)?.is_some();
    }
    // A turntable: one still cloud seen from a turning camera, prepared once.
    let still = !patterned && scene.input.sample.is_none();
    let orbit = scene.camera.orbit.is_some_and(|d| d != 0.0) || !scene.camera.key.is_empty();
    if expand(&out_pattern, 0)?.is_none() {
        return Err(Error::invalid(format!(
            "{out_pattern}: --frames needs a frame pattern ({{}} or {{:04}}) in -o"
        )));
    }
    if !is_toml && !patterned && !orbit {
        return Err(Error::invalid(format!(
            "{}: --frames needs a frame pattern ({{}} or {{:04}}) in an input, or --orbit \
             DEG for a turntable of one cloud",
            a.first_input()
        )));
    }
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
    let exr_pattern = a.exr.as_ref().map(|e| e.to_string_lossy().into_owned());
    let job = Frames {
        a: base,
        out_pattern,
        exr_pattern,
        still: still && orbit,
        kept: RefCell::new(None),
    };
    crate::pipeline::sequence::render_sequence(&job, &opts, out, &mut std::io::stderr())
}

/// The frames of one `render --frames` command line.
struct Frames {
    /// The command line's arguments without its frame list.
    a: RenderArgs,
    /// `-o`, with its frame pattern.
    out_pattern: String,
    /// `--exr`, if given (a frame pattern in it or not).
    exr_pattern: Option<String>,
    /// A turntable: every frame draws the same cloud (no frame pattern, no generated sample)
    /// from a moving camera, so it is prepared once and re-aimed.
    still: bool,
    /// A turntable's prepared cloud, kept between frames.
    kept: RefCell<Option<Prepared>>,
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
        let output = expand(&self.out_pattern, f)?.expect("checked");
        let exr = match &self.exr_pattern {
            Some(e) => Some(expand(e, f)?.unwrap_or_else(|| e.clone())),
            None => None,
        };
        Ok([Some(PathBuf::from(output)), exr.map(PathBuf::from)])
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
        if !self.still {
            return render_one(&one, out, ready);
        }
        let (desc, base) = scene_from_args(&one)?;
        let mut kept = self.kept.borrow_mut();
        let (mut prepared, fresh) = match kept.take() {
            Some(p) => (p, Fresh::Reaimed),
            None => (ready_or_prepare(&one, &desc, ready)?, Fresh::Prepared),
        };
        prepared.aim(&desc).map_err(|e| desc.locate(e))?;
        let output = super::render_one::output_path(&one, &desc, &base);
        crate::atomic::prepare_output(&output)?;
        let done = render_prepared(&one, &prepared, &output, fresh, out);
        *kept = Some(prepared);
        done
    }
}
