//! The particle scene: disks or spheres in a BVH, answering film-crossing queries.

use glam::Vec3;
use rayon::prelude::*;

use super::disk4::{PAD, PAD_DISK};
use super::primitives::{disk_bounds, sphere_bounds};
use super::sphere4::PAD_SPHERE;
use super::{Aabb, Bvh, BvhParams, LayerBlend, Primitive, Ray};
use crate::{Error, Result};

/// One film crossing found by [`SplatGeometry::intersect`].
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

/// A disk in slot order (32 bytes). The array is followed by [`PAD`] padding disks.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(super) struct DiskPrim {
    pub center: Vec3,
    pub radius: f32,
    pub normal: Vec3,
    pub thickness: f32,
}

/// A sphere in slot order (20 bytes). The array is followed by padding spheres (`sphere4`).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub(super) struct SpherePrim {
    pub center: Vec3,
    pub radius: f32,
    pub thickness: f32,
}

/// Relative padding of primitive boxes so rounding in the hit point never makes the BVH cull a
/// primitive the exact test would accept.
const BOUNDS_PAD: f32 = 1e-6;

/// Particles as disks or spheres in a [`Bvh`], with disk-layer blending ([`LayerBlend`]).
///
/// Memory: 32 bytes per disk (20 per sphere) plus the BVH (binary and 4-wide nodes and the slot
/// order, ~30 bytes per particle): ~62 bytes per disk on a 1M-disk shell, see
/// [`SplatGeometry::memory_bytes`]. Disk leaves are tested four disks at a time. Queries are
/// `&self` and thread-safe.
#[derive(Clone, Debug)]
pub struct SplatGeometry {
    pub(super) primitive: Primitive,
    pub(super) bvh: Bvh,
    pub(super) disks: Vec<DiskPrim>,
    pub(super) spheres: Vec<SpherePrim>,
    pub(super) blend: LayerBlend,
    /// Per-disk first-order detail in slot order (curvature, thickness gradient); empty means
    /// flat disks of constant thickness.
    pub(super) detail: Vec<DiskDetail>,
}

/// First-order detail of a disk (16 bytes), read only for the disks blended into a crossing.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct DiskDetail {
    /// Normal curvature κ, 1/scene units: n(p) = normalize(n + κ (p − c)).
    pub curvature: f32,
    /// Thickness gradient in the disk plane, nm per scene unit: h(p) = h + g·(p − c).
    pub thickness_gradient: Vec3,
}

/// `make(particle)` for every slot of `order`, then [`PAD`] copies of `pad` (so a four-wide
/// packet can start at any slot).
fn padded_slots<T: Copy + Send>(order: &[u32], pad: T, make: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let mut out = Vec::with_capacity(order.len() + PAD);
    out.par_extend(order.par_iter().map(|&i| make(i as usize)));
    out.extend([pad; PAD]);
    out
}

/// The first index `i < n` for which `bad(i)` holds (parallel search).
fn first_bad(n: usize, bad: impl Fn(usize) -> bool + Sync) -> Option<usize> {
    (0..n)
        .into_par_iter()
        .with_min_len(4096)
        .find_first(|&i| bad(i))
}

/// Checks the particle arrays every film geometry is built from: one entry per particle in each
/// slice (`normals` may be empty unless `need_normals`), finite positions, finite positive radii,
/// finite non-negative thickness, and usable normals when needed. Errors name the offending
/// array and particle.
pub(super) fn check_particles(
    positions: &[Vec3],
    normals: &[Vec3],
    radii: &[f32],
    thickness_nm: &[f32],
    need_normals: bool,
) -> Result<()> {
    let n = positions.len();
    let check_len = |name: &str, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(Error::invalid(format!(
                "geometry: {name} has {len} entries but positions has {n}"
            )))
        }
    };
    check_len("radii", radii.len())?;
    check_len("thickness", thickness_nm.len())?;
    if need_normals || !normals.is_empty() {
        check_len("normals", normals.len())?;
    }
    if n >= u32::MAX as usize {
        return Err(Error::invalid(format!(
            "geometry: {n} particles is more than the supported {}",
            u32::MAX - 1
        )));
    }
    let bad = |what: &str, i: usize, v: String| {
        Err(Error::invalid(format!(
            "geometry: particle {i} has {what} {v}"
        )))
    };
    if let Some(i) = first_bad(n, |i| !positions[i].is_finite()) {
        return bad("a non-finite position", i, format!("{}", positions[i]));
    }
    if let Some(i) = first_bad(n, |i| !(radii[i] > 0.0 && radii[i].is_finite())) {
        return bad(
            "an invalid radius",
            i,
            format!("{} (must be > 0)", radii[i]),
        );
    }
    if let Some(i) = first_bad(n, |i| {
        !(thickness_nm[i] >= 0.0 && thickness_nm[i].is_finite())
    }) {
        return bad("an invalid thickness", i, format!("{} nm", thickness_nm[i]));
    }
    if need_normals {
        let ok = |v: Vec3| v.is_finite() && v.length_squared() > 1e-12;
        if let Some(i) = first_bad(n, |i| !ok(normals[i])) {
            return bad("an unusable normal", i, format!("{}", normals[i]));
        }
    }
    Ok(())
}

impl SplatGeometry {
    /// Builds the scene. All slices have one entry per particle; `normals` (unit length; other
    /// non-zero lengths are normalised) are required for disks and may be empty for spheres.
    /// Radii must be finite and positive, thickness finite and non-negative, positions finite.
    /// Errors name the offending array and particle. Cost: O(n log n), parallel; about 0.5 s per
    /// million particles on two cores.
    pub fn build(
        primitive: Primitive,
        positions: &[Vec3],
        normals: &[Vec3],
        radii: &[f32],
        thickness_nm: &[f32],
    ) -> Result<Self> {
        Self::build_with(
            primitive,
            positions,
            normals,
            radii,
            thickness_nm,
            BvhParams::default(),
        )
    }

    /// [`SplatGeometry::build`] with explicit BVH build parameters.
    pub fn build_with(
        primitive: Primitive,
        positions: &[Vec3],
        normals: &[Vec3],
        radii: &[f32],
        thickness_nm: &[f32],
        params: BvhParams,
    ) -> Result<Self> {
        if primitive == Primitive::Mls {
            return Err(Error::invalid(
                "geometry: the 'mls' primitive is built by MlsSurface, not SplatGeometry",
            ));
        }
        let n = positions.len();
        check_particles(
            positions,
            normals,
            radii,
            thickness_nm,
            primitive == Primitive::Disk,
        )?;
        let unit_normal = |i: usize| normals[i].normalize();
        let pad = |c: Vec3, r: f32| (c.abs().max_element() + r) * BOUNDS_PAD;
        let bounds: Vec<Aabb> = (0..n)
            .into_par_iter()
            .map(|i| {
                let (c, r) = (positions[i], radii[i]);
                let b = match primitive {
                    Primitive::Disk => disk_bounds(c, unit_normal(i), r),
                    // `Mls` never gets here: it is refused above.
                    Primitive::Sphere | Primitive::Mls => sphere_bounds(c, r),
                };
                b.padded(pad(c, r))
            })
            .collect();
        let bvh = Bvh::build_with(&bounds, params);
        drop(bounds);
        let order = bvh.order();
        // Both arrays are padded for the four-wide leaf tests (see `disk4` and `sphere4`), and
        // both pads have the same length.
        let (disks, spheres) = match primitive {
            Primitive::Disk => {
                let disks = padded_slots(order, PAD_DISK, |i| DiskPrim {
                    center: positions[i],
                    radius: radii[i],
                    normal: unit_normal(i),
                    thickness: thickness_nm[i],
                });
                (disks, Vec::new())
            }
            Primitive::Sphere | Primitive::Mls => {
                let spheres = padded_slots(order, PAD_SPHERE, |i| SpherePrim {
                    center: positions[i],
                    radius: radii[i],
                    thickness: thickness_nm[i],
                });
                (Vec::new(), spheres)
            }
        };
        Ok(SplatGeometry {
            primitive,
            bvh,
            disks,
            spheres,
            blend: LayerBlend::default(),
            detail: Vec::new(),
        })
    }

    /// The first film crossing with `t_min < t < t_max`. For disks, overlapping disks of the same
    /// layer are blended into one crossing (see [`LayerBlend`]); continue with
    /// `t_min = hit.t_exit + eps` to find the next layer. Cost: one BVH traversal (for disks it
    /// runs on to the end of the layer band and collects the members on the way; a second, short
    /// segment traversal is needed only for unusual layers, see the `query` module).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        if !ray.is_valid() {
            return None;
        }
        match self.primitive {
            Primitive::Sphere | Primitive::Mls => self.sphere_hit(ray, t_min, t_max),
            Primitive::Disk => self.disk_layer_hit(ray, t_min, t_max),
        }
    }

    /// The closest single splat with `t_min < t < t_max`, without layer blending (coverage 1,
    /// `t_exit == t`). For spheres the same as [`SplatGeometry::intersect`]. Ties in `t` go to
    /// the lowest particle index.
    pub fn intersect_single(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        if !ray.is_valid() {
            return None;
        }
        match self.primitive {
            Primitive::Sphere | Primitive::Mls => self.sphere_hit(ray, t_min, t_max),
            Primitive::Disk => {
                let (slot, t, _) = self.closest_disk(ray, t_min, t_max)?;
                let d = &self.disks[slot as usize];
                Some(SurfaceHit {
                    t,
                    t_exit: t,
                    position: ray.at(t),
                    normal: d.normal,
                    thickness_nm: d.thickness,
                    coverage: 1,
                    particle: self.bvh.order[slot as usize],
                })
            }
        }
    }

    /// True if any splat is hit with `t_min < t < t_max` (shadow rays). Cost: stops at the first
    /// hit found, usually cheaper than [`SplatGeometry::intersect`].
    pub fn intersect_any(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        if !ray.is_valid() {
            return false;
        }
        match self.primitive {
            Primitive::Disk => self.any_disk(ray, t_min, t_max),
            Primitive::Sphere | Primitive::Mls => self.any_sphere(ray, t_min, t_max),
        }
    }

    /// Bounds of all splats (slightly padded; the empty box for zero particles).
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.bvh.len()
    }

    /// True if there are no particles.
    pub fn is_empty(&self) -> bool {
        self.bvh.is_empty()
    }

    /// How particles are drawn.
    pub fn primitive(&self) -> Primitive {
        self.primitive
    }

    /// Heap bytes held (primitives, BVH nodes, slot order).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.disks.capacity() * std::mem::size_of::<DiskPrim>()
            + self.spheres.capacity() * std::mem::size_of::<SpherePrim>()
            + self.detail.capacity() * std::mem::size_of::<DiskDetail>()
    }

    /// The blending parameters in use (default: [`LayerBlend::default`]).
    pub fn layer_blend(&self) -> LayerBlend {
        self.blend
    }

    /// Replaces the blending parameters (negative values are treated as zero).
    pub fn set_layer_blend(&mut self, blend: LayerBlend) {
        self.blend = LayerBlend {
            layer_factor: blend.layer_factor.max(0.0),
            min_normal_dot: blend.min_normal_dot.max(0.0),
            band_cap: blend.band_cap.max(0.0),
        };
    }

    /// Gives every disk a normal that varies across it, `n(p) = normalize(nᵢ + κᵢ·(p − cᵢ))`
    /// ("Phong splats", Botsch et al. 2004), with `curvature[i]` = κᵢ in 1/scene units per
    /// particle (in input order; e.g. from `pointcloud::curvature`). A curved film drawn with flat
    /// disks is faceted, and its reflections show an orange-peel texture at the splat scale; with
    /// κ the blended normal follows the surface (exactly, for spheres). |κᵢ|·rᵢ is capped at 0.5
    /// (a normal tilts at most ~27° across a disk). Ignored for spheres. Cost: 4 bytes a disk,
    /// a few flops per blended disk.
    pub fn set_curvature(&mut self, curvature: &[f32]) -> Result<()> {
        if self.primitive != Primitive::Disk {
            return Ok(());
        }
        if curvature.len() != self.len() {
            return Err(Error::invalid(format!(
                "curvature has {} values for {} particles",
                curvature.len(),
                self.len()
            )));
        }
        let caps: Vec<f32> = self
            .disks
            .iter()
            .take(self.len())
            .map(|d| 0.5 / d.radius)
            .collect();
        let order = self.bvh.order.clone();
        let detail = self.detail_mut();
        for ((slot, &i), cap) in order.iter().enumerate().zip(caps) {
            let k = curvature[i as usize];
            detail[slot].curvature = if k.is_finite() {
                k.clamp(-cap, cap)
            } else {
                0.0
            };
        }
        Ok(())
    }

    /// Gives every disk a thickness that varies linearly across it, `h(p) = hᵢ + gᵢ·(p − cᵢ)`
    /// (clamped at 0), with `gradient[i]` = gᵢ in nm per scene unit per particle (input order;
    /// e.g. from `pointcloud::curvature::gradient_from_table`). Blending then reproduces linear
    /// thickness fields exactly, where blending constants leaves a bump at every splat centre —
    /// a fine texture wherever colour changes fast with thickness. Ignored for spheres.
    pub fn set_thickness_gradient(&mut self, gradient: &[Vec3]) -> Result<()> {
        if self.primitive != Primitive::Disk {
            return Ok(());
        }
        if gradient.len() != self.len() {
            return Err(Error::invalid(format!(
                "thickness gradient has {} values for {} particles",
                gradient.len(),
                self.len()
            )));
        }
        let order = self.bvh.order.clone();
        let detail = self.detail_mut();
        for (slot, &i) in order.iter().enumerate() {
            let g = gradient[i as usize];
            detail[slot].thickness_gradient = if g.is_finite() { g } else { Vec3::ZERO };
        }
        Ok(())
    }

    fn detail_mut(&mut self) -> &mut [DiskDetail] {
        if self.detail.is_empty() {
            self.detail = vec![DiskDetail::default(); self.len()];
        }
        &mut self.detail
    }

    /// Thickness of the disk in `slot` at the point `p` on it (nm).
    #[inline]
    pub(super) fn disk_thickness_at(&self, slot: u32, p: Vec3) -> f32 {
        let d = &self.disks[slot as usize];
        match self.detail.get(slot as usize) {
            Some(x) => (d.thickness + x.thickness_gradient.dot(p - d.center)).max(0.0),
            None => d.thickness,
        }
    }

    /// The normal of the disk in `slot` at the point `p` on it: its own normal, tilted by its
    /// curvature when one is set.
    #[inline]
    pub(super) fn disk_normal_at(&self, slot: u32, p: Vec3) -> Vec3 {
        let d = &self.disks[slot as usize];
        match self.detail.get(slot as usize) {
            Some(x) if x.curvature != 0.0 => {
                (d.normal + x.curvature * (p - d.center)).normalize_or(d.normal)
            }
            _ => d.normal,
        }
    }

    /// The underlying BVH (slot order and nodes), for statistics and debugging.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }
}
