//! Splat radii fitted to the sampling: grown where the disks would leave a pinhole between
//! particles that sample the surface, trimmed where the surface ends.
//!
//! For each particle i the neighbours of its kNN row that lie on its sheet (normals within
//! 60°, not farther off its tangent plane than along it) are projected onto i's tangent plane,
//! and i's Voronoi cell among them is cut out: the part of the surface nearer to i than to any
//! other particle, clipped to a square of half-side [`LONG_EDGE`] × the cloud's spacing. A disk
//! that reaches its cell's farthest vertex covers the whole cell, and the cells tile the
//! surface: if every disk covers its cell, no ray slips between them, whatever the sampling
//! (hexagonal, jittered, rows much farther apart than their particles, random). A cell vertex
//! at [`OPEN_FRACTION`] of the clipping square or beyond means no particle on that side: an
//! open edge (a free edge, the rim of a hole wider than about twice that, a rupture front, a
//! film torn into sparse fragments), and i is an edge particle.
//!
//! - **Gaps.** An interior particle's radius grows to [`GAP_MARGIN`] × the distance to its
//!   cell's farthest vertex, if that is more (capped at [`MAX_GROWTH`] × the median radius).
//! - **Edges.** An edge particle's disk is shrunk to what its cell's closed side needs, and at least
//!   [`EDGE_REACH`] × its spacing (the mean distance to its three nearest sheet neighbours),
//!   but never above its previous radius nor the cloud's median radius: a rim
//!   ends about half a spacing beyond its last particles instead of bulging by a whole
//!   (inflated) spacing.
//! - **Isolated** particles (fewer than two neighbours on their sheet) keep at most
//!   [`EDGE_REACH`] × the distance to their nearest neighbour, and at most the median radius.
//!
//! A particle that looks like an edge among its [`FAN_NEIGHBOURS`] nearest is looked at again
//! among its [`WIDE_NEIGHBOURS`] nearest (a seam of an anisotropic sampling, where the next
//! row lies beyond the nearest twenty, is no edge).
//!
//! Cost: one k-nearest-neighbour search (k = [`FAN_NEIGHBOURS`], in slices unless a table is
//! given) plus O(k²) a particle, parallel; edges again with k = [`WIDE_NEIGHBOURS`].

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::estimate::median_positive;
use super::knn::{KnnTable, PointIndex};

/// Half-side of the square a Voronoi cell is clipped to, as a multiple of the cloud's median
/// distance to the [`SPACING_RANK`]-th nearest neighbour (on a hexagonal sampling of spacing d
/// that distance is d; on a random one about 1.9 times the nearest-neighbour distance). A cell
/// vertex beyond half of it means an open side: no particle within a hole's width.
pub const LONG_EDGE: f32 = 2.5;

/// A cell vertex at least this fraction of [`LONG_EDGE`] × spacing from the particle marks an
/// open side (the cell reaches the clipping square there: no particle beyond).
pub const OPEN_FRACTION: f32 = 0.8;

/// Which neighbour's distance measures the spacing for [`LONG_EDGE`].
pub const SPACING_RANK: usize = 6;

/// Most particles the spacing's median is taken over (evenly strided).
const SPACING_SAMPLE: usize = 65_536;

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

/// Neighbours a particle that looks like an edge among [`FAN_NEIGHBOURS`] is looked at again
/// with.
pub const WIDE_NEIGHBOURS: usize = 64;

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
    fit_radii_indexed(
        &PointIndex::build(positions),
        positions,
        normals,
        radii,
        table,
    )
}

/// [`fit_radii`] with the neighbour index over the same `positions` already built (e.g. the
/// one the caller built `table` from), so it is not built twice.
pub fn fit_radii_indexed(
    index: &PointIndex,
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &mut [f32],
    table: Option<&KnnTable>,
) -> GapReport {
    let n = positions.len();
    if n < 3
        || normals.len() != n
        || radii.len() != n
        || index.len() > n
        || table.is_some_and(|t| t.len() != n)
    {
        return GapReport::default();
    }
    let median = median_positive(radii.iter().copied()).unwrap_or(0.0);
    let cap = MAX_GROWTH * median;
    let longest = LONG_EDGE * median_kth_distance(index, positions, SPACING_RANK);
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
            let mut fits = Vec::with_capacity(n);
            for start in (0..n).step_by(CHUNK) {
                let rows = start..(start + CHUNK).min(n);
                let t = KnnTable::build_rows(index, positions, FAN_NEIGHBOURS, rows.clone());
                fits.par_extend(
                    rows.into_par_iter()
                        .with_min_len(512)
                        .map(|i| fit(i, &mut t.row(i - start))),
                );
            }
            fits
        }
    };
    // An edge seen among the nearest few may be a seam of an anisotropic sampling, with film
    // beyond the next rows: look again with more neighbours before trimming.
    let fits: Vec<Fit> = fits
        .into_par_iter()
        .enumerate()
        .with_min_len(512)
        .map(|(i, f)| match f {
            Fit::Interior(_) => f,
            _ => {
                let row = index.nearest_excluding(positions[i], WIDE_NEIGHBOURS, i as u32);
                fit(i, &mut row.into_iter())
            }
        })
        .collect();
    apply(radii, fits, cap)
}

/// Sets the radii from their fans' verdicts (growth capped at `cap` or the radius itself).
fn apply(radii: &mut [f32], fits: Vec<Fit>, cap: f32) -> GapReport {
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
/// The median over (up to [`SPACING_SAMPLE`] strided) particles of the distance to their
/// `k`-th nearest neighbour (0 when there is none).
fn median_kth_distance(index: &PointIndex, positions: &[Vec3], k: usize) -> f32 {
    let n = positions.len();
    let m = n.min(SPACING_SAMPLE);
    let d = (0..m).into_par_iter().filter_map(|s| {
        let i = if m == n { s } else { s * n / m };
        index
            .nearest_excluding(positions[i], k, i as u32)
            .last()
            .map(|r| r.1)
    });
    median_positive(d.collect::<Vec<f32>>().into_iter()).unwrap_or(0.0)
}

/// `edge_r`: the most an edge particle keeps; `longest`: the farthest a sampled neighbour may
/// be; `row`: its neighbours, nearest first.
fn fan(
    i: usize,
    positions: &[Vec3],
    normals: &[Vec3],
    edge_r: f32,
    longest: f32,
    row: &mut dyn Iterator<Item = (u32, f32)>,
) -> Fit {
    let (p, nrm) = (positions[i], normals[i]);
    if !(p.is_finite() && nrm.is_finite())
        || nrm.length_squared() < 0.5
        || longest.is_nan()
        || longest <= 0.0
    {
        return Fit::Interior(0.0);
    }
    let (u, v) = nrm.any_orthonormal_pair();
    let mut near: Vec<Vec2> = Vec::with_capacity(FAN_NEIGHBOURS);
    let mut nearest = f32::INFINITY;
    for (j, d) in row {
        let (q, nj) = (positions[j as usize], normals[j as usize]);
        let off = q - p;
        let flat = Vec2::new(off.dot(u), off.dot(v));
        nearest = nearest.min(d);
        if nj.dot(nrm).abs() < 0.5
            || off.dot(nrm).abs() > flat.length()
            || flat.length_squared() == 0.0
        {
            continue;
        }
        near.push(flat);
    }
    if near.len() < 2 {
        return Fit::Isolated((EDGE_REACH * nearest).min(edge_r));
    }
    // i's Voronoi cell among its sheet neighbours, clipped to a square of half-side
    // `longest`: the part of the surface nearer to i than to any other particle.
    let cell = voronoi_cell(&near, longest);
    let open = OPEN_FRACTION * longest;
    let mut need = 0.0f32;
    let mut edge = cell.is_empty();
    for c in &cell {
        let d = c.length();
        if d >= open {
            edge = true;
        } else {
            need = need.max(GAP_MARGIN * d);
        }
    }
    if edge {
        let mut d: Vec<f32> = near.iter().map(|q| q.length()).collect();
        d.sort_by(f32::total_cmp);
        let spacing = d.iter().take(3).sum::<f32>() / d.len().min(3) as f32;
        Fit::Edge(need.max(EDGE_REACH * spacing).min(edge_r))
    } else {
        Fit::Interior(need)
    }
}

/// The vertices of the cell {x : |x| ≤ |x − q| for every q in `near`} ∩ [−half, half]²: the
/// square clipped by the half-planes x·q ≤ |q|²/2 (Sutherland–Hodgman on a convex polygon).
fn voronoi_cell(near: &[Vec2], half: f32) -> Vec<Vec2> {
    let mut poly = vec![
        Vec2::new(-half, -half),
        Vec2::new(half, -half),
        Vec2::new(half, half),
        Vec2::new(-half, half),
    ];
    let mut next = Vec::with_capacity(poly.len() + 2);
    for q in near {
        let (lim, side) = (0.5 * q.length_squared(), |x: Vec2| x.dot(*q));
        next.clear();
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (sa, sb) = (side(a) - lim, side(b) - lim);
            if sa <= 0.0 {
                next.push(a);
            }
            if (sa < 0.0) != (sb < 0.0) && sa != sb {
                next.push(a + (b - a) * (sa / (sa - sb)));
            }
        }
        std::mem::swap(&mut poly, &mut next);
        if poly.is_empty() {
            break;
        }
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn voronoi_cell_of_a_square_lattice_point_is_its_square() {
        let near = [Vec2::X, -Vec2::X, Vec2::Y, -Vec2::Y, Vec2::ONE, -Vec2::ONE];
        let mut cell = voronoi_cell(&near, 10.0);
        // The diagonal neighbours' lines pass through corners: drop the repeated vertices.
        cell.dedup_by(|a, b| (*a - *b).length() < 1e-6);
        assert_eq!(cell.len(), 4, "{cell:?}");
        for c in cell {
            assert!(
                (c.x.abs() - 0.5).abs() < 1e-6 && (c.y.abs() - 0.5).abs() < 1e-6,
                "{c}"
            );
        }
        // One side open: the cell reaches the clipping square there.
        let cell = voronoi_cell(&[Vec2::X, Vec2::Y, -Vec2::Y], 10.0);
        assert!(cell.iter().any(|c| c.x <= -9.99));
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

    #[test]
    fn a_whole_table_fits_as_the_sliced_search() {
        // The render searches one whole 12-neighbour table for the fit and the disks' detail
        // together; the fit must not change with it. A jittered grid with a hole and a free
        // edge, more particles than one slice so the sliced search takes several.
        let w = 300;
        let mut seed = 0x9e37_79b9u32;
        let mut jitter = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32 - 0.5
        };
        let pos: Vec<Vec3> = grid(w)
            .into_iter()
            .filter(|p| (*p - Vec3::new(150.0, 150.0, 0.0)).length() > 20.0)
            .map(|p| p + Vec3::new(0.4 * jitter(), 0.4 * jitter(), 0.05 * jitter()))
            .collect();
        assert!(pos.len() > CHUNK);
        let normals = vec![Vec3::Z; pos.len()];
        let mut sliced = vec![0.55; pos.len()];
        let a = fit_radii(&pos, &normals, &mut sliced, None);
        let index = PointIndex::build(&pos);
        let table = KnnTable::build_with(&index, &pos, FAN_NEIGHBOURS);
        let mut whole = vec![0.55; pos.len()];
        let b = fit_radii_indexed(&index, &pos, &normals, &mut whole, Some(&table));
        assert!(a.grown > 0 && a.edge > 0, "{a:?}");
        assert_eq!(a, b);
        assert!(
            sliced
                .iter()
                .zip(&whole)
                .all(|(x, y)| x.to_bits() == y.to_bits())
        );
    }
}
