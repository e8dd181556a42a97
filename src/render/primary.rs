//! The camera ray: droplets first, each grown to the pixel's footprint so that one smaller
//! than a pixel still shows its share of it, then the film, props and lights behind them.
//!
//! A camera ray that meets a grown droplet (radius g ≥ the droplet's r, see
//! [`crate::geometry::Droplets::footprints`]) sees the droplet with weight (r/g)² of what
//! is left of the sample, shaded at the point of the true sphere with the same normal (a ray
//! parallel to the camera ray meeting it there), and sees on past the grown sphere with the
//! rest. Over a pixel's samples the expected droplet share is π r² / pixel area (the sample
//! falls in the grown disk with probability π g² / A); a droplet larger than its footprint has
//! g = r and covers its samples fully, as before.
//!
//! With one sample at each pixel's centre, a pinhole camera, disks and no droplets, the camera
//! rays' film crossings come from rasterising the disks ([`PrimaryRaster`], tile by tile)
//! instead of one BVH query per ray: the same layers, blended up to the order of the float
//! sums. Only with at least one pixel per two disks: every disk is projected, and on the 1M
//! bubble at 960×540 (0.52 pixels a disk) the whole render already costs what it did.

use super::radiance::{Lanes, Radiance};
use super::transport::{Branch, PathState, Tracer};
use super::world::{RenderSettings, WorldRef};
use crate::geometry::{FilmGeometry, PinholeGrid, PrimaryRaster, RASTER_TILE, Ray, SurfaceHit};
use glam::Vec3;

/// The camera rays' film crossings of one raster tile, row-major, [`RASTER_TILE`] a row.
pub(crate) type TileFilm = [Option<SurfaceHit>; RASTER_TILE * RASTER_TILE];

/// The disks binned for the camera rays of this render, where the raster applies (see the
/// module docs); `None` otherwise.
pub(crate) fn camera_raster<'a>(
    scene: &WorldRef<'a>,
    settings: &RenderSettings,
) -> Option<PrimaryRaster<'a>> {
    let (FilmGeometry::Disks(disks), 1) = (scene.geometry, settings.spp) else {
        return None;
    };
    let camera = scene.camera;
    let pixels = settings.width.saturating_mul(settings.height);
    if camera.has_lens() || !scene.staging.droplets.is_empty() || 2 * pixels < disks.len() {
        return None;
    }
    let aspect = settings.width as f32 / settings.height as f32;
    disks.primary_raster(&PinholeGrid {
        eye: camera.position,
        forward: camera.forward(),
        right: camera.right(),
        up: camera.up(),
        half_width: camera.tan_half_fov() * aspect,
        half_height: camera.tan_half_fov(),
        width: settings.width,
        height: settings.height,
    })
}

/// The film crossings of the camera rays through the centres of the tile whose top-left pixel
/// is (`x0`, `y0`) (a multiple of [`RASTER_TILE`]).
pub(crate) fn tile_film(
    raster: &PrimaryRaster,
    scene: &WorldRef,
    settings: &RenderSettings,
    (x0, y0): (usize, usize),
) -> TileFilm {
    let (w, h) = (settings.width, settings.height);
    let aspect = w as f32 / h as f32;
    let camera = scene.camera;
    // The ray `camera_sample` casts through the pixel centre, bit for bit.
    let ray = |x: usize, y: usize| {
        camera.ray(
            (x as f32 + 0.5) / w as f32,
            (y as f32 + 0.5) / h as f32,
            aspect,
        )
    };
    let t = (y0 / RASTER_TILE) * w.div_ceil(RASTER_TILE) + x0 / RASTER_TILE;
    let mut out = [None; RASTER_TILE * RASTER_TILE];
    raster.tile(t, &ray, &mut out);
    out
}

/// Most partly covering droplets followed along one camera ray; what is left after them is
/// seen through the last.
const MAX_PARTIAL: usize = 16;

/// What one camera sample leaves in the auxiliary buffers, each part with its share of the
/// sample (the shares sum to at most 1).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FirstHits {
    /// The film crossing seen behind the droplets, and the share of the sample that sees it.
    pub film: Option<(SurfaceHit, f32)>,
    /// Share of the sample covered by droplets.
    pub droplet: f32,
    /// Σ share · distance of the droplets seen.
    pub droplet_depth: f32,
    /// Σ share · outward normal of the droplets seen.
    pub droplet_normal: Vec3,
}

impl Tracer<'_> {
    /// Radiance along camera ray `ray`, and what it meets first (see the module docs); `film`,
    /// when `Some`, is the ray's film crossing from the raster.
    pub(super) fn camera_trace<L: Lanes>(
        &self,
        l: &L,
        ray: &Ray,
        st: &mut PathState,
        film: Option<Option<SurfaceHit>>,
    ) -> (L::C, FirstHits) {
        let drops = &self.scene.staging.droplets;
        let mut first = FirstHits::default();
        let mut sum = L::C::splat(0.0);
        let mut rest = 1.0f32;
        let mut t_min = 0.0;
        if !drops.is_empty() {
            for _ in 0..MAX_PARTIAL {
                let t_max = self.opaque_distance(ray, t_min);
                let Some(g) = drops.intersect_grown(self.scene.footprints, ray, t_min, t_max)
                else {
                    break;
                };
                let share = rest * g.coverage;
                let (c, r) = drops.sphere(g.hit.index);
                // The true sphere's point with the grown hit's normal, met along the camera
                // ray's direction at the same distance.
                let p = c + g.hit.normal * r;
                let shrunk = Ray {
                    origin: p - ray.dir * g.hit.t,
                    dir: ray.dir,
                };
                let colour = self.shade_droplet(l, &shrunk, &g.hit, 0, L::C::splat(share), st);
                sum = sum + colour * share;
                first.droplet += share;
                first.droplet_depth += share * g.hit.t;
                first.droplet_normal += share * g.hit.normal;
                rest -= share;
                if g.coverage >= 1.0 || rest <= 1e-6 {
                    return (sum, first);
                }
                // Past the grown sphere: a relative margin too, so rounding at large distances
                // cannot meet its far side again.
                t_min = g.t_exit * (1.0 + 1e-5) + self.scene.epsilon;
            }
        }
        let behind = Branch {
            ray,
            t_min,
            depth: 0,
            weight: L::C::splat(rest),
        };
        // The raster's crossing holds for the ray from its origin on (no droplet moved it).
        let film = film.filter(|_| t_min == 0.0);
        let (c, hit) = self.nearest_with(l, behind, st, film);
        first.film = hit.map(|h| (h, rest));
        (sum + c * rest, first)
    }

    /// Distance along `ray` from `t_min` to the nearest film, prop or light (∞ if none).
    fn opaque_distance(&self, ray: &Ray, t_min: f32) -> f32 {
        let staging = &self.scene.staging;
        let mut t = self
            .scene
            .geometry
            .intersect(ray, t_min, f32::INFINITY)
            .map_or(f32::INFINITY, |h| h.t);
        if !staging.props.is_empty()
            && let Some(p) = staging.props.intersect(ray, t_min, t)
        {
            t = p.t;
        }
        if !staging.lights.is_empty()
            && let Some((_, tl, _)) = super::lights::nearest(&staging.lights, ray, t_min, t)
        {
            t = tl;
        }
        t
    }
}
