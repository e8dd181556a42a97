//! The build of the field's grid ([`super::grid::FieldGrid`]): φ at the nodes of the bricks a
//! support sphere reaches. The lattice is cut into tiles of [`TILE`]³ bricks; each tile (in
//! parallel) scatters the particles that reach it into dense arrays of its nodes (Σ w and the
//! three sums of Σ w x, each an array of its own), a row of nodes at a time: the kernel's x
//! terms computed once a particle, and each row of its support's box taken in fixed runs of
//! [`LANES`] nodes (no square root or bounds a row; the nodes past the support add zero), so
//! the sums compile to four-wide vector code. φ is then computed once a node of the tile and
//! copied into its bricks. Against scattering into each brick on its own, a
//! particle's kernel is split into a few tile pieces instead of ~60 brick pieces of rows of at
//! most five nodes, and no node on a shared brick face is summed twice.
//!
//! Every node sums the same particles in the same order (their index order) in whichever tile
//! computes it, so a node on a face two tiles share holds one value, and the result does not
//! depend on the threads.

use glam::{IVec3, Vec3};
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

/// Nodes a row of a particle's kernel is scattered in at once: a fixed width, so the update
/// is a straight run of four-wide sums with no per-row bounds (the nodes past the kernel's end
/// get weight zero). 16 covers a kernel's widest row at three cells a spacing (14 nodes);
/// a wider row takes more runs.
const LANES: usize = 16;

/// The sums of one tile's nodes within `[a, b]` (tile node coordinates, inclusive; the rest
/// of its nodes no particle reaches): per node Σ wᵢ and Σ wᵢ (xᵢ − tile corner), each in an
/// array of its own (x fastest, rows [`LANES`] longer than the range for the runs' ends).
struct Tile {
    a: IVec3,
    b: IVec3,
    cell: f32,
    /// Row length of the arrays: the range's plus [`LANES`].
    stride: usize,
    w: Vec<f32>,
    s: [Vec<f32>; 3],
}

impl Tile {
    /// The node range of the support of a particle at `x` (relative to the tile's corner).
    fn reach(x: Vec3, support: f32, inv_cell: f32) -> (IVec3, IVec3) {
        let (lo, hi) = ((x - support) * inv_cell, (x + support) * inv_cell);
        let a = IVec3::new(ceil(lo.x), ceil(lo.y), ceil(lo.z)).max(IVec3::ZERO);
        let b = IVec3::new(floor(hi.x), floor(hi.y), floor(hi.z)).min(IVec3::splat(TILE_CELLS));
        (a, b)
    }

    /// Sums the kernels of the particles `list` over the nodes of tile `t`: per particle, each
    /// row of its support's box that the support meets, [`LANES`] nodes at a time from the
    /// box's low end, weight (1 − (dx² + dy² + dz²)/R²)₊³ (zero past the support).
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
        let (stride, ny) = (dim.x as usize + LANES, dim.y as usize);
        let len = stride * ny * dim.z.max(0) as usize;
        let mut tile = Tile {
            a,
            b,
            cell,
            stride,
            w: vec![0.0; len],
            s: [vec![0.0; len], vec![0.0; len], vec![0.0; len]],
        };
        // The x part of the kernel's argument, once a particle, from the box's low end; 2 past
        // its high end (so 1 − off − e < 0 there).
        let mut ex = [2.0f32; TILE_CELLS as usize + 1 + LANES];
        for &(_, i) in list {
            let x = p.points[i as usize] - corner;
            let (pa, pb) = Self::reach(x, p.support, inv_cell);
            if pa.cmpgt(pb).any() {
                continue;
            }
            let width = (pb.x - pa.x + 1) as usize;
            for (k, e) in ex[..width].iter_mut().enumerate() {
                let d = x.x - (pa.x + k as i32) as f32 * cell;
                *e = d * d * inv_r2;
            }
            for nz in pa.z..=pb.z {
                let dz = x.z - nz as f32 * cell;
                for ny_ in pa.y..=pb.y {
                    let dy = x.y - ny_ as f32 * cell;
                    let off = dy * dy + dz * dz;
                    if off >= r2 {
                        continue;
                    }
                    let q0 = 1.0 - off * inv_r2;
                    let row = ((nz - a.z) as usize * ny + (ny_ - a.y) as usize) * stride;
                    let start = row + (pa.x - a.x) as usize;
                    for k in (0..width).step_by(LANES) {
                        tile.add_run(start + k, &ex[k..k + LANES], q0, x);
                    }
                }
            }
            ex[..width].fill(2.0);
        }
        tile
    }

    /// Adds one run of [`LANES`] nodes from array index `at`: weights (q0 − e)₊³.
    #[inline(always)]
    fn add_run(&mut self, at: usize, ex: &[f32], q0: f32, x: Vec3) {
        let ex: &[f32; LANES] = ex.try_into().unwrap();
        let mut q3 = [0.0f32; LANES];
        for (q, e) in q3.iter_mut().zip(ex) {
            let q1 = (q0 - e).max(0.0);
            *q = q1 * q1 * q1;
        }
        let run = |v: &mut Vec<f32>, c: f32| {
            let v: &mut [f32; LANES] = (&mut v[at..at + LANES]).try_into().unwrap();
            for (v, q) in v.iter_mut().zip(&q3) {
                *v += c * q;
            }
        };
        run(&mut self.w, 1.0);
        let [sx, sy, sz] = &mut self.s;
        run(sx, x.x);
        run(sy, x.y);
        run(sz, x.z);
    }

    /// ψ (the field in its cut-off form) at every node of the range, in the arrays' order,
    /// and whether the node holds weight.
    fn psi(&self, p: &Params) -> Vec<(f32, bool)> {
        let dim = (self.b - self.a + IVec3::ONE).max(IVec3::ZERO);
        let mut out = vec![(p.support, false); self.w.len()];
        for z in 0..dim.z {
            for y in 0..dim.y {
                let row = (z as usize * dim.y as usize + y as usize) * self.stride;
                for x in 0..dim.x {
                    let k = row + x as usize;
                    let w = self.w[k];
                    if w <= 0.0 {
                        continue;
                    }
                    let mean = Vec3::new(self.s[0][k], self.s[1][k], self.s[2][k]) / w;
                    let n = self.a + IVec3::new(x, y, z);
                    let phi = (mean - n.as_vec3() * self.cell).length() - p.radius;
                    out[k] = (phi.max(CUT_OFF_SLOPE * p.spacing * (MIN_WEIGHT - w)), true);
                }
            }
        }
        out
    }

    /// φ at the nodes of this tile's bricks that hold some weight, by brick coordinates (tile
    /// `t`'s bricks).
    fn bricks(&self, p: &Params, t: IVec3) -> Vec<(IVec3, [f32; NODES])> {
        let psi = self.psi(p);
        let dim = self.b - self.a + IVec3::ONE;
        let mut out = Vec::new();
        for bz in 0..TILE {
            for by in 0..TILE {
                for bx in 0..TILE {
                    let lo = IVec3::new(bx, by, bz) * BRICK;
                    let hi = lo + IVec3::splat(BRICK);
                    if hi.cmplt(self.a).any() || lo.cmpgt(self.b).any() {
                        continue;
                    }
                    let mut v = [p.support; NODES];
                    let mut any = false;
                    let (d0, d1) = ((lo - self.a).max(IVec3::ZERO), (hi - self.a).min(dim - 1));
                    for z in d0.z..=d1.z {
                        for y in d0.y..=d1.y {
                            let at = (z * dim.y + y) as usize * self.stride;
                            let to = (z + self.a.z - lo.z) as usize * SIDE * SIDE
                                + (y + self.a.y - lo.y) as usize * SIDE;
                            for x in d0.x..=d1.x {
                                let (f, has) = psi[at + x as usize];
                                v[to + (x + self.a.x - lo.x) as usize] = f;
                                any |= has;
                            }
                        }
                    }
                    if any {
                        out.push((t * TILE + IVec3::new(bx, by, bz), v));
                    }
                }
            }
        }
        out
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
    /// a tile misses a particle (e.g. one tile fewer either side), a row is cut short, or the
    /// x terms of one particle are left for the next (the runs read past its row). With a
    /// kernel of 3 spacings (rows of up to 19 nodes: two runs of [`LANES`]) too; fails when a
    /// row takes only its first run.
    #[test]
    fn every_node_holds_the_field_summed_over_all_particles() {
        for support in [2.25, 3.0] {
            field_on_every_node(support);
        }
    }

    fn field_on_every_node(support: f32) {
        let pts = cloud();
        let s = 1.0;
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
