//! The typed configuration of a render. [`SceneDesc::resolve`] turns a scene description
//! (strings, optional keys, from a scene file and the command line's flags) into a
//! [`RenderConfig`]: every enum parsed, every default applied, every number checked, each error
//! naming its key. It is the one place that validates the description; the stages after it
//! (`load`, `build`, `output`) take the typed values.
//!
//! It covers every section, `[input]` and `film.thickness_unit` (`input_config`; a
//! cloud given in memory replaces them), `[[light]]` and `[[prop]]` (`lights_props`)
//! too: a mistake anywhere is refused before any particle is read. What depends on the loaded
//! scene (lights facing its centre, the camera's framing, distances from its size) is filled
//! in after loading, from values checked here.

pub use super::environment_config::EnvironmentConfig;
pub use super::image_size::image_size;
pub use super::shutter::ShutterConfig;
use crate::geometry::Primitive;
use crate::image::{Grade, ToneMap};
use crate::optics::check_film_params;
use crate::render::{MAX_SPP, Preset, RenderSettings, ShadingMode, View};
use crate::scene::{CameraDesc, OutputDesc, SceneDesc};
use crate::spectrum::WavelengthStrategy;

use super::environment_config::{environment, vec3};
use super::fit_mode::{FitRadii, fit_mode};
use super::input_config::InputConfig;
use super::lights_props::{LightConfig, PropConfig};
use crate::{Error, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Default direction from the cloud toward an auto-framed camera.
pub const DEFAULT_FROM: [f32; 3] = [0.35, 0.3, 1.0];
/// Default vertical field of view, degrees.
pub const DEFAULT_FOV: f32 = 40.0;
/// Default up direction.
pub const DEFAULT_UP: [f32; 3] = [0.0, 1.0, 0.0];

/// A render's settings, typed and checked (see the module docs).
#[derive(Debug, Clone)]
pub struct RenderConfig {
    /// The film's optics and splats.
    pub film: FilmConfig,
    /// The preset that filled the sampling settings left unset.
    pub preset: Preset,
    /// Sampling settings (image size in pixels, spp, depth, ...); the progress bar off.
    pub settings: RenderSettings,
    /// How the film is shaded.
    pub shading: ShadingMode,
    /// Wavelengths per camera sample for RGB and spectral shading.
    pub wavelengths: usize,
    /// How those wavelengths are chosen.
    pub strategy: WavelengthStrategy,
    /// What to show.
    pub view: View,
    /// The attribute shown by an `attribute:NAME` view (`None` for other views).
    pub attribute: Option<AttributeView>,
    /// The camera.
    pub camera: CameraConfig,
    /// The light around the scene.
    pub environment: EnvironmentConfig,
    /// Output file and tone mapping.
    pub output: OutputConfig,
    /// Where the particles come from.
    pub input: InputConfig,
    /// `[[light]]`s (placed in the loaded scene by `studio::staging`).
    pub lights: Vec<LightConfig>,
    /// `[[prop]]`s (a mesh's file is read by `studio::props`).
    pub props: Vec<PropConfig>,
    /// Motion blur: the open shutter (`None`: closed, the default).
    pub shutter: Option<ShutterConfig>,
}

/// `[film]`, checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmConfig {
    /// Film index of refraction.
    pub ior: f32,
    /// How particles are drawn.
    pub primitive: Primitive,
    /// Factor on thickness after the unit conversion (>= 0).
    pub thickness_scale: f32,
    /// Thickness of particles without one, nm.
    pub default_thickness_nm: f32,
    /// Factor on every splat radius (> 0).
    pub radius_scale: f32,
    /// Disks tilt with the film's curvature and follow its thickness gradient.
    pub first_order_detail: bool,
    /// When radii are fitted to the sampling (disks and MLS; never for spheres).
    pub fit_radii: FitRadii,
    /// Overlapping disks of one layer blend into one crossing.
    pub blend: bool,
}

/// The attribute of an `attribute:NAME` view.
#[derive(Debug, Clone, PartialEq)]
pub struct AttributeView {
    /// NAME: a stored attribute, a vector's name without `_x/_y/_z`, `thickness` or `radius`.
    pub name: String,
    /// Values at the ends of the colour bar (`None`: the range of what is visible).
    pub range: Option<(f32, f32)>,
}

/// `[camera]`, checked. Scene units; the focus distance default depends on the framing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraConfig {
    /// Eye position (`None`: auto-framed).
    pub position: Option<Vec3>,
    /// Point looked at (`None`: the framing's centre).
    pub look_at: Option<Vec3>,
    /// Up direction.
    pub up: Vec3,
    /// Vertical field of view, degrees (1..170).
    pub fov_deg: f32,
    /// Direction from the cloud toward an auto-framed camera.
    pub from: Vec3,
    /// `from` is the default (the scene names none): auto-framing may raise it to see a flat
    /// film from above its plane ([`super::framing::view_direction`]).
    pub from_default: bool,
    /// Thin-lens aperture radius (>= 0; 0 is a pinhole).
    pub aperture: f32,
    /// Distance in focus (> 0; `None`: the distance to the target).
    pub focus_distance: Option<f32>,
}

/// `[output]`, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputConfig {
    /// Output image, resolved against the scene's folder.
    pub path: Option<PathBuf>,
    /// Exposure, EV (-64..64).
    pub exposure_ev: f32,
    /// Tone curve for PNG output.
    pub tonemap: ToneMap,
    /// White balance, contrast and saturation before the tone curve.
    pub grade: Grade,
}

fn parse_enum<T: std::str::FromStr>(v: &Option<String>, default: T, key: &str) -> Result<T>
where
    T::Err: std::fmt::Display,
{
    match v {
        None => Ok(default),
        Some(s) => s.parse().map_err(|e| Error::invalid(format!("{key}: {e}"))),
    }
}

impl SceneDesc {
    /// The typed, checked configuration of this description; paths are resolved against
    /// `base` (the scene file's folder). Cost: parsing a few strings; reads no file.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the first bad key and its value (see [`SceneDesc::locate`] to
    /// add the scene file's line).
    pub fn resolve(&self, base: &Path) -> Result<RenderConfig> {
        self.resolve_for(base, false)
    }

    /// [`SceneDesc::resolve`]; with `given_cloud` the particles are given in memory (the
    /// Python API) and `[input]` is not checked (it is not read).
    ///
    /// # Errors
    /// As [`SceneDesc::resolve`].
    pub fn resolve_for(&self, base: &Path, given_cloud: bool) -> Result<RenderConfig> {
        let (ior, primitive) = optics(self)?;
        let preset: Preset = parse_enum(&self.render.preset, Preset::Balanced, "render.preset")?;
        let defaults = preset.values();
        let shading = parse_enum(&self.render.shading, defaults.shading, "render.shading")?;
        let strategy = parse_enum(
            &self.render.strategy,
            WavelengthStrategy::Jittered,
            "render.strategy",
        )?;
        let tonemap = parse_enum(&self.output.tonemap, ToneMap::Filmic, "output.tonemap")?;
        let view: View = parse_enum(&self.render.view, View::Shaded, "render.view")?;
        let settings = settings(self, preset, primitive)?;
        let exposure_ev = exposure(&self.output)?;
        let wavelengths = wavelengths(
            self.render.wavelengths.unwrap_or(defaults.wavelengths),
            shading,
        )?;
        let film = film(self, ior, primitive, preset)?;
        let attribute = match &view {
            View::Attribute(name) => Some(attribute_view(self, name)?),
            _ => None,
        };
        let shutter = ShutterConfig::resolve(self, &view)?;
        Ok(RenderConfig {
            shutter,
            film,
            preset,
            settings,
            shading,
            wavelengths,
            strategy,
            view,
            attribute,
            camera: CameraConfig::resolve(&self.camera)?,
            environment: environment(&self.environment, base)?,
            output: OutputConfig {
                path: self.output.path.as_ref().map(|p| base.join(p)),
                exposure_ev,
                tonemap,
                grade: grade(&self.output)?,
            },
            input: super::input_config::input(self, given_cloud)?,
            lights: super::lights_props::lights(self)?,
            props: super::lights_props::props(self, base)?,
        })
    }
}

/// `film.ior` and `film.primitive` (the rest is checked after the sampling, by [`film`]).
fn optics(d: &SceneDesc) -> Result<(f32, Primitive)> {
    let ior = d.film.ior.unwrap_or(1.33);
    check_film_params(ior as f64, 0.0).map_err(|m| Error::invalid(format!("film.ior: {m}")))?;
    Ok((ior, primitive(d)?))
}

/// `film.primitive` (default: [`Primitive::default`]).
///
/// # Errors
/// [`Error::Invalid`] naming the key for an unknown name.
pub fn primitive(d: &SceneDesc) -> Result<Primitive> {
    parse_enum(&d.film.primitive, Primitive::default(), "film.primitive")
}

/// `[film]` with its defaults: checks the default thickness and the thickness and radius
/// factors.
fn film(d: &SceneDesc, ior: f32, primitive: Primitive, preset: Preset) -> Result<FilmConfig> {
    let f = &d.film;
    let default_thickness_nm = f.default_thickness_nm.unwrap_or(500.0);
    check_film_params(ior as f64, default_thickness_nm as f64)
        .map_err(|m| Error::invalid(format!("film.default_thickness_nm: {m}")))?;
    let thickness_scale = f.thickness_scale.unwrap_or(1.0);
    if !(thickness_scale.is_finite() && thickness_scale >= 0.0) {
        return Err(Error::invalid(format!(
            "film.thickness_scale must be >= 0, got {thickness_scale}"
        )));
    }
    let radius_scale = f.radius_scale.unwrap_or(1.0);
    if !(radius_scale.is_finite() && radius_scale > 0.0) {
        return Err(Error::invalid(format!(
            "film.radius_scale must be > 0, got {radius_scale}"
        )));
    }
    Ok(FilmConfig {
        ior,
        primitive,
        thickness_scale,
        default_thickness_nm,
        radius_scale,
        // First-order detail on disks unless the scene or the preset turns it off.
        first_order_detail: primitive.takes_first_order_detail()
            && f.curvature.unwrap_or(preset.first_order_detail()),
        fit_radii: match fit_mode(f.fit_radii.as_ref())? {
            _ if !primitive.fits_radii() => FitRadii::Never,
            mode => mode,
        },
        blend: f.blend != Some(false),
    })
}

/// `[render]`'s sampling settings, the preset filling what is unset; checks the image size
/// (also against the memory allowance), roulette and minimum weight.
fn settings(d: &SceneDesc, preset: Preset, primitive: Primitive) -> Result<RenderSettings> {
    let r = &d.render;
    let defaults = preset.values();
    let settings = RenderSettings {
        width: image_size(d).0,
        height: image_size(d).1,
        spp: r.spp.unwrap_or(defaults.spp),
        max_depth: r.max_depth.unwrap_or(defaults.max_depth).min(64),
        min_weight: r.min_weight.unwrap_or(defaults.min_weight),
        roulette: r.roulette.unwrap_or(preset.roulette(primitive)),
        seed: r.seed.unwrap_or(0),
        progress: false,
        light_samples: r.light_samples.unwrap_or(1).clamp(1, 1024),
        prop_bounces: r.prop_bounces.unwrap_or(1).min(8),
        ..RenderSettings::default()
    };
    check_spp(settings.spp)?;
    check_image_size(settings.width, settings.height)?;
    if !(0.0..=1.0).contains(&settings.roulette) {
        return Err(Error::invalid(format!(
            "render.roulette must be between 0 (off) and 1, got {}",
            settings.roulette
        )));
    }
    if !(0.0..=1.0).contains(&settings.min_weight) {
        return Err(Error::invalid(format!(
            "render.min_weight must be between 0 and 1, got {}",
            settings.min_weight
        )));
    }
    Ok(settings)
}

/// Checks `render.spp` against the one range of every way in (CLI flag, scene file, Python):
/// 1..=[`MAX_SPP`].
///
/// # Errors
/// [`Error::Invalid`] naming the key, the range and the value.
pub fn check_spp(spp: u32) -> Result<()> {
    if (1..=MAX_SPP).contains(&spp) {
        Ok(())
    } else {
        Err(Error::invalid(format!(
            "render.spp must be between 1 and {MAX_SPP}, got {spp}"
        )))
    }
}

/// Checks an image size of `w`×`h` pixels: each side 1..=32768, and the buffers of a shaded
/// render and its PNG within the memory allowance ([`crate::budget`]). The buffers are
/// allocated after the cloud is loaded: this refuses a size that cannot fit before anything
/// is read or allocated.
///
/// # Errors
/// [`Error::Invalid`] with the size and, over the allowance, what it needs.
pub fn check_image_size(w: usize, h: usize) -> Result<()> {
    if w == 0 || h == 0 || w > 32_768 || h > 32_768 {
        return Err(Error::invalid(format!(
            "image size must be between 1x1 and 32768x32768, got {w}x{h}"
        )));
    }
    let pixels = w as u64 * h as u64;
    crate::budget::check(
        pixels * (super::memory::RENDER_BYTES_PER_PIXEL + super::memory::PNG_BYTES_PER_PIXEL),
        || format!("a {w}x{h} render"),
    )
    .map_err(|m| {
        Error::invalid(format!(
            "{m} (a smaller size, or a higher limit: --max-memory, FILMSPLAT_MEMORY_LIMIT)"
        ))
    })
}

/// `output.exposure` (default 0 EV), checked to be within -64..64 EV.
pub(super) fn exposure(o: &OutputDesc) -> Result<f32> {
    if let Some(ev) = o.exposure
        && !(ev.is_finite() && ev.abs() <= 64.0)
    {
        return Err(Error::invalid(format!(
            "output.exposure must be within -64..64 EV, got {ev}"
        )));
    }
    Ok(o.exposure.unwrap_or(0.0))
}

/// `render.wavelengths`, checked against the most a sample carries (fewer for spectral).
fn wavelengths(n: usize, shading: ShadingMode) -> Result<usize> {
    let max = crate::spectrum::wavelengths::MAX_WAVELENGTHS;
    if !(1..=max).contains(&n) {
        return Err(Error::invalid(format!(
            "render.wavelengths must be 1..={max}, got {n}"
        )));
    }
    let lanes = crate::render::radiance::SPECTRAL_LANES;
    if shading == ShadingMode::Spectral && n > lanes {
        return Err(Error::invalid(format!(
            "render.wavelengths must be 1..={lanes} for spectral shading, got {n}"
        )));
    }
    Ok(n)
}

/// The NAME and colour-bar range of an `attribute:NAME` view.
fn attribute_view(d: &SceneDesc, name: &str) -> Result<AttributeView> {
    let range = match d.render.view_range {
        Some([a, b]) if a.is_finite() && b.is_finite() && a < b => Some((a, b)),
        Some([a, b]) => {
            return Err(Error::invalid(format!(
                "render.view_range must be two finite numbers MIN < MAX, got [{a}, {b}]"
            )));
        }
        None => None,
    };
    Ok(AttributeView {
        name: name.to_string(),
        range,
    })
}

impl CameraConfig {
    /// `[camera]` with its defaults, checked: a field of view of 1..170 degrees, finite
    /// vectors, an aperture >= 0 and a focus distance > 0.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming the key.
    pub fn resolve(c: &CameraDesc) -> Result<Self> {
        let fov_deg = c.fov.unwrap_or(DEFAULT_FOV);
        if !(1.0..=170.0).contains(&fov_deg) {
            return Err(Error::invalid(format!(
                "camera.fov must be 1..170 degrees, got {fov_deg}"
            )));
        }
        let up = vec3(c.up.unwrap_or(DEFAULT_UP), "camera.up")?;
        let look_at = c.look_at.map(|t| vec3(t, "camera.look_at")).transpose()?;
        let position = c.position.map(|p| vec3(p, "camera.position")).transpose()?;
        let from = vec3(c.from.unwrap_or(DEFAULT_FROM), "camera.from")?;
        let aperture = c.aperture.unwrap_or(0.0);
        if !(aperture.is_finite() && aperture >= 0.0) {
            return Err(Error::invalid(format!(
                "camera.aperture must be >= 0, got {aperture}"
            )));
        }
        if let Some(f) = c.focus_distance {
            check_focus(f)?;
        }
        if position.is_some() && position == look_at {
            return Err(Error::invalid(
                "camera.position and camera.look_at are the same point",
            ));
        }
        Ok(CameraConfig {
            position,
            look_at,
            up,
            fov_deg,
            from,
            from_default: c.from.is_none(),
            aperture,
            focus_distance: c.focus_distance,
        })
    }
}

/// A focus distance must be finite and > 0.
pub(crate) fn check_focus(focus: f32) -> Result<f32> {
    if focus.is_finite() && focus > 0.0 {
        Ok(focus)
    } else {
        Err(Error::invalid(format!(
            "camera.focus_distance must be > 0, got {focus}"
        )))
    }
}

/// The grading of `[output]`.
fn grade(o: &OutputDesc) -> Result<Grade> {
    let mut gains = match o.white_balance {
        Some(k) => Grade::white_balance_gains(k)
            .map_err(|e| Error::invalid(format!("output.white_balance: {e}")))?,
        None => [1.0; 3],
    };
    if let Some(g) = o.gains {
        gains = [0, 1, 2].map(|i| gains[i] * g[i]);
    }
    let g = Grade {
        gains,
        contrast: o.contrast.unwrap_or(1.0),
        saturation: o.saturation.unwrap_or(1.0),
    };
    g.validate()
        .map_err(|e| Error::invalid(format!("output: {e}")))?;
    Ok(g)
}
