//! Rendering: camera, environment and area lights, prop materials, the film shader and the
//! integrator.

pub mod camera;
mod droplet;
pub mod env_sampling;
pub mod environment;
pub mod integrator;
pub mod lights;
mod liquid;
pub mod material;
pub mod presets;
mod primary;
pub mod props;
pub mod radiance;
pub mod sampler;
pub mod shading;
mod studio;
mod transport;
pub mod views;
pub mod world;

pub use camera::Camera;
pub use environment::{Environment, LatLongMap, SoftBox, Studio};
pub use integrator::{RenderOutput, render};
pub use world::{DEFAULT_HEIGHT, DEFAULT_WIDTH, MAX_SPP, RenderSettings, Staging, World, WorldRef};

/// The old name of [`World`] (kept so callers need not change).
pub type Scene = World;
pub use lights::{AreaLight, Light, LightShape};
pub use material::Material;
pub use presets::{Preset, PresetValues};
pub use props::{Prop, PropHit, Props};
pub use shading::{FilmShader, ShadingMode};
pub use views::{AttributeValues, Legend, Ramp, View, ViewImage, render_view, render_view_of};
