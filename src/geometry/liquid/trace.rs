//! Ray–liquid intersection: the support spheres along the ray from the BVH, merged into
//! intervals, marched with distance-bounded steps, sign changes bisected (see the parent
//! module's docs).

use std::cell::RefCell;

use glam::Vec3;

use super::field::{MIN_WEIGHT, Sums};
use super::grid::{FieldGrid, Last};
use super::{LiquidHit, LiquidSurface};
use crate::geometry::Ray;
use crate::geometry::aabb::{safe_inv_dir, slab};
use crate::geometry::primitives::sphere_roots;

/// Smallest march step, spacings.
const MIN_STEP: f32 = 0.05;
/// Largest march step, spacings.
const MAX_STEP: f32 = 0.5;
/// Steps are this fraction of |φ| between the two bounds.
const STEP_OF_PHI: f32 = 0.8;
/// A crossing is bisected until its bracket is narrower than this many spacings.
const TOLERANCE: f32 = 1e-4;
/// The first window of the ray whose runs of bricks are collected, spacings (then twice
/// that, and so on; a body of a thousand particles is about 12 spacings across).
const WINDOW_SPACINGS: f32 = 6.0;
/// Upper bound on march steps per query (a guard; a ray through a body takes tens).
const MAX_MARCH: usize = 1 << 16;

/// A support sphere the ray is inside over `(ta, tb)`, with what the march needs of it.
#[derive(Clone, Copy, Debug)]
struct Cand {
    ta: f32,
    tb: f32,
    on: OnRay,
}

/// A particle relative to the ray: `p = centre − origin`, `c0 = |p|²`, `c1 = p · dir`, so its
/// squared distance from `ray.at(t)` is `c0 − 2 t c1 + t²`.
#[derive(Clone, Copy, Debug)]
struct OnRay {
    p: Vec3,
    c0: f32,
    c1: f32,
}

/// Scratch buffers of one thread: the support spheres along the current ray, and the active
/// ones (with where each ends).
#[derive(Default)]
struct Scratch {
    cands: Vec<Cand>,
    on: Vec<OnRay>,
    ends: Vec<f32>,
    /// The runs of grid bricks along the ray.
    runs: Vec<(f32, f32)>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The spheres of one merged interval that cover the march's current position: every sphere
/// entered by then (`next` is the first not yet entered), less those left before `low`.
struct Active<'c> {
    cands: &'c [Cand],
    next: usize,
    on: &'c mut Vec<OnRay>,
    ends: &'c mut Vec<f32>,
}

impl Active<'_> {
    /// Brings the set up to `t`, keeping every sphere that covers any point of `[low, t]`.
    fn advance(&mut self, low: f32, t: f32) {
        let mut k = 0;
        while k < self.on.len() {
            if self.ends[k] < low {
                self.on.swap_remove(k);
                self.ends.swap_remove(k);
            } else {
                k += 1;
            }
        }
        while self.next < self.cands.len() && self.cands[self.next].ta <= t {
            let c = self.cands[self.next];
            if c.tb >= low {
                self.on.push(c.on);
                self.ends.push(c.tb);
            }
            self.next += 1;
        }
    }
}

impl LiquidSurface {
    /// The first crossing of the surface with `t_min < t < t_max`, entering or leaving.
    /// Cost: one BVH traversal collecting the support spheres along the segment, a sort, and
    /// per sample of the march (tens through a body) the spheres covering it (~50 in a body).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<LiquidHit> {
        if self.is_empty() || !ray.is_valid() || t_min.is_nan() || t_max.is_nan() {
            return None;
        }
        // Rays run over t ≥ 0 (so entry distances sort by their bits, below).
        let (t_min, t_max) = (t_min.max(0.0), t_max.min(f32::MAX));
        if t_min >= t_max {
            return None;
        }
        if let Some(g) = &self.grid {
            return self.intersect_grid(g, ray, t_min, t_max);
        }
        SCRATCH.with_borrow_mut(|sc| {
            let Scratch {
                cands, on, ends, ..
            } = sc;
            self.gather(ray, t_min, t_max, cands);
            let mut start = 0;
            while start < cands.len() {
                // One connected piece of the union of the support intervals.
                let mut end = cands[start].tb;
                let mut stop = start + 1;
                while stop < cands.len() && cands[stop].ta <= end {
                    end = end.max(cands[stop].tb);
                    stop += 1;
                }
                on.clear();
                ends.clear();
                let mut act = Active {
                    cands: &cands[start..stop],
                    next: 0,
                    on,
                    ends,
                };
                if let Some(hit) = self.march(ray, &mut act, cands[start].ta, end) {
                    return Some(hit);
                }
                start = stop;
            }
            None
        })
    }

    /// The support spheres the ray is inside somewhere in `(t_min, t_max)`, sorted by entry.
    fn gather(&self, ray: &Ray, t_min: f32, t_max: f32, cands: &mut Vec<Cand>) {
        cands.clear();
        self.bvh.visit_segment(ray, t_min, t_max, |slot| {
            let c = self.points[slot as usize];
            if let Some((t0, t1)) = sphere_roots(ray, c, self.support) {
                let (ta, tb) = (t0.max(t_min), t1.min(t_max));
                if ta < tb {
                    let p = c - ray.origin;
                    let on = OnRay {
                        p,
                        c0: p.length_squared(),
                        c1: p.dot(ray.dir),
                    };
                    cands.push(Cand { ta, tb, on });
                }
            }
        });
        // Non-negative floats order as their bits.
        cands.sort_unstable_by_key(|c| c.ta.to_bits());
    }

    /// φ at `ray.at(t)` over the active spheres `on` (the field module's sums, written for
    /// particles relative to the ray).
    #[inline]
    fn phi(&self, ray: &Ray, on: &[OnRay], t: f32) -> f32 {
        let inv_r2 = 1.0 / (self.support * self.support);
        let (mut w, mut sp) = (0.0f32, Vec3::ZERO);
        for c in on {
            let q = 1.0 - (c.c0 - t * (2.0 * c.c1 - t)) * inv_r2;
            if q > 0.0 {
                let wi = q * q * q;
                w += wi;
                sp += wi * c.p;
            }
        }
        if w < MIN_WEIGHT {
            return self.support;
        }
        (sp / w - t * ray.dir).length() - self.radius
    }

    /// Marches `(t0, t1)`, covered by the spheres of `act`, for the first sign change of φ;
    /// bisects it; the hit with its normal.
    fn march(&self, ray: &Ray, act: &mut Active, t0: f32, t1: f32) -> Option<LiquidHit> {
        let s = self.spacing;
        act.advance(t0, t0);
        let mut t = t0;
        let mut f = self.phi(ray, act.on, t);
        for _ in 0..MAX_MARCH {
            if t >= t1 {
                return None;
            }
            let step = (STEP_OF_PHI * f.abs()).clamp(MIN_STEP * s, MAX_STEP * s);
            let tn = (t + step).min(t1);
            act.advance(t, tn);
            let fnext = self.phi(ray, act.on, tn);
            if (f < 0.0) != (fnext < 0.0) {
                return Some(self.refine(ray, act.on, (t, f), tn));
            }
            (t, f) = (tn, fnext);
        }
        None
    }

    /// Bisects the bracket `[a, b]` (φ changes sign) to [`TOLERANCE`] spacings; the hit at its
    /// midpoint.
    fn refine(&self, ray: &Ray, on: &[OnRay], (mut a, fa): (f32, f32), mut b: f32) -> LiquidHit {
        let inside_a = fa < 0.0;
        let tol = TOLERANCE * self.spacing;
        for _ in 0..64 {
            if b - a <= tol {
                break;
            }
            let m = 0.5 * (a + b);
            if (self.phi(ray, on, m) < 0.0) == inside_a {
                a = m;
            } else {
                b = m;
            }
        }
        let t = 0.5 * (a + b);
        let mut sums = Sums::new(ray.at(t), self.support);
        on.iter()
            .for_each(|c| sums.add_with_gradient(ray.origin + c.p));
        hit_facing(ray, t, sums.gradient(), inside_a)
    }

    /// [`LiquidSurface::intersect`] on the field's grid: the runs of bricks along the ray,
    /// each marched as the exact field is, a sign change bisected on the grid; the normal the
    /// exact field's at the crossing.
    fn intersect_grid(
        &self,
        g: &FieldGrid,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<LiquidHit> {
        let s = self.spacing;
        let last = std::cell::Cell::new(None);
        let phi = |t: f32| {
            let mut l = last.get();
            let v = g.phi(ray.at(t), &mut l);
            last.set(l);
            v
        };
        SCRATCH.with_borrow_mut(|sc| {
            // Clipped to the grid's box, the runs are collected a window at a time, each twice
            // the last, so a crossing near the start does not pay for the bricks beyond it.
            let b = g.bounds();
            let inv = safe_inv_dir(ray.dir);
            let (mut lo, t_max) = slab(b.min, b.max, ray.origin, inv, t_min, t_max)?;
            let mut window = WINDOW_SPACINGS * s;
            while lo < t_max {
                let hi = if t_max - lo > 2.0 * window {
                    lo + window
                } else {
                    t_max
                };
                window *= 2.0;
                g.runs(ray, lo, hi, &mut sc.runs);
                if let Some(hit) = self.march_runs(g, ray, &sc.runs, &phi, &last) {
                    return Some(hit);
                }
                lo = hi;
            }
            None
        })
    }

    /// Marches the runs of bricks `runs` in order for the first sign change of `phi` (the
    /// grid along the ray; `last` its brick cache); the crossing and its exact normal.
    fn march_runs(
        &self,
        g: &FieldGrid,
        ray: &Ray,
        runs: &[(f32, f32)],
        phi: &impl Fn(f32) -> f32,
        last: &std::cell::Cell<Last>,
    ) -> Option<LiquidHit> {
        let s = self.spacing;
        for &(t0, t1) in runs {
            let (mut t, mut f) = (t0, phi(t0));
            for _ in 0..MAX_MARCH {
                if t >= t1 {
                    break;
                }
                let step = (STEP_OF_PHI * f.abs()).clamp(MIN_STEP * s, MAX_STEP * s);
                // A brick of one sign is crossed in one step (just past its far face).
                let skip = g
                    .exit_if_uniform(ray, last.get(), f < 0.0)
                    .map(|e| e + MIN_STEP * s);
                let tn = (t + step).max(skip.unwrap_or(t)).min(t1);
                let fnext = phi(tn);
                if (f < 0.0) != (fnext < 0.0) {
                    let t = regula_falsi(phi, (t, f), (tn, fnext), TOLERANCE * s);
                    let grad = self.field_at(ray.at(t)).grad;
                    return Some(hit_facing(ray, t, grad, f < 0.0));
                }
                (t, f) = (tn, fnext);
            }
        }
        None
    }
}

/// The crossing in `[a, b]`, where `phi` changes sign (inside: < 0), to `tol`: regula falsi
/// with the Illinois step (an end kept twice in a row has its value halved), falling back to
/// bisection where the secant leaves the bracket. A few evaluations where bisection takes ten.
fn regula_falsi(
    phi: impl Fn(f32) -> f32,
    (mut a, mut fa): (f32, f32),
    (mut b, mut fb): (f32, f32),
    tol: f32,
) -> f32 {
    let inside_a = fa < 0.0;
    let mut kept = 0i8;
    let mut m = 0.5 * (a + b);
    for _ in 0..64 {
        if b - a <= tol {
            return 0.5 * (a + b);
        }
        m = (a * fb - b * fa) / (fb - fa);
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
        }
        let fm = phi(m);
        if fm.abs() <= tol {
            return m;
        }
        if (fm < 0.0) == inside_a {
            (a, fa) = (m, fm);
            if kept == -1 {
                fb *= 0.5;
            }
            kept = -1;
        } else {
            (b, fb) = (m, fm);
            if kept == 1 {
                fa *= 0.5;
            }
            kept = 1;
        }
    }
    m
}

/// The crossing at `t` with normal ∇φ = `grad`; where the gradient is undefined (the weight
/// cut-off), facing the ray.
fn hit_facing(ray: &Ray, t: f32, grad: Vec3, inside_a: bool) -> LiquidHit {
    let normal = if grad.length_squared() > 0.0 {
        grad.normalize()
    } else if inside_a {
        ray.dir
    } else {
        -ray.dir
    };
    LiquidHit {
        t,
        normal,
        entering: !inside_a,
    }
}

#[cfg(test)]
mod tests {
    use super::super::LiquidField;
    use super::*;

    /// Exact to the bisection's tolerance; on the grid, within its interpolation (a lone
    /// particle's φ is a cone, the grid's worst case).
    #[test]
    fn lone_particle_enters_and_leaves_its_sphere() {
        for (field, tol) in [(LiquidField::Exact, 1e-3), (LiquidField::Grid, 0.03)] {
            lone_particle(field, tol);
        }
    }

    fn lone_particle(field: LiquidField, tol: f32) {
        let s = 1.0;
        let l = LiquidSurface::build_with(&[Vec3::new(0.0, 0.0, 5.0)], s, field).unwrap();
        let r = super::super::VOLUME_RADIUS;
        let ray = Ray::new(Vec3::new(0.1, 0.0, 0.0), Vec3::Z);
        let h = l.intersect(&ray, 0.0, f32::INFINITY).unwrap();
        let chord = (r * r - 0.01).sqrt();
        assert!(
            h.entering && (h.t - (5.0 - chord)).abs() < tol,
            "{field:?} {h:?}"
        );
        assert!(h.normal.z < -0.9);
        let out = l.intersect(&ray, h.t + 1e-3, f32::INFINITY).unwrap();
        assert!(
            !out.entering && (out.t - (5.0 + chord)).abs() < tol,
            "{field:?} {out:?}"
        );
        assert!(l.intersect(&ray, out.t + 1e-3, f32::INFINITY).is_none());
        assert!(l.intersect(&ray, 0.0, 4.0).is_none());
    }
}

#[cfg(test)]
mod window_tests {
    use super::super::LiquidField;
    use super::*;

    /// Every crossing along a row of 16 lone particles with gaps growing from 5 to 24.5
    /// spacings, found one after another from just past the last: the next lies 3.8 to 23
    /// spacings on, so in the first, second or third window of the grid's runs, and the
    /// windows' ends fall all along the gaps. Crossings as the exact field finds them (within
    /// 0.04 spacings along the ray: a lone particle's field is a cone, the grid's worst case;
    /// the ray off the axis by 0.2 meets it at 19°). Fails when the windows leave a gap (the
    /// next window starting a spacing past the last).
    #[test]
    fn crossings_past_many_windows_match_the_exact_field() {
        let mut x = 0.0;
        let pts: Vec<Vec3> = (0..16)
            .map(|k| {
                x += 5.0 + 1.3 * k as f32;
                Vec3::new(x, 0.0, 0.0)
            })
            .collect();
        let end = x + 7.0;
        let exact = LiquidSurface::build_with(&pts, 1.0, LiquidField::Exact).unwrap();
        let grid = LiquidSurface::build_with(&pts, 1.0, LiquidField::Grid).unwrap();
        for (o, dir) in [
            (Vec3::new(-7.0, 0.1, 0.0), Vec3::X),
            (Vec3::new(end, 0.0, -0.2), -Vec3::X),
        ] {
            let ray = Ray::new(o, dir);
            let (mut te, mut tg, mut n) = (0.0, 0.0, 0);
            while let Some(e) = exact.intersect(&ray, te, f32::INFINITY) {
                let g = grid.intersect(&ray, tg, f32::INFINITY);
                let g = g.unwrap_or_else(|| panic!("crossing {n} at {} missed", e.t));
                assert!((g.t - e.t).abs() < 0.04, "crossing {n}: {} vs {}", g.t, e.t);
                assert_eq!(g.entering, e.entering);
                (te, tg, n) = (e.t + 1e-3, g.t + 1e-3, n + 1);
            }
            assert_eq!(n, 32);
            assert!(grid.intersect(&ray, tg, f32::INFINITY).is_none());
        }
    }
}
