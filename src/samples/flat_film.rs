//! Flat soap films in wire frames: `square_film` (a 2 × 2 square) and `circle_film` (a unit
//! disk), standing vertically in the plane z = 0 (y up) and facing +z. Both bulge gently in
//! their fundamental membrane mode, a lasting push (a draught) plus a slow oscillation:
//! b(t) = B·(0.5 + sin(2πt/T)), with the mode cos(πx/2)·cos(πy/2) for the square and
//! J₀(j₀₁·r) (j₀₁ ≈ 2.405, J₀'s first zero) for the disk, so the rim stays in the frame.
//! The film drains top to bottom: vivid thin bands and black patches at the top, thick at
//! the bottom, stirred by vortices in the film's plane.

use super::rng::SplitMix64;
use super::surface::{SPLAT_FRACTION, SampleParams, Surfel, lat_long, revolution, to_cloud};
use super::thickness::{Chart, ThicknessField};
use crate::pointcloud::PointCloud;
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::f64::consts::{FRAC_PI_2, TAU};

/// Half the side of the square film and the radius of the circular one, scene units: the
/// frames are the square |x|, |y| ≤ HALF_SIZE and the circle r = HALF_SIZE in the plane z = 0.
pub const HALF_SIZE: f64 = 1.0;
/// Bulge amplitude B, scene units (film half-width 1).
pub const BULGE: f64 = 0.05;
/// Period of the bulge oscillation, seconds.
pub const PERIOD_S: f64 = 3.0;
/// First zero of the Bessel function J₀.
const J01: f64 = 2.404_825_557_695_773;
/// Film (x, z) ↦ the field's sphere: longitude K·x, latitude K·z (rad).
const K: f64 = 0.75;

fn bulge(time: f64) -> f64 {
    BULGE * (0.5 + (TAU * time / PERIOD_S).sin())
}

/// The thickness-field chart of a film spanning x, z ∈ [−1, 1] mapped by [`lat_long`].
fn film_chart() -> Chart {
    Chart {
        top: K.sin(),
        bottom: -K.sin(),
        axis: -DVec3::Y,
        angle: 1.5 * K,
        patch_pole: lat_long(0.0, 0.8 * K),
        patch_tilt: 0.35,
        scale: 0.6,
        h_bottom_nm: 800.0,
        ..Chart::sphere()
    }
}

/// Bessel J₀(x) and J₀′(x) = −J₁(x) by their power series (|x| ≤ 3: error < 1e-12).
fn bessel_j0(x: f64) -> (f64, f64) {
    let (mut j0, mut j1) = (0.0, 0.0);
    let q = 0.25 * x * x;
    let mut term = 1.0; // (−q)^k / (k!)²
    for k in 0..20 {
        j0 += term;
        // J₁(x) = Σ (−1)^k (x/2)^(2k+1) / (k!(k+1)!)
        j1 += term * 0.5 * x / (k as f64 + 1.0);
        term *= -q / ((k as f64 + 1.0) * (k as f64 + 1.0));
    }
    (j0, -j1)
}

/// A square film: x, y ∈ [−1, 1] in the plane z = w(x, y) (y up), normals toward +z.
/// Particles: the rank-1 Fibonacci lattice of the square ((i + ½)/n, frac(i/φ)), jittered by
/// up to 15 % of the spacing d = √(8/(√3·n)) and kept inside the frame; radius 0.9·d.
/// Deterministic for a seed.
pub fn square_film(p: &SampleParams) -> PointCloud {
    let n = p.particles;
    let b = bulge(p.time as f64);
    let d = (8.0 / (3f64.sqrt() * n.max(1) as f64)).sqrt();
    let inv_phi = 0.5 * (5f64.sqrt() - 1.0);
    let surfels: Vec<Surfel> = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut g = SplitMix64::for_item(p.seed, i as u64);
            let u = (i as f64 + 0.5) / n as f64;
            let v = (i as f64 * inv_phi + 0.5).fract();
            let x = (2.0 * u - 1.0 + 0.15 * d * g.range(-1.0, 1.0)).clamp(-1.0, 1.0);
            let z = (2.0 * v - 1.0 + 0.15 * d * g.range(-1.0, 1.0)).clamp(-1.0, 1.0);
            let (cx, sx) = ((FRAC_PI_2 * x).cos(), (FRAC_PI_2 * x).sin());
            let (cz, sz) = ((FRAC_PI_2 * z).cos(), (FRAC_PI_2 * z).sin());
            // Field frame: the film is y = −b·cos·cos, bulging toward −y (the viewer).
            let y = -b * cx * cz;
            let (fx, fz) = (b * FRAC_PI_2 * sx * cz, b * FRAC_PI_2 * cx * sz);
            Surfel {
                position: DVec3::new(x, y, z),
                normal: DVec3::new(fx, -1.0, fz).normalize(),
                radius: SPLAT_FRACTION * d,
                chart: lat_long(K * x, K * z),
            }
        })
        .collect();
    to_cloud(
        &surfels,
        &ThicknessField::new(p.seed, film_chart()),
        p.time,
        |_, h| h,
    )
}

/// A circular film: the unit disk in the plane z = w(r) (y up), normals toward +z; sampled as
/// a surface of revolution about its normal (Vogel's sunflower spiral). Deterministic for a
/// seed.
pub fn circle_film(p: &SampleParams) -> PointCloud {
    let b = bulge(p.time as f64);
    let profile = |u: f64| DVec2::new(u, b * bessel_j0(J01 * u).0);
    // Revolution frame (axis = film normal) → field frame: x stays, axis → −y, y → z.
    let turn = |v: DVec3| DVec3::new(v.x, -v.z, v.y);
    let chart = |u: f64, lon: f64| lat_long(K * u * lon.cos(), K * u * lon.sin());
    let mut surfels = revolution(p.particles, p.seed, profile, chart);
    for s in &mut surfels {
        s.position = turn(s.position);
        s.normal = turn(s.normal);
    }
    to_cloud(
        &surfels,
        &ThicknessField::new(p.seed, film_chart()),
        p.time,
        |_, h| h,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bessel_j0_zero_and_derivative() {
        assert!(bessel_j0(J01).0.abs() < 1e-12);
        assert!((bessel_j0(0.0).0 - 1.0).abs() < 1e-15);
        // J₀(1) = 0.7651976865579666, J₁(1) = 0.4400505857449335 (Abramowitz & Stegun).
        let (j0, dj0) = bessel_j0(1.0);
        assert!((j0 - 0.765_197_686_557_966_6).abs() < 1e-13);
        assert!((dj0 + 0.440_050_585_744_933_5).abs() < 1e-13);
    }
}
