//! [`FilmGeometry`]: the one interface the renderer queries for film crossings, whatever draws
//! the film (splats or the MLS surface; further geometries add a variant here).

use std::fmt;

use super::{Aabb, MeshGeometry, MlsSurface, Ray, SplatGeometry, SurfaceHit};

/// The films of a scene. A closed set of geometries dispatched by `match` (no virtual calls).
/// Every variant answers the same three questions: the first crossing along a ray, whether there
/// is any crossing (shadow rays), and its bounds.
#[derive(Clone, Debug)]
pub enum FilmGeometry {
    /// Particles drawn as blended disks or as spheres.
    Splats(SplatGeometry),
    /// A triangle mesh (e.g. a meshed pipeline's surface), smooth-shaded.
    Mesh(MeshGeometry),
    /// The smooth moving-least-squares surface of the particles.
    Mls(MlsSurface),
}

impl FilmGeometry {
    /// The first film crossing with `t_min < t < t_max`; continue with
    /// `t_min = hit.t_exit + eps` to find the next one.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        match self {
            FilmGeometry::Splats(g) => g.intersect(ray, t_min, t_max),
            FilmGeometry::Mesh(g) => g.intersect(ray, t_min, t_max),
            FilmGeometry::Mls(g) => g.intersect(ray, t_min, t_max),
        }
    }

    /// True if any film is crossed with `t_min < t < t_max`.
    #[inline]
    pub fn intersect_any(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        match self {
            FilmGeometry::Splats(g) => g.intersect_any(ray, t_min, t_max),
            FilmGeometry::Mesh(g) => g.intersect_any(ray, t_min, t_max),
            FilmGeometry::Mls(g) => g.intersect_any(ray, t_min, t_max),
        }
    }

    /// Bounds of the films (the empty box for an empty scene).
    pub fn bounds(&self) -> Aabb {
        match self {
            FilmGeometry::Splats(g) => g.bounds(),
            FilmGeometry::Mesh(g) => g.bounds(),
            FilmGeometry::Mls(g) => g.bounds(),
        }
    }

    /// Number of elements (particles, triangles) the geometry was built from.
    pub fn len(&self) -> usize {
        match self {
            FilmGeometry::Splats(g) => g.len(),
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
            FilmGeometry::Splats(g) => g.memory_bytes(),
            FilmGeometry::Mesh(g) => g.memory_bytes(),
            FilmGeometry::Mls(g) => g.memory_bytes(),
        }
    }
}

impl fmt::Display for FilmGeometry {
    /// What draws the films, as the `--primitive` value names it (`disk`, `sphere`, ...).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FilmGeometry::Splats(g) => write!(f, "{}", g.primitive()),
            FilmGeometry::Mesh(_) => f.write_str("mesh"),
            FilmGeometry::Mls(_) => f.write_str("mls"),
        }
    }
}

impl From<SplatGeometry> for FilmGeometry {
    fn from(g: SplatGeometry) -> Self {
        FilmGeometry::Splats(g)
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
