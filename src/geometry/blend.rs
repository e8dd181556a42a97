//! Disk-layer blending: the overlapping disks a ray meets in one film layer become one crossing.
//!
//! After the closest disk hit at `t0` (point `p0`, normal `n0`, radius `r0`), every disk hit `j`
//! with `p_j` inside the slab `|dot(p_j − p0, n0)| < layer_factor · r0` and a normal agreeing with
//! `n0` (`|dot(n_j, n0)| > min_normal_dot`) belongs to the same layer. Along the ray the slab test
//! is exactly `t_j − t0 < layer_factor · r0 / |cos θ0|`, capped at `band_cap · r0` for grazing rays.
//! Each member is weighted by the smooth compact kernel `w = (1 − (d/r)²)²` of the distance `d`
//! from its hit point to its centre (zero with zero slope at the rim, so results are continuous
//! when a disk starts or stops covering a pixel).

use glam::Vec3;

/// Parameters of the disk-layer blending (all relative to the closest splat's radius `r0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerBlend {
    /// Half-thickness of a film layer in units of `r0` (default 0.5): hits whose points lie
    /// within `layer_factor · r0` of the closest disk's plane join its layer.
    pub layer_factor: f32,
    /// Minimum `|dot(n_j, n0)|` for a disk to join the layer (default 0.5, i.e. within 60°).
    pub min_normal_dot: f32,
    /// Longest band searched along the ray, in units of `r0` (default 2); bounds the search for
    /// grazing rays, where the slab is long along the ray.
    pub band_cap: f32,
}

impl Default for LayerBlend {
    fn default() -> Self {
        LayerBlend {
            layer_factor: 0.5,
            min_normal_dot: 0.5,
            band_cap: 2.0,
        }
    }
}

impl LayerBlend {
    /// No blending: every disk is its own crossing (layer of zero thickness).
    pub const NONE: LayerBlend = LayerBlend {
        layer_factor: 0.0,
        min_normal_dot: 1.0,
        band_cap: 0.0,
    };

    /// Length of the band beyond `t0` searched for layer members, for a closest disk of radius
    /// `r0` whose normal makes `|cos θ0| = abs_cos` with the ray.
    #[inline]
    pub fn band(&self, r0: f32, abs_cos: f32) -> f32 {
        let cap = self.band_cap * r0;
        let slab = self.layer_factor * r0;
        if slab < cap * abs_cos {
            slab / abs_cos
        } else {
            cap
        }
    }
}

/// The kernel weight of a hit at squared distance `d2` from the centre of a disk of radius²
/// `r2`: `(1 − d2/r2)²`, clamped to `[0, 1]`.
#[inline(always)]
pub(crate) fn kernel(d2: f32, r2: f32) -> f32 {
    let x = (1.0 - d2 / r2).max(0.0);
    x * x
}

/// Running sums of one layer's members. The closest disk is added first.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LayerSum {
    n0: Vec3,
    t0: f32,
    thickness0: f32,
    particle0: u32,
    sum_w: f32,
    sum_n: Vec3,
    sum_h: f32,
    sum_t: f32,
    t_last: f32,
    count: u32,
    best_w: f32,
    best_particle: u32,
}

/// The blended crossing (fields as in [`SurfaceHit`](super::SurfaceHit), without position).
pub(crate) struct Blended {
    pub t: f32,
    pub t_exit: f32,
    pub normal: Vec3,
    pub thickness_nm: f32,
    pub coverage: u32,
    pub particle: u32,
}

/// Below this total weight (all hits essentially at rims) the closest hit's values are used.
const MIN_TOTAL_WEIGHT: f32 = 1e-12;

impl LayerSum {
    /// Starts a layer with the closest hit.
    #[inline]
    pub fn new(t0: f32, n0: Vec3, thickness: f32, particle: u32, w: f32) -> LayerSum {
        LayerSum {
            n0,
            t0,
            thickness0: thickness,
            particle0: particle,
            sum_w: w,
            sum_n: w * n0,
            sum_h: w * thickness,
            sum_t: w * t0,
            t_last: t0,
            count: 1,
            best_w: w,
            best_particle: particle,
        }
    }

    /// Adds a member hit (`t >= t0`). Ties in weight go to the lower particle index, so the
    /// result does not depend on the visiting order.
    #[inline]
    pub fn add(&mut self, t: f32, n: Vec3, thickness: f32, particle: u32, w: f32) {
        let s = if n.dot(self.n0) >= 0.0 { 1.0 } else { -1.0 };
        self.sum_w += w;
        self.sum_n += (w * s) * n;
        self.sum_h += w * thickness;
        self.sum_t += w * t;
        self.t_last = self.t_last.max(t);
        self.count += 1;
        if w > self.best_w || (w == self.best_w && particle < self.best_particle) {
            self.best_w = w;
            self.best_particle = particle;
        }
    }

    /// The blended crossing.
    #[inline]
    pub fn finish(&self) -> Blended {
        let normal = self.sum_n.normalize_or_zero();
        if self.sum_w > MIN_TOTAL_WEIGHT && normal != Vec3::ZERO {
            Blended {
                t: (self.sum_t / self.sum_w).clamp(self.t0, self.t_last),
                t_exit: self.t_last,
                normal,
                thickness_nm: self.sum_h / self.sum_w,
                coverage: self.count,
                particle: self.best_particle,
            }
        } else {
            Blended {
                t: self.t0,
                t_exit: self.t_last,
                normal: self.n0,
                thickness_nm: self.thickness0,
                coverage: self.count,
                particle: self.particle0,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernel_is_one_at_centre_zero_at_rim() {
        assert_eq!(kernel(0.0, 4.0), 1.0);
        assert_eq!(kernel(4.0, 4.0), 0.0);
        assert_eq!(kernel(5.0, 4.0), 0.0);
        // Zero slope at the rim: the value just inside is second order.
        assert!(kernel(4.0 * (1.0 - 1e-3), 4.0) < 2e-6);
    }

    #[test]
    fn band_is_slab_then_capped() {
        let b = LayerBlend::default();
        assert!((b.band(2.0, 1.0) - 1.0).abs() < 1e-6);
        assert!((b.band(2.0, 0.5) - 2.0).abs() < 1e-6);
        assert_eq!(b.band(2.0, 0.0), 4.0);
        assert_eq!(LayerBlend::NONE.band(2.0, 0.3), 0.0);
    }

    #[test]
    fn blend_weights_and_rim_fallback() {
        let mut s = LayerSum::new(1.0, Vec3::Z, 100.0, 7, 1.0);
        s.add(1.2, -Vec3::Z, 300.0, 3, 1.0);
        let b = s.finish();
        assert_eq!(b.coverage, 2);
        assert!((b.thickness_nm - 200.0).abs() < 1e-4);
        assert!((b.t - 1.1).abs() < 1e-6 && b.t_exit == 1.2);
        assert_eq!(b.normal, Vec3::Z, "flipped member aligned with n0");
        assert_eq!(b.particle, 3, "weight tie goes to the lower index");
        let mut s = LayerSum::new(1.0, Vec3::X, 100.0, 7, 0.0);
        s.add(1.5, Vec3::Y, 300.0, 3, 0.0);
        let b = s.finish();
        assert!(b.t == 1.0 && b.t_exit == 1.5 && b.thickness_nm == 100.0 && b.particle == 7);
        assert_eq!(b.normal, Vec3::X);
    }
}
