//! The build of the field's grid ([`super::grid::FieldGrid`]): φ at the nodes of the bricks a
//! support sphere reaches. The lattice is cut into tiles of [`TILE`]³ bricks; each tile (in
//! parallel) scatters the particles that reach it into one dense array of its nodes, a row of
//! nodes at a time (the kernel's x terms computed once a particle, one square root a row), and
//! then cuts that array into its bricks. Against scattering into each brick on its own, a
//! particle's kernel is split into a few tile pieces instead of ~60 brick pieces of rows of at
//! most five nodes, and no node on a shared brick face is summed twice.
//!
//! Every node sums the same particles in the same order (their index order) in whichever tile
//! computes it, so a node on a face two tiles share holds one value, and the result does not
//! depend on the threads.

use glam::{IVec3, Vec3, Vec4};
use rayon::prelude::*;

use super::field::MIN_WEIGHT;

/// Cells along a brick's side.
pub(super) const BRICK: i32 = 4;
/// Nodes along a brick's side (its faces' nodes are stored in both bricks that share them).
pub(super) const SIDE: usize = BRICK as usize + 1;
/// Nodes of a brick.
pub(super) const NODES: usize = SIDE * SIDE * SIDE;

/// Bricks along a tile's side.
const TILE: i32 = 4;
/// Cells along a tile's side.
const TILE_CELLS: i32 = TILE * BRICK;

/// The exact field is +R wherever the weight is below [`MIN_WEIGHT`], a jump the
/// interpolation would smear over a cell. The nodes hold ψ = max(φ, k s (MIN_WEIGHT − Σw))
/// instead: negative exactly where the exact field is, and continuous across the cut-off. k
/// makes that term change about a spacing per spacing where a lone particle's weight crosses
/// the cut-off (dΣw/dd ≈ 0.42 a spacing there), so the march's steps stay safe.
const CUT_OFF_SLOPE: f32 = 2.4;

/// What the field needs of the liquid: particle centres and the three lengths (scene units).
pub(super) struct Params<'a> {
    pub points: &'a [Vec3],
    pub spacing: f32,
    pub radius: f32,
    pub support: f32,
}

/// The lattice: its corner and its cell side, scene units.
#[derive(Clone, Copy)]
pub(super) struct Lattice {
    pub origin: Vec3,
    pub cell: f32,
}

/// ⌊v⌋ as an integer (without libm's `floorf`, which this target does not inline); `v` finite
/// and within `i32`'s range, else saturated.
#[inline(always)]
pub(super) fn floor(v: f32) -> i32 {
    let i = v as i32;
    if (i as f32) > v { i - 1 } else { i }
}

/// ⌈v⌉ as an integer, as [`floor`].
#[inline(always)]
fn ceil(v: f32) -> i32 {
    -floor(-v)
}

/// φ at the nodes of every brick with a node within some particle's support, by brick
/// coordinates (a brick no support reaches a node of would hold +R throughout, which is what
/// the grid answers where there is no brick). Cost: per particle, the ~1,300 nodes within its
/// support (at three cells a spacing), parallel over tiles.
pub(super) fn bricks(p: &Params, lat: Lattice) -> Vec<(IVec3, [f32; NODES])> {
    let inv_side = 1.0 / (TILE_CELLS as f32 * lat.cell);
    // Each tile whose nodes, far faces included, a support's box reaches: t ≤ u + r and
    // t + 1 ≥ u − r in tile units (a little generous; the tile clips exactly).
    let mut pairs: Vec<(IVec3, u32)> = Vec::with_capacity(p.points.len() * 8);
    for (i, &x) in p.points.iter().enumerate() {
        let u = (x - lat.origin) * inv_side;
        let r = p.support * inv_side;
        let r0 = r + 1e-4;
        let lo = IVec3::new(floor(u.x - r0), floor(u.y - r0), floor(u.z - r0));
        let hi = IVec3::new(floor(u.x + r), floor(u.y + r), floor(u.z + r));
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                for t in lo.x..=hi.x {
                    pairs.push((IVec3::new(t, y, z), i as u32));
                }
            }
        }
    }
    pairs.sort_unstable_by_key(|(k, i)| (k.z, k.y, k.x, *i));
    let mut tiles: Vec<(IVec3, &[(IVec3, u32)])> = Vec::new();
    let mut start = 0;
    for end in 1..=pairs.len() {
        if end == pairs.len() || pairs[end].0 != pairs[start].0 {
            tiles.push((pairs[start].0, &pairs[start..end]));
            start = end;
        }
    }
    let per_tile: Vec<Vec<(IVec3, [f32; NODES])>> = tiles
        .par_iter()
        .map(|(t, list)| Tile::scatter(p, lat, *t, list).bricks(p, *t))
        .collect();
    per_tile.concat()
}

/// The sums of one tile's nodes within `[a, b]` (tile node coordinates, inclusive; the rest
/// of its nodes no particle reaches): per node Σ wᵢ and Σ wᵢ (xᵢ − tile corner).
struct Tile {
    a: IVec3,
    b: IVec3,
    cell: f32,
    sums: Vec<Vec4>,
}

impl Tile {
    /// The node range of the support of a particle at `x` (relative to the tile's corner).
    fn reach(x: Vec3, support: f32, inv_cell: f32) -> (IVec3, IVec3) {
        let (lo, hi) = ((x - support) * inv_cell, (x + support) * inv_cell);
        let a = IVec3::new(ceil(lo.x), ceil(lo.y), ceil(lo.z)).max(IVec3::ZERO);
        let b = IVec3::new(floor(hi.x), floor(hi.y), floor(hi.z)).min(IVec3::splat(TILE_CELLS));
        (a, b)
    }

    /// Sums the kernels of the particles `list` over the nodes of tile `t`.
    fn scatter(p: &Params, lat: Lattice, t: IVec3, list: &[(IVec3, u32)]) -> Tile {
        let cell = lat.cell;
        let (inv_cell, r2) = (1.0 / cell, p.support * p.support);
        let inv_r2 = 1.0 / r2;
        let corner = lat.origin + (t * TILE_CELLS).as_vec3() * cell;
        let (mut a, mut b) = (IVec3::splat(TILE_CELLS + 1), IVec3::splat(-1));
        for &(_, i) in list {
            let (pa, pb) = Self::reach(p.points[i as usize] - corner, p.support, inv_cell);
            (a, b) = (a.min(pa), b.max(pb));
        }
        let dim = (b - a + IVec3::ONE).max(IVec3::ZERO);
        let (nx, ny) = (dim.x as usize, dim.y as usize);
        let mut sums = vec![Vec4::ZERO; nx * ny * dim.z.max(0) as usize];
        let mut ex = [0.0f32; TILE_CELLS as usize + 1];
        for &(_, i) in list {
            let x = p.points[i as usize] - corner;
            let (pa, pb) = Self::reach(x, p.support, inv_cell);
            if pa.cmpgt(pb).any() {
                continue;
            }
            // The x part of the kernel's argument, once a particle.
            for n in pa.x..=pb.x {
                let d = x.x - n as f32 * cell;
                ex[n as usize] = d * d * inv_r2;
            }
            let terms = Vec4::new(1.0, x.x, x.y, x.z);
            for nz in pa.z..=pb.z {
                let dz = x.z - nz as f32 * cell;
                for ny_ in pa.y..=pb.y {
                    let dy = x.y - ny_ as f32 * cell;
                    let off = dy * dy + dz * dz;
                    if off >= r2 {
                        continue;
                    }
                    // The row's nodes within the support: |dx| < √(R² − dy² − dz²).
                    let half = (r2 - off).sqrt();
                    let x0 = ceil((x.x - half) * inv_cell).max(pa.x);
                    let x1 = floor((x.x + half) * inv_cell).min(pb.x);
                    let q0 = 1.0 - off * inv_r2;
                    if x0 > x1 {
                        continue;
                    }
                    let row = ((nz - a.z) as usize * ny + (ny_ - a.y) as usize) * nx;
                    let (s0, s1) = (row + (x0 - a.x) as usize, row + (x1 - a.x) as usize);
                    let nodes = sums[s0..=s1].iter_mut();
                    for (sum, e) in nodes.zip(&ex[x0 as usize..=x1 as usize]) {
                        let q = (q0 - e).max(0.0);
                        *sum += terms * (q * q * q);
                    }
                }
            }
        }
        Tile { a, b, cell, sums }
    }

    /// The sums at tile node `n` (zero outside the range any particle reaches).
    #[inline]
    fn at(&self, n: IVec3) -> Vec4 {
        if n.cmplt(self.a).any() || n.cmpgt(self.b).any() {
            return Vec4::ZERO;
        }
        let d = n - self.a;
        let dim = self.b - self.a + IVec3::ONE;
        self.sums[((d.z * dim.y + d.y) * dim.x + d.x) as usize]
    }

    /// φ at the nodes of this tile's bricks that hold some weight, by brick coordinates (tile
    /// `t`'s bricks).
    fn bricks(&self, p: &Params, t: IVec3) -> Vec<(IVec3, [f32; NODES])> {
        let mut out = Vec::new();
        for bz in 0..TILE {
            for by in 0..TILE {
                for bx in 0..TILE {
                    let lo = IVec3::new(bx, by, bz) * BRICK;
                    let hi = lo + IVec3::splat(BRICK);
                    if hi.cmplt(self.a).any() || lo.cmpgt(self.b).any() {
                        continue;
                    }
                    if let Some(v) = self.brick(p, lo) {
                        out.push((t * TILE + IVec3::new(bx, by, bz), v));
                    }
                }
            }
        }
        out
    }

    /// φ at the nodes of the brick whose lowest tile node is `lo`; `None` if none has weight.
    fn brick(&self, p: &Params, lo: IVec3) -> Option<[f32; NODES]> {
        let mut v = [p.support; NODES];
        let mut any = false;
        for (k, out) in v.iter_mut().enumerate() {
            let o = IVec3::new(
                (k % SIDE) as i32,
                (k / SIDE % SIDE) as i32,
                (k / (SIDE * SIDE)) as i32,
            );
            let n = lo + o;
            let s = self.at(n);
            if s.x <= 0.0 {
                continue;
            }
            any = true;
            let mean = Vec3::new(s.y, s.z, s.w) / s.x;
            let phi = (mean - n.as_vec3() * self.cell).length() - p.radius;
            *out = phi.max(CUT_OFF_SLOPE * p.spacing * (MIN_WEIGHT - s.x));
        }
        any.then_some(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// A jittered 5×5×5 block and a few lone particles, spacing 1.
    fn cloud() -> Vec<Vec3> {
        let mut rnd = crate::geometry::ray4::test_rng(11);
        let mut pts = Vec::new();
        for z in 0..5 {
            for y in 0..5 {
                for x in 0..5 {
                    let p = Vec3::new(x as f32, y as f32, z as f32);
                    pts.push(p + 0.15 * Vec3::new(rnd(), rnd(), rnd()));
                }
            }
        }
        for i in 0..8 {
            pts.push(Vec3::new(9.0 + 3.1 * i as f32, 10.0 * rnd(), 10.0 * rnd()));
        }
        pts
    }

    /// Brute force over all particles: every node of every brick holds the field (the cut-off
    /// form), and every node some support reaches lies in a brick; no brick twice. Fails when
    /// a tile misses a particle (e.g. one tile fewer either side) or a row is cut short.
    #[test]
    fn every_node_holds_the_field_summed_over_all_particles() {
        let pts = cloud();
        let (s, support) = (1.0, 2.25);
        let p = Params {
            points: &pts,
            spacing: s,
            radius: 0.62,
            support,
        };
        let cell = s / 3.0;
        let origin = pts.iter().fold(Vec3::INFINITY, |a, x| a.min(*x)) - Vec3::splat(support);
        let lat = Lattice { origin, cell };
        let field = |n: IVec3| {
            let x = origin + n.as_vec3() * cell;
            let (mut w, mut sum) = (0.0f32, Vec3::ZERO);
            for &q in &pts {
                let t = 1.0 - (q - x).length_squared() / (support * support);
                if t > 0.0 {
                    w += t * t * t;
                    sum += t * t * t * (q - x);
                }
            }
            let phi = if w > 0.0 {
                let phi = (sum / w).length() - p.radius;
                phi.max(CUT_OFF_SLOPE * s * (MIN_WEIGHT - w))
            } else {
                support
            };
            (phi, w)
        };
        let bricks = bricks(&p, lat);
        let keys: HashSet<IVec3> = bricks.iter().map(|(k, _)| *k).collect();
        assert_eq!(keys.len(), bricks.len(), "a brick twice");
        let mut worst = 0.0f32;
        for (k, v) in &bricks {
            for (i, got) in v.iter().enumerate() {
                let o = IVec3::new((i % SIDE) as i32, (i / SIDE % SIDE) as i32, (i / 25) as i32);
                worst = worst.max((field(*k * BRICK + o).0 - got).abs());
            }
        }
        assert!(worst < 1e-4, "worst node off the field by {worst}");
        // Coverage: every node with weight, around every particle, in its brick.
        let reach = (support / cell).ceil() as i32;
        for &q in &pts {
            let c = ((q - origin) / cell).floor().as_ivec3();
            for d in (-reach..=reach).flat_map(|z| (-reach..=reach).map(move |y| (y, z))) {
                for x in -reach..=reach {
                    let n = c + IVec3::new(x, d.0, d.1);
                    if field(n).1 > 1e-6 {
                        let b = IVec3::new(
                            floor(n.x as f32 / 4.0),
                            floor(n.y as f32 / 4.0),
                            floor(n.z as f32 / 4.0),
                        );
                        assert!(
                            keys.contains(&b),
                            "node {n} has weight but brick {b} is missing"
                        );
                    }
                }
            }
        }
    }
}
