//! What preparing a scene gives: everything ready to render, and notes for the user.

use super::framing::Framing;
use super::shot::Shot;
use crate::render::{AttributeValues, Environment, FilmShader, Scene};
use std::borrow::Cow;
use std::path::PathBuf;
use std::time::Duration;

/// Everything ready to render, plus what it cost to get here. Never written to once prepared:
/// each render takes a [`Shot`] (camera, light turn, view, settings, exposure), so the CLI's
/// frames, the viewer's tabs and Python's calls share one `Prepared` (behind an `Arc` across
/// threads) and render it at once.
#[derive(Debug)]
pub struct Prepared {
    /// Geometry, distances, studio (droplets at their own size) and the environment as
    /// prepared, before any turn. Its camera is the scene file's, as prepared: renders take
    /// theirs from a [`Shot`] ([`Prepared::shot`] starts with this one).
    pub scene: Scene,
    /// What auto-framing frames of this cloud (used for the camera unless the scene names a
    /// position; a sequence frames once, see `framing`).
    pub framing: Framing,
    /// Width / height of the part of the image the scene fills (the image without a view's
    /// colour bar): the aspect auto-framing frames for.
    pub aspect: f32,
    /// The environment turned as the scene file turns it (its degrees and the turned copy;
    /// `None` when it is not turned), so the default shot's renders need no copy.
    pub(super) turned: Option<(f32, Environment)>,
    /// With an open shutter (`render.shutter`), the films at each time slice, in time order:
    /// a render averages them (see [`super::motion`]); empty when the shutter is closed.
    pub motion: Vec<super::motion::MotionSlice>,
    /// The film shader.
    pub shader: FilmShader,
    /// The picture the scene file describes: its camera, turn, view, settings and exposure.
    pub shot: Shot,
    /// Output path from the scene file, resolved against its folder.
    pub output: Option<PathBuf>,
    /// The values of an `attribute:NAME` view, one per film particle (`None` for other views).
    pub attribute: Option<AttributeValues>,
    /// The film particles as loaded, for the render summary's data-aware pinhole figure
    /// ([`super::pinholes::front_layer_of`]); `None` above
    /// [`super::film_data::FILM_DATA_CAP`] particles.
    pub film_data: Option<super::film_data::FilmData>,
    /// Some film's radii were kept because a sample of its particles needed no fit: the
    /// render warns if it then finds pinholes where the particles hold film.
    pub fit_screened: bool,
    /// Number of film particles.
    pub particles: usize,
    /// Number of droplets (water spheres).
    pub droplets: usize,
    /// Time spent loading or generating the cloud.
    pub load_time: Duration,
    /// Time spent estimating missing normals/radii.
    pub estimate_time: Duration,
    /// Time spent building the acceleration structure (with an open shutter, every slice's).
    pub build_time: Duration,
    /// Notes for the user (what was estimated, defaults applied).
    pub notes: Vec<Note>,
}

impl Prepared {
    /// The default shot aimed at `desc`'s `[camera]`, its light turned as `desc` turns it (a
    /// turntable) and its exposure taken (a turntable's next frame, a camera path's next key):
    /// the geometry stays as prepared; the droplets' pixel footprints follow the new camera
    /// when it renders, as a fresh preparation would set them.
    ///
    /// # Errors
    /// As [`super::camera`] for a bad `[camera]`; [`crate::Error::Invalid`] for a bad
    /// exposure.
    pub fn aimed(&self, desc: &crate::scene::SceneDesc) -> crate::Result<Shot> {
        Ok(Shot {
            camera: super::camera(desc, &self.framing, self.aspect)?,
            turn_deg: desc.environment.turn_deg,
            exposure: super::config::exposure(&desc.output)?,
            ..self.shot.clone()
        })
    }

    /// The environment turned `deg` degrees about +y from where it was prepared (see
    /// [`Environment::turn`]): exactly the prepared light at 0, whatever was rendered before.
    /// Costs a copy of the environment (a map's texels) for a turn other than 0 and the scene
    /// file's own.
    pub fn environment(&self, deg: f32) -> Cow<'_, Environment> {
        match &self.turned {
            _ if deg == 0.0 => Cow::Borrowed(&self.scene.environment),
            Some((d, env)) if *d == deg => Cow::Borrowed(env),
            _ => Cow::Owned(turned(&self.scene.environment, deg)),
        }
    }

    /// The light `shot` is rendered in: the built-in studio rigged to the shot's camera
    /// ([`crate::render::Studio::rigged_to`]: the dark ground behind the subject, the dome
    /// around, from any camera; an orbit's turn is in its camera already) and sized to the
    /// shot's picture ([`crate::render::Studio::framed`]), any other
    /// environment turned by the shot's `turn_deg` ([`Prepared::environment`]). Costs a copy
    /// of the studio (a few hundred bytes).
    pub fn environment_of(&self, shot: &Shot) -> Cow<'_, Environment> {
        match &self.scene.environment {
            Environment::Studio(s) => {
                let (w, h) = (shot.settings.width, shot.settings.height);
                Cow::Owned(Environment::Studio(
                    s.rigged_to(shot.camera.forward(), shot.camera.up())
                        .framed(shot.camera.tan_half_fov(), w as f32 / h.max(1) as f32),
                ))
            }
            _ => self.environment(shot.turn_deg),
        }
    }

    /// Adds a note for the user.
    pub fn note(&mut self, text: impl Into<String>) {
        self.notes.push(Note::new(text));
    }
}

/// `env` turned `deg` degrees about +y (a copy; the same copy at 0).
pub(super) fn turned(env: &Environment, deg: f32) -> Environment {
    let mut env = env.clone();
    if deg != 0.0 {
        env.turn(deg);
    }
    env
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
