//! Lights: [`Light`], a closed enum with pbrt's interface (`sample_li`, `pdf_li`, `le`). The
//! one kind is the diffuse area light, [`AreaLight`]: a shape of the shape library
//! ([`Shape`]: rectangle, disk, sphere) that emits a constant radiance.
//!
//! Units: `radiance` is linear-sRGB radiance per channel in the renderer's scene units,
//! W·sr⁻¹·m⁻² when the scene is in metres (the same scale as the environment: at 0 EV a
//! radiance of 1 in every channel shows as display white). The scene parser also accepts a
//! luminance in cd/m² (nits), converted with the convention 1 radiance unit = 100 nits.
//!
//! A film is a perfect specular surface: it shows only what lies exactly along its mirror and
//! transmission directions, so a light without area (point, directional) would never appear
//! in it. Only lights with area exist here. Rectangles and disks emit from their front face
//! (the side their normal points to) and are black from behind; spheres emit outward. Lights
//! are opaque to rays. A scene without lights holds an empty list: rays pay one length check.

use super::radiance::{Lanes, Radiance};
use crate::geometry::{Ray, Shape, ShapeSample};
use crate::spectrum::Blackbody;
use glam::Vec3;

pub use crate::geometry::frame;

/// The old name of the light's [`Shape`] (the shape library's enum, which also holds the
/// light shapes `Rect`, `Disk` and `Sphere`).
pub type LightShape = Shape;

/// The old name of [`ShapeSample`].
pub type LightSample = ShapeSample;

/// A diffuse area light (pbrt's `DiffuseAreaLight`): a shape emitting a constant radiance from
/// its front (the side a flat shape's normal points to, a sphere's outside).
#[derive(Debug, Clone)]
pub struct AreaLight {
    /// Its shape: [`Shape::Rect`], [`Shape::Disk`] or [`Shape::Sphere`] (others are lit only
    /// by material sampling, see [`Shape::sample`]).
    pub shape: Shape,
    /// Emitted radiance, linear sRGB (see the module docs for units).
    pub radiance: Vec3,
    /// A black-body emission spectrum (scaled to the light's luminance), used as such by
    /// spectral transport; `radiance` is then its colour. `None`: the spectrum is made from
    /// `radiance`.
    pub blackbody: Option<Blackbody>,
}

impl AreaLight {
    /// A light of `shape` emitting RGB `radiance`.
    pub fn rgb(shape: Shape, radiance: Vec3) -> Self {
        AreaLight {
            shape,
            radiance,
            blackbody: None,
        }
    }
}

/// A light of the studio. A closed set dispatched by `match`; every kind answers where a ray
/// meets it, what it emits toward that ray ([`Light::le`]), and how it is sampled from a
/// shading point ([`Light::sample_li`], [`Light::pdf_li`]).
#[derive(Debug, Clone)]
pub enum Light {
    /// A diffuse area light.
    Area(AreaLight),
}

impl From<AreaLight> for Light {
    fn from(l: AreaLight) -> Self {
        Light::Area(l)
    }
}

impl Light {
    /// Distance along `ray` to the light within (t_min, t_max), and whether the ray meets its
    /// emitting side.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, bool)> {
        match self {
            Light::Area(a) => a
                .shape
                .intersect(ray, t_min, t_max, 0.0)
                .map(|h| (h.t, h.front)),
        }
    }

    /// Radiance emitted toward a ray that meets the light on its front (`front`) or back, as
    /// the lanes `l` carry it: the emission from the front, black from behind.
    #[inline]
    pub fn le<L: Lanes>(&self, l: &L, front: bool) -> L::C {
        match self {
            Light::Area(a) if front => l.emission(a.radiance, a.blackbody.as_ref()),
            Light::Area(_) => L::C::splat(0.0),
        }
    }

    /// Samples a direction from `p` toward the light with the random pair `u`; `None` when the
    /// sample cannot carry light (behind the emitting side, or `p` inside a sphere light).
    #[inline]
    pub fn sample_li(&self, p: Vec3, u: (f32, f32)) -> Option<ShapeSample> {
        match self {
            Light::Area(a) => a.shape.sample(p, u),
        }
    }

    /// Solid-angle density with which [`Light::sample_li`] from `p` picks `dir`, given that a
    /// ray from `p` along `dir` meets the light's emitting side at distance `t`.
    #[inline]
    pub fn pdf_li(&self, p: Vec3, dir: Vec3, t: f32) -> f32 {
        match self {
            Light::Area(a) => a.shape.pdf(p, dir, t),
        }
    }
}

/// The nearest light along `ray` within (t_min, t_max): index, distance, front side.
#[inline]
pub fn nearest(lights: &[Light], ray: &Ray, t_min: f32, t_max: f32) -> Option<(usize, f32, bool)> {
    let mut best = None;
    let mut t_max = t_max;
    for (i, l) in lights.iter().enumerate() {
        if let Some((t, front)) = l.intersect(ray, t_min, t_max) {
            t_max = t;
            best = Some((i, t, front));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::sampler::Pcg32;
    use std::f32::consts::TAU;

    /// The sampled densities integrate to 1 over the directions that reach the light, and
    /// `pdf` agrees with `sample`: Σ 1/pdf over samples estimates the solid angle, which a
    /// brute-force count of uniform directions hitting the light also estimates.
    #[test]
    fn sampling_densities_match_the_solid_angle() {
        let p = Vec3::new(0.2, -0.1, 0.0);
        let lights = [
            LightShape::Rect {
                centre: Vec3::new(0.0, 2.0, 0.0),
                u: Vec3::new(0.7, 0.0, 0.0),
                v: Vec3::new(0.0, 0.0, 0.4),
            },
            LightShape::Disk {
                centre: Vec3::new(0.0, 2.0, 0.5),
                normal: Vec3::NEG_Y,
                radius: 0.6,
            },
            LightShape::Sphere {
                centre: Vec3::new(0.5, 1.5, 0.0),
                radius: 0.5,
            },
        ];
        let mut rng = Pcg32::new(3, 1);
        for shape in lights {
            // u × v of the rect must face down (toward p) for it to be lit.
            let light = Light::from(AreaLight::rgb(shape.clone(), Vec3::ONE));
            let n = 20_000;
            let mut est = 0.0f64;
            for _ in 0..n {
                if let Some(s) = light.sample_li(p, (rng.next_f32(), rng.next_f32())) {
                    let ray = Ray::new(p, s.dir);
                    let (t, front) = light.intersect(&ray, 0.0, f32::INFINITY).unwrap();
                    assert!(front && (t - s.dist).abs() < 1e-3 * s.dist.max(1.0));
                    let pdf = light.pdf_li(p, s.dir, t);
                    assert!((pdf - s.pdf).abs() < 1e-3 * s.pdf, "{shape:?}");
                    est += 1.0 / s.pdf as f64;
                }
            }
            let solid = est / n as f64;
            let mut hits = 0u32;
            let m = 400_000;
            for _ in 0..m {
                let z = 1.0 - 2.0 * rng.next_f32();
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = TAU * rng.next_f32();
                let d = Vec3::new(r * phi.cos(), z, r * phi.sin());
                if let Some((_, true)) = light.intersect(&Ray::new(p, d), 0.0, f32::INFINITY) {
                    hits += 1;
                }
            }
            let brute = 4.0 * std::f64::consts::PI * hits as f64 / m as f64;
            assert!(
                (solid - brute).abs() < 0.03 * brute,
                "{shape:?}: {solid} vs {brute}"
            );
        }
    }
}
