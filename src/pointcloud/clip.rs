//! Straight open edges: a splat on the edge of the film its neighbours span (a free rim, a
//! rupture front, the edge of a small fragment) is cut by the lines half a spacing outside the
//! two hull edges beside it, so it can grow to cover its whole share of the film — the corners
//! of its Voronoi cell, the stretch of edge to its neighbours — without reaching further past
//! the last particles than the cut lines. Without the cut a disk small enough to stay within
//! half a spacing of the edge leaves notches between the edge particles (pinholes where a rim
//! is seen edge-on) and a triangle of film uncovered in the middle of a three-particle fragment.

use glam::{Vec2, Vec3, Vec4};

/// Two half-spaces of a disk's plane, each `(m, k)` as a [`Vec4`] (`m` unit, in the disk's
/// plane; `k` scene units): the disk keeps the points x with (x − centre)·m ≤ k in both.
pub type EdgeClip = [Vec4; 2];

/// No cut (both offsets +∞).
pub const NO_CLIP: EdgeClip = [
    Vec4::new(0.0, 0.0, 0.0, f32::INFINITY),
    Vec4::new(0.0, 0.0, 0.0, f32::INFINITY),
];

/// Whether the point at offset `x` from the disk's centre is kept by `clip`.
#[inline(always)]
pub fn keeps(clip: &EdgeClip, x: Vec3) -> bool {
    clip.iter().all(|c| x.dot(c.truncate()) <= c.w)
}

/// For a particle at the origin of its tangent plane that is a vertex of its neighbourhood's
/// hull, between hull vertices `next` and `prev` (counter-clockwise order prev → origin →
/// next), with sheet neighbours `near`: the outward unit normals of the two hull edges beside
/// it, the cut's offset (`edge_reach` × the spacing along the edge, less at a corner), and the farthest point
/// of the two edge strips it covers (half-way to the next particle along each edge, out to
/// the cut line). The spacing along an edge is the distance to the nearest neighbour within
/// 14° of the edge's direction (the hull drops particles that lie on its edges, so its next
/// vertex may be several particles along a straight rim).
pub fn edge_cut(next: Vec2, prev: Vec2, near: &[Vec2], edge_reach: f32) -> ([Vec2; 2], f32, f32) {
    let along = |e: Vec2| {
        let dir = e.normalize();
        near.iter()
            .filter(|q| q.dot(dir) > 0.0 && q.perp_dot(dir).abs() <= 0.25 * q.dot(dir))
            .map(|q| q.length())
            .fold(e.length(), f32::min)
    };
    let (ln, lp) = (along(next), along(prev));
    let m1 = Vec2::new(next.y, -next.x) / next.length();
    let m2 = Vec2::new(-prev.y, prev.x) / prev.length();
    // At a corner the two cut lines meet 1/cos(φ/2) times their offset from the vertex (φ the
    // angle between the edges' normals): offsets shrink by cos(φ/2) so no point of the splat
    // lies further than `edge_reach` spacings from the film the particles span.
    let corner_factor = (0.5 * (1.0 + m1.dot(m2))).max(0.0).sqrt();
    let reach = edge_reach * ln.min(lp) * corner_factor;
    let corner = |l: f32| (0.25 * l * l + reach * reach).sqrt();
    ([m1, m2], reach, corner(ln).max(corner(lp)))
}

/// The [`EdgeClip`] in 3D of the cut `m` (2D, in the basis `u`, `v` of the tangent plane) at
/// offset `reach`.
pub fn to_3d(m: [Vec2; 2], reach: f32, u: Vec3, v: Vec3) -> EdgeClip {
    m.map(|m| (m.x * u + m.y * v).extend(reach))
}

/// How far particle i (at the origin, `depth` inside the `hull` of its sheet neighbours
/// `near`, whose nearest hull edge is `row` long) reaches past the hull, from `reach` (half its
/// spacing): on the hull, i is cut half the shorter of the hull's edges beside it past them
/// (the cut's normals and the farthest corner of the edge strips it covers are returned), and
/// covers its cell and the edge strips to its neighbours' halves. Inside, i reaches at most
/// half a spacing of that row (or its own) past the nearest hull edge; "half" is
/// `edge_reach`.
pub fn reach_and_cut(
    hull: &[Vec2],
    near: &[Vec2],
    depth: f32,
    row: f32,
    reach: f32,
    edge_reach: f32,
) -> (f32, Option<([Vec2; 2], f32)>) {
    match hull.iter().position(|h| *h == Vec2::ZERO) {
        Some(k) if depth == 0.0 => {
            let (a, b) = (
                hull[(k + 1) % hull.len()],
                hull[(k + hull.len() - 1) % hull.len()],
            );
            let (m, reach, corner) = edge_cut(a, b, near, edge_reach);
            (reach, Some((m, corner)))
        }
        _ => (reach.min(edge_reach * row), None),
    }
}

/// For a particle at the origin inside the `hull` of its sheet neighbours (not on it), the cut
/// that lets its disk grow past the reach of a plain disk, `reach` beyond the nearest hull edge,
/// while keeping every point of it within `reach` of the hull: the lines `reach` outside the
/// two hull edges nearest to it (their outward unit normals and offsets from the particle),
/// and the largest radius the cut disk may have — `reach` past every other edge, and
/// √(|v|² + reach²) for every hull vertex v (a point past the corner at v lies at least that
/// far from the particle when it is more than `reach` from v). Where the two edges meet at a
/// vertex at an angle of 90° or more, the cut lines bound the corner there themselves (they
/// meet within √2 × `reach` of it, as an edge particle's meet near its own vertex,
/// [`edge_cut`]), so that vertex bounds no radius: a neighbour a fraction of a spacing away
/// on the nearest edge no longer trims the disk to that fraction. A particle one row in from a
/// torn edge, trimmed to `reach` past it, may then be round on the film side and
/// straight at the edge. `None` for a hull of fewer than three vertices or the origin on it.
pub fn inner_cut(hull: &[Vec2], reach: f32) -> Option<([(Vec2, f32); 2], f32)> {
    let n = hull.len();
    if n < 3 || hull.contains(&Vec2::ZERO) {
        return None;
    }
    // Each edge's outward normal, the particle's distance to its line, and its first vertex.
    let mut edges: Vec<(Vec2, f32, usize)> = (0..n)
        .filter_map(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % n]);
            let e = b - a;
            let m = Vec2::new(e.y, -e.x).try_normalize()?;
            Some((m, a.dot(m).max(0.0), k))
        })
        .collect();
    if edges.len() < 3 {
        return None;
    }
    edges.sort_by(|a, b| a.1.total_cmp(&b.1));
    // The vertex the two nearest edges share, if they are neighbours on the hull.
    let (k0, k1) = (edges[0].2, edges[1].2);
    let shared = [
        ((k0 + 1) % n == k1).then_some(k1),
        ((k1 + 1) % n == k0).then_some(k0),
    ]
    .into_iter()
    .flatten()
    .next();
    // cos(φ/2), φ the angle between the two edges' normals: the lines meet `reach` / cos(φ/2)
    // past the vertex; at most √2 × `reach` (φ ≤ 90°), else the vertex bounds the radius.
    let meet = (0.5 * (1.0 + edges[0].0.dot(edges[1].0))).max(0.0).sqrt();
    let shared = shared.filter(|_| meet >= std::f32::consts::FRAC_1_SQRT_2 - 1e-6);
    let past_edges = edges[2..].iter().map(|e| e.1 + reach);
    let past_corners = (0..n)
        .filter(|k| Some(*k) != shared)
        .map(|k| (hull[k].length_squared() + reach * reach).sqrt());
    let most = past_edges.chain(past_corners).fold(f32::INFINITY, f32::min);
    let cut = [edges[0], edges[1]].map(|(m, d, _)| (m, d + reach));
    Some((cut, most))
}

/// Whether `clip` removes any part of a disk: a cut with a half-plane of non-zero normal and
/// finite offset (not [`NO_CLIP`]).
pub fn cuts(clip: &EdgeClip) -> bool {
    clip.iter()
        .any(|h| h.w.is_finite() && h.is_finite() && h.truncate() != Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cut_follows_the_edges_and_keeps_the_inside() {
        // A particle at the origin on the bottom edge of a film above the x axis (neighbours at
        // ±1 along the edge): both cuts face −y, half a spacing out.
        let (m, reach, corner) = edge_cut(Vec2::X, -Vec2::X, &[Vec2::X, -Vec2::X], 0.5);
        assert!((m[0] - Vec2::NEG_Y).length() < 1e-6 && (m[1] - Vec2::NEG_Y).length() < 1e-6);
        assert!((reach - 0.5).abs() < 1e-6 && (corner - 0.5f32.sqrt()).abs() < 1e-6);
        let clip = to_3d(m, reach, Vec3::X, Vec3::Y);
        assert!(keeps(&clip, Vec3::new(0.3, 5.0, 0.0)), "inside the film");
        assert!(
            keeps(&clip, Vec3::new(0.5, -0.49, 0.0)),
            "half a spacing out"
        );
        assert!(!keeps(&clip, Vec3::new(0.0, -0.51, 0.0)), "beyond the cut");
        assert!(keeps(&NO_CLIP, Vec3::splat(1e30)));
        // A corner of a triangle fragment: each cut faces away from its own edge.
        let (m, _, _) = edge_cut(Vec2::X, Vec2::new(0.5, 0.866), &[], 0.5);
        assert!((m[0] - Vec2::NEG_Y).length() < 1e-6, "{m:?}");
        assert!((m[1] - Vec2::new(-0.866, 0.5)).length() < 1e-3, "{m:?}");
        // A straight rim: the hull's next vertex three particles along, the spacing one.
        let rim: Vec<Vec2> = (1..4)
            .flat_map(|k| [k as f32 * Vec2::X, -(k as f32) * Vec2::X])
            .collect();
        let (_, reach, _) = edge_cut(3.0 * Vec2::X, -3.0 * Vec2::X, &rim, 0.5);
        assert!((reach - 0.5).abs() < 1e-6, "{reach}");
        // The corner of a square film (film in x, y > 0): the cut lines meet half a spacing
        // from the corner particle, no further.
        let (m, reach, _) = edge_cut(Vec2::X, Vec2::Y, &[Vec2::X, Vec2::Y, Vec2::ONE], 0.5);
        let clip = to_3d(m, reach, Vec3::X, Vec3::Y);
        let meet = Vec3::new(-reach, -reach, 0.0);
        assert!(
            keeps(&clip, meet) && (meet.length() - 0.5).abs() < 1e-5,
            "{meet}"
        );
        assert!(!keeps(&clip, 1.01 * meet));
    }

    /// Distance from `x` to the convex polygon `hull` (counter-clockwise; 0 inside).
    fn outside(hull: &[Vec2], x: Vec2) -> f32 {
        let n = hull.len();
        let inside = (0..n).all(|k| (hull[(k + 1) % n] - hull[k]).perp_dot(x - hull[k]) >= 0.0);
        if inside {
            return 0.0;
        }
        (0..n)
            .map(|k| {
                let (a, b) = (hull[k], hull[(k + 1) % n]);
                let t = ((x - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                (x - a - t * (b - a)).length()
            })
            .fold(f32::INFINITY, f32::min)
    }

    #[test]
    fn a_near_corner_between_the_two_cut_edges_bounds_no_radius() {
        use std::f32::consts::SQRT_2;
        // Bursting frame 46: a particle 0.2 spacings inside the hull, whose nearest hull edges
        // meet at a neighbour 0.36 spacings away, was trimmed to √(0.36² + reach²) ≈ 0.47 by
        // that corner, though its cut lines bound the corner as an edge particle's do: slits
        // beside it where a grazing ray passed its rolled rim. Now the farther corners and
        // edges bound it, and no kept point lies further than `reach` past the hull (√2 ×
        // `reach` beside that corner).
        let near = [
            Vec2::new(-0.2, 0.3),
            Vec2::new(-0.4, -2.0),
            Vec2::new(2.0, -2.0),
            Vec2::new(2.0, 2.5),
        ];
        let hull = super::super::cell::hull_with_origin(&near);
        let reach = 0.3;
        let (cut, most) = inner_cut(&hull, reach).unwrap();
        assert!(most > 2.0, "{most}");
        let hull_vertex = near[0];
        let kept = |x: Vec2| cut.iter().all(|(m, k)| x.dot(*m) <= *k);
        for a in 0..360 {
            for s in 1..=60 {
                let a = a as f32 * std::f32::consts::TAU / 360.0;
                let x = s as f32 / 60.0 * most * Vec2::new(a.cos(), a.sin());
                let past = outside(&hull, x);
                let corner = (x - hull_vertex).length() <= SQRT_2 * reach;
                assert!(!kept(x) || past <= reach * 1.0001 || corner, "{x}");
                assert!(!kept(x) || past <= SQRT_2 * reach * 1.0001, "{x}");
            }
        }
    }

    #[test]
    fn an_inner_cut_keeps_the_hull_and_reaches_no_further_past_it() {
        use std::f32::consts::SQRT_2;
        // Brute force over random hulls around a particle inside them: every point of the cut
        // disk lies within `reach` of the hull (√2 × `reach` at the corner the cut lines meet
        // past), and the cut keeps the whole hull.
        let mut seed = 0x2545_f491u32;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        let mut tried = 0;
        for _ in 0..400 {
            let near: Vec<Vec2> = (0..3 + (rnd() * 9.0) as usize)
                .map(|_| {
                    let a = std::f32::consts::TAU * rnd();
                    (0.3 + 1.5 * rnd()) * Vec2::new(a.cos(), a.sin())
                })
                .collect();
            let hull = super::super::cell::hull_with_origin(&near);
            let reach = 0.1 + 0.6 * rnd();
            let Some((cut, most)) = inner_cut(&hull, reach) else {
                assert!(hull.len() < 3 || hull.contains(&Vec2::ZERO));
                continue;
            };
            tried += 1;
            let kept = |x: Vec2| cut.iter().all(|(m, k)| x.dot(*m) <= *k);
            for a in 0..90 {
                for s in 1..=30 {
                    let (a, s) = (a as f32 * std::f32::consts::TAU / 90.0, s as f32 / 30.0);
                    let x = s * most * Vec2::new(a.cos(), a.sin());
                    if kept(x) {
                        // Within `reach` of the hull; within √2 × `reach` beside a vertex the
                        // two cut lines meet past.
                        let past = outside(&hull, x);
                        let corner = hull.iter().any(|v| (x - *v).length() <= SQRT_2 * reach);
                        let most_past = if corner { SQRT_2 * reach } else { reach };
                        assert!(
                            past <= most_past * 1.0001,
                            "{past} > {reach} at {x} of {hull:?}"
                        );
                    }
                }
            }
            assert!(hull.iter().all(|v| kept(*v)), "{cut:?} cuts {hull:?}");
        }
        assert!(tried > 100, "{tried}");
    }
}
