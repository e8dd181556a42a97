//! Four ray–disk tests at once (SSE lanes via glam's `Vec4`), for the leaves of the disk BVH.
//!
//! The lanes evaluate exactly the operations of [`intersect_disk`](super::primitives::intersect_disk)
//! in the same order (no fused multiply-add), so each lane's `t` and `d2` are bit-identical to
//! the scalar test and hit/miss decisions agree with it.

use glam::{Mat4, Vec3, Vec4};

use super::primitives::DISK_PARALLEL_COS;
use super::ray4::{Ray4, lane_mask};

/// A disk in slot order (32 bytes). The array is followed by [`PAD`](super::ray4::PAD)
/// [`PAD_DISK`]s.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(super) struct DiskPrim {
    pub center: Vec3,
    pub radius: f32,
    pub normal: Vec3,
    pub thickness: f32,
}

/// Disks the slot array is padded with, so a packet starting at any slot can read four: zero
/// normal (parallel to every ray, never hit).
pub(super) const PAD_DISK: DiskPrim = DiskPrim {
    center: Vec3::ZERO,
    radius: 0.0,
    normal: Vec3::ZERO,
    thickness: 0.0,
};

/// Hits of one packet: distances and squared distances to the centres per lane, and a bit mask
/// (bit `i` for lane `i`) of the lanes that hit within the range.
pub(super) struct Hits4 {
    pub t: Vec4,
    pub d2: Vec4,
    pub mask: u32,
}

impl Ray4 {
    /// Tests the disks `disks[0..4]` against the ray for `t_min < t < t_max`; lanes at or beyond
    /// `lanes` are masked off. Cost: one 4-lane division and ~30 lane operations.
    #[inline(always)]
    pub fn test_disks(&self, disks: &[DiskPrim; 4], lanes: usize, t_min: f32, t_max: f32) -> Hits4 {
        let cr = |d: &DiskPrim| Vec4::new(d.center.x, d.center.y, d.center.z, d.radius);
        let nt = |d: &DiskPrim| Vec4::new(d.normal.x, d.normal.y, d.normal.z, 0.0);
        let c =
            Mat4::from_cols(cr(&disks[0]), cr(&disks[1]), cr(&disks[2]), cr(&disks[3])).transpose();
        let n =
            Mat4::from_cols(nt(&disks[0]), nt(&disks[1]), nt(&disks[2]), nt(&disks[3])).transpose();
        let (nx, ny, nz) = (n.x_axis, n.y_axis, n.z_axis);
        // Same expression order as `intersect_disk`.
        let denom = nx * self.dx + ny * self.dy + nz * self.dz;
        let ocx = c.x_axis - self.ox;
        let ocy = c.y_axis - self.oy;
        let ocz = c.z_axis - self.oz;
        let t = (nx * ocx + ny * ocy + nz * ocz) / denom;
        let (px, py, pz) = (t * self.dx - ocx, t * self.dy - ocy, t * self.dz - ocz);
        let d2 = px * px + py * py + pz * pz;
        let r = c.w_axis;
        let ok = denom.abs().cmpgt(Vec4::splat(DISK_PARALLEL_COS))
            & t.cmpgt(Vec4::splat(t_min))
            & t.cmplt(Vec4::splat(t_max))
            & d2.cmple(r * r);
        Hits4 {
            t,
            d2,
            mask: ok.bitmask() & lane_mask(lanes),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use crate::geometry::primitives::intersect_disk;
    use crate::geometry::ray4::{assert_lanes_match, test_packet, test_rng};

    /// Every lane agrees bit for bit with the scalar test, including near-parallel rays, rays
    /// in a disk's plane, masked-off lanes and padding disks.
    #[test]
    fn lanes_match_scalar_disk_test() {
        let mut rnd = test_rng(0x2545_f491);
        let mut hits = 0;
        for k in 0..4000 {
            let disks = test_packet(k, PAD_DISK, || {
                let n = Vec3::new(rnd(), rnd(), rnd() + 1e-3).normalize();
                DiskPrim {
                    center: Vec3::new(rnd(), rnd(), rnd()) * 0.3,
                    radius: 0.05 + 0.3 * rnd().abs(),
                    normal: if k % 5 == 0 { Vec3::Z } else { n },
                    thickness: 0.0,
                }
            });
            let origin = Vec3::new(rnd(), rnd(), rnd() * 0.1);
            let dir = if k % 5 == 0 {
                // Parallel, or nearly parallel, to the z-normal disks.
                Vec3::new(rnd(), rnd(), [0.0, 1e-8, 1e-3][k % 3])
            } else {
                // Aimed near a disk centre.
                disks[k % 2].center + Vec3::new(rnd(), rnd(), rnd()) * 0.1 - origin
            };
            let ray = Ray::new(origin, dir);
            let (t_min, t_max) = if k % 3 == 0 { (0.1, 0.6) } else { (0.0, 10.0) };
            let lanes = 1 + k % 4;
            let h = Ray4::new(&ray).test_disks(&disks, lanes, t_min, t_max);
            hits += assert_lanes_match(
                k,
                lanes,
                |i| (h.mask & (1 << i) != 0).then(|| (h.t[i].to_bits(), h.d2[i].to_bits())),
                |i| {
                    let d = &disks[i];
                    intersect_disk(&ray, d.center, d.normal, d.radius, t_min, t_max)
                        .map(|(t, d2)| (t.to_bits(), d2.to_bits()))
                },
            );
        }
        assert!(hits > 1000, "only {hits} hits");
    }
}
