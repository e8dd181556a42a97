//! Importance sampling of the environment for light sampling at props: a piecewise-constant
//! density over a lat-long grid, proportional to the environment's brightness (averaged over
//! 2×2 points per cell) times the cell's solid angle, with a floor so every direction keeps
//! some density. Works for every [`Environment`] kind; built once per render, only when the
//! scene has props.

use super::environment::Environment;
use glam::Vec3;
use std::f32::consts::{PI, TAU};

const W: usize = 128;
const H: usize = 64;

/// The environment's sampling distribution.
#[derive(Debug, Clone)]
pub struct EnvSampler {
    /// Row CDF (H + 1 entries).
    rows: Vec<f32>,
    /// Per-row column CDFs (H × (W + 1)).
    cols: Vec<f32>,
    /// Probability of each cell.
    cell: Vec<f32>,
}

/// Direction of lat-long coordinates (u, v) ∈ [0, 1]², v = 0 straight up.
fn direction(u: f32, v: f32) -> Vec3 {
    let (theta, phi) = (v * PI, (u - 0.5) * TAU);
    let s = theta.sin();
    Vec3::new(s * phi.sin(), theta.cos(), -s * phi.cos())
}

fn luminance(c: Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

fn cdf(weights: &[f32]) -> Vec<f32> {
    let mut out = Vec::with_capacity(weights.len() + 1);
    let mut s = 0.0;
    out.push(0.0);
    for w in weights {
        s += w;
        out.push(s);
    }
    let total = s.max(1e-30);
    out.iter_mut().for_each(|v| *v /= total);
    out
}

/// Index i with cdf[i] <= u < cdf[i+1], and the position within that bin.
fn invert(cdf: &[f32], u: f32) -> (usize, f32) {
    let i = cdf.partition_point(|&c| c <= u).clamp(1, cdf.len() - 1) - 1;
    let w = cdf[i + 1] - cdf[i];
    let f = if w > 0.0 { (u - cdf[i]) / w } else { 0.5 };
    (i, f.clamp(0.0, 0.999_999))
}

impl EnvSampler {
    /// The distribution for `env`.
    pub fn new(env: &Environment) -> Self {
        let mut weight = vec![0.0f32; W * H];
        for y in 0..H {
            let sin = ((y as f32 + 0.5) / H as f32 * PI).sin();
            for x in 0..W {
                let mut l = 0.0;
                for (a, b) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
                    let d = direction((x as f32 + a) / W as f32, (y as f32 + b) / H as f32);
                    l += luminance(env.radiance(d)).max(0.0);
                }
                weight[y * W + x] = 0.25 * l * sin;
            }
        }
        // Floor: 1% of the mean, spread like the solid angle, so no direction has density 0.
        let mean = weight.iter().sum::<f32>() / (W * H) as f32;
        for y in 0..H {
            let sin = ((y as f32 + 0.5) / H as f32 * PI).sin();
            for x in 0..W {
                weight[y * W + x] += (0.01 * mean).max(1e-12) * sin;
            }
        }
        let total: f32 = weight.iter().sum();
        let cell: Vec<f32> = weight.iter().map(|w| w / total).collect();
        let row_sums: Vec<f32> = (0..H)
            .map(|y| cell[y * W..(y + 1) * W].iter().sum())
            .collect();
        let rows = cdf(&row_sums);
        let cols = (0..H)
            .flat_map(|y| cdf(&cell[y * W..(y + 1) * W]))
            .collect();
        EnvSampler { rows, cols, cell }
    }

    /// A direction and its solid-angle density.
    pub fn sample(&self, u: (f32, f32)) -> (Vec3, f32) {
        let (y, fy) = invert(&self.rows, u.0);
        let (x, fx) = invert(&self.cols[y * (W + 1)..(y + 1) * (W + 1)], u.1);
        let (su, sv) = ((x as f32 + fx) / W as f32, (y as f32 + fy) / H as f32);
        let d = direction(su, sv);
        (d, self.density(x, y, sv))
    }

    fn density(&self, x: usize, y: usize, v: f32) -> f32 {
        let sin = (v * PI).sin().max(1e-6);
        self.cell[y * W + x] * (W * H) as f32 / (TAU * PI * sin)
    }

    /// Solid-angle density of `dir` (unit).
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let v = dir.y.clamp(-1.0, 1.0).acos() / PI;
        let u = (dir.x.atan2(-dir.z) / TAU + 0.5).rem_euclid(1.0);
        let x = ((u * W as f32) as usize).min(W - 1);
        let y = ((v * H as f32) as usize).min(H - 1);
        self.density(x, y, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Studio;
    use crate::render::sampler::Pcg32;

    /// E[L/pdf] over sampled directions equals the environment's total power estimated by
    /// uniform directions, and `pdf` agrees with the density `sample` reports.
    #[test]
    fn sampled_estimate_matches_uniform_estimate() {
        let env = Environment::Studio(Studio::default());
        let s = EnvSampler::new(&env);
        let mut rng = Pcg32::new(9, 9);
        let n = 200_000;
        let (mut a, mut b) = (0.0f64, 0.0f64);
        let mut mismatched = 0;
        for _ in 0..n {
            let (d, pdf) = s.sample((rng.next_f32(), rng.next_f32()));
            // Rounding can move a direction on a cell border into the neighbour cell.
            if (s.pdf(d) - pdf).abs() > 1e-3 * pdf {
                mismatched += 1;
            }
            a += (luminance(env.radiance(d)) / pdf) as f64;
            let z = 1.0 - 2.0 * rng.next_f32();
            let r = (1.0 - z * z).sqrt();
            let phi = TAU * rng.next_f32();
            b += (luminance(env.radiance(Vec3::new(r * phi.cos(), z, r * phi.sin()))) * 2.0 * TAU)
                as f64;
        }
        let (a, b) = (a / n as f64, b / n as f64);
        assert!(mismatched < n / 1000, "{mismatched} densities disagree");
        assert!((a - b).abs() < 0.03 * b, "{a} vs {b}");
    }
}
