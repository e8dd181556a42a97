//! A particle's share of the film in its tangent plane: its Voronoi cell among its neighbours,
//! cut to the convex hull of the neighbourhood — the part of the surface nearer to the particle
//! than to any other, and inside the film the particles span. The radius fit
//! ([`super::gaps`]) sizes each splat from it.
//!
//! All coordinates are 2D offsets from the particle (at the origin), scene units.

use glam::{Vec2, Vec3};

/// Reusable buffers for one particle's polygons, so a fit over a million particles allocates
/// once a worker instead of some thirty times a particle. The `_into` functions below compute
/// exactly what their allocating namesakes do, operation for operation.
#[derive(Debug, Default)]
pub struct CellScratch {
    /// The polygon being clipped, then the result.
    pub poly: Vec<Vec2>,
    /// The other half of the double buffer.
    spare: Vec<Vec2>,
    /// Points being hulled.
    pts: Vec<Vec2>,
}

/// The vertices of the cell {x : |x| ≤ |x − q| for every q in `near`} ∩ [−half, half]²: the
/// square clipped by the half-planes x·q ≤ |q|²/2 (Sutherland–Hodgman on a convex polygon).
/// Cost: O(|near| × vertices).
pub fn voronoi_cell(near: &[Vec2], half: f32) -> Vec<Vec2> {
    let mut s = CellScratch::default();
    voronoi_cell_into(near, half, &mut s);
    s.poly
}

/// [`voronoi_cell`] into `s.poly`. A neighbour farther than twice the cell's farthest vertex
/// (with a margin far above rounding) has every vertex strictly inside its half-plane, where
/// the clip returns the polygon unchanged: it is passed over, which gives the same vertices
/// (the clip would copy them) in O(1) instead of O(vertices).
pub fn voronoi_cell_into(near: &[Vec2], half: f32, s: &mut CellScratch) {
    s.poly.clear();
    s.poly.extend([
        Vec2::new(-half, -half),
        Vec2::new(half, -half),
        Vec2::new(half, half),
        Vec2::new(-half, half),
    ]);
    let mut reach2 = farthest_squared(&s.poly);
    for q in near {
        let q2 = q.length_squared();
        // |x| ≤ √reach2 and |q| ≥ 2.01 √reach2 ⇒ x·q ≤ |q|²/2.01 < |q|²/2 − rounding.
        if q2 > 4.05 * reach2 {
            continue;
        }
        let lim = 0.5 * q2;
        clip_into(&s.poly, |x| x.dot(*q) - lim, &mut s.spare);
        std::mem::swap(&mut s.poly, &mut s.spare);
        reach2 = farthest_squared(&s.poly);
    }
}

/// The largest |x|² over `poly` (0 for none).
fn farthest_squared(poly: &[Vec2]) -> f32 {
    poly.iter().map(|x| x.length_squared()).fold(0.0, f32::max)
}

/// `poly` (convex) cut to where `side(x) ≤ 0` (`side` affine), into `next` (cleared first).
fn clip_into(poly: &[Vec2], side: impl Fn(Vec2) -> f32, next: &mut Vec<Vec2>) {
    next.clear();
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let (sa, sb) = (side(a), side(b));
        if sa <= 0.0 {
            next.push(a);
        }
        if (sa < 0.0) != (sb < 0.0) && sa != sb {
            next.push(a + (b - a) * (sa / (sa - sb)));
        }
    }
}

/// The convex hull of the origin and `near`, counter-clockwise, collinear points dropped
/// (Andrew's monotone chain). Fewer than 3 vertices when every point is on one line.
pub fn hull_with_origin(near: &[Vec2]) -> Vec<Vec2> {
    let mut s = CellScratch::default();
    let mut hull = Vec::new();
    hull_with_origin_into(near, &mut s, &mut hull);
    hull
}

/// [`hull_with_origin`] into `hull`, with `s` for the sorted points. (Points equal under the
/// sort's order are the same bits, so the unstable sort orders them as a stable one would.)
pub fn hull_with_origin_into(near: &[Vec2], s: &mut CellScratch, hull: &mut Vec<Vec2>) {
    let pts = &mut s.pts;
    pts.clear();
    pts.extend(near.iter().copied().chain([Vec2::ZERO]));
    pts.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    hull.clear();
    if pts.len() < 3 {
        hull.extend_from_slice(pts);
        return;
    }
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let chain = |hull: &mut Vec<Vec2>, start: usize, p: Vec2| {
        while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
        {
            hull.pop();
        }
        hull.push(p);
    };
    for &p in pts.iter() {
        chain(hull, 0, p);
    }
    hull.pop();
    let start = hull.len();
    for &p in pts.iter().rev() {
        chain(hull, start, p);
    }
    hull.pop();
}

/// `cell` (convex) cut to the convex polygon `hull` (counter-clockwise, ≥ 3 vertices).
pub fn clip_to_hull(cell: &[Vec2], hull: &[Vec2]) -> Vec<Vec2> {
    let mut s = CellScratch::default();
    s.poly.extend_from_slice(cell);
    clip_to_hull_into(hull, &mut s);
    s.poly
}

/// [`clip_to_hull`] of `s.poly`, in place.
pub fn clip_to_hull_into(hull: &[Vec2], s: &mut CellScratch) {
    for k in 0..hull.len() {
        let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
        // Inside is to the left of a → b.
        clip_into(&s.poly, |x| -(b - a).perp_dot(x - a), &mut s.spare);
        std::mem::swap(&mut s.poly, &mut s.spare);
        if s.poly.is_empty() {
            break;
        }
    }
}

/// Distance from the origin to the boundary of the convex polygon `hull` (counter-clockwise,
/// containing the origin; 0 when the origin is on it), and the length of the edge nearest to
/// the origin (the shorter of two at the same distance).
pub fn depth_in_hull(hull: &[Vec2]) -> (f32, f32) {
    (0..hull.len())
        .map(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
            let len = (b - a).length();
            let d = if len > 0.0 {
                ((b - a).perp_dot(-a) / len).max(0.0)
            } else {
                0.0
            };
            (d, len)
        })
        .fold((f32::INFINITY, 0.0), |best, e| {
            if e.0 < best.0 || (e.0 == best.0 && e.1 < best.1) {
                e
            } else {
                best
            }
        })
}

/// The farthest midpoint of an edge of `hull` (the film's edge as i's neighbours `near` see
/// it) that makes a Delaunay triangle with i (no neighbour inside the circle through i and the
/// edge's ends): i is the particle one row in from that stretch of open edge, and covers the
/// film up to its middle, which the two edge particles' disks (half an edge each) only touch.
/// 0 when there is none.
pub fn rim_midpoints(near: &[Vec2], hull: &[Vec2]) -> f32 {
    let mut most = 0.0f32;
    for k in 0..hull.len() {
        let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
        let det = a.perp_dot(b);
        if a == Vec2::ZERO
            || b == Vec2::ZERO
            || det.abs()
                <= 1e-6 * a.length_squared() * b.length_squared()
                    / (a.length_squared() + b.length_squared())
        {
            continue;
        }
        // The circle through 0, a and b: c·a = |a|²/2, c·b = |b|²/2.
        let (ha, hb) = (0.5 * a.length_squared(), 0.5 * b.length_squared());
        let c = Vec2::new(ha * b.y - hb * a.y, hb * a.x - ha * b.x) / det;
        let r2 = c.length_squared() * (1.0 - 1e-4);
        if near
            .iter()
            .all(|q| *q == a || *q == b || (*q - c).length_squared() >= r2)
        {
            most = most.max((0.5 * (a + b)).length());
        }
    }
    most
}

/// The two smallest lengths of `near`, shortest first (the first two of them sorted; ∞ for
/// none).
pub fn two_shortest(near: &[Vec2]) -> (f32, f32) {
    let (mut d0, mut d1) = (f32::INFINITY, f32::INFINITY);
    for l in near.iter().map(|q| q.length()) {
        if l < d0 {
            (d0, d1) = (l, d0);
        } else if l < d1 {
            d1 = l;
        }
    }
    (d0, d1)
}

/// Whether a neighbour at offset `off` from a particle with unit normal `nrm`, `flat` from it
/// along the particle's tangent plane, with normal `nj`, lies off the particle's sheet: normals
/// more than 60° apart, or farther off the tangent plane than `slope` × `flat`.
pub fn off_sheet(nrm: Vec3, nj: Vec3, off: Vec3, flat: f32, slope: f32) -> bool {
    nj.dot(nrm).abs() < 0.5 || off.dot(nrm).abs() > slope * flat
}

/// How far off a particle's tangent plane a neighbour of its fan may lie, per unit distance
/// along it ([`sheet_neighbours`]).
pub const FAN_SLOPE: f32 = 1.0;

/// The neighbours in `row` on the sheet of the particle at `p` with unit normal `nrm` (normals
/// within 60°, not farther off its tangent plane than along it), nearer than `open`, as
/// offsets in its tangent plane, into `near`; returns the distance to the nearest particle of
/// `row` (∞ for none).
pub fn sheet_neighbours(
    p: Vec3,
    nrm: Vec3,
    (positions, normals): (&[Vec3], &[Vec3]),
    open: f32,
    row: &[(u32, f32)],
    near: &mut Vec<Vec2>,
) -> f32 {
    let (u, v) = nrm.any_orthonormal_pair();
    near.clear();
    let mut nearest = f32::INFINITY;
    for &(j, d) in row {
        let (q, nj) = (positions[j as usize], normals[j as usize]);
        let off = q - p;
        let flat = Vec2::new(off.dot(u), off.dot(v));
        nearest = nearest.min(d);
        if off_sheet(nrm, nj, off, flat.length(), FAN_SLOPE)
            || flat.length_squared() == 0.0
            || flat.length() >= open
        {
            continue;
        }
        near.push(flat);
    }
    nearest
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

    /// Random neighbourhoods, 3 to 64 points, some far beyond the cell.
    fn random_neighbourhoods() -> impl Iterator<Item = Vec<Vec2>> {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..3000).map(move |case| {
            let n = 3 + case % 62;
            let spread = 0.5 + 4.0 * next();
            (0..n)
                .map(|_| spread * Vec2::new(next() - 0.5, next() - 0.5))
                .filter(|q| *q != Vec2::ZERO)
                .collect()
        })
    }

    #[test]
    fn passing_over_far_neighbours_gives_the_clipped_cell_bit_for_bit() {
        // Oracle: the square clipped by every neighbour's half-plane, none passed over.
        let mut passed = 0;
        for near in random_neighbourhoods() {
            let half = 2.5;
            let mut s = CellScratch::default();
            s.poly.extend([
                Vec2::new(-half, -half),
                Vec2::new(half, -half),
                Vec2::new(half, half),
                Vec2::new(-half, half),
            ]);
            for q in &near {
                let lim = 0.5 * q.length_squared();
                clip_into(&s.poly, |x| x.dot(*q) - lim, &mut s.spare);
                std::mem::swap(&mut s.poly, &mut s.spare);
            }
            let fast = voronoi_cell(&near, half);
            let bits = |c: &[Vec2]| {
                c.iter()
                    .map(|v| v.to_array().map(f32::to_bits))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&fast), bits(&s.poly), "{near:?}");
            let reach = farthest_squared(&fast);
            passed += near
                .iter()
                .filter(|q| q.length_squared() > 4.05 * reach)
                .count();
        }
        // The shortcut is taken (else this test would not test it).
        assert!(passed > 10_000, "{passed}");
    }

    #[test]
    fn the_reused_buffers_give_the_allocating_hull_and_clip() {
        // One scratch carried from neighbourhood to neighbourhood, as a fit's worker does.
        let mut s = CellScratch::default();
        let mut hull = Vec::new();
        for near in random_neighbourhoods() {
            hull_with_origin_into(&near, &mut s, &mut hull);
            // Andrew's monotone chain written out again with fresh vectors and a stable sort.
            let mut pts: Vec<Vec2> = near.iter().copied().chain([Vec2::ZERO]).collect();
            pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
            pts.dedup();
            let mut want: Vec<Vec2> = Vec::new();
            for pass in [pts.clone(), pts.iter().rev().copied().collect()] {
                let start = want.len();
                for p in pass {
                    while want.len() >= start + 2
                        && (want[want.len() - 1] - want[want.len() - 2])
                            .perp_dot(p - want[want.len() - 2])
                            <= 0.0
                    {
                        want.pop();
                    }
                    want.push(p);
                }
                want.pop();
            }
            assert_eq!(hull, want, "{near:?}");
            voronoi_cell_into(&near, 2.5, &mut s);
            let cell = s.poly.clone();
            clip_to_hull_into(&hull, &mut s);
            assert_eq!(s.poly, clip_to_hull(&cell, &hull));
        }
    }

    #[test]
    fn the_hull_stops_an_open_cell_at_the_last_row() {
        // A particle on the bottom row of a unit square lattice: nothing below it.
        let near = [
            Vec2::X,
            -Vec2::X,
            Vec2::Y,
            Vec2::new(1.0, 1.0),
            Vec2::new(-1.0, 1.0),
        ];
        let hull = hull_with_origin(&near);
        // On the hull's bottom edge (between its row neighbours, so not a vertex of it).
        assert_eq!(depth_in_hull(&hull), (0.0, 2.0), "{hull:?}");
        let cell = clip_to_hull(&voronoi_cell(&near, 10.0), &hull);
        let low = cell.iter().map(|c| c.y).fold(f32::INFINITY, f32::min);
        let far = cell.iter().map(|c| c.length()).fold(0.0, f32::max);
        assert!(
            low.abs() < 1e-6 && (far - 0.5f32.sqrt()).abs() < 1e-5,
            "{cell:?}"
        );
        // The same particle one row up is inside, as far from the hull's edge as the diagonal
        // between its side and top neighbours.
        let mut up: Vec<Vec2> = near.iter().map(|q| *q - Vec2::Y).collect();
        up.retain(|q| *q != Vec2::ZERO);
        up.push(Vec2::new(0.0, 1.0));
        let hull = hull_with_origin(&up);
        let (depth, edge) = depth_in_hull(&hull);
        assert!(
            (depth - 0.5f32.sqrt()).abs() < 1e-6 && (edge - 2f32.sqrt()).abs() < 1e-6,
            "{hull:?}"
        );
        // Collinear points have no area.
        assert!(hull_with_origin(&[Vec2::X, -Vec2::X, 2.0 * Vec2::X]).len() < 3);
    }
}
