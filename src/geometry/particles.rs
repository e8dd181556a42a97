//! What every particle geometry (disks, spheres, the MLS surface) shares: the checks of the
//! particle arrays it is built from, and the padded per-slot arrays its four-wide leaf tests
//! read.

use glam::Vec3;
use rayon::prelude::*;

use super::bvh::BvhParams;
use super::ray4::PAD;
use super::{Aabb, Bvh};
use crate::{Error, Result};

/// The accessors every particle geometry with a `bvh: Bvh` field shares: bounds, count,
/// emptiness and the tree itself (expanded inside its `impl`).
macro_rules! particle_accessors {
    () => {
        /// Bounds of all particles (slightly padded; the empty box for zero particles).
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

        /// The underlying BVH (slot order and nodes), for statistics and debugging.
        pub fn bvh(&self) -> &Bvh {
            &self.bvh
        }
    };
}
pub(super) use particle_accessors;

/// Relative padding of primitive boxes so rounding in the hit point never makes the BVH cull a
/// primitive the exact test would accept.
const BOUNDS_PAD: f32 = 1e-6;

/// A BVH over `n` particles whose unpadded box is `bounds(i)` around centre `centre(i)` with
/// reach `reach(i)` (radius or support); each box is padded by [`BOUNDS_PAD`] of its magnitude.
/// Cost: O(n log n), parallel.
pub(super) fn particle_bvh(
    n: usize,
    centre: impl Fn(usize) -> Vec3 + Sync,
    reach: impl Fn(usize) -> f32 + Sync,
    bounds: impl Fn(usize) -> Aabb + Sync,
) -> Bvh {
    let padded = |i| bounds(i).padded((centre(i).abs().max_element() + reach(i)) * BOUNDS_PAD);
    Bvh::build_by(n, padded, BvhParams::default())
}

/// `make(particle)` for every slot of `order`, then [`PAD`] copies of `pad` (so a four-wide
/// packet can start at any slot).
pub(super) fn padded_slots<T: Copy + Send>(
    order: &[u32],
    pad: T,
    make: impl Fn(usize) -> T + Sync,
) -> Vec<T> {
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
pub(crate) fn check_particles(
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
