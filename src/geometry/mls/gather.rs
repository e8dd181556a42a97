//! The gathering of the support spheres along a ray: a BVH traversal whose leaves'
//! spheres are tested four at a time (SSE lanes), each lane computing exactly what
//! [`sphere_roots`](crate::geometry::primitives::sphere_roots) does, in the same order.

use glam::{Mat4, Vec4};

use super::MlsSurface;
use super::field::{Cand, Chord};
use crate::geometry::Ray;
use crate::geometry::ray4::{Ray4, lane_mask};

impl MlsSurface {
    /// Collects into `cands` every support sphere the ray is inside somewhere in
    /// `(from, t_max)`, in the order of the BVH's near-first traversal (a leaf's spheres in
    /// slot order). The whole ray at once: gathering only the spheres entered within a window
    /// of 6 support radii beyond the first one, and traversing again for the rest when no
    /// crossing lay in it (a bubble's back wall, a transmitted branch), cost more on the real
    /// frames (docs/benchmarks.md); the pictures are the same either way.
    pub(super) fn gather_all(&self, ray: &Ray, from: f32, t_max: f32, cands: &mut Vec<Cand>) {
        cands.clear();
        let r4 = Ray4::new(ray);
        self.bvh
            .closest_leaves(ray, from, t_max, |first, count, _| {
                let end = first + count;
                for s in (first..end).step_by(4) {
                    let lanes = (end - s).min(4) as usize;
                    let c = self.clip4(&r4, s, lanes, from, t_max);
                    let mut m = c.mask;
                    if m == 0 {
                        continue;
                    }
                    // 1/h² and the particle radius h/support, as `cand` computes them.
                    let inv_h2 = Vec4::ONE / (c.h * c.h);
                    let r = c.h / Vec4::splat(self.params.support);
                    // In slot order.
                    while m != 0 {
                        let i = m.trailing_zeros() as usize;
                        m &= m - 1;
                        let chord = Chord {
                            ta: c.ta[i],
                            tb: c.tb[i],
                            b: c.b[i],
                            k2: c.k2[i],
                            inv_h2: inv_h2[i],
                            r: r[i],
                        };
                        cands.push(self.cand_chord(ray, s + i as u32, chord));
                    }
                }
            });
    }

    /// Where the ray is inside each of the support spheres of slots `s .. s + lanes` (at most
    /// four) within `(t_min, t_max)` (lane `i` of the mask: the scalar `clip` of that sphere, bit
    /// for bit), with the chords `cand_on` needs.
    #[inline(always)]
    fn clip4(&self, r: &Ray4, s: u32, lanes: usize, t_min: f32, t_max: f32) -> Clip4 {
        let q = |k: usize| {
            let p = &self.particles[s as usize + k.min(lanes - 1)];
            Vec4::new(p.p.x, p.p.y, p.p.z, p.h)
        };
        let c = Mat4::from_cols(q(0), q(1), q(2), q(3)).transpose();
        // The operations of `sphere_roots`, in its order.
        let roots = r.sphere_roots4(&c);
        let (t0, t1) = (roots.t0, roots.t1);
        let lower = t0.cmple(t1);
        let (lo, hi) = (Vec4::select(lower, t0, t1), Vec4::select(lower, t1, t0));
        // `clip`: (max(t0, t_min), min(t1, t_max)) if not empty.
        let ta = Vec4::select(lo.cmpgt(Vec4::splat(t_min)), lo, Vec4::splat(t_min));
        let tb = Vec4::select(hi.cmplt(Vec4::splat(t_max)), hi, Vec4::splat(t_max));
        let mask = (roots.real & ta.cmplt(tb)).bitmask() & lane_mask(lanes);
        Clip4 {
            ta,
            tb,
            mask,
            b: roots.b,
            k2: roots.disc,
            h: c.w_axis,
        }
    }
}

/// Four support spheres clipped to a ray ([`MlsSurface::clip4`]), lane `i` sphere `i`.
struct Clip4 {
    /// Entries, clipped to the query.
    ta: Vec4,
    /// Exits, clipped to the query.
    tb: Vec4,
    /// The lanes the ray is inside somewhere in the query.
    mask: u32,
    /// Where the ray passes closest to the centre (`Cand::b`).
    b: Vec4,
    /// h² − e² (`Cand::k2`).
    k2: Vec4,
    /// Support radii.
    h: Vec4,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::sphere_roots;
    use glam::Vec3;

    /// Every lane agrees bit for bit with the scalar roots clipped as the gathering clips
    /// them: rays from outside and inside the spheres, near misses, short ranges, partial packets.
    #[test]
    fn lanes_match_the_scalar_roots() {
        let mut rnd = crate::geometry::ray4::test_rng(0x2545_f491);
        let p: Vec<Vec3> = (0..9).map(|_| Vec3::new(rnd(), rnd(), rnd())).collect();
        let n = vec![Vec3::Z; p.len()];
        let radii: Vec<f32> = (0..p.len()).map(|_| 0.1 + 0.3 * rnd().abs()).collect();
        let m = MlsSurface::build(&p, &n, &radii, &vec![100.0; p.len()]).unwrap();
        let mut hits = 0;
        for k in 0..3000 {
            let slot = (k % p.len()) as u32;
            let target = m.particles[slot as usize].p + 0.5 * Vec3::new(rnd(), rnd(), rnd());
            let origin = if k % 5 == 0 {
                target + 0.1 * Vec3::new(rnd(), rnd(), rnd())
            } else {
                Vec3::new(3.0 * rnd(), 3.0 * rnd(), 4.0)
            };
            let ray = Ray::new(origin, target - origin);
            let (t_min, t_max) = if k % 3 == 0 { (0.0, 100.0) } else { (4.0, 5.0) };
            let first = (k % 7) as u32;
            let lanes = (p.len() - first as usize).min(4);
            let c = m.clip4(&Ray4::new(&ray), first, lanes, t_min, t_max);
            let (ta, tb, mask) = (c.ta, c.tb, c.mask);
            for i in 0..4 {
                let q = &m.particles[first as usize + i.min(lanes - 1)];
                let want = (i < lanes)
                    .then(|| sphere_roots(&ray, q.p, q.h))
                    .flatten()
                    .map(|(t0, t1)| (t0.max(t_min), t1.min(t_max)))
                    .filter(|(a, b)| a < b);
                let got = (mask >> i & 1 == 1).then(|| (ta[i], tb[i]));
                let bits = |v: Option<(f32, f32)>| v.map(|(a, b)| (a.to_bits(), b.to_bits()));
                assert_eq!(bits(got), bits(want), "case {k} lane {i}");
                hits += got.is_some() as usize;
            }
        }
        assert!(hits > 1000, "{hits}");
    }
}
