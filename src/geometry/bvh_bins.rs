//! The pieces of the binned-SAH build (`bvh_build`): the SIMD box, the primitive arrays the
//! partitions permute, the binning with its sweep for the cheapest split, and the partition.

use glam::{BVec3A, Vec3A};

/// A SIMD box used during the build.
#[derive(Clone, Copy)]
pub(super) struct Box3 {
    pub(super) min: Vec3A,
    pub(super) max: Vec3A,
}

impl Box3 {
    pub(super) const EMPTY: Box3 = Box3 {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    #[inline(always)]
    pub(super) fn union(self, o: Box3) -> Box3 {
        Box3 {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    #[inline(always)]
    pub(super) fn grow(&mut self, p: Vec3A) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    #[inline(always)]
    pub(super) fn area(self) -> f32 {
        let e = (self.max - self.min).max(Vec3A::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// Twice the centroid (binning only needs an affine image of it).
    #[inline(always)]
    pub(super) fn c2(self) -> Vec3A {
        self.min + self.max
    }
}

/// Primitive boxes and their original indices, permuted together by the partitions.
pub(super) struct Prims<'a> {
    pub(super) boxes: &'a mut [Box3],
    pub(super) ids: &'a mut [u32],
}

impl Prims<'_> {
    pub(super) fn len(&self) -> usize {
        self.boxes.len()
    }

    pub(super) fn split_at(self, mid: usize) -> (Self, Self) {
        let (bl, br) = self.boxes.split_at_mut(mid);
        let (il, ir) = self.ids.split_at_mut(mid);
        (Prims { boxes: bl, ids: il }, Prims { boxes: br, ids: ir })
    }
}

/// The cheapest SAH split found by binning.
pub(super) struct BinnedSplit {
    pub(super) cost: f32,
    pub(super) axis: usize,
    pub(super) k: usize,
    pub(super) scale: Vec3A,
    pub(super) top: Vec3A,
    pub(super) left: Box3,
    pub(super) right: Box3,
    pub(super) left_count: usize,
}

/// Bins centroids into `NB` buckets on all three axes and sweeps for the cheapest split
/// (unnormalised cost `area_left · n_left + area_right · n_right`).
#[inline(always)]
pub(super) fn best_binned_split<const NB: usize>(
    boxes: &[Box3],
    cbounds: &Box3,
) -> Option<BinnedSplit> {
    let n = boxes.len();
    let ext = cbounds.max - cbounds.min;
    let scale = Vec3A::select(ext.cmpgt(Vec3A::ZERO), NB as f32 / ext, Vec3A::ZERO);
    let cmin = cbounds.min;
    let mut bins = [[Box3::EMPTY; NB]; 3];
    let mut counts = [[0u32; NB]; 3];
    let top = Vec3A::splat((NB - 1) as f32);
    for b in boxes {
        let k = bin_coords(b.c2(), cmin, scale, top).as_uvec3();
        for axis in 0..3 {
            let k = k[axis] as usize;
            bins[axis][k] = bins[axis][k].union(*b);
            counts[axis][k] += 1;
        }
    }
    let mut best: Option<(f32, usize, usize, usize)> = None; // (cost, axis, k, left count)
    for axis in 0..3 {
        let spread = ext[axis] > 0.0;
        if !spread {
            continue;
        }
        let (bins, counts) = (&bins[axis], &counts[axis]);
        let mut right_cost = [0f32; NB];
        let mut acc = Box3::EMPTY;
        let mut cnt = 0u32;
        for k in (1..NB).rev() {
            acc = acc.union(bins[k]);
            cnt += counts[k];
            right_cost[k] = acc.area() * cnt as f32;
        }
        let mut acc = Box3::EMPTY;
        let mut cnt = 0usize;
        for k in 1..NB {
            acc = acc.union(bins[k - 1]);
            cnt += counts[k - 1] as usize;
            if cnt == 0 || cnt == n {
                continue;
            }
            let cost = acc.area() * cnt as f32 + right_cost[k];
            if best.is_none_or(|b| cost < b.0) {
                best = Some((cost, axis, k, cnt));
            }
        }
    }
    let (cost, axis, k, left_count) = best?;
    let sum = |bins: &[Box3]| bins.iter().fold(Box3::EMPTY, |a, b| a.union(*b));
    Some(BinnedSplit {
        cost,
        axis,
        k,
        scale,
        top,
        left: sum(&bins[axis][..k]),
        right: sum(&bins[axis][k..]),
        left_count,
    })
}

/// Bin coordinates of a centroid (×2) `c` on each axis: `(c - cmin) · scale` clamped to
/// `[0, top]`, its floor the bin (a NaN lands in bin 0).
#[inline(always)]
pub(super) fn bin_coords(c: Vec3A, cmin: Vec3A, scale: Vec3A, top: Vec3A) -> Vec3A {
    ((c - cmin) * scale).max(Vec3A::ZERO).min(top)
}

/// In-place partition by centroid; returns the number of primitives satisfying `pred` (now at
/// the front) and the centroid bounds of both sides. Branch-free (a Lomuto pass that always
/// swaps): which side a centroid falls on is a coin toss the branch predictor loses, and the
/// mispredictions were most of the build.
#[inline(always)]
pub(super) fn partition(
    prims: &mut Prims<'_>,
    pred: impl Fn(Vec3A) -> bool,
) -> (usize, Box3, Box3) {
    let (mut lc, mut rc) = (Box3::EMPTY, Box3::EMPTY);
    let (boxes, ids) = (&mut *prims.boxes, &mut *prims.ids);
    let mut mid = 0;
    for i in 0..boxes.len() {
        let (b, id) = (boxes[i], ids[i]);
        let c = b.c2();
        let left = pred(c);
        let m = BVec3A::splat(left);
        let (inf, ninf) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        lc.min = lc.min.min(Vec3A::select(m, c, inf));
        lc.max = lc.max.max(Vec3A::select(m, c, ninf));
        rc.min = rc.min.min(Vec3A::select(m, inf, c));
        rc.max = rc.max.max(Vec3A::select(m, ninf, c));
        boxes[i] = boxes[mid];
        ids[i] = ids[mid];
        boxes[mid] = b;
        ids[mid] = id;
        mid += left as usize;
    }
    (mid, lc, rc)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ray4::test_rng;

    /// The partition against a plain filter: the front holds exactly the primitives the test
    /// sends left, nothing is lost or doubled, the ids travel with their boxes, and the returned
    /// centroid bounds are those of each side.
    #[test]
    fn partition_matches_a_filter() {
        let mut rnd = test_rng(7);
        for n in [0usize, 1, 2, 9, 100, 1000] {
            let mut boxes: Vec<Box3> = (0..n)
                .map(|_| {
                    let c = Vec3A::new(rnd(), rnd(), rnd());
                    Box3 {
                        min: c - Vec3A::splat(0.01),
                        max: c + Vec3A::splat(0.02),
                    }
                })
                .collect();
            let original = boxes.clone();
            let mut ids: Vec<u32> = (0..n as u32).collect();
            let goes_left = |c: Vec3A| c.y < 0.3;
            let mut prims = Prims {
                boxes: &mut boxes,
                ids: &mut ids,
            };
            let (mid, lc, rc) = partition(&mut prims, goes_left);
            let (mut want_l, mut want_r) = (Box3::EMPTY, Box3::EMPTY);
            let mut seen = vec![false; n];
            for (s, (b, &id)) in boxes.iter().zip(&ids).enumerate() {
                let o = original[id as usize];
                assert!(o.min == b.min && o.max == b.max, "id {id} left its box");
                assert!(!seen[id as usize]);
                seen[id as usize] = true;
                assert_eq!(goes_left(b.c2()), s < mid, "slot {s} on the wrong side");
                let side = if s < mid { &mut want_l } else { &mut want_r };
                side.grow(b.c2());
            }
            assert!(seen.iter().all(|&s| s));
            for (got, want) in [(lc, want_l), (rc, want_r)] {
                assert!(got.min == want.min && got.max == want.max);
            }
        }
    }
}
