//! [`LiquidSurface`]: bulk liquid — 3D SPH particles packed into bodies (drops falling onto a
//! film, a film dripping) — as the implicit surface of the particles, ray traced directly, no
//! mesh.
//!
//! * **Surface** (the `field` module): Zhu & Bridson's φ(x) = |x − x̄(x)| − r, x̄ the mean of
//!   the particles within the kernel radius R weighted by (1 − d²/R²)³, r = (3/4π)^⅓ s the
//!   radius of a sphere of one particle's volume s³ (s the liquid's spacing). Why these two:
//!   * a lone particle gives x̄ = its centre, so exactly the sphere of its volume s³;
//!   * R = [`KERNEL_SPACINGS`] s = 2.25 s puts the face of a cubic block of spacing s at
//!     0.52–0.53 s past the outer layer (flat to 0.01 s; computed on the lattice: R = 1.5 s
//!     gives 0.62 s, 2 s gives 0.60 s, 2.5 s gives 0.43 s), i.e. on the boundary of the outer
//!     particles' own cells, half a spacing out, where a block of volume N s³ ends;
//!   * inside a body x̄ ≈ x, so φ ≈ −r: no spurious cavities.
//! * **Rays**: a BVH over the support spheres (radius R) gives the spheres the ray crosses,
//!   sorted and merged into intervals (outside them φ is +R); each interval is marched with
//!   steps of 0.8|φ| (φ is exact distance for a lone particle and below it near a body's face)
//!   bounded to 0.05–0.5 s, and a sign change is bisected to 10⁻⁴ s. The first crossing after
//!   `t_min` is returned, entering or leaving (a refracted ray inside a body finds its exit).
//!
//! Queries are `&self` and thread-safe.

mod field;
mod grid;
mod sample;
mod trace;

use glam::Vec3;

use super::particles::particle_bvh;
use super::primitives::sphere_bounds;
use super::{Aabb, Bvh};
use crate::{Error, Result};
use field::Sums;
pub use grid::CELLS_PER_SPACING;
use grid::FieldGrid;
use sample::Params;

/// Kernel radius of the field in liquid spacings (see the module docs for why 2.25).
pub const KERNEL_SPACINGS: f32 = 2.25;

/// Radius of a sphere of volume s³ in spacings s: (3 / 4π)^⅓.
pub const VOLUME_RADIUS: f32 = 0.620_350_5;

/// How rays find the surface: on the field sampled once on a grid (the default), or on the
/// field summed over the particles at every step (exact, ~4–10× the rays' cost).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LiquidField {
    /// φ at the nodes of a grid of [`CELLS_PER_SPACING`] cells a spacing, interpolated
    /// trilinearly (the `grid` module); normals from the exact field at the crossing.
    #[default]
    Grid,
    /// φ summed over the particles within reach at every march step.
    Exact,
}

/// Where a ray crosses the liquid's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiquidHit {
    /// Distance along the ray.
    pub t: f32,
    /// Outward unit normal (∇φ / |∇φ|).
    pub normal: Vec3,
    /// The ray enters the liquid here (false: it leaves it).
    pub entering: bool,
}

/// The field at one point ([`LiquidSurface::field_at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LiquidPoint {
    /// φ, scene units: negative in the liquid (+R where the weight is too small).
    pub phi: f32,
    /// ∇φ.
    pub grad: Vec3,
    /// Total kernel weight Σ wᵢ.
    pub weight: f32,
}

/// Bodies of liquid as one implicit surface (see the module docs). Empty by default (a scene
/// without liquid pays one branch a ray).
///
/// Memory: 16 bytes a particle plus the BVH (~30 bytes a particle).
#[derive(Clone, Debug, Default)]
pub struct LiquidSurface {
    bvh: Bvh,
    /// Particle centres in slot order.
    points: Vec<Vec3>,
    /// Liquid spacing s, scene units.
    spacing: f32,
    /// Sphere radius r = [`VOLUME_RADIUS`] s.
    radius: f32,
    /// Kernel radius R = [`KERNEL_SPACINGS`] s.
    support: f32,
    /// The field on a grid, unless rays sum it exactly ([`LiquidField`]).
    grid: Option<FieldGrid>,
}

impl LiquidSurface {
    /// Builds the surface of particles at `positions` (scene units, finite) of spacing
    /// `spacing` (scene units, > 0: each particle holds the volume `spacing³`). Cost: the BVH
    /// build, O(n log n).
    ///
    /// # Errors
    /// A non-finite position or a spacing that is not finite and positive.
    pub fn build(positions: &[Vec3], spacing: f32) -> Result<Self> {
        Self::build_with(positions, spacing, LiquidField::default())
    }

    /// [`LiquidSurface::build`] with rays finding the surface as `field` says; the grid adds
    /// the field's samples to the build (about 1,300 node updates a particle, parallel).
    ///
    /// # Errors
    /// As [`LiquidSurface::build`].
    pub fn build_with(positions: &[Vec3], spacing: f32, field: LiquidField) -> Result<Self> {
        if positions.is_empty() {
            return Ok(LiquidSurface::default());
        }
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(Error::invalid(format!(
                "liquid spacing must be finite and > 0, got {spacing}"
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::invalid(format!(
                "liquid particle {i} has a non-finite position {}",
                positions[i]
            )));
        }
        let support = KERNEL_SPACINGS * spacing;
        let bvh = particle_bvh(
            positions.len(),
            |i| positions[i],
            |_| support,
            |i| sphere_bounds(positions[i], support),
        );
        let points: Vec<Vec3> = bvh.order().iter().map(|&i| positions[i as usize]).collect();
        let radius = VOLUME_RADIUS * spacing;
        let grid = (field == LiquidField::Grid).then(|| {
            FieldGrid::build(&Params {
                points: &points,
                spacing,
                radius,
                support,
            })
        });
        Ok(LiquidSurface {
            bvh,
            points,
            spacing,
            radius,
            support,
            grid,
        })
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// How rays find the surface.
    pub fn field(&self) -> LiquidField {
        if self.grid.is_some() || self.is_empty() {
            LiquidField::Grid
        } else {
            LiquidField::Exact
        }
    }

    /// The liquid spacing s, scene units.
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// Bounds of the support spheres (the empty box for none).
    pub fn bounds(&self) -> Aabb {
        if self.is_empty() {
            Aabb::EMPTY
        } else {
            self.bvh.bounds()
        }
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.points.len() * 12
            + self.grid.as_ref().map_or(0, FieldGrid::memory_bytes)
    }

    /// The field at `x` (a BVH point query over the support spheres). Cost: O(log n) plus
    /// the ~50 particles within reach in a body.
    pub fn field_at(&self, x: Vec3) -> LiquidPoint {
        let mut s = Sums::new(x, self.support);
        self.bvh
            .visit_point(x, |slot| s.add_with_gradient(self.points[slot as usize]));
        let f = s.sample(self.radius, self.support);
        LiquidPoint {
            phi: f.phi,
            grad: s.gradient(),
            weight: f.weight,
        }
    }
}
