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
//! crossing must also lie in the film those areas hold: within the crossed particle's own
//! radius √(A/π) of it (its area is film), or where the areas of the sheet's particles, spread by a
//! normalised kernel, cover at least half the plane ([`area_coverage`], the SPH estimate of
//! how much of the plane is film: about 1 inside an intact sheet, ½ on its last row) and at
//! least three particles reach it. The particles of a torn fragment, far apart for their size
//! or too few to span a sheet, hold film only within their own radii.

use glam::{Vec2, Vec3};

use super::estimate::median_spacing;
use super::knn::PointIndex;

/// Radius, in spacings, of the neighbourhood whose hull is the film around a crossing.
pub const HULL_REACH: f32 = 4.0;

/// How deep inside that hull, in spacings, a crossing must lie to be in the data's film.
pub const INSIDE: f32 = 0.1;

/// Support radius of the kernel that spreads a particle's area ([`area_coverage`]), as a
/// multiple of its own radius √(A/π): 3 reaches the six nearest of a hexagonal sampling
/// (spacing 1.9 × √(A/π)), not the next ring.
pub const COVER_SUPPORT: f32 = 3.0;

/// Least share of the plane the particles' areas cover where the data holds film (an intact
/// sheet: about 1; the line through its last row: ½).
pub const COVER_FILM: f32 = 0.5;

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
        // Particle i's own area is film (other particles' own disks are met when the ray
        // passes them); beyond it, the areas spread around x must cover the plane.
        let within_own = self.own.get(i).is_some_and(|o| (x - p).length() <= *o);
        let (mut unknown, mut cover) = (self.own.is_empty(), Cover::default());
        let flat: Vec<Vec2> = self
            .index
            .nearest_excluding(x, HULL_NEIGHBOURS, u32::MAX)
            .into_iter()
            .filter_map(|(j, _)| {
                let off = self.positions[j as usize] - x;
                let nj = self.normals[j as usize].normalize_or_zero();
                let q = Vec2::new(off.dot(u), off.dot(v));
                let sheet = nj.dot(n).abs() > 0.5 && off.dot(n).abs() < 2.0 * s;
                let own = self.own.get(j as usize).copied().unwrap_or(0.0);
                unknown |= own.is_nan() || own <= 0.0;
                if sheet && own > 0.0 {
                    cover.add(off.length(), own);
                }
                sheet.then_some(q)
            })
            .filter(|q| q.length() < HULL_REACH * s)
            .collect();
        if !(unknown || within_own || cover.is_film()) {
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

/// The particles' areas spread around a point ([`area_coverage`]): their sum, and how many
/// particles reach it.
#[derive(Debug, Default, Clone, Copy)]
struct Cover {
    share: f32,
    particles: usize,
}

impl Cover {
    /// Adds a particle of own radius `own` at distance `r`.
    fn add(&mut self, r: f32, own: f32) {
        let w = area_coverage(r, own);
        self.share += w;
        self.particles += usize::from(w > 0.0);
    }

    /// Film: at least [`COVER_FILM`] of the plane covered, by at least three particles (fewer
    /// span no sheet, as in the radius fit's strands: a fragment of two holds film only
    /// within each one's own radius).
    fn is_film(&self) -> bool {
        self.particles >= 3 && self.share >= COVER_FILM
    }
}

/// The share of the plane at distance `r` from a particle of own radius `own` = √(A/π) that
/// its area covers: A × W(r), W the 2D Wendland C2 kernel of support h = [`COVER_SUPPORT`] ×
/// `own` (W(r) = 7/(πh²) (1 − r/h)⁴ (1 + 4r/h), which integrates to 1 over the plane;
/// Wendland 1995). Summed over the particles around a point: the SPH estimate of how much of
/// the plane there is film.
pub fn area_coverage(r: f32, own: f32) -> f32 {
    let h = COVER_SUPPORT * own;
    let q = r / h;
    if q.is_nan() || q >= 1.0 {
        return 0.0;
    }
    7.0 / (COVER_SUPPORT * COVER_SUPPORT) * (1.0 - q).powi(4) * (1.0 + 4.0 * q)
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
        // Particles of area radius 0.2 a spacing apart (their areas cover an eighth of the
        // plane): film only within their own radius.
        let span = FilmSpan::new(&pos, &normals).with_own_radii(vec![0.2; pos.len()]);
        let down = |x: f32, y: f32| span.crosses(Vec3::new(x, y, 5.0), -Vec3::Z, f32::INFINITY);
        assert!(down(5.15, 6.0) && !down(5.3, 6.0) && !down(5.5, 6.5));
        // Areas that tile the plane (A = spacing²): film everywhere inside, the cells' corners
        // (1.25 × √(A/π) from every particle) included; not past the last row.
        let own = 1.0 / std::f32::consts::PI.sqrt();
        let span = FilmSpan::new(&pos, &normals).with_own_radii(vec![own; pos.len()]);
        let down = |x: f32, y: f32| span.crosses(Vec3::new(x, y, 5.0), -Vec3::Z, f32::INFINITY);
        assert!(down(5.5, 6.5) && down(20.5, 3.5) && !down(14.5, 14.5) && !down(-0.3, 5.5));
    }

    #[test]
    fn areas_that_tile_the_plane_cover_it_once() {
        // Partition of unity: on a square grid of spacing 1 with A = 1 (√(A/π) = 0.564), the
        // kernel-spread areas sum to 1 everywhere (independent of where in the cell), within
        // a tenth.
        let own = 1.0 / std::f32::consts::PI.sqrt();
        for (x, y) in [(0.0, 0.0), (0.5, 0.5), (0.3, 0.1), (0.25, 0.7)] {
            let sum: f32 = (-4..=4)
                .flat_map(|i| (-4..=4).map(move |j| (i as f32 - x, j as f32 - y)))
                .map(|(dx, dy)| area_coverage((dx * dx + dy * dy).sqrt(), own))
                .sum();
            assert!((sum - 1.0).abs() < 0.1, "({x}, {y}): {sum}");
        }
        // At the particle: A × 7/(πh²) = 7/9 with h = 3 × √(A/π).
        assert!((area_coverage(0.0, own) - 7.0 / 9.0).abs() < 1e-6);
        assert_eq!(area_coverage(COVER_SUPPORT * own, own), 0.0);
    }
}
