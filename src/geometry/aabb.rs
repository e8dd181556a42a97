//! Axis-aligned bounding boxes and the ray slab test.

use glam::Vec3;

use super::Ray;

/// An axis-aligned box `[min, max]`. The empty box has `min = +inf`, `max = -inf`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// Relative widening of the far slab distance so that rounding never culls a box the ray
/// touches (Ize, "Robust BVH ray traversal", 1 + 2·gamma(3) rounded up).
pub(crate) const SLAB_ROBUST: f32 = 1.000_000_4;

impl Aabb {
    /// The empty box (identity of [`Aabb::union`]).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
    };

    /// The box with the given corners.
    pub fn new(min: Vec3, max: Vec3) -> Aabb {
        Aabb { min, max }
    }

    /// The box holding just `p`.
    pub fn from_point(p: Vec3) -> Aabb {
        Aabb { min: p, max: p }
    }

    /// True if the box holds no point (some `min > max`, or NaN).
    pub fn is_empty(&self) -> bool {
        !self.min.cmple(self.max).all()
    }

    /// The smallest box holding both.
    #[inline]
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Grows the box to hold `p`.
    #[inline]
    pub fn grow(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// The box widened by `pad` on every side.
    pub fn padded(&self, pad: f32) -> Aabb {
        Aabb {
            min: self.min - Vec3::splat(pad),
            max: self.max + Vec3::splat(pad),
        }
    }

    /// Centre of the box.
    #[inline]
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Edge lengths (zero for the empty box).
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Surface area (zero for the empty box).
    #[inline]
    pub fn surface_area(&self) -> f32 {
        let e = (self.max - self.min).max(Vec3::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// Index (0, 1, 2) of the longest axis.
    pub fn largest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    /// True if `p` is inside or on the boundary.
    pub fn contains(&self, p: Vec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// Slab test: the parameter interval `[t_near, t_far]` of the ray inside the box, clipped to
    /// `[t_min, t_max]`, or `None` if the ray misses it. Rays parallel to a slab are handled
    /// (no NaN); one lying exactly in a face plane may be reported as a miss (primitive boxes are
    /// padded, so this never loses a primitive). Cost: a few dozen flops.
    pub fn intersect_ray(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, f32)> {
        let inv = safe_inv_dir(ray.dir);
        slab(self.min, self.max, ray.origin, inv, t_min, t_max)
    }
}

/// `1 / dir` with zero components replaced by a huge finite value of the same sign, so the slab
/// test never computes `0 * inf`.
#[inline]
pub(crate) fn safe_inv_dir(dir: Vec3) -> Vec3 {
    const TINY: f32 = 1e-30;
    let f = |d: f32| {
        if d.abs() < TINY {
            1.0 / TINY.copysign(d)
        } else {
            1.0 / d
        }
    };
    Vec3::new(f(dir.x), f(dir.y), f(dir.z))
}

/// The slab test with a precomputed inverse direction (see [`Aabb::intersect_ray`]).
#[inline(always)]
pub(crate) fn slab(
    min: Vec3,
    max: Vec3,
    origin: Vec3,
    inv: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, f32)> {
    let t1 = (min - origin) * inv;
    let t2 = (max - origin) * inv;
    let tn = t1.min(t2).max_element().max(t_min);
    let tf = t1.max(t2).min_element().min(t_max);
    if tn <= tf * SLAB_ROBUST {
        Some((tn, tf))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn union_grow_area() {
        let mut b = Aabb::EMPTY;
        assert!(b.is_empty());
        assert_eq!(b.surface_area(), 0.0);
        b.grow(Vec3::ZERO);
        b.grow(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(b.surface_area(), 2.0 * (2.0 + 6.0 + 3.0));
        assert_eq!(b.centroid(), Vec3::new(0.5, 1.0, 1.5));
        assert_eq!(b.largest_axis(), 2);
        let u = b.union(&Aabb::from_point(Vec3::splat(-1.0)));
        assert_eq!(u.min, Vec3::splat(-1.0));
        assert_eq!(Aabb::EMPTY.union(&b), b);
    }

    #[test]
    fn slab_hits_misses_and_parallel() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let r = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        let (tn, tf) = b.intersect_ray(&r, 0.0, f32::INFINITY).unwrap();
        assert!((tn - 1.0).abs() < 1e-6 && (tf - 2.0).abs() < 1e-6);
        // Parallel to the x and y slabs, outside in x: miss.
        let r = Ray::new(Vec3::new(1.5, 0.5, -1.0), Vec3::Z);
        assert!(b.intersect_ray(&r, 0.0, f32::INFINITY).is_none());
        // Parallel and just inside a face: hits (exactly on the face plane may count as a miss).
        let r = Ray::new(Vec3::new(0.999_99, 0.5, -1.0), Vec3::Z);
        assert!(b.intersect_ray(&r, 0.0, f32::INFINITY).is_some());
        // Box behind the ray, or beyond t_max.
        let r = Ray::new(Vec3::new(0.5, 0.5, 3.0), Vec3::Z);
        assert!(b.intersect_ray(&r, 0.0, f32::INFINITY).is_none());
        let r = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        assert!(b.intersect_ray(&r, 0.0, 0.5).is_none());
        // Starting inside: t_near is t_min.
        let r = Ray::new(Vec3::splat(0.5), Vec3::X);
        let (tn, tf) = b.intersect_ray(&r, 0.0, f32::INFINITY).unwrap();
        assert!(tn == 0.0 && (tf - 0.5).abs() < 1e-6);
    }
}
