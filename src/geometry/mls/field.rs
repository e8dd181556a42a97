//! The implicit function of the MLS surface and its gradient at one point, from a list of
//! neighbours (the particles whose support sphere may contain the point).
//!
//! f(x) = Σ wᵢ(x)·nᵢ·(x − pᵢ) / Σ wᵢ(x): the weighted mean of the signed distances from x to the
//! particles' tangent planes (the "implicit MLS" of Shen et al. 2004 and Kolluri 2008, the
//! normal-carrying form of Adamson & Alexa's point set surface). With the compact weight
//! wᵢ(x) = (1 − |x − pᵢ|²/hᵢ²)³ (zero beyond the support radius hᵢ, with zero slope there) f is
//! continuously differentiable wherever Σ w > 0, and near the particles it measures the signed
//! distance to the surface (|∇f| ≈ 1), which the ray marcher relies on for its step size.

use glam::Vec3;

/// Below this total weight f is not evaluated (the point is at the very edge of the support).
pub(super) const MIN_EVAL_WEIGHT: f32 = 1e-6;

/// A particle that may contribute to points along one ray (or at one point).
#[derive(Clone, Copy, Debug)]
pub(super) struct Cand {
    /// Particle position.
    pub p: Vec3,
    /// 1 / support radius².
    pub inv_h2: f32,
    /// Unit normal.
    pub n: Vec3,
    /// Thickness, nm.
    pub thickness: f32,
    /// The ray parameters where the ray is inside the support sphere (clipped to the query).
    pub ta: f32,
    /// See `ta`.
    pub tb: f32,
    /// BVH slot.
    pub slot: u32,
    /// Particle radius (the local spacing scale), scene units.
    pub r: f32,
    /// The signed distance to the particle's tangent plane along the ray, gᵢ(t) = nᵢ·(x(t) − pᵢ)
    /// = `g0 + g1·t` (scene units; zero for point queries).
    pub g0: f32,
    /// See `g0`.
    pub g1: f32,
    /// The ray parameter where the ray passes closest to `p` (zero for point queries).
    pub b: f32,
    /// h² − e², e the distance of `p` from the ray (scene units²; zero for point queries): along
    /// the ray |x(t) − p|² = h² − `k2` + (t − `b`)², so the weight needs no 3D point.
    pub k2: f32,
}

/// A support sphere's chord along a ray and the per-particle terms of [`Cand`] (see there).
#[derive(Clone, Copy)]
pub(super) struct Chord {
    pub ta: f32,
    pub tb: f32,
    pub b: f32,
    pub k2: f32,
    pub inv_h2: f32,
    pub r: f32,
}

/// Everything known about the surface at one point.
#[derive(Clone, Copy, Debug)]
pub(super) struct FieldSample {
    /// f(x), scene units.
    pub f: f32,
    /// ∇f(x).
    pub grad: Vec3,
    /// Σ wᵢ(x).
    pub weight: f32,
    /// |Σ wᵢ nᵢ| / Σ wᵢ: 1 where the neighbours' normals agree, small where they cancel.
    pub coherence: f32,
    /// Σ wᵢ hᵢ / Σ wᵢ, nm.
    pub thickness: f32,
    /// Number of particles with wᵢ(x) > 0.
    pub coverage: u32,
    /// Slot of the particle with the largest weight.
    pub best_slot: u32,
}

/// The weight of `c` at `x` and the squared-distance term u = 1 − |x − p|²/h² (`None` outside
/// the support).
#[inline(always)]
fn weight(c: &Cand, x: Vec3) -> Option<(f32, f32, Vec3)> {
    let d = x - c.p;
    let u = 1.0 - d.length_squared() * c.inv_h2;
    if u > 0.0 {
        Some((u * u * u, u, d))
    } else {
        None
    }
}

/// Candidates that may contribute at ray parameter `t` (those whose interval contains it). The
/// slice is sorted by `ta`, so the scan stops at the first later entry.
#[inline(always)]
fn active(cands: &[Cand], t: f32) -> impl Iterator<Item = &Cand> {
    cands
        .iter()
        .take_while(move |c| c.ta <= t)
        .filter(move |c| c.tb >= t)
}

/// f at `ray.at(t)` for candidates gathered along that ray (`None` where the total weight is
/// below [`MIN_EVAL_WEIGHT`]): [`value`] in one dimension, from each candidate's chord
/// (uᵢ = (k2ᵢ − (t − bᵢ)²)/hᵢ²) and its plane distance along the ray (gᵢ = g0ᵢ + g1ᵢ·t), so a
/// candidate costs a few multiplies and no 3D point. Candidates are scanned up to the first
/// entered after `t`; those already left weigh nothing (u ≤ 0).
#[inline]
pub(super) fn value_on_ray(cands: &[Cand], t: f32) -> Option<f32> {
    let (mut sw, mut sf) = (0.0f32, 0.0f32);
    for c in cands.iter().take_while(|c| c.ta <= t) {
        let dt = t - c.b;
        let u = ((c.k2 - dt * dt) * c.inv_h2).max(0.0);
        let w = u * u * u;
        sw += w;
        sf += w * (c.g0 + c.g1 * t);
    }
    (sw >= MIN_EVAL_WEIGHT).then(|| sf / sw)
}

/// f at `x = ray.at(t)` (`None` where the total weight is below [`MIN_EVAL_WEIGHT`]), from the
/// 3D points: the reference [`value_on_ray`] is checked against.
#[cfg(test)]
pub(super) fn value(cands: &[Cand], x: Vec3, t: f32) -> Option<f32> {
    let (mut sw, mut sf) = (0.0f32, 0.0f32);
    for c in active(cands, t) {
        if let Some((w, _, d)) = weight(c, x) {
            sw += w;
            sf += w * c.n.dot(d);
        }
    }
    (sw >= MIN_EVAL_WEIGHT).then(|| sf / sw)
}

/// f, ∇f and the interpolated attributes at `x = ray.at(t)`. With wᵢ' = ∇wᵢ = −6uᵢ²(x − pᵢ)/hᵢ²
/// and gᵢ = nᵢ·(x − pᵢ): ∇f = (Σ wᵢ nᵢ + Σ wᵢ'·(gᵢ − f)) / Σ wᵢ.
pub(super) fn sample(cands: &[Cand], x: Vec3, t: f32) -> Option<FieldSample> {
    let (mut sw, mut sf, mut swh) = (0.0f32, 0.0f32, 0.0f32);
    let (mut sn, mut sdg, mut sd) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    let (mut coverage, mut best, mut best_w) = (0u32, 0u32, -1.0f32);
    for c in active(cands, t) {
        if let Some((w, u, d)) = weight(c, x) {
            let g = c.n.dot(d);
            let dw = (-6.0 * u * u * c.inv_h2) * d;
            sw += w;
            sf += w * g;
            swh += w * c.thickness;
            sn += w * c.n;
            sdg += g * dw;
            sd += dw;
            coverage += 1;
            if w > best_w {
                best_w = w;
                best = c.slot;
            }
        }
    }
    if sw < MIN_EVAL_WEIGHT {
        return None;
    }
    let f = sf / sw;
    Some(FieldSample {
        f,
        grad: (sn + sdg - f * sd) / sw,
        weight: sw,
        coherence: sn.length() / sw,
        thickness: swh / sw,
        coverage,
        best_slot: best,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cand(p: Vec3, n: Vec3, h: f32, thickness: f32) -> Cand {
        Cand {
            p,
            inv_h2: 1.0 / (h * h),
            n,
            thickness,
            ta: f32::NEG_INFINITY,
            tb: f32::INFINITY,
            slot: 0,
            r: h,
            g0: 0.0,
            g1: 0.0,
            b: 0.0,
            k2: 0.0,
        }
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let cands: Vec<Cand> = (0..7)
            .map(|i| {
                let a = i as f32 * 0.9;
                let p = Vec3::new(a.cos() * 0.4, a.sin() * 0.3, 0.05 * a.sin());
                let n = Vec3::new(0.1 * a.cos(), 0.2 * a.sin(), 1.0).normalize();
                let mut c = cand(p, n, 0.8, 100.0 + 10.0 * i as f32);
                c.slot = i;
                c
            })
            .collect();
        let x = Vec3::new(0.1, -0.05, 0.07);
        let s = sample(&cands, x, 0.0).unwrap();
        assert!((s.f - value(&cands, x, 0.0).unwrap()).abs() < 1e-6);
        let e = 1e-3;
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let fd = (value(&cands, x + e * axis, 0.0).unwrap()
                - value(&cands, x - e * axis, 0.0).unwrap())
                / (2.0 * e);
            assert!((fd - s.grad.dot(axis)).abs() < 2e-3, "{fd} vs {}", s.grad);
        }
        assert_eq!(s.coverage, 7);
        assert!(s.thickness > 100.0 && s.thickness < 160.0);
        assert!(s.coherence > 0.9 && s.coherence <= 1.0 + 1e-6);
    }

    /// Random particles seen along random rays: f from the chords along the ray is f from the
    /// 3D points, wherever both are defined, and undefined where the 3D form is.
    #[test]
    fn value_on_the_ray_is_the_value_at_the_point() {
        let mut rnd = crate::geometry::ray4::test_rng(0x9e37_79b9);
        let mut compared = 0;
        for _ in 0..100 {
            let o = Vec3::new(3.0 * rnd(), 3.0 * rnd(), 4.0);
            let dir = (Vec3::new(0.5 * rnd(), 0.5 * rnd(), 0.0) - o).normalize();
            let mut cands: Vec<Cand> = (0..30)
                .filter_map(|i| {
                    let p = Vec3::new(rnd(), rnd(), 0.2 * rnd());
                    let n = (Vec3::Z + 0.5 * Vec3::new(rnd(), rnd(), rnd())).normalize();
                    let h = 0.3 + 0.2 * rnd().abs();
                    let f = o - p;
                    let b = -f.dot(dir);
                    let k2 = h * h - (f + b * dir).length_squared();
                    let mut c = cand(p, n, h, 100.0);
                    (c.ta, c.tb, c.slot) = (b - k2.max(0.0).sqrt(), b + k2.max(0.0).sqrt(), i);
                    (c.g0, c.g1, c.b, c.k2) = (n.dot(f), n.dot(dir), b, k2);
                    (k2 > 0.0).then_some(c)
                })
                .collect();
            cands.sort_unstable_by(|a, b| a.ta.total_cmp(&b.ta));
            for k in 0..600 {
                let t = 2.5 + k as f32 * 0.005;
                let (got, want) = (value_on_ray(&cands, t), value(&cands, o + t * dir, t));
                match (got, want) {
                    (Some(g), Some(w)) => {
                        assert!((g - w).abs() < 1e-4 * (1.0 + w.abs()), "{g} vs {w} at {t}");
                        compared += 1;
                    }
                    (None, None) => {}
                    // Rounding at the very edge of the supports.
                    (g, w) => assert!(g.or(w).unwrap().abs() < 1.0, "{g:?} vs {w:?} at {t}"),
                }
            }
        }
        assert!(compared > 10_000, "{compared}");
    }

    #[test]
    fn plane_is_reproduced_exactly() {
        // Particles on z = 0 with normal +z: f(x) = z anywhere in the support.
        let cands: Vec<Cand> = (0..9)
            .map(|i| {
                let p = Vec3::new((i % 3) as f32 - 1.0, (i / 3) as f32 - 1.0, 0.0);
                cand(p, Vec3::Z, 1.5, 0.0)
            })
            .collect();
        let x = Vec3::new(0.3, -0.2, 0.25);
        let s = sample(&cands, x, 0.0).unwrap();
        assert!((s.f - 0.25).abs() < 1e-6);
        assert!((s.grad - Vec3::Z).length() < 1e-5);
        assert!(value(&cands, Vec3::new(10.0, 0.0, 0.0), 0.0).is_none());
    }
}
