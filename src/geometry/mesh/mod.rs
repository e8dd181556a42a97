//! Triangle meshes as films: the surface a meshed pipeline renders, drawn with the same film
//! shading as splats so a comparison differs only in the geometry.
//!
//! Triangles sit in the same [`Bvh`] as splats and are tested with the watertight algorithm of
//! Woop et al. (see `triangle`). A hit's normal and thickness are interpolated barycentrically
//! from the vertices (smooth shading).
//!
//! # Thin closed shells
//! A surface reconstructed around a *single layer* of film particles (an SPH iso-surface) is
//! not one sheet but a thin closed shell: every film crossing is two surface crossings, about
//! one shell thickness apart, and a film rendered on both sheets reflects twice. With
//! [`MeshSides::Merge`] the geometry treats a crossing and whatever lies within the given
//! distance behind it (divided by the cosine to the sheet, capped at 10×) as one film: the
//! first sheet is shaded and the ray continues beyond the second. [`MeshGeometry::shell_width`]
//! detects such shells (from each vertex, the distance to the surface along its normal).

mod triangle;

use glam::Vec3;
use rayon::prelude::*;

pub(crate) use self::triangle::ShearedRay;
use super::{Aabb, Bvh, Ray, SurfaceHit};
use crate::{Error, Result};

/// Which surface crossings of a mesh are films.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum MeshSides {
    /// Every crossing is a film (a mesh of the film's mid-surface).
    #[default]
    All,
    /// A crossing swallows every crossing within this distance (scene units, along the normal)
    /// behind it: one film per crossing of a thin closed shell whose walls are thinner than it.
    Merge(f32),
}

/// A triangle in slot order: corners and their vertex indices (48 bytes).
#[derive(Clone, Copy, Debug)]
struct TriPrim {
    v: [Vec3; 3],
    idx: [u32; 3],
}

/// Relative padding of triangle boxes (as for splats).
const BOUNDS_PAD: f32 = 1e-6;

/// A triangle mesh in a [`Bvh`] answering film-crossing queries with smooth normals and
/// thickness interpolated from the vertices. Memory: 48 bytes per triangle plus the BVH
/// (~30 bytes per triangle) plus 16 bytes per vertex. Queries are `&self` and thread-safe.
#[derive(Clone, Debug)]
pub struct MeshGeometry {
    bvh: Bvh,
    tris: Vec<TriPrim>,
    normals: Vec<Vec3>,
    thickness: Vec<f32>,
    sides: MeshSides,
}

/// Checks the mesh arrays (see [`MeshGeometry::build`]); errors name the array and element.
fn check_mesh(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    normals: &[Vec3],
    thickness_nm: &[f32],
) -> Result<()> {
    let n = positions.len();
    if thickness_nm.len() != n {
        return Err(Error::invalid(format!(
            "mesh: thickness has {} entries for {n} vertices",
            thickness_nm.len()
        )));
    }
    if !normals.is_empty() && normals.len() != n {
        return Err(Error::invalid(format!(
            "mesh: normals has {} entries for {n} vertices",
            normals.len()
        )));
    }
    if triangles.len() >= u32::MAX as usize {
        return Err(Error::invalid("mesh: too many triangles"));
    }
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::invalid(format!(
            "mesh: vertex {i} has a non-finite position {}",
            positions[i]
        )));
    }
    if let Some(i) = thickness_nm
        .iter()
        .position(|t| !(t.is_finite() && *t >= 0.0))
    {
        return Err(Error::invalid(format!(
            "mesh: vertex {i} has an invalid thickness {} nm",
            thickness_nm[i]
        )));
    }
    if let Some((i, t)) = triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
    {
        return Err(Error::invalid(format!(
            "mesh: triangle {i} names vertex {} of {n}",
            t.iter().max().expect("three")
        )));
    }
    Ok(())
}

/// Unit vertex normals: `normals` normalised, or if empty the area-weighted mean of the
/// adjacent triangles' normals (oriented by the winding); zero where none is defined.
fn vertex_normals(positions: &[Vec3], triangles: &[[u32; 3]], normals: &[Vec3]) -> Vec<Vec3> {
    let n = positions.len();
    if normals.is_empty() {
        let mut sum = vec![Vec3::ZERO; n];
        for t in triangles {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            let g = (b - a).cross(c - a);
            for v in t {
                sum[*v as usize] += g;
            }
        }
        sum.into_iter().map(Vec3::normalize_or_zero).collect()
    } else {
        normals.iter().map(|v| v.normalize_or_zero()).collect()
    }
}

impl MeshGeometry {
    /// Builds the mesh. `positions`, `thickness_nm` and `normals` have one entry per vertex;
    /// `normals` may be empty, then they are the area-weighted mean of the adjacent triangles'
    /// normals (oriented by the winding). Vertex normals that are zero or not finite fall back
    /// to the triangle's own normal at shading time. Positions must be finite and thickness
    /// finite and non-negative; triangles must index existing vertices. Degenerate triangles
    /// are kept but never hit. Cost: O(n log n) in triangles, parallel.
    pub fn build(
        positions: &[Vec3],
        triangles: &[[u32; 3]],
        normals: &[Vec3],
        thickness_nm: &[f32],
    ) -> Result<Self> {
        check_mesh(positions, triangles, normals, thickness_nm)?;
        let normals = vertex_normals(positions, triangles, normals);
        let bounds: Vec<Aabb> = triangles
            .par_iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| positions[v as usize]);
                let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
                let pad =
                    (lo.abs().max(hi.abs()).max_element() + (hi - lo).max_element()) * BOUNDS_PAD;
                Aabb::new(lo, hi).padded(pad)
            })
            .collect();
        let bvh = Bvh::build(&bounds);
        let tris = bvh
            .order()
            .iter()
            .map(|&i| {
                let idx = triangles[i as usize];
                TriPrim {
                    v: idx.map(|v| positions[v as usize]),
                    idx,
                }
            })
            .collect();
        Ok(MeshGeometry {
            bvh,
            tris,
            normals,
            thickness: thickness_nm.to_vec(),
            sides: MeshSides::All,
        })
    }

    /// Which crossings are films (default [`MeshSides::All`]).
    pub fn sides(&self) -> MeshSides {
        self.sides
    }

    /// Sets which crossings are films (a negative or non-finite merge distance means
    /// [`MeshSides::All`]).
    pub fn set_sides(&mut self, sides: MeshSides) {
        self.sides = match sides {
            MeshSides::Merge(d) if d.is_finite() && d > 0.0 => sides,
            _ => MeshSides::All,
        };
    }

    /// The closest triangle hit with `t_min < t < t_max`, as `(slot, t, weights)`.
    fn closest(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(u32, f32, [f32; 3])> {
        let sr = ShearedRay::new(ray);
        let mut best = None;
        self.bvh.closest(ray, t_min, t_max, |s, t_max| {
            let p = &self.tris[s as usize];
            if let Some((t, w)) = sr.intersect(p.v[0], p.v[1], p.v[2], t_min, *t_max) {
                *t_max = t;
                best = Some((s, t, w));
            }
        });
        best
    }

    /// The first film crossing with `t_min < t < t_max`: the closest triangle, with the normal
    /// and thickness interpolated from its vertices; `t_exit` is `t`, or for
    /// [`MeshSides::Merge`] the end of the merged shell wall. `particle` is the triangle's index.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        if !ray.is_valid() {
            return None;
        }
        let (slot, t, w) = self.closest(ray, t_min, t_max)?;
        let p = &self.tris[slot as usize];
        let geometric = (p.v[1] - p.v[0])
            .cross(p.v[2] - p.v[0])
            .normalize_or(Vec3::Z);
        let mut normal = Vec3::ZERO;
        let mut thickness = 0.0;
        for (&v, &wk) in p.idx.iter().zip(&w) {
            let n = self.normals[v as usize];
            normal += wk * if n == Vec3::ZERO { geometric } else { n };
            thickness += wk * self.thickness[v as usize];
        }
        let normal = normal.normalize_or(geometric);
        let t_exit = match self.sides {
            MeshSides::All => t,
            MeshSides::Merge(d) => t + d / ray.dir.dot(geometric).abs().max(0.1),
        };
        Some(SurfaceHit {
            t,
            t_exit,
            position: ray.at(t),
            normal,
            thickness_nm: thickness.max(0.0),
            coverage: 1,
            particle: self.bvh.order()[slot as usize],
        })
    }

    /// The wall width of a thin closed shell, if the mesh is one: from up to `samples` vertices
    /// spread over the mesh, the distance along the vertex normal (either way) to the nearest
    /// other part of the surface. If at least 80% of them find the surface within 5% of the
    /// mesh's diagonal, returns the median distance (scene units); else `None` (an open sheet
    /// or a solid body). Cost: two rays per sampled vertex.
    pub fn shell_width(&self, samples: usize) -> Option<f32> {
        let b = self.bounds();
        let diag = (b.max - b.min).length();
        let n = self.normals.len();
        if n == 0 || diag.is_nan() || diag <= 0.0 {
            return None;
        }
        let limit = 0.05 * diag;
        let step = n.div_ceil(samples.max(1)).max(1);
        // Vertices used by triangles, with their position.
        let mut pos = vec![None; n];
        for p in &self.tris {
            for k in 0..3 {
                pos[p.idx[k] as usize] = Some(p.v[k]);
            }
        }
        let eps = 1e-4 * limit;
        let found: Vec<Option<f32>> = (0..n)
            .step_by(step)
            .filter_map(|v| Some((pos[v]?, self.normals[v])))
            .filter(|(_, nrm)| *nrm != Vec3::ZERO)
            .map(|(p, nrm)| {
                [nrm, -nrm]
                    .into_iter()
                    .filter_map(|d| self.closest(&Ray::new(p, d), eps, limit).map(|h| h.1))
                    .reduce(f32::min)
            })
            .collect();
        let mut hit: Vec<f32> = found.iter().flatten().copied().collect();
        if found.is_empty() || (hit.len() as f32) < 0.8 * found.len() as f32 {
            return None;
        }
        let mid = hit.len() / 2;
        Some(*hit.select_nth_unstable_by(mid, f32::total_cmp).1)
    }

    /// Bounds of all triangles (slightly padded; empty for no triangles).
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The underlying BVH (slot order and nodes), for statistics and debugging.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// True if there are no triangles.
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// Heap bytes held (triangles, vertex attributes, BVH).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.tris.capacity() * std::mem::size_of::<TriPrim>()
            + self.normals.capacity() * 12
            + self.thickness.capacity() * 4
    }
}
