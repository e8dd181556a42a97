//! Droplets: the bulk-fluid particles a rupturing film sheds, as solid spheres of water
//! (centre, radius), found along a ray through the splat BVH of spheres. What they do to light
//! (refraction, Fresnel) is the integrator's business; this answers where a ray meets one and
//! where a ray inside one leaves it.

use glam::Vec3;

use super::{Aabb, Ray, SphereGeometry};
use crate::error::Result;

/// Index of refraction of water, the droplets' default.
pub const WATER_IOR: f32 = 1.33;

/// A set of spheres of one index of refraction. Empty by default (a scene without droplets
/// pays one branch a ray).
#[derive(Clone, Debug)]
pub struct Droplets {
    spheres: Option<SphereGeometry>,
    centres: Vec<Vec3>,
    radii: Vec<f32>,
    /// Index of refraction inside the spheres (default [`WATER_IOR`]).
    pub ior: f32,
}

impl Default for Droplets {
    fn default() -> Self {
        Droplets {
            spheres: None,
            centres: Vec::new(),
            radii: Vec::new(),
            ior: WATER_IOR,
        }
    }
}

/// The droplets grown to one camera's pixel footprints (see [`Droplets::footprints`]): a
/// camera's own, so one set of droplets serves many cameras at once.
#[derive(Clone, Debug)]
pub struct GrownDroplets {
    /// The spheres grown to the footprints.
    spheres: SphereGeometry,
    /// Their grown radii, scene units (each at least the droplet's own).
    radii: Vec<f32>,
}

impl GrownDroplets {
    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.spheres.memory_bytes() + self.radii.len() * 4
    }
}

/// Where a camera ray meets a droplet grown to the pixel footprint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrownHit {
    /// The hit on the grown sphere.
    pub hit: DropletHit,
    /// Share of the grown sphere's cross-section the droplet covers, (r / g)² ∈ (0, 1]: 1 for
    /// a droplet at least as large as the footprint.
    pub coverage: f32,
    /// Distance along the ray where it leaves the grown sphere.
    pub t_exit: f32,
}

/// Where a ray meets a droplet from outside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DropletHit {
    /// Distance along the ray.
    pub t: f32,
    /// Outward unit normal at the hit.
    pub normal: Vec3,
    /// Which droplet.
    pub index: u32,
}

impl Droplets {
    /// Builds the droplets from centres and radii (scene units; finite, radii > 0).
    /// Cost: O(n log n), as [`SphereGeometry::build`].
    ///
    /// # Errors
    /// As [`SphereGeometry::build`]: lengths that disagree, non-finite centres, bad radii.
    pub fn build(centres: &[Vec3], radii: &[f32]) -> Result<Self> {
        if centres.is_empty() {
            return Ok(Droplets::default());
        }
        let zeros = vec![0.0; centres.len()];
        let spheres = SphereGeometry::build(centres, &[], radii, &zeros)?;
        Ok(Droplets {
            spheres: Some(spheres),
            centres: centres.to_vec(),
            radii: radii.to_vec(),
            ior: WATER_IOR,
        })
    }

    /// Each droplet seen by camera rays grown to at least `footprint(centre)` (scene units;
    /// the radius of a disk covering one pixel at the droplet's distance), so a droplet smaller
    /// than a pixel is still found by the pixel's samples and counts with its share of the
    /// pixel ([`Droplets::intersect_grown`]); `None` without droplets. Cost: one more sphere
    /// tree, O(n log n).
    ///
    /// # Errors
    /// As [`SphereGeometry::build`].
    pub fn footprints(&self, footprint: impl Fn(Vec3) -> f32) -> Result<Option<GrownDroplets>> {
        if self.is_empty() {
            return Ok(None);
        }
        let g: Vec<f32> = self
            .centres
            .iter()
            .zip(&self.radii)
            .map(|(c, r)| {
                let f = footprint(*c);
                if f.is_finite() && f > *r { f } else { *r }
            })
            .collect();
        let zeros = vec![0.0; g.len()];
        Ok(Some(GrownDroplets {
            spheres: SphereGeometry::build(&self.centres, &[], &g, &zeros)?,
            radii: g,
        }))
    }

    /// The nearest of the droplets `grown` (see [`Droplets::footprints`]; this set's own) a
    /// camera ray enters with `t_min < t < t_max`; without footprints, the droplets themselves
    /// at coverage 1. The expected coverage over a pixel's samples is the droplet's own
    /// cross-section over the pixel's: P(hit grown) · (r/g)² = π g² / A · r² / g² = π r² / A.
    pub fn intersect_grown(
        &self,
        grown: Option<&GrownDroplets>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<GrownHit> {
        let Some(GrownDroplets { spheres, radii: g }) = grown else {
            let hit = self.intersect(ray, t_min, t_max)?;
            let t_exit = hit.t + self.exit_distance(hit.index, ray.at(hit.t), ray.dir);
            return Some(GrownHit {
                hit,
                coverage: 1.0,
                t_exit,
            });
        };
        let h = spheres.intersect(ray, t_min, t_max)?;
        let i = h.particle as usize;
        let (r, g) = (self.radii[i], g[i]);
        let oc = ray.at(h.t) - self.centres[i];
        let b = oc.dot(ray.dir);
        let t_exit = h.t + (-b + (b * b - (oc.length_squared() - g * g)).max(0.0).sqrt()).max(0.0);
        Some(GrownHit {
            hit: DropletHit {
                t: h.t,
                normal: h.normal,
                index: h.particle,
            },
            coverage: ((r / g) * (r / g)).min(1.0),
            t_exit,
        })
    }

    /// Number of droplets.
    pub fn len(&self) -> usize {
        self.centres.len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.centres.is_empty()
    }

    /// Bounds of all droplets (the empty box for none).
    pub fn bounds(&self) -> Aabb {
        self.spheres
            .as_ref()
            .map_or(Aabb::EMPTY, SphereGeometry::bounds)
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.spheres
            .as_ref()
            .map_or(0, SphereGeometry::memory_bytes)
            + self.centres.len() * 16
    }

    /// The nearest droplet the ray enters with `t_min < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<DropletHit> {
        let hit = self.spheres.as_ref()?.intersect(ray, t_min, t_max)?;
        Some(DropletHit {
            t: hit.t,
            normal: hit.normal,
            index: hit.particle,
        })
    }

    /// Centre and radius of droplet `i`.
    pub fn sphere(&self, i: u32) -> (Vec3, f32) {
        (self.centres[i as usize], self.radii[i as usize])
    }

    /// Distance from `origin` (inside or on droplet `i`) along unit `dir` to where the ray
    /// leaves the sphere: the far root of |o + t d − c|² = r².
    pub fn exit_distance(&self, i: u32, origin: Vec3, dir: Vec3) -> f32 {
        let (c, r) = self.sphere(i);
        let oc = origin - c;
        let b = oc.dot(dir);
        let q = (b * b - (oc.length_squared() - r * r)).max(0.0);
        (-b + q.sqrt()).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rays_enter_and_leave_the_right_sphere() {
        let d = Droplets::build(&[Vec3::ZERO, Vec3::new(5.0, 0.0, 0.0)], &[1.0, 0.5]).unwrap();
        let ray = Ray {
            origin: Vec3::new(5.0, 0.0, -10.0),
            dir: Vec3::Z,
        };
        let h = d.intersect(&ray, 0.0, f32::INFINITY).unwrap();
        assert_eq!(h.index, 1);
        assert!((h.t - 9.5).abs() < 1e-4 && (h.normal + Vec3::Z).length() < 1e-4);
        let p = ray.origin + ray.dir * h.t;
        assert!((d.exit_distance(1, p, Vec3::Z) - 1.0).abs() < 1e-4);
        // From the centre every exit is one radius away.
        assert!((d.exit_distance(0, Vec3::ZERO, Vec3::new(0.6, 0.8, 0.0)) - 1.0).abs() < 1e-6);
        assert!(d.intersect(&ray, 0.0, 9.0).is_none());
        assert!(
            Droplets::build(&[], &[])
                .unwrap()
                .intersect(&ray, 0.0, 1e9)
                .is_none()
        );
    }

    #[test]
    fn grown_droplets_cover_their_share() {
        // A droplet of radius 0.1 grown to 0.4: any ray through the grown sphere counts with
        // (0.1/0.4)² = 1/16; one larger than its footprint keeps coverage 1.
        let d = Droplets::build(&[Vec3::ZERO, Vec3::new(5.0, 0.0, 0.0)], &[0.1, 1.0]).unwrap();
        let grown = d.footprints(|_| 0.4).unwrap();
        let grown = grown.as_ref();
        let ray = |x: f32| Ray {
            origin: Vec3::new(x, 0.3, -10.0),
            dir: Vec3::Z,
        };
        let h = d
            .intersect_grown(grown, &ray(0.0), 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!(h.hit.index, 0);
        assert!((h.coverage - 1.0 / 16.0).abs() < 1e-6, "{}", h.coverage);
        let chord = 2.0 * (0.4f32 * 0.4 - 0.3 * 0.3).sqrt();
        assert!((h.t_exit - h.hit.t - chord).abs() < 1e-4);
        assert!(d.intersect(&ray(0.0), 0.0, f32::INFINITY).is_none());
        let big = d
            .intersect_grown(grown, &ray(5.0), 0.0, f32::INFINITY)
            .unwrap();
        assert_eq!((big.hit.index, big.coverage), (1, 1.0));
    }
}
