//! The whole pipeline behind `filmsplat render`, callable from Rust: scene description →
//! particles → geometry → rendered buffers → image files.
//!
//! ```no_run
//! use filmsplat::pipeline;
//! use filmsplat::scene::SceneDesc;
//! let desc = SceneDesc::from_toml("[input]\nsample = \"bubble\"\n", "inline").unwrap();
//! let prepared = pipeline::prepare(&desc, std::path::Path::new("."), false).unwrap();
//! let out = pipeline::render(&prepared).unwrap();
//! pipeline::write_image(&prepared, &out, std::path::Path::new("bubble.png")).unwrap();
//! ```

pub mod compare;
pub mod memory;
#[cfg(feature = "reconstruct")]
pub mod reconstruct;
mod studio;

use crate::geometry::{FilmGeometry, LayerBlend, MlsSurface, Primitive, SplatGeometry};
use crate::image::{ExrLayers, Grade, RgbImage, ToneMap, save_png, write_exr};
use crate::io::{ReadOptions, read_cloud};
use crate::optics::check_film_params;
use crate::pointcloud::curvature::{curvature_from_table, first_order_detail, gradient_from_table};
use crate::pointcloud::knn::KnnTable;
use crate::pointcloud::{
    EstimateOptions, PointCloud, fill_missing_keeping_table, repair, validate,
};
use crate::render::{
    Camera, Environment, FilmShader, LatLongMap, Preset, RenderOutput, RenderSettings, Scene,
    ShadingMode, Studio, View, ViewImage,
};
use crate::samples::{SampleKind, SampleParams, sparse};
use crate::scene::SceneDesc;
use crate::spectrum::WavelengthStrategy;
use crate::{Error, Result};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Neighbours used to estimate each disk's curvature and thickness gradient.
const DETAIL_NEIGHBOURS: usize = 12;

/// Everything ready to render, plus what it cost to get here.
#[derive(Debug)]
pub struct Prepared {
    /// Geometry, camera and light.
    pub scene: Scene,
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
    /// Number of particles.
    pub particles: usize,
    /// Time spent loading or generating the cloud.
    pub load_time: Duration,
    /// Time spent estimating missing normals/radii.
    pub estimate_time: Duration,
    /// Time spent building the acceleration structure.
    pub build_time: Duration,
    /// Notes for the user (what was estimated, defaults applied).
    pub notes: Vec<String>,
    /// Centre of the geometry's bounds and the farthest reach of a splat from it, scene units:
    /// what [`camera`] frames.
    pub framing: (Vec3, f32),
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

/// Thickness unit name → factor to nanometres.
pub fn thickness_unit_factor(unit: &str) -> Result<f64> {
    match unit {
        "nm" => Ok(1.0),
        "um" | "µm" => Ok(1e3),
        "mm" => Ok(1e6),
        "m" => Ok(1e9),
        _ => Err(Error::invalid(format!(
            "thickness unit '{unit}' is not one of nm, um, mm, m"
        ))),
    }
}

/// Checks a sample's parameters (`prefix` names where they came from: "input." in scene
/// files, "--" on the command line): particles in 1..=50 000 000, a finite time, a sparse
/// fraction in (0, 1].
pub fn check_sample_params(p: &SampleParams, sparse: Option<f64>, prefix: &str) -> Result<()> {
    if p.particles == 0 || p.particles > 50_000_000 {
        return Err(Error::invalid(format!(
            "{prefix}particles must be 1..=50000000, got {}",
            p.particles
        )));
    }
    if !p.time.is_finite() {
        return Err(Error::invalid(format!("{prefix}time must be finite")));
    }
    if let Some(f) = sparse
        && !(f > 0.0 && f <= 1.0)
    {
        return Err(Error::invalid(format!(
            "{prefix}sparse must be a fraction in (0, 1], got {f}"
        )));
    }
    Ok(())
}

/// Loads (or generates) the scene's particle cloud, with thickness in nm.
pub fn load_cloud(desc: &SceneDesc, base: &Path) -> Result<PointCloud> {
    let input = &desc.input;
    match (&input.cloud, &input.sample) {
        (Some(_), Some(_)) => Err(Error::invalid(
            "input: give either cloud or sample, not both",
        )),
        (None, None) => Err(Error::invalid(
            "input: no particles given (set input.cloud or input.sample)",
        )),
        (None, Some(name)) => {
            let kind = SampleKind::from_name(name)
                .map_err(|e| Error::invalid(format!("input.sample: {e}")))?;
            let mut p = SampleParams::default();
            if let Some(n) = input.particles {
                p.particles = n;
            }
            if let Some(s) = input.sample_seed {
                p.seed = s;
            }
            if let Some(t) = input.time {
                p.time = t;
            }
            check_sample_params(&p, input.sparse, "input.")?;
            let cloud = kind.generate(&p);
            Ok(match input.sparse {
                Some(f) if f < 1.0 => sparse(&cloud, f, p.seed),
                _ => cloud,
            })
        }
        (Some(path), None) => {
            let mut opts = ReadOptions {
                thickness_attr: input.thickness_attr.clone(),
                normal_attr: input.normal_attr.clone(),
                radius_attr: input.radius_attr.clone(),
                ..ReadOptions::default()
            };
            // Without an explicit unit each format's own applies (m for frame folders, nm else).
            if let Some(unit) = desc.film.thickness_unit.as_deref() {
                opts.thickness_scale_to_nm = thickness_unit_factor(unit)?;
                opts.thickness_unit_explicit = true;
            }
            read_cloud(&base.join(path), &opts)
        }
    }
}

/// Builds everything the renderer needs from a scene description. `base` is the folder paths
/// are relative to; `progress` enables the progress bar.
pub fn prepare(desc: &SceneDesc, base: &Path, progress: bool) -> Result<Prepared> {
    prepare_with(desc, base, progress, None)
}

/// [`prepare`], with the particles given in memory (`cloud`, thickness in nm) instead of the
/// scene's `[input]`, which is then ignored. Everything else (checks, estimation of missing
/// normals and radii, geometry, camera) is the same. For the Python package.
pub fn prepare_with(
    desc: &SceneDesc,
    base: &Path,
    progress: bool,
    cloud: Option<PointCloud>,
) -> Result<Prepared> {
    let mut notes = Vec::new();
    let ior = desc.film.ior.unwrap_or(1.33);
    check_film_params(ior as f64, 0.0).map_err(|m| Error::invalid(format!("film.ior: {m}")))?;
    let primitive: Primitive = parse_enum(&desc.film.primitive, Primitive::Disk, "film.primitive")?;
    let preset: Preset = parse_enum(&desc.render.preset, Preset::Balanced, "render.preset")?;
    let defaults = preset.values();
    let shading: ShadingMode =
        parse_enum(&desc.render.shading, defaults.shading, "render.shading")?;
    let strategy: WavelengthStrategy = parse_enum(
        &desc.render.strategy,
        WavelengthStrategy::Jittered,
        "render.strategy",
    )?;
    let tonemap: ToneMap = parse_enum(&desc.output.tonemap, ToneMap::Filmic, "output.tonemap")?;
    let view: View = parse_enum(&desc.render.view, View::Shaded, "render.view")?;
    let r = &desc.render;
    let settings = RenderSettings {
        width: r.width.unwrap_or(960),
        height: r.height.unwrap_or(540),
        spp: r.spp.unwrap_or(defaults.spp),
        max_depth: r.max_depth.unwrap_or(defaults.max_depth).min(64),
        min_weight: r.min_weight.unwrap_or(defaults.min_weight),
        roulette: r.roulette.unwrap_or(preset.roulette(primitive)),
        seed: r.seed.unwrap_or(0),
        progress,
        light_samples: r.light_samples.unwrap_or(1).clamp(1, 1024),
        prop_bounces: r.prop_bounces.unwrap_or(1).min(8),
        ..RenderSettings::default()
    };
    if settings.width == 0
        || settings.height == 0
        || settings.width > 32_768
        || settings.height > 32_768
    {
        return Err(Error::invalid(format!(
            "image size must be between 1x1 and 32768x32768, got {}x{}",
            settings.width, settings.height
        )));
    }
    if !(0.0..=1.0).contains(&settings.roulette) {
        return Err(Error::invalid(format!(
            "render.roulette must be between 0 (off) and 1, got {}",
            settings.roulette
        )));
    }
    if settings.spp == 0 {
        return Err(Error::invalid("render.spp must be at least 1"));
    }
    let wavelengths = r.wavelengths.unwrap_or(defaults.wavelengths);
    if !(1..=crate::spectrum::wavelengths::MAX_WAVELENGTHS).contains(&wavelengths) {
        return Err(Error::invalid(format!(
            "render.wavelengths must be 1..={}, got {wavelengths}",
            crate::spectrum::wavelengths::MAX_WAVELENGTHS
        )));
    }
    if shading == ShadingMode::Spectral && wavelengths > crate::render::radiance::SPECTRAL_LANES {
        return Err(Error::invalid(format!(
            "render.wavelengths must be 1..={} for spectral shading, got {wavelengths}",
            crate::render::radiance::SPECTRAL_LANES
        )));
    }
    let thickness_scale = desc.film.thickness_scale.unwrap_or(1.0);
    let default_thickness = desc.film.default_thickness_nm.unwrap_or(500.0);
    check_film_params(ior as f64, default_thickness as f64)
        .map_err(|m| Error::invalid(format!("film.default_thickness_nm: {m}")))?;
    if !(thickness_scale.is_finite() && thickness_scale >= 0.0) {
        return Err(Error::invalid(format!(
            "film.thickness_scale must be >= 0, got {thickness_scale}"
        )));
    }
    let radius_scale = desc.film.radius_scale.unwrap_or(1.0);
    if !(radius_scale.is_finite() && radius_scale > 0.0) {
        return Err(Error::invalid(format!(
            "film.radius_scale must be > 0, got {radius_scale}"
        )));
    }

    let t0 = Instant::now();
    let mut cloud = match cloud {
        Some(c) => c,
        None => load_cloud(desc, base)?,
    };
    let load_time = t0.elapsed();
    let name_file = |e: Error| match &desc.input.cloud {
        Some(path) => Error::invalid(format!("{}: {e}", base.join(path).display())),
        None => e,
    };
    let repairing = desc.input.repair == Some(true);
    if repairing {
        let report = repair(&mut cloud);
        notes.push(report.to_string());
    } else {
        validate(&cloud).map_err(name_file)?;
    }
    let t1 = Instant::now();
    if let Some(t) = cloud
        .thickness_nm
        .as_mut()
        .filter(|_| thickness_scale != 1.0)
    {
        t.iter_mut().for_each(|v| *v *= thickness_scale);
    }
    let had_radius = cloud.radius.is_some();
    let (report, neighbours) = fill_missing_keeping_table(
        &mut cloud,
        &EstimateOptions {
            default_thickness_nm: default_thickness,
            ..EstimateOptions::default()
        },
    );
    notes.push(report.to_string());
    if repairing {
        validate(&cloud).map_err(name_file)?;
    }
    let estimate_time = t1.elapsed();
    let thickness_ok = |v: &f32| check_film_params(ior as f64, *v as f64).is_ok();
    if let Some((i, v)) = cloud
        .thickness_nm
        .iter()
        .flatten()
        .enumerate()
        .find(|(_, v)| !thickness_ok(v))
    {
        return Err(Error::invalid(format!(
            "particle {i} has thickness {v} nm after scaling, outside 0..1e6 nm"
        )));
    }
    // Estimated radii make disks overlap into a closed film; spheres drawn as particles get half
    // of that, so each particle stays visible as its own ball.
    let estimated_scale = if !had_radius && primitive == Primitive::Sphere {
        0.5
    } else {
        1.0
    };
    let scale = radius_scale * estimated_scale;
    let radii: Vec<f32> = cloud
        .radius
        .as_ref()
        .expect("filled")
        .iter()
        .map(|r| r * scale)
        .collect();

    let t2 = Instant::now();
    let normals = cloud.normals.as_ref().expect("filled");
    let thickness = cloud.thickness_nm.as_ref().expect("filled");
    let geometry: FilmGeometry = if primitive == Primitive::Mls {
        MlsSurface::build(&cloud.positions, normals, &radii, thickness)?.into()
    } else {
        // First-order detail on disks unless the scene or the preset turns it off.
        let detail = primitive == Primitive::Disk
            && desc.film.curvature.unwrap_or(preset.first_order_detail());
        let mut splats = splats(
            primitive,
            &cloud.positions,
            normals,
            &radii,
            thickness,
            detail,
            neighbours,
        )?;
        if desc.film.blend == Some(false) {
            splats.set_layer_blend(LayerBlend::NONE);
        }
        splats.into()
    };
    let build_time = t2.elapsed();

    let bounds = geometry.bounds();
    let diag = (bounds.max - bounds.min).length().max(1e-12);
    let epsilon = 1e-5 * diag.max(bounds.max.abs().max_element());
    let mut sorted = radii.clone();
    let mid = sorted.len() / 2;
    let median_radius = *sorted.select_nth_unstable_by(mid, f32::total_cmp).1;
    let layer_skip = match primitive {
        Primitive::Disk => 0.5 * median_radius,
        Primitive::Sphere => epsilon,
        // An MLS crossing is refined to 1e-3 radii: a twentieth of a radius clears it.
        Primitive::Mls => 0.05 * median_radius,
    };
    let centre = 0.5 * (bounds.min + bounds.max);
    let reach = cloud
        .positions
        .iter()
        .zip(&radii)
        .map(|(p, r)| (*p - centre).length() + r)
        .fold(0.0f32, f32::max);
    let camera = camera(
        desc,
        centre,
        reach,
        settings.width as f32 / settings.height as f32,
    )?;
    let environment = environment(desc, base)?;
    let staging = studio::staging(desc, base, centre, epsilon)?;
    let shader = FilmShader::new(ior, shading, wavelengths, strategy);
    let output = desc.output.path.as_ref().map(|p| base.join(p));
    Ok(Prepared {
        scene: Scene {
            geometry,
            camera,
            environment,
            layer_skip,
            epsilon,
            staging,
        },
        shader,
        settings,
        exposure: desc.output.exposure.unwrap_or(0.0),
        tonemap,
        grade: grade(desc)?,
        view,
        output,
        particles: cloud.len(),
        load_time,
        estimate_time,
        build_time,
        notes,
        framing: (centre, reach),
    })
}

/// Disks or spheres, with first-order detail when `detail` is set; `neighbours` is the
/// estimate's neighbour table, if it built one.
fn splats(
    primitive: Primitive,
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &[f32],
    thickness: &[f32],
    detail: bool,
    neighbours: Option<KnnTable>,
) -> Result<SplatGeometry> {
    let mut geometry = SplatGeometry::build(primitive, positions, normals, radii, thickness)?;
    if detail {
        // First-order splats: normals tilt with the curvature, thickness follows its gradient.
        // Reuse the estimate's neighbour table when it has enough neighbours per particle.
        // Otherwise find the neighbours a slice at a time, so no whole table is ever held
        // (96 bytes a particle for 12 neighbours).
        let (curvature, gradient) = match neighbours {
            Some(t) if t.k >= DETAIL_NEIGHBOURS => (
                curvature_from_table(positions, normals, &t),
                gradient_from_table(positions, normals, thickness, &t),
            ),
            _ => first_order_detail(positions, normals, thickness, DETAIL_NEIGHBOURS),
        };
        geometry.set_curvature(&curvature)?;
        geometry.set_thickness_gradient(&gradient)?;
    }
    Ok(geometry)
}

fn vec3(v: [f32; 3], key: &str) -> Result<Vec3> {
    let v = Vec3::from(v);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Error::invalid(format!("{key} must be finite")))
    }
}

/// The camera of `[camera]`: explicit (`position`, `look_at`) or framing a scene of `reach`
/// scene units around `centre` (see [`Prepared::framing`]) for an image of `aspect` = width /
/// height.
pub fn camera(desc: &SceneDesc, centre: Vec3, reach: f32, aspect: f32) -> Result<Camera> {
    let c = &desc.camera;
    let fov = c.fov.unwrap_or(40.0);
    if !(1.0..=170.0).contains(&fov) {
        return Err(Error::invalid(format!(
            "camera.fov must be 1..170 degrees, got {fov}"
        )));
    }
    let up = vec3(c.up.unwrap_or([0.0, 1.0, 0.0]), "camera.up")?;
    match c.position {
        Some(p) => {
            let target = c
                .look_at
                .map(|t| vec3(t, "camera.look_at"))
                .transpose()?
                .unwrap_or(centre);
            let p = vec3(p, "camera.position")?;
            if (p - target).length_squared() == 0.0 {
                return Err(Error::invalid(
                    "camera.position and camera.look_at are the same point",
                ));
            }
            lens(c, Camera::look_at(p, target, up, fov), target)
        }
        None => {
            let from = vec3(c.from.unwrap_or([0.35, 0.3, 1.0]), "camera.from")?;
            lens(
                c,
                Camera::frame(centre, reach, from, up, fov, aspect),
                centre,
            )
        }
    }
}

/// The grading of `[output]`.
fn grade(desc: &SceneDesc) -> Result<Grade> {
    let o = &desc.output;
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

/// Adds the thin lens of `[camera]` (`aperture`, `focus_distance`, default: focused on
/// `target`).
fn lens(c: &crate::scene::CameraDesc, cam: Camera, target: Vec3) -> Result<Camera> {
    let aperture = c.aperture.unwrap_or(0.0);
    if !(aperture.is_finite() && aperture >= 0.0) {
        return Err(Error::invalid(format!(
            "camera.aperture must be >= 0, got {aperture}"
        )));
    }
    let focus = c
        .focus_distance
        .unwrap_or_else(|| (target - cam.position).dot(cam.forward()));
    if !(focus.is_finite() && focus > 0.0) {
        return Err(Error::invalid(format!(
            "camera.focus_distance must be > 0, got {focus}"
        )));
    }
    Ok(cam.with_lens(aperture, focus))
}

fn environment(desc: &SceneDesc, base: &Path) -> Result<Environment> {
    let e = &desc.environment;
    let intensity = e.intensity.unwrap_or(1.0);
    if !(intensity.is_finite() && intensity >= 0.0) {
        return Err(Error::invalid(format!(
            "environment.intensity must be >= 0, got {intensity}"
        )));
    }
    match e
        .kind
        .as_deref()
        .unwrap_or(if e.map.is_some() { "map" } else { "studio" })
    {
        "studio" => Ok(Environment::Studio(Studio {
            intensity,
            ..Studio::default()
        })),
        "uniform" => Ok(Environment::Uniform(
            vec3(e.colour.unwrap_or([1.0; 3]), "environment.colour")? * intensity,
        )),
        "map" => {
            let path = e.map.as_ref().ok_or_else(|| {
                Error::invalid("environment.kind = \"map\" needs environment.map")
            })?;
            let (w, h, rgba) = crate::image::read_exr_rgba(&base.join(path))?;
            let texels = rgba
                .into_iter()
                .map(|p| Vec3::new(p[0], p[1], p[2]))
                .collect();
            Ok(Environment::Map(LatLongMap::new(
                w,
                h,
                texels,
                e.rotation.unwrap_or(0.0),
                intensity,
            )))
        }
        other => Err(Error::invalid(format!(
            "environment.kind: unknown '{other}' (expected studio, uniform or map)"
        ))),
    }
}

/// Renders a prepared scene.
pub fn render(p: &Prepared) -> Result<RenderOutput> {
    crate::render::render(&p.scene, &p.shader, &p.settings)
}

/// Writes `out` to `path`: PNG (exposure + tone curve + sRGB) or EXR (linear RGBA plus depth,
/// normal, thickness and hit-count layers), by extension. Written atomically.
pub fn write_image(p: &Prepared, out: &RenderOutput, path: &Path) -> Result<()> {
    write_output(out, &p.grade, p.exposure, p.tonemap, path)
}

/// [`write_image`] with the grading, exposure (EV) and tone curve given directly.
pub fn write_output(
    out: &RenderOutput,
    grade: &Grade,
    exposure: f32,
    tonemap: ToneMap,
    path: &Path,
) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => {
            let data = out.rgb.iter().map(|c| c.to_array()).collect();
            let img = RgbImage::from_data(out.width, out.height, data)?;
            save_png(path, &grade.apply(&img), exposure, tonemap)
        }
        Some("exr") => {
            let rgba = out
                .rgb
                .iter()
                .zip(&out.alpha)
                .map(|(c, a)| [c.x, c.y, c.z, *a])
                .collect();
            let mut layers = ExrLayers::rgba(out.width, out.height, rgba);
            layers.depth = Some(out.depth.clone());
            layers.normal = Some(out.normal.iter().map(|n| n.to_array()).collect());
            layers.thickness = Some(out.thickness.clone());
            layers.hit_count = Some(out.hits.clone());
            write_exr(path, &layers)
        }
        _ => Err(Error::invalid(format!(
            "{}: output must end in .png or .exr",
            path.display()
        ))),
    }
}

/// Renders the prepared scene's scientific view (see [`View`]); `None` for the shaded view.
pub fn render_view(p: &Prepared) -> Result<Option<ViewImage>> {
    if p.view == View::Shaded {
        return Ok(None);
    }
    crate::render::render_view(&p.scene, p.view, p.settings.width, p.settings.height).map(Some)
}

/// Writes a view: PNG with its colour bar beside it (clamp tone curve, 0 EV), or EXR with the
/// view's linear RGB.
pub fn write_view(v: &ViewImage, path: &Path) -> Result<()> {
    let data: Vec<[f32; 3]> = v.rgb.iter().map(|c| c.to_array()).collect();
    let img = RgbImage::from_data(v.width, v.height, data)?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => {
            let img = match &v.legend {
                Some(l) => {
                    let ramp = |t: f32| {
                        if l.viridis {
                            crate::image::viridis(t)
                        } else {
                            [crate::image::srgb_to_linear(0.08 + 0.92 * t); 3]
                        }
                    };
                    crate::figure::add_colour_bar(&img, &l.title, l.min, l.max, &ramp)
                }
                None => img,
            };
            save_png(path, &img, 0.0, ToneMap::Clamp)
        }
        Some("exr") => {
            let rgba = img.data.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
            write_exr(path, &ExrLayers::rgba(v.width, v.height, rgba))
        }
        _ => Err(Error::invalid(format!(
            "{}: output must end in .png or .exr",
            path.display()
        ))),
    }
}
