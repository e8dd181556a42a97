//! One picture of a prepared scene: its camera, the turn of its light, its view, sampling and
//! exposure. A small value made for each render; the prepared scene it is rendered from is
//! never written to, so renders of one scene with different shots run at once.

use crate::image::{Grade, ToneMap};
use crate::render::{Camera, RenderSettings, View};

/// What one render of a [`super::Prepared`] scene chooses: everything that may differ between
/// two pictures of the same prepared particles (a turntable's frames, a camera path's keys,
/// the viewer's tabs, Python's `Scene.render` calls). [`super::Prepared::shot`] is the one the
/// scene file describes; change fields of a copy for another picture.
#[derive(Debug, Clone)]
pub struct Shot {
    /// The camera (the droplets' pixel footprints follow it: see [`super::render`]).
    pub camera: Camera,
    /// Degrees the environment is turned about +y from where it was prepared (a turntable's
    /// frame; see [`crate::render::Environment::turn`]); 0: the light as prepared.
    pub turn_deg: f32,
    /// What to show.
    pub view: View,
    /// Sampling settings, image size and the render's cancel flag and progress.
    pub settings: RenderSettings,
    /// Exposure, EV.
    pub exposure: f32,
    /// Tone curve for PNG output.
    pub tonemap: ToneMap,
    /// Grading (white balance, contrast, saturation) before the tone curve.
    pub grade: Grade,
}
