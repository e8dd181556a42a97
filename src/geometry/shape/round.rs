//! Ray tests of the solid shapes: sphere (the films' robust test), box, capped cylinder and
//! torus (sphere tracing of its exact distance function).

use super::ShapeHit;
use crate::geometry::Ray;
use crate::geometry::primitives::sphere_roots;
use glam::Vec3;

/// Roots of `a t² + 2 b t + c = 0` (a > 0), ascending; `None` if there are none.
#[inline]
fn quadratic(a: f32, b: f32, c: f32) -> Option<(f32, f32)> {
    let disc = b * b - a * c;
    if disc < 0.0 || a <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    // Stable form: avoid cancellation in −b ± s.
    let q = -(b + s.copysign(b));
    let (t0, t1) = if q != 0.0 { (q / a, c / q) } else { (0.0, 0.0) };
    Some((t0.min(t1), t0.max(t1)))
}

/// The first root inside (t_min, t_max).
#[inline]
fn first_in(roots: (f32, f32), t_min: f32, t_max: f32) -> Option<f32> {
    [roots.0, roots.1]
        .into_iter()
        .find(|&t| t > t_min && t < t_max)
}

/// The sphere (`centre`, `radius`): the entry point, or the exit point for a ray starting
/// inside (then `front` is false).
#[inline]
pub(super) fn sphere(
    ray: &Ray,
    centre: Vec3,
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<ShapeHit> {
    let roots = sphere_roots(ray, centre, radius)?;
    let t = first_in(roots, t_min, t_max)?;
    Some(ShapeHit {
        t,
        normal: (ray.at(t) - centre) / radius,
        front: (ray.origin - centre).length_squared() - radius * radius > 0.0,
    })
}

/// The axis-aligned box around `centre` with half extents `half`: distance and the normal of
/// the face hit.
#[inline]
pub(super) fn aabox(
    ray: &Ray,
    centre: Vec3,
    half: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, Vec3)> {
    let inv = ray.dir.recip();
    let o = ray.origin - centre;
    let t0 = (-half - o) * inv;
    let t1 = (half - o) * inv;
    let (near, far) = (t0.min(t1), t0.max(t1));
    let (tn, tf) = (near.max_element(), far.min_element());
    if tn > tf {
        return None;
    }
    let t = first_in((tn, tf), t_min, t_max)?;
    // The normal is the face whose slab bound is t.
    let p = (ray.at(t) - centre) / half;
    let a = p.abs();
    let normal = if a.x >= a.y && a.x >= a.z {
        Vec3::X * p.x.signum()
    } else if a.y >= a.z {
        Vec3::Y * p.y.signum()
    } else {
        Vec3::Z * p.z.signum()
    };
    Some((t, normal))
}

/// The capped cylinder from `base` along `axis`: distance and outward normal.
#[allow(clippy::too_many_arguments)]
pub(super) fn cylinder(
    ray: &Ray,
    base: Vec3,
    axis: Vec3,
    height: f32,
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, Vec3)> {
    let o = ray.origin - base;
    let (oa, da) = (o.dot(axis), ray.dir.dot(axis));
    let (op, dp) = (o - oa * axis, ray.dir - da * axis);
    let mut best: Option<(f32, Vec3)> = None;
    let mut t_max = t_max;
    // Side.
    if let Some((t0, t1)) = quadratic(
        dp.length_squared(),
        op.dot(dp),
        op.length_squared() - radius * radius,
    ) {
        for t in [t0, t1] {
            let h = oa + t * da;
            if t > t_min && t < t_max && (0.0..=height).contains(&h) {
                best = Some((t, (op + t * dp) / radius));
                t_max = t;
                break;
            }
        }
    }
    // Caps.
    if da.abs() > 1e-12 {
        for (h, n) in [(0.0, -axis), (height, axis)] {
            let t = (h - oa) / da;
            if t > t_min && t < t_max && (op + t * dp).length_squared() <= radius * radius {
                best = Some((t, n));
                t_max = t;
            }
        }
    }
    best
}

/// The torus around `axis`: distance and outward normal; `eps` is the convergence distance of
/// the sphere tracing, which starts where the ray enters the bounding sphere.
#[allow(clippy::too_many_arguments)]
pub(super) fn torus(
    ray: &Ray,
    centre: Vec3,
    axis: Vec3,
    major: f32,
    minor: f32,
    t_min: f32,
    t_max: f32,
    eps: f32,
) -> Option<(f32, Vec3)> {
    // Bound the march by the enclosing sphere.
    let oc = ray.origin - centre;
    let outer = major + minor;
    let (s0, s1) = quadratic(1.0, oc.dot(ray.dir), oc.length_squared() - outer * outer)?;
    let mut t = s0.max(t_min);
    let end = s1.min(t_max);
    let sdf = |p: Vec3| {
        let q = p - centre;
        let y = q.dot(axis);
        let r = (q - y * axis).length();
        ((r - major).powi(2) + y * y).sqrt() - minor
    };
    // Sphere tracing: the exact distance never overshoots the surface.
    for _ in 0..512 {
        if t > end {
            return None;
        }
        let d = sdf(ray.at(t));
        if d < eps {
            if t <= t_min {
                return None;
            }
            let q = ray.at(t) - centre;
            let y = q.dot(axis);
            let ring = (q - y * axis).try_normalize().unwrap_or(Vec3::ZERO) * major;
            let n = (q - ring).try_normalize().unwrap_or(axis);
            return Some((t, n));
        }
        t += d;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::super::Shape;
    use super::*;

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
        Ray::new(Vec3::from(o), Vec3::from(d))
    }

    /// Distance and normal of the hit of the ray `o + t d` with `t` in (0, 10).
    fn hit(shape: &Shape, o: [f32; 3], d: [f32; 3]) -> Option<(f32, Vec3)> {
        shape
            .intersect(&ray(o, d), 0.0, 10.0, 1e-5)
            .map(|h| (h.t, h.normal))
    }

    #[test]
    fn planes_and_spheres_are_hit_where_geometry_says() {
        let plane = Shape::Plane {
            point: Vec3::new(0.0, -1.0, 0.0),
            normal: Vec3::Y,
        };
        let (t, n) = hit(&plane, [0.0, 1.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!((t - 2.0).abs() < 1e-5 && n == Vec3::Y);
        let sphere = Shape::Sphere {
            centre: Vec3::ZERO,
            radius: 1.0,
        };
        let (t, n) = hit(&sphere, [0.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap();
        assert!((t - 4.0).abs() < 1e-5 && (n - Vec3::Z).length() < 1e-5);
        // From inside: the far side, met from the back.
        let inside = sphere
            .intersect(&ray([0.0; 3], [1.0, 0.0, 0.0]), 0.0, 10.0, 1e-5)
            .unwrap();
        assert!(!inside.front);
        let (t, _) = hit(&sphere, [0.0; 3], [1.0, 0.0, 0.0]).unwrap();
        assert!((t - 1.0).abs() < 1e-5);
    }

    #[test]
    fn boxes_and_cylinders_are_hit_on_the_right_face() {
        let bx = Shape::Box {
            centre: Vec3::ZERO,
            half: Vec3::new(1.0, 2.0, 3.0),
        };
        let (t, n) = hit(&bx, [0.0, 5.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!((t - 3.0).abs() < 1e-5 && n == Vec3::Y);
        assert!(hit(&bx, [5.0, 5.0, 0.0], [0.0, -1.0, 0.0]).is_none());
        let cyl = Shape::Cylinder {
            base: Vec3::ZERO,
            axis: Vec3::Y,
            height: 2.0,
            radius: 0.5,
        };
        let (t, n) = hit(&cyl, [3.0, 1.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
        assert!((t - 2.5).abs() < 1e-5 && (n - Vec3::X).length() < 1e-5);
        let (t, n) = hit(&cyl, [0.1, 5.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!((t - 3.0).abs() < 1e-5 && n == Vec3::Y, "top cap");
        assert!(hit(&cyl, [3.0, 2.5, 0.0], [-1.0, 0.0, 0.0]).is_none());
    }

    #[test]
    fn a_torus_is_hit_on_its_tube_and_missed_through_its_hole() {
        let torus = Shape::Torus {
            centre: Vec3::ZERO,
            axis: Vec3::Y,
            major: 1.0,
            minor: 0.1,
        };
        // Down through the tube at x = 1: hits the top of the tube at y = 0.1.
        let (t, n) = hit(&torus, [1.0, 2.0, 0.0], [0.0, -1.0, 0.0]).unwrap();
        assert!(
            (t - 1.9).abs() < 1e-4 && (n - Vec3::Y).length() < 1e-3,
            "{t} {n}"
        );
        // Through the hole: a miss.
        assert!(hit(&torus, [0.0, 2.0, 0.0], [0.0, -1.0, 0.0]).is_none());
        // Along the axis plane from outside: the outer rim at x = 1.1.
        let (t, _) = hit(&torus, [3.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
        assert!((t - 1.9).abs() < 1e-4, "{t}");
    }
}
