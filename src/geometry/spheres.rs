//! [`SphereGeometry`]: particles as spheres in a BVH, each drawn as one film crossing.

use glam::Vec3;

use super::particles::{check_particles, particle_accessors, particle_bvh};
use super::primitives::{sphere_bounds, sphere_roots};
use super::ray4::Ray4;
use super::sphere4::{PAD_SPHERE4, Sphere4};
use super::wide::{Node4, remap_leaves, traverse_prefetching};
use super::{Aabb, Bvh, Ray, SurfaceHit};
use crate::Result;
use crate::prefetch::prefetch_read;

/// Particles drawn as spheres around their centres (normals are not needed).
///
/// Layout: each BVH leaf's spheres are stored in its own run of 64-byte four-sphere packets
/// (`Sphere4`, structure-of-arrays), so a leaf test reads whole cache lines and needs no
/// gather; a *lane* `4 · packet + i` names one sphere of that layout. Memory: ~32 bytes per
/// sphere (packets, thickness and particle index per lane, padded to whole packets per leaf)
/// plus the BVH (~30 bytes per particle) and a copy of its 4-wide nodes whose leaves point at
/// packets (~15 bytes per particle). Queries are `&self` and thread-safe.
#[derive(Clone, Debug)]
pub struct SphereGeometry {
    pub(super) bvh: Bvh,
    /// The BVH's 4-wide nodes with each leaf's start turned into its first lane.
    tree: Vec<Node4>,
    /// The spheres, leaf by leaf, each leaf starting a packet.
    packets: Vec<Sphere4>,
    /// Per lane: film thickness (nm) and the particle's index (`u32::MAX` for padding).
    thickness: Vec<f32>,
    particle: Vec<u32>,
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
        // Each leaf (a slot range) starts a packet: its first lane, by its first slot.
        let mut leaves: Vec<(u32, u32)> = (bvh.nodes().iter())
            .filter(|n| n.is_leaf())
            .map(|n| (n.offset, n.count))
            .collect();
        leaves.sort_unstable();
        let mut lane_of = vec![0u32; bvh.len()];
        let mut lanes = 0u32;
        for &(first, count) in &leaves {
            lane_of[first as usize] = lanes;
            lanes += count.div_ceil(4) * 4;
        }
        let mut packets = vec![PAD_SPHERE4; lanes as usize / 4];
        let mut thickness = vec![0.0; lanes as usize];
        let mut particle = vec![u32::MAX; lanes as usize];
        for &(first, count) in &leaves {
            for s in first..first + count {
                let lane = (lane_of[first as usize] + s - first) as usize;
                let i = bvh.order()[s as usize];
                packets[lane / 4].set(lane % 4, positions[i as usize], radii[i as usize]);
                thickness[lane] = thickness_nm[i as usize];
                particle[lane] = i;
            }
        }
        let tree = remap_leaves(&bvh.wide, |first| lane_of[first as usize]);
        Ok(SphereGeometry {
            bvh,
            tree,
            packets,
            thickness,
            particle,
        })
    }

    /// The first sphere crossing with `t_min < t < t_max` (the entry point, or the exit point
    /// for a ray starting inside); ties in `t` go to the lowest particle index. `t_exit` is the
    /// far side of the sphere, since a sphere is drawn as one film crossing; the normal points
    /// outward. Leaves are tested four spheres at a time (`sphere4`, bit-identical to the
    /// scalar test).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        if !ray.is_valid() {
            return None;
        }
        let (lane, t) = self.closest_sphere(ray, t_min, t_max)?;
        let (center, radius) = self.packets[lane / 4].sphere(lane % 4);
        let position = ray.at(t);
        // A sphere is one film crossing: the ray leaves it at the far root (for a ray that
        // starts inside, the hit is already that root).
        let t_exit = sphere_roots(ray, center, radius).map_or(t, |(_, far)| far.max(t));
        Some(SurfaceHit {
            t,
            t_exit,
            position,
            normal: (position - center).normalize_or_zero(),
            thickness_nm: self.thickness[lane],
            coverage: 1,
            particle: self.particle[lane],
        })
    }

    /// Lane and distance of the closest sphere crossing: the leaves the ray enters, nearest
    /// first, four spheres a test; a hit replaces the best one if nearer, or as near and of a
    /// lower particle index (so the answer does not depend on the visiting order).
    #[inline]
    fn closest_sphere(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(usize, f32)> {
        let mut best: Option<(usize, f32)> = None;
        let r4 = Ray4::new(ray);
        // Inclusive of the current closest `t` (ties), as `intersect_sphere(.., hi)`.
        let hi = |best: Option<(usize, f32)>, lim: f32| {
            if best.is_some() { lim.next_up() } else { t_max }
        };
        let mut lim = t_max;
        let stack = self.bvh.wide_stack;
        // A deferred leaf's packets are fetched while nearer boxes are searched.
        let prefetch = |first: u32, count: u32| {
            for p in (first..first + count).step_by(4) {
                prefetch_read(&self.packets[p as usize / 4]);
            }
        };
        let leaf = |first: u32, count: u32, lim: &mut f32| {
            let first = first as usize;
            for p in (first..first + count as usize).step_by(4) {
                let lanes = (first + count as usize - p).min(4);
                let (t4, mut m) =
                    r4.test_spheres(&self.packets[p / 4], lanes, t_min, hi(best, *lim));
                while m != 0 {
                    let i = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let (lane, t) = (p + i, t4[i]);
                    if t < hi(best, *lim)
                        && best.is_none_or(|(bl, bt)| {
                            t < bt || self.particle[lane] < self.particle[bl]
                        })
                    {
                        best = Some((lane, t));
                        *lim = t;
                    }
                }
            }
            false
        };
        traverse_prefetching(&self.tree, stack, ray, t_min, &mut lim, leaf, prefetch);
        best
    }

    particle_accessors!();

    /// Heap bytes held (packets, per-lane arrays, BVH nodes and slot order, the remapped
    /// 4-wide nodes).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.tree.capacity() * std::mem::size_of::<Node4>()
            + self.packets.capacity() * std::mem::size_of::<Sphere4>()
            + self.thickness.capacity() * 4
            + self.particle.capacity() * 4
    }
}
