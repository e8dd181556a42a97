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
    /// What passes straight through the water along `ray` up to `t_max` (a shadow ray, as a
    /// film's: refraction and the light the water focuses, its caustics, are left out): the
    /// product over the crossings of the bulk liquid's surface and of the droplets of the
    /// Fresnel transmittance `1 − F(cos θ, 1, n)` seen from the air side (by reciprocity the
    /// same for light leaving the water along the refracted path, which the straight ray
    /// stands for: so no total internal reflection); a droplet is entered and left at the same
    /// angle, `(1 − F)²`. `None` once the product falls below `min_weight`; 1 without water.
    /// Cost: one surface march per liquid crossing, one sphere-tree query per droplet.
    pub(super) fn liquid_transmittance(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let staging = &self.scene.staging;
        let transmit = |cos: f32| 1.0 - dielectric_reflectance(cos.abs(), 1.0, WATER_IOR);
        let mut tr = 1.0;
        let (liquid, drops) = (&staging.liquid, &staging.droplets);
        if !liquid.is_empty() {
            let eps = (OFFSET_SPACINGS * liquid.spacing()).max(self.scene.epsilon);
            let mut t = 0.0;
            for _ in 0..self.settings.max_depth {
                let Some(hit) = liquid.intersect(ray, t, t_max) else {
                    break;
                };
                tr *= transmit(ray.dir.dot(hit.normal));
                if tr < self.settings.min_weight {
                    return None;
                }
                t = hit.t + eps;
            }
        }
        if !drops.is_empty() {
            let mut t = 0.0;
            for _ in 0..self.settings.max_depth {
                let Some(hit) = drops.intersect(ray, t, t_max) else {
                    break;
                };
                tr *= transmit(ray.dir.dot(hit.normal)).powi(2);
                if tr < self.settings.min_weight {
                    return None;
                }
                let p = ray.at(hit.t);
                t = hit.t + drops.exit_distance(hit.index, p, ray.dir) + self.scene.epsilon;
            }
        }
        Some(tr)
    }

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{DiskGeometry, Droplets, LiquidSurface};
    use crate::render::{Camera, Environment, RenderSettings, World, WorldRef};
    use glam::Vec3;

    /// A ball of water of radius 10 spacings (1 cm) at the origin, and one film disk far away.
    fn world() -> World {
        let s = 1e-3;
        let mut pts = Vec::new();
        for i in -10..=10 {
            for j in -10..=10 {
                for k in -10..=10 {
                    let p = Vec3::new(i as f32, j as f32, k as f32) * s;
                    if p.length() <= 10.0 * s {
                        pts.push(p);
                    }
                }
            }
        }
        let far = [Vec3::new(5.0, 0.0, 0.0)];
        let geometry = DiskGeometry::build(&far, &[Vec3::Z], &[0.1], &[300.0]).unwrap();
        let staging = crate::render::Staging {
            liquid: LiquidSurface::build(&pts, s).unwrap(),
            ..Default::default()
        };
        World {
            geometry: geometry.into(),
            camera: Camera::look_at(Vec3::Z, Vec3::ZERO, Vec3::Y, 20.0),
            environment: Environment::Uniform(Vec3::ONE),
            layer_skip: 1e-4,
            epsilon: 1e-6,
            staging,
        }
    }

    #[test]
    fn a_shadow_ray_through_water_keeps_the_fresnel_transmittance_of_each_crossing() {
        let w = world();
        let settings = RenderSettings::default();
        let tracer = Tracer::new(WorldRef::from(&w), &settings);
        let up = |x: f32| Ray {
            origin: Vec3::new(x, -0.1, 0.0),
            dir: Vec3::Y,
        };
        // Through the centre: in and out at normal incidence, (1 − F₀)² with
        // F₀ = ((n − 1)/(n + 1))² (Hecht, Optics, eq. 4.67 at normal incidence).
        let f0 = ((WATER_IOR - 1.0) / (WATER_IOR + 1.0)).powi(2);
        let centre = tracer
            .liquid_transmittance(&up(0.0), f32::INFINITY)
            .unwrap();
        assert!((centre - (1.0 - f0).powi(2)).abs() < 2e-3, "{centre}");
        // Stopping inside the ball (a prop in the water): the entry alone.
        let inside = tracer.liquid_transmittance(&up(0.0), 0.1).unwrap();
        assert!((inside - (1.0 - f0)).abs() < 2e-3, "{inside}");
        // Off-centre the crossings are oblique: less passes. Missing the ball: all.
        let oblique = tracer.liquid_transmittance(&up(0.009), f32::INFINITY);
        assert!(oblique.is_none_or(|t| t < centre - 0.01), "{oblique:?}");
        assert_eq!(
            tracer.liquid_transmittance(&up(0.02), f32::INFINITY),
            Some(1.0)
        );
    }

    #[test]
    fn a_shadow_ray_through_a_droplet_keeps_its_two_fresnel_transmittances() {
        let mut w = world();
        w.staging.liquid = LiquidSurface::default();
        let c = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0)];
        w.staging.droplets = Droplets::build(&c, &[0.01, 0.01]).unwrap();
        let settings = RenderSettings::default();
        let tracer = Tracer::new(WorldRef::from(&w), &settings);
        let ray = |x: f32| Ray {
            origin: Vec3::new(x, -0.1, 0.0),
            dir: Vec3::Y,
        };
        // Two droplets on the axis, each in and out at normal incidence: (1 − F₀)⁴.
        let f0 = ((WATER_IOR - 1.0) / (WATER_IOR + 1.0)).powi(2);
        let two = tracer
            .liquid_transmittance(&ray(0.0), f32::INFINITY)
            .unwrap();
        assert!((two - (1.0 - f0).powi(4)).abs() < 1e-4, "{two}");
        // Only the first before a prop between them; at 60° incidence (x = r sin 60°) the
        // exact Fresnel transmittance squared, twice.
        let one = tracer.liquid_transmittance(&ray(0.0), 0.3).unwrap();
        assert!((one - (1.0 - f0).powi(2)).abs() < 1e-4, "{one}");
        let cos = 60f32.to_radians().cos();
        let t60 = 1.0 - dielectric_reflectance(cos, 1.0, WATER_IOR);
        let x = 0.01 * 60f32.to_radians().sin();
        let oblique = tracer.liquid_transmittance(&ray(x), f32::INFINITY).unwrap();
        assert!(
            (oblique - t60.powi(4)).abs() < 2e-3,
            "{oblique} vs {}",
            t60.powi(4)
        );
    }
}
