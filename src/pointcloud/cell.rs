//! A particle's share of the film in its tangent plane: its Voronoi cell among its neighbours,
//! cut to the convex hull of the neighbourhood — the part of the surface nearer to the particle
//! than to any other, and inside the film the particles span. The radius fit
//! ([`super::gaps`]) sizes each splat from it.
//!
//! All coordinates are 2D offsets from the particle (at the origin), scene units.

use glam::{Vec2, Vec3};

/// The vertices of the cell {x : |x| ≤ |x − q| for every q in `near`} ∩ [−half, half]²: the
/// square clipped by the half-planes x·q ≤ |q|²/2 (Sutherland–Hodgman on a convex polygon).
/// Cost: O(|near| × vertices).
pub fn voronoi_cell(near: &[Vec2], half: f32) -> Vec<Vec2> {
    let poly = vec![
        Vec2::new(-half, -half),
        Vec2::new(half, -half),
        Vec2::new(half, half),
        Vec2::new(-half, half),
    ];
    near.iter().fold(poly, |poly, q| {
        let lim = 0.5 * q.length_squared();
        clip(&poly, |x| x.dot(*q) - lim)
    })
}

/// `poly` (convex) cut to where `side(x) ≤ 0` (`side` affine).
fn clip(poly: &[Vec2], side: impl Fn(Vec2) -> f32) -> Vec<Vec2> {
    let mut next = Vec::with_capacity(poly.len() + 2);
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
    next
}

/// The convex hull of the origin and `near`, counter-clockwise, collinear points dropped
/// (Andrew's monotone chain). Fewer than 3 vertices when every point is on one line.
pub fn hull_with_origin(near: &[Vec2]) -> Vec<Vec2> {
    let mut pts: Vec<Vec2> = near.iter().copied().chain([Vec2::ZERO]).collect();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<Vec2> = Vec::with_capacity(2 * pts.len());
    for pass in [false, true] {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vec2>> = if pass {
            Box::new(pts.iter().rev())
        } else {
            Box::new(pts.iter())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// `cell` (convex) cut to the convex polygon `hull` (counter-clockwise, ≥ 3 vertices).
pub fn clip_to_hull(cell: &[Vec2], hull: &[Vec2]) -> Vec<Vec2> {
    let mut poly = cell.to_vec();
    for k in 0..hull.len() {
        let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
        // Inside is to the left of a → b.
        poly = clip(&poly, |x| -(b - a).perp_dot(x - a));
        if poly.is_empty() {
            break;
        }
    }
    poly
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

/// The neighbours in `row` on the sheet of the particle at `p` with unit normal `nrm` (normals
/// within 60°, not farther off its tangent plane than along it), nearer than `open`, as
/// offsets in its tangent plane; and the distance to the nearest particle of `row` (∞ for
/// none).
pub fn sheet_neighbours(
    p: Vec3,
    nrm: Vec3,
    positions: &[Vec3],
    normals: &[Vec3],
    open: f32,
    row: &mut dyn Iterator<Item = (u32, f32)>,
) -> (Vec<Vec2>, f32) {
    let (u, v) = nrm.any_orthonormal_pair();
    let mut near: Vec<Vec2> = Vec::with_capacity(16);
    let mut nearest = f32::INFINITY;
    for (j, d) in row {
        let (q, nj) = (positions[j as usize], normals[j as usize]);
        let off = q - p;
        let flat = Vec2::new(off.dot(u), off.dot(v));
        nearest = nearest.min(d);
        if nj.dot(nrm).abs() < 0.5
            || off.dot(nrm).abs() > flat.length()
            || flat.length_squared() == 0.0
            || flat.length() >= open
        {
            continue;
        }
        near.push(flat);
    }
    (near, nearest)
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
