//! Ray tests of the flat shapes: plane, rectangle and disk share one ray–plane step.

use glam::Vec3;

use super::ShapeHit;
use crate::geometry::Ray;

/// The ray's crossing of the plane through `point` with (not necessarily unit) normal `n`
/// within `(t_min, t_max)`: `(t, dir · n)`. `None` for a ray (nearly) parallel to the plane.
#[inline]
fn plane_t(ray: &Ray, point: Vec3, n: Vec3, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
    let denom = ray.dir.dot(n);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (point - ray.origin).dot(n) / denom;
    (t > t_min && t < t_max).then_some((t, denom))
}

/// An infinite two-sided plane.
#[inline]
pub(super) fn plane(
    ray: &Ray,
    point: Vec3,
    normal: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<ShapeHit> {
    let (t, denom) = plane_t(ray, point, normal, t_min, t_max)?;
    Some(ShapeHit {
        t,
        normal,
        front: denom < 0.0,
    })
}

/// The parallelogram `centre + a·u + b·v`, |a|, |b| ≤ 1, facing `u × v`.
#[inline]
pub(super) fn rect(
    ray: &Ray,
    centre: Vec3,
    u: Vec3,
    v: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<ShapeHit> {
    let n = u.cross(v);
    let (t, denom) = plane_t(ray, centre, n, t_min, t_max)?;
    let d = ray.at(t) - centre;
    let inside = d.dot(u).abs() <= u.length_squared() && d.dot(v).abs() <= v.length_squared();
    inside.then(|| ShapeHit {
        t,
        normal: n.normalize(),
        front: denom < 0.0,
    })
}

/// The disk of `radius` around `centre` facing `normal`.
#[inline]
pub(super) fn disk(
    ray: &Ray,
    centre: Vec3,
    normal: Vec3,
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<ShapeHit> {
    let (t, denom) = plane_t(ray, centre, normal, t_min, t_max)?;
    ((ray.at(t) - centre).length_squared() <= radius * radius).then_some(ShapeHit {
        t,
        normal,
        front: denom < 0.0,
    })
}
