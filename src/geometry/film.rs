//! [`FilmGeometry`]: the one interface the renderer queries for film crossings, whatever draws
//! the film (disks, spheres, a triangle mesh or the MLS surface; further geometries add a
//! variant here).

use std::fmt;

use glam::Vec3;

use super::{
    Aabb, Bvh, DiskGeometry, MeshGeometry, MlsSurface, Primitive, Ray, SphereGeometry, SurfaceHit,
};
use crate::Result;

/// The films of a scene. A closed set of geometries dispatched by `match` (no virtual calls),
/// each variant with its own data. Every variant answers the same questions: the first
/// crossing along a ray, its bounds and its size.
#[derive(Clone, Debug)]
pub enum FilmGeometry {
    /// Particles drawn as blended disks.
    Disks(DiskGeometry),
    /// Particles drawn as spheres.
    Spheres(SphereGeometry),
    /// A triangle mesh (e.g. a meshed pipeline's surface), smooth-shaded.
    Mesh(MeshGeometry),
    /// The smooth moving-least-squares surface of the particles.
    Mls(MlsSurface),
}

impl FilmGeometry {
    /// The particles drawn as `primitive`: [`DiskGeometry::build`],
    /// [`SphereGeometry::build`] or [`MlsSurface::build`] (arguments and errors as there).
    pub fn particles(
        primitive: Primitive,
        positions: &[Vec3],
        normals: &[Vec3],
        radii: &[f32],
        thickness_nm: &[f32],
    ) -> Result<Self> {
        Ok(match primitive {
            Primitive::Disk => DiskGeometry::build(positions, normals, radii, thickness_nm)?.into(),
            Primitive::Sphere => {
                SphereGeometry::build(positions, normals, radii, thickness_nm)?.into()
            }
            Primitive::Mls => MlsSurface::build(positions, normals, radii, thickness_nm)?.into(),
        })
    }

    /// The first film crossing with `t_min < t < t_max`; continue with
    /// `t_min = hit.t_exit + eps` to find the next one.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        match self {
            FilmGeometry::Disks(g) => g.intersect(ray, t_min, t_max),
            FilmGeometry::Spheres(g) => g.intersect(ray, t_min, t_max),
            FilmGeometry::Mesh(g) => g.intersect(ray, t_min, t_max),
            FilmGeometry::Mls(g) => g.intersect(ray, t_min, t_max),
        }
    }

    /// The closest single element with `t_min < t < t_max`, without blending: for disks
    /// [`DiskGeometry::intersect_single`], for the others the same as
    /// [`FilmGeometry::intersect`].
    pub fn intersect_single(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        match self {
            FilmGeometry::Disks(g) => g.intersect_single(ray, t_min, t_max),
            _ => self.intersect(ray, t_min, t_max),
        }
    }

    /// How the particles are drawn (`None` for a mesh).
    pub fn primitive(&self) -> Option<Primitive> {
        match self {
            FilmGeometry::Disks(_) => Some(Primitive::Disk),
            FilmGeometry::Spheres(_) => Some(Primitive::Sphere),
            FilmGeometry::Mesh(_) => None,
            FilmGeometry::Mls(_) => Some(Primitive::Mls),
        }
    }

    /// Bounds of the films (the empty box for an empty scene).
    pub fn bounds(&self) -> Aabb {
        self.bvh().bounds()
    }

    /// The acceleration structure (slot order and nodes), for statistics and debugging.
    pub fn bvh(&self) -> &Bvh {
        match self {
            FilmGeometry::Disks(g) => g.bvh(),
            FilmGeometry::Spheres(g) => g.bvh(),
            FilmGeometry::Mesh(g) => g.bvh(),
            FilmGeometry::Mls(g) => g.bvh(),
        }
    }

    /// Number of elements (particles, triangles) the geometry was built from.
    pub fn len(&self) -> usize {
        match self {
            FilmGeometry::Disks(g) => g.len(),
            FilmGeometry::Spheres(g) => g.len(),
            FilmGeometry::Mesh(g) => g.len(),
            FilmGeometry::Mls(g) => g.len(),
        }
    }

    /// True if the geometry holds nothing.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Heap bytes held by the geometry and its acceleration structure.
    pub fn memory_bytes(&self) -> usize {
        match self {
            FilmGeometry::Disks(g) => g.memory_bytes(),
            FilmGeometry::Spheres(g) => g.memory_bytes(),
            FilmGeometry::Mesh(g) => g.memory_bytes(),
            FilmGeometry::Mls(g) => g.memory_bytes(),
        }
    }
}

impl fmt::Display for FilmGeometry {
    /// What draws the films, as the `--primitive` value names it (`disk`, `sphere`, ...).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.primitive() {
            Some(p) => write!(f, "{p}"),
            None => f.write_str("mesh"),
        }
    }
}

impl From<DiskGeometry> for FilmGeometry {
    fn from(g: DiskGeometry) -> Self {
        FilmGeometry::Disks(g)
    }
}

impl From<SphereGeometry> for FilmGeometry {
    fn from(g: SphereGeometry) -> Self {
        FilmGeometry::Spheres(g)
    }
}

impl From<MeshGeometry> for FilmGeometry {
    fn from(g: MeshGeometry) -> Self {
        FilmGeometry::Mesh(g)
    }
}

impl From<MlsSurface> for FilmGeometry {
    fn from(g: MlsSurface) -> Self {
        FilmGeometry::Mls(g)
    }
}
