//! Rendering: camera, environment lighting, the film shader and the integrator.

pub mod camera;
pub mod environment;
pub mod integrator;
pub mod presets;
pub mod sampler;
pub mod shading;
pub mod views;

pub use camera::Camera;
pub use environment::{Environment, LatLongMap, SoftBox, Studio};
pub use integrator::{RenderOutput, RenderSettings, Scene, render};
pub use presets::{Preset, PresetValues};
pub use shading::{FilmShader, ShadingMode};
pub use views::{Legend, View, ViewImage, render_view};
