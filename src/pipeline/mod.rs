//! The whole pipeline behind `filmsplat render`, callable from Rust: scene description →
//! particles → geometry → rendered buffers → image files.
//!
//! [`prepare`] reads and builds once; the [`Prepared`] scene is read only from then on.
//! [`render`] takes it with a [`Shot`] (camera, light turn, view, settings, exposure): the
//! scene file's is [`Prepared::shot`]; change a copy for another picture of the same
//! particles. Renders of one `Prepared` (shared in an `Arc`) may run at once from many threads.
//!
//! ```
//! use filmsplat::pipeline;
//! use filmsplat::scene::SceneDesc;
//! let toml = "[input]\nsample = \"bubble\"\nparticles = 2000\n[render]\nwidth = 64\nheight = 48\nspp = 1\n";
//! let desc = SceneDesc::from_toml(toml, "inline").unwrap();
//! let prepared = pipeline::prepare(&desc, std::path::Path::new("."), false).unwrap();
//! let out = pipeline::render(&prepared, &prepared.shot).unwrap();
//! assert_eq!((out.width, out.height), (64, 48));
//! // Another picture of the same prepared particles: the camera moved to the side.
//! let mut side = desc.clone();
//! side.camera.position = Some([2.5, 0.4, 0.5]);
//! let shot = prepared.aimed(&side).unwrap();
//! let from_side = pipeline::render(&prepared, &shot).unwrap();
//! assert_ne!(out.rgb, from_side.rgb);
//! let dir = std::env::temp_dir().join(format!("filmsplat-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! pipeline::write_image(&prepared.shot, &out, &dir.join("bubble.png")).unwrap();
//! assert!(dir.join("bubble.png").is_file());
//! std::fs::remove_dir_all(&dir).unwrap();
//! ```

pub mod beside;
mod build;
pub mod camera_path;
pub mod compare;
pub mod config;
mod droplets;
mod environment_config;
pub mod film_data;
mod fit_mode;
mod foam;
pub mod framing;
mod image_size;
pub mod input_config;
pub mod lights_props;
mod liquid;
mod liquid_mode;
mod liquid_origin;
mod load;
mod melp_sets;
pub mod memory;
pub mod motion;
mod motion_staging;
mod one_film;
mod output;
pub mod pinholes;
mod prepared;
#[cfg(feature = "reconstruct")]
pub mod reconstruct;
mod sample_check;
pub mod sequence;
mod shot;
pub mod shutter;
pub mod stages;
mod studio;
pub mod velocity_check;
mod visibility;

pub use config::RenderConfig;
pub use droplets::{EARLIER_FRAMES, read_input_parts, size_droplets};
pub use fit_mode::FitRadii;
pub use framing::camera;
pub use liquid::LiquidMode;
pub use load::{
    check_sample_params, load_cloud, load_parts, thickness_unit_factor, thickness_unit_hint,
};
pub use output::{
    check_extension, image_srgb8, render_view, scene_aspect, view_srgb8, write_image, write_output,
    write_view,
};
pub use prepared::{Note, Prepared};
pub use shot::Shot;
pub use stages::Progress;
pub use visibility::colour_visibility_of;

use crate::Result;
use crate::io::CloudPart;
use crate::pointcloud::PointCloud;
use crate::render::{Camera, FilmShader, RenderOutput, RenderSettings, Scene, Studio, WorldRef};
use crate::scene::SceneDesc;
use build::Tolerances;
use film_data::FilmData;
use std::path::Path;

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
    prepare_staged(desc, base, Progress::bar_if(progress), cloud)
}

/// [`prepare_with`], reporting each stage (reading, estimation, building) as `progress` says:
/// a spinner in a terminal, a line per stage in a log, or nothing.
pub fn prepare_staged(
    desc: &SceneDesc,
    base: &Path,
    progress: Progress,
    cloud: Option<PointCloud>,
) -> Result<Prepared> {
    // Resolve: the typed, checked configuration, before anything is read.
    let config = desc.resolve_for(base, cloud.is_some())?;
    let mut notes = Vec::new();
    // Read before the particles: props' meshes, the environment map (the studio is set up for
    // the default camera here; each render rigs it to its own camera, `environment_of`).
    let props = studio::props(&config.props)?;
    let environment = build::environment(&config.environment, Studio::default().view)?;

    // Load and estimate: the particles, as completed films and droplets.
    let loaded = load(desc, base, cloud, &config, progress, &mut notes)?;
    let (mut films, drops, droplets) = (loaded.films, loaded.drops, loaded.droplets);
    let (kept, liquid_index, liquid) = (loaded.kept, loaded.liquid_index, loaded.liquid);
    let (radii, film_data) = (films.radii(&config.film), FilmData::of(&films.cloud));
    let attribute = config
        .attribute
        .as_ref()
        .map(|a| build::attribute_values(a, &films.cloud, &radii))
        .transpose()?;

    // Build: the film geometry (and, with an open shutter, the films at each slice's time).
    let (geometry, detail, build_time) = build_geometry(&config, &mut films, &radii, progress)?;
    let unmoved = (&films, radii.as_slice(), detail.as_ref());
    let (mut motion, motion_time) = motion_slices(desc, base, &config, unmoved, progress)?;
    drop(detail);
    let build_time = build_time + motion_time;

    // Stage: distances from the scene's size, the framing, camera, light, lights and props.
    let bounds = geometry
        .bounds()
        .union(&droplets.bounds())
        .union(&liquid.bounds());
    let tol = Tolerances::of(bounds, config.film.primitive, &radii);
    let framing = build::framing(&geometry, &films.cloud, &radii, &drops, bounds);
    let (width, height) = (config.settings.width, config.settings.height);
    let aspect = scene_aspect(&config.view, width, height);
    let camera = config.camera.camera(&framing, aspect)?;
    let mut staging = studio::staging(&config.lights, props, framing.centre, tol.epsilon)?;
    let (n_droplets, fit_screened) = (droplets.len(), films.screened);
    staging.droplets = droplets;
    staging.liquid = liquid;
    let moving = (kept.as_slice(), drops.as_slice(), liquid_index.as_slice());
    move_staging(&mut motion, moving, &staging, &mut notes)?;
    let shader = film_shader(&config);
    // A turntable's frame: the light turns with the camera (once here, for the default shot).
    let turn_deg = desc.environment.turn_deg;
    let turned = (turn_deg != 0.0).then(|| (turn_deg, prepared::turned(&environment, turn_deg)));
    let shot = default_shot(&config, camera, turn_deg, progress);
    Ok(Prepared {
        scene: Scene {
            geometry,
            camera,
            environment,
            layer_skip: tol.layer_skip,
            epsilon: tol.epsilon,
            staging,
        },
        framing,
        aspect,
        turned,
        motion,
        shader,
        shot,
        output: config.output.path,
        attribute,
        film_data,
        fit_screened,
        particles: films.cloud.len(),
        droplets: n_droplets,
        load_time: loaded.load_time,
        estimate_time: loaded.estimate_time,
        build_time,
        notes,
    })
}

/// The picture `config` describes, from `camera`, its light turned `turn_deg` degrees.
fn default_shot(config: &RenderConfig, camera: Camera, turn_deg: f32, progress: Progress) -> Shot {
    Shot {
        camera,
        turn_deg,
        view: config.view.clone(),
        settings: RenderSettings {
            progress: progress == Progress::Bar,
            ..config.settings.clone()
        },
        exposure: config.output.exposure_ev,
        tonemap: config.output.tonemap,
        grade: config.output.grade,
    }
}

/// With an open shutter, the films at each time slice (see [`motion`]) and the time their
/// build took; none otherwise.
fn motion_slices(
    desc: &SceneDesc,
    base: &Path,
    config: &RenderConfig,
    (films, radii, detail): Unmoved,
    progress: Progress,
) -> Result<(Vec<motion::MotionSlice>, std::time::Duration)> {
    let Some(shutter) = config.shutter else {
        return Ok((Vec::new(), std::time::Duration::ZERO));
    };
    let source = desc.input.paths().first().map_or_else(
        || "the given cloud".to_string(),
        |p| base.join(p).display().to_string(),
    );
    // No films (droplets or liquid only): nothing of theirs to move.
    let velocities = match films.cloud.is_empty() {
        true => Vec::new(),
        false => motion::velocities(&films.cloud, &source)?,
    };
    let times = shutter.times_s(config.settings.spp);
    let stage = progress.start(&format!("building {} motion-blur slices", times.len()));
    let slices = motion::slices(
        &config.film,
        &films.cloud,
        &velocities,
        (radii, detail),
        (&films.cuts, &films.sheets),
        &times,
    )?;
    let took = stage.finish(&format!("built {} motion-blur slices", slices.len()));
    Ok((slices, took))
}

/// The film shader `config` asks for.
fn film_shader(config: &RenderConfig) -> FilmShader {
    FilmShader::new(
        config.film.ior,
        config.shading,
        config.wavelengths,
        config.strategy,
    )
}

/// The unmoved films motion blur's slices start from: the completed films, their radii and
/// their disks' first-order detail.
type Unmoved<'a> = (&'a load::Films, &'a [f32], Option<&'a build::Detail>);

/// [`motion_staging::move_staging`] of the droplet clouds `kept`, the droplet parts `drops`
/// and the liquid's particles `liquid` (indices into `drops`), its notes added to `notes`.
fn move_staging(
    motion: &mut [motion::MotionSlice],
    (kept, drops, liquid): (&[PointCloud], &[PointCloud], &[usize]),
    staging: &crate::render::Staging,
    notes: &mut Vec<Note>,
) -> Result<()> {
    let mut said = Vec::new();
    let moving = motion_staging::Moving {
        kept,
        drops,
        liquid,
    };
    motion_staging::move_staging(motion, &moving, staging, &mut said)?;
    notes.extend(said.into_iter().map(Note::new));
    Ok(())
}

/// Build: the film geometry of the completed films (their neighbour table handed on to the
/// disks' detail), timed and shown as a progress stage; the detail is handed back with an open
/// shutter (its slices share it), dropped otherwise.
fn build_geometry(
    config: &RenderConfig,
    films: &mut load::Films,
    radii: &[f32],
    progress: Progress,
) -> Result<(
    crate::geometry::FilmGeometry,
    Option<build::Detail>,
    std::time::Duration,
)> {
    let stage = progress.start(&format!("building the {} geometry", config.film.primitive));
    let neighbours = films.neighbours.take();
    let detail = build::film_detail(&config.film, &films.cloud, radii, neighbours);
    let geometry = build::film_geometry(
        &config.film,
        &films.cloud,
        radii,
        detail.as_ref(),
        (&films.cuts, &films.sheets),
    )?;
    let build_time = stage.finish(&format!(
        "built the {geometry} geometry of {} particles",
        stages::thousands(films.cloud.len())
    ));
    let detail = detail.filter(|_| config.shutter.is_some());
    Ok((geometry, detail, build_time))
}

/// The scene's particles, loaded and completed.
struct Loaded {
    films: load::Films,
    drops: Vec<PointCloud>,
    /// The droplet clouds drawn as droplets, with an open shutter (empty otherwise).
    kept: Vec<PointCloud>,
    droplets: crate::geometry::Droplets,
    liquid: crate::geometry::LiquidSurface,
    /// The liquid surface's particles, indices into `drops`' particles taken in order.
    liquid_index: Vec<usize>,
    load_time: std::time::Duration,
    estimate_time: std::time::Duration,
}

/// Loads the particles (`cloud`, or the scene's `[input]`) as films and droplets, and
/// completes the films: what they lack estimated, their radii fitted to the sampling.
fn load(
    desc: &SceneDesc,
    base: &Path,
    cloud: Option<PointCloud>,
    config: &RenderConfig,
    progress: Progress,
    notes: &mut Vec<Note>,
) -> Result<Loaded> {
    let what = desc.input.paths().first().map_or_else(
        || {
            format!(
                "generating the {} sample",
                desc.input.sample.as_deref().unwrap_or("")
            )
        },
        |p| format!("reading {}", p.display()),
    );
    let stage = progress.start(&what);
    // The inputs the droplet parts came from (none for a cloud given in memory).
    let inputs: Vec<_> = match cloud {
        Some(_) => Vec::new(),
        None => desc.input.paths().iter().map(|p| base.join(p)).collect(),
    };
    let parts = match cloud {
        // A cloud given in memory (the Python API) replaces what `[input]` would load.
        Some(c) => vec![CloudPart::film("the given cloud".into(), c, Vec::new())],
        None => load_parts(desc, base)?,
    };
    let n: usize = parts.iter().map(|p| p.cloud.len()).sum();
    let load_time = stage.finish(&format!("read {} particles", stages::thousands(n)));
    let stage = progress.start("estimating what the particles lack, fitting radii");
    let repairing = desc.input.repair == Some(true);
    let (mut films, drops) = load::split(parts, repairing, notes)?;
    let bubbles = foam::merge_walls(&mut films, notes);
    let liquid::Split {
        kept,
        surface: liquid,
        liquid: liquid_index,
    } = liquid::split(
        &drops,
        (config.input.liquid, config.input.liquid_field),
        &inputs,
        notes,
    )?;
    let droplets = build::droplets(&kept)?;
    // Kept for motion blur's slices only (they move the droplets too).
    let kept = if config.shutter.is_some() {
        kept
    } else {
        Vec::new()
    };
    if films.is_empty() && droplets.is_empty() && liquid.is_empty() {
        return Err(load::nothing_loaded(desc, base));
    }
    let unit_named = desc.film.thickness_unit.is_some() || desc.film.thickness_scale.is_some();
    let films = load::films(
        films,
        &bubbles,
        &config.film,
        (repairing, unit_named),
        notes,
    )?;
    let estimate_time = stage.finish(&format!(
        "completed {} film particles (normals, radii, thickness estimated where missing; radii fitted)",
        stages::thousands(films.cloud.len())
    ));
    Ok(Loaded {
        films,
        kept,
        drops,
        droplets,
        liquid,
        liquid_index,
        load_time,
        estimate_time,
    })
}

/// Renders `shot` of a prepared scene (its shaded view; see [`render_view`] for the others).
/// Reads `p` only: renders of one `Prepared` with different shots may run at once from many
/// threads. The droplets are grown to the shot camera's pixel footprints (one sphere tree,
/// O(n log n) in the droplets) and the environment turned as the shot turns it.
///
/// # Errors
/// As [`crate::render::render`]: a bad size or sample count, [`crate::Error::Cancelled`].
pub fn render(p: &Prepared, shot: &Shot) -> Result<RenderOutput> {
    let environment = p.environment_of(shot);
    let height = shot.settings.height;
    let camera = &shot.camera;
    // Droplets smaller than a pixel show their share of it (see render's camera ray).
    let footprints =
        (p.scene.staging.droplets).footprints(|c| camera.pixel_footprint(c, height))?;
    let world = WorldRef {
        camera,
        environment: &environment,
        footprints: footprints.as_ref(),
        ..WorldRef::from(&p.scene)
    };
    if !p.motion.is_empty() {
        return motion::render(&p.motion, world, &p.shader, &shot.settings);
    }
    crate::render::render(world, &p.shader, &shot.settings)
}
