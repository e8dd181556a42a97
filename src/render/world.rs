//! What a render sees and how it runs: the [`World`] (films, camera, lighting, studio), the
//! borrowed [`WorldRef`] a render reads it through, and the [`RenderSettings`]. Shared by the
//! integrator and the transport, so neither imports the other.

use super::camera::Camera;
use super::environment::Environment;
use super::lights::Light;
use super::props::Props;
use crate::geometry::{Droplets, FilmGeometry, GrownDroplets, LiquidSurface};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize};

/// What to render: geometry, camera, light. (Named `World` so it does not clash with
/// [`crate::scene`], the scene-file description; [`super::Scene`] is the same type.)
#[derive(Debug)]
pub struct World {
    /// The films.
    pub geometry: FilmGeometry,
    /// The camera.
    pub camera: Camera,
    /// The lighting.
    pub environment: Environment,
    /// Distance (scene units) a reflected ray skips before it may hit film again: about half a
    /// splat radius for disks, so the layer it left is not hit twice.
    pub layer_skip: f32,
    /// Small distance (scene units) against self-intersection, ~1e-5 of the scene's size.
    pub epsilon: f32,
    /// Area lights and props (empty by default: then rays pay nothing for them).
    pub staging: Staging,
}

/// What one render reads, all borrowed: the parts a prepared scene shares between renders
/// (films, studio, distances) and the render's own camera, lighting and droplet footprints. A
/// render never writes to it, so many renders of one prepared scene, each with its own camera,
/// run at once. `&World` converts into it (without droplet footprints).
#[derive(Debug, Clone, Copy)]
pub struct WorldRef<'a> {
    /// The films.
    pub geometry: &'a FilmGeometry,
    /// The camera.
    pub camera: &'a Camera,
    /// The lighting.
    pub environment: &'a Environment,
    /// As [`World::layer_skip`], scene units.
    pub layer_skip: f32,
    /// As [`World::epsilon`], scene units.
    pub epsilon: f32,
    /// Area lights, props, droplets, liquid.
    pub staging: &'a Staging,
    /// The droplets grown to this camera's pixel footprints (see
    /// [`Droplets::footprints`]); `None`: camera rays see the droplets at their own size.
    pub footprints: Option<&'a GrownDroplets>,
}

impl<'a> From<&'a World> for WorldRef<'a> {
    fn from(w: &'a World) -> Self {
        WorldRef {
            geometry: &w.geometry,
            camera: &w.camera,
            environment: &w.environment,
            layer_skip: w.layer_skip,
            epsilon: w.epsilon,
            staging: &w.staging,
            footprints: None,
        }
    }
}

/// The studio around the films: area lights and props.
#[derive(Debug, Clone, Default)]
pub struct Staging {
    /// Area lights.
    pub lights: Vec<Light>,
    /// Opaque props, each with its material.
    pub props: Props,
    /// Water droplets (the bulk fluid a rupturing film sheds): clear refracting spheres.
    pub droplets: Droplets,
    /// Bulk liquid (3D particles packed into bodies): a refracting body of water bounded by
    /// the particles' implicit surface.
    pub liquid: LiquidSurface,
}

/// Most camera samples per pixel, whichever way they are asked for (CLI flag, scene file,
/// Python): 65536, about a minute per 16×16 tile of a small scene.
pub const MAX_SPP: u32 = 65_536;

/// How to render it.
#[derive(Debug, Clone)]
pub struct RenderSettings {
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Camera samples per pixel (1..=[`MAX_SPP`]).
    pub spp: u32,
    /// Most film crossings along one path.
    pub max_depth: u32,
    /// Branches whose RGB weight falls below this escape to the environment.
    pub min_weight: f32,
    /// Russian roulette below this branch weight (0 = off, the deterministic ray tree): a
    /// branch of weight w < `roulette` is followed with probability w / `roulette`, otherwise
    /// it escapes to the environment. Unbiased (the escape view is a control variate); trades
    /// rays for noise in dim branches, which pays where crossings are many (spheres).
    pub roulette: f32,
    /// Random seed: the same seed gives the same image.
    pub seed: u64,
    /// Draw a progress bar on stderr (only when it is a terminal).
    pub progress: bool,
    /// Light samples (each: one per light, environment and material strategy) per prop hit.
    pub light_samples: u32,
    /// Indirect bounces between props (0: direct light only).
    pub prop_bounces: u32,
    /// Sample lights and environment at props (next-event estimation with MIS); `false`
    /// samples the material only (for checking: same mean, more noise).
    pub next_event: bool,
    /// Set it from another thread to stop the render: it is checked before each 16×16 tile,
    /// each pixel and every 64 camera samples, and the render then returns
    /// [`crate::Error::Cancelled`] (so a stop costs at most 64 samples of one pixel per core).
    pub cancel: Option<Arc<AtomicBool>>,
    /// Counts the finished 16×16 tiles (of `⌈width/16⌉·⌈height/16⌉`), for a caller's own
    /// progress display.
    pub tiles_done: Option<Arc<AtomicUsize>>,
}

/// Image width when none is given, pixels (every way in: flags, scene files, the viewer,
/// Python).
pub const DEFAULT_WIDTH: usize = 960;
/// Image height when none is given, pixels: 540 whatever the width (a scene giving only its
/// width renders at width×540).
pub const DEFAULT_HEIGHT: usize = 540;

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: DEFAULT_WIDTH,
            height: DEFAULT_HEIGHT,
            spp: 4,
            max_depth: 12,
            min_weight: 1e-3,
            roulette: 0.0,
            seed: 0,
            progress: false,
            light_samples: 1,
            prop_bounces: 1,
            next_event: true,
            cancel: None,
            tiles_done: None,
        }
    }
}
