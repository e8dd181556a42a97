//! A wobbling, non-spherical bubble: r(q, t) = 1 + Σₖ aₖ(t)·P_lₖ(dₖ·q), a sum of seeded
//! zonal spherical harmonics of degree 2–4 about random axes dₖ (each one lies in the
//! degree-l harmonic space), with amplitudes aₖ(t) = Aₖ·(0.6·cos φₖ + sin(ωₖt + ψₖ)):
//! a lasting irregular shape plus a wobble. Amplitudes fall with the degree (A = 0.06, 0.035,
//! 0.02 for l = 2, 3, 4) and the angular frequencies rise as √((l−1)(l+1)(l+2)) like
//! Rayleigh's shape modes, slowed down so a 24 fps sequence shows them.

use super::rng::SplitMix64;
use super::surface::{SampleParams, star_shaped, to_cloud, zonal};
use super::thickness::{Chart, ThicknessField};
use crate::pointcloud::PointCloud;
use glam::DVec3;
use std::f64::consts::TAU;

/// One seeded harmonic: degree, axis, amplitude, static phase, angular frequency, phase.
#[derive(Debug, Clone, Copy)]
struct Mode {
    l: usize,
    axis: DVec3,
    amp: f64,
    rest: f64,
    omega: f64,
    phase: f64,
}

fn modes(seed: u64) -> Vec<Mode> {
    let mut g = SplitMix64::new(seed ^ 0x1AE6_B0B1);
    let mut out = Vec::new();
    for (l, amp) in [(2usize, 0.06), (3, 0.035), (4, 0.02)] {
        for _ in 0..3 {
            let z = g.range(-1.0, 1.0);
            let phi = g.range(0.0, TAU);
            let r = (1.0 - z * z).sqrt();
            let lf = l as f64;
            out.push(Mode {
                l,
                axis: DVec3::new(r * phi.cos(), r * phi.sin(), z),
                amp: amp / 3f64.sqrt(),
                rest: 0.6 * g.range(0.0, TAU).cos(),
                omega: 0.9 * ((lf - 1.0) * (lf + 1.0) * (lf + 2.0)).sqrt() * g.range(0.8, 1.2),
                phase: g.range(0.0, TAU),
            });
        }
    }
    out
}

/// Radius along unit `q` at `time` for the modes of `seed`, and its tangential gradient.
fn radius_at(modes: &[Mode], q: DVec3, time: f64) -> (f64, DVec3) {
    let mut r = 1.0;
    let mut grad = DVec3::ZERO;
    for m in modes {
        let a = m.amp * (m.rest + (m.omega * time + m.phase).sin());
        let (p, g) = zonal(m.l, m.axis, q);
        r += a * p;
        grad += g * a;
    }
    (r, grad)
}

/// The irregular bubble (mean radius ≈ 1, centre at the origin, y up) with the bubble's
/// thickness field. Radius stays within 1 ± 0.32 (|aₖ| ≤ 1.6·Aₖ/√3, |P_l| ≤ 1; typically
/// ± 0.1). Particles keep their
/// directions q, so they move smoothly in time. Deterministic for a seed.
pub fn irregular_bubble(p: &SampleParams) -> PointCloud {
    let modes = modes(p.seed);
    let t = p.time as f64;
    let surfels = star_shaped(p.particles, p.seed, |q| radius_at(&modes, q, t));
    let field = ThicknessField::new(p.seed, Chart::sphere());
    to_cloud(&surfels, &field, p.time, |_, h| h)
}
