//! Ray tests of the flat shapes: plane, rectangle and disk share one ray–plane step.

use glam::Vec3;

use super::ShapeHit;
use crate::geometry::Ray;

/// The ray's crossing of the plane through `point` with (not necessarily unit) normal `n`
/// within `(t_min, t_max)`, kept if `inside(offset from point)`; `normal` is reported, and the
/// front is the side `n` points to. A ray (nearly) parallel to the plane misses.
#[inline]
fn flat(
    ray: &Ray,
    (point, n): (Vec3, Vec3),
    (t_min, t_max): (f32, f32),
    inside: impl Fn(Vec3) -> bool,
    normal: impl Fn() -> Vec3,
) -> Option<ShapeHit> {
    let denom = ray.dir.dot(n);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (point - ray.origin).dot(n) / denom;
    (t > t_min && t < t_max && inside(ray.at(t) - point)).then(|| ShapeHit {
        t,
        normal: normal(),
        front: denom < 0.0,
    })
}

/// An infinite two-sided plane through `point` with unit `normal`.
#[inline]
pub(super) fn plane(ray: &Ray, point: Vec3, normal: Vec3, range: (f32, f32)) -> Option<ShapeHit> {
    flat(ray, (point, normal), range, |_| true, || normal)
}

/// The parallelogram `centre + a·u + b·v`, |a|, |b| ≤ 1, facing `u × v`.
#[inline]
pub(super) fn rect(
    ray: &Ray,
    centre: Vec3,
    (u, v): (Vec3, Vec3),
    range: (f32, f32),
) -> Option<ShapeHit> {
    let n = u.cross(v);
    let inside =
        |d: Vec3| d.dot(u).abs() <= u.length_squared() && d.dot(v).abs() <= v.length_squared();
    flat(ray, (centre, n), range, inside, || n.normalize())
}

/// The disk of `radius` around `centre` facing unit `normal`.
#[inline]
pub(super) fn disk(
    ray: &Ray,
    centre: Vec3,
    normal: Vec3,
    radius: f32,
    range: (f32, f32),
) -> Option<ShapeHit> {
    let inside = |d: Vec3| d.length_squared() <= radius * radius;
    flat(ray, (centre, normal), range, inside, || normal)
}
