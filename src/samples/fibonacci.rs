//! Fibonacci (golden-angle) lattice on a sphere: near-uniform, near-hexagonal sampling.

use glam::{DVec3, Vec3};

/// `n` points on the sphere of `radius` about the origin: point i at height
/// z = 1 − (2i + 1)/n (equal-area bands) and longitude i·π(3 − √5). Each point covers an area
/// 4πR²/n; neighbours are ≈ [`fibonacci_spacing`] apart. Computed in f64. Cost: O(n).
pub fn fibonacci_sphere(n: usize, radius: f32) -> Vec<Vec3> {
    (0..n)
        .map(|i| fibonacci_point(i, n).as_vec3() * radius)
        .collect()
}

/// Unit-sphere point `i` of an `n`-point Fibonacci lattice, see [`fibonacci_sphere`].
pub fn fibonacci_point(i: usize, n: usize) -> DVec3 {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let z = 1.0 - (2 * i + 1) as f64 / n as f64;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = golden * i as f64;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Nearest-neighbour spacing of a hexagonal lattice with the Fibonacci lattice's density on
/// a sphere of `radius`: d = √(2A/√3) with A = 4πR²/n.
pub fn fibonacci_spacing(n: usize, radius: f32) -> f32 {
    let area = 4.0 * std::f64::consts::PI * (radius as f64).powi(2) / n.max(1) as f64;
    (2.0 * area / 3f64.sqrt()).sqrt() as f32
}
