//! Splat radii fitted to the sampling: grown where the disks would leave a pinhole between
//! particles that sample the surface, trimmed where the surface ends.
//!
//! For each particle i the neighbours of its kNN row that lie on its sheet (normals within
//! 60°, not farther off its tangent plane than along it) are projected onto i's tangent plane
//! and sorted by angle. Each pair of angularly consecutive neighbours (a, b) spans a fan
//! triangle (i, a, b), unless the angle between them exceeds [`OPEN_ANGLE_DEG`] or a side is
//! longer than [`LONG_EDGE`] × the cloud's median spacing: that side of i is open (a free
//! edge, the rim of a hole, a rupture front, a film torn into sparse fragments), and i is an
//! edge particle.
//!
//! - **Gaps.** The point of a fan triangle farthest from its corners is its circumcentre c
//!   (for an obtuse angle at i, the midpoint of the side facing i). If no other neighbour is
//!   nearer to c than i is, only the disks of i, a and b can cover it, so i's radius grows to
//!   [`GAP_MARGIN`] × |c − i| (capped at [`MAX_GROWTH`] × the median radius). A surface
//!   sampled without gaps then renders without pinholes, whatever the sampling (hexagonal,
//!   jittered, anisotropic, random).
//! - **Edges.** An edge particle's disk is shrunk to what its fan triangles need, and at least
//!   [`EDGE_REACH`] × its spacing (the mean distance to its three nearest sheet neighbours),
//!   but never above its previous radius nor the cloud's median radius: a rim
//!   ends about half a spacing beyond its last particles instead of bulging by a whole
//!   (inflated) spacing.
//! - **Isolated** particles (fewer than two neighbours on their sheet) keep at most
//!   [`EDGE_REACH`] × the distance to their nearest neighbour, and at most the median radius.
//!
//! Cost: O(n·k log k) over an existing k-nearest-neighbour table (k = 12), parallel.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::estimate::median_positive;
use super::knn::{KnnTable, PointIndex};

/// Largest angle (degrees) between consecutive neighbours around a particle that still counts
/// as sampled surface; a wider one is an open side.
pub const OPEN_ANGLE_DEG: f32 = 120.0;

/// Longest side of a fan triangle, as a multiple of the cloud's median nearest-neighbour
/// distance; a longer one spans a hole, not a sampling gap.
pub const LONG_EDGE: f32 = 3.0;

/// Factor on the distance to a gap's centre a disk grows to (its blending weight there is then
/// (1 − 1/1.15²)² ≈ 0.06, not zero).
pub const GAP_MARGIN: f32 = 1.15;

/// How far beyond an edge particle its disk reaches, as a multiple of its spacing.
pub const EDGE_REACH: f32 = 0.6;

/// Most a radius grows, as a multiple of the median radius.
pub const MAX_GROWTH: f32 = 2.5;

/// What [`fit_radii`] changed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GapReport {
    /// Radii grown to close a gap.
    pub grown: usize,
    /// Edge particles whose disks were trimmed.
    pub trimmed: usize,
    /// Particles on an open edge (trimmed or not).
    pub edge: usize,
}

impl std::fmt::Display for GapReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "splat radii fitted to the sampling: {} grown to close gaps, {} of {} edge particles trimmed",
            self.grown, self.trimmed, self.edge
        )
    }
}

/// What one particle's fan says.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fit {
    /// Interior: grow to at least this radius (0: nothing to close).
    Interior(f32),
    /// On an open edge: this radius (already bounded).
    Edge(f32),
    /// No sheet neighbours: at most this radius.
    Isolated(f32),
}

/// Neighbours a fan is built from.
pub const FAN_NEIGHBOURS: usize = 12;

/// Rows of neighbours searched at a time when no table is given (12 neighbours × 8 bytes ×
/// 64k rows ≈ 6 MiB), so no whole table is held.
const CHUNK: usize = 1 << 16;

/// Fits `radii` in place (see the module docs); `normals` unit, one a particle. `table`: the
/// particles' k-nearest-neighbour table if one is at hand (k ≥ 6 for a meaningful fan;
/// [`FAN_NEIGHBOURS`] recommended); without one the neighbours are searched a slice at a
/// time.
pub fn fit_radii(
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &mut [f32],
    table: Option<&KnnTable>,
) -> GapReport {
    let n = positions.len();
    if n < 3 || normals.len() != n || radii.len() != n || table.is_some_and(|t| t.len() != n) {
        return GapReport::default();
    }
    let median = median_positive(radii.iter().copied()).unwrap_or(0.0);
    let cap = MAX_GROWTH * median;
    let longest = LONG_EDGE * super::estimate::median_spacing(positions);
    let fit = |i: usize, row: &mut dyn Iterator<Item = (u32, f32)>| {
        fan(i, positions, normals, radii[i].min(median), longest, row)
    };
    let fits: Vec<Fit> = match table {
        Some(t) => (0..n)
            .into_par_iter()
            .with_min_len(512)
            .map(|i| fit(i, &mut t.row(i)))
            .collect(),
        None => {
            let index = PointIndex::build(positions);
            let mut fits = Vec::with_capacity(n);
            for start in (0..n).step_by(CHUNK) {
                let rows = start..(start + CHUNK).min(n);
                let t = KnnTable::build_rows(&index, positions, FAN_NEIGHBOURS, rows.clone());
                fits.par_extend(
                    rows.into_par_iter()
                        .with_min_len(512)
                        .map(|i| fit(i, &mut t.row(i - start))),
                );
            }
            fits
        }
    };
    let mut report = GapReport::default();
    for (r, fit) in radii.iter_mut().zip(fits) {
        match fit {
            Fit::Interior(need) => {
                let need = need.min(cap.max(*r));
                if need > *r {
                    *r = need;
                    report.grown += 1;
                }
            }
            Fit::Edge(want) => {
                report.edge += 1;
                if want < *r && want > 0.0 {
                    *r = want;
                    report.trimmed += 1;
                }
            }
            Fit::Isolated(most) => {
                if most < *r && most > 0.0 {
                    *r = most;
                    report.trimmed += 1;
                }
            }
        }
    }
    report
}

/// The fan of particle `i` with current radius `r`.
/// `edge_r`: the most an edge particle keeps; `longest`: the longest side of a fan triangle;
/// `row`: its neighbours, nearest first.
fn fan(
    i: usize,
    positions: &[Vec3],
    normals: &[Vec3],
    edge_r: f32,
    longest: f32,
    row: &mut dyn Iterator<Item = (u32, f32)>,
) -> Fit {
    let (p, nrm) = (positions[i], normals[i]);
    if !(p.is_finite() && nrm.is_finite()) || nrm.length_squared() < 0.5 {
        return Fit::Interior(0.0);
    }
    let (u, v) = nrm.any_orthonormal_pair();
    let mut near: Vec<(f32, Vec2)> = Vec::with_capacity(FAN_NEIGHBOURS);
    let mut nearest = f32::INFINITY;
    for (j, d) in row {
        let (q, nj) = (positions[j as usize], normals[j as usize]);
        let off = q - p;
        let along = off.dot(nrm).abs();
        let flat = Vec2::new(off.dot(u), off.dot(v));
        nearest = nearest.min(d);
        if nj.dot(nrm).abs() < 0.5 || along > flat.length() || flat.length_squared() == 0.0 {
            continue;
        }
        near.push((flat.y.atan2(flat.x), flat));
    }
    if near.len() < 2 {
        return Fit::Isolated((EDGE_REACH * nearest).min(edge_r));
    }
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    let open = OPEN_ANGLE_DEG.to_radians();
    let mut need = 0.0f32;
    let mut edge = false;
    for k in 0..near.len() {
        let (a0, qa) = near[k];
        let (b0, qb) = near[(k + 1) % near.len()];
        let mut gap = b0 - a0;
        if k + 1 == near.len() {
            gap += std::f32::consts::TAU;
        }
        let long = qa.length().max(qb.length()).max((qa - qb).length()) > longest;
        if gap > open || long {
            edge = true;
            continue;
        }
        if let Some(c) = far_point(qa, qb) {
            let dc = c.length();
            // Only a gap that i's disk is among the nearest to needs i to cover it.
            if near.iter().all(|(_, q)| (c - *q).length() >= dc * 0.999) {
                need = need.max(GAP_MARGIN * dc);
            }
        }
    }
    if edge {
        // Rows are sorted nearest first, and so are the sheet neighbours taken from them.
        let mut d: Vec<f32> = near.iter().map(|(_, q)| q.length()).collect();
        d.sort_by(f32::total_cmp);
        let spacing = d.iter().take(3).sum::<f32>() / d.len().min(3) as f32;
        Fit::Edge(need.max(EDGE_REACH * spacing).min(edge_r))
    } else {
        Fit::Interior(need)
    }
}

/// The point of triangle (0, a, b) farthest from its nearest corner: the circumcentre when the
/// angle at 0 is at most 90°, else the midpoint of a–b. `None` for a degenerate triangle.
fn far_point(a: Vec2, b: Vec2) -> Option<Vec2> {
    if a.dot(b) < 0.0 {
        return Some(0.5 * (a + b));
    }
    let d = 2.0 * a.perp_dot(b);
    if d.abs() < 1e-12 * a.length_squared().max(b.length_squared()) {
        return None;
    }
    let (a2, b2) = (a.length_squared(), b.length_squared());
    let c = Vec2::new(b.y * a2 - a.y * b2, a.x * b2 - b.x * a2) / d;
    // An obtuse angle at a or b puts the circumcentre outside; the side's midpoint is then the
    // point to cover.
    if (b - a).dot(-a) < 0.0 {
        return Some(0.5 * b);
    }
    if (a - b).dot(-b) < 0.0 {
        return Some(0.5 * a);
    }
    Some(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_point_is_equidistant_in_acute_triangles() {
        let (a, b) = (Vec2::new(1.0, 0.0), Vec2::new(0.5, 0.8));
        let c = far_point(a, b).unwrap();
        let (d0, da, db) = (c.length(), (c - a).length(), (c - b).length());
        assert!((d0 - da).abs() < 1e-5 && (d0 - db).abs() < 1e-5);
        // Obtuse at the origin: the midpoint of the far side.
        let m = far_point(Vec2::new(1.0, 0.0), Vec2::new(-0.5, 0.5)).unwrap();
        assert!((m - Vec2::new(0.25, 0.25)).length() < 1e-6);
        assert!(far_point(Vec2::new(1.0, 0.0), Vec2::new(2.0, 0.0)).is_none());
    }

    /// A square grid of spacing 1 in the z = 0 plane, `w × w` points.
    fn grid(w: usize) -> Vec<Vec3> {
        (0..w * w)
            .map(|i| Vec3::new((i % w) as f32, (i / w) as f32, 0.0))
            .collect()
    }

    #[test]
    fn grid_gaps_close_and_edges_trim() {
        let w = 12;
        let pos = grid(w);
        let normals = vec![Vec3::Z; pos.len()];
        // Too small to cover the square cells (covering radius √2/2 ≈ 0.707) and too big at
        // the edges.
        let mut r = vec![0.6; pos.len()];
        let table = KnnTable::build(&pos, 12);
        let rep = fit_radii(&pos, &normals, &mut r, Some(&table));
        let at = |x: usize, y: usize| r[y * w + x];
        // Interior: grown to cover the cell centres, ~1.15 × 0.707.
        assert!(
            (at(5, 5) - GAP_MARGIN * 0.5f32.sqrt()).abs() < 1e-3,
            "{}",
            at(5, 5)
        );
        assert!(rep.grown > 0 && rep.edge > 0, "{rep:?}");
        // An edge particle reaches about EDGE_REACH spacings, never more than before.
        let mut big = vec![1.5; pos.len()];
        fit_radii(&pos, &normals, &mut big, None);
        assert!(big[w / 2] < 1.0, "edge radius {}", big[w / 2]);
        assert!(
            (big[5 * w + 5] - 1.5).abs() < 1e-6,
            "interior keeps its larger radius"
        );
    }

    #[test]
    fn a_hole_stays_open() {
        // A 12×12 grid with a 4×4 block removed: the hole's rim is an edge, not a gap to fill.
        let w = 12;
        let pos: Vec<Vec3> = grid(w)
            .into_iter()
            .filter(|p| !(4.0..8.0).contains(&p.x) || !(4.0..8.0).contains(&p.y))
            .collect();
        let normals = vec![Vec3::Z; pos.len()];
        let mut r = vec![0.8; pos.len()];
        let table = KnnTable::build(&pos, 12);
        fit_radii(&pos, &normals, &mut r, Some(&table));
        // The hole's centre (6, 6) is covered by no disk.
        let covered = pos
            .iter()
            .zip(&r)
            .any(|(p, r)| (*p - Vec3::new(6.0, 6.0, 0.0)).length() < *r);
        assert!(!covered);
    }
}
