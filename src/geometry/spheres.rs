//! [`SphereGeometry`]: particles as spheres in a BVH, each drawn as one film crossing.

use glam::Vec3;

use super::particles::{check_particles, padded_slots, particle_accessors, particle_bvh};
use super::primitives::{sphere_bounds, sphere_roots};
use super::ray4::Ray4;
use super::sphere4::{PAD_SPHERE, SpherePrim};
use super::{Aabb, Bvh, Ray, SurfaceHit};
use crate::Result;

/// Particles drawn as spheres around their centres (normals are not needed).
///
/// Memory: 20 bytes per sphere plus the BVH (~30 bytes per particle). Leaves are tested four
/// spheres at a time. Queries are `&self` and thread-safe.
#[derive(Clone, Debug)]
pub struct SphereGeometry {
    pub(super) bvh: Bvh,
    /// The spheres in slot order, followed by [`PAD`](super::ray4::PAD) padding spheres.
    pub(super) spheres: Vec<SpherePrim>,
}

impl SphereGeometry {
    /// Builds the spheres. All slices have one entry per particle; `normals` are not needed
    /// and may be empty (if given, their count is checked). Radii must be finite and positive,
    /// thickness finite and non-negative, positions finite. Errors name the offending array and
    /// particle. Cost: O(n log n), parallel.
    pub fn build(
        positions: &[Vec3],
        normals: &[Vec3],
        radii: &[f32],
        thickness_nm: &[f32],
    ) -> Result<Self> {
        check_particles(positions, normals, radii, thickness_nm, false)?;
        let bvh = particle_bvh(
            positions.len(),
            |i| positions[i],
            |i| radii[i],
            |i| sphere_bounds(positions[i], radii[i]),
        );
        let spheres = padded_slots(bvh.order(), PAD_SPHERE, |i| SpherePrim {
            center: positions[i],
            radius: radii[i],
            thickness: thickness_nm[i],
        });
        Ok(SphereGeometry { bvh, spheres })
    }

    /// The first sphere crossing with `t_min < t < t_max` (the entry point, or the exit point
    /// for a ray starting inside); ties in `t` go to the lowest particle index. `t_exit` is the
    /// far side of the sphere, since a sphere is drawn as one film crossing; the normal points
    /// outward. Leaves are tested four spheres at a time (`sphere4`, bit-identical to the
    /// scalar test), the hits then handled in slot order as the scalar loop did.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        if !ray.is_valid() {
            return None;
        }
        let (slot, t) = self.closest_sphere(ray, t_min, t_max)?;
        let p = &self.spheres[slot as usize];
        let position = ray.at(t);
        // A sphere is one film crossing: the ray leaves it at the far root (for a ray that
        // starts inside, the hit is already that root).
        let t_exit = sphere_roots(ray, p.center, p.radius).map_or(t, |(_, far)| far.max(t));
        Some(SurfaceHit {
            t,
            t_exit,
            position,
            normal: (position - p.center).normalize_or_zero(),
            thickness_nm: p.thickness,
            coverage: 1,
            particle: self.bvh.order[slot as usize],
        })
    }

    /// Slot and distance of the closest sphere crossing.
    #[inline]
    fn closest_sphere(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(u32, f32)> {
        let mut best: Option<(u32, f32)> = None;
        let r4 = Ray4::new(ray);
        // Inclusive of the current closest `t` (ties), as `intersect_sphere(.., hi)`.
        let hi = |best: Option<(u32, f32)>, lim: f32| {
            if best.is_some() { lim.next_up() } else { t_max }
        };
        self.bvh
            .closest_leaves(ray, t_min, t_max, |first, count, lim| {
                for (s, packet, lanes) in self.sphere_packets((first, count)) {
                    let (t4, mut m) = r4.test_spheres(packet, lanes, t_min, hi(best, *lim));
                    while m != 0 {
                        let i = m.trailing_zeros() as usize;
                        m &= m - 1;
                        let (slot, t) = ((s + i) as u32, t4[i]);
                        if t < hi(best, *lim)
                            && best
                                .is_none_or(|(bs, bt)| t < bt || self.bvh.lower_particle(slot, bs))
                        {
                            best = Some((slot, t));
                            *lim = t;
                        }
                    }
                }
            });
        best
    }

    /// Sphere packets of the slots `first .. first + count`: (first slot, four spheres, lanes in
    /// range). The sphere array is padded, so four spheres can be read from any slot.
    #[inline(always)]
    fn sphere_packets(
        &self,
        (first, count): (u32, u32),
    ) -> impl Iterator<Item = (usize, &[SpherePrim; 4], usize)> {
        let end = first as usize + count as usize;
        (first as usize..end)
            .step_by(4)
            .filter_map(move |s| Some((s, self.spheres[s..].first_chunk::<4>()?, (end - s).min(4))))
    }

    particle_accessors!();

    /// Heap bytes held (spheres, BVH nodes, slot order).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes() + self.spheres.capacity() * std::mem::size_of::<SpherePrim>()
    }
}
