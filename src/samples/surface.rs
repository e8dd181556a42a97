//! Shared particle layouts for the sample generators: near-uniform sampling of star-shaped
//! closed surfaces and of surfaces of revolution, the chart points of the thickness field, and
//! the conversion from the generators' z-up frame to a y-up [`PointCloud`].
//!
//! Every generator works in a z-up frame (gravity −z, like [`super::thickness`]); scenes are
//! y up, as SPH simulators write them, so [`to_cloud`] turns z into y and y into −z (the
//! generators' −y side then faces a camera on +z).

use super::fibonacci::{fibonacci_point, fibonacci_spacing};
use super::rng::SplitMix64;
use super::thickness::ThicknessField;
use crate::pointcloud::PointCloud;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::f64::consts::TAU;

/// Splat radius as a fraction of the local particle spacing: disks overlap, no holes.
pub const SPLAT_FRACTION: f64 = 0.9;
/// Seeded tangential jitter, fraction of the spacing.
const JITTER: f64 = 0.15;

/// One generated particle in the z-up frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surfel {
    /// Position, scene units.
    pub position: DVec3,
    /// Unit normal (outward for closed surfaces).
    pub normal: DVec3,
    /// Splat radius, scene units.
    pub radius: f64,
    /// Point of the thickness field's unit sphere this particle shows (see
    /// [`super::thickness::Chart`]).
    pub chart: DVec3,
}

/// The common parameters of every generator.
#[derive(Debug, Clone, PartialEq)]
pub struct SampleParams {
    /// Number of particles.
    pub particles: usize,
    /// Animation time, seconds: shapes move and the thickness field evolves smoothly with it.
    pub time: f32,
    /// Seed of the jitter and of the thickness field.
    pub seed: u64,
}

impl Default for SampleParams {
    fn default() -> Self {
        SampleParams {
            particles: 200_000,
            time: 0.0,
            seed: 1,
        }
    }
}

/// The unit vector at longitude `phi` (from −y toward +x) and latitude `lat` (toward +z), rad.
/// Flat films and ring-bounded films map onto this band of the thickness field's sphere.
pub fn lat_long(phi: f64, lat: f64) -> DVec3 {
    DVec3::new(lat.cos() * phi.sin(), -lat.cos() * phi.cos(), lat.sin())
}

/// A closed surface x(q) = r(q)·q over the unit sphere. `shape(q)` returns r(q) and its
/// tangential gradient ∇r on the unit sphere (⟂ q). Particles: the seeded jittered Fibonacci
/// lattice (as the bubble) mapped radially; normal ∝ q − ∇r/r (outward); radius
/// [`SPLAT_FRACTION`] × the local spacing d·r/√(n̂·q) (the radial map scales areas by
/// r²/(n̂·q)); chart point q. Parallel, deterministic. Cost O(n).
pub fn star_shaped<F>(n: usize, seed: u64, shape: F) -> Vec<Surfel>
where
    F: Fn(DVec3) -> (f64, DVec3) + Sync,
{
    let d = fibonacci_spacing(n, 1.0) as f64;
    (0..n)
        .into_par_iter()
        .map(|i| {
            let q = fibonacci_point(i, n);
            let mut g = SplitMix64::for_item(seed, i as u64);
            let (a, b) = q.any_orthonormal_pair();
            let ang = g.range(0.0, TAU);
            let rad = JITTER * d * g.next_f64().sqrt();
            let q = (q + (a * ang.cos() + b * ang.sin()) * rad).normalize();
            let (r, grad) = shape(q);
            let normal = (q - grad / r).normalize();
            Surfel {
                position: q * r,
                normal,
                radius: SPLAT_FRACTION * d * r / normal.dot(q).max(0.2).sqrt(),
                chart: q,
            }
        })
        .collect()
}

/// Profile table entries for [`revolution`].
const PROFILE_STEPS: usize = 4096;

/// A surface of revolution about z: `profile(u)` = (r, z) for u ∈ [0, 1], running from the
/// top down (then the normal (−dz, dr)/|·| of the profile points away from the axis; a profile
/// may touch the axis, e.g. at poles or a pinch). Particles sit at equal-area steps along the
/// profile with golden-angle longitudes — the Fibonacci lattice of any surface of revolution —
/// jittered by up to 15 % of the spacing d = √(2A/(√3·n)) (A the area), so the spacing is
/// near-uniform; radius [`SPLAT_FRACTION`]·d. `chart(u, longitude)` gives each particle's
/// thickness-field point. Positions lie exactly on the profile; normals by central
/// differences (error ≲ 1e-6). Cost O(n·log m), m = 4096 profile steps.
pub fn revolution<P, C>(n: usize, seed: u64, profile: P, chart: C) -> Vec<Surfel>
where
    P: Fn(f64) -> DVec2 + Sync,
    C: Fn(f64, f64) -> DVec3 + Sync,
{
    let m = PROFILE_STEPS;
    let pts: Vec<DVec2> = (0..=m).map(|j| profile(j as f64 / m as f64)).collect();
    let mut cum = Vec::with_capacity(m + 1);
    cum.push(0.0f64);
    for w in pts.windows(2) {
        let r = 0.5 * (w[0].x.abs() + w[1].x.abs());
        cum.push(cum.last().unwrap() + TAU * r * (w[1] - w[0]).length());
    }
    let area = *cum.last().unwrap();
    let d = (2.0 * area / (3f64.sqrt() * n.max(1) as f64)).sqrt();
    // Profile parameter at cumulative area `a`.
    let u_at = |a: f64| {
        let a = a.clamp(0.0, area);
        let j = cum.partition_point(|&c| c < a).clamp(1, m);
        let (c0, c1) = (cum[j - 1], cum[j]);
        let f = if c1 > c0 { (a - c0) / (c1 - c0) } else { 0.0 };
        (j as f64 - 1.0 + f) / m as f64
    };
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let eps = 0.25 / m as f64;
    (0..n)
        .into_par_iter()
        .map(|i| {
            let mut g = SplitMix64::for_item(seed, i as u64);
            let (ja, jb) = (g.range(-1.0, 1.0), g.range(-1.0, 1.0));
            let a0 = area * (i as f64 + 0.5) / n as f64;
            let r0 = profile(u_at(a0)).x.abs();
            let u = u_at(a0 + TAU * r0 * JITTER * d * ja);
            let p = profile(u);
            let t = profile((u + eps).min(1.0)) - profile((u - eps).max(0.0));
            let nrz = if p.x.abs() < 1e-9 {
                // On the axis (a pole, or the end of a pinch): the normal is along the axis,
                // away from the side the surface continues on.
                let side = (1..=64)
                    .find_map(|k| {
                        let du = k as f64 / m as f64;
                        let a = profile((u - du).max(0.0)).x.abs();
                        let b = profile((u + du).min(1.0)).x.abs();
                        (a != b).then_some(if a > b { -1.0 } else { 1.0 })
                    })
                    .unwrap_or(1.0);
                DVec2::new(0.0, side)
            } else {
                DVec2::new(-t.y, t.x).normalize_or(DVec2::new(0.0, 1.0))
            };
            let lon = golden * i as f64 + (JITTER * d * jb / p.x.abs().max(d)).clamp(-0.5, 0.5);
            let (s, c) = lon.sin_cos();
            Surfel {
                position: DVec3::new(p.x * c, p.x * s, p.y),
                normal: DVec3::new(nrz.x * c, nrz.x * s, nrz.y),
                radius: SPLAT_FRACTION * d,
                chart: chart(u, lon),
            }
        })
        .collect()
}

/// Paints `surfels` with `field` at `time` and turns them into a y-up [`PointCloud`] (z → y,
/// y → −z), thickness in nm. `adjust(surfel, h)` may change a particle's thickness (drops).
pub fn to_cloud<A>(surfels: &[Surfel], field: &ThicknessField, time: f32, adjust: A) -> PointCloud
where
    A: Fn(&Surfel, f32) -> f32 + Sync,
{
    let charts: Vec<DVec3> = surfels.iter().map(|s| s.chart).collect();
    let h = field.thickness_of(&charts, time as f64);
    let y_up = |q: DVec3| DVec3::new(q.x, q.z, -q.y);
    PointCloud {
        positions: surfels.iter().map(|s| y_up(s.position).as_vec3()).collect(),
        normals: Some(
            surfels
                .iter()
                .map(|s| y_up(s.normal).as_vec3().normalize())
                .collect(),
        ),
        thickness_nm: Some(
            surfels
                .par_iter()
                .zip(h)
                .map(|(s, h)| adjust(s, h))
                .collect(),
        ),
        radius: Some(surfels.iter().map(|s| s.radius as f32).collect()),
        extra: Vec::new(),
    }
}

/// Keeps a seeded random fraction `keep` ∈ (0, 1] of the particles (each independently, so
/// the spacing becomes irregular, as in sparse simulation output) and widens the splats by
/// 1/√keep, as a generator would for the lower density. Deterministic for a seed.
pub fn sparse(cloud: &PointCloud, keep: f64, seed: u64) -> PointCloud {
    let kept: Vec<usize> = (0..cloud.len())
        .filter(|&i| SplitMix64::for_item(seed ^ 0x5BA2_5E00, i as u64).next_f64() < keep)
        .collect();
    let pick3 = |v: &Vec<glam::Vec3>| kept.iter().map(|&i| v[i]).collect::<Vec<_>>();
    let pick = |v: &Vec<f32>| kept.iter().map(|&i| v[i]).collect::<Vec<_>>();
    let widen = 1.0 / (keep.max(1e-9) as f32).sqrt();
    PointCloud {
        positions: pick3(&cloud.positions),
        normals: cloud.normals.as_ref().map(pick3),
        thickness_nm: cloud.thickness_nm.as_ref().map(pick),
        radius: cloud
            .radius
            .as_ref()
            .map(|r| pick(r).into_iter().map(|x| x * widen).collect()),
        extra: cloud
            .extra
            .iter()
            .map(|(name, v)| (name.clone(), pick(v)))
            .collect(),
    }
}

/// Legendre polynomial P_l(x) and its derivative, l ≤ 4.
pub fn legendre(l: usize, x: f64) -> (f64, f64) {
    match l {
        0 => (1.0, 0.0),
        1 => (x, 1.0),
        2 => (1.5 * x * x - 0.5, 3.0 * x),
        3 => (2.5 * x * x * x - 1.5 * x, 7.5 * x * x - 1.5),
        _ => (
            (35.0 * x.powi(4) - 30.0 * x * x + 3.0) / 8.0,
            (140.0 * x.powi(3) - 60.0 * x) / 8.0,
        ),
    }
}

/// The zonal spherical harmonic P_l(axis·q) of degree `l` ≤ 4 about unit `axis`, at unit `q`:
/// its value and its tangential gradient on the unit sphere, P_l′(x)·(axis − x·q).
pub fn zonal(l: usize, axis: DVec3, q: DVec3) -> (f64, DVec3) {
    let x = axis.dot(q);
    let (p, dp) = legendre(l, x);
    (p, (axis - q * x) * dp)
}
