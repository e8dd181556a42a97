//! The liquid's field sampled once on a grid ([`FieldGrid`]): φ at the nodes of a lattice of
//! [`CELLS_PER_SPACING`] cells a spacing, kept only in the bricks of [`BRICK`]³ cells that a
//! support sphere reaches, and interpolated trilinearly between them. A ray then reads eight
//! node values a march step instead of gathering, sorting and summing the ~50 particles that
//! reach each point of a body (see `docs/benchmarks.md`, "The liquid surface against MLS").
//!
//! The node values are the exact field's ([`super::field`], the same weights; at the
//! weight cut-off made continuous, see `sample`), so the grid's surface is the exact one up to
//! the interpolation: within a few hundredths of a spacing on a body's face (`tests` below hold it to the exact
//! march's crossings). Where no support sphere reaches, there is no brick and φ is +R.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::{IVec3, Vec3};

use super::sample::{self, BRICK, Lattice, NODES, Params, SIDE, floor};
use crate::geometry::aabb::{safe_inv_dir, slab};
use crate::geometry::{Aabb, Bvh, Ray};

/// Grid cells per liquid spacing.
pub const CELLS_PER_SPACING: f32 = 3.0;

/// A hasher for brick coordinates (three `i32`s): multiply and rotate, no more is needed.
#[derive(Default, Clone, Copy)]
pub(super) struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 29)
    }

    fn write(&mut self, bytes: &[u8]) {
        bytes.iter().for_each(|b| self.write_u32(u32::from(*b)));
    }

    #[inline]
    fn write_i32(&mut self, i: i32) {
        self.write_u32(i as u32);
    }

    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.0 = (self.0.rotate_left(21) ^ u64::from(i)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

type BrickMap = HashMap<IVec3, u32, BuildHasherDefault<KeyHasher>>;

/// The brick a march looked up last: its coordinates and its index (`None`: no brick there).
pub(super) type Last = Option<(IVec3, Option<u32>)>;

/// φ on the nodes of the bricks the support spheres reach (see the module docs).
#[derive(Clone, Debug, Default)]
pub(super) struct FieldGrid {
    /// The lattice's corner, scene units.
    origin: Vec3,
    /// Cell side, scene units.
    cell: f32,
    /// 1 / cell.
    inv_cell: f32,
    /// Brick of each brick coordinate.
    bricks: BrickMap,
    /// Brick coordinates, by brick.
    keys: Vec<IVec3>,
    /// φ at each brick's nodes, x fastest.
    phi: Vec<[f32; NODES]>,
    /// Per brick: -1 if φ < 0 at every node (the interpolation is inside throughout), +1 if
    /// φ ≥ 0 at every node (outside throughout), 0 if the surface may cross it.
    sign: Vec<i8>,
    /// Over the bricks' boxes, for the runs of bricks a ray crosses.
    bvh: Bvh,
    /// φ where no particle reaches: the kernel radius R.
    outside: f32,
}

impl FieldGrid {
    /// Samples the field of `p` (see the module docs). Cost: per particle, the nodes within its
    /// support (≈ 4/3 π (R / cell)³ ≈ 1,300), parallel over tiles of bricks (the `sample`
    /// module).
    pub fn build(p: &Params) -> FieldGrid {
        let cell = p.spacing / CELLS_PER_SPACING;
        let reach = Vec3::splat(p.support);
        let origin = p.points.iter().fold(Vec3::INFINITY, |a, x| a.min(*x)) - reach;
        let side = BRICK as f32 * cell;
        let (mut bricks, mut keys, mut phi) = (BrickMap::default(), Vec::new(), Vec::new());
        for (k, v) in sample::bricks(p, Lattice { origin, cell }) {
            bricks.insert(k, keys.len() as u32);
            keys.push(k);
            phi.push(v);
        }
        let sign = phi
            .iter()
            .map(|v| {
                if v.iter().all(|x| *x < 0.0) {
                    -1
                } else if v.iter().all(|x| *x >= 0.0) {
                    1
                } else {
                    0
                }
            })
            .collect();
        let boxes: Vec<Aabb> = keys
            .iter()
            .map(|k| {
                let lo = origin + k.as_vec3() * side;
                Aabb::new(lo, lo + Vec3::splat(side))
            })
            .collect();
        FieldGrid {
            origin,
            cell,
            inv_cell: 1.0 / cell,
            bricks,
            keys,
            phi,
            sign,
            bvh: Bvh::build(&boxes),
            outside: p.support,
        }
    }

    /// Bounds of the bricks.
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        let n = self.keys.len();
        n * (NODES * 4 + 1 + 12 + 24) + self.bvh.memory_bytes()
    }

    /// φ at `x`, interpolated trilinearly between the nodes of its cell; `last` remembers the
    /// brick looked up before (a march stays in one brick for several steps).
    #[inline]
    pub fn phi(&self, x: Vec3, last: &mut Last) -> f32 {
        let u = (x - self.origin) * self.inv_cell;
        let b = u * (1.0 / BRICK as f32);
        let key = IVec3::new(floor(b.x), floor(b.y), floor(b.z));
        let id = match *last {
            Some((k, id)) if k == key => id,
            _ => {
                let id = self.bricks.get(&key).copied();
                *last = Some((key, id));
                id
            }
        };
        let Some(id) = id else {
            return self.outside;
        };
        let l = u - (key * BRICK).as_vec3();
        let top = (BRICK - 1) as usize;
        let cell = |v: f32| (v.max(0.0) as usize).min(top);
        let (cx, cy, cz) = (cell(l.x), cell(l.y), cell(l.z));
        let c = Vec3::new(cx as f32, cy as f32, cz as f32);
        let f = (l - c).clamp(Vec3::ZERO, Vec3::ONE);
        let v = &self.phi[id as usize];
        let base = cz * SIDE * SIDE + cy * SIDE + cx;
        let at = |o: usize| v[base + o];
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        const Y: usize = SIDE;
        const Z: usize = SIDE * SIDE;
        let x00 = lerp(at(0), at(1), f.x);
        let x10 = lerp(at(Y), at(Y + 1), f.x);
        let x01 = lerp(at(Z), at(Z + 1), f.x);
        let x11 = lerp(at(Z + Y), at(Z + Y + 1), f.x);
        lerp(lerp(x00, x10, f.y), lerp(x01, x11, f.y), f.z)
    }

    /// Where the ray leaves the brick [`FieldGrid::phi`] last looked up (`last`; the march
    /// keeps it at its current point), if φ keeps one sign in it, the sign `inside` says (a
    /// march may jump there: no crossing lies between).
    #[inline]
    pub fn exit_if_uniform(&self, ray: &Ray, last: Last, inside: bool) -> Option<f32> {
        let (key, Some(id)) = last? else {
            return None;
        };
        if self.sign[id as usize] != if inside { -1 } else { 1 } {
            return None;
        }
        let side = BRICK as f32 * self.cell;
        let lo = self.origin + key.as_vec3() * side;
        let inv = safe_inv_dir(ray.dir);
        let t2 = (lo + Vec3::splat(side) - ray.origin) * inv;
        let t1 = (lo - ray.origin) * inv;
        Some(t1.max(t2).min_element())
    }

    /// The runs of bricks the ray crosses within `(t_min, t_max)`: sorted, touching bricks
    /// merged, into `runs` (cleared first). Outside them φ is +R.
    pub fn runs(&self, ray: &Ray, t_min: f32, t_max: f32, runs: &mut Vec<(f32, f32)>) {
        runs.clear();
        let inv = safe_inv_dir(ray.dir);
        let side = BRICK as f32 * self.cell;
        let order = self.bvh.order();
        self.bvh.visit_segment(ray, t_min, t_max, |slot| {
            let k = self.keys[order[slot as usize] as usize];
            let lo = self.origin + k.as_vec3() * side;
            if let Some(iv) = slab(lo, lo + Vec3::splat(side), ray.origin, inv, t_min, t_max) {
                runs.push(iv);
            }
        });
        runs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        // Bricks share faces: a ray leaving one enters the next at the same t, up to rounding.
        let gap = 1e-3 * self.cell;
        let mut merged = 0;
        for i in 0..runs.len() {
            if merged > 0 && runs[i].0 <= runs[merged - 1].1 + gap {
                runs[merged - 1].1 = runs[merged - 1].1.max(runs[i].1);
            } else {
                runs[merged] = runs[i];
                merged += 1;
            }
        }
        runs.truncate(merged);
    }
}

#[cfg(test)]
mod tests {
    use super::super::{LiquidField, LiquidSurface};
    use crate::geometry::Ray;
    use glam::Vec3;

    /// A jittered 8×8×8 block of spacing 1 and a ball of water: rays from all round.
    fn bodies() -> Vec<Vec<Vec3>> {
        let mut rnd = crate::geometry::ray4::test_rng(7);
        let mut block = Vec::new();
        let mut ball = Vec::new();
        for z in 0..8 {
            for y in 0..8 {
                for x in 0..8 {
                    let p = Vec3::new(x as f32, y as f32, z as f32);
                    block.push(p + 0.125 * Vec3::new(rnd(), rnd(), rnd()));
                }
            }
        }
        for z in -6..=6 {
            for y in -6..=6 {
                for x in -6..=6 {
                    let p = Vec3::new(x as f32, y as f32, z as f32);
                    if p.length() <= 6.0 {
                        ball.push(p + 0.125 * Vec3::new(rnd(), rnd(), rnd()));
                    }
                }
            }
        }
        vec![block, ball]
    }

    #[test]
    fn the_grid_crosses_where_the_exact_field_does() {
        for pts in bodies() {
            let exact = LiquidSurface::build_with(&pts, 1.0, LiquidField::Exact).unwrap();
            let grid = LiquidSurface::build_with(&pts, 1.0, LiquidField::Grid).unwrap();
            let c = pts.iter().sum::<Vec3>() / pts.len() as f32;
            let (mut worst_t, mut worst_n, mut n, mut miss) = (0.0f32, 1.0f32, 0, 0);
            for i in 0..2000 {
                // Origins on a sphere of radius 20 about the body, aimed near its centre.
                let a = i as f32 * 2.399_963;
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / 2000.0;
                let o = c + 20.0
                    * Vec3::new(
                        (1.0 - z * z).sqrt() * a.cos(),
                        (1.0 - z * z).sqrt() * a.sin(),
                        z,
                    );
                let aim = c + Vec3::new(
                    (i % 7) as f32 - 3.0,
                    (i % 5) as f32 - 2.0,
                    (i % 3) as f32 - 1.0,
                );
                let ray = Ray::new(o, aim - o);
                let (e, g) = (
                    exact.intersect(&ray, 0.0, 100.0),
                    grid.intersect(&ray, 0.0, 100.0),
                );
                match (e, g) {
                    (Some(e), Some(g)) => {
                        n += 1;
                        // How far the grid's crossing lies off the exact surface.
                        let off = exact.field_at(ray.at(g.t)).phi.abs();
                        worst_t = worst_t.max(off);
                        worst_n = worst_n.min(e.normal.dot(g.normal));
                        assert_eq!(e.entering, g.entering);
                    }
                    (None, None) => {}
                    _ => miss += 1,
                }
            }
            eprintln!(
                "hits {n}, disagree {miss}, worst |φ| at the grid's crossing {worst_t}, worst normal cos {worst_n}"
            );
            assert!(n > 1000 && miss <= 2, "hits {n}, disagree {miss}");
            assert!(
                worst_t < 0.03,
                "worst |φ| at the grid's crossing {worst_t} spacings"
            );
            assert!(worst_n > 0.999, "worst normal cos {worst_n}");
        }
    }
}
