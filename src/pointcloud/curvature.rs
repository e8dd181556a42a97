//! Per-particle curvature for curvature-aware ("Phong") splats.
//!
//! A flat disk has one normal everywhere, so a curved film drawn with disks is faceted: its
//! reflections show an orange-peel texture at the scale of the splats, however well the
//! overlapping disks are blended. Phong splatting (Botsch, Spernat & Kobbelt 2004) lets each
//! splat's normal vary linearly across it. We keep one number per particle: the normal
//! curvature κ in `n(p) ≈ normalize(n_i + κ_i · (p − c_i))`, the least-squares fit of
//! `n_j − n_i ≈ κ (c_j − c_i)_tangential` over the k nearest neighbours. It is exact for spheres
//! (κ = 1/R with outward normals, −1/R with inward ones) and planes (κ = 0), and the isotropic
//! (mean) part of the curvature elsewhere.

use super::knn::{KnnTable, PointIndex};
use glam::Vec3;
use rayon::prelude::*;

/// Normal curvature per particle, 1/scene units, from `normals` (unit) and a kNN table of the
/// same positions. Neighbours whose normal is more than 60° away are ignored (another sheet);
/// a particle with no usable neighbour gets 0. Cost: O(n·k), parallel.
pub fn curvature_from_table(positions: &[Vec3], normals: &[Vec3], table: &KnnTable) -> Vec<f32> {
    (0..positions.len())
        .into_par_iter()
        .map(|i| curvature_at(positions, normals, i, table.row(i)))
        .collect()
}

/// Gradient of an attribute (e.g. film thickness) in each particle's tangent plane, by least
/// squares over the k nearest neighbours on the same sheet (normals within 60°):
/// `a_j − a_i ≈ g · (c_j − c_i)` with `g ⟂ n_i`. Splats that carry `a_i + g_i·(p − c_i)`
/// instead of a constant reproduce linear fields exactly when blended, where a weighted mean
/// of constants (Shepard interpolation) leaves bumps at every splat centre — visible as a fine
/// texture wherever colour changes fast with thickness. Degenerate neighbourhoods get 0.
///
/// `radii` (scene units, one a particle; empty for none) limits each gradient so that across
/// its splat, within `radii[i]` of the particle, `a_i + g·(p − c_i)` stays inside the range of
/// the values of i and its neighbours (the slope limiter of Barth & Jespersen 1989): the
/// detail interpolates between the particles, never extrapolates past them (at an open edge,
/// a local extremum or a jump the gradient is flattened just enough).
pub fn gradient_from_table(
    positions: &[Vec3],
    normals: &[Vec3],
    values: &[f32],
    radii: &[f32],
    table: &KnnTable,
) -> Vec<Vec3> {
    (0..positions.len())
        .into_par_iter()
        .map(|i| {
            let g = gradient_at(positions, normals, values, i, table.row(i));
            limit(g, normals, values, radii.get(i), i, table.row(i))
        })
        .collect()
}

/// `g`, the gradient of `values` at particle `i`, scaled down so that within `reach` of i the
/// linear extension stays inside the range of i's value and its neighbours' in `row` on its
/// sheet (normals within 60°; all of `g` when `reach` is `None`).
fn limit(
    g: Vec3,
    normals: &[Vec3],
    values: &[f32],
    reach: Option<&f32>,
    i: usize,
    row: impl Iterator<Item = (u32, f32)>,
) -> Vec3 {
    let Some(&reach) = reach else {
        return g;
    };
    let vi = values[i];
    let ni = normals[i];
    let (lo, hi) = row
        .filter(|(j, _)| normals[*j as usize].dot(ni).abs() >= 0.5)
        .fold((vi, vi), |(lo, hi), (j, _)| {
            let v = values[j as usize];
            (lo.min(v), hi.max(v))
        });
    let span = g.length() * reach;
    if span.is_nan() || span <= 0.0 {
        return g;
    }
    let room = (hi - vi).min(vi - lo).max(0.0);
    if room >= span { g } else { g * (room / span) }
}

/// Rows of neighbour table built at a time by [`first_order_detail`]: 64k rows of k = 12 take
/// 6 MB, where a whole table of 10M particles would take 960 MB.
const DETAIL_CHUNK: usize = 1 << 16;

/// Curvature ([`curvature_from_table`]) and gradient of `values` ([`gradient_from_table`]) of
/// every particle over its `k` nearest neighbours, without ever holding the whole neighbour
/// table: it is built and used a slice of particles at a time. Same results as the two table
/// functions (the gradient limited to `radii` as there); peak memory is the k-d tree (~16
/// bytes a particle) plus the two outputs.
pub fn first_order_detail(
    positions: &[Vec3],
    normals: &[Vec3],
    values: &[f32],
    radii: &[f32],
    k: usize,
) -> (Vec<f32>, Vec<Vec3>) {
    detail_in_chunks(positions, normals, values, radii, k, DETAIL_CHUNK)
}

fn detail_in_chunks(
    positions: &[Vec3],
    normals: &[Vec3],
    values: &[f32],
    radii: &[f32],
    k: usize,
    chunk: usize,
) -> (Vec<f32>, Vec<Vec3>) {
    let n = positions.len();
    let index = PointIndex::build(positions);
    let (mut curvature, mut gradient) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for start in (0..n).step_by(chunk.max(1)) {
        let rows = start..(start + chunk.max(1)).min(n);
        let table = KnnTable::build_rows(&index, positions, k, rows.clone());
        curvature.par_extend(
            rows.clone()
                .into_par_iter()
                .map(|i| curvature_at(positions, normals, i, table.row(i - start))),
        );
        gradient.par_extend(rows.into_par_iter().map(|i| {
            let g = gradient_at(positions, normals, values, i, table.row(i - start));
            limit(g, normals, values, radii.get(i), i, table.row(i - start))
        }));
    }
    (curvature, gradient)
}

/// Curvature of particle `i` over its neighbour `row` (see [`curvature_from_table`]).
fn curvature_at(
    positions: &[Vec3],
    normals: &[Vec3],
    i: usize,
    row: impl Iterator<Item = (u32, f32)>,
) -> f32 {
    let (ci, ni) = (positions[i], normals[i]);
    let (mut num, mut den) = (0.0f32, 0.0f32);
    for (j, _) in row {
        let nj = normals[j as usize];
        let c = nj.dot(ni);
        if c.abs() < 0.5 {
            continue;
        }
        let nj = if c < 0.0 { -nj } else { nj };
        let d = positions[j as usize] - ci;
        let dt = d - d.dot(ni) * ni;
        num += (nj - ni).dot(dt);
        den += dt.length_squared();
    }
    if den > 0.0 && num.is_finite() {
        num / den
    } else {
        0.0
    }
}

/// Gradient of `values` at particle `i` over its neighbour `row` (see [`gradient_from_table`]).
fn gradient_at(
    positions: &[Vec3],
    normals: &[Vec3],
    values: &[f32],
    i: usize,
    row: impl Iterator<Item = (u32, f32)>,
) -> Vec3 {
    let (ci, ni) = (positions[i], normals[i]);
    let (t1, t2) = ni.any_orthonormal_pair();
    let (mut saa, mut sab, mut sbb, mut sa, mut sb) = (0.0f32, 0.0, 0.0, 0.0, 0.0);
    for (j, _) in row {
        let j = j as usize;
        if normals[j].dot(ni).abs() < 0.5 {
            continue;
        }
        let d = positions[j] - ci;
        let (a, b) = (d.dot(t1), d.dot(t2));
        let dv = values[j] - values[i];
        saa += a * a;
        sab += a * b;
        sbb += b * b;
        sa += a * dv;
        sb += b * dv;
    }
    let det = saa * sbb - sab * sab;
    // Degenerate (collinear or too few neighbours), or NaN.
    if det.is_nan() || det <= 1e-12 * (saa + sbb) * (saa + sbb) {
        return Vec3::ZERO;
    }
    let ga = (sa * sbb - sb * sab) / det;
    let gb = (sb * saa - sa * sab) / det;
    let g = ga * t1 + gb * t2;
    if g.is_finite() { g } else { Vec3::ZERO }
}

/// Normal curvature per particle; builds its own kNN table (k neighbours, 8–16 is right).
pub fn estimate_curvature(positions: &[Vec3], normals: &[Vec3], k: usize) -> Vec<f32> {
    let table = KnnTable::build(positions, k.max(2));
    curvature_from_table(positions, normals, &table)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fibonacci(n: usize, r: f32) -> Vec<Vec3> {
        let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
        (0..n)
            .map(|i| {
                let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
                let s = (1.0 - y * y).sqrt();
                let a = golden * i as f32;
                Vec3::new(s * a.cos(), y, s * a.sin()) * r
            })
            .collect()
    }

    /// The chunked one-pass detail equals the two whole-table functions, across chunk
    /// boundaries (chunks of 700 rows, a last partial one, and one chunk for everything).
    #[test]
    fn chunked_detail_matches_the_table_functions() {
        let p = fibonacci(5000, 1.5);
        let n: Vec<Vec3> = p.iter().map(|q| q.normalize()).collect();
        let h: Vec<f32> = p
            .iter()
            .map(|q| 400.0 + 80.0 * q.y + 30.0 * q.x * q.z)
            .collect();
        let table = KnnTable::build(&p, 12);
        let want = (
            curvature_from_table(&p, &n, &table),
            gradient_from_table(&p, &n, &h, &[], &table),
        );
        for chunk in [700, 5000, DETAIL_CHUNK] {
            let got = detail_in_chunks(&p, &n, &h, &[], 12, chunk);
            assert_eq!(got, want, "chunk {chunk}");
        }
        assert!(want.0.iter().all(|k| (k - 1.0 / 1.5).abs() < 0.02));
        assert!(want.1.iter().any(|g| g.length() > 10.0));
    }

    #[test]
    fn sphere_curvature_is_one_over_radius_and_its_sign_follows_the_normals() {
        let p = fibonacci(4000, 2.0);
        let out: Vec<Vec3> = p.iter().map(|q| q.normalize()).collect();
        let k = estimate_curvature(&p, &out, 12);
        for v in &k {
            assert!((v - 0.5).abs() < 0.02, "{v}");
        }
        let inward: Vec<Vec3> = out.iter().map(|n| -*n).collect();
        let k = estimate_curvature(&p, &inward, 12);
        assert!(k.iter().all(|v| (v + 0.5).abs() < 0.02));
    }

    /// 900 points of the plane y = 0: a 30 × 30 grid of spacing 0.1, rows shifted in z by
    /// `jitter` × (index mod 7) so the neighbourhoods are not all alike.
    fn plane_grid(jitter: f32) -> Vec<Vec3> {
        (0..900)
            .map(|i| {
                Vec3::new(
                    (i % 30) as f32 * 0.1,
                    0.0,
                    (i / 30) as f32 * 0.1 + jitter * (i % 7) as f32,
                )
            })
            .collect()
    }

    #[test]
    fn gradients_of_linear_fields_are_exact() {
        let p = fibonacci(3000, 1.0);
        let n: Vec<Vec3> = p.iter().map(|q| q.normalize()).collect();
        // On a plane: a = 3x − 2z exactly.
        let plane = plane_grid(0.013);
        let a: Vec<f32> = plane.iter().map(|q| 3.0 * q.x - 2.0 * q.z).collect();
        let table = KnnTable::build(&plane, 8);
        for g in gradient_from_table(&plane, &vec![Vec3::Y; 900], &a, &[], &table) {
            assert!((g - Vec3::new(3.0, 0.0, -2.0)).length() < 1e-3, "{g}");
        }
        // On a sphere, a = y: the tangential gradient is e_y minus its normal part.
        let a: Vec<f32> = p.iter().map(|q| q.y).collect();
        let table = KnnTable::build(&p, 12);
        let g = gradient_from_table(&p, &n, &a, &[], &table);
        for (gi, ni) in g.iter().zip(&n) {
            let want = Vec3::Y - ni.y * *ni;
            assert!((*gi - want).length() < 0.05, "{gi} vs {want}");
        }
    }

    #[test]
    fn limited_gradients_stay_within_the_neighbours_values() {
        // A linear field on a plane grid: inside, the limited gradient is the exact one; at
        // the grid's edges, where a disk of radius 0.6 spacings extrapolates past the last
        // row, it is flattened so no disk shows a value the particles do not hold.
        let plane = plane_grid(0.0);
        let a: Vec<f32> = plane.iter().map(|q| 100.0 + 300.0 * q.x).collect();
        let table = KnnTable::build(&plane, 12);
        let normals = vec![Vec3::Y; 900];
        let radii = vec![0.06; 900];
        let free = gradient_from_table(&plane, &normals, &a, &[], &table);
        let held = gradient_from_table(&plane, &normals, &a, &radii, &table);
        let (lo, hi) = (100.0, 100.0 + 300.0 * 2.9);
        let reach = |g: &[Vec3]| {
            g.iter()
                .zip(&a)
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), (g, v)| {
                    let s = g.length() * 0.06;
                    (l.min(v - s), h.max(v + s))
                })
        };
        let (l, h) = reach(&free);
        assert!(l < lo - 10.0 && h > hi + 10.0, "unlimited: {l}..{h}");
        let (l, h) = reach(&held);
        assert!(l >= lo - 1e-3 && h <= hi + 1e-3, "limited: {l}..{h}");
        let inside = (0..900).filter(|i| (2..28).contains(&(i % 30)));
        for i in inside {
            assert!(
                (held[i] - Vec3::new(300.0, 0.0, 0.0)).length() < 1e-2,
                "{}",
                held[i]
            );
        }
    }

    #[test]
    fn a_plane_is_flat() {
        let p = plane_grid(0.01);
        let k = estimate_curvature(&p, &vec![Vec3::Y; p.len()], 8);
        assert!(k.iter().all(|v| v.abs() < 1e-5));
    }
}
