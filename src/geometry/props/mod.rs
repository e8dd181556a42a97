//! Props: opaque shapes that stage a shot (ground, backdrop, spheres, boxes, cylinders, wire
//! rings, triangle meshes). Pure geometry: a hit gives the distance, the outward unit normal and the index of
//! the shape; materials live in the renderer. Scenes hold a handful of props, so the set is a
//! flat list tested in order (no acceleration structure), and an empty set costs one length
//! check per ray.

mod mesh;
mod shapes;

use super::Ray;
use glam::Vec3;

pub use mesh::Mesh;
pub use shapes::Shape;

/// A ray's first prop hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropHit {
    /// Distance along the ray, scene units.
    pub t: f32,
    /// Outward unit normal of the surface (for a plane: its given normal).
    pub normal: Vec3,
    /// Index of the shape in its [`Props`].
    pub index: usize,
}

/// The props of a scene.
#[derive(Clone, Debug, Default)]
pub struct Props {
    shapes: Vec<Shape>,
    /// Convergence distance of the iterative (torus) intersection, scene units.
    eps: f32,
}

impl Props {
    /// A set of `shapes`; `eps` (scene units, > 0) is the distance at which the torus's
    /// sphere tracing counts as a hit — keep rays leaving a prop offset by more than it.
    pub fn new(shapes: Vec<Shape>, eps: f32) -> Self {
        Props {
            shapes,
            eps: eps.max(1e-9),
        }
    }

    /// The shapes.
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// Number of props.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// The nearest prop hit with `t_min < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<PropHit> {
        let mut best: Option<PropHit> = None;
        let mut t_max = t_max;
        for (index, s) in self.shapes.iter().enumerate() {
            if let Some((t, normal)) = s.intersect(ray, t_min, t_max, self.eps) {
                t_max = t;
                best = Some(PropHit { t, normal, index });
            }
        }
        best
    }

    /// True if any prop is hit with `t_min < t < t_max` (shadow rays).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.shapes
            .iter()
            .any(|s| s.intersect(ray, t_min, t_max, self.eps).is_some())
    }
}
