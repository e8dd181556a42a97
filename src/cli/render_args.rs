//! The flags of `filmsplat render` (and of `compare`, which renders the same way).

use crate::io::{NORMAL_ALIASES, RADIUS_ALIASES, THICKNESS_ALIASES};
use crate::{Error, Result};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `filmsplat render`. Flags override the scene file.
#[derive(Debug, Clone, Args)]
#[command(after_help = attribute_help())]
pub struct RenderArgs {
    /// Particle inputs, rendered together as one scene: files (.ply, .vtk, .vtu/.vtp, .pvd,
    /// .bgeo[.gz], .csv/.tsv/.xyz/.txt), frame or snapshot folders of the thin-film SPH code
    /// (film and droplets), MELP foam frame folders (every bubble); or one scene file (.toml).
    /// `-` reads a particle file (PLY, VTK, VTK XML or BGEO) from standard input, as does a pipe
    /// such as `<(cat f.ply)`; a single quoted glob ('frames/*.ply': * and ? in the file name)
    /// renders every match, sorted, as a sequence.
    #[arg(required = true, num_args = 1..)]
    pub(super) inputs: Vec<PathBuf>,
    /// Output image: .png (tone-mapped sRGB) or .exr (linear RGBA + depth, normal, thickness,
    /// hit-count layers); `-` writes the PNG to standard output; `{stem}` is the input's file
    /// stem (with a quoted glob input, each match's). With --frames, a movie: .mp4 (H.264,
    /// yuv420p) or .webm (VP9), the frames piped to the system's ffmpeg (see --fps, --crf).
    /// Default: the scene file's output.path, else render.png.
    #[arg(short, long)]
    pub(super) output: Option<PathBuf>,
    /// Also write the linear EXR with all layers to this path.
    #[arg(long)]
    pub(super) exr: Option<PathBuf>,
    /// How particles are drawn: disk (oriented splats, blended into one film), sphere, or mls
    /// (the smooth moving-least-squares surface through the particles).
    #[arg(long, value_parser = super::parse::named::<crate::geometry::Primitive>)]
    pub(super) primitive: Option<String>,
    /// Settings preset: preview (1 spp, 4 crossings), balanced (the default: 4 spp, 12
    /// crossings) or final (16 spp, 16 crossings), points on the measured speed/accuracy front.
    /// Given here it replaces the scene file's spp, max_depth, min_weight, roulette, shading
    /// and wavelengths; the flags for those still override it. For spheres balanced and final
    /// also play Russian roulette below weight 0.1 (see --roulette).
    #[arg(long, value_parser = super::parse::named::<crate::render::Preset>)]
    pub(super) preset: Option<String>,
    /// Camera samples per pixel.
    #[arg(long, value_parser = super::parse::int_in::<u32>(1, crate::render::MAX_SPP))]
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
    #[arg(long, value_parser = super::parse::named::<crate::render::ShadingMode>)]
    pub(super) shading: Option<String>,
    /// Wavelengths per camera sample for --shading rgb (1..64).
    #[arg(long, value_parser = super::parse::int_in::<usize>(1, 64))]
    pub(super) wavelengths: Option<usize>,
    /// Wavelength sampling for --shading rgb: jittered, stratified or hero.
    #[arg(long, value_parser = super::parse::named::<crate::spectrum::WavelengthStrategy>)]
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
    #[arg(long, value_parser = super::parse::named::<crate::io::ThicknessUnit>)]
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
    /// Which set of a MELP frame to draw when its Eulerian (e_) and Lagrangian (l_) files are
    /// both given: lagrangian (the default: they carry the film), eulerian or both.
    #[arg(long)]
    pub(super) melp_set: Option<String>,
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
    /// particles, nor trim them at open edges (film.fit_radii = false; --fit-radii never).
    #[arg(long, conflicts_with = "fit_radii")]
    pub(super) raw_radii: bool,
    /// When splat radii are fitted to the sampling: auto (the default: where the fit run on a
    /// sample of the particles changes something), always (every cloud), never (as
    /// --raw-radii) (film.fit_radii).
    #[arg(long, value_parser = super::parse::named::<crate::pipeline::FitRadii>)]
    pub(super) fit_radii: Option<String>,
    /// Flat disks: skip the curvature estimate that tilts each disk's normal with the film's
    /// curvature (faster set-up; curved films then show faceted reflections).
    #[arg(long)]
    pub(super) flat_splats: bool,
    /// How 3D particles are drawn: auto (the default: if the run's frame 0, <run>/0, holds no
    /// 3D particles, they were shed later and stay droplets; otherwise as surface), surface
    /// (particles packed into bodies of liquid, e.g. drops falling onto a film, as a refracting
    /// water surface; the rest droplets) or droplets (every 3D particle a droplet).
    #[arg(long)]
    pub(super) liquid: Option<String>,
    /// How rays find a liquid body's surface: grid (the default: the field sampled once on a
    /// grid of 3 cells a spacing, within 0.03 spacings of the exact surface) or exact (the
    /// field summed over the particles at every step: slower).
    #[arg(long)]
    pub(super) liquid_field: Option<String>,
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
    #[arg(long, value_parser = super::parse::named::<crate::image::ToneMap>)]
    pub(super) tonemap: Option<String>,
    /// What to show: shaded (the thin-film render), or a scientific view of the first film
    /// crossing: thickness (false colour with a colour bar, nm), normal, depth, particle-id,
    /// coverage (splats blended per pixel: shows sparse regions and holes), or attribute:NAME
    /// (any stored per-particle attribute, e.g. vrt, conc, gamma; a vector such as v by its
    /// magnitude; with a colour bar).
    #[arg(long, value_parser = super::parse::named::<crate::render::View>)]
    pub(super) view: Option<String>,
    /// Values at the ends of the colour bar of --view attribute:NAME, MIN,MAX (default: the
    /// range of what is visible).
    #[arg(long, value_parser = super::parse::min_max, allow_hyphen_values = true)]
    pub(super) view_range: Option<[f32; 2]>,
    /// Motion blur: the fraction of a frame the shutter is open, 0..=1 (default 0, off),
    /// centred on the frame's time. The film particles move along their stored velocity
    /// (velocity, v or V with x, y, z components, scene units per simulation second); needs
    /// --frame-time. The shaded view only.
    #[arg(long, value_name = "S", allow_hyphen_values = true, value_parser = super::parse::finite_f32)]
    pub(super) shutter: Option<f32>,
    /// Simulation seconds between two frames, for --shutter (the simulators do not store it;
    /// e.g. 0.02 for the thin-film SPH code's frame_rate = 50).
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true, value_parser = super::parse::finite_f32)]
    pub(super) frame_time: Option<f32>,
    /// Time slices of the open shutter (1..=256, default 8, at most --spp): each is rendered
    /// with its share of the samples from its own geometry, and the pictures averaged.
    #[arg(long, value_name = "K", value_parser = super::parse::int_in::<u32>(1, 256))]
    pub(super) shutter_slices: Option<u32>,
    /// Drop particles with non-finite positions or bad thickness and re-estimate bad normals
    /// and radii (says how many), instead of refusing the file.
    #[arg(long)]
    pub(super) repair: bool,
    /// Render a sequence: frame numbers A..B (B excluded) or A..=B. The input (or the scene's
    /// input.cloud) and the output contain a frame pattern, {} or {:04} (zero-padded), e.g.
    /// `render 'frames/frame_{:04}.ply' -o 'out/{:04}.png' --frames 0..240`, or straight into
    /// a movie with `-o movie.mp4`. Each frame's seed is the seed plus the frame number.
    #[arg(long, value_parser = super::parse::frame_list)]
    pub(super) frames: Option<super::parse::FrameList>,
    /// Turn the camera DEG degrees about the scene's up axis (camera.up, default +y) over the
    /// --frames sequence, around its look-at point: frame i of N is turned by DEG·i/N, so 360
    /// loops without a repeated frame. The start is the sequence's camera (auto-framed on the
    /// first frame, or the scene's). With a single input without a frame pattern it is a
    /// turntable: N views of the one cloud, loaded and prepared once. Positive turns
    /// counter-clockwise seen from above.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = super::parse::finite_f32)]
    pub(super) orbit: Option<f32>,
    /// Render only every N-th frame of --frames (or match of a quoted glob), starting at the
    /// K-th (K/N, 0 <= K < N), so N jobs of a render farm (e.g. K = $SLURM_ARRAY_TASK_ID) split
    /// a sequence without talking.
    #[arg(long, value_parser = super::parse::shard)]
    pub(super) shard: Option<(u64, u64)>,
    /// With --frames and no camera position: auto-frame the sequence's one camera on the union
    /// of all frames' bounds (each job then prepares every frame once more to measure it),
    /// instead of on the first frame of --frames. The chosen camera is printed as scene-file
    /// lines.
    #[arg(long)]
    pub(super) frame_all: bool,
    /// Degrees the light turns about +y with an orbiting camera (set by the sequence loop).
    #[arg(skip)]
    pub(super) turn_deg: f32,
    /// The frame being rendered (set by the sequence loop; expands patterns in a scene file).
    #[arg(skip)]
    pub(super) frame: Option<u64>,
    /// Skip frames whose output files already exist as regular files (outputs are renamed into
    /// place only when complete, so such a file is a finished frame; a directory there is an
    /// error), and remove the hidden temporary files (`.NAME.tmp-…`) that writers no longer
    /// running left for the frames of this run (a running job's are kept).
    #[arg(long)]
    pub(super) resume: bool,
    /// Report a frame that fails and go on with the others (exit code 2 at the end if any
    /// failed), instead of stopping at the first.
    #[arg(long)]
    pub(super) keep_going: bool,
    /// Frames per second of the sequence: a movie output (-o movie.mp4) plays at this rate,
    /// and a generated sample's clock (`[input] sample`) moves 1/FPS seconds a frame. Default
    /// 24. Frames read from files are not resampled: their simulation time step is theirs.
    #[arg(long, value_parser = fps_arg, allow_hyphen_values = true)]
    pub(super) fps: Option<f64>,
    /// Movie quality, the codec's constant rate factor: lower is better and larger (H.264
    /// 0..=51, default 18, visually lossless; VP9 0..=63, default 31).
    #[arg(long, value_parser = super::parse::int_in::<u32>(0, 63))]
    pub(super) crf: Option<u32>,
    /// The frame is rendered for a movie: no image file is written (set by the movie loop).
    #[arg(skip)]
    pub(super) in_memory: bool,
    /// Refuse to render (exit 2, before loading anything) if the estimated peak memory
    /// exceeds SIZE, e.g. 8G or 512M (binary units; see `filmsplat info` for the estimate).
    /// Default: the memory available to the process (MemAvailable in /proc/meminfo, lowered to
    /// its cgroup's memory limit, v1 or v2, as Slurm sets it; no limit where that cannot be
    /// read). A SIZE above it lets a render try anyway.
    #[arg(long, value_name = "SIZE", value_parser = crate::pipeline::memory::parse_size)]
    pub(super) max_memory: Option<u64>,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub(super) quiet: bool,
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

/// clap value parser for `--fps`: a number in (0, 1000].
pub(super) fn fps_arg(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number of frames per second"))?;
    crate::image::video::check_fps(v)
        .map(|()| v)
        .map_err(|_| format!("'{s}': frames per second must be a number in (0, 1000]"))
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
