//! The shape library: the opaque shapes that stage a shot (ground, backdrop, spheres, boxes,
//! cylinders, wire rings, triangle meshes) and the shapes area lights emit from (rectangles,
//! disks, spheres). Pure geometry: a hit gives the distance, the outward unit normal and the
//! side met; materials and emission belong to the renderer, which pairs them with a shape (as
//! pbrt's primitives and `DiffuseAreaLight(Shape)` do).
//!
//! * [`Shape::intersect`]: every shape, analytic except the torus (sphere tracing of its exact
//!   distance function). The ray–sphere test is the films' ([`super::primitives::sphere_roots`]).
//! * [`Shape::sample`] / [`Shape::pdf`]: solid-angle sampling of the shapes lights use
//!   (rectangle, disk, sphere).

mod flat;
mod mesh;
mod round;
mod sample;

use super::Ray;
use glam::Vec3;
use std::sync::Arc;

pub use mesh::Mesh;
pub use sample::{ShapeSample, frame};

/// A shape. Directions (`normal`, `axis`) are unit vectors.
#[derive(Clone, Debug)]
pub enum Shape {
    /// An infinite plane through `point` (ground, backdrop). Two-sided.
    Plane {
        /// A point on the plane.
        point: Vec3,
        /// Unit normal (the side reported as outward).
        normal: Vec3,
    },
    /// A parallelogram `centre + a·u + b·v`, |a|, |b| ≤ 1 (u, v perpendicular half-edges);
    /// its front faces `u × v`.
    Rect {
        /// Centre.
        centre: Vec3,
        /// Half-edge vector along the width.
        u: Vec3,
        /// Half-edge vector along the height.
        v: Vec3,
    },
    /// A disk; its front faces `normal`.
    Disk {
        /// Centre.
        centre: Vec3,
        /// Unit normal (the front side).
        normal: Vec3,
        /// Radius, > 0.
        radius: f32,
    },
    /// A sphere; its front is the outside.
    Sphere {
        /// Centre.
        centre: Vec3,
        /// Radius, > 0.
        radius: f32,
    },
    /// An axis-aligned box.
    Box {
        /// Centre.
        centre: Vec3,
        /// Half the edge lengths, each > 0.
        half: Vec3,
    },
    /// A closed (capped) cylinder from `base` to `base + height · axis`.
    Cylinder {
        /// Centre of the bottom cap.
        base: Vec3,
        /// Unit axis.
        axis: Vec3,
        /// Length along the axis, > 0.
        height: f32,
        /// Radius, > 0.
        radius: f32,
    },
    /// A torus (a wire ring): the tube of radius `minor` around the circle of radius `major`
    /// centred at `centre` in the plane perpendicular to `axis`.
    Torus {
        /// Centre of the ring.
        centre: Vec3,
        /// Unit axis (the ring's normal).
        axis: Vec3,
        /// Ring radius, > 0.
        major: f32,
        /// Tube radius, 0 < minor < major for a ring.
        minor: f32,
    },
    /// A triangle mesh.
    Mesh(Arc<Mesh>),
}

/// Where a ray meets a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    /// Distance along the ray, scene units.
    pub t: f32,
    /// Outward unit normal (for a plane, rectangle or disk: its given normal).
    pub normal: Vec3,
    /// True if the ray meets the front: the side the normal points to for flat shapes, the
    /// outside (a ray starting outside) for a sphere, `dir · normal < 0` for the others.
    pub front: bool,
}

impl Shape {
    /// First hit with `t_min < t < t_max`. `eps` (scene units) is the torus's convergence
    /// distance (keep rays leaving a shape offset by more than it).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32, eps: f32) -> Option<ShapeHit> {
        let facing = |(t, normal): (f32, Vec3)| ShapeHit {
            t,
            normal,
            front: ray.dir.dot(normal) < 0.0,
        };
        match *self {
            Shape::Plane { point, normal } => flat::plane(ray, point, normal, (t_min, t_max)),
            Shape::Rect { centre, u, v } => flat::rect(ray, centre, (u, v), (t_min, t_max)),
            Shape::Disk {
                centre,
                normal,
                radius,
            } => flat::disk(ray, centre, normal, radius, (t_min, t_max)),
            Shape::Sphere { centre, radius } => round::sphere(ray, centre, radius, t_min, t_max),
            Shape::Box { centre, half } => {
                round::aabox(ray, centre, half, t_min, t_max).map(facing)
            }
            Shape::Cylinder {
                base,
                axis,
                height,
                radius,
            } => round::cylinder(ray, base, axis, height, radius, t_min, t_max).map(facing),
            Shape::Torus {
                centre,
                axis,
                major,
                minor,
            } => round::torus(ray, centre, axis, major, minor, t_min, t_max, eps).map(facing),
            Shape::Mesh(ref m) => m.intersect(ray, t_min, t_max).map(facing),
        }
    }
}
