//! The film the particles hold, drawn where the surface leaves it bare: a guarantee that the
//! MLS surface draws at least each particle's own disk (its tangent plane within a given
//! radius, as a rule its own √(A/π)).
//!
//! At a rolled rim or a strand the blend of tangent planes runs 0.05–0.6 spacings off the
//! particles, or its zero weighs under the weight threshold, and pieces of film the particles'
//! own areas hold were left bare. So, at the build ([`MlsSurface::set_own_disks`]), each
//! particle's disk is probed at its centre and at [`RIM_POINTS`] points on its rim: a probe is
//! covered if f has a zero along the particle's normal within [`BAND`] particle radii of it
//! that counts as film. A particle with a probe not covered joins a small set of disks with a
//! BVH of its own; a cloud whose surface covers every disk has none and pays nothing.
//!
//! At a ray query the disks crossed before the surface's first crossing are looked at nearest
//! first; a disk crossing counts as film only if the surface has no crossing within
//! [`BAND`] radii / |cos θ| of it along the ray (θ between ray and the disk's normal, |cos θ|
//! floored at [`MIN_COS`]), looked for on both sides of it, also before the query's `t_min`:
//! so a disk is never drawn where the surface already crosses that film (no doubled layer),
//! and a ray that crosses a particle's own disk always meets film near it.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::MlsSurface;
use super::field::FieldSample;
use super::gathered::aside;
use crate::geometry::particles::particle_bvh;
use crate::geometry::primitives::{disk_bounds, intersect_disk};
use crate::geometry::{Bvh, Ray, SurfaceHit};
use crate::{Error, Result};

/// Two half-planes of a disk's plane, each `(m, k)` (`m` unit, in the plane; `k` scene units):
/// the disk keeps the points at offset x from its centre with x·m ≤ k in both (as
/// `DiskGeometry::set_edge_clips` takes them).
type EdgeClip = [Vec4; 2];

/// No cut.
const NO_CLIP: EdgeClip = [
    Vec4::new(0.0, 0.0, 0.0, f32::INFINITY),
    Vec4::new(0.0, 0.0, 0.0, f32::INFINITY),
];

/// Whether `clip` keeps the point at offset `x` from the disk's centre.
#[inline(always)]
fn keeps(clip: &EdgeClip, x: Vec3) -> bool {
    clip.iter().all(|c| x.dot(c.truncate()) <= c.w)
}

/// Half-width of the band around a disk point in which a crossing of the surface counts as
/// drawing that film, in the particle's (MLS) radii, along the normal (along a ray: divided by
/// |cos θ|).
pub(super) const BAND: f32 = 0.6;

/// Probes on each disk's rim (besides its centre).
pub(super) const RIM_POINTS: usize = 6;

/// Rings of neighbours around a particle whose own disk may be left bare that join it (0: only
/// such particles; 1: also every particle whose support holds one).
pub(super) const RINGS: usize = 1;

/// Floor of |cos θ| in the band along a ray (so a grazing ray's band stays finite).
const MIN_COS: f32 = 0.1;

/// A particle's own disk, drawn where the surface leaves it bare.
#[derive(Clone, Copy, Debug)]
struct OwnDisk {
    p: Vec3,
    n: Vec3,
    /// The radius drawn, scene units.
    radius: f32,
    /// The half-planes that cut the disk drawn ([`NO_CLIP`]: none).
    clip: EdgeClip,
    /// The radius probed (the particle's own), scene units.
    own: f32,
    /// The band's half-width along the normal, scene units.
    band: f32,
    thickness: f32,
    /// Index into the build input.
    particle: u32,
}

/// The disks of the particles the surface may leave bare, with their BVH.
#[derive(Clone, Debug, Default)]
pub(super) struct Fallback {
    disks: Vec<OwnDisk>,
    bvh: Option<Bvh>,
}

impl Fallback {
    /// Number of disks.
    pub(super) fn len(&self) -> usize {
        self.disks.len()
    }

    /// True if there are no disks.
    pub(super) fn is_empty(&self) -> bool {
        self.disks.is_empty()
    }

    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.disks.capacity() * std::mem::size_of::<OwnDisk>()
            + self.bvh.as_ref().map_or(0, Bvh::memory_bytes)
    }
}

impl MlsSurface {
    /// Gives each particle its own disk, `own[i]` (input order, scene units; 0: none): where
    /// the surface may leave that disk bare (see the `fallback` module), the ray queries draw
    /// the particle's disk `drawn` (its radius, scene units, and the half-planes that cut it,
    /// one each; `None`: the own disk itself). Call after [`MlsSurface::set_sheets`]. Cost:
    /// (1 + `RIM_POINTS` = 7) × 2 point queries per particle with a disk, in parallel.
    ///
    /// # Errors
    /// A length other than the particle count, or a radius that is negative or not finite.
    pub fn set_own_disks(
        &mut self,
        own: &[f32],
        drawn: Option<(&[f32], &[[Vec4; 2]])>,
    ) -> Result<()> {
        let (radii, clips) = drawn.unwrap_or((own, &[]));
        check_own_disks(self.particles.len(), own, radii, clips)?;
        let order = self.bvh.order();
        let all: Vec<OwnDisk> = (0..self.particles.len())
            .into_par_iter()
            .map(|slot| {
                let q = &self.particles[slot];
                let particle = order[slot];
                let i = particle as usize;
                let clip = clips.get(i).copied().unwrap_or(NO_CLIP);
                OwnDisk {
                    p: q.p,
                    n: q.n,
                    radius: radii[i],
                    clip: if clip.iter().any(|c| c.is_nan()) {
                        NO_CLIP
                    } else {
                        clip
                    },
                    own: own[i],
                    band: BAND * q.h / self.params.support,
                    thickness: q.thickness,
                    particle,
                }
            })
            .collect();
        let usable = |d: &OwnDisk| d.own > 0.0 && d.radius > 0.0;
        let mut keep: Vec<bool> = all
            .par_iter()
            .map(|d| usable(d) && !self.covers_disk(d))
            .collect();
        // The neighbours of each such particle (whose support holds it) join too: a torn
        // fragment's film is then drawn by one primitive where the surface leaves it.
        for _ in 0..RINGS {
            keep = (0..all.len())
                .into_par_iter()
                .map(|slot| {
                    if keep[slot] || !usable(&all[slot]) {
                        return keep[slot];
                    }
                    let mut c = Vec::new();
                    self.neighbours(all[slot].p, &mut c);
                    c.iter().any(|c| keep[c.slot as usize])
                })
                .collect();
        }
        let disks: Vec<OwnDisk> = all
            .into_iter()
            .zip(keep)
            .filter_map(|(d, k)| k.then_some(d))
            .collect();
        let bvh = (!disks.is_empty()).then(|| {
            particle_bvh(
                disks.len(),
                |i| disks[i].p,
                |i| disks[i].radius,
                |i| disk_bounds(disks[i].p, disks[i].n, disks[i].radius),
            )
        });
        let disks = match &bvh {
            Some(b) => b.order().iter().map(|&i| disks[i as usize]).collect(),
            None => disks,
        };
        self.fallback = Fallback { disks, bvh };
        Ok(())
    }

    /// The number of particles whose own disk the ray queries may draw.
    pub fn own_disk_count(&self) -> usize {
        self.fallback.len()
    }

    /// Whether the surface has a film crossing near every probe of `disk`: its centre and
    /// the rim of its own disk (pulled in to the cut where the drawn disk is cut).
    fn covers_disk(&self, d: &OwnDisk) -> bool {
        let (u, v) = d.n.any_orthonormal_pair();
        let step = std::f32::consts::TAU / RIM_POINTS as f32;
        std::iter::once(d.p)
            .chain((0..RIM_POINTS).map(|k| {
                let a = k as f32 * step;
                let dir = a.cos() * u + a.sin() * v;
                let reach = d.clip.iter().fold(d.own, |r, c| {
                    let m = dir.dot(c.truncate());
                    if m > 0.0 { r.min(c.w / m) } else { r }
                });
                d.p + reach.max(0.0) * dir
            }))
            .all(|x| self.covers_point(x, d.n, d.band))
    }

    /// Whether f has a zero along `n` within `band` of `x` that counts as film: one Newton
    /// step from `x` along `n`, then the field there must be film and within a quarter band
    /// of zero.
    fn covers_point(&self, x: Vec3, n: Vec3, band: f32) -> bool {
        let Some(s) = self.sample_at(x) else {
            return false;
        };
        let slope = s.grad.dot(n);
        if s.f.abs() > band || slope.abs() < 1e-3 {
            return false;
        }
        let t = -s.f / slope;
        if t.abs() > band {
            return false;
        }
        let near = |z: &FieldSample| z.f.abs() <= 0.25 * band && self.is_film(z);
        self.sample_at(x + t * n).is_some_and(|z| near(&z))
    }

    /// The first crossing in `(t_min, t_max)` of the surface (`hit`, the surface's first) or,
    /// where the surface has none near it, of an own disk (see the `fallback` module);
    /// `crossed`, the surface crossing this ray met before (NaN: none).
    pub(super) fn with_own_disks(
        &self,
        ray: &Ray,
        (t_min, t_max): (f32, f32),
        hit: Option<SurfaceHit>,
        crossed: f32,
    ) -> Option<SurfaceHit> {
        let Some(bvh) = &self.fallback.bvh else {
            return hit;
        };
        let limit = hit.map_or(t_max, |h| h.t);
        let mut from = t_min;
        loop {
            // The nearest disk crossing in (from, limit).
            let mut best: Option<(f32, u32)> = None;
            bvh.closest(ray, from, limit, |slot, t_far| {
                let d = &self.fallback.disks[slot as usize];
                if let Some((t, _)) = intersect_disk(ray, d.p, d.n, d.radius, from, *t_far)
                    && keeps(&d.clip, ray.at(t) - d.p)
                {
                    *t_far = t;
                    best = Some((t, slot));
                }
            });
            let Some((t, slot)) = best else {
                return hit;
            };
            let d = &self.fallback.disks[slot as usize];
            let band = d.band / d.n.dot(ray.dir).abs().max(MIN_COS);
            if hit.is_some_and(|h| h.t - t <= band) {
                return hit; // the surface's own crossing draws this film
            }
            if (t - crossed).abs() <= band {
                from = t; // so does the crossing this ray just passed
                continue;
            }
            if aside(|| self.surface_hit(ray, t - band, t + band)).is_none() {
                let next = hit.map_or(f32::INFINITY, |h| h.t - band);
                return Some(SurfaceHit {
                    t,
                    // Past the band (but before the surface's next crossing): the other
                    // disks of this film met within it are not drawn again as a second layer.
                    t_exit: (t + band).min(next).max(t),
                    position: ray.at(t),
                    normal: d.n,
                    thickness_nm: d.thickness,
                    coverage: 1,
                    particle: d.particle,
                });
            }
            // The surface draws this disk's film (perhaps before `t_min`): on to the next.
            from = t;
        }
    }
}

/// The arguments of [`MlsSurface::set_own_disks`] for `n` particles: lengths, and radii finite
/// and non-negative.
fn check_own_disks(n: usize, own: &[f32], radii: &[f32], clips: &[EdgeClip]) -> Result<()> {
    for (name, r) in [("own radii", own), ("drawn radii", radii)] {
        if r.len() != n {
            return Err(Error::invalid(format!(
                "mls: {} {name} for {n} particles",
                r.len()
            )));
        }
        if let Some(i) = r.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
            return Err(Error::invalid(format!(
                "mls: {name}: {} of particle {i} is not finite and non-negative",
                r[i]
            )));
        }
    }
    if !clips.is_empty() && clips.len() != n {
        return Err(Error::invalid(format!(
            "mls: {} cuts for {n} particles",
            clips.len()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat film (21 × 21 particles 0.1 apart at z = 0, own radius √(0.01/π)) and, 0.35
    /// above it, a strand of three particles 0.2 apart with tilted normals (own radius 0.08):
    /// positions, normals, MLS radii, own radii; the strand's are the last three.
    fn film_and_strand() -> (Vec<Vec3>, Vec<Vec3>, Vec<f32>, Vec<f32>) {
        let (mut p, mut n, mut r, mut own) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for i in 0..21 {
            for j in 0..21 {
                p.push(Vec3::new(i as f32 * 0.1 - 1.0, j as f32 * 0.1 - 1.0, 0.0));
                n.push(Vec3::Z);
                r.push(0.1);
                own.push((0.01 / std::f32::consts::PI).sqrt());
            }
        }
        for k in 0..3 {
            p.push(Vec3::new(k as f32 * 0.2 - 0.2, 0.1, 0.35));
            n.push(Vec3::new(0.0, 0.3, 1.0).normalize());
            r.push(0.1);
            own.push(0.08);
        }
        (p, n, r, own)
    }

    /// Rays from above the film towards random points on it, within ~50° of straight down.
    fn rays(count: usize) -> Vec<Ray> {
        let mut seed = 0x2545_f491_u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed as f32 / u32::MAX as f32
        };
        (0..count)
            .map(|_| {
                let target = Vec3::new(next() - 0.5, next() * 0.6 - 0.2, 0.2 * next());
                let origin = target + Vec3::new(2.0 * next() - 1.0, 2.0 * next() - 1.0, 1.5);
                Ray::new(origin, target - origin)
            })
            .collect()
    }

    #[test]
    fn every_ray_crossing_an_own_disk_meets_film_within_the_band() {
        let (p, n, r, own) = film_and_strand();
        let thickness: Vec<f32> = (0..p.len()).map(|i| 100.0 + i as f32).collect();
        let mut s = MlsSurface::build(&p, &n, &r, &thickness).unwrap();
        s.set_own_disks(&own, None).unwrap();
        assert!(s.own_disk_count() >= 3, "{}", s.own_disk_count());
        let (mut crossing, mut by_disk) = (0, 0);
        for ray in rays(20_000) {
            let hit = s.intersect(&ray, 0.0, f32::INFINITY);
            let bare = s.surface_hit(&ray, 0.0, f32::INFINITY);
            by_disk += usize::from(hit.map(|h| h.t) != bare.map(|h| h.t));
            for i in 0..p.len() {
                let nn = n[i].normalize();
                let Some((t, _)) = intersect_disk(&ray, p[i], nn, own[i], 0.0, f32::INFINITY)
                else {
                    continue;
                };
                crossing += 1;
                let band = BAND * r[i] / nn.dot(ray.dir).abs().max(MIN_COS);
                let h = hit.unwrap_or_else(|| panic!("{ray:?} crosses disk {i} at {t}, no film"));
                assert!(
                    h.t <= t + band * 1.001,
                    "{ray:?}: disk {i} at {t}, film at {}",
                    h.t
                );
            }
        }
        // The strand's disks are met by many rays and drawn where the surface has no crossing.
        assert!(crossing > 10_000 && by_disk > 100, "{crossing} {by_disk}");
    }

    #[test]
    fn a_disk_is_drawn_with_its_particles_normal_and_thickness() {
        let (p, n, r, own) = film_and_strand();
        let thickness: Vec<f32> = (0..p.len()).map(|i| 100.0 + i as f32).collect();
        let mut s = MlsSurface::build(&p, &n, &r, &thickness).unwrap();
        // Straight down through the middle strand particle's own disk, 0.07 from its centre:
        // its support weighs under the film's threshold there, so the surface alone is bare.
        let ray = Ray::new(Vec3::new(0.07, 0.1, 2.0), -Vec3::Z);
        let bare = s.intersect(&ray, 0.0, 1.9);
        assert!(bare.is_none(), "{bare:?}");
        s.set_own_disks(&own, None).unwrap();
        let h = s.intersect(&ray, 0.0, 1.9).expect("the own disk is drawn");
        let k = p.len() - 2;
        assert_eq!(h.particle as usize, k);
        assert_eq!(h.thickness_nm, thickness[k]);
        assert!((h.normal - n[k].normalize()).length() < 1e-6);
        // The film below is still found past it, once.
        let below = s.intersect(&ray, h.t_exit + 1e-4, f32::INFINITY).unwrap();
        assert!(below.position.z.abs() < 1e-3, "{below:?}");
        // Zero radii take the disks away again.
        s.set_own_disks(&vec![0.0; p.len()], None).unwrap();
        assert_eq!(s.own_disk_count(), 0);
        assert!(s.set_own_disks(&own[1..], None).is_err());
    }

    #[test]
    fn a_surface_that_covers_every_disk_keeps_none() {
        // A closed sphere of 4000 particles, own radii the area each holds: the surface covers
        // every disk, so no disk is kept and the ray queries are the surface's alone.
        let count = 4000;
        let own = (4.0 / count as f32).sqrt(); // √(A/π), A = 4π / count
        let (_, _, mut s) = super::super::unit_sphere_surface(count);
        s.set_own_disks(&vec![own; count], None).unwrap();
        assert_eq!(s.own_disk_count(), 0);
    }
}
