//! Four ray–sphere tests at once (SSE lanes via glam's `Vec4`), for the leaves of the sphere BVH.
//!
//! The lanes evaluate exactly the operations of [`sphere_roots`](super::primitives::sphere_roots)
//! and [`intersect_sphere`](super::primitives::intersect_sphere) in the same order (no fused
//! multiply-add), so each lane's `t` is bit-identical to the scalar test and hit/miss decisions
//! agree with it.

use glam::{BVec4A, Mat4, Vec3, Vec4};

use super::ray4::{Ray4, lane_mask};

/// Four spheres in structure-of-arrays form, one 64-byte cache line: the matrix's columns are
/// the centres' x, y, z and the radii (lane `i` a sphere), as [`Ray4::sphere_roots4`] reads
/// them, so a leaf's packet is one aligned load per column and no transpose. Unused lanes hold
/// [`PAD_SPHERE4`]'s NaN centre, which no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Sphere4(pub Mat4);

const _: () = assert!(std::mem::size_of::<Sphere4>() == 64);

/// A packet of four padding spheres: NaN centres, radius 0.
pub(super) const PAD_SPHERE4: Sphere4 =
    Sphere4(Mat4::from_cols(Vec4::NAN, Vec4::NAN, Vec4::NAN, Vec4::ZERO));

impl Sphere4 {
    /// Lane `lane`'s centre and radius.
    #[inline(always)]
    pub fn sphere(&self, lane: usize) -> (Vec3, f32) {
        let m = &self.0;
        (
            Vec3::new(m.x_axis[lane], m.y_axis[lane], m.z_axis[lane]),
            m.w_axis[lane],
        )
    }

    /// Puts a sphere into lane `lane`.
    pub fn set(&mut self, lane: usize, center: Vec3, radius: f32) {
        let m = &mut self.0;
        m.x_axis[lane] = center.x;
        m.y_axis[lane] = center.y;
        m.z_axis[lane] = center.z;
        m.w_axis[lane] = radius;
    }
}

/// Four rays' roots with four spheres ([`Ray4::sphere_roots4`]), lane `i` sphere `i`.
pub(crate) struct Roots4 {
    /// The two roots, unordered.
    pub t0: Vec4,
    /// See `t0`.
    pub t1: Vec4,
    /// The lanes whose roots are real (false for NaN).
    pub real: BVec4A,
    /// Where the ray passes closest to the centre, d·(c − o), scene units (`b` of
    /// `sphere_roots`).
    pub b: Vec4,
    /// The half chord's square, r² − e² (e the centre's distance from the ray), scene units².
    pub disc: Vec4,
}

impl Ray4 {
    /// The two roots along the ray of each of four spheres, `c`'s rows the centres' x, y, z
    /// and the radii (lane `i` a sphere), unordered, and the lanes where they are real (false
    /// for NaN). The operations of [`sphere_roots`](super::primitives::sphere_roots) in its
    /// order, so each lane is bit-identical to it; a ray tangent at its origin (q = 0) gets a
    /// double root at 0. The chord's middle and half-length² come with them (see [`Roots4`]).
    #[inline(always)]
    pub(crate) fn sphere_roots4(&self, c: &Mat4) -> Roots4 {
        let (fx, fy, fz) = (self.ox - c.x_axis, self.oy - c.y_axis, self.oz - c.z_axis);
        let b = -(fx * self.dx + fy * self.dy + fz * self.dz);
        let (px, py, pz) = (fx + b * self.dx, fy + b * self.dy, fz + b * self.dz);
        let r2 = c.w_axis * c.w_axis;
        let disc = r2 - (px * px + py * py + pz * pz);
        let real = disc.cmpge(Vec4::ZERO); // false for NaN
        let cc = (fx * fx + fy * fy + fz * fz) - r2;
        let q = b + disc.sqrt().copysign(b);
        let zero = q.cmpeq(Vec4::ZERO);
        let t0 = Vec4::select(zero, Vec4::ZERO, cc / q);
        let t1 = Vec4::select(zero, Vec4::ZERO, q);
        Roots4 {
            t0,
            t1,
            real,
            b,
            disc,
        }
    }

    /// The first crossing with `t_min < t < t_max` of each of the four spheres of `packet` (the
    /// entry point, or the exit point for a ray starting inside), and a bit mask (bit `i` for
    /// lane `i`) of the lanes that have one; lanes at or beyond `lanes` are masked off.
    #[inline(always)]
    pub fn test_spheres(
        &self,
        packet: &Sphere4,
        lanes: usize,
        t_min: f32,
        t_max: f32,
    ) -> (Vec4, u32) {
        let Roots4 {
            t0: ta,
            t1: tb,
            real,
            ..
        } = self.sphere_roots4(&packet.0);
        let (t0, t1) = (ta.min(tb), ta.max(tb));
        let (lo, hi) = (Vec4::splat(t_min), Vec4::splat(t_max));
        let in0 = t0.cmpgt(lo) & t0.cmplt(hi);
        let in1 = t1.cmpgt(lo) & t1.cmplt(hi);
        let t = Vec4::select(in0, t0, t1);
        let mask = (real & (in0 | in1)).bitmask() & lane_mask(lanes);
        (t, mask)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use crate::geometry::primitives::intersect_sphere;
    use crate::geometry::ray4::{assert_lanes_match, test_packet, test_rng};

    /// Every lane agrees bit for bit with the scalar test: rays from outside, from inside, on
    /// the surface, tangent and missing, masked-off lanes and padding spheres.
    #[test]
    fn lanes_match_scalar_sphere_test() {
        let mut rnd = test_rng(0x9e37_79b9);
        let mut hits = 0;
        for k in 0..4000 {
            let spheres = test_packet(k, (Vec3::NAN, 0.0), || {
                (
                    Vec3::new(rnd(), rnd(), rnd()) * 0.3,
                    0.05 + 0.3 * rnd().abs(),
                )
            });
            let mut packet = PAD_SPHERE4;
            for (lane, &(center, radius)) in spheres.iter().enumerate() {
                packet.set(lane, center, radius);
            }
            let (c, r) = spheres[k % 2];
            let (origin, dir) = match k % 4 {
                // From inside.
                0 => (
                    c + Vec3::new(rnd(), rnd(), rnd()) * 0.3 * r,
                    Vec3::new(rnd(), rnd(), 1.0),
                ),
                // From exactly on the surface (x axis), tangent or not.
                1 => (c + Vec3::X * r, if k % 8 == 1 { Vec3::Y } else { -Vec3::X }),
                // Aimed near a centre from outside.
                _ => {
                    let o = Vec3::new(rnd(), rnd(), rnd() + 2.0);
                    (o, c + Vec3::new(rnd(), rnd(), rnd()) * 0.2 - o)
                }
            };
            let ray = Ray::new(origin, dir);
            let (t_min, t_max) = if k % 3 == 0 { (0.1, 2.0) } else { (0.0, 10.0) };
            let lanes = 1 + k % 4;
            let (t, mask) = Ray4::new(&ray).test_spheres(&packet, lanes, t_min, t_max);
            hits += assert_lanes_match(
                k,
                lanes,
                |i| (mask & (1 << i) != 0).then(|| t[i].to_bits()),
                |i| {
                    let (center, radius) = spheres[i];
                    intersect_sphere(&ray, center, radius, t_min, t_max).map(f32::to_bits)
                },
            );
        }
        assert!(hits > 2000, "only {hits} hits");
    }
}
