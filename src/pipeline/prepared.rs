//! What preparing a scene gives: everything ready to render, and notes for the user.

use super::framing::Framing;
use crate::image::{Grade, ToneMap};
use crate::render::{AttributeValues, FilmShader, RenderSettings, Scene, View};
use std::path::PathBuf;
use std::time::Duration;

/// Everything ready to render, plus what it cost to get here.
#[derive(Debug)]
pub struct Prepared {
    /// Geometry, camera and light.
    pub scene: Scene,
    /// What auto-framing frames of this cloud (used for the camera unless the scene names a
    /// position; a sequence frames once, see `framing`).
    pub framing: Framing,
    /// Width / height of the part of the image the scene fills (the image without a view's
    /// colour bar): the aspect auto-framing frames for.
    pub aspect: f32,
    /// Degrees the environment is turned about +y (a turntable's frame; see
    /// [`Prepared::turn_light`]).
    pub turn_deg: f32,
    /// The environment as prepared, before any turn (kept once it is first turned, so turning
    /// back gives it exactly).
    pub unturned: Option<crate::render::Environment>,
    /// The film shader.
    pub shader: FilmShader,
    /// Sampling settings.
    pub settings: RenderSettings,
    /// Exposure, EV.
    pub exposure: f32,
    /// Tone curve for PNG output.
    pub tonemap: ToneMap,
    /// Grading (white balance, contrast, saturation) before the tone curve.
    pub grade: Grade,
    /// What to show.
    pub view: View,
    /// Output path from the scene file, resolved against its folder.
    pub output: Option<PathBuf>,
    /// The values of an `attribute:NAME` view, one per film particle (`None` for other views).
    pub attribute: Option<AttributeValues>,
    /// Number of film particles.
    pub particles: usize,
    /// Number of droplets (water spheres).
    pub droplets: usize,
    /// Time spent loading or generating the cloud.
    pub load_time: Duration,
    /// Time spent estimating missing normals/radii.
    pub estimate_time: Duration,
    /// Time spent building the acceleration structure.
    pub build_time: Duration,
    /// Notes for the user (what was estimated, defaults applied).
    pub notes: Vec<Note>,
}

impl Prepared {
    /// Points this prepared scene's camera at `desc`'s `[camera]`, turns its light as `desc`
    /// turns it (a turntable) and takes its exposure (a
    /// turntable's next frame, a camera path's next key): the geometry stays as prepared, the
    /// droplets' pixel footprints follow the new camera, as a fresh preparation would set them.
    ///
    /// # Errors
    /// As [`super::camera`] for a bad `[camera]`; [`crate::Error::Invalid`] for a bad
    /// exposure.
    pub fn aim(&mut self, desc: &crate::scene::SceneDesc) -> crate::Result<()> {
        let camera = super::camera(desc, &self.framing, self.aspect)?;
        let height = self.settings.height;
        let droplets = &mut self.scene.staging.droplets;
        droplets.set_footprints(|c| camera.pixel_footprint(c, height))?;
        self.scene.camera = camera;
        self.turn_light(desc.environment.turn_deg);
        self.exposure = super::config::exposure(&desc.output)?;
        Ok(())
    }

    /// Turns the environment `deg` degrees about +y from where it was prepared (see
    /// [`crate::render::Environment::turn`]): exactly the prepared light again at 0, whatever
    /// turns came before. Costs a copy of the environment (a map's texels) when turned.
    pub fn turn_light(&mut self, deg: f32) {
        if deg == self.turn_deg {
            return;
        }
        let base = self
            .unturned
            .get_or_insert_with(|| self.scene.environment.clone());
        let mut env = base.clone();
        if deg != 0.0 {
            env.turn(deg);
        }
        self.scene.environment = env;
        self.turn_deg = deg;
    }

    /// Adds a note for the user.
    pub fn note(&mut self, text: impl Into<String>) {
        self.notes.push(Note::new(text));
    }
}

/// A note for the user about what preparing a scene did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Note {
    /// What happened (one or more lines).
    pub text: String,
    /// A routine report the CLI leaves out: an estimate that had nothing to fill.
    pub routine: bool,
    /// A warning: something in the input looks wrong (e.g. a thickness unit), shown even
    /// with `--quiet`.
    pub warning: bool,
}

impl Note {
    /// A note worth showing.
    pub fn new(text: impl Into<String>) -> Self {
        Note {
            text: text.into(),
            routine: false,
            warning: false,
        }
    }

    /// A warning (shown even when quiet).
    pub fn warning(text: impl Into<String>) -> Self {
        Note {
            warning: true,
            ..Note::new(text)
        }
    }

    /// Whether the CLI shows it: warnings always, other notes unless `quiet` or routine.
    pub fn shown(&self, quiet: bool) -> bool {
        !self.text.is_empty() && (self.warning || (!quiet && !self.routine))
    }

    /// The line the CLI prints: the text, after `filmsplat: warning: ` for a warning.
    pub fn message(&self) -> String {
        if self.warning {
            format!("filmsplat: warning: {}", self.text)
        } else {
            self.text.clone()
        }
    }
}

impl std::fmt::Display for Note {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}
