//! Triangle-mesh shapes: flat-shaded triangles in a BVH, intersected with the same watertight
//! test as film meshes ([`crate::geometry::MeshGeometry`]).

use crate::geometry::mesh::ShearedRay;
use crate::geometry::{Aabb, Bvh, Ray};
use crate::{Error, Result};
use glam::Vec3;

/// A triangle mesh (flat normals, outward by the counter-clockwise winding).
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Triangles in BVH slot order.
    tris: Vec<[Vec3; 3]>,
    /// Unit face normals, same order.
    normals: Vec<Vec3>,
    bvh: Bvh,
}

impl Mesh {
    /// A mesh from `vertices` and triangle `faces` (indices into `vertices`). Degenerate
    /// triangles (zero area) are dropped; an index out of range or a non-finite vertex is an
    /// error, as is a mesh with no triangle left.
    pub fn new(vertices: &[Vec3], faces: &[[u32; 3]]) -> Result<Mesh> {
        if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(format!("mesh vertex {i} is not finite")));
        }
        let mut tris = Vec::with_capacity(faces.len());
        for (f, face) in faces.iter().enumerate() {
            let get = |k: u32| {
                vertices.get(k as usize).copied().ok_or_else(|| {
                    Error::invalid(format!(
                        "mesh face {f} uses vertex {k}, but there are {}",
                        vertices.len()
                    ))
                })
            };
            let t = [get(face[0])?, get(face[1])?, get(face[2])?];
            if (t[1] - t[0]).cross(t[2] - t[0]).length_squared() > 0.0 {
                tris.push(t);
            }
        }
        if tris.is_empty() {
            return Err(Error::invalid("mesh has no triangles with area"));
        }
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| {
                let mut b = Aabb::from_point(t[0]);
                b.grow(t[1]);
                b.grow(t[2]);
                b
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let tris: Vec<[Vec3; 3]> = bvh.order().iter().map(|&i| tris[i as usize]).collect();
        let normals = tris
            .iter()
            .map(|t| (t[1] - t[0]).cross(t[2] - t[0]).normalize())
            .collect();
        Ok(Mesh { tris, normals, bvh })
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// True if there are none (never, for a built mesh).
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// First hit with `t_min < t < t_max`: distance and face normal (two-sided).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, Vec3)> {
        if !ray.is_valid() {
            return None;
        }
        let sr = ShearedRay::new(ray);
        let mut best = None;
        self.bvh.closest(ray, t_min, t_max, |slot, t_max| {
            let [a, b, c] = self.tris[slot as usize];
            if let Some((t, _)) = sr.intersect(a, b, c, t_min, *t_max) {
                *t_max = t;
                best = Some((t, self.normals[slot as usize]));
            }
        });
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube made of 12 triangles is hit exactly where the analytic box is.
    #[test]
    fn a_triangulated_cube_matches_the_box() {
        let v: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let faces: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let mesh = Mesh::new(&v, &faces).unwrap();
        assert_eq!(mesh.len(), 12);
        let (t, n) = mesh
            .intersect(&Ray::new(Vec3::new(0.3, 0.6, 5.0), Vec3::NEG_Z), 0.0, 100.0)
            .unwrap();
        assert!(
            (t - 4.0).abs() < 1e-5 && (n - Vec3::Z).length() < 1e-5,
            "{t} {n}"
        );
        let (t, n) = mesh
            .intersect(&Ray::new(Vec3::new(-2.0, 0.5, 0.5), Vec3::X), 0.0, 100.0)
            .unwrap();
        assert!(
            (t - 2.0).abs() < 1e-5 && (n - Vec3::NEG_X).length() < 1e-5,
            "{t} {n}"
        );
        assert!(
            mesh.intersect(&Ray::new(Vec3::new(2.0, 2.0, 5.0), Vec3::NEG_Z), 0.0, 100.0)
                .is_none()
        );
        assert!(Mesh::new(&v, &[[0, 1, 9]]).is_err());
    }
}
