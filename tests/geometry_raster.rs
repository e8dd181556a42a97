//! Camera rays by rasterising the disks (`DiskGeometry::primary_layers`) against the BVH query
//! they replace (`DiskGeometry::intersect`), pixel by pixel: the same hits and misses, the same
//! layer members (coverage), the same `t_exit` and particle, and the blended `t`, normal and
//! thickness equal up to the order of the float sums (bit for bit when at most two disks are
//! blended, since the closest disk is always added first).

use filmsplat::geometry::{DiskGeometry, LayerBlend, PinholeGrid, Ray, SurfaceHit};
use glam::{Vec3, Vec4};

mod geometry_support;
use geometry_support::Rng;

/// A look-at pinhole grid with vertical field of view `fov_deg`.
fn grid(eye: Vec3, target: Vec3, fov_deg: f32, w: usize, h: usize) -> PinholeGrid {
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let half_height = (0.5 * fov_deg.to_radians()).tan();
    PinholeGrid {
        eye,
        forward,
        right,
        up: right.cross(forward),
        half_width: half_height * w as f32 / h as f32,
        half_height,
        width: w,
        height: h,
    }
}

/// The ray of pixel (x, y) as the grid defines it.
fn ray(g: &PinholeGrid, x: usize, y: usize) -> Ray {
    let u = (2.0 * (x as f32 + 0.5) / g.width as f32 - 1.0) * g.half_width;
    let v = (1.0 - 2.0 * (y as f32 + 0.5) / g.height as f32) * g.half_height;
    Ray::new(g.eye, g.forward + u * g.right + v * g.up)
}

/// Compares every pixel with `intersect`; returns (pixels hit, pixels blending ≥ 3 disks).
fn check(geo: &DiskGeometry, g: &PinholeGrid, what: &str) -> (usize, usize) {
    let (hit, stacked, _) = check_particles(geo, g, what);
    (hit, stacked)
}

/// As [`check`], also returning the particle seen at each pixel.
fn check_particles(
    geo: &DiskGeometry,
    g: &PinholeGrid,
    what: &str,
) -> (usize, usize, Vec<Option<u32>>) {
    let hits = geo.primary_layers(g, |x, y| ray(g, x, y)).unwrap();
    let (mut hit, mut stacked) = (0, 0);
    for y in 0..g.height {
        for x in 0..g.width {
            let r = ray(g, x, y);
            let want = geo.intersect(&r, 0.0, f32::INFINITY);
            let got = hits[y * g.width + x];
            let at = format!("{what}: pixel ({x}, {y}), raster {got:?}, intersect {want:?}");
            match (got, want) {
                (None, None) => {}
                (Some(a), Some(b)) => {
                    hit += 1;
                    same_crossing(&a, &b, &at);
                    stacked += (a.coverage > 2) as usize;
                }
                _ => panic!("{at}"),
            }
        }
    }
    (
        hit,
        stacked,
        hits.iter().map(|h| h.map(|h| h.particle)).collect(),
    )
}

/// Equal layers; the blended values within float summation order.
fn same_crossing(a: &SurfaceHit, b: &SurfaceHit, at: &str) {
    assert_eq!(
        (a.coverage, a.particle, a.t_exit.to_bits()),
        (b.coverage, b.particle, b.t_exit.to_bits()),
        "{at}"
    );
    if a.coverage <= 2 {
        assert_eq!(a, b, "{at}");
        return;
    }
    let close = |p: f32, q: f32| (p - q).abs() <= 1e-5 * p.abs().max(q.abs()).max(1e-3);
    assert!(close(a.t, b.t), "t {at}");
    assert!(close(a.thickness_nm, b.thickness_nm), "thickness {at}");
    assert!((a.normal - b.normal).length() <= 1e-5, "normal {at}");
}

/// A Fibonacci shell of `n` disks of radius 0.9–1.5× the spacing around the origin (unit
/// radius), normals outward.
fn shell(n: usize, rng: &mut Rng) -> DiskGeometry {
    let spacing = (4.0 * std::f32::consts::PI / n as f32).sqrt();
    let pos = filmsplat::samples::fibonacci_sphere(n, 1.0);
    let radii: Vec<f32> = (0..n).map(|_| rng.range(0.9, 1.5) * spacing).collect();
    let thk: Vec<f32> = pos.iter().map(|p| 500.0 + 300.0 * p.z).collect();
    DiskGeometry::build(&pos, &pos, &radii, &thk).unwrap()
}

#[test]
fn raster_equals_intersect_on_a_shell_from_outside_inside_and_at_its_edge() {
    let mut rng = Rng(7);
    let geo = shell(4000, &mut rng);
    let views = [
        // Fills the frame; the shell's silhouette in the frame; seen from far (misses around);
        // from inside (every disk's back); grazing the shell from just outside it.
        (Vec3::new(0.3, 0.4, 1.5).normalize() * 1.6, Vec3::ZERO, 40.0),
        (Vec3::new(0.0, 0.2, 1.8), Vec3::new(0.9, 0.0, 0.0), 50.0),
        (Vec3::new(2.0, -3.0, 4.0), Vec3::ZERO, 25.0),
        (Vec3::new(0.1, 0.2, -0.3), Vec3::new(1.0, 0.0, 0.3), 90.0),
        (Vec3::new(0.0, 0.0, 1.02), Vec3::new(1.0, 0.0, 1.0), 70.0),
    ];
    let (mut hit, mut stacked) = (0, 0);
    for (k, (eye, target, fov)) in views.into_iter().enumerate() {
        let (a, b) = check(&geo, &grid(eye, target, fov, 64, 48), &format!("view {k}"));
        hit += a;
        stacked += b;
    }
    assert!(
        hit > 10_000 && stacked > 3_000,
        "{hit} hits, {stacked} stacked"
    );
}

#[test]
fn raster_equals_intersect_on_random_oblique_stacks_ties_and_disks_at_the_eye() {
    let mut rng = Rng(11);
    let mut pos = Vec::new();
    let mut nrm = Vec::new();
    let mut rad = Vec::new();
    for _ in 0..600 {
        // Stacks of overlapping, oblique disks, some exact duplicates (ties in t).
        let c = rng.in_box(-1.0, 1.0);
        let n = rng.unit();
        for j in 0..4 {
            pos.push(c + n * (0.02 * j as f32) + rng.in_box(-0.05, 0.05) * (j % 2) as f32);
            nrm.push(if j == 3 {
                n
            } else {
                (n + 0.3 * rng.unit()).normalize()
            });
            rad.push(rng.range(0.02, 0.2));
        }
        // An exact copy of the stack's first disk: ties in t go to the lower particle index.
        let first = pos.len() - 4;
        pos.push(pos[first]);
        nrm.push(nrm[first]);
        rad.push(rad[first]);
    }
    let eye = Vec3::new(0.2, 0.1, 2.5);
    // Disks at the eye: one through it (never hit: t = 0), one beside it reaching past its
    // plane (straddling: tested by every ray), one small just in front of it and one large
    // behind it reaching in front of it.
    for (d, n, r) in [
        (Vec3::ZERO, Vec3::new(0.3, 0.2, 1.0), 0.3),
        (Vec3::new(0.03, 0.0, -0.02), Vec3::new(1.0, 0.0, 0.3), 0.04),
        (Vec3::new(-0.02, 0.01, -0.05), Vec3::Z, 0.02),
        (Vec3::new(0.0, 0.1, 0.05), Vec3::new(0.0, 1.0, 1.0), 0.3),
    ] {
        pos.push(eye + d);
        nrm.push(n.normalize());
        rad.push(r);
    }
    let thk: Vec<f32> = (0..pos.len()).map(|_| rng.range(100.0, 900.0)).collect();
    let mut geo = DiskGeometry::build(&pos, &nrm, &rad, &thk).unwrap();
    let views = [
        (eye, Vec3::ZERO, 60.0, 64, 48),
        (eye, Vec3::X, 100.0, 37, 29),
    ];
    let near = |p: u32| p as usize >= pos.len() - 4;
    for (k, &(eye, target, fov, w, h)) in views.iter().enumerate() {
        let g = grid(eye, target, fov, w, h);
        let (hit, _, seen) = check_particles(&geo, &g, &format!("stacks {k}"));
        let at_eye = seen.iter().flatten().filter(|&&p| near(p)).count();
        assert!(hit > w * h / 4, "view {k}: {hit} hits");
        assert!(
            k > 0 || (at_eye > 50 && hit - at_eye > 500),
            "{at_eye} of {hit} at the eye"
        );
    }
    // Without blending the closest disk alone is seen: ties in t show which one wins.
    let mut single = geo.clone();
    single.set_layer_blend(LayerBlend::NONE);
    check(&single, &grid(eye, Vec3::ZERO, 60.0, 64, 48), "unblended");
    // Curved disks with a thickness gradient, and edge cuts.
    let n = pos.len();
    let curv: Vec<f32> = (0..n).map(|_| rng.range(-3.0, 3.0)).collect();
    let grad: Vec<Vec3> = (0..n).map(|_| rng.in_box(-500.0, 500.0)).collect();
    let cuts: Vec<[Vec4; 2]> = (0..n)
        .map(|_| {
            [
                rng.unit().extend(rng.range(-0.05, 0.1)),
                Vec4::ZERO.with_w(f32::INFINITY),
            ]
        })
        .collect();
    geo.set_curvature(&curv).unwrap();
    geo.set_thickness_gradient(&grad).unwrap();
    geo.set_edge_clips(&cuts).unwrap();
    let (eye, target, fov, w, h) = views[0];
    let (hit, _) = check(&geo, &grid(eye, target, fov, w, h), "detail and cuts");
    assert!(hit > w * h / 8, "{hit} hits");
}

#[test]
fn random_views_of_random_disks_agree_and_unusable_grids_are_refused() {
    let mut rng = Rng(23);
    let n = 2000;
    let pos: Vec<Vec3> = (0..n).map(|_| rng.in_box(-1.0, 1.0)).collect();
    let nrm: Vec<Vec3> = (0..n).map(|_| rng.unit()).collect();
    let rad: Vec<f32> = (0..n).map(|_| rng.range(0.01, 0.15)).collect();
    let thk: Vec<f32> = (0..n).map(|_| rng.range(0.0, 1000.0)).collect();
    let geo = DiskGeometry::build(&pos, &nrm, &rad, &thk).unwrap();
    for k in 0..12 {
        let eye = rng.in_box(-2.5, 2.5);
        let target = rng.in_box(-0.5, 0.5);
        let (w, h) = (8 + (rng.f() * 60.0) as usize, 8 + (rng.f() * 40.0) as usize);
        check(
            &geo,
            &grid(eye, target, rng.range(5.0, 150.0), w, h),
            &format!("random {k}"),
        );
    }
    let mut g = grid(Vec3::Z, Vec3::ZERO, 40.0, 0, 10);
    assert!(geo.primary_raster(&g).is_none(), "zero width");
    g.width = 10;
    g.right *= 2.0;
    assert!(geo.primary_raster(&g).is_none(), "not orthonormal");
}

/// The raster bins a disk by the box of its projected rim (an ellipse), not its sphere's: the
/// bound is tight for disks seen edge-on, so nearly edge-on disks (tilted 0 to 0.1 rad from
/// the line of sight), across the frame and past its edges, near the eye and far, must still
/// give every hit `intersect` gives.
#[test]
fn nearly_edge_on_disks_near_the_frame_edge_and_the_eye_agree() {
    let mut rng = Rng(41);
    let eye = Vec3::new(0.1, -0.2, 3.0);
    let g = grid(eye, Vec3::ZERO, 100.0, 64, 48);
    let (mut pos, mut nrm, mut rad) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..1500 {
        // A direction through the frame or up to 15 % past its edges.
        let (u, v) = (rng.range(-1.15, 1.15), rng.range(-1.15, 1.15));
        let d = (g.forward + u * g.half_width * g.right + v * g.half_height * g.up).normalize();
        let t = [0.03, 0.3, 1.0, 3.0][i % 4] * rng.range(0.8, 1.2);
        // A normal perpendicular to the line of sight, tilted towards it by `tilt`.
        let side = d.cross(rng.unit()).normalize();
        let tilt: f32 = [0.0, 1e-5, 1e-3, 1e-2, 0.1][i % 5];
        pos.push(eye + t * d);
        nrm.push((side * tilt.cos() + d * tilt.sin()).normalize());
        rad.push(t * rng.range(0.01, 0.3));
    }
    let thk: Vec<f32> = (0..pos.len()).map(|_| rng.range(100.0, 900.0)).collect();
    let geo = DiskGeometry::build(&pos, &nrm, &rad, &thk).unwrap();
    let (hit, _) = check(&geo, &g, "edge-on");
    assert!(hit > g.width * g.height / 4, "{hit} hits");
}

/// Over 2^17 disks the binning runs in parallel chunks (each filling its own part of every
/// tile's bin): a 300 000-disk shell, inside and outside, still agrees pixel by pixel.
#[test]
fn a_shell_binned_in_several_chunks_agrees() {
    let mut rng = Rng(5);
    let geo = shell(300_000, &mut rng);
    let (mut hit, mut stacked) = (0, 0);
    for (eye, target) in [
        (Vec3::new(0.3, 0.4, 1.5).normalize() * 1.3, Vec3::ZERO),
        (Vec3::new(0.1, 0.2, -0.3), Vec3::new(1.0, 0.0, 0.3)),
    ] {
        let (a, b) = check(&geo, &grid(eye, target, 60.0, 64, 48), "chunks");
        hit += a;
        stacked += b;
    }
    assert!(
        hit == 2 * 64 * 48 && stacked > 1000,
        "{hit} hits, {stacked} stacked"
    );
}
