//! The MLS ray intersection against a brute-force oracle: every zero of the same field along the
//! ray, found by sampling f ([`MlsSurface::field_at`], a BVH point query that shares nothing
//! with the intersector's gathering, band or march) at a uniform step of 1/100 of the smallest
//! particle radius, and bisecting each sign change. The intersector, continued past each hit as
//! the integrator does (every other ray with a query on another ray between its steps), must report exactly the oracle's film crossings, in order, each within
//! 3·10⁻³ radii. Rays where the oracle itself is unsure are set aside (and counted): two zeros
//! closer than 1/20 radius (a grazing double crossing; the intersector may see two or none), a
//! near-zero dip of |f| without a sign change, or a zero whose weight or normal agreement is
//! within 2 % of the film threshold. Surfaces: a noisy sphere (jittered positions, tilted
//! normals, uneven radii), two close wavy sheets with a hole (a foam's neighbouring films), and
//! the MELP simulator's bubble and foam frames as the pipeline reads them.

mod geometry_support;
use geometry_support::Rng;

use filmsplat::geometry::{MlsSurface, Ray};
use filmsplat::io::{ReadOptions, read_parts};
use filmsplat::pointcloud::{EstimateOptions, PointCloud, fill_missing};
use filmsplat::samples::{fibonacci_spacing, fibonacci_sphere};
use glam::Vec3;
use rayon::prelude::*;
use std::path::Path;

/// Oracle step, particle radii.
const STEP: f32 = 0.01;
/// Allowed distance between the intersector's and the oracle's zero, particle radii.
const AGREE: f32 = 3e-3;

/// One zero of f along a ray, as the oracle found it.
#[derive(Clone, Copy, Debug)]
struct Zero {
    t: f32,
    film: bool,
    /// The weight or the coherence is within 2 % of its threshold.
    marginal: bool,
}

/// Every zero of f along `ray`, or `None` if the oracle is unsure on this ray.
fn oracle(s: &MlsSurface, ray: &Ray, r_min: f32) -> Option<Vec<Zero>> {
    let Some((t0, t1)) = s.bounds().intersect_ray(ray, 0.0, f32::INFINITY) else {
        return Some(Vec::new());
    };
    let step = STEP * r_min;
    let f = |t: f32| s.field_at(ray.at(t)).map(|p| p.f);
    let threshold = s.weight_threshold();
    let mut zeros: Vec<Zero> = Vec::new();
    let mut prev: Option<(f32, f32)> = None;
    let mut prev2: Option<(f32, f32)> = None;
    let n = ((t1 - t0) / step).ceil() as usize + 1;
    for k in 0..=n {
        let t = t0 + k as f32 * step;
        let Some(ft) = f(t) else {
            (prev, prev2) = (None, None);
            continue;
        };
        if let Some((pt, pf)) = prev {
            if (pf < 0.0) != (ft < 0.0) {
                let z = bisect(&f, (pt, pf), (t, ft));
                let p = s.field_at(ray.at(z)).expect("f is defined at its zero");
                let marginal = (p.weight / threshold - 1.0).abs() < 0.02
                    || (p.coherence / 0.5 - 1.0).abs() < 0.02;
                zeros.push(Zero {
                    t: z,
                    film: p.is_film,
                    marginal,
                });
            } else if let Some((_, p2f)) = prev2
                && (p2f < 0.0) == (pf < 0.0)
                && pf.abs() < p2f.abs()
                && pf.abs() <= ft.abs()
                && pf.abs() < 2.0 * step
            {
                return None; // a dip of |f| that may hide two zeros between samples
            }
        }
        (prev2, prev) = (prev, Some((t, ft)));
    }
    let close = zeros.windows(2).any(|w| w[1].t - w[0].t < 0.05 * r_min);
    let marginal = zeros.iter().any(|z| z.marginal);
    (!close && !marginal).then_some(zeros)
}

/// The zero of `f` between `a` and `b` (opposite signs) to f32 resolution.
fn bisect(f: &impl Fn(f32) -> Option<f32>, a: (f32, f32), b: (f32, f32)) -> f32 {
    let (mut a, mut b) = (a, b);
    for _ in 0..40 {
        let m = 0.5 * (a.0 + b.0);
        if m <= a.0 || m >= b.0 {
            break;
        }
        match f(m) {
            Some(fm) if (fm < 0.0) == (a.1 < 0.0) => a = (m, fm),
            Some(fm) => b = (m, fm),
            None => break,
        }
    }
    0.5 * (a.0 + b.0)
}

/// The intersector's crossings along `ray`, continuing past each as the integrator does; with a
/// `decoy`, a query on that ray comes between each two (so the support spheres kept for `ray`
/// are not the last ones gathered).
fn crossings(s: &MlsSurface, ray: &Ray, r_min: f32, decoy: Option<&Ray>) -> Vec<f32> {
    let mut hits = Vec::new();
    let mut t = 0.0;
    while let Some(h) = s.intersect(ray, t, f32::INFINITY) {
        t = h.t_exit + 1e-4 * r_min;
        hits.push(h.t);
        if let Some(d) = decoy {
            s.intersect(d, 0.0, f32::INFINITY);
        }
        assert!(hits.len() < 64, "runaway crossings on {ray:?}");
    }
    hits
}

/// Checks `rays` against the oracle; returns (rays checked, film crossings checked).
fn check(name: &str, s: &MlsSurface, r_min: f32, rays: &[Ray]) -> (usize, usize) {
    let results: Vec<Option<(Vec<f32>, Vec<f32>)>> = (0..rays.len())
        .into_par_iter()
        .map(|k| {
            let zeros = oracle(s, &rays[k], r_min)?;
            let want: Vec<f32> = zeros.iter().filter(|z| z.film).map(|z| z.t).collect();
            let decoy = (k % 2 == 1).then(|| &rays[k - 1]);
            Some((want, crossings(s, &rays[k], r_min, decoy)))
        })
        .collect();
    let (mut checked, mut films) = (0, 0);
    for (ray, res) in rays.iter().zip(&results) {
        let Some((want, got)) = res else { continue };
        let ok = want.len() == got.len()
            && want
                .iter()
                .zip(got)
                .all(|(w, g)| (w - g).abs() <= AGREE * r_min);
        assert!(ok, "{name}: {ray:?}\n  oracle {want:?}\n  found  {got:?}");
        checked += 1;
        films += want.len();
    }
    eprintln!(
        "{name}: {checked}/{} rays, {films} film crossings",
        rays.len()
    );
    assert!(
        checked * 10 >= rays.len() * 9,
        "{name}: oracle unsure on too many rays"
    );
    (checked, films)
}

/// Rays from a sphere of radius 2·`extent` around `centre` toward random points inside
/// `extent`, half of them nearly tangent to a sphere of radius `graze` around `centre`.
fn rays(rng: &mut Rng, centre: Vec3, extent: f32, graze: f32, n: usize) -> Vec<Ray> {
    (0..n)
        .map(|k| {
            let o = centre + 2.0 * extent * rng.unit();
            let target = if k % 2 == 0 {
                centre + extent * rng.f().cbrt() * rng.unit()
            } else {
                let d = (centre - o).normalize();
                let side =
                    (rng.unit() - rng.unit().dot(d) * d).normalize_or(d.any_orthogonal_vector());
                centre + side * graze * rng.range(0.97, 1.03)
            };
            Ray::new(o, target - o)
        })
        .collect()
}

#[test]
fn noisy_sphere_crossings_match_the_oracle() {
    let n = 3000;
    let d = fibonacci_spacing(n, 1.0);
    let mut rng = Rng(17);
    let mut p = fibonacci_sphere(n, 1.0);
    let mut normals = Vec::with_capacity(n);
    let mut radii = Vec::with_capacity(n);
    for q in &mut p {
        let out = q.normalize();
        *q = out * (1.0 + rng.range(-0.1, 0.1) * d) + 0.2 * d * rng.unit().reject_from(out);
        normals.push((out + 0.25 * rng.unit()).normalize());
        radii.push(0.92 * d * rng.range(0.8, 1.15));
    }
    let thk = vec![400.0; n];
    let s = MlsSurface::build(&p, &normals, &radii, &thk).unwrap();
    let r_min = radii.iter().copied().fold(f32::INFINITY, f32::min);
    let rays = rays(&mut rng, Vec3::ZERO, 1.0, 1.0, 800);
    let (_, films) = check("noisy sphere", &s, r_min, &rays);
    assert!(films > 700, "{films}");
}

#[test]
fn close_wavy_sheets_with_a_hole_match_the_oracle() {
    let d = 0.04;
    let m = (2.0 / d) as i32;
    let mut rng = Rng(23);
    let (mut p, mut normals) = (Vec::new(), Vec::new());
    for sheet in 0..2 {
        let z0 = sheet as f32 * 1.6 * d;
        for i in 0..=m {
            for j in 0..=m {
                let (x, y) = (-1.0 + i as f32 * d, -1.0 + j as f32 * d);
                let (x, y) = (
                    x + rng.range(-0.15, 0.15) * d,
                    y + rng.range(-0.15, 0.15) * d,
                );
                if sheet == 1 && (x - 0.3).hypot(y + 0.2) < 0.25 {
                    continue;
                }
                let z = z0 + 0.05 * (3.0 * x).sin() * (2.0 * y).cos();
                let grad = Vec3::new(
                    0.15 * (3.0 * x).cos() * (2.0 * y).cos(),
                    -0.1 * (3.0 * x).sin() * (2.0 * y).sin(),
                    1.0,
                );
                p.push(Vec3::new(x, y, z));
                normals.push(grad.normalize());
            }
        }
    }
    let radii = vec![0.92 * d; p.len()];
    let s = MlsSurface::build(&p, &normals, &radii, &vec![300.0; p.len()]).unwrap();
    let rays = rays(&mut rng, Vec3::ZERO, 1.0, 0.8, 800);
    let (_, films) = check("two sheets", &s, 0.92 * d, &rays);
    assert!(films > 600, "{films}");
}

/// A MELP frame as the pipeline reads it: its films joined, normals and radii estimated where
/// missing.
fn melp(rel: &str) -> (MlsSurface, f32, Vec3, f32) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/melp")
        .join(rel);
    let parts = read_parts(&path, &ReadOptions::default()).unwrap();
    let clouds: Vec<PointCloud> = parts.into_iter().map(|p| p.cloud).collect();
    let mut cloud = PointCloud::concat(&clouds);
    fill_missing(&mut cloud, &EstimateOptions::default());
    let radii = cloud.radius.clone().unwrap();
    let s = MlsSurface::build(
        &cloud.positions,
        cloud.normals.as_ref().unwrap(),
        &radii,
        cloud.thickness_nm.as_ref().unwrap(),
    )
    .unwrap();
    let r_min = radii.iter().copied().fold(f32::INFINITY, f32::min);
    let b = s.bounds();
    (s, r_min, b.centroid(), 0.5 * b.extent().max_element())
}

#[test]
fn melp_frames_match_the_oracle() {
    let mut rng = Rng(29);
    for rel in ["bubble/l_particles_0100.vtp", "foam3/50"] {
        let (s, r_min, centre, extent) = melp(rel);
        let rays = rays(&mut rng, centre, extent, 0.8 * extent, 400);
        let (_, films) = check(rel, &s, r_min, &rays);
        assert!(films > 250, "{rel}: {films}");
    }
}
