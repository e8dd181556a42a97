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
pub mod framing;
pub mod memory;
#[cfg(feature = "reconstruct")]
pub mod reconstruct;
mod studio;

use crate::geometry::{Droplets, FilmGeometry, LayerBlend, MlsSurface, Primitive, SphereGeometry};
use crate::image::{ExrLayers, Grade, RgbImage, ToneMap, save_png, write_exr};
use crate::io::{CloudPart, PartKind, ReadOptions, read_cloud, read_parts};
use crate::optics::check_film_params;
use crate::pointcloud::curvature::{curvature_from_table, first_order_detail, gradient_from_table};
use crate::pointcloud::gaps::{FAN_NEIGHBOURS, fit_radii};
use crate::pointcloud::knn::KnnTable;
use crate::pointcloud::{
    EstimateOptions, PointCloud, fill_missing_keeping_table, repair, validate,
};
use crate::render::{
    AttributeValues, Camera, Environment, FilmShader, LatLongMap, Preset, RenderOutput,
    RenderSettings, Scene, ShadingMode, Studio, View, ViewImage,
};
use crate::samples::{SampleKind, SampleParams, sparse};
use crate::scene::SceneDesc;
use crate::spectrum::WavelengthStrategy;
use crate::{Error, Result};
use framing::Framing;
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
    /// What auto-framing frames of this cloud (used for the camera unless the scene names a
    /// position; a sequence frames once, see [`framing`]).
    pub framing: Framing,
    /// Width / height of the part of the image the scene fills (the image without a view's
    /// colour bar): the aspect auto-framing frames for.
    pub aspect: f32,
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
    pub notes: Vec<String>,
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
    // The generated cloud's arrays (positions, normals, thickness, radius) and the generator's
    // scratch: ~64 bytes a particle.
    crate::budget::check(p.particles as u64 * 64, || {
        format!("{prefix}particles = {}", p.particles)
    })
    .map_err(Error::invalid)?;
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

/// How the scene's input files are read: attribute names and the thickness unit.
fn read_options(desc: &SceneDesc) -> Result<ReadOptions> {
    let input = &desc.input;
    let mut opts = ReadOptions {
        thickness_attr: input.thickness_attr.clone(),
        normal_attr: input.normal_attr.clone(),
        radius_attr: input.radius_attr.clone(),
        ..ReadOptions::default()
    };
    // Without an explicit unit each format's own applies (m for the simulators' files, nm else).
    if let Some(unit) = desc.film.thickness_unit.as_deref() {
        opts.thickness_scale_to_nm = thickness_unit_factor(unit)?;
        opts.thickness_unit_explicit = true;
    }
    Ok(opts)
}

/// Loads (or generates) the scene's particle cloud, with thickness in nm: `input.cloud`'s
/// film (every film part of it as one cloud), or the sample.
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
        (Some(path), None) => read_cloud(&base.join(path), &read_options(desc)?),
    }
}

/// Loads (or generates) every particle set of the scene: `input.cloud` and `input.clouds`
/// (each read into its parts: a simulator frame gives its film and droplets, a foam one film
/// per bubble), or the sample. Thickness in nm.
pub fn load_parts(desc: &SceneDesc, base: &Path) -> Result<Vec<CloudPart>> {
    let input = &desc.input;
    let paths = input.paths();
    if paths.is_empty() || input.sample.is_some() {
        let cloud = load_cloud(desc, base)?;
        return Ok(vec![CloudPart::film(
            input.sample.clone().unwrap_or_default(),
            cloud,
            Vec::new(),
        )]);
    }
    let opts = read_options(desc)?;
    let mut parts = Vec::new();
    for p in paths {
        parts.extend(read_parts(&base.join(p), &opts)?);
    }
    Ok(parts)
}

/// The droplet parts as one set of water spheres.
fn droplets(parts: &[PointCloud]) -> Result<Droplets> {
    let centres: Vec<Vec3> = parts
        .iter()
        .flat_map(|p| p.positions.iter().copied())
        .collect();
    let radii: Vec<f32> = parts
        .iter()
        .flat_map(|p| {
            let r = p.radius.clone().unwrap_or_else(|| vec![0.0; p.len()]);
            r.into_iter()
        })
        .collect();
    Droplets::build(&centres, &radii)
}

/// The values of the scene's `attribute:NAME` view from the film cloud: the extra attribute
/// NAME, the magnitude of the vector NAME_x/_y/_z, or `thickness` / `radius` themselves.
fn attribute_values(
    desc: &SceneDesc,
    cloud: &PointCloud,
    radii: &[f32],
) -> Result<AttributeValues> {
    let view = desc.render.view.as_deref().unwrap_or_default();
    let name = view.strip_prefix("attribute:").unwrap_or(view);
    let range = match desc.render.view_range {
        Some([a, b]) if a.is_finite() && b.is_finite() && a < b => Some((a, b)),
        Some([a, b]) => {
            return Err(Error::invalid(format!(
                "render.view_range must be two finite numbers MIN < MAX, got [{a}, {b}]"
            )));
        }
        None => None,
    };
    let found = |title: String, values: Vec<f32>| AttributeValues {
        title,
        values,
        range,
    };
    if let Some(v) = cloud.extra(name) {
        return Ok(found(name.to_string(), v.to_vec()));
    }
    let comps: Option<Vec<&[f32]>> = ["x", "y", "z"]
        .iter()
        .map(|c| cloud.extra(&format!("{name}_{c}")))
        .collect();
    if let Some(c) = comps {
        let v = (0..cloud.len())
            .map(|i| Vec3::new(c[0][i], c[1][i], c[2][i]).length())
            .collect();
        return Ok(found(format!("|{name}|"), v));
    }
    match name {
        "thickness" => Ok(found(
            "thickness (nm)".into(),
            cloud.thickness_nm.clone().unwrap_or_default(),
        )),
        "radius" => Ok(found("splat radius".into(), radii.to_vec())),
        _ => {
            let mut names: Vec<&str> = cloud.extra.iter().map(|(k, _)| k.as_str()).collect();
            names.truncate(40);
            Err(Error::invalid(format!(
                "render.view: no attribute '{}' in the film particles (they have: {}; vectors \
                 by their name without _x/_y/_z; also thickness, radius)",
                crate::io::show_name(name),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            )))
        }
    }
}

/// A hint when thickness values (nm) are implausible for a soap film as read: all below
/// 0.001 nm (a file in metres read as nm) or all above 1 mm (a file in nm read as metres).
pub fn thickness_unit_hint(thickness_nm: &[f32]) -> Option<String> {
    let finite = thickness_nm.iter().filter(|v| v.is_finite());
    let max = finite.clone().fold(f32::NEG_INFINITY, |a, b| a.max(*b));
    let min = finite.fold(f32::INFINITY, |a, b| a.min(*b));
    if max > 0.0 && max < 1e-3 {
        Some(format!(
            "thickness values are all below 0.001 nm (max {max:.3e} nm): the file's unit is almost \
             certainly not nm; if it is metres, read it with --thickness-unit m (film.thickness_unit = \"m\")"
        ))
    } else if min > 1e6 {
        Some(format!(
            "thickness values are all above 1 mm (min {min:.3e} nm): the file's unit is almost \
             certainly not the one read; if it is nm, read it with --thickness-unit nm \
             (film.thickness_unit = \"nm\")"
        ))
    } else {
        None
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
    // The image buffers are allocated after the cloud is loaded: refuse a size that cannot fit
    // before anything is read.
    let pixels = settings.width as u64 * settings.height as u64;
    crate::budget::check(
        pixels * (memory::RENDER_BYTES_PER_PIXEL + memory::PNG_BYTES_PER_PIXEL),
        || format!("a {}x{} render", settings.width, settings.height),
    )
    .map_err(Error::invalid)?;
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
    if let Some(ev) = desc.output.exposure
        && !(ev.is_finite() && ev.abs() <= 64.0)
    {
        return Err(Error::invalid(format!(
            "output.exposure must be within -64..64 EV, got {ev}"
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
    let parts = match cloud {
        // A cloud given in memory (the Python API) replaces what `[input]` would load.
        Some(c) => vec![CloudPart::film("the given cloud".into(), c, Vec::new())],
        None => load_parts(desc, base)?,
    };
    let load_time = t0.elapsed();
    let t1 = Instant::now();
    let repairing = desc.input.repair == Some(true);
    let mut films = Vec::new();
    let mut drops = Vec::new();
    for part in parts {
        notes.extend(part.notes.iter().cloned());
        match part.kind {
            PartKind::Droplets => drops.push(part.cloud),
            PartKind::Film if part.cloud.is_empty() => {
                notes.push(format!("{}: no film particles left", part.label));
            }
            PartKind::Film => films.push(part),
        }
    }
    let droplets = droplets(&drops)?;
    if films.is_empty() && droplets.is_empty() {
        let what = desc
            .input
            .paths()
            .first()
            .map(|p| base.join(p).display().to_string());
        return Err(Error::invalid(format!(
            "{}point cloud is empty (0 particles)",
            what.map(|w| format!("{w}: ")).unwrap_or_default()
        )));
    }
    let estimate = EstimateOptions {
        default_thickness_nm: default_thickness,
        ..EstimateOptions::default()
    };
    let single = films.len() == 1;
    let mut clouds = Vec::with_capacity(films.len());
    let mut neighbours = None;
    let mut had_radius = true;
    for part in films {
        let label = part.label;
        let mut cloud = part.cloud;
        let name = |e: Error| Error::invalid(format!("{label}: {e}"));
        if repairing {
            notes.push(repair(&mut cloud).to_string());
        } else {
            validate(&cloud).map_err(name)?;
        }
        // Copies at one position would be a pile of identical disks no tree can split.
        let coincident = crate::pointcloud::dedupe::drop_coincident(&mut cloud);
        if coincident > 0 {
            notes.push(format!(
                "{label}: {coincident} particles at the same position as an earlier one: drawn once"
            ));
        }
        if let Some(t) = cloud
            .thickness_nm
            .as_mut()
            .filter(|_| thickness_scale != 1.0)
        {
            t.iter_mut().for_each(|v| *v *= thickness_scale);
        }
        if let Some(hint) = cloud.thickness_nm.as_deref().and_then(thickness_unit_hint) {
            notes.push(format!("{label}: {hint}"));
        }
        had_radius &= cloud.radius.is_some();
        let (report, table) = fill_missing_keeping_table(&mut cloud, &estimate);
        notes.push(report.to_string());
        if repairing {
            validate(&cloud).map_err(name)?;
        }
        if primitive != Primitive::Sphere && desc.film.fit_radii != Some(false) {
            // Radii fitted to the sampling: no pinholes inside, no bulge at open edges. The
            // estimate's table serves if it has the neighbours, else a sliced search.
            let t = table.as_ref().filter(|t| t.k >= FAN_NEIGHBOURS);
            let normals = cloud.normals.as_deref().unwrap_or_default();
            if let Some(r) = cloud.radius.as_mut() {
                let fit = fit_radii(&cloud.positions, normals, r, t);
                notes.push(format!("{label}: {fit}"));
            }
        }
        if single {
            neighbours = table;
        }
        clouds.push(cloud);
    }
    let cloud = if clouds.len() == 1 {
        clouds.pop().unwrap_or_default()
    } else {
        PointCloud::concat(&clouds)
    };
    let estimate_time = t1.elapsed();
    let thickness_ok = |v: &f32| check_film_params(ior as f64, *v as f64).is_ok();
    if let Some((i, v)) = cloud
        .thickness_nm
        .iter()
        .flatten()
        .enumerate()
        .find(|(_, v)| !thickness_ok(v))
    {
        let hint = cloud
            .thickness_nm
            .as_deref()
            .and_then(thickness_unit_hint)
            .map(|h| format!(": {h}"))
            .unwrap_or_default();
        return Err(Error::invalid(format!(
            "particle {i} has thickness {v} nm after scaling, outside 0..1e6 nm{hint}"
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
    let radii: Vec<f32> = cloud.radius.iter().flatten().map(|r| r * scale).collect();

    let attribute = match view {
        View::Attribute => Some(attribute_values(desc, &cloud, &radii)?),
        _ => None,
    };
    let t2 = Instant::now();
    let empty = Vec::new();
    let normals = cloud.normals.as_ref().unwrap_or(&empty);
    let no_thickness = Vec::new();
    let thickness = cloud.thickness_nm.as_ref().unwrap_or(&no_thickness);
    let geometry: FilmGeometry = if cloud.is_empty() {
        SphereGeometry::build(&[], &[], &[], &[])?.into()
    } else if primitive == Primitive::Mls {
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
        if desc.film.blend == Some(false)
            && let FilmGeometry::Disks(disks) = &mut splats
        {
            disks.set_layer_blend(LayerBlend::NONE);
        }
        splats
    };
    let build_time = t2.elapsed();

    let bounds = geometry.bounds().union(&droplets.bounds());
    let diag = (bounds.max - bounds.min).length().max(1e-12);
    let epsilon = 1e-5 * diag.max(bounds.max.abs().max_element());
    let mut sorted = radii.clone();
    let mid = sorted.len() / 2;
    let median_radius = if sorted.is_empty() {
        0.0
    } else {
        *sorted.select_nth_unstable_by(mid, f32::total_cmp).1
    };
    let layer_skip = match primitive {
        Primitive::Disk => 0.5 * median_radius,
        Primitive::Sphere => epsilon,
        // An MLS crossing is refined to 1e-3 radii: a twentieth of a radius clears it.
        Primitive::Mls => 0.05 * median_radius,
    };
    // Frame the films and the droplets together.
    let mut parts = Vec::new();
    if !cloud.is_empty() {
        let fb = geometry.bounds();
        parts.push(Framing::of_splats(fb.min, fb.max, &cloud.positions, &radii));
    }
    for d in drops.iter().filter(|d| !d.is_empty()) {
        let r = d.radius.clone().unwrap_or_else(|| vec![0.0; d.len()]);
        let (lo, hi) = d
            .positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(*p), hi.max(*p))
            });
        parts.push(Framing::of_splats(lo, hi, &d.positions, &r));
    }
    let framing = Framing::union_all(&parts)
        .unwrap_or_else(|| Framing::of_splats(bounds.min, bounds.max, &[], &[]));
    let centre = framing.centre;
    let aspect = scene_aspect(view, settings.width, settings.height);
    let camera = camera(desc, &framing, aspect)?;
    let environment = environment(desc, base)?;
    let mut staging = studio::staging(desc, base, centre, epsilon)?;
    let n_droplets = droplets.len();
    staging.droplets = droplets;
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
        framing,
        aspect,
        shader,
        settings,
        exposure: desc.output.exposure.unwrap_or(0.0),
        tonemap,
        grade: grade(desc)?,
        view,
        output,
        attribute,
        particles: cloud.len(),
        droplets: n_droplets,
        load_time,
        estimate_time,
        build_time,
        notes,
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
) -> Result<FilmGeometry> {
    let mut geometry = FilmGeometry::particles(primitive, positions, normals, radii, thickness)?;
    if detail && let FilmGeometry::Disks(geometry) = &mut geometry {
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

/// The scene's explicit camera, or the auto-framed one for `framing` (see [`framing`]).
pub fn camera(desc: &SceneDesc, framing: &Framing, aspect: f32) -> Result<Camera> {
    let c = &desc.camera;
    let fov = framing::checked_fov(c)?;
    let up = vec3(c.up.unwrap_or(framing::DEFAULT_UP), "camera.up")?;
    match c.position {
        Some(p) => {
            let target = c
                .look_at
                .map(|t| vec3(t, "camera.look_at"))
                .transpose()?
                .unwrap_or(framing.centre);
            let p = vec3(p, "camera.position")?;
            if (p - target).length_squared() == 0.0 {
                return Err(Error::invalid(
                    "camera.position and camera.look_at are the same point",
                ));
            }
            lens(c, Camera::look_at(p, target, up, fov), target)
        }
        None => framing::auto_camera(desc, framing, aspect),
    }
}

/// Width / height of the part of a `width`×`height` image that `view` fills with the scene:
/// all of it, or what its colour bar leaves.
pub fn scene_aspect(view: View, width: usize, height: usize) -> f32 {
    scene_width(view, width, height) as f32 / height as f32
}

/// Columns of a `width`×`height` image that `view` fills with the scene (the rest is its
/// colour bar).
fn scene_width(view: View, width: usize, height: usize) -> usize {
    if view.has_legend() {
        width - crate::figure::colour_bar_width(width, height)
    } else {
        width
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
/// The picture is exactly the settings' width × height: a view with a colour bar renders the
/// scene in the columns the bar leaves (see [`crate::figure::colour_bar_width`]) and draws the
/// bar, its labels matching [`crate::render::Legend::colour`], in the rest.
pub fn render_view(p: &Prepared) -> Result<Option<ViewImage>> {
    if p.view == View::Shaded {
        return Ok(None);
    }
    let (width, height) = (p.settings.width, p.settings.height);
    let scene_w = scene_width(p.view, width, height);
    let mut v =
        crate::render::render_view_of(&p.scene, p.view, scene_w, height, p.attribute.as_ref())?;
    if let Some(l) = &v.legend {
        let data: Vec<[f32; 3]> = v.rgb.iter().map(|c| c.to_array()).collect();
        let img = RgbImage::from_data(v.width, v.height, data)?;
        let ramp = |t: f32| l.colour(l.min + t * (l.max - l.min)).to_array();
        let img =
            crate::figure::add_colour_bar(&img, width - scene_w, &l.title, l.min, l.max, &ramp);
        v.width = img.width;
        v.rgb = img.data.iter().map(|c| Vec3::from(*c)).collect();
    }
    Ok(Some(v))
}

/// Writes a view (from [`render_view`], colour bar included): PNG (clamp tone curve, 0 EV), or
/// EXR holding the same picture in linear RGB.
pub fn write_view(v: &ViewImage, path: &Path) -> Result<()> {
    let data: Vec<[f32; 3]> = v.rgb.iter().map(|c| c.to_array()).collect();
    let img = RgbImage::from_data(v.width, v.height, data)?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => save_png(path, &img, 0.0, ToneMap::Clamp),
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
