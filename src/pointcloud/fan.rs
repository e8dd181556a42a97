//! One particle's fan: its sheet neighbours projected onto its tangent plane, their hull, its
//! Voronoi cell cut to that hull, and the verdict the radius fit ([`super::gaps`]) draws from
//! them (see there).

use glam::{Vec2, Vec3};

use super::cell::{
    CellScratch, FAN_SLOPE, clip_to_hull_into, depth_in_hull, hull_with_origin_into, rim_midpoints,
    sheet_neighbours, two_shortest, voronoi_cell_into,
};
use super::clip::{EdgeClip, NO_CLIP, inner_cut, reach_and_cut, to_3d};

/// Half-side of the square a Voronoi cell is clipped to, as a multiple of the cloud's median
/// distance to the [`SPACING_RANK`]-th nearest neighbour (on a hexagonal sampling of spacing d
/// that distance is d; on a random one about 1.9 times the nearest-neighbour distance).
pub const LONG_EDGE: f32 = 2.5;

/// Sheet neighbours farther than this fraction of [`LONG_EDGE`] × spacing do not span film
/// with the particle (a gap that wide is a hole or the space beyond an edge).
pub const OPEN_FRACTION: f32 = 0.8;

/// Which neighbour's distance measures the spacing for [`LONG_EDGE`].
pub const SPACING_RANK: usize = 6;

/// Factor on the distance to a gap's centre a disk grows to (its blending weight there is then
/// (1 − 1/1.15²)² ≈ 0.06, not zero).
pub const GAP_MARGIN: f32 = 1.15;

/// How far a disk may reach beyond the film its neighbours span, as a multiple of its spacing:
/// open edges end half a spacing past their last particles.
pub const EDGE_REACH: f32 = 0.5;

/// What one particle's neighbourhood says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fit {
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
        /// How far a disk drawn with `clip` may reach: `most` for a particle on the hull (its
        /// cut is always drawn); for one inside it, trimmed to `most`, the radius under the cut
        /// at the two nearest hull edges ([`super::clip::inner_cut`]), drawn only where the
        /// disk grows past `most` (to cover its cell beside a torn rim, see [`super::gaps`]).
        cut_most: f32,
        /// How much further than `need` a disk grows (within `most`), for neighbours whose
        /// planes lie apart from its own where their cells meet ([`shingle_overlap`]; 0 on an
        /// edge): the disks' alone, not the MLS surface's.
        shingle: f32,
    },
    /// No sheet neighbours: the distance to the nearest particle (∞ for none).
    Isolated(f32),
}

impl Fit {
    /// Nothing to change, nothing to look at again (a particle without a valid normal).
    const NOTHING: Fit = Fit::Sheet {
        need: 0.0,
        most: f32::INFINITY,
        edge: false,
        bounded: false,
        clip: NO_CLIP,
        strand: false,
        cut_most: f32::INFINITY,
        shingle: 0.0,
    };

    /// A particle in a strand (its neighbours in a line): kept within `reach`, an edge.
    fn strand(reach: f32) -> Fit {
        Fit::Sheet {
            need: 0.0,
            most: reach,
            edge: true,
            bounded: true,
            clip: NO_CLIP,
            strand: true,
            cut_most: reach,
            shingle: 0.0,
        }
    }
}

/// One worker's buffers for [`fan`] (reused particle after particle: no allocation a fan).
#[derive(Debug, Default)]
pub struct FanScratch {
    row: Vec<(u32, f32)>,
    near: Vec<Vec2>,
    hull: Vec<Vec2>,
    cell: CellScratch,
}

impl FanScratch {
    /// The distance to the [`SPACING_RANK`]-th neighbour of the row the last [`fan`] took
    /// (`None` for a shorter row).
    pub fn sixth(&self) -> Option<f32> {
        self.row.get(SPACING_RANK - 1).map(|r| r.1)
    }
}

/// The half-side of a fan's square and the distance along the tangent plane within which its
/// sheet neighbours lie, for the cloud's `longest` and the particle's `sixth` (its distance to
/// the [`SPACING_RANK`]-th neighbour): where the film thins, its particles spread, and the
/// reach of a neighbourhood follows the local spacing where that is the larger.
fn reach(longest: f32, sixth: Option<f32>) -> (f32, f32) {
    let longest = longest.max(sixth.map_or(0.0, |d| LONG_EDGE * d));
    (longest, OPEN_FRACTION * longest)
}

/// Scene distance beyond which no neighbour enters the fan of a particle whose unit normal is
/// `normal` (see [`reach`] for `longest` and `sixth`): its sheet neighbours lie nearer than
/// `open` along the tangent plane and at most [`FAN_SLOPE`] × that off it. A row holding every
/// neighbour within this distance gives the fan of the row of all neighbours; ∞ (no such
/// bound) for a normal off unit length.
pub fn fan_reach(longest: f32, sixth: Option<f32>, normal: Vec3) -> f32 {
    if (normal.length_squared() - 1.0).abs() > 1e-4 {
        return f32::INFINITY;
    }
    let (_, open) = reach(longest, sixth);
    // A thousandth more covers the rounding of projected against straight distances.
    open * (1.0 + FAN_SLOPE * FAN_SLOPE).sqrt() * 1.001
}

/// The fan of particle `i` with radius `r`: `longest`, the half-side of the square its cell is
/// clipped to; `row`, its neighbours, nearest first; `s`, buffers.
pub fn fan(
    i: usize,
    positions: &[Vec3],
    normals: &[Vec3],
    r: f32,
    longest: f32,
    row: &mut dyn Iterator<Item = (u32, f32)>,
    s: &mut FanScratch,
) -> Fit {
    let (p, nrm) = (positions[i], normals[i]);
    s.row.clear();
    s.row.extend(row);
    if !(p.is_finite() && nrm.is_finite())
        || nrm.length_squared() < 0.5
        || longest.is_nan()
        || longest <= 0.0
    {
        return Fit::NOTHING;
    }
    let (longest, open) = reach(longest, s.sixth());
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
        return Fit::strand(reach);
    }
    let (depth, row) = depth_in_hull(hull);
    let (reach, cut) = reach_and_cut(hull, near, depth, row, reach, EDGE_REACH);
    voronoi_cell_into(near, longest, &mut s.cell);
    let farthest = |c: &[Vec2]| c.iter().map(|c| c.length()).fold(0.0f32, f32::max);
    let whole = farthest(&s.cell.poly);
    clip_to_hull_into(hull, &mut s.cell);
    let far = farthest(&s.cell.poly);
    let rim = rim_midpoints(near, hull);
    let (need, most, clip, cut_most, shingle) = match cut {
        Some((m, corner)) => {
            let (u, v) = nrm.any_orthonormal_pair();
            let need = GAP_MARGIN * far.max(rim).max(corner);
            (need, need, to_3d(m, reach, u, v), need, 0.0)
        }
        None => {
            let sizes = Interior {
                need: GAP_MARGIN * far.max(rim),
                most: depth + reach,
                far,
                reach,
                open,
            };
            interior(i, (positions, normals), r, nrm, hull, sizes, &s.row)
        }
    };
    // The growth past the cell is trimmed to `most` as well (a wider look may move it).
    let trims = most < r.max(need + shingle);
    Fit::Sheet {
        need,
        most,
        edge: depth < 0.5 * reach,
        bounded: far < 0.999 * whole || rim > far || trims,
        clip,
        strand: false,
        cut_most,
        shingle,
    }
}

/// What [`interior`] needs of a particle's fan that no edge cuts.
struct Interior {
    /// The radius its cell needs.
    need: f32,
    /// The most it may reach (its depth in the hull plus the edge reach).
    most: f32,
    /// The farthest corner of its cell cut to the hull.
    far: f32,
    /// Half a spacing (the reach past the hull).
    reach: f32,
    /// The fan's open distance.
    open: f32,
}

/// The sizes of a particle no edge cuts: (need, most, clip, cut_most, shingle) — the growth
/// past its cell where neighbours' planes lie apart, and the cut one row in from an edge
/// where the plain disk would trim.
fn interior(
    i: usize,
    pn: (&[Vec3], &[Vec3]),
    r: f32,
    nrm: Vec3,
    hull: &[Vec2],
    z: Interior,
    row: &[(u32, f32)],
) -> (f32, f32, EdgeClip, f32, f32) {
    let (need, most) = (z.need, z.most);
    // The growth is at most `far`: a disk already that large needs none (most do).
    let shingle = if r >= need + z.far {
        0.0
    } else {
        shingle_overlap(i, pn, z.open, z.far, row)
    };
    // Only a particle the plain disk would trim looks for the cut (most never do).
    let inner = if most < r.max(need) {
        inner_cut(hull, z.reach)
    } else {
        None
    };
    match inner {
        Some((c, cut_most)) if cut_most > most => {
            let (u, v) = nrm.any_orthonormal_pair();
            let clip = c.map(|(m, k)| (m.x * u + m.y * v).extend(k));
            (need, most, clip, cut_most, shingle)
        }
        _ => (need, most, NO_CLIP, most, shingle),
    }
}

/// Tangent of the most grazing ray (to the film's normal) that finds no slit between two
/// neighbouring disks whose planes lie apart where their cells meet.
pub const GRAZING_TAN: f32 = 4.0;

/// Nearest neighbours whose planes [`shingle_overlap`] compares with a particle's (the first
/// look's, `super::gaps::FAN_NEIGHBOURS`).
const SHINGLE_NEIGHBOURS: usize = 12;

/// How far past its cell particle i's disk must reach so that a ray at [`GRAZING_TAN`] finds no
/// slit between it and a neighbour whose plane lies apart from i's where their cells meet:
/// half the planes' separation at the midpoint times [`GRAZING_TAN`], the largest over the sheet
/// neighbours among its [`SHINGLE_NEIGHBOURS`] nearest (within `open` along i's plane) whose
/// bisector passes within `far` of i, and at most `far`.
fn shingle_overlap(
    i: usize,
    (positions, normals): (&[Vec3], &[Vec3]),
    open: f32,
    far: f32,
    row: &[(u32, f32)],
) -> f32 {
    let (p, n) = (positions[i], normals[i]);
    let mut most = 0.0f32;
    // The nearest alone, so a second look among more neighbours finds the same.
    for &(j, _) in row.iter().take(SHINGLE_NEIGHBOURS) {
        let (q, nj) = (positions[j as usize], normals[j as usize]);
        let off = q - p;
        let along = (off - off.dot(n) * n).length();
        if super::cell::off_sheet(n, nj, off, along, FAN_SLOPE)
            || along >= open
            || along > 2.0 * far
        {
            continue;
        }
        let m = 0.5 * off;
        let nj = if nj.dot(n) < 0.0 { -nj } else { nj };
        let gap = n.dot(m) - nj.dot(m - off);
        most = most.max(gap.abs());
    }
    (0.5 * GRAZING_TAN * most).min(far)
}
