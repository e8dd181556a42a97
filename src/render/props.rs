//! Props: opaque shapes that stage a shot (ground, backdrop, spheres, boxes, cylinders, wire
//! rings, triangle meshes), each a [`Shape`] of the shape library paired with its
//! [`Material`] (pbrt's geometric primitive). Scenes hold a handful of props, so the set is a
//! flat list tested in order (no acceleration structure), and an empty set costs one length
//! check per ray.

use super::material::Material;
use crate::geometry::{Ray, Shape};
use glam::Vec3;

/// One prop: a shape and what it is made of.
#[derive(Clone, Debug)]
pub struct Prop {
    /// The shape.
    pub shape: Shape,
    /// Its material.
    pub material: Material,
}

/// A ray's first prop hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropHit {
    /// Distance along the ray, scene units.
    pub t: f32,
    /// Outward unit normal of the surface (for a plane: its given normal).
    pub normal: Vec3,
    /// Index of the prop in its [`Props`].
    pub index: usize,
}

/// The props of a scene.
#[derive(Clone, Debug, Default)]
pub struct Props {
    props: Vec<Prop>,
    /// Convergence distance of the iterative (torus) intersection, scene units.
    eps: f32,
}

impl Props {
    /// A set of `props`; `eps` (scene units, > 0) is the distance at which the torus's sphere
    /// tracing counts as a hit — keep rays leaving a prop offset by more than it.
    pub fn new(props: Vec<Prop>, eps: f32) -> Self {
        Props {
            props,
            eps: eps.max(1e-9),
        }
    }

    /// The props.
    pub fn props(&self) -> &[Prop] {
        &self.props
    }

    /// The material of prop `index` (as in [`PropHit::index`]).
    #[inline]
    pub fn material(&self, index: usize) -> &Material {
        &self.props[index].material
    }

    /// Number of props.
    pub fn len(&self) -> usize {
        self.props.len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.props.is_empty()
    }

    /// The nearest prop hit with `t_min < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<PropHit> {
        let mut best: Option<PropHit> = None;
        let mut t_max = t_max;
        for (index, p) in self.props.iter().enumerate() {
            if let Some(h) = p.shape.intersect(ray, t_min, t_max, self.eps) {
                t_max = h.t;
                best = Some(PropHit {
                    t: h.t,
                    normal: h.normal,
                    index,
                });
            }
        }
        best
    }

    /// True if any prop is hit with `t_min < t < t_max` (shadow rays).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.props
            .iter()
            .any(|p| p.shape.intersect(ray, t_min, t_max, self.eps).is_some())
    }
}
