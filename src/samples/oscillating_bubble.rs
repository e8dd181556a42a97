//! A bubble ringing in its l = 2 shape mode: r(q, t) = R·(1 + ε(t)·P₂(q·z) − ε(t)²/5) with
//! ε(t) = ε₀·cos(2πt/T). The −ε²/5 term keeps the volume constant to second order
//! (∫(1 + εP₂)³dΩ/4π = 1 + 3ε²/5 + O(ε³)). The bubble stretches into a prolate (vertical)
//! and then an oblate spheroid. T is slowed down ([`PERIOD_S`]) so a 24 fps sequence shows the
//! motion; a real 5 cm bubble rings at tens of Hz.

use super::surface::{SampleParams, star_shaped, to_cloud, zonal};
use super::thickness::{Chart, ThicknessField};
use crate::pointcloud::PointCloud;
use glam::DVec3;

/// Amplitude ε₀ of the l = 2 mode (relative to the radius).
pub const AMPLITUDE: f64 = 0.15;
/// Period of the oscillation, seconds.
pub const PERIOD_S: f64 = 1.2;

/// Radius (scene units) of the oscillating bubble along unit direction `q` (z up) at `time`
/// (s), and its tangential gradient; mean radius 1.
pub fn radius_at(q: DVec3, time: f64) -> (f64, DVec3) {
    let eps = AMPLITUDE * (std::f64::consts::TAU * time / PERIOD_S).cos();
    let (p2, g2) = zonal(2, DVec3::Z, q);
    (1.0 + eps * p2 - eps * eps / 5.0, g2 * eps)
}

/// The oscillating bubble (mean radius 1, centre at the origin, y up) with the bubble's
/// thickness field; particles keep their directions q, so they move smoothly (at most
/// 2π·1.5·ε₀/T ≈ 1.2 units/s). Deterministic for a seed.
pub fn oscillating_bubble(p: &SampleParams) -> PointCloud {
    let t = p.time as f64;
    let surfels = star_shaped(p.particles, p.seed, |q| radius_at(q, t));
    let field = ThicknessField::new(p.seed, Chart::sphere());
    to_cloud(&surfels, &field, p.time, |_, h| h)
}
