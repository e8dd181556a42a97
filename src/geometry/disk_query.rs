//! The query internals of [`DiskGeometry`]: the closest disk, and the single-pass disk-layer
//! search.
//!
//! The layer search runs one closest-hit traversal whose pruning distance is not the current
//! closest hit `t` but the end of its layer band, `t + band`, collecting the other disk hits on
//! the way. When the traversal ends, the closest disk `t0` is known and the candidates within its
//! band form the layer — exactly the set a second traversal of `[t0, t0 + band0]` would find,
//! provided the pruning distance never dropped below `t0 + band0` (an earlier, farther closest
//! hit with a narrower band; the distance has some slack, see [`LIMIT_SLACK`]) and the candidate
//! buffer did not overflow. Otherwise that second
//! traversal is run; on smooth films this is rare (3% of primary rays on a 1M-disk shell with
//! radii 0.9–1.5× the spacing).
//!
//! Leaves are tested four disks at a time (`disk4`, bit-identical to the scalar test); the hits
//! are then handled one by one in slot order, exactly as the per-slot closures did.

use super::blend::{LayerSum, kernel};
use super::disks::DiskGeometry;
use super::primitives::intersect_disk;
use super::ray4::Ray4;
use super::{Ray, SurfaceHit};

/// Candidate buffer of the single-pass layer search (entries of 12 bytes on the stack).
const MAX_CANDIDATES: usize = 48;

/// While collecting, the traversal runs to `t + LIMIT_SLACK · band` of the current closest hit,
/// so a later, slightly closer hit with a slightly wider band rarely needs the fallback (measured
/// on a 1M-disk sphere shell: 50% fallbacks without slack, none with 1.25).
pub(super) const LIMIT_SLACK: f32 = 1.5;

/// A disk hit: slot, distance, squared distance from the disk centre.
pub(super) type DiskHit = (u32, f32, f32);

/// What the single-pass layer search collected: the closest disk hit, the candidates for its
/// layer, and whether they are complete (see the module docs).
struct LayerSearch {
    best: DiskHit,
    cands: [DiskHit; MAX_CANDIDATES],
    nc: usize,
    overflow: bool,
    min_lim: f32,
}

impl DiskGeometry {
    /// Tests the disks in slots `first .. first + count` four at a time for
    /// `t_min < t < t_max` and calls `hit(slot, t, d2)` for each hit not cut off by the disk's
    /// edge cut, in slot order.
    #[inline(always)]
    fn disk_leaf(
        &self,
        ray: &Ray,
        r4: &Ray4,
        (first, count): (u32, u32),
        t_min: f32,
        t_max: f32,
        mut hit: impl FnMut(u32, f32, f32),
    ) {
        let (mut s, end) = (first as usize, first as usize + count as usize);
        while s < end {
            // The disk array is padded, so four disks can be read from any slot.
            let Some(packet) = self.disks[s..].first_chunk::<4>() else {
                break;
            };
            let h = r4.test_disks(packet, (end - s).min(4), t_min, t_max);
            let mut m = h.mask;
            while m != 0 {
                let i = m.trailing_zeros() as usize;
                m &= m - 1;
                let slot = (s + i) as u32;
                if !self.cut_off(slot, ray, h.t[i]) {
                    hit(slot, h.t[i], h.d2[i]);
                }
            }
            s += 4;
        }
    }

    /// Closest disk; ties in `t` go to the lowest particle index.
    #[inline]
    pub(super) fn closest_disk(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<DiskHit> {
        let mut best: Option<DiskHit> = None;
        let r4 = Ray4::new(ray);
        self.bvh
            .closest_leaves(ray, t_min, t_max, |first, count, lim| {
                let hi = if best.is_some() { lim.next_up() } else { t_max };
                self.disk_leaf(ray, &r4, (first, count), t_min, hi, |s, t, d2| {
                    // Inclusive of the current closest `t` (ties), as `intersect_disk(.., hi)`.
                    let hi = if best.is_some() { lim.next_up() } else { t_max };
                    if t < hi
                        && best.is_none_or(|(bs, bt, _)| t < bt || self.bvh.lower_particle(s, bs))
                    {
                        best = Some((s, t, d2));
                        *lim = t;
                    }
                });
            });
        best
    }

    /// The blended crossing of the closest disk layer (single pass, see the module docs).
    pub(super) fn disk_layer_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        let search = self.search_layer(ray, t_min, t_max)?;
        Some(self.blend_layer(ray, t_min, t_max, &search))
    }

    /// One closest-hit traversal pruned at the end of the current closest hit's band, collecting
    /// the other disk hits on the way; `None` if no disk is hit.
    #[inline(always)]
    fn search_layer(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<LayerSearch> {
        let mut min_lim = f32::INFINITY;
        let mut best: Option<DiskHit> = None;
        let mut cands = [(0u32, 0f32, 0f32); MAX_CANDIDATES];
        let mut nc = 0usize;
        let mut overflow = false;
        let r4 = Ray4::new(ray);
        // The packet test uses the query range (the band limit can grow within a leaf); the
        // exact per-slot limit is applied below, as if each slot were tested on its own.
        self.bvh
            .closest_leaves(ray, t_min, t_max, |first, count, lim| {
                self.disk_leaf(ray, &r4, (first, count), t_min, t_max, |s, t, d2| {
                    let d = &self.disks[s as usize];
                    // Inclusive of `lim` (ties with the closest hit), exclusive of `t_max`.
                    let hi = if *lim < t_max { lim.next_up() } else { t_max };
                    if t >= hi {
                        return;
                    }
                    let closer = best.is_none_or(|(bs, bt, _)| {
                        t < bt || (t == bt && self.bvh.lower_particle(s, bs))
                    });
                    let candidate = if closer {
                        *lim = (t + LIMIT_SLACK
                            * self.blend.band(d.radius, d.normal.dot(ray.dir).abs()))
                        .min(t_max);
                        min_lim = min_lim.min(*lim);
                        best.replace((s, t, d2))
                    } else {
                        Some((s, t, d2))
                    };
                    if let Some(c) = candidate {
                        overflow |= !push_candidate(&mut cands, &mut nc, c, *lim);
                    }
                });
            });
        Some(LayerSearch {
            best: best?,
            cands,
            nc,
            overflow,
            min_lim,
        })
    }

    /// Blends the layer of the search's closest disk: the candidates within its band, or, when
    /// they may be incomplete, the disks a second traversal of the band finds.
    #[inline(always)]
    fn blend_layer(&self, ray: &Ray, t_min: f32, t_max: f32, search: &LayerSearch) -> SurfaceHit {
        let slot0 = search.best.0;
        let (mut sum, t0, t_end) = self.layer_start(ray, t_max, search.best);
        if t_end > t0 {
            if search.overflow || t_end > search.min_lim {
                self.bvh.visit_segment(ray, t0, t_end, |s| {
                    let d = &self.disks[s as usize];
                    if s != slot0
                        && let Some((t, d2)) =
                            intersect_disk(ray, d.center, d.normal, d.radius, t_min, t_end)
                        && !self.cut_off(s, ray, t)
                    {
                        self.layer_add(&mut sum, ray, slot0, (s, t, d2));
                    }
                });
            } else {
                for &(s, t, d2) in &search.cands[..search.nc] {
                    if t < t_end {
                        self.layer_add(&mut sum, ray, slot0, (s, t, d2));
                    }
                }
            }
        }
        layer_hit(ray, &sum)
    }

    /// Starts the layer of the closest disk hit `best`: its running sum, its distance `t0` and
    /// the end of its band (`min(t0 + band, t_max)`; members have `t < t_end`).
    #[inline(always)]
    pub(super) fn layer_start(&self, ray: &Ray, t_max: f32, best: DiskHit) -> (LayerSum, f32, f32) {
        let (slot0, t0, d2) = best;
        let d0 = &self.disks[slot0 as usize];
        let sum = LayerSum::new(
            t0,
            self.disk_normal_at(slot0, ray.at(t0)),
            self.disk_thickness_at(slot0, ray.at(t0)),
            self.bvh.order[slot0 as usize],
            kernel(d2, d0.radius * d0.radius),
        );
        let band = self.blend.band(d0.radius, d0.normal.dot(ray.dir).abs());
        (sum, t0, (t0 + band).min(t_max))
    }

    /// Adds the disk hit `hit` (another disk than `slot0`, within the band) to the layer of
    /// the closest disk `slot0` if its normal agrees with that disk's.
    #[inline(always)]
    pub(super) fn layer_add(&self, sum: &mut LayerSum, ray: &Ray, slot0: u32, hit: DiskHit) {
        let (s, t, d2) = hit;
        let d = &self.disks[s as usize];
        if d.normal.dot(self.disks[slot0 as usize].normal).abs() > self.blend.min_normal_dot {
            sum.add(
                t,
                self.disk_normal_at(s, ray.at(t)),
                self.disk_thickness_at(s, ray.at(t)),
                self.bvh.order[s as usize],
                kernel(d2, d.radius * d.radius),
            );
        }
    }
}

/// The blended crossing of a finished layer sum.
#[inline(always)]
pub(super) fn layer_hit(ray: &Ray, sum: &LayerSum) -> SurfaceHit {
    let b = sum.finish();
    SurfaceHit {
        t: b.t,
        t_exit: b.t_exit,
        position: ray.at(b.t),
        normal: b.normal,
        thickness_nm: b.thickness_nm,
        coverage: b.coverage,
        particle: b.particle,
    }
}

/// Appends candidate `c` to `cands[..*nc]`; when the buffer is full, first drops the
/// candidates beyond the current band end `keep` (if the band grows again later, `min_lim`
/// sends the query to the exact fallback). Returns false if `c` still did not fit.
#[inline]
pub(super) fn push_candidate<const N: usize>(
    cands: &mut [DiskHit; N],
    nc: &mut usize,
    c: DiskHit,
    keep: f32,
) -> bool {
    if *nc == N {
        let mut k = 0;
        for i in 0..*nc {
            if cands[i].1 <= keep {
                cands[k] = cands[i];
                k += 1;
            }
        }
        *nc = k;
    }
    if *nc < N {
        cands[*nc] = c;
        *nc += 1;
        true
    } else {
        false
    }
}
