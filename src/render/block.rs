//! Camera rays a block of pixels at a time: the film crossings of an 8×8 block's camera rays
//! are found by one tile query ([`FilmGeometry::intersect_tile`]: one walk of the disk tree for
//! the block instead of one a ray), then each sample is traced on from its crossing as
//! [`Tracer::camera_trace`] would.
//!
//! Samples are taken sample-major (the block's first samples, then its second ...), but each
//! pixel keeps its own random stream and draws from it in the same order as when it is traced
//! on its own, and the tile query gives each ray exactly the crossing of the single-ray query,
//! so the image is the same bit for bit.
//!
//! [`FilmGeometry::intersect_tile`]: crate::geometry::FilmGeometry::intersect_tile

use super::pixel::{Pixel, Px, SubPixel};
use super::radiance::{Lanes, RgbLanes, SpectralLanes};
use super::sampler::{Pcg32, mix64};
use super::shading::{FilmShader, SampleShading, ShadingMode};
use super::transport::{PathState, Tracer};
use crate::geometry::{Primitive, Ray, SurfaceHit, TILE_RAYS};
use glam::Vec3;

/// Side of a block of pixels whose camera rays are traced together, pixels.
const BLOCK: usize = 8;
const _: () = assert!(BLOCK * BLOCK <= TILE_RAYS);

/// True if blocks pay and apply: disks (the tile query shares their tree walk), a pinhole
/// camera (every camera ray leaves one point) and no droplets (met before the film).
pub(super) fn applies(tr: &Tracer) -> bool {
    tr.scene.geometry.primitive() == Some(Primitive::Disk)
        && !tr.scene.camera.has_lens()
        && tr.scene.staging.droplets.is_empty()
}

/// One pixel of a block: where it is, its random stream, its sample pattern, its sums.
struct Slot {
    px: Px,
    st: PathState,
    pattern: SubPixel,
    pixel: Pixel,
}

/// The pixels `x0..x1` × `y0..y1` row by row, traced in blocks, and the rays they traced;
/// stops early (with a partial result) once `stop()` says so.
pub(super) fn tile_pixels(
    tr: &Tracer,
    shader: &FilmShader,
    (x0, y0): (usize, usize),
    (x1, y1): (usize, usize),
    stop: impl Fn() -> bool,
) -> (Vec<Pixel>, u64) {
    let tw = x1 - x0;
    let mut pixels: Vec<Pixel> = (0..tw * (y1 - y0)).map(|_| Pixel::default()).collect();
    let mut rays = 0;
    for by in (y0..y1).step_by(BLOCK) {
        for bx in (x0..x1).step_by(BLOCK) {
            if stop() {
                return (pixels, rays);
            }
            let end = ((bx + BLOCK).min(x1), (by + BLOCK).min(y1));
            for s in trace_block(tr, shader, (bx, by), end, &stop) {
                rays += s.st.rays;
                pixels[(s.px.y - y0) * tw + s.px.x - x0] = s.pixel;
            }
        }
    }
    (pixels, rays)
}

/// The block `x0..x1` × `y0..y1`, sample by sample.
fn trace_block(
    tr: &Tracer,
    shader: &FilmShader,
    (x0, y0): (usize, usize),
    (x1, y1): (usize, usize),
    stop: &impl Fn() -> bool,
) -> Vec<Slot> {
    let settings = tr.settings;
    let (w, h, spp) = (settings.width, settings.height, settings.spp);
    let aspect = w as f32 / h as f32;
    let mut slots: Vec<Slot> = (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (x, y)))
        .map(|(x, y)| {
            let mut rng = Pcg32::new(settings.seed, mix64((y * w + x) as u64));
            let pattern = SubPixel::new(spp, &mut rng);
            Slot {
                px: Px { x, y, aspect },
                st: PathState { rng, rays: 0 },
                pattern,
                pixel: Pixel::default(),
            }
        })
        .collect();
    // Each pixel's wavelength randoms, `stride` apart.
    let nu = shader.randoms_per_sample();
    let stride = nu.max(1);
    let mut u = vec![0.0f32; stride * slots.len()];
    let mut rays = vec![Ray::new(Vec3::ZERO, Vec3::Z); slots.len()];
    let mut films: Vec<Option<SurfaceHit>> = vec![None; slots.len()];
    let mut shading = SampleShading::default();
    let camera = tr.scene.camera;
    for i in 0..spp {
        // Up to 65536 samples a pixel: look at the cancel flag every 64.
        if i % 64 == 63 && stop() {
            break;
        }
        // Each pixel's sample position, wavelength randoms and ray, drawn as `camera_sample`
        // draws them (a pinhole camera draws no lens position).
        for ((s, u), ray) in slots.iter_mut().zip(u.chunks_mut(stride)).zip(&mut rays) {
            let (jx, jy) = s.pattern.at(i, &mut s.st.rng);
            u[..nu].iter_mut().for_each(|v| *v = s.st.rng.next_f32());
            let (sx, sy) = (s.px.x as f32 + jx, s.px.y as f32 + jy);
            *ray = camera.ray_lens(sx / w as f32, sy / h as f32, aspect, (0.5, 0.5));
        }
        tr.scene
            .geometry
            .intersect_tile(&rays, 0.0, f32::INFINITY, &mut films);
        for (k, s) in slots.iter_mut().enumerate() {
            let u = &u[k * stride..k * stride + nu];
            shader.begin_sample(&mut shading, u);
            let (c, first) = if shader.mode() == ShadingMode::Spectral {
                let lanes = SpectralLanes::new(&shading, shader.ior());
                trace(tr, &lanes, &rays[k], &mut s.st, films[k])
            } else {
                let lanes = RgbLanes {
                    shader,
                    state: &shading,
                };
                trace(tr, &lanes, &rays[k], &mut s.st, films[k])
            };
            s.pixel.add(c, first);
        }
    }
    for s in &mut slots {
        s.pixel.finish(spp);
    }
    slots
}

/// One camera ray traced on from its film crossing: linear RGB radiance and what it met.
fn trace<L: Lanes>(
    tr: &Tracer,
    l: &L,
    ray: &Ray,
    st: &mut PathState,
    film: Option<SurfaceHit>,
) -> (Vec3, super::primary::FirstHits) {
    let (c, seen) = tr.camera_trace_past_film(l, ray, st, film);
    (l.to_rgb(c), seen)
}
