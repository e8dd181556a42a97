//! Light through bulk liquid: a body of water bounded by the particles' implicit surface
//! ([`crate::geometry::LiquidSurface`]), a dielectric like a droplet, only its surface is not a
//! sphere. Each crossing of the surface, entering or leaving, splits the ray into a reflected
//! and a refracted branch weighted by the unpolarised Fresnel reflectance F and 1 − F
//! (total internal reflection: all reflected); the refracted branch inside the water is traced
//! like any other, so it meets the far side of the body — or a film, a droplet or a prop in the
//! way — as the ray tree's next crossing. Dispersion is neglected (one index for every
//! wavelength).

use super::droplet::{reflect, refract};
use super::radiance::Lanes;
use super::transport::{Branch, PathState, Tracer};
use crate::geometry::{LiquidHit, Ray, SurfaceHit, WATER_IOR};
use crate::optics::interface::dielectric_reflectance;

/// Offset of the rays leaving a liquid crossing along the normal, liquid spacings (well above
/// the crossing's bisection tolerance, 10⁻⁴ spacings).
const OFFSET_SPACINGS: f32 = 1e-3;

impl Tracer<'_> {
    /// Radiance leaving liquid crossing `hit` back along `ray`.
    pub(super) fn shade_liquid<L: Lanes>(
        &self,
        l: &L,
        ray: &Ray,
        hit: &LiquidHit,
        depth: u32,
        weight: L::C,
        st: &mut PathState,
    ) -> L::C {
        let liquid = &self.scene.staging.liquid;
        let eps = (OFFSET_SPACINGS * liquid.spacing()).max(self.scene.epsilon);
        let p = ray.at(hit.t);
        // The normal facing the ray; the indices by which side the ray comes from.
        let n = if ray.dir.dot(hit.normal) < 0.0 {
            hit.normal
        } else {
            -hit.normal
        };
        let (n1, n2) = if hit.entering {
            (1.0, WATER_IOR)
        } else {
            (WATER_IOR, 1.0)
        };
        let f = dielectric_reflectance(-ray.dir.dot(n), n1, n2);
        let reflected = Ray {
            origin: p + n * eps,
            dir: reflect(ray.dir, n),
        };
        let sum = self.trace(l, Branch::new(&reflected, depth + 1, weight * f), st) * f;
        let Some(dir) = refract(ray.dir, n, n1, n2) else {
            return sum;
        };
        let t = 1.0 - f;
        let refracted = Ray {
            origin: p - n * eps,
            dir,
        };
        sum + self.trace(l, Branch::new(&refracted, depth + 1, weight * t), st) * t
    }
}

impl Tracer<'_> {
    /// The first-crossing record of a liquid hit for the auxiliary buffers (alpha, depth,
    /// normal, like a film's): no film there, so thickness 0 nm and no splats.
    pub(super) fn liquid_first_hit(&self, ray: &Ray, hit: &LiquidHit) -> SurfaceHit {
        SurfaceHit {
            t: hit.t,
            t_exit: hit.t,
            position: ray.at(hit.t),
            normal: hit.normal,
            thickness_nm: 0.0,
            coverage: 0,
            particle: u32::MAX,
        }
    }
}
