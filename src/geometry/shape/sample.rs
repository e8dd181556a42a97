//! Solid-angle sampling of the shapes area lights use: a point on a rectangle or disk chosen
//! uniformly by area, or a direction uniform in the cone a sphere subtends (pbrt-v4 §6.2).
//! Other shapes have no sampling routine: [`Shape::sample`] gives `None` and [`Shape::pdf`] 0,
//! so a light of such a shape is found only by the material strategy (still unbiased under
//! multiple importance sampling).

use super::Shape;
use crate::geometry::Ray;
use crate::geometry::primitives::sphere_roots;
use glam::Vec3;
use std::f32::consts::{PI, TAU};

/// A point sampled on a shape as seen from a shading point.
#[derive(Debug, Clone, Copy)]
pub struct ShapeSample {
    /// Unit direction from the shading point toward the shape.
    pub dir: Vec3,
    /// Distance to the sampled point.
    pub dist: f32,
    /// Solid-angle density of `dir` (1/sr).
    pub pdf: f32,
}

impl Shape {
    /// Surface area, scene units² (0 for the shapes [`Shape::sample`] does not sample).
    pub fn area(&self) -> f32 {
        match *self {
            Shape::Rect { u, v, .. } => 4.0 * u.cross(v).length(),
            Shape::Disk { radius, .. } => PI * radius * radius,
            Shape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            _ => 0.0,
        }
    }

    /// Samples a direction from `p` toward the shape's front with the random pair `u`; `None`
    /// when the sample cannot see the front (behind a flat shape, `p` inside a sphere) or the
    /// shape has no sampling routine. Cost: a few flops (a square root or two).
    pub fn sample(&self, p: Vec3, u: (f32, f32)) -> Option<ShapeSample> {
        match *self {
            Shape::Rect {
                centre,
                u: eu,
                v: ev,
            } => {
                let q = centre + (2.0 * u.0 - 1.0) * eu + (2.0 * u.1 - 1.0) * ev;
                let n = eu.cross(ev).normalize();
                area_sample(p, q, n, self.area())
            }
            Shape::Disk {
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
            Shape::Sphere { centre, radius } => sphere_sample(p, centre, radius, u),
            _ => None,
        }
    }

    /// Solid-angle density with which [`Shape::sample`] from `p` picks `dir`, given that a ray
    /// from `p` along `dir` meets the shape's front at distance `t` (0 for the shapes it does
    /// not sample).
    pub fn pdf(&self, p: Vec3, dir: Vec3, t: f32) -> f32 {
        match *self {
            Shape::Rect { u, v, .. } => {
                let n = u.cross(v).normalize();
                t * t / (self.area() * dir.dot(n).abs().max(1e-12))
            }
            Shape::Disk { normal, .. } => t * t / (self.area() * dir.dot(normal).abs().max(1e-12)),
            Shape::Sphere { centre, radius } => {
                let d2 = (centre - p).length_squared();
                if d2 <= radius * radius {
                    return 0.0;
                }
                1.0 / (TAU * (1.0 - cone_cos(radius, d2)).max(1e-12))
            }
            _ => 0.0,
        }
    }
}

/// Cosine of the half-angle of the cone a sphere of `radius` subtends at squared distance `d2`.
#[inline]
fn cone_cos(radius: f32, d2: f32) -> f32 {
    (1.0 - radius * radius / d2).max(0.0).sqrt()
}

/// A direction uniform in the cone the sphere subtends at `p` (outside it).
fn sphere_sample(p: Vec3, centre: Vec3, radius: f32, u: (f32, f32)) -> Option<ShapeSample> {
    let to = centre - p;
    let d2 = to.length_squared();
    if d2 <= radius * radius {
        return None;
    }
    let w = to / d2.sqrt();
    let cos_max = cone_cos(radius, d2);
    let cos = 1.0 - u.0 * (1.0 - cos_max);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = TAU * u.1;
    let (a, b) = frame(w);
    let dir = (cos * w + sin * (phi.cos() * a + phi.sin() * b)).normalize();
    // Distance to the near surface along dir (at the cone's rim, where rounding may miss the
    // sphere, the tangent point's distance).
    let ray = Ray { origin: p, dir };
    let dist = sphere_roots(&ray, centre, radius).map_or(dir.dot(to), |(near, _)| near);
    Some(ShapeSample {
        dir,
        dist,
        pdf: 1.0 / (TAU * (1.0 - cos_max).max(1e-12)),
    })
}

/// The sample toward point `q` on a flat shape of `area` facing `n`.
fn area_sample(p: Vec3, q: Vec3, n: Vec3, area: f32) -> Option<ShapeSample> {
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
    Some(ShapeSample {
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
