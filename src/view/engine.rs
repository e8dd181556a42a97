//! The preview server's only door into the rendering engine: preparing a scene variant once,
//! rendering it again and again with new cameras, sizes and views, the camera as scene-file
//! lines, the attributes a scene offers. Every call into `pipeline`, `render` and `image` of
//! the view module is in this file, so a change of the engine's API is answered here alone.

use super::params::{Job, Pass, Variant, ViewCamera};
use super::picture::Picture;
use crate::geometry::Primitive;
use crate::image::{RgbImage, ToneMap, to_srgb8};
use crate::pipeline::{self, Prepared, Shot, framing, memory};
use crate::render::{Preset, RenderSettings, View};
use crate::scene::{CameraDesc, SceneDesc};
use crate::{Error, Result};
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// A prepared scene variant: geometry, shader and settings, built once and rendered from any
/// camera. Read only: renders of one variant (two tabs on one frame) run at once, each with
/// its own [`pipeline::Shot`].
#[derive(Debug)]
pub struct Built {
    /// The prepared scene; its default shot's settings are where each render starts.
    prepared: Prepared,
    /// The variant's scene description (its lens keys apply to every camera).
    desc: SceneDesc,
    /// Film particles.
    pub particles: usize,
    /// Droplets.
    pub droplets: usize,
    /// Estimated memory the variant holds, bytes.
    pub bytes: u64,
    /// Seconds spent loading, estimating and building.
    pub build_seconds: f64,
}

/// What the scene file and flags choose, shown as the page's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Defaults {
    /// Image size, pixels.
    pub size: (usize, usize),
    /// How the particles are drawn.
    pub primitive: Primitive,
    /// The scene's view (`shaded`, ..., `attribute:NAME`).
    pub view: String,
    /// Exposure, EV.
    pub exposure: f32,
}

/// The scene's defaults (before anything is prepared).
pub fn defaults(desc: &SceneDesc) -> Defaults {
    Defaults {
        size: pipeline::config::image_size(desc),
        // A bad name is refused when the frame is prepared (before the server serves).
        primitive: pipeline::config::primitive(desc).unwrap_or_default(),
        view: desc.render.view.clone().unwrap_or_else(|| "shaded".into()),
        exposure: desc.output.exposure.unwrap_or(0.0),
    }
}

/// `desc` with the variant's primitive, preset (replacing the sampling keys, as `render
/// --preset` does) and view.
fn variant_desc(desc: &SceneDesc, v: &Variant) -> SceneDesc {
    let mut d = desc.clone();
    if let Some(p) = &v.primitive {
        d.film.primitive = Some(p.name().to_string());
    }
    if let Some(p) = &v.preset {
        d.set_preset(p);
    }
    // Attribute values are gathered only for the variant that shows them.
    d.render.view = v.attribute.as_ref().map(|a| format!("attribute:{a}"));
    d
}

/// Prepares variant `v` of the frame described by `desc` (paths relative to `base`): loads the
/// particles, estimates what is missing, builds the geometry. Costs what `filmsplat render`
/// spends before its first ray.
///
/// # Errors
/// As [`pipeline::prepare`].
pub fn build(desc: &SceneDesc, base: &Path, v: &Variant) -> Result<Built> {
    let desc = variant_desc(desc, v);
    let t = Instant::now();
    let p = pipeline::prepare(&desc, base, false).map_err(|e| desc.locate(e))?;
    let count = (p.particles + p.droplets) as u64;
    Ok(Built {
        particles: p.particles,
        droplets: p.droplets,
        bytes: count * (memory::GEOMETRY_BYTES_PER_PARTICLE + 4) + memory::FIXED_BYTES,
        build_seconds: t.elapsed().as_secs_f64(),
        prepared: p,
        desc,
    })
}

/// The camera the page starts from: the scene's (its position, or auto-framed on `built`'s
/// cloud as `render --frames` frames a sequence on its first frame).
///
/// # Errors
/// As [`framing::sequence_camera`].
pub fn start_camera(desc: &SceneDesc, built: &Built) -> Result<ViewCamera> {
    let p = &built.prepared;
    let c = framing::sequence_camera(desc, &p.framing, p.aspect)?
        .unwrap_or_else(|| desc.camera.clone());
    let position = c
        .position
        .ok_or_else(|| Error::Internal("start camera without a position".into()))?;
    Ok(ViewCamera {
        position,
        look_at: c.look_at.unwrap_or(p.framing.centre.to_array()),
        up: c.up.unwrap_or(framing::DEFAULT_UP),
        fov: c.fov.unwrap_or(40.0),
    })
}

/// The scene's `[camera]` with the page's position, look-at, up and field of view.
fn camera_desc(desc: &SceneDesc, cam: &ViewCamera) -> CameraDesc {
    CameraDesc {
        position: Some(cam.position),
        look_at: Some(cam.look_at),
        up: Some(cam.up),
        fov: Some(cam.fov),
        ..desc.camera.clone()
    }
}

/// The scene-file lines that render `cam` (position, look-at, field of view, up, and the
/// scene's lens if it has one), every number read back to the same `f32`.
pub fn camera_lines(desc: &SceneDesc, cam: &ViewCamera) -> String {
    let c = camera_desc(desc, cam);
    let mut s = framing::camera_toml(&c);
    if let Some(a) = c.aperture {
        s += &format!("aperture = {a:?}\n");
    }
    if let Some(f) = c.focus_distance {
        s += &format!("focus_distance = {f:?}\n");
    }
    s
}

/// The `[[camera.key]]` lines of a camera path's key that holds `cam` at frame `frame`
/// (position, look-at, field of view, and the scene's lens if it has one); the path's keys
/// must all give the same optional keys, as copying them from here does.
pub fn key_lines(desc: &SceneDesc, cam: &ViewCamera, frame: u64) -> String {
    let key = crate::scene::CameraKey {
        frame,
        position: cam.position,
        look_at: Some(cam.look_at),
        fov: Some(cam.fov),
        aperture: desc.camera.aperture,
        focus_distance: desc.camera.focus_distance,
        ..Default::default()
    };
    crate::pipeline::camera_path::key_toml(&key)
}

/// Film crossings followed while the camera moves: the front and the back wall of a bubble
/// (at most 2; the preview preset follows 4). Depth dominates the cost of a small picture: on
/// the bubble at 240×135, 2 crossings took 0.05 s where 4 took 0.12 s, and the picture only
/// lacks the faint inner reflections, which come back as it refines.
pub const MOVE_DEPTH: u32 = 2;

/// The sampling of `pass`: the prepared settings (`Final`); 1 sample per pixel and at most the
/// preview preset's depth and weight cut-off (`Draft`); and at most [`MOVE_DEPTH`] crossings
/// (`Move`).
fn pass_settings(base: &RenderSettings, job: &Job, cancel: Arc<AtomicBool>) -> RenderSettings {
    let mut s = base.clone();
    (s.width, s.height) = (job.width, job.height);
    s.progress = false;
    s.cancel = Some(cancel);
    if job.pass != Pass::Final {
        let preview = Preset::Preview.values();
        s.spp = 1;
        s.max_depth = s.max_depth.min(preview.max_depth);
        s.min_weight = s.min_weight.max(preview.min_weight);
    }
    if job.pass == Pass::Move {
        s.max_depth = s.max_depth.min(MOVE_DEPTH);
    }
    s
}

/// Renders `job` on `built` (a `Final` pass gives exactly the pixels `filmsplat render` gives
/// for the same scene, camera lines, size and view). `cancel` raised stops a shaded render
/// within a tile per thread ([`Error::Cancelled`]).
///
/// # Errors
/// [`Error::Cancelled`]; [`Error::Invalid`] for a view the scene cannot show.
pub fn render(built: &Built, job: &Job, cancel: Arc<AtomicBool>) -> Result<Picture> {
    let view: View = job
        .view
        .parse()
        .map_err(|e: String| Error::invalid(format!("view: {e}")))?;
    let p = &built.prepared;
    let settings = pass_settings(&p.shot.settings, job, cancel);
    let spp = settings.spp;
    let desc = SceneDesc {
        camera: camera_desc(&built.desc, &job.camera),
        ..SceneDesc::default()
    };
    let aspect = pipeline::scene_aspect(&view, job.width, job.height);
    let shot = Shot {
        camera: pipeline::camera(&desc, &p.framing, aspect)?,
        view: view.clone(),
        settings,
        ..p.shot.clone()
    };
    let t = Instant::now();
    let rgb8 = if let Some(v) = pipeline::render_view(p, &shot)? {
        let data = v.rgb.iter().map(|c| c.to_array()).collect();
        to_srgb8(
            &RgbImage::from_data(v.width, v.height, data)?,
            0.0,
            ToneMap::Clamp,
        )
    } else {
        let out = pipeline::render(p, &shot)?;
        let data = out.rgb.iter().map(|c| c.to_array()).collect();
        let img = shot
            .grade
            .apply(&RgbImage::from_data(out.width, out.height, data)?);
        to_srgb8(&img, job.exposure.unwrap_or(shot.exposure), shot.tonemap)
    };
    Ok(Picture {
        width: job.width,
        height: job.height,
        rgb8,
        spp: if view == View::Shaded { spp } else { 1 },
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// Refuses a picture whose buffers would not fit in the memory available.
pub fn check_pixels(width: usize, height: usize) -> std::result::Result<(), String> {
    let pixels = width as u64 * height as u64;
    crate::budget::check(
        pixels * (memory::RENDER_BYTES_PER_PIXEL + memory::PNG_BYTES_PER_PIXEL),
        || format!("a {width}x{height} picture"),
    )
}

/// The names an `attribute:NAME` view accepts for the scene: each film part's stored
/// attributes, vectors (NAME_x, _y, _z) by their NAME, and `thickness` and `radius`. A
/// generated sample is asked at 1000 particles (its attributes do not depend on the count).
///
/// # Errors
/// As [`pipeline::load_parts`].
pub fn attribute_names(desc: &SceneDesc, base: &Path) -> Result<Vec<String>> {
    let mut d = desc.clone();
    if d.input.sample.is_some() {
        d.input.particles = Some(1000);
    }
    let parts = pipeline::load_parts(&d, base)?;
    let mut names: Vec<String> = vec!["thickness".into(), "radius".into()];
    for part in parts.iter().filter(|p| p.kind == crate::io::PartKind::Film) {
        for (name, _) in &part.cloud.extra {
            let vector = name
                .strip_suffix("_x")
                .filter(|b| part.cloud.extra(&format!("{b}_y")).is_some());
            for n in [Some(name.as_str()), vector].into_iter().flatten() {
                if !names.iter().any(|k| k == n) {
                    names.push(n.to_string());
                }
            }
        }
    }
    Ok(names)
}
