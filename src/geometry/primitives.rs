//! Ray–disk and ray–sphere intersection and the bounds of each primitive.
//!
//! All functions take a unit-length ray direction and accept hits with `t_min < t < t_max`.

use glam::Vec3;

use super::{Aabb, Ray};

/// Rays with `|dot(dir, normal)|` at or below this miss a disk (treated as parallel to its plane).
/// About 1e-7 rad from grazing; avoids dividing by (nearly) zero.
pub const DISK_PARALLEL_COS: f32 = 1e-7;

/// Ray against the two-sided disk with centre `center`, unit `normal` and `radius`.
///
/// Returns `(t, d2)`: the hit distance and the squared distance from the hit point to the centre
/// (`d2 <= radius²`). A ray parallel to the plane (see [`DISK_PARALLEL_COS`]) misses; the result
/// is never NaN. Cost: ~20 flops.
#[inline(always)]
pub fn intersect_disk(
    ray: &Ray,
    center: Vec3,
    normal: Vec3,
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, f32)> {
    let denom = normal.dot(ray.dir);
    if denom.abs() <= DISK_PARALLEL_COS {
        return None;
    }
    let oc = center - ray.origin;
    let t = normal.dot(oc) / denom;
    if !(t > t_min && t < t_max) {
        return None;
    }
    let d2 = (t * ray.dir - oc).length_squared();
    if d2 <= radius * radius {
        Some((t, d2))
    } else {
        None
    }
}

/// Both roots `t_near <= t_far` of the ray against the sphere (`center`, `radius`), or `None` if
/// the ray's line misses it. Negative roots are included (a ray starting inside has
/// `t_near < 0 < t_far`).
///
/// Numerically robust form (Haines et al., Ray Tracing Gems ch. 7): the discriminant is computed
/// from the perpendicular offset of the centre from the line, and the smaller root from
/// `c / q` to avoid cancellation. Cost: ~30 flops and a square root.
#[inline(always)]
pub fn sphere_roots(ray: &Ray, center: Vec3, radius: f32) -> Option<(f32, f32)> {
    let f = ray.origin - center;
    let b = -f.dot(ray.dir); // half of -b in the textbook quadratic (a = 1)
    let perp = f + b * ray.dir; // f minus its component along dir
    let r2 = radius * radius;
    let disc = r2 - perp.length_squared();
    if disc < 0.0 || disc.is_nan() {
        return None;
    }
    let c = f.length_squared() - r2;
    let q = b + disc.sqrt().copysign(b);
    if q == 0.0 {
        // Origin on the sphere and the ray tangent to it: double root at 0.
        return Some((0.0, 0.0));
    }
    let (t0, t1) = (c / q, q);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// First sphere crossing with `t_min < t < t_max`: the entry point, or the exit point for a ray
/// starting inside. Cost: see [`sphere_roots`].
#[inline(always)]
pub fn intersect_sphere(
    ray: &Ray,
    center: Vec3,
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    let (t0, t1) = sphere_roots(ray, center, radius)?;
    if t0 > t_min && t0 < t_max {
        Some(t0)
    } else if t1 > t_min && t1 < t_max {
        Some(t1)
    } else {
        None
    }
}

/// Tight bounds of a disk: `center ± radius·sqrt(1 − n_k²)` on axis k (`normal` unit length).
#[inline]
pub fn disk_bounds(center: Vec3, normal: Vec3, radius: f32) -> Aabb {
    let e = radius * (Vec3::ONE - normal * normal).max(Vec3::ZERO).sqrt();
    Aabb::new(center - e, center + e)
}

/// Bounds of a sphere: `center ± radius`.
#[inline]
pub fn sphere_bounds(center: Vec3, radius: f32) -> Aabb {
    Aabb::new(center - Vec3::splat(radius), center + Vec3::splat(radius))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disk_front_back_rim_and_parallel() {
        let c = Vec3::new(0.0, 0.0, 2.0);
        let n = Vec3::Z;
        let front = Ray::new(Vec3::new(0.3, 0.0, 0.0), Vec3::Z);
        let (t, d2) = intersect_disk(&front, c, n, 0.5, 0.0, f32::INFINITY).unwrap();
        assert!((t - 2.0).abs() < 1e-6 && (d2 - 0.09).abs() < 1e-6);
        let back = Ray::new(Vec3::new(0.3, 0.0, 4.0), -Vec3::Z);
        assert!(
            (intersect_disk(&back, c, n, 0.5, 0.0, f32::INFINITY)
                .unwrap()
                .0
                - 2.0)
                .abs()
                < 1e-6
        );
        // Outside the radius, behind the ray, beyond t_max.
        let off = Ray::new(Vec3::new(0.6, 0.0, 0.0), Vec3::Z);
        assert!(intersect_disk(&off, c, n, 0.5, 0.0, f32::INFINITY).is_none());
        assert!(intersect_disk(&back, c, n, 0.5, 0.0, 1.0).is_none());
        let away = Ray::new(Vec3::ZERO, -Vec3::Z);
        assert!(intersect_disk(&away, c, n, 0.5, 0.0, f32::INFINITY).is_none());
        // Parallel rays, in the plane and off it: no hit, no NaN.
        for z in [2.0, 2.1] {
            let par = Ray::new(Vec3::new(-1.0, 0.0, z), Vec3::X);
            assert!(intersect_disk(&par, c, n, 0.5, 0.0, f32::INFINITY).is_none());
        }
        // Nearly grazing but not parallel: a finite hit.
        let graze = Ray::new(Vec3::new(-0.5, 0.0, 2.001), Vec3::new(1.0, 0.0, -0.002));
        let (t, _) = intersect_disk(&graze, c, n, 0.5, 0.0, f32::INFINITY).unwrap();
        assert!(t.is_finite() && (graze.at(t).z - 2.0).abs() < 1e-5);
    }

    #[test]
    fn sphere_entry_exit_inside() {
        let c = Vec3::new(0.0, 0.0, 5.0);
        let r = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(sphere_roots(&r, c, 1.0), Some((4.0, 6.0)));
        assert_eq!(intersect_sphere(&r, c, 1.0, 0.0, f32::INFINITY), Some(4.0));
        let inside = Ray::new(c, Vec3::X);
        assert_eq!(
            intersect_sphere(&inside, c, 1.0, 0.0, f32::INFINITY),
            Some(1.0)
        );
        let miss = Ray::new(Vec3::new(1.5, 0.0, 0.0), Vec3::Z);
        assert!(sphere_roots(&miss, c, 1.0).is_none());
        // Far away, small sphere: the naive quadratic loses the near root, this must not.
        let far = Ray::new(Vec3::new(0.0, 0.0, -1.0e4), Vec3::Z);
        let (t0, t1) = sphere_roots(&far, Vec3::ZERO, 1e-2).unwrap();
        assert!((t0 - (1.0e4 - 1e-2)).abs() < 2e-3 && (t1 - (1.0e4 + 1e-2)).abs() < 2e-3);
        assert!(t0 < t1);
        // Tangent ray from a point on the sphere.
        let tan = Ray::new(Vec3::new(1.0, 0.0, 5.0), Vec3::Z);
        assert_eq!(sphere_roots(&tan, c, 1.0), Some((0.0, 0.0)));
    }

    #[test]
    fn disk_bounds_are_tight() {
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let b = disk_bounds(Vec3::ZERO, n, 2.0);
        // Extent along z is the full radius, along x and y r·sqrt(1/2).
        assert!((b.max.z - 2.0).abs() < 1e-6);
        assert!((b.max.x - 2.0 * 0.5f32.sqrt()).abs() < 1e-6);
        // Every rim point is inside.
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        for k in 0..64 {
            let a = k as f32 * std::f32::consts::TAU / 64.0;
            let p = 2.0 * (a.cos() * u + a.sin() * v);
            assert!(b.padded(1e-5).contains(p));
        }
    }
}
