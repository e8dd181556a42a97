//! [`DiskGeometry::intersect_tile`]: the layer query for a tile of camera rays from one origin,
//! with one walk of the tree for the whole tile (`wide_tile`) instead of one per ray.
//!
//! Each ray keeps its own single-pass layer search (`disk_query`): it is tested against the leaf
//! boxes of the nodes the tile enters with its own pruning distance, then against the disks of
//! the leaves it enters. The search's result does not depend on the order the leaves come in
//! (the closest disk is the closest whatever the order, the layer's members are summed in slot
//! order, and incomplete candidates send the ray to the same second traversal), and every leaf
//! the ray's own traversal would test is offered to it, so each ray gets exactly the crossing
//! [`DiskGeometry::intersect`] gives it.

use super::aabb::SLAB_ROBUST;
use super::disk_query::LayerSearch;
use super::disks::DiskGeometry;
use super::ray4::Ray4;
use super::wide::{Slabs, sort_lanes};
use super::wide_tile::{Bundle, walk};
use super::{Ray, SurfaceHit};

/// Most rays one tile query traces together (an 8×8 tile); longer slices are split.
pub const TILE_RAYS: usize = 64;

/// One ray of the tile and its search.
struct TileRay {
    ray: Ray,
    slabs: Slabs,
    lim: f32,
    search: LayerSearch,
}

impl DiskGeometry {
    /// [`DiskGeometry::intersect`] for each of `rays`, written to `out` (as many entries as
    /// rays): the same crossing, bit for bit. Rays with one origin (a pinhole camera's, best
    /// a compact block of neighbouring pixels) share one walk of the tree, [`TILE_RAYS`] at a
    /// time; rays with different origins (depth of field), invalid rays or a geometry with few
    /// disks per pixel gain nothing and are traced one at a time.
    ///
    /// # Panics
    /// If `out` and `rays` differ in length.
    pub fn intersect_tile(
        &self,
        rays: &[Ray],
        t_min: f32,
        t_max: f32,
        out: &mut [Option<SurfaceHit>],
    ) {
        assert_eq!(rays.len(), out.len(), "one output per ray");
        for (rays, out) in rays.chunks(TILE_RAYS).zip(out.chunks_mut(TILE_RAYS)) {
            let bundle = if rays.iter().all(Ray::is_valid) {
                Bundle::new(rays, t_min)
            } else {
                None
            };
            match bundle {
                Some(b) => self.trace_bundle(&b, rays, t_min, t_max, out),
                None => {
                    for (r, o) in rays.iter().zip(out) {
                        *o = self.intersect(r, t_min, t_max);
                    }
                }
            }
        }
    }

    /// The tile's rays searched over one shared walk, then blended one by one.
    fn trace_bundle(
        &self,
        bundle: &Bundle,
        rays: &[Ray],
        t_min: f32,
        t_max: f32,
        out: &mut [Option<SurfaceHit>],
    ) {
        let mut tile: Vec<TileRay> = rays
            .iter()
            .map(|r| TileRay {
                ray: *r,
                slabs: Slabs::new(r, t_min),
                lim: t_max,
                search: LayerSearch::new(),
            })
            .collect();
        let (nodes, stack) = (&self.bvh.wide, self.bvh.wide_stack);
        walk(nodes, stack, bundle, t_max, |n, leaves| {
            let mut bound = f32::NEG_INFINITY;
            for tr in tile.iter_mut() {
                let (hit, tn) = tr.slabs.test(n, tr.lim);
                let m = hit & leaves;
                if m != 0 {
                    let r4 = Ray4::new(&tr.ray);
                    // The ray's leaves nearest first (by its own entry distances).
                    let sorted = sort_lanes(tn, m);
                    for &k in &sorted[..m.count_ones() as usize] {
                        let i = (k & 3) as usize;
                        if tn[i] > tr.lim * SLAB_ROBUST {
                            break;
                        }
                        let (ray, search, lim) = (&tr.ray, &mut tr.search, &mut tr.lim);
                        let leaf = (n.child[i], n.count[i]);
                        self.disk_leaf(ray, &r4, leaf, t_min, t_max, |s, t, d2| {
                            search.offer(self, ray, t_max, lim, (s, t, d2))
                        });
                    }
                }
                bound = bound.max(tr.lim);
            }
            bound
        });
        for (tr, o) in tile.iter_mut().zip(out) {
            *o = self.blend_layer(&tr.ray, t_min, t_max, &mut tr.search);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ray4::test_rng;
    use glam::Vec3;

    /// A Fibonacci shell of `n` unit-sphere disks, radii 0.9–1.5× the spacing.
    fn shell(n: usize) -> DiskGeometry {
        let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
        let spacing = (4.0 * std::f32::consts::PI / n as f32).sqrt();
        let pos: Vec<Vec3> = (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
                let (r, a) = ((1.0 - z * z).sqrt(), golden * i as f32);
                Vec3::new(r * a.cos(), r * a.sin(), z)
            })
            .collect();
        let radii: Vec<f32> = (0..n)
            .map(|i| (0.9 + 0.6 * ((i * 7919) % 1000) as f32 / 1000.0) * spacing)
            .collect();
        let thk: Vec<f32> = pos.iter().map(|p| 500.0 + 300.0 * p.z).collect();
        DiskGeometry::build(&pos, &pos, &radii, &thk).unwrap()
    }

    /// A pinhole camera's `side`×`side` tile of rays from `eye` towards `at`, `px` radians a
    /// pixel, starting `(x0, y0)` pixels off the view axis.
    fn tile(eye: Vec3, at: Vec3, px: f32, (x0, y0): (f32, f32), side: usize) -> Vec<Ray> {
        let fwd = (at - eye).normalize();
        let right = fwd.cross(Vec3::Y).normalize();
        let up = right.cross(fwd);
        (0..side * side)
            .map(|k| {
                let (x, y) = (x0 + (k % side) as f32 + 0.5, y0 + (k / side) as f32 + 0.5);
                Ray::new(eye, fwd + px * x * right + px * y * up)
            })
            .collect()
    }

    /// Checks every ray of `rays` against its own layer query, bit for bit; returns (hits,
    /// misses, second traversals).
    fn check(g: &DiskGeometry, rays: &[Ray], t_min: f32, t_max: f32) -> [usize; 3] {
        let mut got = vec![None; rays.len()];
        g.intersect_tile(rays, t_min, t_max, &mut got);
        let mut counts = [0; 3];
        for (k, (ray, got)) in rays.iter().zip(&got).enumerate() {
            let want = g.intersect(ray, t_min, t_max);
            let bits = |h: &Option<SurfaceHit>| {
                h.map(|h| {
                    let v = [
                        h.t,
                        h.t_exit,
                        h.thickness_nm,
                        h.normal.x,
                        h.normal.y,
                        h.normal.z,
                    ];
                    (v.map(f32::to_bits), h.coverage, h.particle)
                })
            };
            assert_eq!(bits(got), bits(&want), "ray {k}: {ray:?}");
            counts[want.is_none() as usize] += 1;
            counts[2] += g.needs_second_traversal(ray, t_min, t_max) as usize;
        }
        counts
    }

    /// The tile query gives every ray exactly its own layer query's crossing: random 8×8
    /// tiles of pinhole cameras outside and inside a 20k-disk shell, at the silhouette (rays
    /// that miss), continuing past a first crossing, with depth of field (origins differ) and
    /// an invalid ray; and a stack of 120 disks whose band holds more candidates than the
    /// single pass keeps, so the second traversal runs.
    #[test]
    fn tile_query_matches_the_per_ray_query() {
        let g = shell(20_000);
        let mut rnd = test_rng(0x1234_5678);
        let mut total = [0usize; 3];
        for k in 0..120 {
            let (eye, px) = if k % 6 == 5 {
                (Vec3::new(rnd(), rnd(), rnd()) * 0.3, 0.004)
            } else {
                let d = 1.6 + 2.0 * rnd().abs();
                (Vec3::new(rnd(), rnd(), rnd()).normalize() * d, 0.004 / d)
            };
            // Aimed at the centre, or off it so the tile meets the silhouette.
            let at = Vec3::new(rnd(), rnd(), rnd()) * if k % 3 == 0 { 0.97 } else { 0.3 };
            let off = (rnd() * 200.0, rnd() * 200.0);
            let rays = tile(eye, at, px, off, 8);
            let t_min = if k % 4 == 3 { 1.0 } else { 0.0 };
            let c = check(&g, &rays, t_min, f32::INFINITY);
            total.iter_mut().zip(c).for_each(|(t, c)| *t += c);
        }
        let [hits, misses, _] = total;
        assert!(hits > 3000 && misses > 300, "hits {hits}, misses {misses}");
        // 100 rays: a full tile and a partial one.
        let mut rays = tile(
            Vec3::new(0.2, 0.1, 3.0),
            Vec3::ZERO,
            0.002,
            (-5.0, -5.0),
            10,
        );
        check(&g, &rays, 0.0, 2.5);
        // Depth of field, and an invalid ray.
        rays[3].origin += Vec3::splat(1e-3);
        check(&g, &rays, 0.0, f32::INFINITY);
        rays[7].dir = Vec3::ZERO;
        check(&g, &rays, 0.0, f32::INFINITY);
        // A stack of nearly coplanar disks: more than the candidate buffer in one band.
        let pos: Vec<Vec3> = (0..120)
            .map(|i| Vec3::new(0.01 * rnd(), 0.01 * rnd(), 1e-4 * i as f32))
            .collect();
        let normals = vec![Vec3::Z; pos.len()];
        let radii = vec![1.0; pos.len()];
        let thk: Vec<f32> = (0..pos.len()).map(|i| 300.0 + i as f32).collect();
        let stack = DiskGeometry::build(&pos, &normals, &radii, &thk).unwrap();
        let rays = tile(Vec3::new(0.1, 0.2, 3.0), Vec3::ZERO, 0.01, (-4.0, -4.0), 8);
        let [hits, _, second] = check(&stack, &rays, 0.0, f32::INFINITY);
        assert!(
            hits == 64 && second == 64,
            "hits {hits}, second traversals {second}"
        );
        eprintln!("shell: {total:?} (hits, misses, second traversals)");
    }
}
