//! A bubble with a drop forming and separating at its bottom: the liquid drained from the film
//! collects into a drop that hangs on a thinning neck, pinches off at [`T_SEPARATE`] and falls.
//!
//! Shape (z up, surface of revolution about z): the unit bubble and a drop sphere of radius
//! ρ(t) centred at z_d(t), joined by a neck of radius r_n(t); the profile radius is the smooth
//! maximum R(z) = (r_b^p + r_d^p + r_n^p)^(1/p), p = 6, of the three (r_n only between the
//! centres). Before separation ρ grows from 0.12 to 0.2, the drop sags (gap 0.3·(t/T)²) and
//! the neck thins as √(1 − t/T) to nothing; then the drop falls with constant acceleration
//! (slow motion) and the profile between them has zero area. Everything is continuous in
//! time, so particles move smoothly (except across the pinch itself, where the neck's few
//! particles jump to the drop or the bubble).
//!
//! Thickness: the bubble's field; toward the bottom, the neck and the drop it blends into
//! [`H_DROP_NM`] (a drop is thick liquid: it shows pale, high-order colours).

use super::surface::{SampleParams, revolution, to_cloud};
use super::thickness::{Chart, ThicknessField};
use crate::pointcloud::PointCloud;
use glam::{DVec2, DVec3};

/// Time at which the drop pinches off, seconds.
pub const T_SEPARATE: f64 = 2.0;
/// Thickness of the drop, nm.
pub const H_DROP_NM: f32 = 2500.0;
/// Drop acceleration after separation, scene units/s² (slow motion).
const FALL: f64 = 1.5;
/// Smooth-maximum exponent.
const P: i32 = 6;

/// The drip's shape at one time: drop radius, drop centre height, neck radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DripShape {
    /// Drop radius, scene units.
    pub drop_radius: f64,
    /// Height of the drop's centre (z up; the bubble's centre is at 0).
    pub drop_z: f64,
    /// Neck radius (0 after separation).
    pub neck: f64,
}

/// The drip's shape at `time` (s); continuous in time.
pub fn shape(time: f64) -> DripShape {
    let s = (time / T_SEPARATE).clamp(0.0, 1.0);
    let rho = 0.12 + 0.08 * s;
    let gap = |s: f64| 0.3 * s * s;
    // Drop top meets the bubble's bottom at s = 0 (overlapping by half its radius).
    let z_sep = |s: f64, rho: f64| -1.0 - 0.5 * rho - gap(s);
    let mut z = z_sep(s, rho);
    if time > T_SEPARATE {
        // Fall on from the separation with the velocity it had (d/dt of z_sep at s = 1).
        let v = -(0.08 * 0.5 + 0.6) / T_SEPARATE;
        let dt = time - T_SEPARATE;
        z += v * dt - 0.5 * FALL * dt * dt;
    }
    DripShape {
        drop_radius: rho,
        drop_z: z,
        neck: 0.5 * rho * (1.0 - s).sqrt(),
    }
}

/// Profile radius at height `z` for `sh`.
fn profile_radius(sh: &DripShape, z: f64) -> f64 {
    let sphere = |r: f64, dz: f64| (r * r - dz * dz).max(0.0).sqrt();
    let rb = sphere(1.0, z);
    let rd = sphere(sh.drop_radius, z - sh.drop_z);
    let rn = if (sh.drop_z..=0.0).contains(&z) {
        sh.neck
    } else {
        0.0
    };
    (rb.powi(P) + rd.powi(P) + rn.powi(P)).powf(1.0 / P as f64)
}

/// The drip (unit bubble centred at the origin, drop below, y up), outward normals.
/// Deterministic for a seed.
pub fn drip(p: &SampleParams) -> PointCloud {
    let sh = shape(p.time as f64);
    let bottom = sh.drop_z - sh.drop_radius;
    let z_of = |u: f64| 1.0 - u * (1.0 - bottom);
    let profile = |u: f64| {
        let z = z_of(u);
        DVec2::new(profile_radius(&sh, z), z)
    };
    let chart = |u: f64, lon: f64| {
        let z = z_of(u).clamp(-1.0, 1.0);
        let r = (1.0 - z * z).sqrt();
        DVec3::new(r * lon.cos(), r * lon.sin(), z)
    };
    let surfels = revolution(p.particles, p.seed, profile, chart);
    let field = ThicknessField::new(p.seed, Chart::sphere());
    to_cloud(&surfels, &field, p.time, |s, h| {
        // Blend into the drop below z = −0.85 (smoothstep down to the bubble's bottom).
        let x = ((-0.85 - s.position.z) / 0.15).clamp(0.0, 1.0);
        h + (H_DROP_NM - h) * (x * x * (3.0 - 2.0 * x)) as f32
    })
}
