//! Estimated and generated splat radii leave no hole in a sphere.
//!
//! Oracle: a ray from the sphere's centre through a random direction q̂ must cross at least one
//! splat disk (centre pⱼ, normal nⱼ, radius rⱼ) — exactly what a renderer's ray meets.

use filmsplat::pointcloud::PointCloud;
use filmsplat::pointcloud::estimate::{EstimateOptions, estimate_radii};
use filmsplat::pointcloud::knn::PointIndex;
use filmsplat::samples::rng::SplitMix64;
use filmsplat::samples::{BubbleParams, bubble, fibonacci_spacing, fibonacci_sphere};
use glam::Vec3;

/// Fraction of `samples` random rays from the origin that miss every disk.
fn hole_fraction(pos: &[Vec3], normals: &[Vec3], radius: &[f32], samples: usize, seed: u64) -> f64 {
    let index = PointIndex::build(pos);
    let sphere_r = pos[0].length();
    let mut g = SplitMix64::new(seed);
    let mut misses = 0;
    for _ in 0..samples {
        let z = g.range(-1.0, 1.0);
        let phi = g.range(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        let dir = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32);
        let near = index.nearest_excluding(dir * sphere_r, 24, u32::MAX);
        let hit = near.iter().any(|&(j, _)| {
            let (p, n) = (pos[j as usize], normals[j as usize]);
            let denom = n.dot(dir);
            if denom.abs() < 1e-6 {
                return false;
            }
            let x = dir * (n.dot(p) / denom);
            x.distance(p) < radius[j as usize]
        });
        misses += usize::from(!hit);
    }
    misses as f64 / samples as f64
}

#[test]
fn estimated_radii_cover_a_jittered_fibonacci_sphere() {
    let n = 20_000;
    let mut g = SplitMix64::new(11);
    // Fibonacci lattice with a ±0.2·d jitter per axis, re-projected.
    let d = fibonacci_spacing(n, 1.0);
    let pos: Vec<Vec3> = fibonacci_sphere(n, 1.0)
        .into_iter()
        .map(|p| {
            let j = Vec3::new(
                g.range(-1.0, 1.0) as f32,
                g.range(-1.0, 1.0) as f32,
                g.range(-1.0, 1.0) as f32,
            );
            (p + j * 0.2 * d).normalize()
        })
        .collect();
    let normals: Vec<Vec3> = pos.clone();
    let o = EstimateOptions::default();
    let radius = estimate_radii(&pos, o.k_radius, o.radius_scale);
    assert_eq!(hole_fraction(&pos, &normals, &radius, 200_000, 1), 0.0);
    // Not trivially hole-free by being huge: radii stay near the spacing.
    let mean = radius.iter().sum::<f32>() / n as f32 / d;
    let max = radius.iter().copied().fold(0.0, f32::max) / d;
    assert!(
        (0.8..1.05).contains(&mean) && max < 1.6,
        "mean {mean}·d, max {max}·d"
    );
    // And the oracle can fail: half the radius leaves holes.
    let small: Vec<f32> = radius.iter().map(|r| r * 0.5).collect();
    assert!(hole_fraction(&pos, &normals, &small, 20_000, 2) > 0.01);
}

#[test]
fn estimated_radii_cover_the_exact_lattice() {
    let pos = fibonacci_sphere(30_000, 3.0);
    let o = EstimateOptions::default();
    let radius = estimate_radii(&pos, o.k_radius, o.radius_scale);
    let normals: Vec<Vec3> = pos.iter().map(|p| p.normalize()).collect();
    assert_eq!(hole_fraction(&pos, &normals, &radius, 200_000, 3), 0.0);
}

#[test]
fn bubble_radii_cover_the_bubble() {
    let cloud: PointCloud = bubble(&BubbleParams {
        particles: 20_000,
        radius: 2.0,
        time: 0.0,
        seed: 4,
    });
    let normals = cloud.normals.as_ref().unwrap();
    let radius = cloud.radius.as_ref().unwrap();
    assert_eq!(
        hole_fraction(&cloud.positions, normals, radius, 200_000, 5),
        0.0
    );
}
