//! Area lights: rectangles, disks and spheres that emit a constant radiance.
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

use crate::geometry::Ray;
use crate::spectrum::Blackbody;
use glam::Vec3;
use std::f32::consts::{PI, TAU};

/// The shape of an area light. Directions are unit vectors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightShape {
    /// A parallelogram `centre + a·u + b·v`, |a|, |b| ≤ 1 (u, v perpendicular half-edges);
    /// it faces `u × v`.
    Rect {
        /// Centre.
        centre: Vec3,
        /// Half-edge vector along the width.
        u: Vec3,
        /// Half-edge vector along the height.
        v: Vec3,
    },
    /// A disk facing `normal`.
    Disk {
        /// Centre.
        centre: Vec3,
        /// Unit normal (the emitting side).
        normal: Vec3,
        /// Radius.
        radius: f32,
    },
    /// A sphere emitting outward.
    Sphere {
        /// Centre.
        centre: Vec3,
        /// Radius.
        radius: f32,
    },
}

/// One area light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaLight {
    /// Its shape.
    pub shape: LightShape,
    /// Emitted radiance, linear sRGB (see the module docs for units).
    pub radiance: Vec3,
    /// A black-body emission spectrum (scaled to the light's luminance), used as such by
    /// spectral transport; `radiance` is then its colour. `None`: the spectrum is made from
    /// `radiance`.
    pub blackbody: Option<Blackbody>,
}

/// A point sampled on a light as seen from a shading point.
#[derive(Debug, Clone, Copy)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light.
    pub dir: Vec3,
    /// Distance to the sampled point.
    pub dist: f32,
    /// Solid-angle density of `dir` (1/sr).
    pub pdf: f32,
}

impl AreaLight {
    /// A light of `shape` emitting RGB `radiance`.
    pub fn rgb(shape: LightShape, radiance: Vec3) -> Self {
        AreaLight {
            shape,
            radiance,
            blackbody: None,
        }
    }

    /// Distance along `ray` to the light within (t_min, t_max), and whether the ray meets its
    /// emitting side.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, bool)> {
        match self.shape {
            LightShape::Rect { centre, u, v } => {
                let n = u.cross(v);
                let denom = ray.dir.dot(n);
                if denom.abs() < 1e-12 {
                    return None;
                }
                let t = (centre - ray.origin).dot(n) / denom;
                if !(t > t_min && t < t_max) {
                    return None;
                }
                let d = ray.at(t) - centre;
                let inside =
                    d.dot(u).abs() <= u.length_squared() && d.dot(v).abs() <= v.length_squared();
                inside.then_some((t, denom < 0.0))
            }
            LightShape::Disk {
                centre,
                normal,
                radius,
            } => {
                let denom = ray.dir.dot(normal);
                if denom.abs() < 1e-12 {
                    return None;
                }
                let t = (centre - ray.origin).dot(normal) / denom;
                if !(t > t_min && t < t_max) {
                    return None;
                }
                ((ray.at(t) - centre).length_squared() <= radius * radius)
                    .then_some((t, denom < 0.0))
            }
            LightShape::Sphere { centre, radius } => {
                let oc = ray.origin - centre;
                let b = oc.dot(ray.dir);
                let c = oc.length_squared() - radius * radius;
                let disc = b * b - c;
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                [-b - s, -b + s]
                    .into_iter()
                    .find(|&t| t > t_min && t < t_max)
                    .map(|t| (t, c > 0.0))
            }
        }
    }

    /// Area of the light, scene units².
    pub fn area(&self) -> f32 {
        match self.shape {
            LightShape::Rect { u, v, .. } => 4.0 * u.cross(v).length(),
            LightShape::Disk { radius, .. } => PI * radius * radius,
            LightShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
        }
    }

    /// Samples a direction from `p` toward the light with the random pair `u`; `None` when the
    /// sample cannot carry light (behind the emitting side, or `p` inside a sphere light).
    pub fn sample(&self, p: Vec3, u: (f32, f32)) -> Option<LightSample> {
        match self.shape {
            LightShape::Rect {
                centre,
                u: eu,
                v: ev,
            } => {
                let q = centre + (2.0 * u.0 - 1.0) * eu + (2.0 * u.1 - 1.0) * ev;
                let n = eu.cross(ev).normalize();
                area_sample(p, q, n, self.area())
            }
            LightShape::Disk {
                centre,
                normal,
                radius,
            } => {
                let (a, b) = frame(normal);
                let r = radius * u.0.sqrt();
                let phi = TAU * u.1;
                let q = centre + r * (phi.cos() * a + phi.sin() * b);
                area_sample(p, q, normal, self.area())
            }
            LightShape::Sphere { centre, radius } => {
                let to = centre - p;
                let d2 = to.length_squared();
                if d2 <= radius * radius {
                    return None;
                }
                let d = d2.sqrt();
                let w = to / d;
                // Uniform in the cone the sphere subtends.
                let cos_max = (1.0 - radius * radius / d2).max(0.0).sqrt();
                let cos = 1.0 - u.0 * (1.0 - cos_max);
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = TAU * u.1;
                let (a, b) = frame(w);
                let dir = (cos * w + sin * (phi.cos() * a + phi.sin() * b)).normalize();
                // Distance to the near surface along dir.
                let bq = -dir.dot(to);
                let disc = (bq * bq - (d2 - radius * radius)).max(0.0);
                let dist = -bq - disc.sqrt();
                Some(LightSample {
                    dir,
                    dist,
                    pdf: 1.0 / (TAU * (1.0 - cos_max).max(1e-12)),
                })
            }
        }
    }

    /// Solid-angle density with which [`sample`](Self::sample) from `p` picks `dir`, given that
    /// a ray from `p` along `dir` meets the light's emitting side at distance `t`.
    pub fn pdf(&self, p: Vec3, dir: Vec3, t: f32) -> f32 {
        match self.shape {
            LightShape::Rect { u, v, .. } => {
                let n = u.cross(v).normalize();
                t * t / (self.area() * dir.dot(n).abs().max(1e-12))
            }
            LightShape::Disk { normal, .. } => {
                t * t / (self.area() * dir.dot(normal).abs().max(1e-12))
            }
            LightShape::Sphere { centre, radius } => {
                let d2 = (centre - p).length_squared();
                if d2 <= radius * radius {
                    return 0.0;
                }
                let cos_max = (1.0 - radius * radius / d2).max(0.0).sqrt();
                1.0 / (TAU * (1.0 - cos_max).max(1e-12))
            }
        }
    }
}

fn area_sample(p: Vec3, q: Vec3, n: Vec3, area: f32) -> Option<LightSample> {
    let to = q - p;
    let d2 = to.length_squared();
    let dist = d2.sqrt();
    if dist <= 0.0 {
        return None;
    }
    let dir = to / dist;
    let cos_l = -dir.dot(n);
    if cos_l <= 0.0 {
        return None;
    }
    Some(LightSample {
        dir,
        dist,
        pdf: d2 / (area * cos_l),
    })
}

/// Two unit vectors completing `n` to an orthonormal frame (Duff et al. 2017).
pub fn frame(n: Vec3) -> (Vec3, Vec3) {
    let s = 1f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// The nearest light along `ray` within (t_min, t_max): index, distance, front side.
#[inline]
pub fn nearest(
    lights: &[AreaLight],
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<(usize, f32, bool)> {
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
            let light = AreaLight::rgb(shape, Vec3::ONE);
            let n = 20_000;
            let mut est = 0.0f64;
            for _ in 0..n {
                if let Some(s) = light.sample(p, (rng.next_f32(), rng.next_f32())) {
                    let ray = Ray::new(p, s.dir);
                    let (t, front) = light.intersect(&ray, 0.0, f32::INFINITY).unwrap();
                    assert!(front && (t - s.dist).abs() < 1e-3 * s.dist.max(1.0));
                    let pdf = light.pdf(p, s.dir, t);
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
