//! Light through a water droplet: a clear sphere of index n (1.33), followed as the film's ray
//! tree is — every interface splits a ray into a reflected and a refracted branch weighted by
//! the unpolarised Fresnel reflectance F and 1 − F (lossless: the weights always sum to one).
//! Inside the sphere the path is followed analytically (a sphere cannot hit itself but at its
//! far side): at each inner hit the part 1 − F leaves, refracted, and F reflects on, until the
//! inner weight falls below the branch threshold or the depth budget ends. Dispersion is
//! neglected (one index for every wavelength).

use super::radiance::{Lanes, Radiance};
use super::transport::{Branch, PathState, Tracer};
use crate::geometry::{DropletHit, Ray};
use crate::optics::interface::{dielectric_reflectance, refracted_cos};
use glam::Vec3;

/// Most inner reflections followed in one droplet.
const MAX_INNER: u32 = 8;

/// Mirror of `d` about the unit normal `n`.
#[inline]
pub(super) fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    (d - 2.0 * d.dot(n) * n).normalize()
}

/// Refraction of unit `d` through a surface of unit normal `n` facing it (d·n < 0), from index
/// `n1` into `n2`; `None` under total internal reflection.
#[inline]
pub(super) fn refract(d: Vec3, n: Vec3, n1: f32, n2: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let cos_t = refracted_cos(cos_i, n1, n2)?;
    let eta = n1 / n2;
    Some((eta * d + (eta * cos_i - cos_t) * n).normalize())
}

impl Tracer<'_> {
    /// Radiance leaving droplet hit `hit` back along `ray` (entering from outside).
    pub(super) fn shade_droplet<L: Lanes>(
        &self,
        l: &L,
        ray: &Ray,
        hit: &DropletHit,
        depth: u32,
        weight: L::C,
        st: &mut PathState,
    ) -> L::C {
        let drops = &self.scene.staging.droplets;
        let ior = drops.ior;
        let eps = self.scene.epsilon;
        let p = ray.at(hit.t);
        // The normal facing the ray (a ray starting inside meets the far side from within).
        let outside = ray.dir.dot(hit.normal) < 0.0;
        let n = if outside { hit.normal } else { -hit.normal };
        let (n1, n2) = if outside { (1.0, ior) } else { (ior, 1.0) };
        let f = dielectric_reflectance(-ray.dir.dot(n), n1, n2);
        let reflected = Ray {
            origin: p + n * eps,
            dir: reflect(ray.dir, n),
        };
        let mut sum = self.trace(l, Branch::new(&reflected, depth + 1, weight * f), st) * f;
        let Some(mut dir) = refract(ray.dir, n, n1, n2).filter(|_| outside) else {
            return sum;
        };
        // Inside: from the entry point to the far side, again and again.
        let mut inner = 1.0 - f;
        let mut origin = p;
        let (c, _) = drops.sphere(hit.index);
        for k in 0..MAX_INNER {
            let s = drops.exit_distance(hit.index, origin, dir);
            let q = origin + dir * s;
            let out_n = (q - c).normalize_or_zero();
            let cos = dir.dot(out_n).clamp(0.0, 1.0);
            let f_in = dielectric_reflectance(cos, ior, 1.0);
            let leave = inner * (1.0 - f_in);
            if leave > 0.0
                && let Some(out_dir) = refract(dir, -out_n, ior, 1.0)
            {
                let out = Ray {
                    origin: q + out_n * eps,
                    dir: out_dir,
                };
                let w = weight * leave;
                sum = sum + self.trace(l, Branch::new(&out, depth + 2 + k, w), st) * leave;
            }
            inner *= f_in;
            if inner * weight.max_channel() < self.settings.min_weight
                || depth + 2 + k >= self.settings.max_depth
            {
                // What is left inside is lost to the budget, as a pruned film branch sees
                // the environment: here it leaves along the current direction.
                let rest = Ray {
                    origin: q + out_n * eps,
                    dir,
                };
                return sum + self.escape_view(l, &rest) * inner;
            }
            dir = reflect(dir, -out_n);
            origin = q;
        }
        // Past the most inner reflections followed, what is left leaves unrefracted.
        let q = origin + dir * drops.exit_distance(hit.index, origin, dir);
        let rest = Ray { origin: q, dir };
        sum + self.escape_view(l, &rest) * inner
    }
}
