//! [`SurfaceHit`]: the film crossing every film geometry (disks, spheres, mesh, MLS surface)
//! answers a ray query with.

use glam::Vec3;

/// One film crossing, as every [`FilmGeometry`](super::FilmGeometry) reports it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the ray to the (blended) film crossing.
    pub t: f32,
    /// Continue rays from just beyond this distance: the farthest splat hit of the blended layer
    /// for disks (`== t` unblended); for spheres the far side of the sphere, since a sphere
    /// is drawn as one film crossing; for the MLS surface the far end of the refined bracket
    /// (within 10⁻³ particle radii of `t`).
    pub t_exit: f32,
    /// The crossing point, `ray.at(t)`.
    pub position: Vec3,
    /// Unit film normal: blended over the layer for disks (oriented like the closest disk's
    /// normal), the outward normal for spheres. Not flipped toward the ray.
    pub normal: Vec3,
    /// Film thickness in nanometres (kernel-weighted mean over the layer for disks, MLS-weighted
    /// mean for the MLS surface).
    pub thickness_nm: f32,
    /// Number of splats blended into this crossing (1 for spheres; for the MLS surface the
    /// particles whose weight reaches the crossing).
    pub coverage: u32,
    /// Index (into the build input) of the particle with the largest weight.
    pub particle: u32,
}
