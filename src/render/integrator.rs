//! The integrator: camera rays, the ray tree through the films, and the per-pixel buffers.
//!
//! A film between air and air is a perfect specular surface that does not bend light: each
//! crossing splits a ray into a mirror reflection carrying `R` and a straight continuation
//! carrying `T = 1 − R` (per RGB channel). Both are followed — a deterministic ray tree, not a
//! random walk — until the branch's weight falls below `min_weight` or the depth reaches
//! `max_depth`; such a branch then returns the environment seen along it (it "escapes"). This
//! keeps a white furnace exactly white and the image free of path-tracing noise.

use super::camera::Camera;
use super::environment::Environment;
use super::sampler::{Pcg32, mix64};
use super::shading::{FilmShader, SampleShading};
use crate::geometry::{FilmGeometry, Ray, SurfaceHit};
use crate::{Error, Result};
use glam::Vec3;
use rayon::prelude::*;

/// What to render: geometry, camera, light.
#[derive(Debug)]
pub struct Scene {
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
}

/// How to render it.
#[derive(Debug, Clone)]
pub struct RenderSettings {
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Camera samples per pixel.
    pub spp: u32,
    /// Most film crossings along one path.
    pub max_depth: u32,
    /// Branches whose RGB weight falls below this escape to the environment.
    pub min_weight: f32,
    /// Random seed: the same seed gives the same image.
    pub seed: u64,
    /// Draw a progress bar on stderr (only when it is a terminal).
    pub progress: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 960,
            height: 540,
            spp: 4,
            max_depth: 12,
            min_weight: 1e-3,
            seed: 0,
            progress: false,
        }
    }
}

/// The rendered buffers, row-major, top row first.
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Linear RGB radiance.
    pub rgb: Vec<Vec3>,
    /// Fraction of camera samples whose first ray hit a film.
    pub alpha: Vec<f32>,
    /// Mean distance to the first film crossing over the samples that hit (0 where none did).
    pub depth: Vec<f32>,
    /// Mean film normal at the first crossing (unit-ish; zero where nothing was hit).
    pub normal: Vec<Vec3>,
    /// Mean film thickness at the first crossing, nm (0 where nothing was hit).
    pub thickness: Vec<f32>,
    /// Mean number of splats blended into the first crossing (0 where nothing was hit).
    pub hits: Vec<f32>,
    /// Total rays traced (for throughput figures).
    pub rays: u64,
}

const TILE: usize = 16;

struct Tracer<'a> {
    scene: &'a Scene,
    shader: &'a FilmShader,
    settings: &'a RenderSettings,
}

/// Per-sample state carried down the ray tree.
struct PathState {
    shading: SampleShading,
    rays: u64,
}

impl Tracer<'_> {
    /// Radiance arriving along `ray` from beyond `t_min`.
    fn trace(&self, ray: &Ray, t_min: f32, depth: u32, weight: Vec3, st: &mut PathState) -> Vec3 {
        if depth >= self.settings.max_depth || weight.max_element() < self.settings.min_weight {
            return self.scene.environment.radiance(ray.dir);
        }
        st.rays += 1;
        match self.scene.geometry.intersect(ray, t_min, f32::INFINITY) {
            None => self.scene.environment.radiance(ray.dir),
            Some(hit) => self.shade(ray, &hit, depth, weight, st),
        }
    }

    /// Radiance leaving a film crossing `hit` back along `ray`: the reflected and the
    /// transmitted branch, weighted by R and T = 1 − R.
    fn shade(
        &self,
        ray: &Ray,
        hit: &SurfaceHit,
        depth: u32,
        weight: Vec3,
        st: &mut PathState,
    ) -> Vec3 {
        let cos_signed = ray.dir.dot(hit.normal);
        let cos_i = cos_signed.abs().min(1.0);
        let r = self
            .shader
            .reflectance(&st.shading, cos_i, hit.thickness_nm);
        let t = Vec3::ONE - r;
        // Transmitted: the same line, beyond the film layer.
        let lt = self.trace(
            ray,
            hit.t_exit + self.scene.epsilon,
            depth + 1,
            weight * t,
            st,
        );
        // Reflected: mirror about the normal that faces the incoming ray.
        let n = if cos_signed < 0.0 {
            hit.normal
        } else {
            -hit.normal
        };
        let dir = (ray.dir - 2.0 * ray.dir.dot(n) * n).normalize();
        let skip = (self.scene.layer_skip / cos_i.max(0.1)).max(self.scene.epsilon);
        let reflected = Ray {
            origin: hit.position,
            dir,
        };
        let lr = self.trace(&reflected, skip, depth + 1, weight * r, st);
        r * lr + t * lt
    }
}

/// Renders `scene` with `shader` and `settings`. Deterministic for a given seed.
pub fn render(
    scene: &Scene,
    shader: &FilmShader,
    settings: &RenderSettings,
) -> Result<RenderOutput> {
    let (w, h) = (settings.width, settings.height);
    if w == 0 || h == 0 {
        return Err(Error::invalid(format!(
            "image size must be at least 1x1, got {w}x{h}"
        )));
    }
    if settings.spp == 0 {
        return Err(Error::invalid("samples per pixel must be at least 1"));
    }
    let aspect = w as f32 / h as f32;
    let tracer = Tracer {
        scene,
        shader,
        settings,
    };
    let tiles_x = w.div_ceil(TILE);
    let tiles: Vec<(usize, usize)> = (0..h.div_ceil(TILE))
        .flat_map(|ty| (0..tiles_x).map(move |tx| (tx, ty)))
        .collect();
    let bar = progress_bar(settings.progress, tiles.len() as u64);
    let results: Vec<(usize, usize, Vec<Pixel>, u64)> = tiles
        .par_iter()
        .map(|&(tx, ty)| {
            let (x0, y0) = (tx * TILE, ty * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let mut st = PathState {
                shading: SampleShading::default(),
                rays: 0,
            };
            let mut u = Vec::with_capacity(shader.randoms_per_sample());
            let mut pixels = Vec::with_capacity((x1 - x0) * (y1 - y0));
            for y in y0..y1 {
                for x in x0..x1 {
                    pixels.push(render_pixel(&tracer, x, y, aspect, &mut st, &mut u));
                }
            }
            bar.inc(1);
            (x0, y0, pixels, st.rays)
        })
        .collect();
    bar.finish_and_clear();
    let mut out = RenderOutput {
        width: w,
        height: h,
        rgb: vec![Vec3::ZERO; w * h],
        alpha: vec![0.0; w * h],
        depth: vec![0.0; w * h],
        normal: vec![Vec3::ZERO; w * h],
        thickness: vec![0.0; w * h],
        hits: vec![0.0; w * h],
        rays: 0,
    };
    for (x0, y0, pixels, rays) in results {
        out.rays += rays;
        let tw = (x0 + TILE).min(w) - x0;
        for (i, p) in pixels.into_iter().enumerate() {
            let k = (y0 + i / tw) * w + x0 + i % tw;
            out.rgb[k] = p.rgb;
            out.alpha[k] = p.alpha;
            out.depth[k] = p.depth;
            out.normal[k] = p.normal;
            out.thickness[k] = p.thickness;
            out.hits[k] = p.hits;
        }
    }
    Ok(out)
}

#[derive(Default)]
struct Pixel {
    rgb: Vec3,
    alpha: f32,
    depth: f32,
    normal: Vec3,
    thickness: f32,
    hits: f32,
}

fn render_pixel(
    tr: &Tracer,
    x: usize,
    y: usize,
    aspect: f32,
    st: &mut PathState,
    u: &mut Vec<f32>,
) -> Pixel {
    let s = tr.settings;
    let (w, h) = (s.width, s.height);
    let mut rng = Pcg32::new(s.seed, mix64((y * w + x) as u64));
    let strata = (s.spp as f32).sqrt() as u32;
    let square = strata * strata == s.spp;
    let mut p = Pixel::default();
    let mut hit_samples = 0u32;
    for i in 0..s.spp {
        // Sub-pixel position: the centre for 1 spp, jittered strata for square counts, else
        // uniform jitter.
        let (jx, jy) = if s.spp == 1 {
            (0.5, 0.5)
        } else if square {
            let (a, b) = (i % strata, i / strata);
            (
                (a as f32 + rng.next_f32()) / strata as f32,
                (b as f32 + rng.next_f32()) / strata as f32,
            )
        } else {
            (rng.next_f32(), rng.next_f32())
        };
        u.clear();
        u.extend((0..tr.shader.randoms_per_sample()).map(|_| rng.next_f32()));
        tr.shader.begin_sample(&mut st.shading, u);
        let ray = tr.scene.camera.ray(
            (x as f32 + jx) / w as f32,
            (y as f32 + jy) / h as f32,
            aspect,
        );
        // The first crossing feeds the auxiliary buffers, then the ray tree.
        st.rays += 1;
        let c = match tr.scene.geometry.intersect(&ray, 0.0, f32::INFINITY) {
            Some(hit) => {
                hit_samples += 1;
                p.depth += hit.t;
                p.normal += hit.normal;
                p.thickness += hit.thickness_nm;
                p.hits += hit.coverage as f32;
                tr.shade(&ray, &hit, 0, Vec3::ONE, st)
            }
            None => tr.scene.environment.radiance(ray.dir),
        };
        // Drop non-finite samples rather than poison the pixel (pbrt does the same).
        if c.is_finite() {
            p.rgb += c;
        }
    }
    let inv = 1.0 / s.spp as f32;
    p.rgb *= inv;
    p.alpha = hit_samples as f32 * inv;
    if hit_samples > 0 {
        let k = 1.0 / hit_samples as f32;
        p.depth *= k;
        p.normal *= k;
        p.thickness *= k;
        p.hits *= k;
    }
    p
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
