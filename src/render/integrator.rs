//! The integrator: camera rays, the ray tree through the films, and the per-pixel buffers.
//!
//! A film between air and air is a perfect specular surface that does not bend light: each
//! crossing splits a ray into a mirror reflection carrying `R` and a straight continuation
//! carrying `T = 1 − R` (per RGB channel). Both are followed — a deterministic ray tree, not a
//! random walk — until the branch's weight falls below `min_weight` or the depth reaches
//! `max_depth`; such a branch then returns the environment seen along it (it "escapes"). This
//! keeps a white furnace exactly white and the image free of path-tracing noise.
//!
//! The studio ([`Staging`](super::Staging)) adds area lights, which rays meet before the environment, and
//! opaque props, shaded by light sampling (see `transport`). The transport is written
//! once, generic over RGB and spectral radiance; `--shading spectral` runs the spectral
//! instance, the other modes the RGB one.

use super::primary::{FirstHits, TileFilm, camera_raster, tile_film};
use super::radiance::{Lanes, RgbLanes, SpectralLanes};
use super::sampler::{Pcg32, mix64};
use super::shading::{FilmShader, SampleShading, ShadingMode};
use super::transport::{PathState, Tracer};
use super::world::{MAX_SPP, RenderSettings, WorldRef};
use crate::{Error, Result};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::atomic::Ordering;

/// The rendered buffers, row-major, top row first.
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Linear RGB radiance.
    pub rgb: Vec<Vec3>,
    /// Share of the pixel's camera samples whose first ray met a film or a droplet (a droplet
    /// smaller than the pixel counts with its share of it).
    pub alpha: Vec<f32>,
    /// Mean distance to the first film crossing or droplet over what was met, weighted by its
    /// share (0 where nothing was).
    pub depth: Vec<f32>,
    /// Mean normal of the first film crossing or droplet (outward), weighted as `depth`
    /// (unit-ish; zero where nothing was met).
    pub normal: Vec<Vec3>,
    /// Mean film thickness at the first crossing, nm (0 where nothing was hit).
    pub thickness: Vec<f32>,
    /// Mean number of splats blended into the first crossing (0 where nothing was hit).
    pub hits: Vec<f32>,
    /// Share of the pixel covered by droplets, 0..1 (included in `alpha`).
    pub droplets: Vec<f32>,
    /// Total rays traced (for throughput figures).
    pub rays: u64,
}

/// Render tiles are the camera rays' raster tiles (16×16), which it answers whole.
const TILE: usize = crate::geometry::RASTER_TILE;

/// Renders `scene` (a `&World`, or a [`WorldRef`] of borrowed parts) with `shader` and
/// `settings`. Deterministic for a given seed. Reads the scene only: renders of one scene with
/// different cameras may run at once.
///
/// # Example
/// A lossless film in a uniform sky: what it reflects plus what it transmits is the sky
/// (R + T = 1), so every pixel is the sky's colour, whatever the film's thickness:
/// ```
/// use filmsplat::geometry::DiskGeometry;
/// use filmsplat::render::{
///     Camera, Environment, FilmShader, RenderSettings, Scene, ShadingMode, Staging, render,
/// };
/// use filmsplat::spectrum::WavelengthStrategy;
/// use glam::Vec3;
/// let sky = Vec3::new(0.2, 0.5, 0.9);
/// let film = DiskGeometry::build(&[Vec3::ZERO], &[Vec3::Z], &[10.0], &[400.0])?;
/// let scene = Scene {
///     geometry: film.into(),
///     camera: Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 30.0),
///     environment: Environment::Uniform(sky),
///     layer_skip: 1e-3,
///     epsilon: 1e-5,
///     staging: Staging::default(),
/// };
/// let shader = FilmShader::new(1.33, ShadingMode::Lut, 16, WavelengthStrategy::Jittered);
/// let settings = RenderSettings { width: 8, height: 6, spp: 1, ..RenderSettings::default() };
/// let out = render(&scene, &shader, &settings)?;
/// for (c, a) in out.rgb.iter().zip(&out.alpha) {
///     assert!((*c - sky).abs().max_element() < 2e-3, "{c}");
///     assert_eq!(*a, 1.0, "the film fills the view");
/// }
/// # Ok::<(), filmsplat::Error>(())
/// ```
pub fn render<'a>(
    scene: impl Into<WorldRef<'a>>,
    shader: &FilmShader,
    settings: &RenderSettings,
) -> Result<RenderOutput> {
    let scene = scene.into();
    let (w, h) = (settings.width, settings.height);
    if w == 0 || h == 0 {
        return Err(Error::invalid(format!(
            "image size must be at least 1x1, got {w}x{h}"
        )));
    }
    if settings.spp == 0 || settings.spp > MAX_SPP {
        return Err(Error::invalid(format!(
            "samples per pixel must be between 1 and {MAX_SPP}, got {}",
            settings.spp
        )));
    }
    let tracer = Tracer::new(scene, settings);
    let raster = camera_raster(&scene, settings);
    let tiles_x = w.div_ceil(TILE);
    let tiles: Vec<(usize, usize)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..tiles_x).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let bar = progress_bar(settings.progress, tiles.len() as u64);
    let results: Vec<Tile> = tiles
        .par_iter()
        .map(|&(x0, y0)| {
            if cancelled(settings) {
                return Tile::empty(x0, y0);
            }
            let film = raster
                .as_ref()
                .map(|r| tile_film(r, &tracer.scene, settings, (x0, y0)));
            let tile = render_tile(&tracer, shader, x0, y0, film.as_ref());
            bar.inc(1);
            if let Some(done) = &settings.tiles_done {
                done.fetch_add(1, Ordering::Relaxed);
            }
            tile
        })
        .collect();
    bar.finish_and_clear();
    if cancelled(settings) {
        return Err(Error::Cancelled);
    }
    Ok(assemble(w, h, results))
}

/// The pixels of one tile, row by row, and the rays they traced.
struct Tile {
    x0: usize,
    y0: usize,
    pixels: Vec<Pixel>,
    rays: u64,
}

impl Tile {
    fn empty(x0: usize, y0: usize) -> Tile {
        Tile {
            x0,
            y0,
            pixels: Vec::new(),
            rays: 0,
        }
    }
}

/// Renders the tile with top-left pixel `(x0, y0)`; each pixel's random stream is seeded by
/// its index, so the image does not depend on how tiles are scheduled. `film`: the camera
/// rays' film crossings from the raster, where it applies.
fn render_tile(
    tracer: &Tracer,
    shader: &FilmShader,
    x0: usize,
    y0: usize,
    film: Option<&TileFilm>,
) -> Tile {
    let settings = tracer.settings;
    let (w, h) = (settings.width, settings.height);
    let aspect = w as f32 / h as f32;
    let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
    let mut shading = SampleShading::default();
    let mut u = Vec::with_capacity(shader.randoms_per_sample());
    let mut tile = Tile::empty(x0, y0);
    tile.pixels.reserve((x1 - x0) * (y1 - y0));
    for y in y0..y1 {
        for x in x0..x1 {
            // A cancelled render stops inside its tile (the tile is dropped).
            if cancelled(settings) {
                return tile;
            }
            let mut st = PathState {
                rng: Pcg32::new(settings.seed, mix64((y * w + x) as u64)),
                rays: 0,
            };
            let film = film.map(|f| f[(y - y0) * TILE + x - x0]);
            let px = Px { x, y, aspect, film };
            let pixel = render_pixel(tracer, shader, px, &mut st, &mut shading, &mut u);
            tile.pixels.push(pixel);
            tile.rays += st.rays;
        }
    }
    tile
}

/// The image from its tiles.
fn assemble(w: usize, h: usize, tiles: Vec<Tile>) -> RenderOutput {
    let mut out = RenderOutput {
        width: w,
        height: h,
        rgb: vec![Vec3::ZERO; w * h],
        alpha: vec![0.0; w * h],
        depth: vec![0.0; w * h],
        normal: vec![Vec3::ZERO; w * h],
        thickness: vec![0.0; w * h],
        hits: vec![0.0; w * h],
        droplets: vec![0.0; w * h],
        rays: 0,
    };
    for tile in tiles {
        out.rays += tile.rays;
        let tw = (tile.x0 + TILE).min(w) - tile.x0;
        for (i, p) in tile.pixels.into_iter().enumerate() {
            let k = (tile.y0 + i / tw) * w + tile.x0 + i % tw;
            out.rgb[k] = p.rgb;
            out.alpha[k] = p.alpha;
            out.depth[k] = p.depth;
            out.normal[k] = p.normal;
            out.thickness[k] = p.thickness;
            out.hits[k] = p.hits;
            out.droplets[k] = p.droplets;
        }
    }
    out
}

/// True once the caller has asked the render to stop.
fn cancelled(settings: &RenderSettings) -> bool {
    settings
        .cancel
        .as_ref()
        .is_some_and(|c| c.load(Ordering::Relaxed))
}

struct Px {
    x: usize,
    y: usize,
    aspect: f32,
    /// The camera ray's film crossing from the raster (one sample at the pixel centre).
    film: Option<Option<crate::geometry::SurfaceHit>>,
}

#[derive(Default)]
struct Pixel {
    rgb: Vec3,
    alpha: f32,
    depth: f32,
    normal: Vec3,
    thickness: f32,
    hits: f32,
    droplets: f32,
    /// Σ share of the samples that saw a film first.
    film: f32,
}

impl Pixel {
    /// Adds one camera sample's radiance `c` and what it met first.
    fn add(&mut self, c: Vec3, first: FirstHits) {
        if let Some((hit, w)) = first.film {
            self.film += w;
            self.depth += w * hit.t;
            self.normal += w * hit.normal;
            self.thickness += w * hit.thickness_nm;
            self.hits += w * hit.coverage as f32;
        }
        self.droplets += first.droplet;
        self.depth += first.droplet_depth;
        self.normal += first.droplet_normal;
        // Drop non-finite samples rather than poison the pixel (pbrt does the same).
        if c.is_finite() {
            self.rgb += c;
        }
    }

    /// Means over `spp` samples.
    fn finish(&mut self, spp: u32) {
        let inv = 1.0 / spp as f32;
        self.rgb *= inv;
        let seen = self.film + self.droplets;
        self.alpha = (seen * inv).min(1.0);
        self.droplets *= inv;
        if seen > 0.0 {
            self.depth /= seen;
            self.normal /= seen;
        }
        if self.film > 0.0 {
            self.thickness /= self.film;
            self.hits /= self.film;
        }
    }
}

/// Sub-pixel positions of a pixel's samples: the centre for 1 spp, jittered strata for square
/// counts, else the R2 low-discrepancy sequence (M. Roberts, "The unreasonable effectiveness
/// of quasirandom sequences", 2018) shifted by one random offset per pixel.
struct SubPixel {
    spp: u32,
    strata: u32,
    square: bool,
    r2_offset: (f32, f32),
}

impl SubPixel {
    /// The pattern for `spp` samples (draws the R2 offset from `rng` when it is used).
    fn new(spp: u32, rng: &mut Pcg32) -> Self {
        let strata = (spp as f32).sqrt() as u32;
        let square = strata * strata == spp;
        let r2_offset = if spp > 1 && !square {
            (rng.next_f32(), rng.next_f32())
        } else {
            (0.0, 0.0)
        };
        SubPixel {
            spp,
            strata,
            square,
            r2_offset,
        }
    }

    /// Position in the pixel of sample `i`, each coordinate in [0, 1).
    fn at(&self, i: u32, rng: &mut Pcg32) -> (f32, f32) {
        let strata = self.strata;
        if self.spp == 1 {
            (0.5, 0.5)
        } else if self.square {
            let (a, b) = (i % strata, i / strata);
            (
                (a as f32 + rng.next_f32()) / strata as f32,
                (b as f32 + rng.next_f32()) / strata as f32,
            )
        } else {
            const R2: (f32, f32) = (0.754_877_7, 0.569_840_3);
            (
                (self.r2_offset.0 + i as f32 * R2.0).fract(),
                (self.r2_offset.1 + i as f32 * R2.1).fract(),
            )
        }
    }
}

fn render_pixel(
    tr: &Tracer,
    shader: &FilmShader,
    px: Px,
    st: &mut PathState,
    shading: &mut SampleShading,
    u: &mut Vec<f32>,
) -> Pixel {
    let spp = tr.settings.spp;
    let mut p = Pixel::default();
    let pattern = SubPixel::new(spp, &mut st.rng);
    for i in 0..spp {
        // Up to 65536 samples a pixel: look at the cancel flag every 64.
        if i % 64 == 63 && cancelled(tr.settings) {
            break;
        }
        let jitter = pattern.at(i, &mut st.rng);
        let (c, first) = camera_sample(tr, shader, &px, jitter, st, shading, u);
        p.add(c, first);
    }
    p.finish(spp);
    p
}

/// One camera sample at sub-pixel position `jitter` of `px`: its wavelengths (in `shading`,
/// from the random numbers `u`), lens position and ray, traced; linear RGB radiance and the
/// first film crossing or droplets.
fn camera_sample(
    tr: &Tracer,
    shader: &FilmShader,
    px: &Px,
    (jx, jy): (f32, f32),
    st: &mut PathState,
    shading: &mut SampleShading,
    u: &mut Vec<f32>,
) -> (Vec3, FirstHits) {
    let (w, h) = (tr.settings.width, tr.settings.height);
    let camera = tr.scene.camera;
    let rng = &mut st.rng;
    u.clear();
    u.extend((0..shader.randoms_per_sample()).map(|_| rng.next_f32()));
    shader.begin_sample(shading, u);
    let lens = if camera.has_lens() {
        (rng.next_f32(), rng.next_f32())
    } else {
        (0.5, 0.5)
    };
    let ray = camera.ray_lens(
        (px.x as f32 + jx) / w as f32,
        (px.y as f32 + jy) / h as f32,
        px.aspect,
        lens,
    );
    // The first crossing feeds the auxiliary buffers, then the ray tree.
    if shader.mode() == ShadingMode::Spectral {
        let lanes = SpectralLanes::new(shading, shader.ior());
        first(tr, &lanes, &ray, st, px.film)
    } else {
        let lanes = RgbLanes {
            shader,
            state: shading,
        };
        first(tr, &lanes, &ray, st, px.film)
    }
}

/// One camera ray: its linear RGB radiance, and the droplets and film crossing it met first.
fn first<L: Lanes>(
    tr: &Tracer,
    l: &L,
    ray: &crate::geometry::Ray,
    st: &mut PathState,
    film: Option<Option<crate::geometry::SurfaceHit>>,
) -> (Vec3, FirstHits) {
    let (c, seen) = tr.camera_trace(l, ray, st, film);
    (l.to_rgb(c), seen)
}

fn progress_bar(enabled: bool, len: u64) -> indicatif::ProgressBar {
    if !enabled {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent}% ({elapsed} elapsed, ETA {eta})",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    bar
}
