//! What the motion-blur tests share: a moving square film and how far an edge is smeared.

#![allow(dead_code)]

use std::path::Path;

/// Writes a square film, 1 × 1 in the plane z = 0, of disks 0.05 apart (radius 0.04, 400 nm),
/// all moving at `velocity` (scene units per second), as an ASCII PLY at `path`.
pub fn square(path: &Path, velocity: [&str; 3]) {
    let mut rows = Vec::new();
    for i in 0..=20 {
        for j in 0..=20 {
            let (x, y) = (-0.5 + 0.05 * i as f32, -0.5 + 0.05 * j as f32);
            let [vx, vy, vz] = velocity;
            rows.push(format!("{x} {y} 0 0 0 1 0.04 400 {vx} {vy} {vz}"));
        }
    }
    let head = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\n\
         property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property float radius\nproperty float thickness\nproperty float velocity_x\n\
         property float velocity_y\nproperty float velocity_z\nend_header\n",
        rows.len()
    );
    std::fs::write(path, head + &rows.join("\n") + "\n").unwrap();
}

/// Pixels partly covered (a smeared edge) along a line of alpha, and the line's centre of
/// coverage.
pub fn smear(line: &[f32]) -> (usize, f32) {
    let partial = line.iter().filter(|a| **a > 0.02 && **a < 0.98).count();
    let total: f32 = line.iter().sum();
    let centre = line
        .iter()
        .enumerate()
        .map(|(i, a)| i as f32 * a)
        .sum::<f32>()
        / total;
    (partial, centre)
}
