//! [`MlsSurface`]: the smooth surface a particle cloud samples, defined by moving least squares
//! and intersected by rays directly — the look of a meshed film without a meshing step.
//!
//! * **Surface.** The zero set of the implicit MLS function f (see the `field` module): the
//!   weighted mean of the signed distances to the particles' tangent planes, with compact
//!   weights of support radius hᵢ = [`MlsParams::support`] × the particle radius (the local
//!   spacing). Thickness is interpolated with the same weights; the normal is ∇f/|∇f|.
//! * **Boundaries.** A zero crossing is part of the film only where the particles carry it: the
//!   total weight Σ wᵢ must reach [`MlsParams::min_weight`] × the median total weight at the
//!   particles themselves, and the neighbours' normals must agree (|Σ wᵢ nᵢ| ≥ ½ Σ wᵢ). So the
//!   open edge of a film stays where its particles end, holes stay open and sparse stray
//!   particles do not grow a surface.
//! * **Sheets.** Films that meet without joining smoothly (a foam's walls, one particle set per
//!   bubble, oriented per bubble) can be labelled as sheets ([`MlsSurface::set_sheets`]): f
//!   then blends one sheet's particles at a time, so the walls run into their junctions instead
//!   of cancelling there (the `sheets` module).
//! * **Own disks.** Where the particles carry their own areas, [`MlsSurface::set_own_disks`]
//!   guarantees the surface draws at least the film they hold: a particle whose own disk the
//!   surface may leave bare (probed at the build), and its neighbours, draw their disk where the
//!   surface has no crossing near it (the `fallback` module). Without such particles a ray
//!   query pays nothing for this.
//! * **Rays** (Adamson & Alexa 2003, "Ray tracing point set surfaces"): the surface lies inside
//!   the union of the support spheres. One BVH traversal collects every sphere the ray
//!   crosses; they are merged into intervals of the ray. f is a weighted mean of the distances
//!   to the particles' tangent planes, each linear along the ray, so in each interval f can
//!   vanish only in the band where covering particles' planes disagree in sign (the `band`
//!   module; a few hundredths of a spacing for a smooth film): the approach to a film and the
//!   way out of it cost no evaluation of f. The band is marched with steps of 0.9|f| (f is
//!   distance-like) bounded to 0.05–1 particle radii, up to its end (f's value there bounds nothing: where the
//!   weight fades, beside another wall, f may jump), a sign change is refined by bracketed Illinois regula
//!   falsi to 10⁻³ radii, and a local minimum of |f| between samples is checked for a grazing
//!   double crossing (so grazing rays do not tunnel).
//! * **Continued rays.** A per-thread buffer keeps the spheres gathered for the last query; a
//!   query on the same ray further on (the transmitted branch of a crossing, a shadow ray's
//!   next crossing) reuses them instead of traversing the BVH again, already in order.
//!
//! Queries are `&self` and thread-safe.

mod band;
mod fallback;
mod field;
mod gather;
mod gathered;
mod sheets;
mod trace;

use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use super::particles::{check_particles, particle_bvh};
use super::primitives::sphere_bounds;
use super::{Aabb, Bvh};
use crate::{Error, Result};
use fallback::Fallback;
use field::Cand;

/// Parameters of the MLS surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MlsParams {
    /// Support radius of each particle's weight as a multiple of its radius (1..=8; default 2:
    /// about 12 neighbours at the estimated radii, ~0.9× the spacing). Larger is smoother and
    /// slower and rounds off detail finer than the support.
    pub support: f32,
    /// A crossing counts only where the total weight is at least this fraction of the median
    /// total weight at the particles (0..1; default 0.3). Higher pulls open edges in and opens
    /// sparse regions; lower lets the surface run on past the last particles.
    pub min_weight: f32,
}

impl Default for MlsParams {
    fn default() -> Self {
        MlsParams {
            support: 2.0,
            min_weight: 0.3,
        }
    }
}

/// The MLS field at one point ([`MlsSurface::field_at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MlsPoint {
    /// f(x), scene units (≈ signed distance to the surface, positive on the normals' side).
    pub f: f32,
    /// ∇f(x) (≈ the unit surface normal near the surface).
    pub grad: Vec3,
    /// Total weight Σ wᵢ(x).
    pub weight: f32,
    /// Agreement of the neighbours' normals, |Σ wᵢ nᵢ| / Σ wᵢ (1 = all alike).
    pub coherence: f32,
    /// Interpolated thickness, nm.
    pub thickness_nm: f32,
    /// A zero of f here would count as film: weight ≥ [`MlsSurface::weight_threshold`] and
    /// coherence ≥ ½ (see the module docs).
    pub is_film: bool,
}

/// One particle in slot order (32 bytes).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
struct MlsParticle {
    p: Vec3,
    /// Support radius h, scene units.
    h: f32,
    n: Vec3,
    thickness: f32,
}

/// Particles in slot order sampled to estimate the median total weight.
const WEIGHT_SAMPLES: usize = 2048;

/// Neighbours' normals must agree at least this much (|Σ wᵢ nᵢ| / Σ wᵢ) at a crossing.
const MIN_COHERENCE: f32 = 0.5;

/// A moving-least-squares point-set surface over particles, ray traced directly.
///
/// Memory: 32 bytes per particle plus the BVH over the support spheres (~30 bytes per particle).
/// See the module docs for the surface definition and the intersection method.
#[derive(Clone, Debug)]
pub struct MlsSurface {
    bvh: Bvh,
    particles: Vec<MlsParticle>,
    params: MlsParams,
    /// Absolute total weight a crossing needs.
    weight_threshold: f32,
    /// Distinct per build (clones share it): names the surface a thread's kept support spheres
    /// belong to.
    id: u64,
    /// Each slot's sheet (empty: one sheet; see [`MlsSurface::set_sheets`]).
    sheets: Vec<u32>,
    /// The particles' own disks the surface may leave bare ([`MlsSurface::set_own_disks`]).
    fallback: Fallback,
}

/// Source of [`MlsSurface`] ids.
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

impl MlsSurface {
    /// Builds the surface with default [`MlsParams`]. One entry per particle in each slice;
    /// `normals` (required; consistently oriented, since f is signed by them) are normalised.
    /// Radii (scene units, the local spacing scale) must be finite and positive, thickness (nm)
    /// finite and non-negative. Errors name the offending array and particle. Cost: the BVH
    /// build (O(n log n), parallel) plus ~2000 point queries.
    pub fn build(
        positions: &[Vec3],
        normals: &[Vec3],
        radii: &[f32],
        thickness_nm: &[f32],
    ) -> Result<Self> {
        Self::build_with(
            positions,
            normals,
            radii,
            thickness_nm,
            MlsParams::default(),
        )
    }

    /// [`MlsSurface::build`] with explicit parameters (out-of-range values are an error).
    pub fn build_with(
        positions: &[Vec3],
        normals: &[Vec3],
        radii: &[f32],
        thickness_nm: &[f32],
        params: MlsParams,
    ) -> Result<Self> {
        if !(1.0..=8.0).contains(&params.support) {
            return Err(Error::invalid(format!(
                "mls: support must be 1..=8 particle radii, got {}",
                params.support
            )));
        }
        if !(0.0..1.0).contains(&params.min_weight) {
            return Err(Error::invalid(format!(
                "mls: min_weight must be in [0, 1), got {}",
                params.min_weight
            )));
        }
        check_particles(positions, normals, radii, thickness_nm, true)?;
        let h = |i: usize| radii[i] * params.support;
        let bvh = particle_bvh(
            positions.len(),
            |i| positions[i],
            h,
            |i| sphere_bounds(positions[i], h(i)),
        );
        let particles: Vec<MlsParticle> = bvh
            .order()
            .par_iter()
            .map(|&i| {
                let i = i as usize;
                MlsParticle {
                    p: positions[i],
                    h: h(i),
                    n: normals[i].normalize(),
                    thickness: thickness_nm[i],
                }
            })
            .collect();
        let mut surface = MlsSurface {
            bvh,
            particles,
            params,
            weight_threshold: 0.0,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            sheets: Vec::new(),
            fallback: Fallback::default(),
        };
        surface.weight_threshold = params.min_weight * surface.median_particle_weight();
        Ok(surface)
    }

    /// The median over (up to [`WEIGHT_SAMPLES`]) particles of the total weight at the particle.
    fn median_particle_weight(&self) -> f32 {
        let n = self.particles.len();
        if n == 0 {
            return 0.0;
        }
        let m = n.min(WEIGHT_SAMPLES);
        let mut w: Vec<f32> = (0..m)
            .into_par_iter()
            .map(|k| {
                let p = self.particles[k * n / m].p;
                self.sample_at(p).map_or(0.0, |s| s.weight)
            })
            .collect();
        let mid = m / 2;
        *w.select_nth_unstable_by(mid, f32::total_cmp).1
    }

    /// The neighbours of the point `x` (particles whose support contains it) as candidates.
    fn neighbours(&self, x: Vec3, out: &mut Vec<Cand>) {
        out.clear();
        self.bvh.visit_point(x, |s| {
            let q = &self.particles[s as usize];
            if (x - q.p).length_squared() < q.h * q.h {
                out.push(self.cand(s, 0.0, 0.0));
            }
        });
    }

    /// The candidate record of the particle in `slot`, inside the support for `ta..=tb`.
    #[inline]
    fn cand(&self, slot: u32, ta: f32, tb: f32) -> Cand {
        let q = &self.particles[slot as usize];
        Cand {
            p: q.p,
            inv_h2: 1.0 / (q.h * q.h),
            n: q.n,
            thickness: q.thickness,
            ta,
            tb,
            slot,
            r: q.h / self.params.support,
            g0: 0.0,
            g1: 0.0,
            b: 0.0,
            k2: 0.0,
        }
    }

    fn sample_at(&self, x: Vec3) -> Option<field::FieldSample> {
        let mut c = Vec::new();
        self.neighbours(x, &mut c);
        self.keep_heaviest_sheet(x, &mut c);
        field::sample(&c, x, 0.0)
    }

    /// The implicit function at `x` (scene units; ≈ signed distance to the surface, positive on
    /// the side the normals point to), or `None` where no particle's support reaches `x`.
    /// Cost: one BVH point query.
    pub fn value_at(&self, x: Vec3) -> Option<f32> {
        self.sample_at(x).map(|s| s.f)
    }

    /// Everything the surface knows at `x` (f, its gradient, the total weight, the normals'
    /// agreement, the thickness), or `None` where no particle's support reaches `x`: the same
    /// field the ray intersection finds the zeros of, for probing and for brute-force checks.
    /// Cost: one BVH point query.
    pub fn field_at(&self, x: Vec3) -> Option<MlsPoint> {
        self.sample_at(x).map(|s| MlsPoint {
            f: s.f,
            grad: s.grad,
            weight: s.weight,
            coherence: s.coherence,
            thickness_nm: s.thickness,
            is_film: self.is_film(&s),
        })
    }

    /// A zero of f with this sample counts as film: enough weight, agreeing normals.
    fn is_film(&self, s: &field::FieldSample) -> bool {
        s.weight >= self.weight_threshold && s.coherence >= MIN_COHERENCE
    }

    /// Bounds of the support spheres (the empty box for zero particles).
    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The underlying BVH (slot order and nodes), for statistics and debugging.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// True if there are no particles.
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// The parameters in use.
    pub fn params(&self) -> MlsParams {
        self.params
    }

    /// The total weight a crossing needs to count as film ([`MlsParams::min_weight`] × the
    /// median total weight at the particles).
    pub fn weight_threshold(&self) -> f32 {
        self.weight_threshold
    }

    /// Heap bytes held (particles, BVH nodes, slot order).
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.particles.capacity() * std::mem::size_of::<MlsParticle>()
            + self.sheets.capacity() * 4
            + self.fallback.memory_bytes()
    }
}

/// A closed unit sphere of `n` particles on a Fibonacci lattice (normals outward, radii 0.92 ×
/// the lattice's hexagonal spacing d, 100 nm), its positions and d: the tests' closed film.
#[cfg(test)]
pub(super) fn unit_sphere_surface(n: usize) -> (Vec<Vec3>, f32, MlsSurface) {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let pos: Vec<Vec3> = (0..n)
        .map(|i| {
            let z = 1.0 - (2 * i + 1) as f32 / n as f32;
            let (rr, a) = ((1.0 - z * z).sqrt(), golden * i as f32);
            Vec3::new(rr * a.cos(), rr * a.sin(), z)
        })
        .collect();
    let d = (8.0 * std::f32::consts::PI / (3f32.sqrt() * n as f32)).sqrt();
    let s = MlsSurface::build(&pos, &pos, &vec![0.92 * d; n], &vec![100.0; n]).unwrap();
    (pos, d, s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn build_checks_inputs_and_params() {
        let p = [Vec3::ZERO, Vec3::X];
        let n = [Vec3::Z, Vec3::Z];
        assert!(MlsSurface::build(&p, &n, &[0.5, 0.5], &[100.0, 100.0]).is_ok());
        let e = MlsSurface::build(&p, &[], &[0.5, 0.5], &[100.0, 100.0]).unwrap_err();
        assert!(e.to_string().contains("normals"), "{e}");
        let e = MlsSurface::build(&p, &n, &[0.5, -1.0], &[100.0, 100.0]).unwrap_err();
        assert!(e.to_string().contains("particle 1"), "{e}");
        let bad = MlsParams {
            support: 0.5,
            ..MlsParams::default()
        };
        assert!(MlsSurface::build_with(&p, &n, &[0.5, 0.5], &[1.0, 1.0], bad).is_err());
        let empty = MlsSurface::build(&[], &[], &[], &[]).unwrap();
        assert!(empty.is_empty() && empty.bounds().is_empty());
    }

    #[test]
    fn value_is_signed_distance_to_a_plane() {
        let mut p = Vec::new();
        for i in 0..21 {
            for j in 0..21 {
                p.push(Vec3::new(i as f32 * 0.1 - 1.0, j as f32 * 0.1 - 1.0, 0.5));
            }
        }
        let n = vec![Vec3::Z; p.len()];
        let s = MlsSurface::build(&p, &n, &vec![0.1; p.len()], &vec![300.0; p.len()]).unwrap();
        for z in [-0.15, -0.02, 0.0, 0.07, 0.19] {
            let f = s.value_at(Vec3::new(0.03, -0.04, 0.5 + z)).unwrap();
            assert!((f - z).abs() < 1e-5, "{f} vs {z}");
        }
        assert!(s.value_at(Vec3::new(0.0, 0.0, 0.75)).is_none());
        // An interior particle of a square grid carries 1 + 4·(3/4)³ + 4·(1/2)³ ≈ 3.19 at h = 2d.
        assert!(s.weight_threshold() > 0.3 * 3.0 && s.weight_threshold() < 0.3 * 4.0);
    }
}
