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

use super::radiance::{Lanes, Radiance};
use super::transport::{Branch, PathState, Tracer};
use crate::geometry::{Ray, SurfaceHit};
use glam::Vec3;

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
    /// Radiance along camera ray `ray`, and what it meets first (see the module docs).
    pub(super) fn camera_trace<L: Lanes>(
        &self,
        l: &L,
        ray: &Ray,
        st: &mut PathState,
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
        let (c, hit) = self.nearest(l, behind, st);
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
