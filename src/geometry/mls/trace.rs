//! Ray–MLS-surface intersection: support intervals from the BVH, a distance-guided march with a
//! grazing check, and bracketed refinement (see the parent module's docs).

use super::MlsSurface;
use super::band;
use super::field::{self, Cand, Chord};
use super::gathered::{GATHERED, QueryKey, sort_by_entry};
use crate::geometry::{Ray, SurfaceHit};

/// Smallest march step, particle radii (near the surface, where |f| is small).
const MIN_STEP: f32 = 0.05;
/// Largest march step, particle radii.
const MAX_STEP: f32 = 1.0;
/// Steps are this fraction of |f| between the two bounds (f is about a distance).
const STEP_OF_F: f32 = 0.9;
/// A crossing is refined until its bracket is narrower than this many particle radii.
const TOLERANCE: f32 = 1e-3;
/// Upper bound on march steps per interval (a guard; ordinary intervals take tens).
const MAX_MARCH: usize = 1 << 16;
/// Upper bound on refinement iterations (two per halving of the bracket at worst).
const MAX_REFINE: usize = 64;

/// A sample of f along the ray: (t, f).
type Sample = (f32, f32);

impl MlsSurface {
    /// The first crossing of the surface with `t_min < t < t_max`. `t_exit` is the far end of the
    /// final bracket (at most 10⁻³ radii beyond `t`), so a ray continued from
    /// `t_exit + eps` never finds the same crossing again. Cost: one near-first BVH traversal
    /// collecting every support sphere the ray crosses in `(t_min, t_max)` (none when the query
    /// continues the previous one on this thread along the same ray, whose spheres are kept),
    /// then per support interval up to the crossing O(spheres) to bound where the tangent
    /// planes allow a crossing (see the `band` module) and ~3–6 evaluations of f inside that
    /// band, each over the spheres covering that point.
    /// Where [`MlsSurface::set_own_disks`] gave the particles disks that the surface may leave
    /// bare, a crossing of such a disk with no crossing of the surface near it comes first
    /// (the `fallback` module); a surface without them pays nothing for that.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        if !ray.is_valid() || t_min.is_nan() || t_max.is_nan() || t_min >= t_max {
            return None;
        }
        if self.fallback.is_empty() {
            return self.gathered_hit::<false>(ray, t_min, t_max).0;
        }
        let (hit, crossed) = self.gathered_hit::<true>(ray, t_min, t_max);
        self.with_own_disks(ray, (t_min, t_max), hit, crossed)
    }

    /// The first crossing of the surface alone (see [`MlsSurface::intersect`]).
    pub(super) fn surface_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        if t_min >= t_max {
            return None;
        }
        self.gathered_hit::<true>(ray, t_min, t_max).0
    }

    /// The first crossing of the surface in `(t_min, t_max)` (`t_min < t_max`) from the
    /// spheres this thread keeps for the ray or gathers now; with `TRACK`, also the crossing
    /// found by the last such query if it was on the same ray (NaN if none), and this one kept
    /// for the next (without, the crossing returned is NaN and none is kept).
    fn gathered_hit<const TRACK: bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> (Option<SurfaceHit>, f32) {
        GATHERED.with_borrow_mut(|g| {
            let key = QueryKey::new(self.id, ray, t_max);
            let crossed = if TRACK && g.key == Some(key) {
                g.crossed
            } else {
                f32::NAN
            };
            if g.key == Some(key) && t_min >= g.from {
                // The same ray further on: the spheres it is still inside or enters later are
                // exactly the kept ones that end beyond `t_min`.
                g.cands.retain_mut(|c| {
                    c.ta = c.ta.max(t_min);
                    c.ta < c.tb
                });
            } else {
                self.gather_all(ray, t_min, t_max, &mut g.cands);
                g.key = Some(key);
            }
            g.from = t_min;
            let hit = self.march_sheets(ray, &mut g.cands);
            if TRACK {
                g.crossed = hit.map_or(crossed, |h| h.t);
            }
            (hit, crossed)
        })
    }

    /// The candidate record of the sphere in `slot` if the ray is inside it somewhere in
    /// `(t_min, t_max)` (the scalar form of the gathering, for tests).
    #[cfg(test)]
    fn clipped(&self, ray: &Ray, slot: u32, t_min: f32, t_max: f32) -> Option<Cand> {
        let q = &self.particles[slot as usize];
        let (ta, tb) = clip(ray, q.p, q.h, t_min, t_max)?;
        Some(self.cand_on(ray, slot, ta, tb))
    }

    /// The candidate record of the sphere in `slot`, which the ray is inside for `ta..=tb`.
    #[cfg(test)]
    fn cand_on(&self, ray: &Ray, slot: u32, ta: f32, tb: f32) -> Cand {
        let q = &self.particles[slot as usize];
        // The chord as `sphere_roots` computes it: b = d·(p − o), k2 = h² − |perpendicular|².
        let f = ray.origin - q.p;
        let b = -f.dot(ray.dir);
        let chord = Chord {
            ta,
            tb,
            b,
            k2: q.h * q.h - (f + b * ray.dir).length_squared(),
            inv_h2: 1.0 / (q.h * q.h),
            r: q.h / self.params.support,
        };
        self.cand_chord(ray, slot, chord)
    }

    /// The candidate record of the sphere in `slot` from its chord along the ray, computed
    /// already (by `cand_on`, or four at a time by the gathering).
    #[inline(always)]
    pub(super) fn cand_chord(&self, ray: &Ray, slot: u32, c: Chord) -> Cand {
        let q = &self.particles[slot as usize];
        Cand {
            p: q.p,
            inv_h2: c.inv_h2,
            n: q.n,
            thickness: q.thickness,
            ta: c.ta,
            tb: c.tb,
            slot,
            r: c.r,
            g0: q.n.dot(ray.origin - q.p),
            g1: q.n.dot(ray.dir),
            b: c.b,
            k2: c.k2,
        }
    }

    /// Sorts `cands` and marches the union of their support intervals, one connected piece at a
    /// time, returning the first valid crossing; inside each piece only the band where the
    /// tangent planes allow a crossing is marched. `cands` holds every sphere along the part of
    /// the ray queried, so each interval is complete. Intervals starting beyond `stop` (a
    /// crossing is already known there) are not marched.
    pub(super) fn march_all(&self, ray: &Ray, cands: &mut [Cand], stop: f32) -> Option<SurfaceHit> {
        sort_by_entry(cands);
        let mut i = 0;
        while i < cands.len() {
            let (s0, mut s1, mut r) = (cands[i].ta, cands[i].tb, cands[i].r);
            if s0 > stop {
                break;
            }
            let mut j = i + 1;
            while j < cands.len() && cands[j].ta <= s1 {
                s1 = s1.max(cands[j].tb);
                r = r.min(cands[j].r);
                j += 1;
            }
            let piece = &cands[i..j];
            let tol = tolerance(ray, s1, r);
            if let Some((u, v)) = band::sign_band(piece, s0, s1, tol) {
                let (u, v) = ((u - tol).max(s0), (v + tol).min(s1));
                // f inside the band: the spheres entered by its end, from the first still
                // covering its start (those before it never cover a point of the band).
                let last = piece.partition_point(|c| c.ta <= v);
                let first = piece[..last].iter().position(|c| c.tb >= u).unwrap_or(last);
                if let Some(hit) = self.march(ray, &piece[first..last], u, v, r, tol) {
                    return Some(hit);
                }
            }
            i = j;
        }
        None
    }

    /// The first valid crossing in `[s0, s1]` (part of a support interval covered by `cands`,
    /// whose smallest particle radius is `r`), refined to `tol`. f is sampled at both ends
    /// first: opposite signs across at most one march step are refined at once; otherwise the
    /// march from `s0` stops as soon as the step rule (no zero within `STEP_OF_F`·|f| of a
    /// sample) leaves no room for one before `s1`.
    fn march(
        &self,
        ray: &Ray,
        cands: &[Cand],
        s0: f32,
        s1: f32,
        r: f32,
        tol: f32,
    ) -> Option<SurfaceHit> {
        let (min_step, max_step) = (MIN_STEP * r, MAX_STEP * r);
        let min_step = min_step.max(2.0 * tol);
        let f_at = |t: f32| field::value_on_ray(cands, t);
        let end: Option<Sample> = f_at(s1).map(|f| (s1, f));
        let (mut prev, mut prev2): (Option<Sample>, Option<Sample>) = (None, None);
        let mut t = s0;
        for _ in 0..MAX_MARCH {
            let f = if t >= s1 { end.map(|e| e.1) } else { f_at(t) };
            let step = match f {
                Some(f) => {
                    let cur = (t, f);
                    if let Some(p) = prev {
                        if let Some(p2) = prev2
                            && let Some(hit) = self.grazing(ray, cands, p2, p, cur, max_step, tol)
                        {
                            return Some(hit);
                        }
                        if (p.1 < 0.0) != (f < 0.0)
                            && let Some(hit) = self.crossing(ray, cands, p, cur, tol)
                        {
                            return Some(hit);
                        }
                    }
                    if let Some(e) = end
                        && t < s1
                    {
                        if (e.1 < 0.0) == (f < 0.0) {
                            // Only the bound from this sample is trusted: f is about a distance
                            // near its zeros, but not where the weight fades out, and the end of
                            // a support interval may lie past such a seam (a wall's edge beside
                            // another wall) where f jumps, its size saying nothing of the room
                            // before it. Nor is this sample's, beyond one step: inside only the
                            // fringe of a support whose plane lies spacings away, f is that far
                            // from zero, and past the seam it may cross within a spacing
                            // (bursting frame 57: `tests/torn_fragments.rs`).
                            if STEP_OF_F * f.abs() >= s1 - t && s1 - t <= max_step {
                                break; // no room for a zero before the end
                            }
                        } else if prev.is_none()
                            && s1 - t <= max_step
                            && let Some(hit) = self.crossing(ray, cands, cur, e, tol)
                        {
                            return Some(hit);
                        }
                    }
                    (prev2, prev) = (prev, Some(cur));
                    (STEP_OF_F * f.abs()).clamp(min_step, max_step)
                }
                None => {
                    (prev2, prev) = (None, None);
                    min_step
                }
            };
            if t >= s1 {
                break;
            }
            t = (t + step).min(s1);
        }
        None
    }

    /// Three samples of one sign whose middle one is the smallest in |f| and near the surface may
    /// hide two crossings between them (a ray grazing the surface): check f at the vertex of the
    /// parabola through them, and if its sign differs, refine both crossings.
    #[allow(clippy::too_many_arguments)]
    fn grazing(
        &self,
        ray: &Ray,
        cands: &[Cand],
        a: Sample,
        b: Sample,
        c: Sample,
        near: f32,
        tol: f32,
    ) -> Option<SurfaceHit> {
        let neg = b.1 < 0.0;
        if (a.1 < 0.0) != neg || (c.1 < 0.0) != neg {
            return None;
        }
        let (fa, fb, fc) = (a.1.abs(), b.1.abs(), c.1.abs());
        if !(fb < fa && fb <= fc && fb < near) {
            return None;
        }
        // Vertex of the parabola through the three points (|f| is smallest in the middle, so
        // the parabola opens upwards).
        let tv = b.0 + vertex_offset(a.0 - b.0, c.0 - b.0, fa - fb, fc - fb);
        if !(tv > a.0 && tv < c.0) || (tv - b.0).abs() < tol {
            return None;
        }
        let fv = field::value_on_ray(cands, tv)?;
        if (fv < 0.0) == neg {
            return None;
        }
        let v = (tv, fv);
        let (first, second) = if tv < b.0 {
            ((a, v), (v, b))
        } else {
            ((b, v), (v, c))
        };
        self.crossing(ray, cands, first.0, first.1, tol)
            .or_else(|| self.crossing(ray, cands, second.0, second.1, tol))
    }

    /// Refines the crossing bracketed by `lo` and `hi` (f of opposite signs, `lo.0 < hi.0`) and
    /// returns it if it is film (enough weight, agreeing normals).
    fn crossing(
        &self,
        ray: &Ray,
        cands: &[Cand],
        lo: Sample,
        hi: Sample,
        tol: f32,
    ) -> Option<SurfaceHit> {
        let (t, t_exit) = refine(|t| field::value_on_ray(cands, t), lo, hi, tol)?;
        let x = ray.at(t);
        let s = field::sample(cands, x, t)?;
        if !self.is_film(&s) {
            return None;
        }
        let normal = s
            .grad
            .try_normalize()
            .or_else(|| (s.coherence > 0.0).then_some(s.grad))?;
        Some(SurfaceHit {
            t,
            t_exit,
            position: x,
            normal,
            thickness_nm: s.thickness,
            coverage: s.coverage,
            particle: self.bvh.order()[s.best_slot as usize],
        })
    }
}

/// Where the ray is inside the sphere (`centre`, `radius`) within `(t_min, t_max)`, if anywhere.
#[cfg(test)]
fn clip(ray: &Ray, centre: glam::Vec3, radius: f32, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
    let (t0, t1) = crate::geometry::primitives::sphere_roots(ray, centre, radius)?;
    let (ta, tb) = (t0.max(t_min), t1.min(t_max));
    (ta < tb).then_some((ta, tb))
}

/// The refinement tolerance in a support interval ending at `s1` whose smallest particle radius
/// is `r`: [`TOLERANCE`] radii, but not below ~8 ulps of the coordinates, where the bracket
/// cannot shrink further.
fn tolerance(ray: &Ray, s1: f32, r: f32) -> f32 {
    let scale = ray.origin.abs().max_element() + s1.abs();
    (TOLERANCE * r).max(8.0 * f32::EPSILON * scale)
}

/// Offset from the middle abscissa to the vertex of the parabola through (da, ya), (0, 0) and
/// (dc, yc).
fn vertex_offset(da: f32, dc: f32, ya: f32, yc: f32) -> f32 {
    // y = α x² + β x; α = (ya/da − yc/dc)/(da − dc), β = ya/da − α da; vertex at −β/(2α).
    let alpha = (ya / da - yc / dc) / (da - dc);
    let beta = ya / da - alpha * da;
    -beta / (2.0 * alpha)
}

/// Bracketed root of `f` between `lo` and `hi` (opposite signs): Illinois regula falsi with a
/// bisection whenever a step did not halve the bracket. After a secant step the next point is
/// placed ½`tol` beyond it towards the root: f is nearly linear across a film, so the secant
/// point is usually within that of the root and the bracket closes to `tol` in one more
/// evaluation. Returns (root estimate, far end of the final bracket), or `None` if f cannot be
/// evaluated inside the bracket.
fn refine(f: impl Fn(f32) -> Option<f32>, lo: Sample, hi: Sample, tol: f32) -> Option<(f32, f32)> {
    let ((mut a, mut fa), (mut b, mut fb)) = (lo, hi);
    // Illinois-scaled copies of fa, fb used for the secant.
    let (mut ga, mut gb) = (fa, fb);
    let mut side = 0i8;
    let (mut bisect, mut nudge) = (false, None);
    for _ in 0..MAX_REFINE {
        let width = b - a;
        if width <= tol {
            break;
        }
        let secant = a - ga * width / (gb - ga);
        let (c, was_secant) = match nudge.take() {
            Some(n) if n > a && n < b => (n, false),
            _ if bisect || !(secant > a && secant < b) => (0.5 * (a + b), false),
            _ => (secant, true),
        };
        let fc = f(c)?;
        if fc == 0.0 {
            return Some((c, c));
        }
        if (fc < 0.0) == (fa < 0.0) {
            (a, fa, ga) = (c, fc, fc);
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb, gb) = (c, fc, fc);
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
        if was_secant {
            nudge = Some(if c == a { c + 0.5 * tol } else { c - 0.5 * tol });
        }
        bisect = b - a > 0.5 * width;
    }
    let t = (a - fa * (b - a) / (fb - fa)).clamp(a, b);
    Some((if t.is_finite() { t } else { 0.5 * (a + b) }, b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn refine_finds_roots_to_tolerance() {
        for (root, k) in [(0.3f32, 1.0f32), (0.71, 8.0), (0.05, 0.01)] {
            let f = |t: f32| Some(k * (t - root) * (1.0 + 3.0 * (t - root).powi(2)));
            let (t, te) = refine(f, (0.0, f(0.0).unwrap()), (1.0, f(1.0).unwrap()), 1e-5).unwrap();
            assert!((t - root).abs() < 1e-5, "{t} vs {root}");
            assert!(te >= root && te - t < 1e-5 + 1e-7);
        }
    }

    /// A ray dipping just inside a sphere of particles crosses it twice within a fraction of a
    /// spacing; three samples that straddle the dip, all outside, must still find the crossing.
    #[test]
    fn grazing_check_finds_a_dip_between_samples() {
        let n = 4000;
        let (_, d, s) = super::super::unit_sphere_surface(n);
        // Step the ray y = ρ, z = 0.2 outwards until it dips into the surface for 0.2–1 d.
        let f_of = |_ray: &Ray, cands: &[Cand], t: f32| field::value_on_ray(cands, t);
        let mut cands = Vec::new();
        let (mut found, mut rho) = (false, 0.97f32);
        while rho < 0.99 && !found {
            let ray = Ray::new(Vec3::new(-3.0, rho, 0.2), Vec3::X);
            cands.clear();
            cands.extend((0..n as u32).filter_map(|k| s.clipped(&ray, k, 0.0, 10.0)));
            cands.sort_unstable_by(|a, b| a.ta.total_cmp(&b.ta));
            let fine: Vec<(f32, f32)> = (0..(1.0 / (5e-3 * d)) as usize)
                .map(|k| 2.5 + k as f32 * 5e-3 * d)
                .filter_map(|t| f_of(&ray, &cands, t).map(|f| (t, f)))
                .collect();
            let inside: Vec<f32> = fine.iter().filter(|p| p.1 < 0.0).map(|p| p.0).collect();
            if let (Some(&t1), Some(&t2)) = (inside.first(), inside.last())
                && t2 - t1 < d
                && t2 - t1 > 0.2 * d
            {
                found = true;
                let sample = |t: f32| (t, f_of(&ray, &cands, t).unwrap());
                let (a, b, c) = (
                    sample(t1 - 0.6 * d),
                    sample(t1 - 0.01 * d),
                    sample(t2 + 0.2 * d),
                );
                assert!(a.1 > b.1 && c.1 >= b.1 && b.1 > 0.0, "{a:?} {b:?} {c:?}");
                let hit = s
                    .grazing(&ray, &cands, a, b, c, 0.5 * d, 1e-4 * d)
                    .expect("the dip between the samples is found");
                assert!((hit.t - t1).abs() < 0.02 * d, "{} vs {t1}", hit.t);
                // Without the dip (a ray 0.2 d further out) nothing is found.
                let ray2 = Ray::new(Vec3::new(-3.0, rho + 0.2 * d, 0.2), Vec3::X);
                let mut c2: Vec<Cand> = (0..n as u32)
                    .filter_map(|k| s.clipped(&ray2, k, 0.0, 10.0))
                    .collect();
                c2.sort_unstable_by(|a, b| a.ta.total_cmp(&b.ta));
                let sample2 = |t: f32| (t, f_of(&ray2, &c2, t).unwrap());
                let (a, b, c) = (sample2(a.0), sample2(0.5 * (t1 + t2)), sample2(c.0));
                assert!(s.grazing(&ray2, &c2, a, b, c, 0.5 * d, 1e-4 * d).is_none());
            }
            rho += 1e-3 * d;
        }
        assert!(found, "no ray with a short dip");
    }

    #[test]
    fn parabola_vertex() {
        // y = (x − 0.3)² − 0.09 through x = −1, 0, 2.
        let y = |x: f32| (x - 0.3) * (x - 0.3) - 0.09;
        let v = vertex_offset(-1.0, 2.0, y(-1.0), y(2.0));
        assert!((v - 0.3).abs() < 1e-5, "{v}");
    }
}
