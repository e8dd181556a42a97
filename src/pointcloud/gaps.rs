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
//!   plus half its spacing (the mean distance to its two nearest sheet neighbours) past the
//!   nearest hull edge: where its cell reaches further, it is cut by the lines that far outside
//!   the two hull edges nearest to it and grows to cover its cell, as far as every point of it
//!   stays within that reach of the hull ([`super::clip::inner_cut`]) — a plain disk trimmed
//!   to the reach left crevices beside a torn rim.
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
//! A particle whose fan its [`FAN_NEIGHBOURS`] nearest bound (it looks like an edge, its cell
//! or a rim midpoint reaches past their hull, its radius is trimmed) is looked at again among
//! its [`WIDE_NEIGHBOURS`] nearest (a seam of an anisotropic sampling, where the next row lies beyond the nearest
//! twelve, is no edge; on a Fibonacci sphere a third of the particles have a first-ring
//! neighbour on their 12-neighbour hull, which 24 neighbours would settle: see
//! [`SecondLook`]).
//!
//! Cost: one k-nearest-neighbour search (k = [`FAN_NEIGHBOURS`], in slices unless a table is
//! given) plus O(k²) a particle, parallel; bounded fans again with up to [`WIDE_NEIGHBOURS`],
//! searched only as far as a fan can take a neighbour (see [`SecondLook::Bounded`]).

use glam::Vec3;
use rayon::prelude::*;

use super::adrift::adrift_flags;
pub use super::area::{
    AREA_ATTRIBUTES, AREA_GROWTH, AREA_OVERLAP, area_radii, bound_by_area, own_radii,
};
use super::clip::{EdgeClip, NO_CLIP};
use super::cut::Cut;
use super::estimate::median_positive;
pub use super::fan::{EDGE_REACH, GAP_MARGIN, GRAZING_TAN, LONG_EDGE, OPEN_FRACTION, SPACING_RANK};
use super::fan::{FanScratch, Fit, fan};
use super::knn::{KnnTable, PointIndex};
use super::looks::{Cloud, refit_where, second_looks};
pub use super::looks::{MIDDLE_NEIGHBOURS, SecondLook, WIDE_NEIGHBOURS};

/// Most particles the spacing's median is taken over (evenly strided).
const SPACING_SAMPLE: usize = 65_536;

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
    /// Particles looked at again among their [`MIDDLE_NEIGHBOURS`] nearest (see
    /// [`SecondLook`]).
    pub middle_looks: usize,
    /// Particles looked at again among their [`WIDE_NEIGHBOURS`] nearest.
    pub wide_looks: usize,
    /// Particles adrift past a rupture ([`super::adrift`]), drawn at their own size.
    pub adrift: usize,
}

impl std::fmt::Display for GapReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "splat radii fitted to the sampling: {} grown to close gaps, {} trimmed to the film the particles span, {} particles on open edges ({} looked at again among their {MIDDLE_NEIGHBOURS} nearest, {} among their {WIDE_NEIGHBOURS})",
            self.grown, self.trimmed, self.edge, self.middle_looks, self.wide_looks
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
/// radius grows beyond [`AREA_GROWTH`] times it; also returning each splat's [`Cut`]: the cut
/// at the open edge it lies on or one row in from it ([`super::clip`]), its growth past its
/// cell for tilted neighbours, or none (and an empty list when nothing was fitted). A splat
/// drawn without its cut may leave notches at open edges.
pub fn fit_radii_clipped(
    index: &PointIndex,
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &mut [f32],
    table: Option<&KnnTable>,
    own: &[f32],
) -> (GapReport, Vec<Cut>) {
    let look = SecondLook::default();
    fit_radii_looking(index, positions, normals, radii, table, own, look)
}

/// [`fit_radii_clipped`] with the particles looked at again chosen by `look`.
pub fn fit_radii_looking(
    index: &PointIndex,
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &mut [f32],
    table: Option<&KnnTable>,
    own: &[f32],
    look: SecondLook,
) -> (GapReport, Vec<Cut>) {
    let n = positions.len();
    if n < 3
        || normals.len() != n
        || radii.len() != n
        || index.len() > n
        || table.is_some_and(|t| t.len() != n)
    {
        return (GapReport::default(), Vec::new());
    }
    let (cap, longest) = scales(index, positions, radii);
    // Particles adrift past a rupture are drawn at their own size and span no film.
    let adrift = adrift_flags(index, (positions, normals), own, table, FAN_NEIGHBOURS);
    let drifting = |j: usize| adrift.get(j).copied().unwrap_or(false);
    let fit = fit_row((positions, normals, &*radii), (cap, longest), &drifting);
    // The first look, keeping each particle's distance to its SPACING_RANK-th neighbour.
    let first = |s: &mut FanScratch, i: usize, row: &mut dyn Iterator<Item = (u32, f32)>| {
        let f = fit(s, i, row);
        (f, if drifting(i) { None } else { s.sixth() })
    };
    let mut looked = vec![(Fit::Isolated(f32::INFINITY), None); n];
    match table {
        Some(t) => {
            refit_where(
                &mut looked,
                |_, _| true,
                |s, i, _| first(s, i, &mut t.row(i)),
            );
        }
        None => {
            for start in (0..n).step_by(CHUNK) {
                let rows = start..(start + CHUNK).min(n);
                let t = KnnTable::build_rows(index, positions, FAN_NEIGHBOURS, rows.clone());
                let pick = |i: usize, _: &_| rows.contains(&i);
                refit_where(&mut looked, pick, |s, i, _| {
                    first(s, i, &mut t.row(i - start))
                });
            }
        }
    }
    let cloud = Cloud {
        index,
        ids: None,
        positions,
        normals,
        longest,
        drifting: &drifting,
        fit: &fit,
    };
    let (middle_looks, wide_looks) = second_looks(&cloud, &mut looked, look);
    drop(fit);
    let (report, verdicts) = apply(radii, looked.into_iter().map(|(f, _)| f), cap, own);
    let report = GapReport {
        middle_looks,
        wide_looks,
        adrift: adrift.iter().filter(|a| **a).count(),
        ..report
    };
    (report, verdicts)
}

/// The cloud's scales for its fans: the most a radius grows ([`MAX_GROWTH`] × the median
/// radius) and the half-side of a fan's square ([`LONG_EDGE`] × the median distance to the
/// [`SPACING_RANK`]-th neighbour), scene units.
pub(super) fn scales(index: &PointIndex, positions: &[Vec3], radii: &[f32]) -> (f32, f32) {
    let median = median_positive(radii.iter().copied()).unwrap_or(0.0);
    let longest = LONG_EDGE * median_kth_distance(index, positions, SPACING_RANK);
    (MAX_GROWTH * median, longest)
}

/// The fan of particle `i` from a row of its neighbours (nearest first), with the cloud's
/// `(cap, longest)` from [`scales`]: the `drifting` left out of the row, and a drifting `i`
/// isolated.
pub(super) fn fit_row<'a>(
    (positions, normals, radii): (&'a [Vec3], &'a [Vec3], &'a [f32]),
    (cap, longest): (f32, f32),
    drifting: &'a (dyn Fn(usize) -> bool + Sync),
) -> impl Fn(&mut FanScratch, usize, &mut dyn Iterator<Item = (u32, f32)>) -> Fit + Sync + 'a {
    move |s, i, row| {
        if drifting(i) {
            return Fit::Isolated(f32::INFINITY);
        }
        let row = &mut row.filter(|(j, _)| !drifting(*j as usize));
        fan(i, positions, normals, radii[i].min(cap), longest, row, s)
    }
}

/// Sets the radii from their fans' verdicts (growth capped at `cap`, and at [`AREA_GROWTH`] ×
/// the particles' own sizes `own` where known: empty or 0 for unknown); returns their [`Cut`]s.
pub(super) fn apply(
    radii: &mut [f32],
    fits: impl Iterator<Item = Fit>,
    cap: f32,
    own: &[f32],
) -> (GapReport, Vec<Cut>) {
    let mut report = GapReport::default();
    let mut verdicts = vec![Cut::None; radii.len()];
    for (i, (r, fit)) in radii.iter_mut().zip(fits).enumerate() {
        let own = own.get(i).copied().filter(|o| *o > 0.0);
        let (new, verdict) = match fit {
            Fit::Sheet {
                need,
                most,
                edge,
                clip,
                strand,
                cut_most,
                shingle,
                ..
            } => {
                report.edge += usize::from(edge);
                let floor = if strand { own.unwrap_or(0.0) } else { 0.0 };
                let reach = (need, most, cut_most, shingle);
                on_sheet(*r, own, cap, reach, clip, floor)
            }
            Fit::Isolated(nearest) => {
                let new = match own {
                    Some(o) => o,
                    None if nearest.is_finite() => r.min(EDGE_REACH * nearest),
                    None => *r,
                };
                (bounded(*r, own, new, AREA_GROWTH), Cut::None)
            }
        };
        verdicts[i] = verdict;
        if new > *r {
            report.grown += 1;
        } else if new < *r && new > 0.0 {
            report.trimmed += 1;
        }
        if new > 0.0 && new.is_finite() {
            *r = new;
        }
    }
    (report, verdicts)
}

/// `new`, its growth capped at `growth` × the particle's own size `own` (if known), never
/// below what it had (`r`).
fn bounded(r: f32, own: Option<f32>, new: f32, growth: f32) -> f32 {
    match own {
        Some(o) => new.min(growth * o).max(r.min(new)),
        None => new,
    }
}

/// The radius and verdict of a particle of radius `r` whose fan asks for `need` (capped at
/// `cap`), allows `most` as a plain disk and `cut_most` with its `clip` drawn, with `shingle`
/// of growth for its neighbours' tilted planes and at least `floor`. One row in from an open
/// edge (`cut_most` > `most`): trimmed to `most` as a plain disk, it covers its cell (`need`,
/// and `shingle` past it) up to `cut_most` with its cut drawn (else crevices open beside the
/// rim), as an edge particle does. A cut splat grows no further than a splat keeps unfitted.
fn on_sheet(
    r: f32,
    own: Option<f32>,
    cap: f32,
    (need, most, cut_most, shingle): (f32, f32, f32, f32),
    clip: EdgeClip,
    floor: f32,
) -> (f32, Cut) {
    let inner = cut_most > most;
    let plain_growth = if clip == NO_CLIP || inner {
        AREA_GROWTH
    } else {
        AREA_OVERLAP
    };
    let plain = |need: f32| {
        bounded(
            r,
            own,
            r.max(need.min(cap)).min(most).max(floor),
            plain_growth,
        )
    };
    let flat = plain(need);
    let cut = bounded(
        r,
        own,
        (need + shingle).min(cap).min(cut_most),
        AREA_OVERLAP,
    );
    if inner && cut > flat {
        (cut, Cut::Inner(clip))
    } else if !inner && clip != NO_CLIP {
        (flat, Cut::Edge(clip))
    } else {
        // Grown past its cell for its neighbours' planes: the disk alone (the MLS surface
        // keeps `flat`, see [`Cut::Grown`]).
        let grown = plain(need + shingle);
        if grown > flat {
            (grown, Cut::Grown { flat })
        } else {
            (flat, Cut::None)
        }
    }
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
        let same = |x: &[f32], y: &[f32]| x.iter().zip(y).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same(&sliced, &whole));
        // The middle look and the default's shorter searches fit the whole rows' radii and
        // cuts, the hole's rim and the free edges included (tests/fit_second_look.rs does the
        // same on real frames).
        let looking = |look| {
            let mut r = vec![0.55; pos.len()];
            let fit = fit_radii_looking(&index, &pos, &normals, &mut r, None, &[], look);
            (r, fit)
        };
        let (before, c) = looking(SecondLook::BoundedWholeRows);
        let (new, d) = looking(SecondLook::WhereItCanChange);
        assert!(same(&before, &new) && c.1 == d.1);
        let (short, e) = looking(SecondLook::Bounded);
        assert!(same(&before, &short) && c.1 == e.1 && c.0 == e.0);
        assert_eq!(
            (c.0.grown, c.0.trimmed, c.0.edge),
            (a.grown, a.trimmed, a.edge)
        );
        assert!(
            c.0.wide_looks > d.0.wide_looks && d.0.wide_looks > 0,
            "{:?} {:?}",
            c.0,
            d.0
        );
    }
}
