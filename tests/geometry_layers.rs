//! Disk-layer blending: overlapping disks of one film layer form ONE crossing whose thickness is a
//! smooth interpolation of the particles' thicknesses.

use filmsplat::geometry::{DiskGeometry, Ray};
use glam::Vec3;

mod geometry_support;
use geometry_support::Rng;

/// All crossings along a ray, continuing from just beyond each `t_exit`.
fn crossings(g: &DiskGeometry, ray: &Ray) -> Vec<filmsplat::geometry::SurfaceHit> {
    let mut out = Vec::new();
    let mut t_min = 0.0;
    while let Some(h) = g.intersect(ray, t_min, f32::INFINITY) {
        out.push(h);
        t_min = h.t_exit + 1e-4;
        if out.len() > 20 {
            break;
        }
    }
    out
}

/// A tilted plane tiled by jittered, overlapping coplanar disks (radius 1.5× spacing) with
/// random normal signs and a linear thickness gradient along `u`.
struct Plane {
    p0: Vec3,
    n: Vec3,
    u: Vec3,
    v: Vec3,
    geometry: DiskGeometry,
}

const SPACING: f32 = 0.1;
const RADIUS: f32 = 1.5 * SPACING;
/// Thickness gradient along `u`, nm per scene unit.
const GRADIENT: f32 = 100.0;

impl Plane {
    fn new() -> Plane {
        let n = Vec3::new(0.3, -0.2, 1.0).normalize();
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        let p0 = Vec3::new(0.2, -0.1, 0.5);
        let mut rng = Rng(99);
        let (mut pos, mut nrm, mut thk) = (Vec::new(), Vec::new(), Vec::new());
        for i in -22..=22 {
            for j in -22..=22 {
                let x = (i as f32 + rng.range(-0.25, 0.25)) * SPACING;
                let y = (j as f32 + rng.range(-0.25, 0.25)) * SPACING;
                pos.push(p0 + x * u + y * v);
                nrm.push(if rng.f() < 0.5 { n } else { -n });
                thk.push(Self::thickness_at(x));
            }
        }
        let rad = vec![RADIUS; pos.len()];
        let geometry = DiskGeometry::build(&pos, &nrm, &rad, &thk).unwrap();
        Plane {
            p0,
            n,
            u,
            v,
            geometry,
        }
    }

    fn thickness_at(x: f32) -> f32 {
        400.0 + GRADIENT * x
    }

    /// The analytic thickness at a point of the plane.
    fn analytic(&self, p: Vec3) -> f32 {
        Self::thickness_at((p - self.p0).dot(self.u))
    }

    fn point(&self, x: f32, y: f32) -> Vec3 {
        self.p0 + x * self.u + y * self.v
    }
}

#[test]
fn coplanar_disks_give_one_crossing_with_the_analytic_thickness() {
    let plane = Plane::new();
    let g = &plane.geometry;
    let mut rng = Rng(5);
    let (mut max_err, mut max_err_single) = (0f32, 0f32);
    let mut min_coverage = u32::MAX;
    for _ in 0..3000 {
        let target = plane.point(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
        // From either side, up to ~70° from the normal.
        let side = if rng.f() < 0.5 { 1.0 } else { -1.0 };
        let origin = target
            + side * 2.0 * plane.n
            + rng.range(-2.5, 2.5) * plane.u
            + rng.range(-2.5, 2.5) * plane.v;
        let ray = Ray::new(origin, target - origin);
        let all = crossings(g, &ray);
        assert_eq!(all.len(), 1, "ray {ray:?}: {all:?}");
        let h = all[0];
        min_coverage = min_coverage.min(h.coverage);
        assert!(
            (h.position - plane.p0).dot(plane.n).abs() < 1e-4,
            "off the plane: {h:?}"
        );
        assert!(h.normal.dot(plane.n).abs() > 1.0 - 1e-5, "normal {h:?}");
        max_err = max_err.max((h.thickness_nm - plane.analytic(h.position)).abs());
        let s = g.intersect_single(&ray, 0.0, f32::INFINITY).unwrap();
        max_err_single = max_err_single.max((s.thickness_nm - plane.analytic(s.position)).abs());
    }
    // Blended: the kernel-weighted mean of a linear field is exact up to the offset of the
    // weighted centroid of the centres, a fraction of the spacing (measured: 2.7 nm with ±0.25 spacing jitter).
    let tolerance = 0.35 * GRADIENT * SPACING;
    assert!(
        min_coverage >= 2,
        "radius 1.5× spacing: every point is covered twice or more"
    );
    assert!(max_err < tolerance, "blended thickness error {max_err} nm");
    // One disk's value is off by up to gradient × radius (15 nm): the test tells them apart.
    assert!(
        max_err_single > 3.0 * tolerance,
        "unblended error {max_err_single} nm"
    );
}

#[test]
fn blended_thickness_is_continuous_along_a_line() {
    let plane = Plane::new();
    let g = &plane.geometry;
    let dir = (-plane.n + 0.5 * plane.u + 0.3 * plane.v).normalize();
    let steps = 3000;
    let (mut jump, mut jump_single) = (0f32, 0f32);
    let mut prev: Option<(f32, f32)> = None;
    for k in 0..=steps {
        let x = -1.5 + 3.0 * k as f32 / steps as f32;
        let target = plane.point(x, 0.37);
        let ray = Ray::new(target - 3.0 * dir, dir);
        let b = g.intersect(&ray, 0.0, f32::INFINITY).unwrap().thickness_nm;
        let s = g
            .intersect_single(&ray, 0.0, f32::INFINITY)
            .unwrap()
            .thickness_nm;
        if let Some((pb, ps)) = prev {
            jump = jump.max((b - pb).abs());
            jump_single = jump_single.max((s - ps).abs());
        }
        prev = Some((b, s));
    }
    // Neighbouring rays are 1 mm apart on the plane: the analytic change is 0.1 nm.
    let step_change = GRADIENT * 3.0 / steps as f32;
    assert!(jump < 5.0 * step_change, "blended jump {jump} nm");
    assert!(
        jump_single > 20.0 * jump,
        "unblended jump {jump_single} nm vs blended {jump} nm"
    );
}

/// `n` points evenly spread on the unit sphere (Fibonacci lattice).
fn fibonacci_sphere(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).sqrt();
            let a = golden * i as f32;
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
        .collect()
}

#[test]
fn sphere_shell_of_disks_has_two_crossings_on_the_sphere() {
    let n = 2000;
    let pos = fibonacci_sphere(n);
    let spacing = (4.0 * std::f32::consts::PI / n as f32).sqrt();
    let radius = 1.5 * spacing;
    let mut rng = Rng(11);
    // Outward normals, half of them flipped (a film has no inside).
    let nrm: Vec<Vec3> = pos
        .iter()
        .map(|&p| if rng.f() < 0.5 { p } else { -p })
        .collect();
    let thk: Vec<f32> = pos.iter().map(|p| 500.0 + 200.0 * p.z).collect();
    let g = DiskGeometry::build(&pos, &nrm, &vec![radius; n], &thk).unwrap();
    // Tangent disks lie outside the sphere by at most sqrt(1 + r²) − 1 where they cover a ray
    // through the centre.
    let tolerance = (1.0 + radius * radius).sqrt() - 1.0 + 1e-4;
    for _ in 0..300 {
        let d = rng.unit();
        let ray = Ray::new(-3.0 * d, d);
        let all = crossings(&g, &ray);
        assert_eq!(all.len(), 2, "ray {ray:?}: {all:?}");
        for (h, t) in all.iter().zip([2.0, 4.0]) {
            assert!(
                (h.t - t).abs() <= tolerance,
                "t {} vs {t} (tolerance {tolerance})",
                h.t
            );
            assert!(h.normal.dot(d).abs() > 0.99, "{h:?}");
            assert!(h.coverage >= 2);
            let want = 500.0 + 200.0 * h.position.z;
            assert!(
                (h.thickness_nm - want).abs() < 0.25 * 200.0 * spacing,
                "{h:?} vs {want}"
            );
        }
        // From the centre: only the far wall.
        let inside = crossings(&g, &Ray::new(Vec3::ZERO, d));
        assert_eq!(inside.len(), 1);
        assert!((inside[0].t - 1.0).abs() <= tolerance);
        // Off-centre rays at distance b: still two crossings, at 3 ∓ sqrt(1 − b²); the
        // tolerance grows with 1 / cos(incidence).
        for b in [0.5f32, 0.9] {
            let ray = Ray::new(-3.0 * d + b * d.any_orthonormal_vector(), d);
            let all = crossings(&g, &ray);
            assert_eq!(all.len(), 2, "b = {b}, ray {ray:?}: {all:?}");
            let half = (1.0 - b * b).sqrt();
            for (h, t) in all.iter().zip([3.0 - half, 3.0 + half]) {
                assert!(
                    (h.t - t).abs() <= tolerance / half,
                    "b = {b}: t {} vs {t}",
                    h.t
                );
            }
        }
    }
}
