//! Splat radii fitted to the sampling: grown where the disks would leave a pinhole between
//! particles that sample the surface, kept within the film the particles span, and bounded by
//! the particles' own area where the simulator stores it.
//!
//! For each particle i the neighbours of its kNN row that lie on its sheet (normals within
//! 60°, not farther off its tangent plane than along it, nearer than [`OPEN_FRACTION`] ×
//! [`LONG_EDGE`] × the cloud's spacing) are projected onto i's tangent plane. Two polygons
//! there (see [`super::cell`]): the convex hull of i and these neighbours — the film they span
//! around i — and i's Voronoi cell among them, the part of the surface nearer to i than to any
//! other particle. The cells tile the surface: if every disk covers its cell within the hull,
//! no ray slips between them, whatever the sampling (hexagonal, jittered, rows much farther
//! apart than their particles, random).
//!
//! - **Gaps.** A radius grows to [`GAP_MARGIN`] × the distance to the farthest vertex of its
//!   cell cut to the hull, if that is more (capped at [`MAX_GROWTH`] × the median radius). A
//!   cell that runs past the last particles is cut at the hull's edge, so a particle near an
//!   open edge never grows into the empty side.
//! - **Reach.** No disk reaches more than [`EDGE_REACH`] × its spacing beyond the hull of its
//!   neighbourhood: an edge particle (i on the hull: neighbours on one side only — a free
//!   edge, the rim of a hole, a rupture front, a small fragment) is cut by the lines half the
//!   shorter hull edge beside it outside those edges ([`super::clip`]), and grows to cover its
//!   cell and the edge strips to its neighbours' halves out to the cut, so the edge runs
//!   straight, without notches; a particle one row in reaches at most its depth in the hull
//!   plus half its spacing (the mean distance to its two nearest sheet neighbours).
//! - **Isolated** particles (fewer than two sheet neighbours in reach) are drawn at their own
//!   size: the disk of their area where the simulator stores one, else at most [`EDGE_REACH`]
//!   × the distance to their nearest neighbour.
//! - **Area.** Where the particles' areas A are known, no radius grows beyond [`AREA_GROWTH`]
//!   × √(A/π), and none read or estimated keeps more than [`AREA_OVERLAP`] × √(A/π)
//!   ([`bound_by_area`]; see there).
//!
//! - **Adrift** particles, left past a rupture (see [`super::adrift`]), are drawn at their
//!   own size and left out of the other particles' fans, so the film's last row is an edge.
//!
//! A particle that looks like an edge among its [`FAN_NEIGHBOURS`] nearest is looked at again
//! among its [`WIDE_NEIGHBOURS`] nearest (a seam of an anisotropic sampling, where the next
//! row lies beyond the nearest twelve, is no edge).
//!
//! Cost: one k-nearest-neighbour search (k = [`FAN_NEIGHBOURS`], in slices unless a table is
//! given) plus O(k²) a particle, parallel; edges again with k = [`WIDE_NEIGHBOURS`].

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::adrift::adrift_flags;
pub use super::area::{
    AREA_ATTRIBUTES, AREA_GROWTH, AREA_OVERLAP, area_radii, bound_by_area, own_radii,
};
use super::cell::{
    CellScratch, clip_to_hull_into, depth_in_hull, hull_with_origin_into, rim_midpoints,
    sheet_neighbours, two_shortest, voronoi_cell_into,
};
use super::clip::{EdgeClip, NO_CLIP, reach_and_cut, to_3d};
use super::estimate::median_positive;
use super::knn::{KnnTable, PointIndex};

/// Half-side of the square a Voronoi cell is clipped to, as a multiple of the cloud's median
/// distance to the [`SPACING_RANK`]-th nearest neighbour (on a hexagonal sampling of spacing d
/// that distance is d; on a random one about 1.9 times the nearest-neighbour distance).
pub const LONG_EDGE: f32 = 2.5;

/// Sheet neighbours farther than this fraction of [`LONG_EDGE`] × spacing do not span film
/// with the particle (a gap that wide is a hole or the space beyond an edge).
pub const OPEN_FRACTION: f32 = 0.8;

/// Which neighbour's distance measures the spacing for [`LONG_EDGE`].
pub const SPACING_RANK: usize = 6;

/// Most particles the spacing's median is taken over (evenly strided).
const SPACING_SAMPLE: usize = 65_536;

/// Factor on the distance to a gap's centre a disk grows to (its blending weight there is then
/// (1 − 1/1.15²)² ≈ 0.06, not zero).
pub const GAP_MARGIN: f32 = 1.15;

/// How far a disk may reach beyond the film its neighbours span, as a multiple of its spacing:
/// open edges end half a spacing past their last particles.
pub const EDGE_REACH: f32 = 0.5;

/// Most a radius grows, as a multiple of the median radius.
pub const MAX_GROWTH: f32 = 2.5;

/// What [`fit_radii`] changed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GapReport {
    /// Radii grown to close a gap.
    pub grown: usize,
    /// Radii trimmed: at open edges, isolated particles, or to their area.
    pub trimmed: usize,
    /// Particles on an open edge (trimmed or not).
    pub edge: usize,
    /// Particles adrift past a rupture ([`super::adrift`]), drawn at their own size.
    pub adrift: usize,
}

impl std::fmt::Display for GapReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "splat radii fitted to the sampling: {} grown to close gaps, {} trimmed to the film the particles span, {} particles on open edges",
            self.grown, self.trimmed, self.edge
        )?;
        if self.adrift > 0 {
            write!(
                f,
                ", {} adrift past a rupture (nearest neighbour on their sheet farther than {} × both particles' own area radii) drawn at their own size, √(SA/π)",
                self.adrift,
                super::area::DETACHED
            )?;
        }
        Ok(())
    }
}

/// What one particle's neighbourhood says.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fit {
    /// On a sheet: grow to at least `need` (0: nothing to close), keep at most `most`; `edge`:
    /// on the hull of its neighbourhood; `bounded`: the hull cut the cell or the radius (worth
    /// a second look with more neighbours, whose hull may reach further).
    Sheet {
        need: f32,
        most: f32,
        edge: bool,
        bounded: bool,
        clip: EdgeClip,
        /// Its neighbours lie in a line: never trimmed below its own area's radius.
        strand: bool,
    },
    /// No sheet neighbours: the distance to the nearest particle (∞ for none).
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
    fit_radii_clipped(index, positions, normals, radii, table, &[]).0
}

/// [`fit_radii_indexed`] knowing each particle's own size `own` (the radius of its area, from
/// [`area_radii`]; empty or 0 where unknown): isolated particles are drawn at it, and no
/// radius grows beyond [`AREA_GROWTH`] times it; also returning each splat's cut at the open
/// edge it lies on ([`super::clip`]; [`NO_CLIP`] elsewhere, and for all when nothing was
/// fitted: then the list is empty). A splat drawn without its cut may leave notches at open edges.
pub fn fit_radii_clipped(
    index: &PointIndex,
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &mut [f32],
    table: Option<&KnnTable>,
    own: &[f32],
) -> (GapReport, Vec<EdgeClip>) {
    let n = positions.len();
    if n < 3
        || normals.len() != n
        || radii.len() != n
        || index.len() > n
        || table.is_some_and(|t| t.len() != n)
    {
        return (GapReport::default(), Vec::new());
    }
    let median = median_positive(radii.iter().copied()).unwrap_or(0.0);
    let cap = MAX_GROWTH * median;
    let longest = LONG_EDGE * median_kth_distance(index, positions, SPACING_RANK);
    // Particles adrift past a rupture are drawn at their own size and span no film.
    let adrift = adrift_flags(index, (positions, normals), own, table, FAN_NEIGHBOURS);
    let drifting = |j: usize| adrift.get(j).copied().unwrap_or(false);
    let fit = |s: &mut FanScratch, i: usize, row: &mut dyn Iterator<Item = (u32, f32)>| {
        if drifting(i) {
            return Fit::Isolated(f32::INFINITY);
        }
        let row = &mut row.filter(|(j, _)| !drifting(*j as usize));
        fan(i, positions, normals, radii[i].min(cap), longest, row, s)
    };
    let fits: Vec<Fit> = match table {
        Some(t) => (0..n)
            .into_par_iter()
            .with_min_len(512)
            .map_init(FanScratch::default, |s, i| fit(s, i, &mut t.row(i)))
            .collect(),
        None => {
            let mut fits = Vec::with_capacity(n);
            for start in (0..n).step_by(CHUNK) {
                let rows = start..(start + CHUNK).min(n);
                let t = KnnTable::build_rows(index, positions, FAN_NEIGHBOURS, rows.clone());
                fits.par_extend(
                    rows.into_par_iter()
                        .with_min_len(512)
                        .map_init(FanScratch::default, |s, i| fit(s, i, &mut t.row(i - start))),
                );
            }
            fits
        }
    };
    // An edge seen among the nearest few may be a seam of an anisotropic sampling, with film
    // beyond the next rows, and the hull of a lopsided neighbourhood may stop short of film
    // that goes on: look again with more neighbours before trimming or cutting.
    let fits: Vec<Fit> = fits
        .into_par_iter()
        .enumerate()
        .with_min_len(512)
        .map_init(FanScratch::default, |s, (i, f)| match f {
            Fit::Sheet { bounded: false, .. } => f,
            _ => {
                let row = index.nearest_excluding(positions[i], WIDE_NEIGHBOURS, i as u32);
                fit(s, i, &mut row.into_iter())
            }
        })
        .collect();
    let (mut report, clips) = apply(radii, fits, cap, own);
    report.adrift = adrift.iter().filter(|a| **a).count();
    (report, clips)
}

/// Sets the radii from their fans' verdicts (growth capped at `cap`, and at [`AREA_GROWTH`] ×
/// the particles' own sizes `own` where known: empty or 0 for unknown); returns the edge cuts.
fn apply(radii: &mut [f32], fits: Vec<Fit>, cap: f32, own: &[f32]) -> (GapReport, Vec<EdgeClip>) {
    let mut report = GapReport::default();
    let mut clips = vec![NO_CLIP; fits.len()];
    for (i, (r, fit)) in radii.iter_mut().zip(fits).enumerate() {
        let own = own.get(i).copied().filter(|o| *o > 0.0);
        let new = match fit {
            Fit::Sheet {
                need,
                most,
                edge,
                clip,
                strand,
                ..
            } => {
                report.edge += usize::from(edge);
                clips[i] = clip;
                let floor = if strand { own.unwrap_or(0.0) } else { 0.0 };
                r.max(need.min(cap)).min(most).max(floor)
            }
            Fit::Isolated(nearest) => match own {
                Some(o) => o,
                None if nearest.is_finite() => r.min(EDGE_REACH * nearest),
                None => *r,
            },
        };
        // An edge splat, cut at the edge, grows no further than a splat keeps unfitted.
        let growth = if clips[i] == NO_CLIP {
            AREA_GROWTH
        } else {
            AREA_OVERLAP
        };
        let new = match own {
            Some(o) => new.min(growth * o).max(r.min(new)),
            None => new,
        };
        if new > *r {
            report.grown += 1;
        } else if new < *r && new > 0.0 {
            report.trimmed += 1;
        }
        if new > 0.0 && new.is_finite() {
            *r = new;
        }
    }
    (report, clips)
}

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

/// One worker's buffers for [`fan`] (reused particle after particle: no allocation a fan).
#[derive(Debug, Default)]
struct FanScratch {
    row: Vec<(u32, f32)>,
    near: Vec<Vec2>,
    hull: Vec<Vec2>,
    cell: CellScratch,
}

/// The fan of particle `i` with radius `r`: `longest`, the half-side of the square its cell is
/// clipped to; `row`, its neighbours, nearest first; `s`, buffers.
fn fan(
    i: usize,
    positions: &[Vec3],
    normals: &[Vec3],
    r: f32,
    longest: f32,
    row: &mut dyn Iterator<Item = (u32, f32)>,
    s: &mut FanScratch,
) -> Fit {
    let (p, nrm) = (positions[i], normals[i]);
    if !(p.is_finite() && nrm.is_finite())
        || nrm.length_squared() < 0.5
        || longest.is_nan()
        || longest <= 0.0
    {
        return Fit::Sheet {
            need: 0.0,
            most: f32::INFINITY,
            edge: false,
            bounded: false,
            clip: NO_CLIP,
            strand: false,
        };
    }
    // Where the film thins, its particles spread: the reach of a neighbourhood follows the
    // local spacing (the distance to the SPACING_RANK-th neighbour) where that is the larger.
    s.row.clear();
    s.row.extend(row);
    let local = s.row.get(SPACING_RANK - 1).map_or(0.0, |r| LONG_EDGE * r.1);
    let longest = longest.max(local);
    let open = OPEN_FRACTION * longest;
    let nearest = sheet_neighbours(p, nrm, (positions, normals), open, &s.row, &mut s.near);
    let near = &s.near;
    if near.len() < 2 {
        return Fit::Isolated(nearest);
    }
    let (d0, d1) = two_shortest(near);
    let reach = EDGE_REACH * 0.5 * (d0 + d1);
    // The film i's neighbours span around it, and i's share of it.
    hull_with_origin_into(near, &mut s.cell, &mut s.hull);
    let hull = &s.hull;
    if hull.len() < 3 {
        // A strand of particles in a line: half a spacing about each, never less than its own
        // area (the area holds that much film).
        return Fit::Sheet {
            need: 0.0,
            most: reach,
            edge: true,
            bounded: true,
            clip: NO_CLIP,
            strand: true,
        };
    }
    let (depth, row) = depth_in_hull(hull);
    let (reach, cut) = reach_and_cut(hull, near, depth, row, reach, EDGE_REACH);
    voronoi_cell_into(near, longest, &mut s.cell);
    let farthest = |c: &[Vec2]| c.iter().map(|c| c.length()).fold(0.0f32, f32::max);
    let whole = farthest(&s.cell.poly);
    clip_to_hull_into(hull, &mut s.cell);
    let far = farthest(&s.cell.poly);
    let rim = rim_midpoints(near, hull);
    let (need, most, clip) = match cut {
        Some((m, corner)) => {
            let (u, v) = nrm.any_orthonormal_pair();
            let need = GAP_MARGIN * far.max(rim).max(corner);
            (need, need, to_3d(m, reach, u, v))
        }
        None => (GAP_MARGIN * far.max(rim), depth + reach, NO_CLIP),
    };
    Fit::Sheet {
        need,
        most,
        edge: depth < 0.5 * reach,
        bounded: far < 0.999 * whole || rim > far || most < r.max(need),
        clip,
        strand: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
