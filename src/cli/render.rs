//! `filmsplat render`: render a particle cloud or a scene file.

use super::{glob, sequence};
use crate::io::{NORMAL_ALIASES, RADIUS_ALIASES, THICKNESS_ALIASES};
use crate::pipeline;
use crate::pipeline::{Prepared, memory};
use crate::scene::SceneDesc;
use crate::{Error, Result};
use clap::Args;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `filmsplat render`. Flags override the scene file.
#[derive(Debug, Clone, Args)]
#[command(after_help = attribute_help())]
pub struct RenderArgs {
    /// Particle inputs, rendered together as one scene: files (.ply, .vtk, .vtu/.vtp, .pvd,
    /// .bgeo[.gz], .csv/.xyz), frame or snapshot folders of the thin-film SPH code (film and
    /// droplets), MELP foam frame folders (every bubble); or one scene file (.toml). `-` reads a
    /// particle file (PLY, VTK, VTK XML or BGEO) from standard input, as does a pipe such as
    /// `<(cat f.ply)`; a single quoted glob ('frames/*.ply': * and ? in the file name) renders
    /// every match, sorted, as a sequence.
    #[arg(required = true, num_args = 1..)]
    pub(super) inputs: Vec<PathBuf>,
    /// Output image: .png (tone-mapped sRGB) or .exr (linear RGBA + depth, normal, thickness,
    /// hit-count layers); `-` writes the PNG to standard output; `{stem}` is the input's file
    /// stem (with a quoted glob input, each match's). Default: the scene file's output.path,
    /// else render.png.
    #[arg(short, long)]
    pub(super) output: Option<PathBuf>,
    /// Also write the linear EXR with all layers to this path.
    #[arg(long)]
    pub(super) exr: Option<PathBuf>,
    /// How particles are drawn: disk (oriented splats, blended into one film), sphere, or mls
    /// (the smooth moving-least-squares surface through the particles).
    #[arg(long)]
    pub(super) primitive: Option<String>,
    /// Settings preset: preview (1 spp, 4 crossings), balanced (the default: 4 spp, 12
    /// crossings) or final (16 spp, 16 crossings), points on the measured speed/accuracy front.
    /// Given here it replaces the scene file's spp, max_depth, min_weight, roulette, shading
    /// and wavelengths; the flags for those still override it. For spheres balanced and final
    /// also play Russian roulette below weight 0.1 (see --roulette).
    #[arg(long)]
    pub(super) preset: Option<String>,
    /// Camera samples per pixel.
    #[arg(long, value_parser = super::parse::int_in::<u32>(1, 65_536))]
    pub(super) spp: Option<u32>,
    /// Image size WIDTHxHEIGHT in pixels (default 960x540).
    #[arg(long, value_parser = super::parse::size)]
    pub(super) size: Option<(usize, usize)>,
    /// Random seed; the same seed gives the same image.
    #[arg(long)]
    pub(super) seed: Option<u64>,
    /// Film shading: lut (precomputed colour table, fastest), rgb (per-hit spectral
    /// integration over --wavelengths wavelengths) or spectral (full spectral transport, the
    /// reference; at most 16 wavelengths).
    #[arg(long)]
    pub(super) shading: Option<String>,
    /// Wavelengths per camera sample for --shading rgb (1..64).
    #[arg(long, value_parser = super::parse::int_in::<usize>(1, 64))]
    pub(super) wavelengths: Option<usize>,
    /// Wavelength sampling for --shading rgb: jittered, stratified or hero.
    #[arg(long)]
    pub(super) strategy: Option<String>,
    /// Most film crossings along one path.
    #[arg(long, value_parser = super::parse::int_in::<u32>(0, 64))]
    pub(super) max_depth: Option<u32>,
    /// Russian roulette below this branch weight (0..1; 0, the default, is off): dim branches
    /// of the ray tree are followed at random, unbiased. Fewer rays for some noise; pays for
    /// --primitive sphere, where a camera sample crosses many films (the balanced and final
    /// presets use 0.1 there).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) roulette: Option<f32>,
    /// Film index of refraction (default 1.33).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) ior: Option<f32>,
    /// Unit of the file's thickness values: nm, um, mm or m (default: the format's unit, m for
    /// the thin-film SPH code's frame folders, nm otherwise).
    #[arg(long)]
    pub(super) thickness_unit: Option<String>,
    /// Extra factor on thickness after the unit conversion.
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) thickness_scale: Option<f32>,
    /// Name of the thickness attribute (default: the first of the aliases below).
    #[arg(long)]
    pub(super) thickness_attr: Option<String>,
    /// Prefix of the normal attributes (n for nx ny nz, normal for normal_x ..., N).
    #[arg(long)]
    pub(super) normal_attr: Option<String>,
    /// Name of the radius attribute.
    #[arg(long)]
    pub(super) radius_attr: Option<String>,
    /// Thickness in nm for clouds without one (default 500).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) default_thickness: Option<f32>,
    /// Factor on all splat radii (estimated from spacing or read from the file).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) radius_scale: Option<f32>,
    /// Do not blend overlapping disks into one film crossing (for comparison: the film is then
    /// applied once per disk and colours jump at splat rims).
    #[arg(long)]
    pub(super) no_blend: bool,
    /// Use the splat radii as read or estimated: do not grow them to close pinholes between
    /// particles, nor trim them at open edges (film.fit_radii = false).
    #[arg(long)]
    pub(super) raw_radii: bool,
    /// Flat disks: skip the curvature estimate that tilts each disk's normal with the film's
    /// curvature (faster set-up; curved films then show faceted reflections).
    #[arg(long)]
    pub(super) flat_splats: bool,
    /// Lighting: studio (built-in), white (uniform white), or a lat-long .exr panorama.
    #[arg(long)]
    pub(super) env: Option<String>,
    /// Rotation of an environment map about +y, degrees.
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) env_rotation: Option<f32>,
    /// Multiplier on the environment's radiance.
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) env_intensity: Option<f32>,
    /// Camera position x,y,z (scene units); default: auto-framing (a sequence is framed once,
    /// on its first frame, see --frame-all).
    #[arg(long, value_parser = super::parse::vec3, allow_hyphen_values = true)]
    pub(super) camera: Option<[f32; 3]>,
    /// Point the camera looks at, x,y,z (default: the cloud's centre).
    #[arg(long, value_parser = super::parse::vec3, allow_hyphen_values = true)]
    pub(super) look_at: Option<[f32; 3]>,
    /// Vertical field of view, degrees.
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) fov: Option<f32>,
    /// Exposure, EV (stops).
    #[arg(long, allow_hyphen_values = true, value_parser = super::parse::finite_f32)]
    pub(super) exposure: Option<f32>,
    /// Light samples per prop hit (each: a light point, an environment direction and a
    /// material direction, combined by multiple importance sampling).
    #[arg(long, value_parser = super::parse::int_in::<u32>(1, 1024))]
    pub(super) light_samples: Option<u32>,
    /// Thin-lens aperture radius, scene units (0: pinhole, everything sharp).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) aperture: Option<f32>,
    /// Distance in focus, scene units (default: the distance to the look-at point).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) focus_distance: Option<f32>,
    /// White balance: neutralise light of this colour temperature, kelvin (1667..25000).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) white_balance: Option<f32>,
    /// Contrast around middle grey (1 = unchanged).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) contrast: Option<f32>,
    /// Saturation (1 = unchanged, 0 = grey).
    #[arg(long, value_parser = super::parse::finite_f32)]
    pub(super) saturation: Option<f32>,
    /// Tone curve for PNG: filmic or clamp.
    #[arg(long)]
    pub(super) tonemap: Option<String>,
    /// What to show: shaded (the thin-film render), or a scientific view of the first film
    /// crossing: thickness (false colour with a colour bar, nm), normal, depth, particle-id,
    /// coverage (splats blended per pixel: shows sparse regions and holes), or attribute:NAME
    /// (any stored per-particle attribute, e.g. vrt, conc, gamma; a vector such as v by its
    /// magnitude; with a colour bar).
    #[arg(long)]
    pub(super) view: Option<String>,
    /// Values at the ends of the colour bar of --view attribute:NAME, MIN,MAX (default: the
    /// range of what is visible).
    #[arg(long, value_parser = super::parse::min_max, allow_hyphen_values = true)]
    pub(super) view_range: Option<[f32; 2]>,
    /// Drop particles with non-finite positions or bad thickness and re-estimate bad normals
    /// and radii (says how many), instead of refusing the file.
    #[arg(long)]
    pub(super) repair: bool,
    /// Render a sequence: frame numbers A..B (B excluded) or A..=B. The input (or the scene's
    /// input.cloud) and the output contain a frame pattern, {} or {:04} (zero-padded), e.g.
    /// `render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..240`. Each frame's seed
    /// is the seed plus the frame number.
    #[arg(long, value_parser = super::sequence::frame_list)]
    pub(super) frames: Option<sequence::FrameList>,
    /// Render only every N-th frame of --frames, starting at the K-th (K/N, 0 <= K < N), so N
    /// jobs of a render farm (e.g. K = $SLURM_ARRAY_TASK_ID) split a sequence without talking.
    #[arg(long, value_parser = super::sequence::shard)]
    pub(super) shard: Option<(u64, u64)>,
    /// With --frames and no camera position: auto-frame the sequence's one camera on the union
    /// of all frames' bounds (each job then prepares every frame once more to measure it),
    /// instead of on the first frame of --frames. The chosen camera is printed as scene-file
    /// lines.
    #[arg(long)]
    pub(super) frame_all: bool,
    /// The frame being rendered (set by the sequence loop; expands patterns in a scene file).
    #[arg(skip)]
    pub(super) frame: Option<u64>,
    /// Skip frames whose output file already exists (outputs are renamed into place only when
    /// complete, so an existing file is a finished frame), and remove the hidden temporary
    /// files (`.NAME.tmp-PID-N`) a killed run left for the frames of this run.
    #[arg(long)]
    pub(super) resume: bool,
    /// Report a frame that fails and go on with the others (exit code 2 at the end if any
    /// failed), instead of stopping at the first.
    #[arg(long)]
    pub(super) keep_going: bool,
    /// Refuse to render (exit 2, before loading anything) if the estimated peak memory
    /// exceeds SIZE, e.g. 8G or 512M (binary units; see `filmsplat info` for the estimate).
    /// Default: the machine's available memory (MemAvailable in /proc/meminfo; no limit where
    /// that cannot be read). A SIZE above it lets a render try anyway.
    #[arg(long, value_name = "SIZE", value_parser = crate::pipeline::memory::parse_size)]
    pub(super) max_memory: Option<u64>,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub(super) quiet: bool,
}

/// " and N droplets" when there are any.
fn droplet_note(n: usize) -> String {
    if n == 0 {
        String::new()
    } else {
        format!(" and {n} droplets")
    }
}

impl RenderArgs {
    /// The first input, for messages.
    pub(super) fn first_input(&self) -> String {
        self.inputs
            .first()
            .map(|p| p.display().to_string())
            .unwrap_or_default()
    }

    /// The scene file, if the input is one (it must then be the only input).
    ///
    /// # Errors
    /// [`Error::Invalid`] if a scene file is given with other inputs.
    pub(super) fn scene_file(&self) -> Result<Option<&PathBuf>> {
        let toml = |p: &&PathBuf| {
            p.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
        };
        match self.inputs.iter().find(toml) {
            Some(f) if self.inputs.len() > 1 => Err(Error::invalid(format!(
                "{}: a scene file is rendered alone; list several inputs in its \
                 input.clouds instead",
                f.display()
            ))),
            found => Ok(found),
        }
    }
}

fn attribute_help() -> String {
    format!(
        "Attribute names recognised in particle files:\n  thickness: {}\n  normals:   {}\n  radius:    {}\n\
         Missing normals are estimated by PCA over nearest neighbours, missing radii from the local spacing.",
        THICKNESS_ALIASES.join(", "),
        NORMAL_ALIASES.join(", "),
        RADIUS_ALIASES.join(", ")
    )
}

/// The scene description: from the TOML file, or a default one around a particle file; then the
/// flags on top. Returns it with the folder its paths are relative to.
pub(super) fn scene_from_args(a: &RenderArgs) -> Result<(SceneDesc, PathBuf)> {
    let (mut d, base) = match a.scene_file()? {
        Some(file) => {
            // Scene files are small: at most 16 MiB, never a device.
            let bytes = crate::io::input::read_small(file, 16 << 20)?;
            let text = String::from_utf8(bytes).map_err(|_| Error::Format {
                path: file.clone(),
                format: "scene TOML",
                message: "not UTF-8 text".into(),
            })?;
            let d = SceneDesc::from_toml(&text, &file.display().to_string())?;
            (d, file.parent().map(Path::to_path_buf).unwrap_or_default())
        }
        None => {
            let mut d = SceneDesc::default();
            d.input.cloud = a.inputs.first().cloned();
            if a.inputs.len() > 1 {
                d.input.clouds = Some(a.inputs[1..].to_vec());
            }
            (d, PathBuf::new())
        }
    };
    macro_rules! set {
        ($field:expr, $flag:expr) => {
            if let Some(v) = $flag.clone() {
                $field = Some(v);
            }
        };
    }
    if let Some(p) = &a.preset {
        let r = &mut d.render;
        (r.spp, r.max_depth, r.min_weight, r.shading, r.wavelengths) =
            (None, None, None, None, None);
        r.roulette = None;
        r.preset = Some(p.clone());
    }
    set!(d.film.primitive, a.primitive);
    set!(d.render.spp, a.spp);
    set!(d.render.seed, a.seed);
    set!(d.render.shading, a.shading);
    set!(d.render.wavelengths, a.wavelengths);
    set!(d.render.strategy, a.strategy);
    set!(d.render.max_depth, a.max_depth);
    set!(d.render.roulette, a.roulette);
    set!(d.film.ior, a.ior);
    set!(d.film.thickness_unit, a.thickness_unit);
    set!(d.film.thickness_scale, a.thickness_scale);
    set!(d.input.thickness_attr, a.thickness_attr);
    set!(d.input.normal_attr, a.normal_attr);
    set!(d.input.radius_attr, a.radius_attr);
    set!(d.film.default_thickness_nm, a.default_thickness);
    set!(d.film.radius_scale, a.radius_scale);
    set!(d.environment.rotation, a.env_rotation);
    set!(d.environment.intensity, a.env_intensity);
    set!(d.camera.position, a.camera);
    set!(d.camera.look_at, a.look_at);
    set!(d.camera.fov, a.fov);
    set!(d.output.exposure, a.exposure);
    set!(d.camera.aperture, a.aperture);
    set!(d.render.light_samples, a.light_samples);
    set!(d.camera.focus_distance, a.focus_distance);
    set!(d.output.white_balance, a.white_balance);
    set!(d.output.contrast, a.contrast);
    set!(d.output.saturation, a.saturation);
    set!(d.output.tonemap, a.tonemap);
    set!(d.render.view, a.view);
    set!(d.render.view_range, a.view_range);
    if a.repair {
        d.input.repair = Some(true);
    }
    if a.raw_radii {
        d.film.fit_radii = Some(false);
    }
    if a.flat_splats {
        d.film.curvature = Some(false);
    }
    if a.no_blend {
        d.film.blend = Some(false);
    }
    if let Some(f) = a.frame {
        let expand = |p: &mut PathBuf| -> Result<()> {
            if let Some(e) = sequence::expand(&p.to_string_lossy(), f)? {
                *p = PathBuf::from(e);
            }
            Ok(())
        };
        d.input.cloud.iter_mut().try_for_each(expand)?;
        d.input.clouds.iter_mut().flatten().try_for_each(expand)?;
        if d.input.sample.is_some() {
            // A generated sample animates at 24 frames a second from its scene time.
            d.input.time = Some(d.input.time.unwrap_or(0.0) + f as f32 / super::sample::FPS);
        }
    }
    if let Some((w, h)) = a.size {
        d.render.width = Some(w);
        d.render.height = Some(h);
    }
    if let Some(env) = &a.env {
        match env.as_str() {
            "studio" => d.environment.kind = Some("studio".into()),
            "white" => {
                d.environment.kind = Some("uniform".into());
                d.environment.colour = Some([1.0; 3]);
            }
            path => {
                d.environment.kind = Some("map".into());
                // A path given on the command line is relative to the working directory.
                d.environment.map =
                    Some(std::path::absolute(path).map_err(|e| Error::io(path, e))?);
            }
        }
    }
    Ok((d, base))
}

/// Runs `filmsplat render`: one image, or a sequence with --frames.
pub fn run(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    if let [only] = a.inputs.as_slice()
        && a.frames.is_none()
        && glob::is_glob(only)
        && !only.exists()
    {
        return run_glob(a, out);
    }
    let Some(frames) = &a.frames else {
        if a.frame_all {
            return Err(Error::invalid(
                "--frame-all frames a whole sequence; it needs --frames",
            ));
        }
        return render_one(a, out, None);
    };
    sequence::render_sequence(a, &frames.0, out)
}

/// The image a render writes: -o, else the scene file's output.path, else render.png.
fn output_path(a: &RenderArgs, desc: &SceneDesc, base: &Path) -> PathBuf {
    match (&a.output, &desc.output.path) {
        (Some(o), _) => match a.inputs.first() {
            Some(i) => glob::with_stem(o, i),
            None => o.clone(),
        },
        (None, Some(p)) => base.join(p),
        (None, None) => PathBuf::from("render.png"),
    }
}

/// Renders every match of a quoted glob input (`'frames/*.ply'`), sorted by name, as a sequence:
/// `{stem}` in -o (and --exr) names each output after its input; the n-th match's seed is the
/// seed plus n.
fn run_glob(a: &RenderArgs, out: &mut dyn Write) -> Result<()> {
    let pattern = a.inputs.first().cloned().unwrap_or_default();
    let inputs = glob::expand(&pattern)?;
    let output = a.output.as_ref().ok_or_else(|| {
        Error::invalid(format!(
            "{}: a glob input needs -o with {{stem}}, e.g. -o 'out/{{stem}}.png'",
            pattern.display()
        ))
    })?;
    for p in std::iter::once(output).chain(a.exr.as_ref()) {
        if inputs.len() > 1 && !p.to_string_lossy().contains("{stem}") {
            return Err(Error::invalid(format!(
                "{}: {} files match {}; the output needs {{stem}} (e.g. 'out/{{stem}}.png') so \
                 they do not overwrite each other",
                p.display(),
                inputs.len(),
                pattern.display()
            )));
        }
    }
    let mut failed = Vec::new();
    for (n, input) in inputs.iter().enumerate() {
        let mut one = a.clone();
        one.inputs = vec![input.clone()];
        one.output = Some(glob::with_stem(output, input));
        one.exr = a.exr.as_ref().map(|e| glob::with_stem(e, input));
        one.seed = Some(a.seed.unwrap_or(0).wrapping_add(n as u64));
        let target = one.output.clone().expect("set");
        if a.resume
            && std::iter::once(&target)
                .chain(one.exr.as_ref())
                .all(|p| p.exists())
        {
            if !a.quiet {
                let _ = writeln!(
                    out,
                    "{}: {} exists, skipped",
                    input.display(),
                    target.display()
                );
            }
            continue;
        }
        if !a.quiet {
            let _ = writeln!(out, "{} ({}/{}):", input.display(), n + 1, inputs.len());
        }
        match render_one(&one, out, None) {
            Ok(()) => {}
            Err(e) if a.keep_going => {
                eprintln!("filmsplat: error: {e}");
                failed.push(input.display().to_string());
            }
            Err(e) => return Err(e),
        }
    }
    if !failed.is_empty() {
        return Err(Error::invalid(format!(
            "{} of {} inputs failed: {}",
            failed.len(),
            inputs.len(),
            failed.join(", ")
        )));
    }
    Ok(())
}

/// Renders `a` (whose output is `-`) to a spool file, then copies the finished PNG to standard
/// output, so standard output receives the whole image or nothing; messages go to stderr.
fn render_to_stdout(a: &RenderArgs) -> Result<()> {
    static SPOOLS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = SPOOLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let spool =
        std::env::temp_dir().join(format!("filmsplat-{}-{n}-stdout.png", std::process::id()));
    let mut one = a.clone();
    one.output = Some(spool.clone());
    let mut said = Vec::new();
    let result = render_one(&one, &mut said, None);
    let said =
        String::from_utf8_lossy(&said).replace(&spool.display().to_string(), "standard output");
    eprint!("{said}");
    let result = result.and_then(|()| {
        let bytes = std::fs::read(&spool).map_err(|e| Error::io(&spool, e))?;
        let mut stdout = std::io::stdout().lock();
        stdout
            .write_all(&bytes)
            .and_then(|()| stdout.flush())
            .map_err(|e| Error::io("-", e))
    });
    let _ = std::fs::remove_file(&spool);
    result
}

/// Refuses an output that is neither .png nor .exr.
pub(super) fn check_extension(p: &Path) -> Result<()> {
    let ext = p
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if matches!(ext.as_deref(), Some("png" | "exr")) {
        Ok(())
    } else {
        Err(Error::invalid(format!(
            "{}: output must end in .png or .exr",
            p.display()
        )))
    }
}

/// Checks everything that can be checked before loading: output names, the estimated peak
/// memory against --max-memory or the machine's available memory, the output folders
/// (created); then prepares the scene. `progress` shows the render's progress bar.
pub(super) fn prepare_frame(a: &RenderArgs, progress: bool) -> Result<Prepared> {
    let (desc, base) = scene_from_args(a)?;
    let output = output_path(a, &desc, &base);
    let outputs: Vec<&PathBuf> = std::iter::once(&output).chain(a.exr.as_ref()).collect();
    for p in &outputs {
        check_extension(p)?;
    }
    if let Some(bytes) = a.max_memory {
        crate::budget::set_allowance(bytes);
    }
    if let Some(limit) = memory::Limit::new(a.max_memory) {
        let exr = outputs
            .iter()
            .any(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")));
        match memory::estimate_scene(&desc, &base, exr) {
            Ok(estimate) => limit
                .check(&estimate)
                .map_err(|m| Error::invalid(format!("{}: {m}", a.first_input())))?,
            // Without a limit of the user's, an input the estimate cannot read is left to the
            // reader, which names the problem better.
            Err(_) if matches!(limit, memory::Limit::Available(_)) => {}
            Err(e) => return Err(e),
        }
    }
    for p in &outputs {
        crate::atomic::prepare_output(p)?;
    }
    pipeline::prepare(&desc, &base, progress)
}

/// Renders one image; `ready` is its scene if the caller already prepared it.
pub(super) fn render_one(
    a: &RenderArgs,
    out: &mut dyn Write,
    ready: Option<Prepared>,
) -> Result<()> {
    let (desc, base) = scene_from_args(a)?;
    let output = output_path(a, &desc, &base);
    if output.as_os_str() == "-" {
        return render_to_stdout(a);
    }
    let progress = !a.quiet && std::io::stderr().is_terminal();
    let prepared = match ready {
        Some(mut p) => {
            p.settings.progress = progress;
            p
        }
        None => prepare_frame(a, progress).map_err(|e| desc.locate(e))?,
    };
    if !a.quiet {
        for note in prepared
            .notes
            .iter()
            .filter(|n| !n.is_empty() && !n.contains("nothing to fill"))
        {
            let _ = writeln!(out, "{note}");
        }
    }
    if let Some(view) = pipeline::render_view(&prepared)? {
        pipeline::write_view(&view, &output)?;
        if let Some(exr) = &a.exr {
            pipeline::write_view(&view, exr)?;
        }
        if !a.quiet {
            let _ = writeln!(
                out,
                "{} particles: {} view; wrote {}",
                prepared.particles,
                prepared.view,
                output.display()
            );
        }
        return Ok(());
    }
    let t = Instant::now();
    let result = pipeline::render(&prepared)?;
    let render_time = t.elapsed();
    pipeline::write_image(&prepared, &result, &output)?;
    if let Some(exr) = &a.exr {
        pipeline::write_image(&prepared, &result, exr)?;
    }
    if !a.quiet {
        let s = &prepared.settings;
        let front = crate::image::pinholes::missing_front_layer(&result.depth, s.width, s.height);
        let _ = writeln!(
            out,
            "{} particles ({}){}: load {:.3} s, estimate {:.3} s, build {:.3} s; render {}x{} at {} spp: {:.3} s ({:.2} Mrays/s); front layer missing at {:.3} % of the film's interior; wrote {}",
            prepared.particles,
            prepared.scene.geometry,
            droplet_note(prepared.droplets),
            prepared.load_time.as_secs_f64(),
            prepared.estimate_time.as_secs_f64(),
            prepared.build_time.as_secs_f64(),
            s.width,
            s.height,
            s.spp,
            render_time.as_secs_f64(),
            result.rays as f64 / render_time.as_secs_f64() / 1e6,
            front.percent(),
            output.display()
        );
    }
    Ok(())
}
