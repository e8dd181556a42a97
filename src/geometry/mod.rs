//! Ray-tracing geometry for particle splats: rays, boxes, disk/sphere intersection, a BVH and the
//! disk-layer blending that turns a stack of overlapping splats into one film crossing.
//!
//! This module sees only positions, normals, radii and a per-particle thickness (an opaque `f32`
//! it blends); it knows nothing of spectra or colours. Imports: `glam`, `rayon`, [`crate::error`].
//!
//! * [`Ray`], [`Aabb`]: the basic types (the slab test lives on [`Aabb`]).
//! * [`primitives`]: ray–disk and ray–sphere tests and primitive bounds.
//! * [`Bvh`]: a binned-SAH bounding volume hierarchy over any set of boxes, queried with closures.
//! * [`FilmGeometry`]: the closed set of film geometries the renderer queries for
//!   [`SurfaceHit`]s, one variant each:
//!   * [`DiskGeometry`]: particles as blended disks (four-wide leaf tests, `disk4`; camera rays
//!     of a pinhole grid by rasterisation, [`PrimaryRaster`]);
//!   * [`SphereGeometry`]: particles as spheres (`sphere4`);
//!   * [`MeshGeometry`]: a triangle mesh drawn as a film (for comparisons with meshed renders);
//!   * [`MlsSurface`]: the smooth moving-least-squares surface of the particles, ray traced
//!     directly.
//! * [`LiquidSurface`]: bulk liquid (3D particles packed into bodies) as the implicit surface
//!   of the particles, ray traced directly (the integrator refracts through it like a droplet).
//! * [`LayerBlend`]: parameters of the disk-layer blending.
//! * [`shape`]: the shape library of props and area lights (plane, rectangle, disk, sphere, box,
//!   cylinder, torus, mesh): intersection and light sampling.

mod aabb;
mod blend;
mod bvh;
mod bvh_bins;
mod bvh_build;
mod disk4;
mod disk_query;
mod disk_raster;
mod disk_raster_tile;
mod disks;
mod droplets;
mod film;
mod hit;
mod liquid;
pub mod mesh;
mod mls;
mod particles;
mod primitive_kind;
pub mod primitives;
mod ray4;
pub mod shape;
mod sphere4;
mod spheres;
mod tree;
mod wide;

use glam::Vec3;

pub use aabb::Aabb;
pub use blend::LayerBlend;
pub use bvh::{BvhNode, BvhParams};
pub use disk_raster::{PinholeGrid, PrimaryRaster};
pub use disk_raster_tile::RASTER_TILE;
pub use disks::DiskGeometry;
pub use droplets::{DropletHit, Droplets, GrownDroplets, GrownHit, WATER_IOR};
pub use film::FilmGeometry;
pub use hit::SurfaceHit;
pub use liquid::{
    CELLS_PER_SPACING, KERNEL_SPACINGS, LiquidField, LiquidHit, LiquidPoint, LiquidSurface,
    VOLUME_RADIUS,
};
pub use mesh::{MeshGeometry, MeshSides};
pub use mls::{MlsParams, MlsPoint, MlsSurface};
pub use primitive_kind::Primitive;
pub use shape::{Mesh, Shape, ShapeHit, ShapeSample, frame};
pub use spheres::SphereGeometry;
pub use tree::Bvh;

/// A ray `origin + t * dir`, `t >= 0`. `dir` must be unit length (queries return `None`/`false`
/// for a zero or non-finite direction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point, scene units.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along `dir` (normalised here; a zero `dir` stays zero and hits nothing).
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray {
            origin,
            dir: dir.normalize_or_zero(),
        }
    }

    /// The point at distance `t` along the ray.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }

    /// True if the direction is usable (finite and roughly unit length).
    #[inline]
    pub(crate) fn is_valid(&self) -> bool {
        let l = self.dir.length_squared();
        l > 0.5 && l < 2.0 && self.origin.is_finite()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_new_normalises() {
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, 3.0, 4.0));
        assert!((r.dir.length() - 1.0).abs() < 1e-6);
        assert!((r.at(5.0) - Vec3::new(0.0, 3.0, 4.0)).length() < 1e-5);
        assert!(!Ray::new(Vec3::ZERO, Vec3::ZERO).is_valid());
    }
}
