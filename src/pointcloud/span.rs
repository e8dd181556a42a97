//! Where the particles themselves hold film: the question the pinhole metric asks of a pixel
//! that shows no film (or film far behind its neighbours'), so a hole the renderer opened is
//! told from a hole, a torn rim or an open edge that is in the data.
//!
//! A ray crosses the film the particles span if it passes a particle i within one spacing,
//! crosses i's tangent plane within one spacing of it, and that crossing lies inside the convex
//! hull of the particles around it on i's sheet (within [`HULL_REACH`] spacings, normals within
//! 60°, less than two spacings off i's plane) by more than [`INSIDE`] spacings: the same oracle
//! as `tests/film_coverage.rs`. Gaps narrower than 2 × [`HULL_REACH`] spacings count as film
//! (the hull bridges them), so the test never hides a hole the renderer opened inside a sheet.
//! Where the simulator stores each particle's area A ([`FilmSpan::with_own_radii`]), a
//! crossing must also lie within [`AREA_OVERLAP`] × √(A/π) of a particle of the sheet: the
//! particles of a torn fragment, far apart for their size, span no film between them.

use glam::{Vec2, Vec3};

use super::area::AREA_OVERLAP;
use super::estimate::median_spacing;
use super::knn::PointIndex;

/// Radius, in spacings, of the neighbourhood whose hull is the film around a crossing.
pub const HULL_REACH: f32 = 4.0;

/// How deep inside that hull, in spacings, a crossing must lie to be in the data's film.
pub const INSIDE: f32 = 0.1;

/// Particles searched around each step along a ray.
const STEP_NEIGHBOURS: usize = 8;

/// Particles whose hull is built around a crossing.
const HULL_NEIGHBOURS: usize = 40;

/// Most steps along one ray (a ray through a cloud many thousand spacings long is cut there).
const MAX_STEPS: usize = 100_000;

/// The film a set of oriented particles spans (positions and unit normals, one each).
pub struct FilmSpan<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    index: PointIndex,
    /// The cloud's median nearest-neighbour spacing, scene units.
    spacing: f32,
    lo: Vec3,
    hi: Vec3,
    /// Each particle's own radius √(A/π) (empty or 0: unknown).
    own: Vec<f32>,
}

impl<'a> FilmSpan<'a> {
    /// Indexes the particles. Cost: one k-d tree build and a spacing estimate, O(n log n).
    pub fn new(positions: &'a [Vec3], normals: &'a [Vec3]) -> Self {
        let finite = positions.iter().filter(|p| p.is_finite());
        let (lo, hi) = finite.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), p| {
            (l.min(*p), h.max(*p))
        });
        FilmSpan {
            positions,
            normals,
            index: PointIndex::build(positions),
            spacing: median_spacing(positions),
            lo,
            hi,
            own: Vec::new(),
        }
    }

    /// The particles' own radii √(A/π) (from `super::area::own_radii`; one a particle, 0 for
    /// unknown; empty for none).
    pub fn with_own_radii(mut self, own: Vec<f32>) -> Self {
        self.own = own;
        self
    }

    /// The median spacing the tests are measured in, scene units.
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// Whether the ray `origin + t·dir` (`dir` unit) crosses the particles' film at some
    /// 0 < t < `t_max` (see the module docs). Cost: O(length / spacing) neighbour searches,
    /// plus a hull of `HULL_NEIGHBOURS` for each particle passed.
    pub fn crosses(&self, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        let s = self.spacing;
        if s.is_nan() || s <= 0.0 || self.positions.len() != self.normals.len() || !dir.is_finite()
        {
            return false;
        }
        // The stretch of the ray inside the cloud's box grown by a spacing.
        let (lo, hi) = (self.lo - Vec3::splat(s), self.hi + Vec3::splat(s));
        let inv = dir.recip();
        let (a, b) = ((lo - origin) * inv, (hi - origin) * inv);
        let t0 = a.min(b).max_element().max(0.0);
        let t1 = a.max(b).min_element().min(t_max);
        if t0.is_nan() || t1.is_nan() || t0 >= t1 {
            return false;
        }
        let mut seen: Vec<u32> = Vec::new();
        let steps = (((t1 - t0) / s).ceil() as usize + 1).min(MAX_STEPS);
        for k in 0..steps {
            let t = t0 + k as f32 * s;
            for (j, _) in self
                .index
                .nearest_excluding(origin + t * dir, STEP_NEIGHBOURS, u32::MAX)
            {
                if seen.contains(&j) {
                    continue;
                }
                seen.push(j);
                if self.crossing_inside(j as usize, origin, dir, t_max) {
                    return true;
                }
            }
            if seen.len() > 64 {
                seen.drain(..32);
            }
        }
        false
    }

    /// Whether the ray crosses particle `i`'s tangent plane within a spacing of it, before
    /// `t_max`, inside the hull of its sheet.
    fn crossing_inside(&self, i: usize, origin: Vec3, dir: Vec3, t_max: f32) -> bool {
        let s = self.spacing;
        let (p, n) = (self.positions[i], self.normals[i].normalize_or_zero());
        let cos = n.dot(dir);
        if n == Vec3::ZERO || cos.abs() < 1e-4 {
            return false;
        }
        let t = n.dot(p - origin) / cos;
        let x = origin + t * dir;
        if !(t > 0.0 && t < t_max) || (x - p).length() > s {
            return false;
        }
        let (u, v) = n.any_orthonormal_pair();
        let mut covered = self.own.is_empty();
        let flat: Vec<Vec2> = self
            .index
            .nearest_excluding(x, HULL_NEIGHBOURS, u32::MAX)
            .into_iter()
            .filter_map(|(j, _)| {
                let off = self.positions[j as usize] - x;
                let nj = self.normals[j as usize].normalize_or_zero();
                let q = Vec2::new(off.dot(u), off.dot(v));
                let own = self.own.get(j as usize).copied().unwrap_or(0.0);
                covered |= own.is_nan() || own <= 0.0 || q.length() <= AREA_OVERLAP * own;
                (nj.dot(n).abs() > 0.5 && off.dot(n).abs() < 2.0 * s).then_some(q)
            })
            .filter(|q| q.length() < HULL_REACH * s)
            .collect();
        if !covered {
            return false;
        }
        let hull = super::cell::hull_with_origin(&flat);
        // The origin (x) is one of the hull's points: it is inside the particles' hull only if
        // it is no vertex of it, and then as deep as its distance to the nearest edge.
        hull.len() >= 3
            && !hull.contains(&Vec2::ZERO)
            && super::cell::depth_in_hull(&hull).0 > INSIDE * s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hole_in_the_data_is_no_film_and_the_film_around_it_is() {
        // A 30×30 grid of spacing 1 in z = 0 with a 6×6 hole; rays straight down.
        let pos: Vec<Vec3> = (0..900)
            .map(|i| Vec3::new((i % 30) as f32, (i / 30) as f32, 0.0))
            .filter(|p| !(12.0..18.0).contains(&p.x) || !(12.0..18.0).contains(&p.y))
            .collect();
        let normals = vec![Vec3::Z; pos.len()];
        let span = FilmSpan::new(&pos, &normals);
        let down = |x: f32, y: f32, t_max: f32| span.crosses(Vec3::new(x, y, 5.0), -Vec3::Z, t_max);
        assert!(down(5.3, 6.7, f32::INFINITY), "inside the sheet");
        assert!(!down(14.5, 14.5, f32::INFINITY), "the hole's middle");
        assert!(!down(40.0, 5.0, f32::INFINITY), "beyond the edge");
        assert!(!down(-0.05, 5.5, f32::INFINITY), "just past the last row");
        assert!(!down(5.3, 6.7, 4.0), "the film lies beyond t_max");
        // Seen at a grazing angle, through the sheet: still film.
        let dir = Vec3::new(1.0, 0.0, -0.05).normalize();
        assert!(span.crosses(Vec3::new(-20.0, 6.5, 1.25), dir, f32::INFINITY));
        // Particles of area radius 0.2 a spacing apart: film only within 0.4 of one.
        let span = FilmSpan::new(&pos, &normals).with_own_radii(vec![0.2; pos.len()]);
        let down = |x: f32, y: f32| span.crosses(Vec3::new(x, y, 5.0), -Vec3::Z, f32::INFINITY);
        assert!(down(5.3, 6.0) && !down(5.5, 6.5));
    }
}
