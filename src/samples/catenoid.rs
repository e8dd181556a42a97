//! A soap film between two parallel coaxial rings being pulled apart: the catenoid
//! r(z) = a·cosh(z/a), |z| ≤ h/2, the minimal surface spanning rings of radius R = 1 at
//! z = ±h/2 (z up). `a` solves R = a·cosh(h/2a) on the stable (larger-a) branch, which exists
//! while h/R < 1.3255 (Goldschmidt's limit, x·tanh x = 1 at x = h/2a ≈ 1.1997). The
//! separation grows smoothly toward just below the limit: h(t) = h_max − (h_max − h₀)·e^(−t/τ).

use super::surface::{SampleParams, lat_long, revolution, to_cloud};
use super::thickness::{Chart, ThicknessField};
use crate::pointcloud::PointCloud;
use glam::DVec2;

/// Radius of the two rings the film spans, scene units (the film's scale).
pub const RING_RADIUS: f64 = 1.0;
/// Ring separation at time 0, in ring radii.
pub const H0: f64 = 0.5;
/// Separation approached as time goes on (the film would pop beyond 1.3255), ring radii.
pub const H_MAX: f64 = 1.25;
/// Time constant of the pulling, seconds.
pub const TAU_S: f64 = 3.0;
/// x = h/2a at Goldschmidt's limit: the root of x·tanh x = 1.
const X_LIMIT: f64 = 1.199_678_640_257_734;
/// Latitude (rad) of the thickness-field band the rings map to.
const LAT: f64 = 0.8;

/// Ring separation at `time` (s), in ring radii.
pub fn separation(time: f64) -> f64 {
    H_MAX - (H_MAX - H0) * (-time.max(0.0) / TAU_S).exp()
}

/// Height of the upper ring above the middle, scene units, at `time` (s): the rings sit at
/// y = ±[`ring_half_separation`], radius [`RING_RADIUS`], on the vertical y axis.
pub fn ring_half_separation(time: f64) -> f64 {
    0.5 * RING_RADIUS * separation(time)
}

/// The neck parameter a of the stable catenoid spanning unit rings `h` apart, or `None` if
/// h ≥ 1.3255 (no catenoid). Bisection on x = h/2a ∈ (0, x_limit], where cosh(x)/x = 2/h is
/// decreasing; 100 halvings, exact to f64.
pub fn neck(h: f64) -> Option<f64> {
    let target = 2.0 / h;
    if h.is_nan() || h <= 0.0 || X_LIMIT.cosh() / X_LIMIT > target {
        return None;
    }
    let (mut lo, mut hi) = (1e-12, X_LIMIT);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mid.cosh() / mid > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(h / (2.0 * 0.5 * (lo + hi)))
}

/// The catenoid film (unit rings on the vertical y axis at y = ±h/2, y up), with normals away
/// from the axis and the thickness field on a band of the field's sphere (latitude ±0.8 rad
/// from ring to ring). Deterministic for a seed; particles move smoothly with `time`.
pub fn catenoid(p: &SampleParams) -> PointCloud {
    let h = separation(p.time as f64);
    let a = neck(h).expect("separation stays below Goldschmidt's limit");
    let profile = |u: f64| {
        let z = h * (0.5 - u);
        DVec2::new(a * (z / a).cosh(), z)
    };
    let chart = |u: f64, lon: f64| lat_long(lon, LAT * (1.0 - 2.0 * u));
    let surfels = revolution(p.particles, p.seed, profile, chart);
    let field = ThicknessField::new(
        p.seed,
        Chart {
            top: LAT.sin(),
            bottom: -LAT.sin(),
            patch_pole: lat_long(0.0, 0.55),
            patch_tilt: 0.5,
            scale: 0.7,
            ..Chart::sphere()
        },
    );
    to_cloud(&surfels, &field, p.time, |_, h| h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neck_solves_the_ring_condition_on_the_stable_branch() {
        for h in [0.1, 0.5, 1.0, 1.25, 1.32] {
            let a = neck(h).unwrap();
            assert!((a * (h / (2.0 * a)).cosh() - 1.0).abs() < 1e-12, "h {h}");
            assert!(h / (2.0 * a) <= X_LIMIT + 1e-12);
        }
        assert!((X_LIMIT * X_LIMIT.tanh() - 1.0).abs() < 1e-14);
        assert!(neck(1.33).is_none() && neck(0.0).is_none());
        // Small separations: a nearly flat cylinder (a → R).
        assert!((neck(0.01).unwrap() - 1.0).abs() < 1e-4);
    }
}
