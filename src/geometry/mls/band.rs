//! Where along a ray the MLS function can be zero, from its particles' tangent planes alone.
//!
//! f(x) = Σ wᵢ gᵢ / Σ wᵢ is a convex combination of the signed plane distances gᵢ(x) =
//! nᵢ·(x − pᵢ) of the particles whose support contains x (wᵢ ≥ 0). Along a ray each gᵢ is linear
//! in t, so on the stretch where the ray is inside particle i's support the sign of gᵢ is known
//! exactly. Wherever every covering particle has gᵢ ≥ m (or every one gᵢ ≤ −m), f ≥ m (f ≤ −m):
//! no crossing. The band returned is the hull of the points where both signs are present —
//! a film's crossing is confined to the few hundredths of a spacing where its tangent planes
//! are crossed, so the march skips the approach to a film and the way out of it without
//! evaluating f (Adamson & Alexa's support spheres give the interval; the planes bound it).

use super::field::Cand;

/// The smallest interval of `[u, v]` outside which every particle of `cands` covering a point
/// has gᵢ > `margin` there, or every one has gᵢ < −`margin` (so f has one sign and |f| >
/// `margin`); `None` if there is no such point, i.e. f has no zero in `[u, v]`. Cost: O(n).
pub(super) fn sign_band(cands: &[Cand], u: f32, v: f32, margin: f32) -> Option<(f32, f32)> {
    let inf = f32::INFINITY;
    // Hulls of {t : some gᵢ(t) > −margin} and {t : some gᵢ(t) < margin}.
    let (mut pos_lo, mut pos_hi, mut neg_lo, mut neg_hi) = (inf, -inf, inf, -inf);
    for c in cands {
        let (lo, hi) = (c.ta.max(u), c.tb.min(v));
        if lo > hi {
            continue;
        }
        if let Some((a, b)) = above(c.g0 + margin, c.g1, lo, hi) {
            (pos_lo, pos_hi) = (pos_lo.min(a), pos_hi.max(b));
        }
        if let Some((a, b)) = above(margin - c.g0, -c.g1, lo, hi) {
            (neg_lo, neg_hi) = (neg_lo.min(a), neg_hi.max(b));
        }
    }
    let (lo, hi) = (pos_lo.max(neg_lo), pos_hi.min(neg_hi));
    (lo <= hi).then_some((lo, hi))
}

/// The part of `[lo, hi]` where `a + b·t > 0` (as a closed interval), if any.
#[inline(always)]
fn above(a: f32, b: f32, lo: f32, hi: f32) -> Option<(f32, f32)> {
    let (mut lo, mut hi) = (lo, hi);
    if b > 0.0 {
        lo = lo.max(-a / b);
    } else if b < 0.0 {
        hi = hi.min(-a / b);
    } else if a <= 0.0 {
        return None;
    }
    (lo <= hi).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::super::field;
    use super::*;
    use glam::Vec3;

    /// Random particles near z = 0 with tilted normals, seen along random rays: wherever f is
    /// defined outside the band its sign is the one the band promises, and f never changes sign
    /// outside it.
    #[test]
    fn f_has_no_zero_outside_the_band() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        let mut banded = 0;
        for _ in 0..200 {
            let o = Vec3::new(rnd(), rnd(), 2.0);
            let dir = (Vec3::new(0.7 * rnd(), 0.7 * rnd(), 0.0) - o).normalize();
            let cands: Vec<Cand> = (0..40)
                .filter_map(|i| {
                    let p = Vec3::new(rnd(), rnd(), 0.05 * rnd());
                    let n = (Vec3::Z + 0.3 * Vec3::new(rnd(), rnd(), rnd())).normalize();
                    let h = 0.4;
                    let f = o - p;
                    let b = -f.dot(dir);
                    let disc = h * h - (f + b * dir).length_squared();
                    (disc > 0.0).then(|| field::Cand {
                        p,
                        inv_h2: 1.0 / (h * h),
                        n,
                        thickness: 0.0,
                        ta: b - disc.sqrt(),
                        tb: b + disc.sqrt(),
                        slot: i,
                        r: 0.2,
                        g0: n.dot(o - p),
                        g1: n.dot(dir),
                        b,
                        k2: disc,
                    })
                })
                .collect();
            let mut sorted = cands.clone();
            sorted.sort_unstable_by(|a, b| a.ta.total_cmp(&b.ta));
            let band = sign_band(&cands, 0.0, 5.0, 1e-4);
            banded += band.is_some() as usize;
            let mut last: Option<(f32, f32)> = None;
            for k in 0..5000 {
                let t = k as f32 * 1e-3;
                let inside = band.is_some_and(|(a, b)| t >= a && t <= b);
                let Some(f) = field::value(&sorted, o + t * dir, t) else {
                    last = None;
                    continue;
                };
                if !inside {
                    assert!(f.abs() > 1e-4, "f = {f} at t = {t} outside {band:?}");
                    // Two samples on one side of the band have one sign.
                    if let Some((lt, l)) = last
                        && !band.is_some_and(|(a, _)| lt < a && t > a)
                    {
                        assert_eq!(l < 0.0, f < 0.0, "sign change at {t} outside {band:?}");
                    }
                }
                last = (!inside).then_some((t, f));
            }
        }
        assert!(banded > 100, "{banded}");
    }

    #[test]
    fn one_plane_gives_a_band_at_its_crossing() {
        // g(t) = 0.5 − t on [0, 2]: both signs within 0.01 of t = 0.5 only.
        let c = Cand {
            p: Vec3::ZERO,
            inv_h2: 1.0,
            n: Vec3::Z,
            thickness: 0.0,
            ta: 0.0,
            tb: 2.0,
            slot: 0,
            r: 1.0,
            g0: 0.5,
            g1: -1.0,
            b: 0.0,
            k2: 0.0,
        };
        let (a, b) = sign_band(&[c], 0.0, 2.0, 0.01).unwrap();
        assert!(
            (a - 0.49).abs() < 1e-6 && (b - 0.51).abs() < 1e-6,
            "{a} {b}"
        );
        assert!(sign_band(&[c], 0.6, 2.0, 0.01).is_none());
    }
}
