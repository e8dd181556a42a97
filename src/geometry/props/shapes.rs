//! The prop shapes and their ray intersections (analytic, except the torus: sphere tracing of
//! its exact distance function).

use super::mesh::Mesh;
use crate::geometry::Ray;
use glam::Vec3;
use std::sync::Arc;

/// An opaque shape. Directions (`normal`, `axis`) are unit vectors.
#[derive(Clone, Debug)]
pub enum Shape {
    /// An infinite plane through `point` (ground, backdrop). Two-sided.
    Plane {
        /// A point on the plane.
        point: Vec3,
        /// Unit normal (the side reported as outward).
        normal: Vec3,
    },
    /// A sphere.
    Sphere {
        /// Centre.
        centre: Vec3,
        /// Radius, > 0.
        radius: f32,
    },
    /// An axis-aligned box.
    Box {
        /// Centre.
        centre: Vec3,
        /// Half the edge lengths, each > 0.
        half: Vec3,
    },
    /// A closed (capped) cylinder from `base` to `base + height · axis`.
    Cylinder {
        /// Centre of the bottom cap.
        base: Vec3,
        /// Unit axis.
        axis: Vec3,
        /// Length along the axis, > 0.
        height: f32,
        /// Radius, > 0.
        radius: f32,
    },
    /// A torus (a wire ring): the tube of radius `minor` around the circle of radius `major`
    /// centred at `centre` in the plane perpendicular to `axis`.
    Torus {
        /// Centre of the ring.
        centre: Vec3,
        /// Unit axis (the ring's normal).
        axis: Vec3,
        /// Ring radius, > 0.
        major: f32,
        /// Tube radius, 0 < minor < major for a ring.
        minor: f32,
    },
    /// A triangle mesh.
    Mesh(Arc<Mesh>),
}

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

impl Shape {
    /// First hit with `t_min < t < t_max`: distance and outward unit normal. `eps` is the
    /// torus's convergence distance.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32, eps: f32) -> Option<(f32, Vec3)> {
        match *self {
            Shape::Plane { point, normal } => {
                let denom = ray.dir.dot(normal);
                if denom.abs() < 1e-12 {
                    return None;
                }
                let t = (point - ray.origin).dot(normal) / denom;
                (t > t_min && t < t_max).then_some((t, normal))
            }
            Shape::Sphere { centre, radius } => {
                let oc = ray.origin - centre;
                let roots = quadratic(1.0, oc.dot(ray.dir), oc.length_squared() - radius * radius)?;
                let t = first_in(roots, t_min, t_max)?;
                Some((t, (ray.at(t) - centre) / radius))
            }
            Shape::Box { centre, half } => {
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
            Shape::Cylinder {
                base,
                axis,
                height,
                radius,
            } => cylinder(ray, base, axis, height, radius, t_min, t_max),
            Shape::Torus {
                centre,
                axis,
                major,
                minor,
            } => torus(ray, centre, axis, major, minor, t_min, t_max, eps),
            Shape::Mesh(ref m) => m.intersect(ray, t_min, t_max),
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn cylinder(
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

#[allow(clippy::too_many_arguments)]
fn torus(
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
    use super::*;

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray {
        Ray::new(Vec3::from(o), Vec3::from(d))
    }

    #[test]
    fn each_shape_is_hit_where_geometry_says() {
        let eps = 1e-5;
        let plane = Shape::Plane {
            point: Vec3::new(0.0, -1.0, 0.0),
            normal: Vec3::Y,
        };
        let (t, n) = plane
            .intersect(&ray([0.0, 1.0, 0.0], [0.0, -1.0, 0.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!((t - 2.0).abs() < 1e-5 && n == Vec3::Y);
        let sphere = Shape::Sphere {
            centre: Vec3::ZERO,
            radius: 1.0,
        };
        let (t, n) = sphere
            .intersect(&ray([0.0, 0.0, 5.0], [0.0, 0.0, -1.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!((t - 4.0).abs() < 1e-5 && (n - Vec3::Z).length() < 1e-5);
        // From inside: the far side.
        let (t, _) = sphere
            .intersect(&ray([0.0; 3], [1.0, 0.0, 0.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!((t - 1.0).abs() < 1e-5);
        let bx = Shape::Box {
            centre: Vec3::ZERO,
            half: Vec3::new(1.0, 2.0, 3.0),
        };
        let (t, n) = bx
            .intersect(&ray([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!((t - 3.0).abs() < 1e-5 && n == Vec3::Y);
        assert!(
            bx.intersect(&ray([5.0, 5.0, 0.0], [0.0, -1.0, 0.0]), 0.0, 10.0, eps)
                .is_none()
        );
        let cyl = Shape::Cylinder {
            base: Vec3::ZERO,
            axis: Vec3::Y,
            height: 2.0,
            radius: 0.5,
        };
        let (t, n) = cyl
            .intersect(&ray([3.0, 1.0, 0.0], [-1.0, 0.0, 0.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!((t - 2.5).abs() < 1e-5 && (n - Vec3::X).length() < 1e-5);
        let (t, n) = cyl
            .intersect(&ray([0.1, 5.0, 0.0], [0.0, -1.0, 0.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!((t - 3.0).abs() < 1e-5 && n == Vec3::Y, "top cap");
        assert!(
            cyl.intersect(&ray([3.0, 2.5, 0.0], [-1.0, 0.0, 0.0]), 0.0, 10.0, eps)
                .is_none()
        );
        let torus = Shape::Torus {
            centre: Vec3::ZERO,
            axis: Vec3::Y,
            major: 1.0,
            minor: 0.1,
        };
        // Down through the tube at x = 1: hits the top of the tube at y = 0.1.
        let (t, n) = torus
            .intersect(&ray([1.0, 2.0, 0.0], [0.0, -1.0, 0.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!(
            (t - 1.9).abs() < 1e-4 && (n - Vec3::Y).length() < 1e-3,
            "{t} {n}"
        );
        // Through the hole: a miss.
        assert!(
            torus
                .intersect(&ray([0.0, 2.0, 0.0], [0.0, -1.0, 0.0]), 0.0, 10.0, eps)
                .is_none()
        );
        // Along the axis plane from outside: the outer rim at x = 1.1.
        let (t, _) = torus
            .intersect(&ray([3.0, 0.0, 0.0], [-1.0, 0.0, 0.0]), 0.0, 10.0, eps)
            .unwrap();
        assert!((t - 1.9).abs() < 1e-4, "{t}");
    }
}
