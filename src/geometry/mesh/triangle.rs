//! Watertight ray–triangle intersection (Woop, Benthin and Wald, "Watertight Ray/Triangle
//! Intersection", JCGT 2(1), 2013): the ray is sheared so that it runs along +z, and the three
//! edge functions are evaluated in 2D. A ray through a shared edge or vertex hits at least one
//! of the triangles sharing it (no cracks), because neighbouring triangles evaluate the same
//! edge function with the same numbers; edge functions that come out exactly zero are
//! recomputed in f64 as the paper recommends.

use glam::Vec3;

use crate::geometry::Ray;

/// The ray in the sheared frame, computed once per ray.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearedRay {
    origin: Vec3,
    k: [usize; 3],
    s: Vec3,
}

impl ShearedRay {
    /// Precomputes the permutation and shear for `ray` (direction must be non-zero).
    pub(crate) fn new(ray: &Ray) -> Self {
        let d = ray.dir;
        let a = d.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        ShearedRay {
            origin: ray.origin,
            k: [kx, ky, kz],
            s: Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]),
        }
    }

    /// The hit with triangle `(a, b, c)`: `(t, [wa, wb, wc])` with barycentric weights summing
    /// to one, if `t_min < t < t_max`. Both sides of the triangle are hit.
    #[inline]
    pub(crate) fn intersect(
        &self,
        a: Vec3,
        b: Vec3,
        c: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, [f32; 3])> {
        let [kx, ky, kz] = self.k;
        let s = self.s;
        let (a, b, c) = (a - self.origin, b - self.origin, c - self.origin);
        let ax = a[kx] - s.x * a[kz];
        let ay = a[ky] - s.y * a[kz];
        let bx = b[kx] - s.x * b[kz];
        let by = b[ky] - s.y * b[kz];
        let cx = c[kx] - s.x * c[kz];
        let cy = c[ky] - s.y * c[kz];
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let f =
                |p: f32, q: f32, r: f32, t: f32| (p as f64 * q as f64 - r as f64 * t as f64) as f32;
            u = f(cx, by, cy, bx);
            v = f(ax, cy, ay, cx);
            w = f(bx, ay, by, ax);
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let tt = u * (s.z * a[kz]) + v * (s.z * b[kz]) + w * (s.z * c[kz]);
        let t = tt / det;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let inv = 1.0 / det;
        Some((t, [u * inv, v * inv, w * inv]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_inside_misses_outside_and_weights_locate_the_point() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        for dir in [Vec3::NEG_Z, Vec3::Z] {
            let ray = Ray::new(Vec3::new(0.2, 0.3, -dir.z * 2.0), dir);
            let (t, w) = ShearedRay::new(&ray)
                .intersect(a, b, c, 0.0, f32::INFINITY)
                .unwrap();
            assert!((t - 2.0).abs() < 1e-6);
            let p = w[0] * a + w[1] * b + w[2] * c;
            assert!((p - Vec3::new(0.2, 0.3, 0.0)).length() < 1e-6, "{w:?}");
        }
        let miss = Ray::new(Vec3::new(0.6, 0.6, 1.0), Vec3::NEG_Z);
        assert!(
            ShearedRay::new(&miss)
                .intersect(a, b, c, 0.0, 9.0)
                .is_none()
        );
        let ray = Ray::new(Vec3::new(0.2, 0.3, 1.0), Vec3::NEG_Z);
        assert!(ShearedRay::new(&ray).intersect(a, b, c, 0.0, 0.5).is_none());
    }

    #[test]
    fn a_ray_through_a_shared_edge_or_vertex_is_never_lost() {
        // A fan of triangles around the origin; rays straight down at the shared vertex and
        // along the shared edges must hit at least one of them.
        let n = 7;
        let rim: Vec<Vec3> = (0..n)
            .map(|i| {
                let a = i as f32 / n as f32 * std::f32::consts::TAU;
                Vec3::new(a.cos(), a.sin(), 0.1 * a.sin())
            })
            .collect();
        for target in std::iter::once(Vec3::ZERO).chain(rim.iter().map(|r| 0.37 * *r)) {
            for tilt in [Vec3::ZERO, Vec3::new(0.13, -0.07, 0.0)] {
                let dir = (Vec3::NEG_Z + tilt).normalize();
                let ray = Ray::new(target - 3.0 * dir, dir);
                let sr = ShearedRay::new(&ray);
                let hits = (0..n)
                    .filter(|&i| {
                        sr.intersect(Vec3::ZERO, rim[i], rim[(i + 1) % n], 0.0, 9.0)
                            .is_some()
                    })
                    .count();
                assert!(hits >= 1, "{target} {tilt}");
            }
        }
    }
}
