//! The support spheres along a ray, handed to the march in order of entry a window at a time:
//! a ray's march ends at its first crossing, usually within a few spacings of where it meets
//! the first sphere, so gathering and sorting every sphere along the whole ray (through the
//! body and past it) is mostly wasted. Each window is one front-to-back BVH traversal that
//! keeps the spheres entering in `(a, e + WINDOW]`, `e` the first entry after `a` (the
//! traversal's bound lowered as `e` is found), so every sphere belongs to exactly one window
//! and the windows' sorted lists join into one sorted stream.

use glam::Vec3;

use super::LiquidSurface;
use crate::geometry::Ray;
use crate::geometry::primitives::sphere_roots;

/// Length of a window past its first entry, liquid spacings (a ray from outside meets the
/// surface within about 2.8 spacings of its first sphere: R = 2.25 to the particle's centre,
/// less the half spacing the surface lies past the outer particles, plus slack).
const WINDOW_SPACINGS: f32 = 4.0;

/// A support sphere the ray is inside over `(ta, tb)`, with what the march needs of it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cand {
    pub ta: f32,
    pub tb: f32,
    pub on: OnRay,
}

/// A particle relative to the ray: `p = centre − origin`, `c0 = |p|²`, `c1 = p · dir`, so its
/// squared distance from `ray.at(t)` is `c0 − 2 t c1 + t²`.
#[derive(Clone, Copy, Debug)]
pub(super) struct OnRay {
    pub p: Vec3,
    pub c0: f32,
    pub c1: f32,
}

/// The sorted stream of support spheres along `ray` within `(t_min, t_max)`.
pub(super) struct Stream<'a> {
    surface: &'a LiquidSurface,
    ray: &'a Ray,
    t_min: f32,
    t_max: f32,
    /// The current window's spheres, sorted by entry.
    cands: &'a mut Vec<Cand>,
    /// First of `cands` not yet taken.
    next: usize,
    /// Entries up to here are gathered (−∞ before the first window).
    gathered_to: f32,
}

impl<'a> Stream<'a> {
    /// The stream of `ray` over `(t_min, t_max)` (`t_min ≥ 0`), with `cands` as its buffer.
    pub fn new(
        surface: &'a LiquidSurface,
        ray: &'a Ray,
        (t_min, t_max): (f32, f32),
        cands: &'a mut Vec<Cand>,
    ) -> Self {
        cands.clear();
        Stream {
            surface,
            ray,
            t_min,
            t_max,
            cands,
            next: 0,
            gathered_to: f32::NEG_INFINITY,
        }
    }

    /// Entry of the next sphere not yet taken (gathering the next window when needed).
    #[inline]
    pub fn peek(&mut self) -> Option<f32> {
        while self.next >= self.cands.len() {
            if !self.fill() {
                return None;
            }
        }
        Some(self.cands[self.next].ta)
    }

    /// Takes the sphere [`Stream::peek`] showed.
    #[inline]
    pub fn take(&mut self) -> Cand {
        self.next += 1;
        self.cands[self.next - 1]
    }

    /// Gathers the next window (it may come out empty); false when no sphere is left.
    fn fill(&mut self) -> bool {
        let lo = self.gathered_to;
        if lo >= self.t_max {
            return false;
        }
        let (s, ray, t_min, t_max) = (self.surface, self.ray, self.t_min, self.t_max);
        // The part `(ta, tb)` of a sphere's `(t0, t1)` inside `(t_min, t_max)`, if its entry
        // `t0` is past `lo` and that part is not empty.
        let clip = |(t0, t1): (f32, f32)| {
            let (ta, tb) = (t0.max(t_min), t1.min(t_max));
            (t0 > lo && ta < tb).then_some((ta, tb))
        };
        let from = lo.max(t_min);
        let window = WINDOW_SPACINGS * s.spacing;
        // One front-to-back traversal finds the first entry past `lo` and lowers its bound to
        // that entry plus the window as it goes: a sphere entering by then is never culled.
        let mut first = f32::INFINITY;
        self.cands.clear();
        self.next = 0;
        let cands = &mut *self.cands;
        s.bvh.closest_leaves(ray, from, t_max, |a, count, lim| {
            for slot in a..a + count {
                let c = s.points[slot as usize];
                let Some((ta, tb)) = sphere_roots(ray, c, s.support).and_then(clip) else {
                    continue;
                };
                if ta < first {
                    first = ta;
                    *lim = lim.min(first + window);
                }
                if ta <= *lim {
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
        if !first.is_finite() {
            self.gathered_to = t_max;
            return false;
        }
        let hi = (first + window).min(t_max);
        self.cands.retain(|c| c.ta <= hi);
        self.gathered_to = hi;
        // Non-negative floats order as their bits.
        self.cands.sort_unstable_by_key(|c| c.ta.to_bits());
        true
    }
}
