//! The liquid's implicit field (Zhu & Bridson 2005, "Animating sand as a fluid", §4): at a
//! point x, with compact weights wᵢ = (1 − |x − xᵢ|²/R²)³ over the particles within the kernel
//! radius R, the weighted mean position x̄ = Σ wᵢ xᵢ / Σ wᵢ and
//!
//! φ(x) = |x − x̄| − r,
//!
//! r the radius of a sphere of one particle's volume. φ < 0 is liquid. Where the total weight
//! Σ wᵢ is below [`MIN_WEIGHT`] (far from every particle, or between two far-apart ones, where
//! the normalised mean would otherwise make a spurious blob) the point is outside: the field
//! there is +R. The gradient is analytic: with v = x̄ − x = S/W, S = Σ wᵢ (xᵢ − x),
//! ∂v/∂x = (Σ (xᵢ − x) ⊗ ∇wᵢ)/W − I − v ⊗ ∇W / W and ∇φ = −(∂v/∂x)ᵀ v / |v|.

use glam::{Mat3, Vec3};

/// Total weight below which a point is outside whatever φ says (the weight a lone particle
/// gives at 0.73 kernel radii; on a liquid body's surface it is above 1).
pub(crate) const MIN_WEIGHT: f32 = 0.1;

/// The field at a point, from the particles within reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sample {
    /// φ, scene units (+R where the weight is below [`MIN_WEIGHT`]).
    pub phi: f32,
    /// Total weight Σ wᵢ.
    pub weight: f32,
}

/// Accumulates the weighted sums at one point `x`.
pub(crate) struct Sums {
    x: Vec3,
    inv_r2: f32,
    w: f32,
    s: Vec3,
    /// Σ (xᵢ − x) ⊗ ∇wᵢ (only when the gradient is wanted).
    m: Mat3,
    /// Σ ∇wᵢ.
    g: Vec3,
}

impl Sums {
    /// Empty sums at `x` for kernel radius `support` (scene units).
    #[inline]
    pub fn new(x: Vec3, support: f32) -> Self {
        Sums {
            x,
            inv_r2: 1.0 / (support * support),
            w: 0.0,
            s: Vec3::ZERO,
            m: Mat3::ZERO,
            g: Vec3::ZERO,
        }
    }

    /// Adds particle `p` (no gradient terms; the march has its own form of this sum).
    #[cfg(test)]
    #[inline(always)]
    pub fn add(&mut self, p: Vec3) {
        let d = p - self.x;
        let q = 1.0 - d.length_squared() * self.inv_r2;
        if q > 0.0 {
            let w = q * q * q;
            self.w += w;
            self.s += w * d;
        }
    }

    /// Adds particle `p` with the gradient terms: ∇wᵢ = 6 (1 − q)² (xᵢ − x) / R².
    #[inline]
    pub fn add_with_gradient(&mut self, p: Vec3) {
        let d = p - self.x;
        let q = 1.0 - d.length_squared() * self.inv_r2;
        if q > 0.0 {
            let w = q * q * q;
            let gw = d * (6.0 * q * q * self.inv_r2);
            self.w += w;
            self.s += w * d;
            // Column j of the outer product d ⊗ gw is d · gw_j.
            self.m += Mat3::from_cols(d * gw.x, d * gw.y, d * gw.z);
            self.g += gw;
        }
    }

    /// φ and the weight, for sphere radius `radius` and kernel radius `support`.
    #[inline]
    pub fn sample(&self, radius: f32, support: f32) -> Sample {
        if self.w < MIN_WEIGHT {
            return Sample {
                phi: support,
                weight: self.w,
            };
        }
        Sample {
            phi: (self.s / self.w).length() - radius,
            weight: self.w,
        }
    }

    /// ∇φ (needs [`Sums::add_with_gradient`]); zero where it is undefined (x = x̄ or no
    /// weight).
    pub fn gradient(&self) -> Vec3 {
        if self.w <= 0.0 {
            return Vec3::ZERO;
        }
        let v = self.s / self.w;
        let len = v.length();
        if len <= 0.0 {
            return Vec3::ZERO;
        }
        // J = ∂v/∂x = M / W − I − v ⊗ G / W.
        let vg = Mat3::from_cols(v * self.g.x, v * self.g.y, v * self.g.z);
        let j = (self.m - vg) * (1.0 / self.w) - Mat3::IDENTITY;
        (j.transpose() * v) / len
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn phi_at(points: &[Vec3], x: Vec3, r: f32, h: f32) -> f32 {
        let mut s = Sums::new(x, h);
        points.iter().for_each(|&p| s.add(p));
        s.sample(r, h).phi
    }

    #[test]
    fn lone_particle_is_a_sphere_and_the_gradient_matches_differences() {
        let p = [Vec3::new(0.1, -0.2, 0.3)];
        let x = Vec3::new(0.5, 0.1, 0.2);
        assert!((phi_at(&p, x, 0.62, 2.25) - ((x - p[0]).length() - 0.62)).abs() < 1e-6);
        // A small irregular cluster: the analytic gradient against central differences.
        let pts = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.1, 0.0),
            Vec3::new(0.2, 0.9, 0.3),
            Vec3::new(-0.4, 0.3, 1.1),
            Vec3::new(0.8, 0.8, 0.9),
        ];
        for x in [Vec3::new(1.2, 1.1, 0.4), Vec3::new(-0.9, 0.2, 0.5)] {
            let mut s = Sums::new(x, 2.25);
            pts.iter().for_each(|&p| s.add_with_gradient(p));
            let g = s.gradient();
            let e = 1e-3;
            let fd = Vec3::new(
                phi_at(&pts, x + Vec3::X * e, 0.62, 2.25)
                    - phi_at(&pts, x - Vec3::X * e, 0.62, 2.25),
                phi_at(&pts, x + Vec3::Y * e, 0.62, 2.25)
                    - phi_at(&pts, x - Vec3::Y * e, 0.62, 2.25),
                phi_at(&pts, x + Vec3::Z * e, 0.62, 2.25)
                    - phi_at(&pts, x - Vec3::Z * e, 0.62, 2.25),
            ) / (2.0 * e);
            assert!((g - fd).length() < 2e-3, "analytic {g} vs differences {fd}");
        }
    }

    #[test]
    fn far_from_weight_is_outside() {
        // Two particles 4.4 apart: the normalised mean sits between them, but the weight there
        // is tiny, so the midpoint is not liquid.
        let pts = [Vec3::ZERO, Vec3::new(4.4, 0.0, 0.0)];
        assert!(phi_at(&pts, Vec3::new(2.2, 0.0, 0.0), 0.62, 2.25) > 0.0);
    }
}
